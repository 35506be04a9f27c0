"""IR JSON at scale: 10,000-deep trees round-trip, shared structure is written once."""

from __future__ import annotations

import io
import json
from dataclasses import fields, is_dataclass
from fractions import Fraction as F

import pytest
from ir_builders import EFF, action, add, atom, model, params, pred

from stampc.diagnostics import StampcError
from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.ir.grounded import (GAnd, GEffect, GLit, GOr, GProb, GroundAction, GroundAtom,
                                GroundCondition, GroundModel)
from stampc.ir.json_io import (grounded_from_json, grounded_to_json, lifted_from_json,
                               lifted_to_json, write_grounded_json)
from stampc.ir.json_tree import SPILL_HEIGHT

DEPTH = 10_000


def deep_equal(a: object, b: object) -> bool:
    """``a == b`` for dataclass trees, without recursion (``==`` would hit the limit)."""
    stack = [(a, b)]
    seen: set[tuple[int, int]] = set()  # shared sub-trees are compared once
    while stack:
        x, y = stack.pop()
        if type(x) is not type(y):
            return False
        if (id(x), id(y)) in seen:
            continue
        seen.add((id(x), id(y)))
        if is_dataclass(x):
            stack.extend((getattr(x, f.name), getattr(y, f.name)) for f in fields(x) if f.compare)
        elif isinstance(x, (tuple, list)):
            if len(x) != len(y):
                return False
            stack.extend(zip(x, y))
        elif x != y:
            return False
    return True


def json_depth(text: str) -> int:
    depth = deepest = 0
    in_string = escaped = False
    for ch in text:
        if in_string:
            escaped = not escaped and ch == "\\"
            in_string = escaped or ch != '"'
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


def chain(leaf, wrap, n: int = DEPTH):
    node = leaf
    for i in range(n):
        node = wrap(node, i)
    return node


def deep_lifted_model() -> L.Model:
    p, q = atom("p"), atom("q")
    pre = chain(p, lambda f, i: L.Not(f) if i % 3 else L.And((f, q)))
    eff = chain(add("p"), lambda e, i: L.When(q, e) if i % 2 else
                L.Probabilistic((L.Outcome(F(1, 2), e, f"o{i}"),)))
    cost = chain(L.Num(F(1)), lambda e, i: L.BinOp("+", e, L.Num(F(i))))
    goal = chain(q, lambda f, i: L.Or((f, L.Exists(params(("x", "thing")), p))))
    m = model(preds=(pred("p"), pred("q")),
              actions=(action("deep", (), pre, EFF(eff, add("q")), cost=cost),), goal=goal)
    return m


def test_10000_deep_lifted_trees_round_trip_through_shallow_json_text():
    m = deep_lifted_model()
    data = lifted_to_json(m)
    text = json.dumps(data)
    assert json_depth(text) < 4 * SPILL_HEIGHT + 20  # json.loads recurses: keep it shallow
    assert len(data["subtrees"]) >= 4 * DEPTH // SPILL_HEIGHT - 4
    back = lifted_from_json(json.loads(text))
    assert deep_equal(back, m)
    assert not deep_equal(back.problem.goal, m.domain.actions[0].precondition)


def deep_ground_model() -> GroundModel:
    facts = tuple(GroundAtom("f", (str(i),)) for i in range(4))
    rest = chain(GLit(0), lambda f, i: GAnd((f, GLit(i % 4, False))) if i % 2 else
                 GOr((GLit(1), f)))
    cond = GroundCondition(pos=0b10, rest=(rest,))
    effect = chain(GEffect(add=0b100), lambda e, i: GEffect(whens=((cond, e),)) if i % 2 else
                   GEffect(delete=0b1, blocks=(GProb(((F(1, 3), e),)),)))
    act = GroundAction(0, "deep", (), cond, effect, F(1))
    return GroundModel(facts, (act,), 0b1, GroundCondition(rest=(rest,)), (("a", "thing"),))


