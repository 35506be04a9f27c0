"""Static binding checks: `check` reads bound functions with `ast`, never imports them."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from stampc.commands import check as check_cmd
from stampc.semantics.api import check

from .helpers import REPO, run_command

ALL_EXAMPLES = sorted(p.parent.name for p in (REPO / "examples").glob("*/problem.stamp"))


def codes(diags) -> list[str]:
    return [d.code for d in diags]


@pytest.mark.parametrize("name", ALL_EXAMPLES)
def test_every_example_binds_what_exists(name: str) -> None:
    folder = REPO / "examples" / name
    found = [d for d in check(folder / "domain.stamp", folder / "problem.stamp")
             if d.code.startswith(("E6", "W407", "N6"))]
    assert found == []


KITCHEN_PICK = """domain k
type cup, surface
continuous type pose, config, traj
predicate handempty
predicate holding(c: cup)
predicate at(c: cup, p: pose)
predicate on(c: cup, s: surface)
predicate path(q: config, t: traj)
action pick(c: cup, s: surface, p: pose, q: config, t: traj)
    pre  handempty, at(c, p), on(c, s), path(q, t)
    eff  holding(c), not handempty
    executes ".manipulation:pick"
"""


def test_a_world_executor_reading_other_parameter_names_is_reported_before_any_run() -> None:
    """The issue's S274 case ("missing argument 'o' (has c, s, p, q, t)"), now at check."""
    [d] = [d for d in check(KITCHEN_PICK) if d.code == "E604"]
    assert "reads action parameter `o`" in d.message and "(c, s, p, q, t)" in d.message
    assert (d.span.line, d.span.col) == (12, 14)
    [label] = d.labels
    assert label.span.file.endswith("manipulation.py") and "`o`" in label.message


def test_renaming_the_parameter_makes_it_clean() -> None:
    fixed = KITCHEN_PICK.replace("c: cup", "o: cup").replace("(c", "(o").replace("c)", "o)")
    assert [c for c in codes(check(fixed)) if c.startswith("E6")] == []


def test_check_imports_nothing(tmp_path: Path) -> None:
    pkg = tmp_path / "sidefx"
    pkg.mkdir()
    marker = tmp_path / "ran"
    (pkg / "__init__.py").write_text(f"open({str(marker)!r}, 'w').close()\n")
    (pkg / "ex.py").write_text(f"open({str(marker)!r}, 'w').close()\n"
                               "def wash(ctx, action):\n    return action.args['c']\n")
    stamp = tmp_path / "d.stamp"
    stamp.write_text("domain d\ntype cup\npredicate clean(c: cup)\naction wash(c: cup)\n"
                     "    pre  not clean(c)\n    eff  clean(c)\n    executes \"sidefx.ex:wash\"\n")
    assert check(stamp) == []
    assert not marker.exists() and "sidefx" not in sys.modules
    (pkg / "ex.py").write_text("def wash(ctx, action):\n    return action.args['cup']\n")
    assert codes(check(stamp)) == ["E604"]


def test_outcome_aware_executors_and_optional_parameters_are_accepted(tmp_path: Path) -> None:
    (tmp_path / "robot.py").write_text(
        "def drive(ctx, action, outcome):\n"
        "    t = action.args['t'] if 't' in action.args else None\n"
        "    return action.args.get('speed'), action.args['u']\n")
    stamp = tmp_path / "d.stamp"
    stamp.write_text("domain d\ntype robot\npredicate moved(u: robot)\naction drive(u: robot)\n"
                     "    pre  not moved(u)\n    eff  moved(u)\n    executes \"robot:drive\"\n")
    assert check(stamp) == []


def test_check_command_reports_in_both_files() -> None:
    case = "tests/frontend/golden/E604_executor_parameter.stamp"
    code, out, _ = run_command(check_cmd, [case, "--format", "json"])
    assert code == 1 and '"code": "E604"' in out and "bindkit/kitchen.py" in out
