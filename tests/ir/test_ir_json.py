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
from stampc.ir.grounded import (GAnd, GEffect, GLit, GOr, GProb, GroundAction, GroundAtom,
                                GroundCondition, GroundModel)
from stampc.ir.json_io import (bits_to_list, grounded_from_json, grounded_to_json,
                               lifted_from_json, lifted_to_json, list_to_bits, read_ir_json,
                               write_grounded_json, write_lifted_json)


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
    assert "subtrees" in data and data["subtrees"] == []  # shallow trees stay nested
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


def test_grounded_json_uses_a_node_table_index_lists_and_fraction_strings():
    m = model(preds=(pred("p"), pred("q")),
              actions=(action("a", (), NOT(atom("q")), EFF(add("p"), prob(("1/3", add("q"))))),))
    data = grounded_to_json(ground(m), include_lifted=False)
    assert data["lifted"] is None
    nodes = data["nodes"]
    (a,) = data["actions"]
    assert nodes[a["pre"]] == {"t": "cond", "neg": [1]}
    effect = nodes[a["effect"]]
    assert effect["t"] == "effect" and effect["add"] == [0]
    (block,) = effect["blocks"]
    assert nodes[block] == {"t": "prob", "outcomes": [["1/3", block - 1]]}
    assert nodes[block - 1] == {"t": "effect", "add": [1]}
    assert a["base_cost"] == "1" and "index" not in a and "generated" not in a
    assert nodes[data["goal"]] == {"t": "cond"}


def test_grounded_nodes_only_refer_backwards():
    data = grounded_to_json(ground(pick_place()), include_lifted=False)
    for k, node in enumerate(data["nodes"]):
        refs = node.get("whens", []) + node.get("blocks", []) + node.get("rest", []) + \
            node.get("args", []) + [r for _, r in node.get("outcomes", [])] + \
            [node[key] for key in ("cond", "effect") if key in node]
        assert all(0 <= r < k for r in refs), (k, node)
    texts = [json.dumps(n, sort_keys=True) for n in data["nodes"]]
    assert len(set(texts)) == len(texts)  # equal nodes are merged


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


def test_unknown_versions_get_a_migration_hint():
    gdata = grounded_to_json(ground(model(preds=(pred("p"),),
                                          actions=(action("a", (), L.TRUE, add("p")),))))
    with pytest.raises(StampcError) as exc:
        grounded_from_json({**gdata, "ir_version": "3.0"}, source="new.json")
    (d,) = exc.value.diagnostics
    assert d.code == "G190" and "3.0" in d.message and "stampc compile" in d.hint


def test_version_1_documents_still_load():
    """A grounded 1.0 document (conditions and effects inline) as stampc 1.0 wrote it."""
    facts = (GroundAtom("p", ()), GroundAtom("q", ("a",)), GroundAtom("r", ()))
    cond = GroundCondition(pos=0b1, rest=(GOr((GLit(1), GAnd((GLit(2, False), GLit(0))))),))
    effect = GEffect(add=0b10, delete=0b1, cost=F(1, 2), unknown=0b100,
                     whens=((cond, GEffect(add=0b100)),),
                     blocks=(GProb(((F(1, 3), GEffect(delete=0b10)),
                                    (F(1, 2), GEffect(whens=((cond, GEffect(add=0b1)),))))),))
    gm = GroundModel(facts, (GroundAction(0, "act", ("a",), cond, effect, F(2), schema=0),),
                     0b1, GroundCondition(neg=0b100), (("a", "thing"),),
                     (GroundAtom("s", ("a",)),), horizon=7, has_costs=True)
    v1_cond = {"pos": [0], "rest": [{"or": [{"lit": 1}, {"and": [{"not": 2}, {"lit": 0}]}]}]}
    v1 = {"ir_version": "1.0", "kind": "grounded",
          "facts": [["p", []], ["q", ["a"]], ["r", []]],
          "actions": [{"index": 0, "name": "act", "args": ["a"], "schema": 0, "pre": v1_cond,
                       "effect": {"add": [1], "del": [0], "unknown": [2], "cost": "1/2",
                                  "whens": [[v1_cond, {"add": [2]}]],
                                  "blocks": [[["1/3", {"del": [1]}],
                                              ["1/2", {"whens": [[v1_cond, {"add": [0]}]]}]]]},
                       "base_cost": "2", "generated": []}],
          "init": [0], "goal": {"neg": [2]}, "objects": [["a", "thing"]],
          "static_facts": [["s", ["a"]]], "horizon": 7, "has_costs": True,
          "lifted": {**lifted_to_json(rich_model()), "ir_version": "1.0"}}
    for key in ("subtrees",):
        del v1["lifted"][key]
    back = grounded_from_json(json.loads(json.dumps(v1)))
    assert back == gm and back.lifted == rich_model()
    assert back.actions[0].precondition is back.actions[0].effect.whens[0][0]  # merged nodes
    broken = {**v1, "actions": [{**v1["actions"][0], "pre": {"rest": [{"and": 5}]}}]}
    with pytest.raises(StampcError) as exc:
        grounded_from_json(broken, source="old.json")
    assert exc.value.diagnostics[0].code == "G192"


