"""Grounding: reachability, static pruning, types, formulas, determinism."""

from __future__ import annotations

from ir_builders import (AND, EFF, NOT, OR, action, add, atom, delete, fact, find, labels,
                         model, params, pred, state)

from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.ir.grounded import GAnd, GLit, GOr, GroundAtom


def road_model(goal=atom("at", "c")) -> L.Model:
    """a -> b -> c by road, d unreachable; 'road' is static, 'at' fluent."""
    return model(
        types=(L.Type("loc"),),
        preds=(pred("at", "loc"), pred("road", "loc", "loc")),
        actions=(action("move", params(("from", "loc"), ("to", "loc")),
                        AND(atom("at", "?from"), atom("road", "?from", "?to")),
                        EFF(add("at", "?to"), delete("at", "?from"))),),
        objs="a b c d - loc",
        init=(atom("at", "a"), atom("road", "a", "b"), atom("road", "b", "c"),
              atom("road", "d", "a")),
        goal=goal)


def test_static_predicates_compiled_away_and_unreachable_pruned():
    gm = ground(road_model())
    # road is static: no fact for it; at(d) is never reachable, so move(d, a) is pruned
    assert [str(f) for f in gm.facts] == ["at(a)", "at(b)", "at(c)"]
    assert labels(gm) == ["move(a, b)", "move(b, c)"]
    assert GroundAtom("road", ("a", "b")) in gm.static_facts
    move = find(gm, "move(a, b)")
    assert move.precondition.pos == fact(gm, "at", "a") and not move.precondition.rest
    assert move.effect.add == fact(gm, "at", "b") and move.effect.delete == fact(gm, "at", "a")
    assert gm.init == fact(gm, "at", "a")
    assert gm.goal.pos == fact(gm, "at", "c")
    assert all(a.index == i for i, a in enumerate(gm.actions))
    assert gm.lifted is not None and gm.lifted.problem.name == "t-p"


def test_join_does_not_enumerate_cross_product():
    # 30 locations on a line: the join over road yields 29 moves, not 900 candidates
    names = [f"l{i}" for i in range(30)]
    m = road_model()
    m = L.Model(m.domain, L.Problem(
        "line", "t", tuple(L.Object(n, "loc") for n in names),
        (atom("at", "l0"),) + tuple(atom("road", a, b) for a, b in zip(names, names[1:])),
        goal=atom("at", "l29")))
    gm = ground(m)
    assert len(gm.actions) == 29 and len(gm.facts) == 30


def test_type_hierarchy_subtypes_are_instances_of_ancestors():
    m = model(
        types=(L.Type("vehicle"), L.Type("truck", "vehicle"), L.Type("pickup", "truck"),
               L.Type("city")),
        preds=(pred("washed", "vehicle"), pred("big", "truck")),
        actions=(action("wash", params(("v", "vehicle")), L.TRUE, add("washed", "?v")),
                 action("wash-any", params(("o", "object")), atom("big", "?o"),
                        add("washed", "?o"))),
        objs="t1 - truck p1 - pickup car - vehicle paris - city",
        init=(atom("big", "t1"), atom("big", "p1")))
    gm = ground(m)
    assert labels(gm) == ["wash(car)", "wash(p1)", "wash(t1)", "wash-any(p1)", "wash-any(t1)"]
    assert ("paris", "city") in gm.objects and ("p1", "pickup") in gm.objects


def test_forall_exists_imply_equality_in_preconditions():
    m = model(
        types=(L.Type("box"),),
        preds=(pred("open", "box"), pred("red", "box"), pred("done")),
        actions=(
            # all red boxes open (red is static: only b1, b2 matter)
            action("all-red-open", (), L.Forall(params(("b", "box")),
                                                L.Imply(atom("red", "?b"), atom("open", "?b"))),
                   add("done")),
            # some box other than ?x is open
            action("other-open", params(("x", "box")),
                   L.Exists(params(("y", "box")),
                            AND(NOT(L.Equals(L.Var("y"), L.Var("x"))), atom("open", "?y"))),
                   add("done")),
            action("open", params(("b", "box")), NOT(atom("open", "?b")), add("open", "?b")),
            action("never", params(("b", "box")),
                   AND(L.Equals(L.Var("b"), L.Const("nobox2")), atom("red", "?b")), add("done")),
            action("only", params(("b", "box")), L.Equals(L.Const("b3"), L.Var("b")),
                   add("done"))),
        objs="b1 b2 b3 nobox2 - box",
        init=(atom("red", "b1"), atom("red", "b2")))
    gm = ground(m)
    o = {b: fact(gm, "open", b) for b in ("b1", "b2", "b3", "nobox2")}
    a = find(gm, "all-red-open")
    assert a.precondition.pos == o["b1"] | o["b2"] and not a.precondition.rest
    x = find(gm, "other-open(b1)")
    (rest,) = x.precondition.rest
    assert isinstance(rest, GOr) and {g.fact for g in rest.args} == \
        {gm.fact_index(GroundAtom("open", (b,))) for b in ("b2", "b3", "nobox2")}
    assert x.precondition.holds(o["b2"]) and not x.precondition.holds(o["b1"])
    assert find(gm, "open(b3)").precondition.neg == o["b3"]
    assert not any(label.startswith("never") for label in labels(gm))
    assert [x for x in labels(gm) if x.startswith("only")] == ["only(b3)"]
    assert find(gm, "only(b3)").precondition.is_trivial