def test_10000_deep_grounded_formulas_and_effects_round_trip():
    gm = deep_ground_model()
    buf = io.StringIO()
    write_grounded_json(gm, buf)
    assert json_depth(buf.getvalue()) <= 6  # the node table is flat
    back = grounded_from_json(json.loads(buf.getvalue()))
    assert deep_equal(back, gm)
    # the condition object is shared by every `when`, in memory and in the file
    assert buf.getvalue().count('"t":"cond"') == 2  # the shared one and the goal's


def test_shared_sub_effects_are_written_once_and_shared_again_on_load(ppddl_benchmarks):
    from stampc.backends.ppddl.importer import import_ppddl
    sysadmin = ppddl_benchmarks / "ippc2008-sysadmin-slp"
    gm = ground(import_ppddl(sysadmin / "domain.pddl", sysadmin / "p05-n12-l6-s5.pddl"))
    data = grounded_to_json(gm, include_lifted=False)
    blocks_per_action = len(gm.actions[0].effect.blocks)
    distinct_blocks = {id(b) for a in gm.actions for b in a.effect.blocks}
    assert sum(n["t"] == "prob" for n in data["nodes"]) == len(distinct_blocks)
    assert len(distinct_blocks) < blocks_per_action * len(gm.actions) / 4
    back = grounded_from_json(data)
    assert back == gm
    first, second = back.actions[0].effect, back.actions[1].effect
    assert first.whens[0] is second.whens[0]  # one object per node, as grounding made them
    assert len({id(b) for a in back.actions for b in a.effect.blocks}) == len(distinct_blocks)


def _many_similar_effects(n_actions: int = 40, n_blocks: int = 200) -> GroundModel:
    """SysAdmin's shape: every action has all blocks but its own, plus one of its own."""
    facts = tuple(GroundAtom("up", (f"c{i}",)) for i in range(n_blocks))
    blocks = [GProb(((F(1, 20), GEffect(delete=1 << i)),)) for i in range(n_blocks)]
    actions = tuple(
        GroundAction(k, "reboot", (f"c{k}",), GroundCondition(), GEffect(blocks=(
            GProb(((F(9, 10), GEffect(add=1 << k)),)), *blocks[:k], *blocks[k + 1:])), F(1))
        for k in range(n_actions))
    return GroundModel(facts, actions, 0, GroundCondition(), (("c0", "comp"),))


def test_long_reference_lists_share_runs_through_seq_nodes():
    gm = _many_similar_effects()
    data = grounded_to_json(gm)
    nodes = data["nodes"]
    seqs = [n for n in nodes if n["t"] == "seq"]
    assert seqs and all(len(n["items"]) >= 2 for n in seqs)
    effect_refs = sum(len(nodes[a["effect"]]["blocks"]) for a in data["actions"])
    assert effect_refs < len(gm.actions) * 200 / 4  # runs shared, not spelled per action
    back = grounded_from_json(json.loads(json.dumps(data)))
    assert back == gm
    assert back.actions[3].effect.blocks[10] is back.actions[7].effect.blocks[10]  # both b10


@pytest.mark.parametrize("bad_seq", [{"t": "seq", "items": [0]}, {"t": "seq", "items": []}])
def test_seq_nodes_need_two_items(bad_seq):
    data = grounded_to_json(_many_similar_effects(3, 40))
    data["nodes"].append(bad_seq)
    with pytest.raises(StampcError) as exc:
        grounded_from_json(data)
    assert exc.value.diagnostics[0].code == "G192" and "two or more" in \
        exc.value.diagnostics[0].message


def test_a_seq_of_the_wrong_kind_is_rejected_where_it_is_used():
    data = grounded_to_json(_many_similar_effects(3, 40))
    nodes = data["nodes"]
    seq = next(k for k, n in enumerate(nodes) if n["t"] == "seq")
    cond = next(k for k, n in enumerate(nodes) if n["t"] == "cond")
    nodes.append({"t": "seq", "items": [cond, cond]})
    nodes.append({"t": "effect", "blocks": [seq, len(nodes) - 1]})
    data["actions"][0]["effect"] = len(nodes) - 1
    with pytest.raises(StampcError) as exc:
        grounded_from_json(data)
    assert exc.value.diagnostics[0].code == "G192" and "GProb" in exc.value.diagnostics[0].message
