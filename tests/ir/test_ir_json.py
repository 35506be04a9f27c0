"""Versioned JSON form of the lifted and grounded IR: round trips and load errors."""

from __future__ import annotations

import json
from fractions import Fraction as F

import pytest
from ir_builders import AND, EFF, NOT, OR, action, add, atom, delete, model, params, pred, prob
from test_ground_generators import pick_place

from stampc.diagnostics import Span, StampcError
from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.ir.json_io import (bits_to_list, grounded_from_json, grounded_to_json,
                               lifted_from_json, lifted_to_json, list_to_bits)


def rich_model() -> L.Model:
    """Touches every lifted node type at least once."""
    fn = L.Function("w", params(("o", "box")))
    act = L.Action(
        "shuffle", params(("x", "box"), ("y", "box")),
        AND(L.Imply(atom("red", "?x"), OR(atom("open", "?y"), L.Truth(False))),
            L.Forall(params(("z", "box")), NOT(L.Equals(L.Var("z"), L.Const("?odd")))),
            L.Exists(params(("z", "box")), atom("open", "?z"))),
        EFF(add("open", "?x"), delete("open", "?y"), L.Unknown(atom("seen", "?x")),
            L.When(atom("red", "?y"), L.CostEffect(L.BinOp("-", L.FuncTerm("w", (L.Var("x"),)),
                                                          L.Num(F(1, 3))))),
            L.EffForall(params(("z", "box")), prob(("1/3", add("open", "?z")))),
            L.Probabilistic((L.Outcome(F(1, 2), add("seen", "?y"), label="lucky"),))),
        cost=L.Num(F(2)), generated=(L.GeneratorUse("gen", ("x",), ("y",)),),
        executes=L.Binding(".w:shuffle", Span("d.stamp", 4, 2, 4, 9)),
        span=Span("d.stamp", 3, 1, 9, 2))
    gen = L.Generator("gen", params(("a", "box")), params(("b", "box")), (atom("red", "?b"),),
                      L.Binding("pkg.mod:gen"), (("budget", 8), ("dims", (1, 2))))
    domain = L.Domain(
        "rich", (L.Type("box", None, False), L.Type("pose", "object", True)),
        (L.Object("?odd", "box"),),
        (pred("open", "box"), pred("red", "box"),
         pred("seen", "box", unknowable=True, optimistic=True)),
        (fn,), (act,), (gen,), (L.Evaluator("seen", L.Binding(".w:seen")),), (":rewards",),
        span=Span("d.stamp", 1, 1, 1, 4))
    problem = L.Problem(
        "p", "rich", (L.Object("b1", "box"), L.Object("q0", "pose", symbolic=True)),
        (atom("red", "b1"),), ((atom("w", "b1"), F(7, 2)),), atom("open", "b1"), horizon=12,
        scene=L.SceneRef("builder", ".scenes:table", (("n", 3), ("size", (0.5, 1.0)))),
        goal_reward=F(100), metric="maximize (reward)")
    return L.Model(domain, problem)


def reload(data: dict) -> dict:
    return json.loads(json.dumps(data))  # must survive real JSON text


def test_lifted_round_trip_is_equal_and_keeps_spans():
    m = rich_model()
    data = reload(lifted_to_json(m))
    assert data["ir_version"] == L.IR_VERSION and data["kind"] == "lifted"
    back = lifted_from_json(data)
    assert back == m
    assert back.domain.actions[0].span == Span("d.stamp", 3, 1, 9, 2)
    assert back.domain.actions[0].executes.span == Span("d.stamp", 4, 2, 4, 9)
    assert back.domain.generators[0].options == (("budget", 8), ("dims", (1, 2)))
    prob_json = data["domain"]["actions"][0]["effect"]["effects"][5]
    assert prob_json["outcomes"][0] == {"p": "1/2", "effect": prob_json["outcomes"][0]["effect"],
                                        "label": "lucky"}


@pytest.mark.parametrize("build", [pick_place, rich_model], ids=["pick_place", "rich"])
def test_grounded_round_trip_is_equal(build):
    m = build()
    if build is rich_model:
        # ground a generator-free variant: drop the generator use
        act = m.domain.actions[0]
        stripped = L.Action(act.name, act.params, act.precondition, act.effect, act.cost)
        m = L.Model(L.Domain(m.domain.name, m.domain.types, m.domain.constants, m.domain.predicates,
                             m.domain.functions, (stripped,), (), (), (":rewards",)),
                    m.problem)
    gm = ground(m)
    data = reload(grounded_to_json(gm))
    assert data["kind"] == "grounded" and isinstance(data["init"], list)
    back = grounded_from_json(data)
    assert back == gm
    assert back.lifted == m
    assert [a.label for a in back.actions] == [a.label for a in gm.actions]
    assert grounded_to_json(back) == data


def test_grounded_json_uses_index_lists_and_fraction_strings():
    m = model(preds=(pred("p"), pred("q")),
              actions=(action("a", (), NOT(atom("q")), EFF(add("p"), prob(("1/3", add("q"))))),))
    data = grounded_to_json(ground(m), include_lifted=False)
    assert data["lifted"] is None
    (a,) = data["actions"]
    assert a["pre"] == {"neg": [1]} and a["effect"]["add"] == [0]
    assert a["effect"]["blocks"] == [[["1/3", {"add": [1]}]]]
    assert a["base_cost"] == "1"


def test_bits_helpers():
    mask = (1 << 0) | (1 << 31) | (1 << 32) | (1 << 200)
    assert bits_to_list(mask) == [0, 31, 32, 200]
    assert list_to_bits([0, 31, 32, 200]) == mask
    assert bits_to_list(0) == []


def test_version_kind_and_malformed_documents_are_diagnostics():
    data = lifted_to_json(rich_model())
    with pytest.raises(StampcError) as exc:
        lifted_from_json({**data, "ir_version": "0.1"}, source="old.json")
    (d,) = exc.value.diagnostics
    assert d.code == "G190" and d.span.file == "old.json" and "0.1" in d.message
    with pytest.raises(StampcError) as exc:
        grounded_from_json(data)
    assert exc.value.diagnostics[0].code == "G191"
    broken = json.loads(json.dumps(data))
    del broken["domain"]["actions"][0]["effect"]
    with pytest.raises(StampcError) as exc:
        lifted_from_json(broken)
    assert exc.value.diagnostics[0].code == "G192" and "effect" in exc.value.diagnostics[0].message
    with pytest.raises(StampcError) as exc:
        lifted_from_json([1, 2])  # type: ignore[arg-type]
    assert exc.value.diagnostics[0].code == "G192"
    gdata = grounded_to_json(ground(model(preds=(pred("p"),),
                                          actions=(action("a", (), L.TRUE, add("p")),))))
    gdata["actions"][0]["effect"]["add"] = [5]  # only one fact exists
    with pytest.raises(StampcError) as exc:
        grounded_from_json(gdata)
    assert exc.value.diagnostics[0].code == "G192"