def test_disjunctive_precondition_any_branch_reachable():
    m = model(
        preds=(pred("p"), pred("q"), pred("r"), pred("g")),
        actions=(action("a", (), OR(atom("p"), atom("q")), add("r")),
                 action("b", (), AND(atom("r"), OR(atom("p"), NOT(atom("q")))), add("g")),
                 action("c", (), atom("r"), delete("q"))),
        init=(atom("q"),), goal=atom("g"))
    gm = ground(m)
    # p is never reachable: a's precondition simplifies to q, b's to r and not q
    a, b = find(gm, "a"), find(gm, "b")
    assert a.precondition.pos == fact(gm, "q")
    assert b.precondition.pos == fact(gm, "r") and b.precondition.neg == fact(gm, "q")
    assert not gm.has_fact(GroundAtom("p", ()))


def test_static_false_goal_and_contradictory_precondition():
    m = road_model(goal=AND(atom("at", "c"), atom("road", "c", "a")))
    gm = ground(m)
    assert gm.goal.never and not gm.is_goal(state(gm, ("at", "c")))
    m2 = model(preds=(pred("p"), pred("q")),
               actions=(action("x", (), AND(atom("p"), NOT(atom("p"))), add("q")),
                        action("y", (), L.TRUE, add("p"))))
    assert labels(ground(m2)) == ["y"]


def test_grounding_is_deterministic():
    first, second = ground(road_model()), ground(road_model())
    assert first == second
    assert [a.label for a in first.actions] == [a.label for a in second.actions]
    assert list(first.facts) == sorted(first.facts)


def test_constants_and_negative_static_filters():
    m = model(
        preds=(pred("blocked", "object"), pred("visited", "object")),
        actions=(action("visit", params(("x", "object")), NOT(atom("blocked", "?x")),
                        add("visited", "?x")),),
        objs="a b", constants=(L.Object("home", "object"),),
        init=(atom("blocked", "b"),))
    gm = ground(m)
    assert labels(gm) == ["visit(a)", "visit(home)"]
    assert gm.objects[0] == ("home", "object")
    assert all(isinstance(a.precondition.rest, tuple) and not a.precondition.neg
               for a in gm.actions)


def test_nested_condition_remainder_evaluates_like_the_formula():
    m = model(
        preds=(pred("p"), pred("q"), pred("r"), pred("s"), pred("t")),
        actions=(action("mk", params(), L.TRUE, EFF(add("p"), add("q"), add("r"), add("s"))),
                 action("x", (), AND(atom("p"), OR(AND(atom("q"), atom("r")), atom("s"))),
                        add("t"))))
    gm = ground(m)
    pre = find(gm, "x").precondition
    assert pre.pos == fact(gm, "p")
    assert len(pre.rest) == 1 and isinstance(pre.rest[0], GOr)
    assert isinstance(pre.rest[0].args[0], GAnd) and isinstance(pre.rest[0].args[1], GLit)
    for bits in range(32):
        s = sum(fact(gm, n) for i, n in enumerate("pqrst") if bits >> i & 1)
        truth = {n: bool(bits >> i & 1) for i, n in enumerate("pqrst")}
        expected = truth["p"] and ((truth["q"] and truth["r"]) or truth["s"])
        assert pre.holds(s) == expected


def test_grounding_does_not_depend_on_hash_seed():
    """Sets are iterated during grounding: output must still be identical across processes."""
    import json
    import subprocess
    import sys
    from pathlib import Path

    from stampc.ir.json_io import grounded_to_json

    here = Path(__file__).resolve().parent
    script = ("import json, sys; sys.path[:0] = [{!r}, {!r}]\n"
              "from test_ground_semantics import quantifier_zoo\n"
              "from stampc.ir.ground import ground\n"
              "from stampc.ir.json_io import grounded_to_json\n"
              "print(json.dumps(grounded_to_json(ground(quantifier_zoo()))))"
              ).format(str(here), str(here.parents[1]))
    outputs = []
    for seed in ("1", "2"):
        env = {"PYTHONHASHSEED": seed, "PATH": "/usr/bin:/bin"}
        run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                             env=env, timeout=60, check=True)
        outputs.append(json.loads(run.stdout))
    from test_ground_semantics import quantifier_zoo
    here_json = json.loads(json.dumps(grounded_to_json(ground(quantifier_zoo()))))
    assert outputs[0] == outputs[1] == here_json
