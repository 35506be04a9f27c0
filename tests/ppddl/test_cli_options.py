"""``--lenient`` and ``--conflicting-effects`` on ``stampc compile`` and ``stampc solve``:
warnings are printed located on stderr, and the run succeeds (exit 0)."""

from __future__ import annotations

import json

import pytest

from stampc.cli import main
from tests.ppddl.test_ground_warnings import TOGGLE
from tests.ppddl.test_lenient import DOMAIN, PROBLEM


@pytest.fixture
def lenient_file(tmp_path):
    path = tmp_path / "mini.pddl"
    path.write_text(DOMAIN + PROBLEM)
    return path


@pytest.fixture
def toggle_file(tmp_path):
    path = tmp_path / "toggle.pddl"
    path.write_text(TOGGLE)
    return path


@pytest.mark.parametrize("command", ["compile", "solve"])
def test_without_lenient_the_errors_hint_at_it(command, lenient_file, capsys):
    assert main([command, str(lenient_file)]) == 1
    err = capsys.readouterr().err
    assert "P111" in err and "--lenient" in err


def test_compile_lenient_prints_located_warnings(lenient_file, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["compile", str(lenient_file), "--lenient", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert f"{lenient_file}:7:" in err and "P201" in err and "P202" in err
    lifted = json.loads((out / "lifted.json").read_text())
    assert "terminated" in json.dumps(lifted)


def test_solve_lenient_solves(lenient_file, capsys):
    assert main(["solve", str(lenient_file), "--lenient", "--format", "json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["expected_cost"] == 2.0
    assert "warning" in captured.err and "P201" in captured.err


@pytest.mark.parametrize("rule, cost", [("add-wins", 1.0), ("delete-wins", 5.0)])
def test_solve_conflicting_effects_option(rule, cost, toggle_file, capsys):
    assert main(["solve", str(toggle_file), "--conflicting-effects", rule,
                 "--format", "json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["expected_cost"] == cost
    assert "G203" in captured.err and rule.replace("-", " ") in captured.err


def test_compile_conflicting_effects_option(toggle_file, capsys):
    code = main(["compile", str(toggle_file), "--level", "grounded",
                 "--conflicting-effects", "delete-wins"])
    assert code == 0 and "delete wins" in capsys.readouterr().err


def test_bad_rule_is_a_usage_error(toggle_file, capsys):
    assert main(["solve", str(toggle_file), "--conflicting-effects", "mini-gpt"]) == 2
    assert "--conflicting-effects" in capsys.readouterr().err
