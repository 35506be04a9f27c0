"""Bad PPDDL inputs and their exact diagnostics (code, line, column).

Positions are located independently of the parser: ``_at`` finds the offending text
in the input. Every failure must be a StampcError carrying located diagnostics.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from stampc.backends.ppddl import import_ppddl, import_ppddl_text
from stampc.diagnostics import StampcError

DOMAIN = """(define (domain d)
  (:requirements :typing :probabilistic-effects :rewards)
  (:types block - object)
  (:predicates (on ?a ?b - block) (clear ?a - block))
  (:action move
    :parameters (?a ?b - block)
    :precondition (clear ?a)
    :effect (and (on ?a ?b) (not (clear ?b)))))
"""
PROBLEM = """(define (problem q) (:domain d) (:objects b1 b2 - block)
  (:init (clear b1)) (:goal (on b1 b2)))
"""


def _at(text: str, needle: str, nth: int = 0) -> tuple[int, int]:
    """1-based (line, column) of the ``nth`` occurrence of ``needle``."""
    pos = -1
    for _ in range(nth + 1):
        pos = text.index(needle, pos + 1)
    line = text.count("\n", 0, pos) + 1
    return line, pos - (text.rfind("\n", 0, pos) + 1) + 1


def _diag(text: str, **kwargs):
    with pytest.raises(StampcError) as info:
        import_ppddl_text(text, "bad.pddl", **kwargs)
    diags = info.value.diagnostics
    assert diags and all(d.span.file == "bad.pddl" for d in diags)
    return diags[0]


def _check(text, code, needle, nth=0, offset=0):
    """The first diagnostic with ``code`` starts at ``needle`` (+ ``offset`` columns)."""
    with pytest.raises(StampcError) as info:
        import_ppddl_text(text, "bad.pddl")
    diags = info.value.diagnostics
    assert all(d.span.file == "bad.pddl" for d in diags)
    d = next((d for d in diags if d.code == code), None)
    assert d is not None, diags
    line, col = _at(text, needle, nth)
    assert (d.span.line, d.span.col) == (line, col + offset), d
    return d


def test_valid_base_imports():
    m = import_ppddl_text(DOMAIN + PROBLEM, "ok.pddl")
    assert m.problem.name == "q" and len(m.domain.actions) == 1


def test_missing_close_paren_at_end_of_file():
    text = DOMAIN + PROBLEM.rstrip()[:-1]
    d = _diag(text)
    lines = text.split("\n")
    assert (d.code, d.span.line, d.span.col) == ("P100", len(lines), len(lines[-1]) + 1)
    assert "end of file" in d.message and "')'" in d.message


def test_unexpected_token_lists_expected_words():
    text = DOMAIN.replace(":parameters (?a ?b - block)", ":parameters (?a ?b - block) 42")
    d = _check(text + PROBLEM, "P100", "42")
    assert d.message.startswith("unexpected '42'; expected one of")
    assert "':effect'" in d.message and "':precondition'" in d.message


def test_unexpected_character():
    text = DOMAIN.replace("(clear ?a)\n", "(clear ?a) #\n")
    d = _check(text + PROBLEM, "P100", "#")
    assert "'#'" in d.message


def test_unsupported_section():
    text = DOMAIN.replace("(:action move", "(:durative-action m)\n  (:action move")
    _check(text + PROBLEM, "P101", ":durative-action")


def test_derived_rule_for_an_undeclared_predicate():
    text = DOMAIN.replace("(:action move", "(:derived (above ?a) (on ?a ?a))\n  (:action move")
    _check(text + PROBLEM, "P111", "above")


def test_either_type_rejected():
    text = DOMAIN.replace("(clear ?a - block))", "(clear ?a - (either block object)))")
    d = _check(text + PROBLEM, "P101", "(either")
    assert "either" in d.message


@pytest.mark.parametrize("flag", [":foo", ":durative-actions"])
def test_bad_requirement(flag):
    text = DOMAIN.replace(":rewards", f":rewards {flag}")
    _check(text + PROBLEM, "P102", flag)


def test_duplicate_predicate():
    text = DOMAIN.replace("(clear ?a - block))", "(clear ?a - block) (on ?x ?y))")
    _check(text + PROBLEM, "P103", "on", nth=1)


def test_missing_file(tmp_path):
    with pytest.raises(StampcError) as info:
        import_ppddl(tmp_path / "nope.pddl")
    d = info.value.diagnostics[0]
    assert d.code == "P104" and d.span.file.endswith("nope.pddl")


def test_problem_only_without_domain(tmp_path):
    (tmp_path / "p.pddl").write_text(PROBLEM)
    with pytest.raises(StampcError) as info:
        import_ppddl(tmp_path / "p.pddl")
    assert info.value.diagnostics[0].code == "P105"
    (tmp_path / "domain.pddl").write_text(DOMAIN)
    assert import_ppddl(tmp_path / "p.pddl").domain.name == "d"


def test_unknown_problem_name():
    d = _diag(DOMAIN + PROBLEM, problem_name="zz")
    assert d.code == "P105" and "'zz'" in d.message and "q" in d.message


def test_domain_mismatch():
    text = DOMAIN + PROBLEM.replace("(:domain d)", "(:domain other)")
    _check(text, "P106", "other")


def test_missing_goal():
    text = DOMAIN + PROBLEM.replace("(:goal (on b1 b2))", "")
    _check(text, "P107", "q) (:domain")


def test_undefined_type():
    text = DOMAIN.replace("(clear ?a - block)", "(clear ?a - blok)")
    _check(text + PROBLEM, "P110", "blok")


def test_undefined_predicate_in_effect():
    text = DOMAIN.replace("(not (clear ?b))", "(not (clean ?b))")
    _check(text + PROBLEM, "P111", "clean")


def test_undefined_object_in_goal():
    text = DOMAIN + PROBLEM.replace("(on b1 b2)", "(on b1 b3)")
    _check(text, "P112", "b3")


def test_undefined_variable():
    text = DOMAIN.replace(":precondition (clear ?a)", ":precondition (clear ?c)")
    _check(text + PROBLEM, "P113", "?c")


def test_arity():
    text = DOMAIN + PROBLEM.replace("(:init (clear b1))", "(:init (clear b1 b2))")
    d = _check(text, "P114", "(clear b1 b2)")
    assert "takes 1 argument, got 2" in d.message


def test_type_mismatch():
    text = DOMAIN.replace("(:types block - object)", "(:types block table - object)")
    text += PROBLEM.replace("(:objects b1 b2 - block)", "(:objects b1 b2 - block t - table)")
    text = text.replace("(:init (clear b1))", "(:init (clear t))")
    _check(text, "P115", "(clear t)", offset=len("(clear "))


def test_type_cycle():
    text = DOMAIN.replace("(:types block - object)", "(:types block - a a - block)")
    _check(text + PROBLEM, "P116", "block")


def test_undefined_fluent():
    text = DOMAIN.replace("(not (clear ?b))", "(not (clear ?b)) (decrease (fuel) 1)")
    _check(text + PROBLEM, "P117", "fuel")


@pytest.mark.parametrize("prob", ["1.5", "-0.5"])
def test_probability_out_of_range(prob):
    text = DOMAIN.replace("(on ?a ?b)", f"(probabilistic {prob} (on ?a ?b))")
    d = _check(text + PROBLEM, "P120", prob)
    assert "outside [0, 1]" in d.message


def test_probabilities_sum_above_one():
    text = DOMAIN.replace("(on ?a ?b)", "(probabilistic 2/3 (on ?a ?b) 0.5 (clear ?a))")
    d = _check(text + PROBLEM, "P121", "(probabilistic")
    assert "7/6" in d.message


def test_zero_denominator():
    text = DOMAIN.replace("(on ?a ?b)", "(probabilistic 1/0 (on ?a ?b))")
    _check(text + PROBLEM, "P122", "1/0")


def test_decrease_total_cost():
    text = DOMAIN.replace("(not (clear ?b))", "(not (clear ?b)) (decrease (total-cost) 1)")
    _check(text + PROBLEM, "P123", "(decrease")


def test_unsupported_metric():
    text = DOMAIN + PROBLEM.replace("(:goal (on b1 b2))", "(:goal (on b1 b2)) (:metric minimize (reward))")
    _check(text, "P123", "(:metric")


def test_several_errors_are_all_reported_in_order():
    text = DOMAIN.replace("(clear ?a)\n", "(clean ?a)\n").replace("(not (clear ?b))", "(not (clear ?z))")
    with pytest.raises(StampcError) as info:
        import_ppddl_text(text + PROBLEM, "bad.pddl")
    got = [(d.code, d.span.line, d.span.col) for d in info.value.diagnostics]
    assert got == [("P111", *_at(text, "clean")), ("P113", *_at(text, "?z"))]


# ------------------------------------------------------------- robustness
@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(min_value=0, max_value=len(DOMAIN + PROBLEM) - 1),
       st.sampled_from(["", "(", ")", "?", "-", "1/0", " and ", "x", ":effect", "\n;",
                        "(not " * 3000, "(and " * 3000, "(and (p) " * 3000 + ")" * 3000,
                        "(not (p)" + ")" * 3000]))
def test_mutations_never_raise_bare_exceptions(position, insert):
    """Any corruption of a valid file gives a Model or located StampcError, never a crash."""
    base = DOMAIN + PROBLEM
    text = base[:position] + insert + base[position + 1:]
    try:
        import_ppddl_text(text, "fuzz.pddl")
    except StampcError as exc:
        assert exc.diagnostics and all(d.span.line >= 1 and d.span.col >= 1
                                       for d in exc.diagnostics)


@settings(max_examples=100, deadline=None, derandomize=True)
@given(st.text(alphabet="()?-:; \nabcdefpq0123456789./", max_size=80))
def test_random_text_never_raises_bare_exceptions(text):
    try:
        import_ppddl_text(text, "fuzz.pddl")
    except StampcError as exc:
        assert exc.diagnostics
