"""The Markdown tables of ``bench/paper.py``: outcome and time beside the paper's figures,
the work each class took, and the anytime profile of the slower classes."""

from __future__ import annotations

import statistics
from typing import Any, Sequence

from paper_classes import PAPER_SETUP

SPEEDUP = 50.0  # target: median whole-process time <= paper average / 50
ANYTIME_MIN_S = 10.0  # classes whose median run takes this long get the anytime table
WORK = (("learned", "facts learned"), ("updates", "UpdateAbstraction"),
        ("solves", "abstract solves"), ("timeouts", "capped solves"),
        ("resamples", "re-samples"), ("prg", "PRG nodes"), ("refined", "refined nodes"),
        ("planner", "planner calls"), ("checks", "collision checks"),
        ("branches", "policy branches"), ("ground_actions", "ground actions"),
        ("ground_facts", "ground facts"))


def _mean(values: Sequence[float]) -> float | None:
    return statistics.fmean(values) if values else None


def _median(values: Sequence[float]) -> float | None:
    return statistics.median(values) if values else None


def _fmt(x: float | None, digits: int = 1) -> str:
    return "—" if x is None else f"{x:,.{digits}f}"


def _rows(records: list[Any], cls: Any) -> list[Any]:
    return [r for r in records if r.cls == cls.name]


def executed(records: list[Any]) -> str:
    """``success/runs, collisions`` over the executions of ``records``' policies refined to
    the target; then the collisions in the executions of partial policies, if any ran."""
    full = [r.execution for r in records if r.execution and r.coverage >= 0.999]
    part = [r.execution for r in records if r.execution and r.coverage < 0.999]
    text = "—"
    if full:
        text = (f"{sum(int(e.get('success', 0)) for e in full)}/"
                f"{sum(int(e.get('runs', 0)) for e in full)}, "
                f"{sum(int(e.get('collisions', 0)) for e in full)} coll.")
    if part:
        text += (f"; partial: {sum(int(e.get('collisions', 0)) for e in part)} coll. in "
                 f"{sum(int(e.get('runs', 0)) for e in part)}")
    return text


def _goal_probability(records: list[Any]) -> str:
    """The median goal probability and, beside it, the least: a run "solved" by proving
    its instance a dead end (goal probability 0) must not hide behind a median of 1."""
    values = [r.goal_probability for r in records if r.goal_probability is not None]
    if not values:
        return "—"
    return f"{_fmt(_median(values), 3)} ({_fmt(min(values), 3)})"


def outcome_table(records: list[Any], classes: Sequence[Any]) -> list[str]:
    head = ("| class | runs | solved | executed (success, collisions) | goal prob. median (min) | "
            "median process s | median process CPU s | median engine s | paper solved | "
            "paper avg s | process / paper avg | split |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for cls in classes:
        rs = _rows(records, cls)
        if not rs:
            continue
        solved = [r for r in rs if r.solved]
        med = _median([r.process_s for r in solved])
        share = (f"{100 * med / cls.paper_time_s:.2f} %"
                 + (" ✓" if med <= cls.paper_time_s / SPEEDUP else " ✗")
                 if med is not None and cls.paper_time_s else "—")
        paper = ("not attempted" if cls.paper_solved is None
                 else f"{100 * cls.paper_solved:.0f} %")
        # the engine's split: median proven-dead-end mass (goal mass = goal prob.)
        split = ("n/a" if all(r.given_up is None for r in rs) else
                 f"dead end {_fmt(_median([r.coverage - r.goal_probability for r in rs]), 3)}")
        lines.append(
            f"| {cls.name} | {len(rs)} | {len(solved)}/{len(rs)} | {executed(rs)} | "
            f"{_goal_probability(rs)} | {_fmt(med)} | "
            f"{_fmt(_median([r.cpu_s for r in solved]))} | "
            f"{_fmt(_median([r.engine_s for r in solved]), 2)} | {paper} | "
            f"{_fmt(cls.paper_time_s, 0)} | {share} | {split} |")
    return lines


def work_table(records: list[Any], classes: Sequence[Any]) -> list[str]:
    head = "| class | " + " | ".join(label for _, label in WORK) + " |"
    lines = ["Mean per run (all runs of the class):", "", head,
             "|" + "---|" * (len(WORK) + 1)]
    for cls in classes:
        rs = [r for r in _rows(records, cls) if r.work]
        if rs:
            # a counter older runs.json files lack is "—", not a mean of zeros
            cells = [_fmt(_mean([r.work[k] for r in rs if k in r.work]), 1) for k, _ in WORK]
            lines.append(f"| {cls.name} | " + " | ".join(cells) + " |")
    return lines


def anytime_table(records: list[Any], classes: Sequence[Any]) -> list[str]:
    lines = [f"Classes whose median whole-process time is ≥ {ANYTIME_MIN_S:.0f} s: median "
             "engine time to 50/80/90 % of the probability mass and to the run's end (the "
             "target coverage, 0.999: not every solved run reaches exactly 1), and how many "
             "runs had 80 % within 30 % of their run (the paper's figure) / 90 % within 15 %.",
             "", "| class | t50 | t80 | t90 | t end | 80 % ≤ 30 % | 90 % ≤ 15 % |",
             "|---|---|---|---|---|---|---|"]
    for cls in classes:
        solved = [r for r in _rows(records, cls) if r.solved]
        med = _median([r.process_s for r in solved])
        if med is None or med < ANYTIME_MIN_S:
            continue
        tt = [_median([r.time_to[k] for r in solved if r.time_to.get(k) is not None])
              for k in ("0.5", "0.8", "0.9")] + [_median([r.engine_s for r in solved])]
        early80 = sum(_early(r, "0.8", 0.30) for r in solved)
        early90 = sum(_early(r, "0.9", 0.15) for r in solved)
        lines.append(f"| {cls.name} | " + " | ".join(_fmt(t, 2) for t in tt)
                     + f" | {early80}/{len(solved)} | {early90}/{len(solved)} |")
    return lines if len(lines) > 4 else lines[:1] + ["", "(no class)"]


def _early(r: Any, mass: str, share: float) -> bool:
    t = r.time_to.get(mass)
    return t is not None and t <= share * r.engine_s + 1e-9


def table(records: list[Any], classes: Sequence[Any]) -> str:
    by_note: dict[str, list[str]] = {}
    for c in classes:
        if c.note and _rows(records, c):
            by_note.setdefault(c.note, []).append(c.name)
    notes = [f"- {', '.join(names)}: {note}" for note, names in by_note.items()]
    parts = outcome_table(records, classes) + [
        "", f"Solved: coverage ≥ 0.999 within the timeout, no goal mass given up "
        f"and every execution of the policy in the world clean (\"executed\": `stampc "
        f"execute` of each policy that reached the target: outcomes sampled by the world, "
        f"trajectories re-swept at 10x, the goal checked on the concrete state; a failure, "
        f"collision or missed goal makes the run exec-failed; \"partial\": the collisions "
        f"in the executions of partial policies, whose refined part must work too) "
        f"(coverage counts a dead end only when the abstract model, with everything learned, "
        f"proves the goal unreachable there; \"split\": the median proven-dead-end mass, the "
        f"rest of the coverage is goal mass; \"n/a\": the engine did not report it). Times are "
        f"whole processes; \"process / paper avg\" compares them with the paper's average "
        f"(✓ when ≤ 1/{SPEEDUP:.0f}), across different robots, simulators and hardware: "
        f"{PAPER_SETUP}.", "", "Instances:"] + notes + [""] + work_table(records, classes) \
        + [""] + anytime_table(records, classes)
    return "\n".join(parts) + "\n"
