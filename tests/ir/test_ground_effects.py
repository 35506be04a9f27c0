"""Grounding of effects: conditional and probabilistic effects, costs, ``?`` folding."""

from __future__ import annotations

from fractions import Fraction as F

import pytest
from ir_builders import (AND, EFF, NOT, action, add, atom, delete, fact, find, model, params,
                         pred, prob, state)

from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.ir.grounded import GroundAtom, outcome_distribution


def dist(gm, act, s):
    """{resulting state: probability} of ``act`` in ``s``."""
    out: dict[int, F] = {}
    for succ in outcome_distribution(act, s):
        nxt = succ.apply(s)
        out[nxt] = out.get(nxt, F(0)) + succ.probability
    return out


def coins_model() -> L.Model:
    """Two independent coins (1/2 and 1/3) plus a nested block inside the first."""
    return model(
        preds=(pred("h1"), pred("h2"), pred("lucky"), pred("armed")),
        actions=(action("flip", (), L.TRUE, EFF(
            prob(("1/2", EFF(add("h1"), prob(("1/4", add("lucky")))))),
            prob(("1/3", add("h2"))))),
            action("arm", (), L.TRUE, add("armed"))))


def test_independent_and_nested_blocks_match_hand_computed_distribution():
    gm = ground(coins_model())
    flip = find(gm, "flip")
    h1, h2, lucky = fact(gm, "h1"), fact(gm, "h2"), fact(gm, "lucky")
    d = dist(gm, flip, 0)
    assert sum(d.values()) == 1
    assert d == {
        h1 | lucky | h2: F(1, 2) * F(1, 4) * F(1, 3),
        h1 | lucky: F(1, 2) * F(1, 4) * F(2, 3),
        h1 | h2: F(1, 2) * F(3, 4) * F(1, 3),
        h1: F(1, 2) * F(3, 4) * F(2, 3),
        h2: F(1, 2) * F(1, 3),
        0: F(1, 2) * F(2, 3),
    }
    assert len(flip.effect.blocks) == 2  # kept factored, not multiplied out


def test_conditional_effects_inline_drop_and_keep():
    m = model(
        types=(L.Type("door"),),
        preds=(pred("open", "door"), pred("locked", "door"), pred("alarm"), pred("seen")),
        actions=(action("push", params(("d", "door")), L.TRUE, EFF(
            L.When(atom("locked", "?d"), add("alarm")),          # static: inline or drop
            L.When(NOT(atom("open", "?d")), add("open", "?d")),  # state-dependent: kept
            L.When(atom("open", "?d"), prob(("1/2", add("seen")))))),
            action("close", params(("d", "door")), atom("open", "?d"), delete("open", "?d"))),
        objs="d1 d2 - door", init=(atom("locked", "d1"),))
    gm = ground(m)
    p1, p2 = find(gm, "push(d1)"), find(gm, "push(d2)")
    alarm = fact(gm, "alarm")
    assert p1.effect.add == alarm and p2.effect.add == 0
    assert len(p1.effect.whens) == 2 and not p1.effect.state_independent
    o1 = fact(gm, "open", "d1")
    assert dist(gm, p1, 0) == {alarm | o1: 1}
    # when open: the "not open" branch is off, the probabilistic branch fires
    assert dist(gm, p1, o1) == {alarm | o1 | fact(gm, "seen"): F(1, 2), alarm | o1: F(1, 2)}
    for a in gm.actions:
        for s in (0, o1, o1 | fact(gm, "open", "d2")):
            assert sum(x.probability for x in outcome_distribution(a, s)) == 1


def test_forall_effect_expands_and_shares_conditions():
    m = model(
        types=(L.Type("comp"),),
        preds=(pred("up", "comp"), pred("conn", "comp", "comp")),
        actions=(action("reboot", params(("x", "comp")), L.TRUE, EFF(
            add("up", "?x"),
            L.EffForall(params(("d", "comp")), prob(("1/10", L.When(
                AND(NOT(L.Equals(L.Var("d"), L.Var("x"))),
                    L.Exists(params(("c", "comp")), AND(atom("conn", "?c", "?d"),
                                                        NOT(atom("up", "?c"))))),
                delete("up", "?d"))))))),),
        objs="c1 c2 c3 - comp",
        init=(atom("up", "c1"), atom("up", "c2"), atom("conn", "c1", "c2"),
              atom("conn", "c2", "c3")))
    gm = ground(m)
    r1 = find(gm, "reboot(c1)")
    # d = c1 excluded by equality; d = c1 has no incoming conn either way -> only c2, c3
    assert len(r1.effect.blocks) == 2
    up = {c: fact(gm, "up", c) for c in ("c1", "c2", "c3")}
    s = up["c2"]  # c1 down: c2 may fail, c3's upstream c2 is up
    d = dist(gm, r1, s)
    assert d == {up["c1"] | up["c2"]: F(9, 10), up["c1"]: F(1, 10)}


