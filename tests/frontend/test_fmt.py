"""The canonical printer: parse(fmt(x)) == x, idempotence, comments kept."""

from __future__ import annotations

from pathlib import Path

import pytest

from stampc.commands import fmt as fmt_cmd
from stampc.semantics.api import parse
from stampc.syntax.fmt import format_program

from .helpers import EXAMPLES, REPO, run_command

FILES = [REPO / "stdlib" / "manipulation.stamp"] + [
    REPO / "examples" / name / f for name in EXAMPLES for f in ("domain.stamp", "problem.stamp")]


@pytest.mark.parametrize("path", FILES, ids=[str(p.relative_to(REPO)) for p in FILES])
def test_roundtrip_and_idempotence(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    program = parse(text, str(path))
    once = format_program(program, text)
    assert parse(once) == program
    assert format_program(parse(once), once) == once


def test_every_comment_survives_formatting() -> None:
    text = (REPO / "examples" / "cluttered_table" / "domain.stamp").read_text(encoding="utf-8")
    out = format_program(parse(text), text)
    comments = [line[line.index("#"):].strip() for line in text.splitlines() if "#" in line]
    for c in comments:
        assert c in out


def test_canonical_layout_of_an_action() -> None:
    messy = ("action  a( x : t,y:t )\n      eff   probabilistic\n          0.5 : p( x ),q(y)\n"
             "      pre p(x),\n          q(y)\n")
    expected = ("action a(x: t, y: t)\n    pre  p(x)\n         q(y)\n    eff  probabilistic\n"
                "             0.5: p(x), q(y)\n")
    assert format_program(parse(messy)) == expected


def test_parenthesizes_by_precedence() -> None:
    src = "goal (a or b) and not (c and d), forall (x: t) (p(x) implies q(x)), (a implies b) implies c\n"
    out = format_program(parse("problem p for d\n" + src))
    assert "goal a or b\n     not (c and d)\n" in out  # top-level `and` is one conjunct per line
    assert "(a or b)" in format_program(parse("problem p for d\ngoal (a or b) and c or d\n"))
    assert "     forall (x: t) (p(x) implies q(x))" in out
    assert "     (a implies b) implies c" in out


def test_fmt_command_check_and_errors(tmp_path: Path) -> None:
    good = tmp_path / "good.stamp"
    good.write_text("domain d\n\ntype t\n", encoding="utf-8")
    bad = tmp_path / "bad.stamp"
    bad.write_text("domain d\ntype\n", encoding="utf-8")
    messy = tmp_path / "messy.stamp"
    messy.write_text("domain d\ntype   t\n", encoding="utf-8")
    assert run_command(fmt_cmd, ["--check", str(good)])[0] == 0
    code, out, _ = run_command(fmt_cmd, ["--check", str(messy)])
    assert code == 1 and "would reformat" in out
    code, _, err = run_command(fmt_cmd, [str(bad)])
    assert code == 1 and "E001" in err
    assert run_command(fmt_cmd, ["-w", str(messy)])[0] == 0
    assert messy.read_text(encoding="utf-8") == "domain d\n\ntype t\n"
    assert run_command(fmt_cmd, [str(tmp_path / "missing.stamp")])[0] == 2
