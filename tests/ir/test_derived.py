"""Derived and symmetric predicates: compiled away before grounding, same state space."""

from __future__ import annotations


import stampc
from stampc.ir import lifted as L
from stampc.ir.derived import compile_derived
from stampc.ir.json_io import lifted_from_json, lifted_to_json
from stampc.ir.lower import lower
from stampc.semantics.api import load
from tests.ppddl.states import reachable_fact_sets

GRID = """domain grid
type cell, robot
symmetric predicate adjacent(a, b: cell)
predicate at(r: robot, c: cell)
predicate blocked(c: cell)
predicate painted(c: cell)
derived predicate free(c: cell) := not blocked(c) and not exists (r: robot) at(r, c)
derived predicate linked(a, b: cell) :=
    adjacent(a, b) or exists (c: cell) (adjacent(a, c) and linked(c, b))
action move(r: robot, a: cell, b: cell)
    pre  at(r, a), adjacent(a, b), free(b), linked(b, a)
    eff  not at(r, a), at(r, b)
action paint(r: robot, c: cell)
    pre  at(r, c), not painted(c)
    eff  painted(c)
problem p for grid
object cell(0..2, 0..1): cell
object r1, r2: robot
init forall (i: 0..1, j: 0..1) adjacent(cell(i, j), cell(i + 1, j))
     forall (i: 0..2) adjacent(cell(i, 0), cell(i, 1))
     at(r1, cell(0, 0)), at(r2, cell(2, 1))
     blocked(cell(1, 1))
goal painted(cell(2, 0)), free(cell(0, 0))
"""

# the same problem written out by hand: both adjacency directions, definitions inlined,
# the (static) closure `linked` listed
HAND = """domain grid
type cell, robot
predicate adjacent(a, b: cell)
predicate at(r: robot, c: cell)
predicate blocked(c: cell)
predicate painted(c: cell)
action move(r: robot, a: cell, b: cell)
    pre  at(r, a), adjacent(a, b), not blocked(b), not exists (x: robot) at(x, b)
    eff  not at(r, a), at(r, b)
action paint(r: robot, c: cell)
    pre  at(r, c), not painted(c)
    eff  painted(c)
problem p for grid
object cell(0..2, 0..1): cell
object r1, r2: robot
init forall (i: 0..1, j: 0..1) adjacent(cell(i, j), cell(i + 1, j))
     forall (i: 0..1, j: 0..1) adjacent(cell(i + 1, j), cell(i, j))
     forall (i: 0..2) adjacent(cell(i, 0), cell(i, 1))
     forall (i: 0..2) adjacent(cell(i, 1), cell(i, 0))
     at(r1, cell(0, 0)), at(r2, cell(2, 1))
     blocked(cell(1, 1))
goal painted(cell(2, 0)), not blocked(cell_0_0), not exists (x: robot) at(x, cell_0_0)
"""


def state_space(gm) -> set[frozenset[str]]:
    return reachable_fact_sets(gm, {"at", "painted"})


def test_derived_grid_has_the_state_space_of_the_hand_written_one() -> None:
    derived = stampc.ground(lower(load(GRID)))
    hand = stampc.ground(lower(load(HAND)))
    assert state_space(derived) == state_space(hand)
    assert len(state_space(derived)) > 10
    assert not derived.is_goal(derived.init)  # `free(cell_0_0)` is false at first: r1 stands there
    assert stampc.solve(derived).expected_cost == stampc.solve(hand).expected_cost


def test_compiled_model_has_no_derived_left_and_the_closure_is_static() -> None:
    model = compile_derived(lower(load(GRID)))
    preds = {p.name: p for p in model.domain.predicates}
    assert "free" not in preds and not model.domain.axioms
    assert preds["linked"].static and not any(p.symmetric for p in preds.values())
    linked = {tuple(t.name for t in a.args) for a in model.problem.init if a.predicate == "linked"}
    assert len(linked) == 36  # the grid is connected (through cell_1_1 too: adjacency is static)
    adjacent = {tuple(t.name for t in a.args) for a in model.problem.init if a.predicate == "adjacent"}
    assert all((b, a) in adjacent for a, b in adjacent) and len(adjacent) == 14


def test_symmetric_effects_write_both_directions() -> None:
    text = """domain links
type node
symmetric predicate link(a, b: node)
predicate done
action connect(a, b: node)
    pre  not link(a, b)
    eff  link(a, b)
action cut(a, b: node)
    pre  link(a, b)
    eff  not link(a, b), done
problem p for links
object n0, n1, n2: node
init link(n0, n1)
goal done
"""
    gm = stampc.ground(lower(load(text)))
    assert {str(f) for f in gm.state_facts(gm.init)} == {"link(n0, n1)", "link(n1, n0)"}
    connect = next(a for a in gm.actions if a.name == "connect" and a.args == ("n2", "n0"))
    [outcome] = connect.outcomes(gm.init)
    after = {str(f) for f in gm.state_facts(outcome.apply(gm.init))}
    assert {"link(n0, n2)", "link(n2, n0)"} <= after
    cut = next(a for a in gm.actions if a.name == "cut" and a.args == ("n1", "n0"))
    [outcome] = cut.outcomes(gm.init)
    assert not any(f.predicate == "link" for f in gm.state_facts(outcome.apply(gm.init)))


def test_recursion_over_a_fluent_is_evaluated_in_every_state() -> None:
    text = GRID.replace("adjacent(a, b) or exists (c: cell) (adjacent(a, c) and linked(c, b))",
                        "painted(a) or exists (c: cell) (adjacent(a, c) and linked(c, b))")
    gm = stampc.ground(lower(load(text)))
    assert gm.axioms and not any(f.predicate == "linked" for f in gm.state_facts(gm.init))
    paint = next(a for a in gm.actions if a.name == "paint" and a.args == ("r1", "cell_0_0"))
    [outcome] = paint.outcomes(gm.init)
    after = gm.state_facts(outcome.apply(gm.init))
    linked = {f.args for f in after if f.predicate == "linked"}
    # painted(cell_0_0) links it to every cell, and through the (connected) adjacency
    # every cell to every cell; before the paint, nothing was linked
    assert ("cell_0_0", "cell_2_1") in linked and ("cell_1_0", "cell_0_0") in linked
    assert len(linked) == 6 * 6


def test_ir_json_keeps_axioms_and_flags() -> None:
    model = lower(load(GRID))
    assert model.domain.axioms and any(p.symmetric for p in model.domain.predicates)
    data = lifted_to_json(model)
    assert data["ir_version"] == L.IR_VERSION == "2.2"
    assert lifted_from_json(data) == model
    data["ir_version"] = "2.0"  # older documents load (without the new fields)
    for p in data["domain"]["predicates"]:
        p.pop("symmetric"), p.pop("derived")
    data["domain"].pop("axioms")
    old = lifted_from_json(data)
    assert not old.domain.axioms and not any(p.symmetric for p in old.domain.predicates)


def test_optimism_looks_through_definitions() -> None:
    text = """domain d
type o
predicate collides(x: o)
predicate done(x: o)
derived predicate safe(x: o) := not collides(x)
action probe(x: o)
    eff  ? collides(x)
action work(x: o)
    pre  safe(x)
    eff  done(x)
problem p for d
object a: o
goal done(a)
"""
    pred = {p.name: p for p in lower(load(text)).domain.predicates}["collides"]
    assert pred.unknowable and pred.optimistic is False
