"""Property test: on any input the front end yields an AST or diagnostics, never another
exception; clean inputs also survive formatting and lowering.

``STAMPC_FUZZ_EXAMPLES=20000 python -m pytest tests/frontend/test_fuzz.py`` runs more
examples (default 300 per property).
"""

from __future__ import annotations

import os
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from stampc.diagnostics import Diagnostic, StampcError
from stampc.ir.lower import lower, lower_domain
from stampc.semantics.api import analyze, parse
from stampc.semantics.loader import source_from_text
from stampc.syntax import ast
from stampc.syntax.fmt import format_program
from stampc.syntax.parser import parse_source

from .helpers import EXAMPLES, REPO

EXAMPLES_COUNT = int(os.environ.get("STAMPC_FUZZ_EXAMPLES", "300"))
SETTINGS = settings(max_examples=EXAMPLES_COUNT, deadline=None, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

CORPUS = [p.read_text(encoding="utf-8") for p in
          [REPO / "stdlib" / "manipulation.stamp"]
          + [REPO / "examples" / n / f for n in EXAMPLES for f in ("domain.stamp", "problem.stamp")]
          + sorted((Path(__file__).parent / "golden").glob("*.stamp"))]
VOCAB = ["domain", "problem", "for", "use", "module", "type", "continuous", "static", "predicate",
         "function", "constant", "generator", "evaluator", "action", "pre", "eff", "cost", "executes",
         "sample", "from", "certifies", "binds", "budget", "option", "not", "and", "or", "implies",
         "forall", "exists", "when", "probabilistic", "nothing", "as", "object", "init", "goal",
         "horizon", "scene", "builder", "true", "false", "?", "(", ")", ",", ":", "=", "!=", "<",
         "->", "..", "+", "-", "*", "/", "0.5", "1/3", "2", "7", '"pkg.mod:f"', '".w:g"', '"',
         "x", "o", "p", "t", "can", "pose", "movable", "at", "holding", "\n", "\n    ", "\n        ",
         "\t", "#c\n", "é", "\x00", "[", ";", "\\"]


def run_front_end(text: str) -> None:
    program, diags = parse_source(text, "<fuzz>")
    assert isinstance(program, ast.Program)
    assert all(isinstance(d, Diagnostic) and d.span.line >= 1 and d.span.col >= 1 for d in diags)
    if not diags:
        formatted = format_program(program, text)
        assert parse(formatted) == program
    for loaded in analyze([source_from_text(text, "<fuzz>")]):
        assert all(isinstance(d, Diagnostic) for d in loaded.diagnostics)
        if loaded.has_errors or loaded.domain is None:
            continue
        assert lower_domain(loaded).name == loaded.domain.name
        if loaded.problem is not None:
            try:
                lower(loaded)
            except StampcError as exc:  # only a problem whose domain is absent may fail
                assert {d.code for d in exc.diagnostics} <= {"E501"}


@st.composite
def mutated(draw) -> str:
    text = draw(st.sampled_from(CORPUS))
    for _ in range(draw(st.integers(1, 4))):
        if not text:
            break
        i = draw(st.integers(0, len(text) - 1))
        j = draw(st.integers(i, min(len(text), i + 12)))
        op = draw(st.sampled_from(["delete", "insert", "replace", "duplicate"]))
        if op == "delete":
            text = text[:i] + text[j:]
        elif op == "insert":
            text = text[:i] + draw(st.sampled_from(VOCAB)) + text[i:]
        elif op == "replace":
            text = text[:i] + draw(st.sampled_from(VOCAB)) + text[j:]
        else:
            text = text[:j] + text[i:j] + text[j:]
    return text


token_soup = st.lists(st.sampled_from(VOCAB), max_size=60).map(" ".join)


@SETTINGS
@given(mutated())
def test_mutated_sources_never_crash(text: str) -> None:
    run_front_end(text)


@SETTINGS
@given(token_soup)
def test_token_soup_never_crashes(text: str) -> None:
    run_front_end(text)


@SETTINGS
@given(st.text(max_size=200))
def test_arbitrary_text_never_crashes(text: str) -> None:
    run_front_end(text)


# deep nesting: a random pattern of wrappers repeated to a random depth, around the
# limit (E006 above it) or far past it (10,000 levels)
FORMULA_WRAPPERS = ["not {}", "exists (y: t) {}", "forall (y: t) {}", "(p(x) or {})", "(q(x) and ({} or p(x)))",
                    "p(x) implies {}", "({})"]
EFFECT_WRAPPERS = ["when p(x): {}", "forall (y: t): {}", "probabilistic 1/2: {}"]
DEEP_HEADER = "domain d\ntype t\npredicate p(x: t)\npredicate q(x: t)\nfunction f(x: t)\n"
DEEP_PROBLEM = "problem pr for d\nobject o: t\ninit p(o), f(o) = 2\ngoal q(o)\n"


def nest(pattern: list[str], depth: int, leaf: str) -> str:
    text = leaf
    for i in range(depth):
        text = pattern[i % len(pattern)].format(text)
    return text


@st.composite
def deep_sources(draw) -> str:
    depth = draw(st.one_of(st.integers(1, 260), st.integers(9_990, 10_000)))
    where = draw(st.sampled_from(["pre", "eff", "cost", "goal"]))
    if where == "eff":
        pattern = draw(st.lists(st.sampled_from(EFFECT_WRAPPERS), min_size=1, max_size=3))
        body = "    pre  p(x)\n    eff  " + nest(pattern, depth, "q(x)") + "\n"
    elif where == "cost":
        body = "    pre  p(x)\n    eff  q(x)\n    cost " + " + ".join(["f(x)"] * depth) + "\n"
    else:
        pattern = draw(st.lists(st.sampled_from(FORMULA_WRAPPERS), min_size=1, max_size=3))
        formula = nest(pattern, depth, "p(x)" if where == "pre" else "q(o)")
        body = f"    pre  {formula if where == 'pre' else 'p(x)'}\n    eff  q(x)\n"
        if where == "goal":
            return DEEP_HEADER + "action a(x: t)\n" + body + DEEP_PROBLEM.replace("goal q(o)", f"goal {formula}")
    return DEEP_HEADER + "action a(x: t)\n" + body + DEEP_PROBLEM


@settings(max_examples=min(EXAMPLES_COUNT, 30), deadline=None, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(deep_sources())
def test_deep_nesting_is_handled_or_e006(text: str) -> None:
    run_front_end(text)
    codes = {d.code for d in parse_source(text, "<fuzz>")[1]}
    assert codes <= {"E006"}
    assert codes or text.count("\n") < 40  # every 10,000-deep case is over the limit
