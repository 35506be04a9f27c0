"""Diagnostics about scenes and executor parameters point at the user's files and say
what to change on which side."""

from __future__ import annotations

import json

import pytest

import stampc
from stampc.diagnostics import StampcError
from stampc.worlds.plane2d.scenes import cluttered

from .paths import EXAMPLES

SHELF_DOMAIN = (EXAMPLES / "shelf2d" / "domain.stamp").read_text(encoding="utf-8")
SHELF_PROBLEM = (EXAMPLES / "shelf2d" / "problem.stamp").read_text(encoding="utf-8")
BUILDER_LINE = 14  # `scene builder ...` in examples/shelf2d/problem.stamp


def _write(tmp_path, domain: str, scene_line: str | None = None):
    problem = SHELF_PROBLEM
    if scene_line is not None:
        problem = problem.replace(problem[problem.index("scene builder"):], scene_line + "\n")
    (tmp_path / "domain.stamp").write_text(domain, encoding="utf-8")
    (tmp_path / "problem.stamp").write_text(problem, encoding="utf-8")
    return [tmp_path / "domain.stamp", tmp_path / "problem.stamp"]


def _diagnostics(files) -> list:
    with pytest.raises(StampcError) as info:
        stampc.refine_policy(files, world="plane2d")
    return list(info.value.diagnostics)


def test_s201_points_at_the_line_of_the_section_in_the_scene_file(tmp_path):
    scene = cluttered(n=5, seed=2, blockers=2, shelf=True)
    scene["objects"][1]["radius"] = -1
    (tmp_path / "scene.json").write_text(json.dumps(scene, indent=1), encoding="utf-8")
    files = _write(tmp_path, SHELF_DOMAIN, 'scene "scene.json"')
    [d] = _diagnostics(files)
    assert d.code == "S201" and "objects[1].radius" in d.message
    assert d.span.file.endswith("scene.json") and d.span.file != "<scene>"
    lines = (tmp_path / "scene.json").read_text(encoding="utf-8").splitlines()
    assert '"objects"' in lines[d.span.line - 1]


def test_s201_from_a_builder_points_at_the_scene_builder_line(tmp_path):
    (tmp_path / "unreachable_scene.py").write_text(
        "from stampc.worlds.plane2d.scenes import cluttered\n"
        "def build():\n"
        "    scene = cluttered(n=5, seed=2, blockers=2, shelf=True)\n"
        "    scene['robot']['reach'] = 0\n"
        "    return scene\n", encoding="utf-8")
    files = _write(tmp_path, SHELF_DOMAIN, 'scene builder "unreachable_scene:build"()')
    diags = _diagnostics(files)
    assert {d.code for d in diags} == {"S201"}
    for d in diags:
        assert d.span.file.endswith("problem.stamp") and d.span.line == BUILDER_LINE
        assert "scene built by unreachable_scene:build" in d.message


def test_s274_hint_names_the_stamp_parameter_and_the_executor_argument(tmp_path):
    start, end = SHELF_DOMAIN.index("action pick"), SHELF_DOMAIN.index("action place")
    pick = SHELF_DOMAIN[start:end]
    renamed = (pick.replace("(o: can,", "(obj: can,").replace("(o,", "(obj,")
               .replace("(o)", "(obj)").replace("(o, t2)", "(obj, t2)"))
    assert renamed != pick
    files = _write(tmp_path, SHELF_DOMAIN[:start] + renamed + SHELF_DOMAIN[end:])
    [d] = _diagnostics(files)
    assert d.code == "S274"
    assert d.span.file.endswith("domain.stamp")
    assert 'executes ".manipulation:pick"' in \
        (tmp_path / "domain.stamp").read_text(encoding="utf-8").splitlines()[d.span.line - 1]
    assert "`o`" in d.hint and "`obj`" in d.hint and "fix the function" not in d.hint
