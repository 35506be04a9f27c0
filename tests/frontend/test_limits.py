"""Hard inputs: 10,000-deep nesting stops at the documented limit (E006, located, exit
1) in check, check --format json, fmt and compile; nesting at the limit works in a
thread with a small stack and the default recursion limit."""

from __future__ import annotations

import contextlib
import io
import json
import sys
import threading
from pathlib import Path

import pytest

from stampc.cli import main
from stampc.semantics.api import check
from stampc.syntax.depth import MAX_NESTING

HEADER = ("domain d\ntype t\npredicate p(x: t)\npredicate q(x: t)\nfunction f(x: t)\n")
PROBLEM = "problem pr for d\nobject o1: t\ninit p(o1), f(o1) = 1\ngoal q(o1)\n"


def action(pre: str = "p(x)", eff: str = "q(x)", cost: str = "1") -> str:
    return f"action a(x: t)\n    pre  {pre}\n    eff  {eff}\n    cost {cost}\n"


def chains(n: int) -> dict[str, str]:
    """Sources nested ``n - 1`` levels deep (operators; atoms are no level), one per kind."""
    return {
        "not": action(pre="not " * (n - 1) + "p(x)"),
        "or": action(pre="(p(x) or " * (n - 1) + "p(x)" + ")" * (n - 1)),
        "and-or": action(pre="(p(x) and (q(x) or " * ((n - 1) // 2) + "p(x)" + "))" * ((n - 1) // 2)),
        "implies": action(pre="p(x) implies " * (n - 1) + "p(x)"),
        "exists": action(pre="".join(f"exists (y{i}: t) " for i in range(n - 1)) + "p(x)"),
        "when": action(eff="when p(x): " * (n - 1) + "q(x)"),
        "forall-effect": action(eff="".join(f"forall (y{i}: t) " for i in range(n - 1)) + "q(x)"),
        "cost": action(cost=" + ".join(["f(x)"] * n)),
    }


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = exc.code
    return code, out.getvalue(), err.getvalue()


def in_small_thread(fn, stack_kib: int = 256):
    """Run ``fn`` in a thread with a small C stack (default recursion limit); return
    its result or re-raise what it raised."""
    result: list = []

    def target() -> None:
        try:
            result.append(("ok", fn()))
        except BaseException as exc:  # noqa: BLE001 - handed to the test thread
            result.append(("raised", exc))

    old = threading.stack_size(stack_kib * 1024)
    try:
        thread = threading.Thread(target=target)
        thread.start()
    finally:
        threading.stack_size(old)
    thread.join()
    kind, value = result[0]
    if kind == "raised":
        raise value
    return value


def test_recursion_limit_is_the_default() -> None:
    assert sys.getrecursionlimit() <= 1000  # what the at-limit tests rely on


FAST = {"not", "when", "cost"}  # the other kinds run with the slow marker


@pytest.mark.parametrize("kind", [k if k in FAST else pytest.param(k, marks=pytest.mark.slow)
                                  for k in sorted(chains(10))])
def test_ten_thousand_deep_is_e006_in_every_command(kind: str, tmp_path: Path) -> None:
    source = HEADER + chains(10_000)[kind] + PROBLEM
    path = tmp_path / "deep.stamp"
    path.write_text(source, encoding="utf-8")
    code, out, err = run_cli(["check", str(path)])
    assert code == 1 and "E006 error: nesting deeper than 200 levels" in out
    assert f"{path}:7:" in out or f"{path}:8:" in out or f"{path}:9:" in out  # located in the action
    code, out, _ = run_cli(["check", "--format", "json", str(path)])
    diags = json.loads(out)
    assert code == 1 and [d["code"] for d in diags] == ["E006"]
    assert diags[0]["span"]["line"] in (7, 8, 9) and diags[0]["span"]["col"] > 1
    code, out, err = run_cli(["fmt", str(path)])
    assert code == 1 and out == "" and "E006" in err
    code, out, err = run_cli(["compile", str(path), "-o", str(tmp_path / "out")])
    assert code == 1 and "E006" in out + err and not (tmp_path / "out" / "lifted.json").exists()


def test_e006_points_at_the_first_node_past_the_limit() -> None:
    source = HEADER + action(pre="not " * (MAX_NESTING + 5) + "p(x)")
    [diag] = check(source)
    assert diag.code == "E006" and diag.span.line == 7
    assert diag.span.col == len("    pre  ") + 1 + 4 * MAX_NESTING  # the 201st `not`
    assert "flatten" in (diag.hint or "")


def test_limit_is_exact() -> None:
    assert check(HEADER + action(pre="not " * MAX_NESTING + "p(x)")) == []
    assert [d.code for d in check(HEADER + action(pre="not " * (MAX_NESTING + 1) + "p(x)"))] == ["E006"]


@pytest.mark.parametrize("kind", ["not", "or", "implies", "when", "forall-effect", "cost"])
def test_at_the_limit_every_command_works_in_a_small_thread(kind: str, tmp_path: Path) -> None:
    source = HEADER + chains(MAX_NESTING + 1)[kind] + PROBLEM
    path = tmp_path / "deep.stamp"
    path.write_text(source, encoding="utf-8")

    def commands() -> list:
        return [run_cli(["check", str(path)]), run_cli(["check", "--format", "json", str(path)]),
                run_cli(["fmt", str(path)]), run_cli(["compile", str(path), "-o", str(tmp_path / "ir")]),
                run_cli(["compile", "--target", "ppddl", str(path), "-o", str(tmp_path / "pddl")])]

    check_run, json_run, fmt_run, ir_run, pddl_run = in_small_thread(commands)
    assert check_run[0] == 0 and "0 errors" in check_run[1]
    assert json_run[0] == 0 and json.loads(json_run[1]) == []
    assert fmt_run[0] == 0
    formatted = tmp_path / "formatted.stamp"
    formatted.write_text(fmt_run[1], encoding="utf-8")
    assert in_small_thread(lambda: run_cli(["fmt", str(formatted)]))[1] == fmt_run[1]  # a fixed point
    assert ir_run[0] == 0 and (tmp_path / "ir" / "lifted.json").exists()
    assert pddl_run[0] == 0 and (tmp_path / "pddl" / "domain.pddl").exists()


def test_bom_is_ignored_and_columns_stay_right(tmp_path: Path) -> None:
    path = tmp_path / "bom.stamp"
    path.write_bytes(b"\xef\xbb\xbf" + (HEADER + action(pre="p(x) and r(x)")).encode("utf-8"))
    code, out, _ = run_cli(["check", str(path)])
    assert code == 1 and f"{path}:7:19: E102" in out  # `r` is column 19 of line 7
    assert "   7 |     pre  p(x) and r(x)\n     |                   ^" in out
    path.write_bytes(b"\xef\xbb\xbf# comment\n" + (HEADER + action()).encode("utf-8"))
    code, out, _ = run_cli(["fmt", str(path)])
    assert code == 0 and out.startswith("# comment\ndomain d\n")


UNICODE = """domain café
type bloc
predicate posé(x: bloc)
predicate sur(x: bloc)
action poser(b: bloc)
    pre  sur(b)
    eff  posé(b), not sur(b)
problem p for café
object 箱1, box2: bloc
init sur(箱1)
goal posé(箱1)
"""


def test_unicode_names_check_format_and_emit_ascii_ppddl(tmp_path: Path) -> None:
    path = tmp_path / "u.stamp"
    path.write_text(UNICODE, encoding="utf-8")
    assert run_cli(["check", str(path)])[0] == 0
    code, out, _ = run_cli(["fmt", str(path)])
    assert code == 0 and "predicate posé(x: bloc)" in out and "object 箱1, box2: bloc" in out
    code, _, _ = run_cli(["compile", "--target", "ppddl", str(path), "-o", str(tmp_path / "pddl")])
    domain = (tmp_path / "pddl" / "domain.pddl").read_text(encoding="utf-8")
    problem = (tmp_path / "pddl" / "problem.pddl").read_text(encoding="utf-8")
    body = [line for line in (domain + problem).splitlines() if not line.startswith(";")]
    assert code == 0 and all(line.isascii() for line in body)
    assert "renamed predicate 'posé'" in domain


def test_decomposed_accent_is_the_same_name() -> None:
    decomposed = UNICODE.replace("goal posé(箱1)", "goal pose\u0301(箱1)")
    assert check(decomposed) == []


@pytest.mark.parametrize("text, char", [("x\u00b2", "²"), ("a\u2192b", "→"), ("p\u00a0q", "\u00a0")])
def test_other_non_ascii_is_e001_naming_the_character(text: str, char: str) -> None:
    source = HEADER.replace("predicate q(x: t)", f"predicate {text}(x: t)")
    [diag] = check(source)
    assert diag.code == "E001" and diag.span.line == 4
    assert f"U+{ord(char):04X}" in (diag.hint or "")


def test_python_api_raises_stampc_error_not_recursion_error() -> None:
    from stampc.diagnostics import StampcError
    from stampc.semantics.api import parse
    with pytest.raises(StampcError) as info:
        parse(HEADER + chains(10_000)["not"])
    assert [d.code for d in info.value.diagnostics] == ["E006"]


@pytest.mark.parametrize("joiner", ["and", "or"])
def test_long_flat_chains_are_one_node_and_one_level(joiner: str) -> None:
    from stampc.syntax.parser import parse_source
    source = HEADER + action(pre=f" {joiner} ".join(["p(x)"] * 20_000))
    program, diags = parse_source(source)
    assert diags == [] and len(program.decls[-1].pre.args) == 20_000
    assert check(source) == []
