"""The run's drawings (stampc.figures): well-formed SVG whose geometry follows the
data — the coverage areas stack to the mass split, the policy tree puts each parent over
its children."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from stampc.figures import MASS_COLORS, coverage_svg, policy_svg

SVG = "{http://www.w3.org/2000/svg}"


def _points(element: ET.Element) -> list[tuple[float, float]]:
    return [tuple(map(float, p.split(","))) for p in element.get("points", "").split()]


def test_coverage_areas_stack_to_the_mass_split():
    times, coverage, goal = [0.0, 1.0, 2.0, 4.0], [0.0, 0.5, 0.8, 1.0], [0.0, 0.5, 0.6, 0.7]
    root = ET.fromstring(coverage_svg(times, coverage, goal, "run <1>"))
    areas = {a.find(f"{SVG}title").text: a for a in root.iter(f"{SVG}polygon")}
    assert list(areas) == [name for name, _ in MASS_COLORS]
    frame = next(r for r in root.iter(f"{SVG}rect") if r.get("fill") == "none")
    top, height = float(frame.get("y")), float(frame.get("height"))

    def value(y: float) -> float:  # pixel row -> probability mass
        return round(1.0 - (y - top) / height, 2)

    # the goal area's upper edge steps through the goal values; the proven dead ends'
    # upper edge through the coverage; the unrefined area reaches 1
    goal_top = [value(y) for _, y in _points(areas["goal"])][:7]
    assert goal_top == [0.0, 0.0, 0.5, 0.5, 0.6, 0.6, 0.7]
    dead_top = [value(y) for _, y in _points(areas["dead end (proven)"])][:7]
    assert dead_top == [0.0, 0.0, 0.5, 0.5, 0.8, 0.8, 1.0]
    assert {value(y) for _, y in _points(areas["unrefined"])[:7]} == {1.0}
    titles = [t.text for t in root.iter(f"{SVG}text")]
    assert "run <1>" in titles and "time (s)" in titles  # escaped in the file, not lost


def test_coverage_keeps_only_changes_and_the_last_event():
    times = [float(t) for t in range(1000)]
    flat = [0.5] * 1000
    root = ET.fromstring(coverage_svg(times, flat, flat))
    line = next(root.iter(f"{SVG}polyline"))
    xs = [x for x, _ in _points(line)]
    assert len(xs) == 3  # first event, a step to the last, the last
    assert max(xs) > min(xs)


def test_an_empty_run_still_draws_its_axes():
    root = ET.fromstring(coverage_svg([], [], []))
    assert not list(root.iter(f"{SVG}polygon"))
    assert "coverage over time" in [t.text for t in root.iter(f"{SVG}text")]


def test_policy_tree_puts_parents_over_their_children():
    # 0 -> 1, 2; 1 -> 3, 4; 2 -> 4 (a merge: 4 stays under 1, which reached it first)
    nodes = [(0, 0, "pick(a, b)", "palegreen"), (1, 1, "place", "lightgrey"),
             (2, 1, "goal", "palegreen"), (3, 2, "goal", "palegreen"),
             (4, 2, "a very long action name indeed", "lightgrey")]
    edges = [(0, 1), (0, 2), (1, 3), (1, 4), (2, 4)]
    root = ET.fromstring(policy_svg(nodes, edges))
    circles = list(root.iter(f"{SVG}circle"))
    assert len(circles) == 5 and len(list(root.iter(f"{SVG}line"))) == 5
    x = [float(c.get("cx")) for c in circles]
    y = [float(c.get("cy")) for c in circles]
    assert y[0] < y[1] == y[2] < y[3] == y[4]  # rows by layer
    assert x[3] < x[1] < x[4]                   # 1 between its children
    assert x[1] < x[0] < x[2]                   # the root between its own
    assert len({round(v) for v in x[3:]}) == 2 and x[2] > x[4]  # leaves side by side
    labels = [t.text for t in root.iter(f"{SVG}text")]
    assert labels[4].endswith("…") and len(labels[4]) == 18
    titles = [t.text for t in root.iter(f"{SVG}title")]
    assert "a very long action name indeed" in titles  # the full label as a tooltip
