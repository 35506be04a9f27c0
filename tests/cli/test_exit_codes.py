"""Exit codes, the same for every command: 0 done, 1 input errors, 2 usage or I/O
errors, 3 ran but stopped short with the partial result written; bad limits are usage
errors. In-process through ``stampc.cli.main`` (argument checks need no subprocess)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from stampc.cli import main
from stampc.refine import RefineOptions

from .paths import EXAMPLES

SHELF = EXAMPLES / "shelf2d"
CLUTTERED = EXAMPLES / "cluttered_table"
DOMAIN, PROBLEM2D = str(CLUTTERED / "domain_fixed.stamp"), str(CLUTTERED / "problem2d_fixed.stamp")

FLOAT_LIMITS = [("solve", "--time-limit"), ("solve", "--epsilon"), ("solve", "--dead-end-cost"),
                ("refine", "--time-limit")]
INT_LIMITS = [("solve", "--horizon"), ("solve", "--max-steps"), ("refine", "--horizon"),
              ("refine", "--solve-work-limit"), ("execute", "--runs"), ("execute", "--max-steps")]
BAD_VALUES = ["0", "-5", "nan", "inf"]


def _inputs(command: str, tmp_path) -> list[str]:
    return [str(tmp_path / "policy.json")] if command == "execute" else [DOMAIN, PROBLEM2D]


@pytest.mark.parametrize("value", BAD_VALUES)
@pytest.mark.parametrize("command,option", FLOAT_LIMITS + INT_LIMITS)
def test_non_positive_or_non_finite_limits_are_usage_errors(command, option, value,
                                                            tmp_path, capsys):
    assert main([command, *_inputs(command, tmp_path), option, value]) == 2
    err = capsys.readouterr().err
    assert f"argument {option}:" in err and repr(value) in err


@pytest.mark.parametrize("command,option,value", [
    ("solve", "--weight", "0.5"), ("solve", "--weight", "inf"), ("solve", "--simulate", "-1"),
    ("refine", "--weight", "nan"), ("refine", "--target-coverage", "0"),
    ("refine", "--target-coverage", "1.5"), ("refine", "--update-probability", "nan"),
    ("refine", "--explore-probability", "-0.1"), ("solve", "--time-limit", "soon"),
])
def test_other_option_values_out_of_range_are_usage_errors(command, option, value,
                                                           tmp_path, capsys):
    assert main([command, *_inputs(command, tmp_path), option, value]) == 2
    assert f"argument {option}:" in capsys.readouterr().err


def test_help_states_the_exit_codes(capsys):
    for command in ("check", "fmt", "compile", "solve", "refine", "execute"):
        assert main([command, "--help"]) == 0
        text = " ".join(capsys.readouterr().out.split())
        assert "exit codes: 0 done; 1 input errors" in text and "3 ran but stopped short" in text


def test_solve_stopped_by_its_time_limit_exits_3_with_the_policy_written(tmp_path, capsys):
    out = tmp_path / "policy.json"
    assert main(["solve", DOMAIN, PROBLEM2D, "--time-limit", "1e-6", "-o", str(out)]) == 3
    assert "time limit reached before convergence" in capsys.readouterr().out
    assert json.loads(out.read_text(encoding="utf-8"))


def test_solve_that_converges_exits_0(capsys):
    assert main(["solve", str(SHELF / "domain.stamp"), str(SHELF / "problem.stamp")]) == 0


def test_refine_below_target_coverage_exits_3_with_the_partial_policy(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["refine", DOMAIN, PROBLEM2D, "--time-limit", "0.001", "--quiet",
                 "-o", str(out)])
    assert code == 3
    assert "stopped short of the target coverage" in capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    assert summary["coverage"] < 1.0
    assert (out / "policy.json").is_file()


def test_the_run_s_options_are_written_beside_its_results(tmp_path):
    """summary.json and policy.json record the engine options the run used (plain JSON:
    no NaN or Infinity), the ones given and the defaults."""
    out = tmp_path / "out"
    assert main(["refine", DOMAIN, PROBLEM2D, "--time-limit", "0.001", "--quiet", "--seed", "7",
                 "--max-resample-loss", "0.25", "-o", str(out)]) == 3
    for name in ("summary.json", "policy.json"):
        options = json.loads((out / name).read_text(encoding="utf-8"),
                             parse_constant=lambda c: pytest.fail(f"{name}: {c}"))["options"]
        assert (options["seed"], options["max_resample_loss"], options["time_limit"]) == (7, 0.25, 0.001)
        assert options["max_attempts"] == RefineOptions().max_attempts
        assert options["solver"]["forbidden"] == []


def test_execute_exits_3_when_a_refined_branch_fails(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["refine", str(SHELF / "domain.stamp"), str(SHELF / "problem.stamp"),
                 "--quiet", "-o", str(out)]) == 0
    assert main(["execute", str(out / "policy.json"), "--runs", "2"]) == 0
    policy = json.loads((out / "policy.json").read_text(encoding="utf-8"))
    root = next(n for n in policy["nodes"] if n["id"] == policy["root"])
    root["args"]["q"] = "no_such_config"  # the executor now fails: not a configuration
    (out / "broken.json").write_text(json.dumps(policy), encoding="utf-8")
    capsys.readouterr()
    assert main(["execute", str(out / "broken.json"), "--runs", "2"]) == 3
    assert "failure 2" in capsys.readouterr().out


def test_unreachable_goal_is_an_input_error(tmp_path, capsys):
    shutil.copy(SHELF / "domain.stamp", tmp_path / "domain.stamp")
    problem = (SHELF / "problem.stamp").read_text(encoding="utf-8")
    (tmp_path / "problem.stamp").write_text(
        problem.replace("goal holding(can0)", "goal holding(can0)\n     is_tray(table)"),
        encoding="utf-8")
    code = main(["refine", str(tmp_path / "domain.stamp"), str(tmp_path / "problem.stamp"),
                 "--quiet"])
    assert code == 1


@pytest.mark.parametrize("options", [{"time_limit": 0}, {"time_limit": -5},
                                     {"time_limit": float("nan")}, {"target_coverage": 0},
                                     {"explore_probability": 2}, {"horizon": 0},
                                     {"warm_state_limit": 0}])
def test_the_api_refuses_the_limits_the_cli_refuses(options):
    import stampc
    from stampc.diagnostics import StampcError
    from stampc.refine import RefineOptions

    with pytest.raises(StampcError) as info:
        stampc.refine_policy([SHELF / "domain.stamp", SHELF / "problem.stamp"],
                             options=RefineOptions(**options))
    assert info.value.diagnostics[0].code in ("R001", "R002", "R003")


SHELF_DATA = Path(__file__).resolve().parents[1] / "refine" / "data"


def _refine_shelf(tmp_path, *flags: str) -> tuple[list[str], dict]:
    """Shelf seed 7 in UpdateAbstraction mode: its events and summary."""
    out = tmp_path / "run"
    code = main(["refine", str(SHELF_DATA / "shelf.stamp"), str(SHELF_DATA / "shelf5.stamp"),
                 "--seed", "7", "--update-probability", "1", "--quiet", "-o", str(out), *flags])
    assert code == 0
    events = [line.rsplit(",", 1)[-1] for line in
              (out / "coverage.csv").read_text().splitlines()[1:]]
    return events, json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("flags,resampled", [((), True), (("--no-resample-placers",), False)])
def test_no_resample_placers_reaches_the_engine(flags, resampled, tmp_path, capsys):
    """This seed re-draws a placement in the way unless ``--no-resample-placers``."""
    events, summary = _refine_shelf(tmp_path, *flags)
    assert ("resample" in events) == resampled
    assert summary["coverage"] == pytest.approx(1.0)


@pytest.mark.parametrize("flags,capped", [((), False), (("--solve-work-limit", "20"), True)])
def test_solve_work_limit_reaches_the_engine(flags, capped, tmp_path, capsys):
    _, summary = _refine_shelf(tmp_path, *flags)
    assert (summary["solver_timeouts"] > 0) == capped
    assert summary["coverage"] == pytest.approx(1.0)


def test_fixed_solve_cap_reaches_the_engine(tmp_path, capsys):
    """With a cap of 20 the shelf's solves are capped and answered by plans; the adaptive
    cap then quarters the next solves' caps, so more of them are capped than with
    ``--fixed-solve-cap``. Both cover everything."""
    _, adaptive = _refine_shelf(tmp_path / "a", "--solve-work-limit", "20")
    _, fixed = _refine_shelf(tmp_path / "f", "--solve-work-limit", "20", "--fixed-solve-cap")
    assert adaptive["solver_timeouts"] > fixed["solver_timeouts"] > 0
    assert adaptive["coverage"] == pytest.approx(1.0) == fixed["coverage"]


def _cli_options(*flags: str) -> RefineOptions:
    """The engine options ``stampc refine DOMAIN PROBLEM *flags`` builds."""
    import argparse

    from stampc.commands import refine as refine_command

    parser = argparse.ArgumentParser()
    refine_command.add_arguments(parser)
    return refine_command.refine_options(parser.parse_args([DOMAIN, PROBLEM2D, *flags]))


@pytest.mark.parametrize("flags,lock_free", [((), True), (("--fewest-facts",), False)])
def test_fewest_facts_reaches_the_engine_options(flags, lock_free):
    """``--fewest-facts`` turns the lock-free choice of learned facts off (the choice
    itself: tests/refine/test_learning_choice.py)."""
    assert _cli_options(*flags).learn_lock_free is lock_free


@pytest.mark.parametrize("flags,loss", [((), 1.0), (("--max-resample-loss", "0.25"), 0.25),
                                        (("--max-resample-loss", "none"), None)])
def test_max_resample_loss_reaches_the_engine_options(flags, loss):
    """``--max-resample-loss`` sets the limit on the covered mass a re-sample may discard
    (the rule itself: tests/refine/test_backtracking.py)."""
    assert _cli_options(*flags).max_resample_loss == loss


def test_the_command_line_defaults_are_the_engine_defaults():
    """``stampc refine`` without options runs the engine with ``RefineOptions()``: the
    command line states its defaults as literals (its help shows them, and importing the
    engine to read them would slow every command), so this pins the two together."""
    import dataclasses

    cli = _cli_options()
    library = RefineOptions()
    differ = [f.name for f in dataclasses.fields(library)
              if getattr(cli, f.name) != getattr(library, f.name)]
    assert differ == []


@pytest.mark.parametrize("value", ["-1", "nan", "inf", "lots"])
def test_a_bad_max_resample_loss_is_a_usage_error(value, capsys):
    assert main(["refine", DOMAIN, PROBLEM2D, "--max-resample-loss", value]) == 2
    err = capsys.readouterr().err
    assert "argument --max-resample-loss:" in err and "Traceback" not in err
