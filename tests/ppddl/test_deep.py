"""Deep nesting: 10,000-deep PPDDL is read without recursion or stops with a located P108.

``and``/``or`` chains of any depth are flattened while reading; other constructs stop
at ``MAX_NESTING`` levels; at exactly that depth import, grounding, emission and
solving all work.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from stampc.api import ground, solve
from stampc.backends.ppddl import emit_ppddl, import_ppddl_text
from stampc.backends.ppddl.shape_base import MAX_NESTING
from stampc.diagnostics import StampcError

DEEP = 10_000


def _domain(pre: str = "(p)", eff: str = "(done)") -> str:
    return f"""(define (domain d) (:requirements :negative-preconditions :probabilistic-effects
    :conditional-effects :rewards)
 (:predicates (p) (q) (done))
 (:action a :precondition {pre} :effect {eff}))
(define (problem x) (:domain d) (:init (p)) (:goal (done)))
"""


def _nest(opening: str, inner: str, depth: int) -> str:
    return opening * depth + inner + ")" * depth


def _round_trip_cost(text: str) -> float:
    """Import, emit, re-import, ground and solve: the expected cost from the initial state."""
    model = import_ppddl_text(text, "deep.pddl")
    domain_text, problem_text = emit_ppddl(model)
    again = import_ppddl_text(domain_text + problem_text, "again.pddl")
    assert again.domain.actions == model.domain.actions
    return solve(ground(again)).expected_cost


def _error(text: str):
    with pytest.raises(StampcError) as info:
        import_ppddl_text(text, "deep.pddl")
    return info.value.diagnostics[0]


@pytest.mark.parametrize("connective", ["and", "or"])
def test_ten_thousand_nested_and_or_in_a_precondition(connective):
    text = _domain(pre=_nest(f"({connective} (p) ", "(p)", DEEP))
    assert _round_trip_cost(text) == 1.0
    model = import_ppddl_text(text, "deep.pddl")
    assert len(model.domain.actions[0].precondition.args) == DEEP + 1  # flattened


def test_ten_thousand_nested_and_in_an_effect():
    assert _round_trip_cost(_domain(eff=_nest("(and ", "(done)", DEEP))) == 1.0


@pytest.mark.parametrize("opening, inner, where", [
    ("(not ", "(q)", "pre"),
    ("(imply (p) ", "(p)", "pre"),
    ("(exists (?x) ", "(p)", "pre"),
    ("(probabilistic 1 ", "(done)", "eff"),
    ("(when (p) ", "(done)", "eff"),
    ("(+ 1 ", "1", "eff"),  # arithmetic, inside (decrease (reward) ...)
])
def test_ten_thousand_deep_other_constructs_stop_with_a_located_p108(opening, inner, where):
    nested = _nest(opening, inner, DEEP)
    if opening.startswith("(+"):
        nested = f"(decrease (reward) {nested})"
    text = _domain(**{where: nested})
    d = _error(text)
    assert d.code == "P108" and str(MAX_NESTING) in d.message and d.hint
    # located at the construct one level too deep, on the action's line
    assert d.span.line == 4 and d.span.col > 1


@pytest.mark.parametrize("opening, inner, where", [
    ("(not ", "(p)", "pre"),  # an even number of nots: holds as (p) does
    ("(when (p) ", "(done)", "eff"),
    ("(probabilistic 1 ", "(done)", "eff"),
    ("(forall (?x) ", "(p)", "pre"),
])
def test_the_deepest_accepted_nesting_grounds_emits_and_solves(opening, inner, where):
    assert MAX_NESTING % 2 == 0
    assert _round_trip_cost(_domain(**{where: _nest(opening, inner, MAX_NESTING)})) == 1.0
    with pytest.raises(StampcError):
        import_ppddl_text(_domain(**{where: _nest(opening, inner, MAX_NESTING + 1)}), "x.pddl")


def test_ten_thousand_open_parentheses_is_a_located_syntax_error():
    text = _domain() + "(" * DEEP
    d = _error(text)
    assert d.code == "P100" and "end of file" in d.message
    assert d.span.line == text.count("\n") + 1


def test_ten_thousand_nested_empty_lists_are_a_syntax_error():
    d = _error(_domain(pre=_nest("(", "", DEEP)))
    assert d.code == "P100" and (d.span.line, d.span.col) == (4, 28)


_CONNECTIVES = st.sampled_from(["(and ", "(or ", "(not ", "(imply (p) ", "(forall (?x) ",
                                "(and (p) ", "(or (q) "])


@settings(max_examples=60, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(st.lists(_CONNECTIVES, min_size=1, max_size=40), st.integers(1, 300))
def test_fuzz_deep_mixed_nesting_never_raises_recursion_error(pattern, repeat):
    """Random connective sequences repeated up to 12,000 levels: a model or P108."""
    openings = (pattern * repeat)[:DEEP + 2000]
    text = _domain(pre="".join(openings) + "(p)" + ")" * len(openings))
    try:
        model = import_ppddl_text(text, "fuzz.pddl")
    except StampcError as exc:
        assert [d.code for d in exc.diagnostics] == ["P108"]
        return
    ground(model)
    emit_ppddl(model)
