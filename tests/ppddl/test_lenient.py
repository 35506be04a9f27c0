"""--lenient (API ``lenient=True``): what mdp-lib's mini-gpt parser accepts, as warnings
with implicit declarations; without it the same inputs are errors whose hint names
--lenient. Also FOND ``oneof`` (P109)."""

from __future__ import annotations

import pytest

import stampc
from stampc.api import ground, solve
from stampc.backends.ppddl import import_ppddl_text
from stampc.diagnostics import Severity, StampcError

DOMAIN = """(define (domain d)
  (:requirements :typing)
  (:types cell)
  (:predicates (at ?c - cell) (adj ?a ?b - cell))
  (:action move
    :parameters (?a ?b - cell)
    :precondition (and (at ?a) (adj ?a ?b) (not (terminated)))
    :effect (and (not (at ?a)) (at ?b) (when (= ?b c3) (terminated)))))
"""
PROBLEM = """(define (problem p) (:domain d) (:objects c1 c2 c3 - cell)
  (:init (at c1) (adj c1 c2) (adj c2 c3) (init))
  (:goal (terminated)))
"""


def _at(text: str, needle: str) -> tuple[int, int]:
    pos = text.index(needle)
    return text.count("\n", 0, pos) + 1, pos - (text.rfind("\n", 0, pos) + 1) + 1


def _well_formed() -> str:
    """DOMAIN + PROBLEM without the undeclared predicates and the constant."""
    text = DOMAIN.replace("(not (terminated))", "").replace("(when (= ?b c3) (terminated))", "")
    return text + PROBLEM.replace("(:goal (terminated))", "(:goal (at c3))").replace(" (init)", "")


def _warnings(model) -> list[tuple[str, int, int]]:
    assert all(d.severity is Severity.WARNING for d in model.diagnostics)
    return [(d.code, d.span.line, d.span.col) for d in model.diagnostics]


def _errors(text: str) -> list:
    with pytest.raises(StampcError) as info:
        import_ppddl_text(text, "strict.pddl")
    return info.value.diagnostics


def test_undeclared_predicates_are_declared_implicitly_with_their_arity():
    text = DOMAIN + PROBLEM
    model = import_ppddl_text(text, "l.pddl", lenient=True)
    preds = {p.name: p for p in model.domain.predicates}
    assert len(preds["terminated"].params) == 0 and not preds["terminated"].static
    assert preds["init"].static and preds["init"].params == ()  # only the problem uses it
    assert _warnings(model) == [("P201", *_at(text, "terminated")),
                                ("P202", *_at(text, "c3)")),
                                ("P201", *_at(text, "init)"))]
    # the implicit predicates work: c1 -> c2 -> c3 sets (terminated), 2 steps
    assert solve(ground(model)).expected_cost == 2.0


def test_problem_objects_used_in_the_domain_become_constants_of_the_inferred_type():
    model = import_ppddl_text(DOMAIN + PROBLEM, "l.pddl", lenient=True)
    assert [(c.name, c.type) for c in model.domain.constants] == [("c3", "cell")]
    assert [o.name for o in model.problem.objects] == ["c1", "c2"]  # c3 is the constant


def test_without_lenient_each_case_is_an_error_whose_hint_names_lenient():
    diags = _errors(DOMAIN + PROBLEM)
    assert {d.code for d in diags} == {"P111", "P112"}
    assert all("--lenient" in d.hint for d in diags)


def test_repeated_variable_in_a_predicate_declaration():
    text = _well_formed().replace("(adj ?a ?b - cell)", "(adj ?a ?a - cell)")
    model = import_ppddl_text(text, "l.pddl", lenient=True)
    assert _warnings(model) == [("P203", *_at(text, "?a - cell)"))]
    assert len(next(p for p in model.domain.predicates if p.name == "adj").params) == 2
    strict = _errors(text)
    assert [d.code for d in strict] == ["P103"] and "--lenient" in strict[0].hint


def test_a_repeated_action_parameter_stays_an_error_even_when_lenient():
    text = DOMAIN.replace(":parameters (?a ?b - cell)", ":parameters (?a ?a - cell)")
    with pytest.raises(StampcError) as info:
        import_ppddl_text(text + PROBLEM, "l.pddl", lenient=True)
    assert "P103" in [d.code for d in info.value.diagnostics]


def test_a_problem_without_goal_has_the_goal_false_as_in_mini_gpt():
    text = _well_formed().replace("(:goal (at c3))", "")
    model = import_ppddl_text(text, "l.pddl", lenient=True)
    assert _warnings(model) == [("P204", *_at(text, "p) (:domain"))]
    gm = ground(model)
    assert gm.goal.never  # no state is a goal
    strict = _errors(text)
    assert [d.code for d in strict] == ["P107"] and "--lenient" in strict[0].hint


def test_lenient_changes_nothing_on_a_well_formed_file():
    text = _well_formed()
    strict = import_ppddl_text(text, "ok.pddl")
    lenient = import_ppddl_text(text, "ok.pddl", lenient=True)
    assert strict == lenient and lenient.diagnostics == ()


def test_public_api_takes_lenient(tmp_path):
    path = tmp_path / "both.pddl"
    path.write_text(DOMAIN + PROBLEM)
    with pytest.raises(StampcError):
        stampc.import_ppddl(path)
    model = stampc.import_ppddl(path, lenient=True)
    assert {d.code for d in model.diagnostics} == {"P201", "P202"}
    assert stampc.load_model([path], lenient=True).diagnostics == model.diagnostics


# ---------------------------------------------------------------- FOND oneof
@pytest.mark.parametrize("effect", ["(oneof (at ?b) (at ?a))", "(and (oneof (at ?b)) (at ?a))"])
def test_oneof_is_its_own_code_saying_fond_is_not_supported(effect):
    text = DOMAIN.replace("(and (not (at ?a)) (at ?b) (when (= ?b c3) (terminated)))", effect)
    diags = _errors(text + PROBLEM)
    d = diags[0]
    assert len(diags) == 1 and d.code == "P109"
    assert (d.span.line, d.span.col) == _at(text, "oneof")
    assert "FOND" in d.message and "probabilistic" in d.hint


def test_emitting_a_lenient_import_gives_a_file_strict_import_reads():
    from stampc.backends.ppddl import emit_ppddl

    model = import_ppddl_text(DOMAIN + PROBLEM, "l.pddl", lenient=True)
    domain_text, problem_text = emit_ppddl(model)
    again = import_ppddl_text(domain_text + problem_text, "again.pddl")  # not lenient
    assert again.diagnostics == () and again.problem == model.problem
    assert again.domain.predicates == model.domain.predicates
    assert again.domain.constants == model.domain.constants
    assert again.domain.actions == model.domain.actions