def test_cost_defaults_and_cost_effects():
    plain = model(preds=(pred("p"),), actions=(action("a", (), L.TRUE, add("p")),))
    gm = ground(plain)
    assert find(gm, "a").base_cost == 1 and not gm.has_costs
    unit = model(preds=(pred("p"),),
                 actions=(action("a", (), L.TRUE, add("p"), cost=L.Num(F(1))),))
    assert not ground(unit).has_costs  # the explicit unit default is not a declared cost

    rewards = model(preds=(pred("p"),), actions=(action("a", (), L.TRUE, add("p")),),
                    requirements=(":rewards",))
    gm = ground(rewards)
    assert find(gm, "a").base_cost == 0 and gm.has_costs

    weight = L.Function("weight", params(("o", "object")))
    costed = model(
        preds=(pred("moved", "object"), pred("p")), functions=(weight,),
        actions=(
            action("move", params(("o", "object")), L.TRUE, EFF(
                add("moved", "?o"),
                L.CostEffect(L.BinOp("*", L.Num(F(2)), L.FuncTerm("weight", (L.Var("o"),)))),
                prob(("1/2", L.CostEffect(L.Num(F(3))))))),
            action("fixed", (), L.TRUE, add("p"), cost=L.Num(F(5, 2)))),
        objs="x y",
        init_values=((atom("weight", "x"), F(3)), (atom("weight", "y"), F(1, 2))))
    gm = ground(costed)
    assert gm.has_costs
    mx, my = find(gm, "move(x)"), find(gm, "move(y)")
    assert mx.base_cost == 0 and mx.effect.cost == 6 and my.effect.cost == 1
    costs = sorted(s.cost for s in outcome_distribution(mx, 0))
    assert costs == [6, 9]
    assert find(gm, "fixed").base_cost == F(5, 2)


def test_unknown_effects_fold_optimistic_value_and_start_optimistic():
    m = model(
        types=(L.Type("obj"), L.Type("traj")),
        preds=(pred("collision", "obj", "traj", unknowable=True, optimistic=False),
               pred("charged", "obj", unknowable=True, optimistic=True),
               pred("moved", "obj")),
        actions=(
            action("move", params(("o", "obj"), ("t", "traj")),
                   AND(NOT(atom("collision", "?o", "?t")), atom("charged", "?o")),
                   EFF(add("moved", "?o"), L.Unknown(atom("collision", "?o", "?t")),
                       L.Unknown(atom("charged", "?o")))),),
        objs="a b - obj t1 - traj", init=(atom("collision", "b", "t1"),))
    gm = ground(m)
    col_a, col_b = fact(gm, "collision", "a", "t1"), fact(gm, "collision", "b", "t1")
    ch_a, ch_b = fact(gm, "charged", "a"), fact(gm, "charged", "b")
    # charged is optimistically true although not in init; collision(b) is in init
    assert gm.init == col_b | ch_a | ch_b
    ma = find(gm, "move(a, t1)")
    assert ma.effect.unknown == col_a | ch_a
    assert ma.effect.delete & col_a and ma.effect.add & ch_a
    assert ma.precondition.holds(gm.init)
    assert not find(gm, "move(b, t1)").precondition.holds(gm.init)


def test_probability_sum_above_one_is_a_diagnostic():
    from stampc.diagnostics import StampcError
    m = model(preds=(pred("p"),),
              actions=(action("a", (), L.TRUE, prob(("2/3", add("p")), ("1/2", add("p")))),))
    with pytest.raises(StampcError) as exc:
        ground(m)
    (d,) = exc.value.diagnostics
    assert d.code == "G108" and d.span.file == "a.stamp"


def test_delete_then_add_same_fact_ends_true():
    m = model(preds=(pred("p"),), actions=(action("a", (), L.TRUE, EFF(delete("p"), add("p"))),),
              init=(atom("p"),))
    gm = ground(m)
    s = state(gm, ("p",))
    assert dist(gm, find(gm, "a"), s) == {s: 1}
    assert gm.has_fact(GroundAtom("p", ()))
