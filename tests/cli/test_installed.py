"""The README's commands, run as the installed ``stampc`` script from outside the
repository, with relative paths (from a copy of ``examples/``) and absolute ones."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from .paths import EXAMPLES, REPO

TINY_PPDDL = """\
(define (domain coin) (:requirements :probabilistic-effects)
  (:predicates (heads))
  (:action flip :effect (probabilistic 1/2 (heads))))
(define (problem once) (:domain coin) (:init) (:goal (heads)))
"""


def test_check_relative_and_absolute(cli, checkout, elsewhere):
    rel = cli.run("check", "examples/cluttered_table/domain.stamp", cwd=checkout)
    assert rel.code == 0, rel.err
    assert "0 errors" in rel.out
    absolute = cli.run("check", str(EXAMPLES / "cluttered_table" / "domain.stamp"),
                       str(EXAMPLES / "cluttered_table" / "problem.stamp"), cwd=elsewhere)
    assert absolute.code == 0, absolute.err


def test_fmt_prints_the_canonical_source(cli, checkout):
    result = cli.run("fmt", "examples/domino/domain.stamp", cwd=checkout)
    assert result.code == 0, result.err
    assert result.out == (EXAMPLES / "domino" / "domain.stamp").read_text(encoding="utf-8")
    check = cli.run("fmt", "--check", str(EXAMPLES / "domino" / "domain.stamp"), cwd=checkout)
    assert check.code == 0 and check.out == ""


def test_compile_to_ppddl(cli, checkout):
    result = cli.run("compile", "examples/keva/domain.stamp", "examples/keva/problem.stamp",
                     "--target", "ppddl", "-o", "out/", cwd=checkout)
    assert result.code == 0, result.err
    domain = (checkout / "out" / "domain.pddl").read_text(encoding="utf-8")
    assert "(define (domain keva" in domain
    assert "(define (problem" in (checkout / "out" / "problem.pddl").read_text(encoding="utf-8")


def test_solve_stamp_and_ppddl(cli, checkout, elsewhere):
    stamp = cli.run("solve", "examples/domino/domain.stamp", "examples/domino/problem.stamp",
                    "--format", "json", cwd=checkout)
    assert stamp.code == 0, stamp.err
    assert json.loads(stamp.out)["goal_probability"] == pytest.approx(1.0)
    (elsewhere / "coin.pddl").write_text(TINY_PPDDL, encoding="utf-8")
    coin = cli.run("solve", str(elsewhere / "coin.pddl"), "--unit-cost", "--format", "json",
                   "-o", "policy.json", cwd=elsewhere)
    assert coin.code == 0, coin.err
    assert json.loads(coin.out)["expected_cost"] == pytest.approx(2.0, abs=1e-3)
    assert (elsewhere / "policy.json").is_file()


@pytest.mark.parametrize("domain, problem", [("domain.stamp", "problem2d.stamp"),
                                             ("domain_fixed.stamp", "problem2d_fixed.stamp")])
def test_refine_plane2d_then_execute(cli, checkout, domain, problem):
    """The README's refine command on the 2-D world (the paper's mobile-base scene, and
    the fixed-base one): the scene builder module ``examples.cluttered_table.scene`` is
    not importable from here and is loaded from the file beside the problem (its
    ``@dataclass`` needs it in ``sys.modules``)."""
    refine = cli.run("refine", f"examples/cluttered_table/{domain}",
                     f"examples/cluttered_table/{problem}", "--world", "plane2d",
                     "--time-limit", "60", "--quiet", "-o", "out/", cwd=checkout)
    assert refine.code == 0, refine.err
    assert "coverage 1.0000" in refine.out
    policy = json.loads((checkout / "out" / "policy.json").read_text(encoding="utf-8"))
    # paths relative to policy.json (issue 13), the absolute ones kept as a fallback:
    # execute works from anywhere
    assert policy["files"][0] == f"../examples/cluttered_table/{domain}"
    assert all(Path(e["absolute"]).is_absolute() for e in policy["provenance"]["inputs"])
    execute = cli.run("execute", str(checkout / "out" / "policy.json"), "--runs", "3",
                      "--seed", "1", cwd=checkout.parent)
    assert execute.code == 0, execute.err
    assert "runs 3: success 3" in execute.out


def test_refine_pybullet_with_absolute_paths_then_execute(cli, elsewhere):
    refine = cli.run("refine", str(EXAMPLES / "domino" / "domain.stamp"),
                     str(EXAMPLES / "domino" / "problem.stamp"), "--world", "pybullet",
                     "--time-limit", "60", "--quiet", "-o", str(elsewhere / "out"),
                     cwd=elsewhere)
    assert refine.code == 0, refine.err
    execute = cli.run("execute", "out/policy.json", "--runs", "2", "--format", "json",
                      cwd=elsewhere)
    assert execute.code == 0, execute.err
    assert json.loads(execute.out)["success"] == 2


@pytest.mark.slow
def test_readme_refine_pybullet_and_execute_with_render(cli, checkout):
    """The README's own commands, verbatim (cluttered table, Panda, 15 cans)."""
    refine = cli.run("refine", "examples/cluttered_table/domain.stamp",
                     "examples/cluttered_table/problem.stamp", "--world", "pybullet",
                     "--time-limit", "120", "-o", "out/", cwd=checkout)
    assert refine.code == 0, refine.err
    execute = cli.run("execute", "out/policy.json", "--runs", "5", "--seed", "1",
                      "--render", "out/frames", cwd=checkout)
    assert execute.code == 0, execute.err
    assert (checkout / "out" / "frames" / "run.gif").is_file()


@pytest.mark.slow
def test_readme_python_api_snippet_as_a_script(cli, checkout, tmp_path):
    """The README's "Python API" block, verbatim, in a script outside the repository."""
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Python API", 1)[1]
    snippet = section.split("```python\n", 1)[1].split("```", 1)[0]
    script = tmp_path / "snippet.py"
    script.write_text(snippet, encoding="utf-8")
    result = cli.python(script, cwd=checkout)
    assert result.code == 0, result.err
    assert float(result.out.strip().splitlines()[-1]) == pytest.approx(1.0)
    assert (checkout / "out" / "policy.json").is_file()
