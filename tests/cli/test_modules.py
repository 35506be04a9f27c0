"""Bound modules that are not on ``sys.path`` load from files beside the stamp file:
registered in ``sys.modules`` (dataclasses, relative imports work), never stale."""

from __future__ import annotations

import os
import sys
import textwrap
from pathlib import Path

import pytest

import stampc
from stampc.diagnostics import StampcError
from stampc.worlds.modules import import_bound_module

from .paths import EXAMPLES, REPO

SCENE = '''\
from __future__ import annotations
from dataclasses import dataclass
from . import helper

@dataclass(frozen=True)
class Spec:
    n: int

def value():
    return helper.TAG + str(Spec({n}).n)
'''


USER_MODULES = ("mylab", "scene", "needs", "myscene", "myexec")


@pytest.fixture(autouse=True)
def forget_user_modules():
    """The modules these tests write are dropped from ``sys.modules`` afterwards (only
    those: C extensions first imported meanwhile cannot be imported twice)."""
    yield
    for name in [n for n in sys.modules if n.split(".")[0] in USER_MODULES]:
        del sys.modules[name]


def _package(root: Path, tag: str, n: int) -> Path:
    pkg = root / "mylab" / "scenes"
    pkg.mkdir(parents=True)
    (pkg / "helper.py").write_text(f"TAG = {tag!r}\n", encoding="utf-8")
    (pkg / "scene.py").write_text(SCENE.format(n=n), encoding="utf-8")
    problems = root / "problems" / "p1"
    problems.mkdir(parents=True)
    return problems


def test_a_module_found_beside_the_problem_supports_dataclasses_and_relative_imports(tmp_path):
    problems = _package(tmp_path, "A", 1)
    module = import_bound_module("mylab.scenes.scene", problems)
    assert module is not None and module.value() == "A1"
    assert sys.modules["mylab.scenes.scene"] is module
    assert module.__file__ == str(tmp_path / "mylab" / "scenes" / "scene.py")
    assert import_bound_module("mylab.scenes.scene", problems) is module  # reused


def test_the_same_name_in_another_folder_is_loaded_afresh(tmp_path):
    first = import_bound_module("mylab.scenes.scene", _package(tmp_path / "a", "A", 1))
    second = import_bound_module("mylab.scenes.scene", _package(tmp_path / "b", "B", 2))
    assert (first.value(), second.value()) == ("A1", "B2")
    assert sys.modules["mylab.scenes.scene"] is second
    assert sys.modules["mylab.scenes.helper"].TAG == "B"


def test_a_changed_file_is_reloaded(tmp_path):
    problems = _package(tmp_path, "A", 1)
    assert import_bound_module("mylab.scenes.scene", problems).value() == "A1"
    scene = tmp_path / "mylab" / "scenes" / "scene.py"
    scene.write_text(SCENE.format(n=7), encoding="utf-8")
    stat = scene.stat()
    os.utime(scene, ns=(stat.st_atime_ns, stat.st_mtime_ns + 10**9))
    assert import_bound_module("mylab.scenes.scene", problems).value() == "A7"


def test_two_top_level_scene_modules_do_not_clash(tmp_path):
    for name in ("one", "two"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "scene.py").write_text(f"NAME = {name!r}\n", encoding="utf-8")
    assert import_bound_module("scene", tmp_path / "one").NAME == "one"
    assert import_bound_module("scene", tmp_path / "two").NAME == "two"
    assert import_bound_module("scene", tmp_path / "one").NAME == "one"


def test_a_missing_dependency_is_not_mistaken_for_a_missing_module(tmp_path):
    (tmp_path / "needs.py").write_text("import no_such_dependency_xyz\n", encoding="utf-8")
    with pytest.raises(ModuleNotFoundError, match="no_such_dependency_xyz"):
        import_bound_module("needs", tmp_path)
    assert import_bound_module("absent_module_xyz", tmp_path) is None


def test_installed_modules_are_never_loaded_again_from_a_checkout():
    from stampc.worlds.plane2d import scenes
    assert import_bound_module("stampc.worlds.plane2d.scenes", EXAMPLES / "shelf2d") is scenes
    assert import_bound_module("stampc.worlds.plane2d.scenes", REPO) is scenes


def _shelf_with(tmp_path: Path, scene_line: str, executes: str | None = None) -> list[Path]:
    domain = (EXAMPLES / "shelf2d" / "domain.stamp").read_text(encoding="utf-8")
    if executes:
        domain = domain.replace('executes ".manipulation:pick"', f'executes "{executes}"')
    problem = (EXAMPLES / "shelf2d" / "problem.stamp").read_text(encoding="utf-8")
    problem = problem.replace(problem[problem.index("scene builder"):], scene_line + "\n")
    (tmp_path / "domain.stamp").write_text(domain, encoding="utf-8")
    (tmp_path / "problem.stamp").write_text(problem, encoding="utf-8")
    return [tmp_path / "domain.stamp", tmp_path / "problem.stamp"]


def test_scene_builders_and_executors_beside_the_stamp_files(tmp_path):
    (tmp_path / "myscene.py").write_text(textwrap.dedent('''\
        from dataclasses import dataclass
        from stampc.worlds.plane2d.scenes import cluttered

        @dataclass
        class Args:
            n: int

        def build(n):
            return cluttered(n=Args(n).n, seed=2, blockers=2, shelf=True)
        '''), encoding="utf-8")
    (tmp_path / "myexec.py").write_text(textwrap.dedent('''\
        from stampc.worlds.plane2d.manipulation import pick as world_pick
        CALLS = []

        def pick(ctx, action):
            CALLS.append(action.name)
            world_pick(ctx, action)
        '''), encoding="utf-8")
    files = _shelf_with(tmp_path, 'scene builder "myscene:build"(n=5)', "myexec:pick")
    run = stampc.refine_policy(files, world="plane2d")
    assert run.result.coverage == pytest.approx(1.0)
    assert sys.modules["myexec"].CALLS  # the bound executor beside the domain ran


def test_a_builder_module_that_cannot_be_found_says_where_it_was_looked_for(tmp_path):
    files = _shelf_with(tmp_path, 'scene builder "nowhere.scene:build"(n=5)')
    with pytest.raises(StampcError) as info:
        stampc.refine_policy(files, world="plane2d")
    d = info.value.diagnostics[0]
    assert d.code == "S103" and d.span.file.endswith("problem.stamp") and d.span.line == 14
    assert "nowhere/scene.py" in d.hint