def _one_action_document() -> dict:
    return grounded_to_json(ground(model(preds=(pred("p"), pred("q")),
                                         actions=(action("a", (), NOT(atom("q")), add("p")),))),
                            include_lifted=False)


@pytest.mark.parametrize("corrupt, words", [
    (lambda d: d["nodes"][d["actions"][0]["effect"]].update(add=[5]), "fact index 5"),
    (lambda d: d["actions"][0].update(effect=d["actions"][0]["pre"]), "not a GEffect"),
    (lambda d: d["actions"][0].update(pre=len(d["nodes"])), "node reference"),
    (lambda d: d["nodes"].insert(0, {"t": "and", "args": [0]}), "out of range"),
    (lambda d: d["nodes"].append({"t": "bogus"}), "bogus"),
    (lambda d: d.update(goal="0"), "node reference"),
    (lambda d: d.update(nodes={}), "expected a list"),
    (lambda d: d["nodes"].append({"t": "prob", "outcomes": [["1/2", 0]]}), "not a GEffect"),
])
def test_malformed_grounded_documents_are_located_diagnostics(corrupt, words):
    data = _one_action_document()
    corrupt(data)
    with pytest.raises(StampcError) as exc:
        grounded_from_json(data, source="bad.json")
    (d,) = exc.value.diagnostics
    assert d.code == "G192" and d.span.file == "bad.json" and words in d.message, d.message


def test_streamed_text_is_the_dict_form_and_read_ir_json_dispatches_on_kind(tmp_path):
    gm = ground(pick_place())
    path = tmp_path / "grounded.json"
    with open(path, "w", encoding="utf-8") as f:
        write_grounded_json(gm, f)
    assert json.loads(path.read_text()) == grounded_to_json(gm)
    assert read_ir_json(path) == gm
    lifted_path = tmp_path / "lifted.json"
    with open(lifted_path, "w", encoding="utf-8") as f:
        write_lifted_json(gm.lifted, f)
    assert json.loads(lifted_path.read_text()) == lifted_to_json(gm.lifted)
    assert read_ir_json(lifted_path) == gm.lifted


@pytest.mark.parametrize("text", ["{not json", "[" * 100_000 + "]" * 100_000, "\x00\xff"])
def test_read_ir_json_reports_unreadable_text_as_g192(tmp_path, text):
    path = tmp_path / "bad.json"
    path.write_bytes(text.encode("latin-1"))
    with pytest.raises(StampcError) as exc:
        read_ir_json(path)
    (d,) = exc.value.diagnostics
    assert d.code == "G192" and d.span.file == str(path)


def test_delete_wins_survives_the_grounded_json(tmp_path):
    """An action grounded under --conflicting-effects delete-wins keeps its rule."""
    from stampc.backends.ppddl import import_ppddl_text
    from stampc.ir.ground import ground
    from stampc.ir.json_io import read_ir_json, write_grounded_json

    domain = """(define (domain toggle) (:requirements :strips)
      (:predicates (on))
      (:action flip :effect (and (on) (not (on)))))"""
    problem = "(define (problem t) (:domain toggle) (:init) (:goal (on)))"
    model = import_ppddl_text(domain + "\n" + problem)
    for rule, expected in (("delete-wins", True), ("add-wins", False)):
        gm = ground(model, conflicting_effects=rule)
        assert [a.delete_wins for a in gm.actions] == [expected]
        path = tmp_path / f"{rule}.json"
        with path.open("w", encoding="utf-8") as f:
            write_grounded_json(gm, f)
        back = read_ir_json(path)
        assert [a.delete_wins for a in back.actions] == [expected]
        assert back == gm
