"""Recursive derived predicates over fluents (ground axiom programs, docs/ir.md): the
blocksworld ``above`` (transitive closure of ``on``) against a hand-unrolled domain
without recursion (``derived/above-unrolled.pddl``), in PPDDL and in the stamp language."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import stampc
from stampc.backends.ppddl import import_ppddl_text
from stampc.ir.grounded import GroundAtom
from stampc.ir.json_io import grounded_from_json, grounded_to_json
from stampc.ir.lower import lower
from stampc.semantics.api import load
from stampc.solvers.heuristics import make_heuristic
from stampc.solvers.lmcut import LMCut
from stampc.solvers.solution import SolverOptions
from stampc.solvers.successors import SuccessorCache

from .states import reachable_fact_sets, reachable_states

HERE = Path(__file__).resolve().parent / "derived"
BLOCKS = ("table", "a", "b", "c", "d")


def imported(domain: str, problem: str):
    return import_ppddl_text((HERE / problem).read_text(), problem,
                             domain_text=(HERE / domain).read_text(), domain_filename=domain)


@pytest.fixture(scope="module")
def axioms_model():
    return stampc.ground(imported("above-domain.pddl", "above-problem.pddl"))


@pytest.fixture(scope="module")
def unrolled_model():
    return stampc.ground(imported("above-unrolled.pddl", "above-unrolled-problem.pddl"))


def closure(on: set[tuple[str, str]]) -> set[tuple[str, str]]:
    """The transitive closure of ``on``, computed independently of stampc."""
    above = set(on)
    while True:
        more = {(x, z) for x, y in above for y2, z in on if y == y2} - above
        if not more:
            return above
        above |= more


def pairs(gm, state: int, predicate: str) -> set[tuple[str, str]]:
    return {f.args for f in gm.state_facts(state) if f.predicate == predicate}


def test_recursive_fluent_predicate_is_kept_as_a_ground_axiom_program(axioms_model):
    gm = axioms_model
    derived = {gm.facts[i] for i in range(len(gm.facts)) if (gm.axioms.derived >> i) & 1}
    assert derived and all(f.predicate == "above" for f in derived)
    assert {r.stratum for r in gm.axioms.rules} == {0}
    assert pairs(gm, gm.init, "above") == closure(pairs(gm, gm.init, "on")) == {
        ("a", "b"), ("a", "table"), ("b", "table"), ("c", "d"), ("c", "table"), ("d", "table")}


def test_same_reachable_states_as_the_unrolled_domain(axioms_model, unrolled_model):
    space = reachable_fact_sets(axioms_model, {"on", "done"})
    assert space == reachable_fact_sets(unrolled_model, {"on", "done"}) and len(space) == 146


def test_every_reachable_state_is_closed_under_the_axioms(axioms_model):
    gm = axioms_model
    states = reachable_states(gm)
    for s in states:
        assert gm.axioms.close(s) == s
        assert pairs(gm, s, "above") == closure(pairs(gm, s, "on"))
    cache = SuccessorCache(gm)  # the solvers' successor function closes states too
    nexts = {n for s in states for a in cache.applicable(s) for _, n, _ in cache.outcomes(s, a)}
    assert nexts <= states and len(nexts) > 100


@settings(max_examples=60, deadline=None)
@given(st.sets(st.tuples(st.sampled_from(BLOCKS[1:]), st.sampled_from(BLOCKS))),
       st.integers(min_value=0))
def test_closing_any_state_derives_the_transitive_closure(on, noise):
    gm = stampc.ground(imported("above-domain.pddl", "above-problem.pddl"))
    basic = gm.state_of(GroundAtom("on", p) for p in on if gm.has_fact(GroundAtom("on", p)))
    state = basic | (noise & gm.axioms.derived)  # stale derived facts must not survive
    closed = gm.axioms.close(state)
    assert closed & ~gm.axioms.derived == basic
    assert pairs(gm, closed, "above") == {p for p in closure(pairs(gm, basic, "on"))
                                          if gm.has_fact(GroundAtom("above", p))}
    assert gm.axioms.close(closed) == closed


@pytest.mark.parametrize("algorithm", ["lao", "vi", "lrtdp"])
def test_solvers_agree_with_the_unrolled_domain(axioms_model, unrolled_model, algorithm):
    options = SolverOptions(algorithm=algorithm)
    a, b = stampc.solve(axioms_model, options), stampc.solve(unrolled_model, options)
    assert a.goal_probability == b.goal_probability == 1.0
    assert a.expected_cost == pytest.approx(b.expected_cost, abs=1e-3)
    assert a.expected_cost == pytest.approx(14 / 3, abs=1e-3)


def test_admissible_heuristics_stay_below_the_optimal_values(axioms_model):
    gm = axioms_model
    exact = stampc.solve(gm, SolverOptions(algorithm="vi", heuristic="zero", epsilon=1e-8))
    hmax, lmcut = make_heuristic("hmax", gm, False), LMCut(gm, False)
    states = reachable_states(gm)
    for s in states:
        v = exact.value(s)
        assert hmax(s) <= lmcut(s) + 1e-9 and lmcut(s) <= v + 1e-6
    # axioms are relaxed actions: the goal's `above` facts are reachable, at a cost
    assert 0 < hmax(gm.init) < float("inf") and lmcut(gm.init) >= 2.0


def test_grounded_json_round_trip_keeps_the_axiom_program(axioms_model):
    data = grounded_to_json(axioms_model)
    assert data["ir_version"] == "2.2" and len(data["axioms"]) == len(axioms_model.axioms.rules)
    again = grounded_from_json(data)
    assert again == axioms_model and again.axioms == axioms_model.axioms
    assert grounded_to_json(again) == data
    assert stampc.solve(again).expected_cost == pytest.approx(14 / 3, abs=1e-3)


def test_grounded_json_rejects_an_axiom_on_a_basic_fact(axioms_model):
    data = grounded_to_json(axioms_model)
    on = next(i for i, f in enumerate(axioms_model.facts) if f.predicate == "on")
    data["axioms"][0][0] = on
    with pytest.raises(stampc.StampcError) as info:
        grounded_from_json(data)
    assert [d.code for d in info.value.diagnostics] == ["G192"]


def test_emitter_keeps_recursive_fluent_predicates_as_derived_sections():
    model = imported("above-domain.pddl", "above-problem.pddl")
    domain_text, problem_text = stampc.to_ppddl(model)
    assert ":derived-predicates" in domain_text and domain_text.count("(:derived ") == 1
    assert "(:derived (above " in domain_text and "(above a b)" not in problem_text
    again = import_ppddl_text(problem_text, "p.pddl", domain_text=domain_text,
                              domain_filename="d.pddl")
    assert reachable_fact_sets(stampc.ground(again), {"on", "done"}) == \
        reachable_fact_sets(stampc.ground(model), {"on", "done"})


def test_an_effect_on_a_derived_predicate_is_reported():
    domain = (HERE / "above-domain.pddl").read_text().replace(
        ":effect (done))", ":effect (and (done) (above ?z ?x)))")
    model = import_ppddl_text((HERE / "above-problem.pddl").read_text(), "p.pddl",
                              domain_text=domain, domain_filename="d.pddl")
    with pytest.raises(stampc.StampcError) as info:
        stampc.ground(model)
    [diag] = info.value.diagnostics
    assert diag.code == "G122" and "celebrate" in diag.message and diag.span.line > 1


def test_stamp_language_version_matches_the_unrolled_domain(unrolled_model):
    gm = stampc.ground(lower(load((HERE / "above.stamp").read_text())))
    assert gm.axioms and all(gm.facts[r.head].predicate == "above" for r in gm.axioms.rules)
    assert reachable_fact_sets(gm, {"on", "done"}) == reachable_fact_sets(unrolled_model,
                                                                          {"on", "done"})
    for algorithm in ("lao", "vi", "lrtdp"):
        assert stampc.solve(gm, SolverOptions(algorithm=algorithm)).expected_cost == \
            pytest.approx(stampc.solve(unrolled_model).expected_cost, abs=1e-3)


STRATA = (HERE / "above.stamp").read_text().replace(
    "action move(", """# stratum 2: recursive, and reads stratum 1 (`above`) negatively
