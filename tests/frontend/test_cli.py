"""``stampc check`` behaviour: exit codes, JSON, --strict, finding a problem's domain."""

from __future__ import annotations

import json
from pathlib import Path

from stampc import cli
from stampc.commands import check as check_cmd

from .helpers import REPO, run_command

CLEAN = "domain d\ntype t\npredicate p(x: t)\naction a(x: t)\n    pre  p(x)\n    eff  not p(x)\n"


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_clean_file_exits_zero(tmp_path: Path) -> None:
    code, out, _ = run_command(check_cmd, [str(write(tmp_path, "d.stamp", CLEAN))])
    assert code == 0 and out.strip() == "0 errors, 0 warnings"


def test_missing_file_is_a_usage_error(tmp_path: Path) -> None:
    code, out, err = run_command(check_cmd, [str(tmp_path / "nope.stamp")])
    assert code == 2 and out == ""
    assert "cannot read" in err and "nope.stamp" in err


def test_warnings_fail_only_with_strict(tmp_path: Path) -> None:
    path = write(tmp_path, "d.stamp", CLEAN + "type spare\n")
    assert run_command(check_cmd, [str(path)])[0] == 0
    assert run_command(check_cmd, ["--strict", str(path)])[0] == 1


def test_json_format(tmp_path: Path) -> None:
    path = write(tmp_path, "d.stamp", "domain d\ntype t\npredicate p(x: u)\n")
    code, out, _ = run_command(check_cmd, ["--format", "json", str(path)])
    data = json.loads(out)
    assert code == 1
    error = next(d for d in data if d["severity"] == "error")
    assert error["code"] == "E101" and error["span"]["line"] == 3 and error["span"]["col"] == 16
    assert error["hint"] is not None


def test_problem_finds_domain_beside_it(tmp_path: Path) -> None:
    write(tmp_path, "domain.stamp", CLEAN)
    prob = write(tmp_path, "p1.stamp", "problem p1 for d\nobject a: t\ninit p(a)\ngoal not p(a)\n")
    assert run_command(check_cmd, [str(prob)])[0] == 0
    bad = write(tmp_path, "p2.stamp", "problem p2 for d\nobject a: t\ninit p(b)\ngoal not p(a)\n")
    code, out, _ = run_command(check_cmd, [str(bad)])
    assert code == 1 and "E103" in out and "p2.stamp:3:" in out


def test_problem_paired_with_domain_given_on_the_command_line(tmp_path: Path) -> None:
    dom = write(tmp_path, "blocks.stamp", CLEAN.replace("domain d", "domain blocks"))
    sub = tmp_path / "problems"
    sub.mkdir()
    prob = write(sub, "p.stamp", "problem p for blocks\nobject a: t\ninit p(a)\ngoal not p(a)\n")
    assert run_command(check_cmd, [str(prob)])[0] == 1  # not found beside the problem
    assert run_command(check_cmd, [str(dom), str(prob)])[0] == 0


def test_problem_for_wrong_domain(tmp_path: Path) -> None:
    write(tmp_path, "domain.stamp", CLEAN)
    prob = write(tmp_path, "p.stamp", "problem p for other\nobject a: t\n")
    code, out, _ = run_command(check_cmd, [str(prob)])
    assert code == 1 and "E107" in out and "is for domain `other`" in out


def test_use_relative_file_and_action_override(tmp_path: Path) -> None:
    write(tmp_path, "common.stamp", "module common\ntype t\npredicate p(x: t)\n"
                                    "action a(x: t)\n    pre  p(x)\n    eff  not p(x)\n")
    sub = tmp_path / "dom"
    sub.mkdir()
    dom = write(sub, "d.stamp", 'domain d\nuse "../common.stamp"\npredicate q(x: t)\n'
                                "action a(x: t)\n    pre  p(x), q(x)\n    eff  not p(x)\n")
    code, out, _ = run_command(check_cmd, [str(dom)])
    assert code == 0, out
    dup = write(sub, "e.stamp", 'domain e\nuse "../common.stamp"\ntype t\n')
    code, out, _ = run_command(check_cmd, [str(dup)])
    assert code == 1 and "E203" in out and "first defined here" in out


def test_cli_discovers_the_commands() -> None:
    parser = cli.build_parser()
    args = parser.parse_args(["check", str(REPO / "stdlib" / "manipulation.stamp")])
    assert args._run is check_cmd.run
    assert cli.main(["check", str(REPO / "stdlib" / "manipulation.stamp")]) == 0