derived predicate loose(a, b: block) :=
    (on(a, b) and not above(b, a)) or exists (c: block) (loose(a, c) and loose(c, b))
action move(""")


@settings(max_examples=60, deadline=None)
@given(st.sets(st.tuples(st.sampled_from(BLOCKS[1:]), st.sampled_from(BLOCKS))))
def test_a_higher_stratum_reads_the_lower_one_negatively(on):
    gm = stampc.ground(lower(load(STRATA)))
    strata = {gm.facts[r.head].predicate: r.stratum for r in gm.axioms.rules}
    assert strata["above"] < strata["loose"]
    state = gm.axioms.close(gm.state_of(GroundAtom("on", p) for p in on
                                        if gm.has_fact(GroundAtom("on", p))))
    on = pairs(gm, state, "on")  # cycles included: then `above(b, a)` blocks `loose`
    above = closure(on)
    assert pairs(gm, state, "above") == above
    assert pairs(gm, state, "loose") == closure({(a, b) for a, b in on if (b, a) not in above})


def test_outcome_labels_stay_aligned_with_closed_outcomes():
    from stampc.refine.outcomes import outcome_labels
    text = (HERE / "above.stamp").read_text().replace(
        "3/4: on(a, dst)", "3/4 as placed: on(a, dst)").replace(
        "1/4: on(a, table)", "1/4 as dropped: on(a, table)")
    gm = stampc.ground(lower(load(text)))
    move = next(a for a in gm.actions if a.label == "move(a, b, c)")
    outcomes = move.outcomes(gm.init)
    after = [pairs(gm, o.apply(gm.init), "above") for o in outcomes]
    assert ("a", "c") in after[0] and ("a", "b") not in after[0]  # derived facts updated
    assert outcome_labels(move, gm.init) == (("placed",), ("dropped",))
