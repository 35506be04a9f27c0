"""Factored JSON form of the grounded IR (format: docs/ir.md, "Grounded documents").

Conditions, formulas, ``when`` pairs, probabilistic blocks and effects live once in a
``"nodes"`` table and are referred to by position, so a sub-effect that the grounder
shares between actions (SysAdmin's per-computer blocks) is written once, not once per
action, and nesting depth never reaches the JSON text. Every node only refers to nodes
before it: the writer interns bottom-up with an explicit stack, the reader builds the
objects in one forward pass; neither recurses. Equal nodes are merged (by their text),
which keeps ``load(dump(x)) == x``.
"""

from __future__ import annotations

from itertools import compress, repeat
from operator import is_
from typing import Any, Callable, Sequence

from stampc.ir.grounded import (
    NO_AXIOMS, AxiomProgram, GAnd, GEffect, GLit, GOr, GProb, GroundAction, GroundAtom,
    GroundAxiom, GroundCondition, GroundGeneratorUse, GroundModel)
from stampc.ir.json_lifted import J, frac_from, frac_to
from stampc.ir.json_model import Write, compact, write_items
from stampc.ir.masks import FactSet, bits_to_list, from_indices, indices, list_to_int


# ----------------------------------------------------------------- bitmasks
def _checked(values: Any, n_facts: int | None) -> list[int]:
    values = _list(values)
    for i in values:
        if isinstance(i, bool) or not isinstance(i, int) or i < 0 or \
                (n_facts is not None and i >= n_facts):
            raise ValueError(f"invalid fact index {i!r}")
    return values


def list_to_bits(indices: Any, n_facts: int | None = None) -> int:
    """Inverse of :func:`bits_to_list`; checks indices against ``n_facts`` when given."""
    return list_to_int(_checked(indices, n_facts))


def _fact_set(indices: Any, n_facts: int) -> FactSet:
    return from_indices(_checked(indices, n_facts))


def _list(x: Any) -> list:
    if not isinstance(x, list):
        raise TypeError(f"expected a list, got {x!r}")
    return x


# ------------------------------------------------------------------ writing
def _children(obj: Any) -> Sequence[Any]:
    if isinstance(obj, GEffect):
        return obj.whens + obj.blocks
    if isinstance(obj, GroundCondition):
        return obj.rest
    if isinstance(obj, (GAnd, GOr)):
        return obj.args
    if isinstance(obj, GProb):
        return [e for _, e in obj.outcomes]
    if isinstance(obj, tuple):  # a (condition, effect) pair of GEffect.whens
        return obj
    return ()


#: Reference lists that may hold ``seq`` nodes; runs average ``_CHUNK`` references.
_LISTS = ("whens", "blocks", "rest", "args")
_CHUNK = 16


def _masks(out: J, *pairs: tuple[str, FactSet]) -> J:
    for key, facts in pairs:
        if facts:
            out[key] = list(indices(facts))
    return out


class NodeWriter:
    """Interns grounded sub-structures into the node table, writing each new node."""

    def __init__(self, emit: Callable[[str], None]) -> None:
        self.emit = emit
        self.by_id: dict[int, int] = {}  # id(object) -> node; objects outlive the writer
        self.by_text: dict[str, int] = {}
        self._seqs: dict[tuple[int, ...], int] = {}
        self._cut: list[bool] = []  # per node: does a run end after it?

    def intern(self, root: Any) -> int:
        by_id = self.by_id
        stack = [root]
        while stack:
            obj = stack[-1]
            if id(obj) in by_id:
                stack.pop()
                continue
            kids = _children(obj)
            refs = list(map(by_id.get, map(id, kids)))  # C loops: effects have 1000s of kids
            if None in refs:
                # reversed: nodes get ascending numbers in child order
                stack.extend(reversed(list(compress(kids, map(is_, refs, repeat(None))))))
                continue
            stack.pop()
            node = _node(obj, refs)
            for key in _LISTS:
                if len(node.get(key, ())) > 2 * _CHUNK:
                    node[key] = self._chunked(node[key])
            by_id[id(obj)] = self._add(compact(node))
        return by_id[id(root)]

    def _chunked(self, refs: list[int]) -> list[int]:
        """``refs`` with runs replaced by ``seq`` nodes, cut where the content says.

        A cut falls after each reference whose hash is 0 mod ``_CHUNK``, so a list that
        differs from another in a few places (SysAdmin: each action's blocks minus the
        rebooted computer's) shares every run that avoids those places: SysAdmin p14's
        2.8 million references become about 0.2 million.
        """
        cut = self._cut
        while len(cut) < len(self.by_text):
            cut.append((len(cut) * 2654435761 >> 8) % _CHUNK == 0)
        ends = list(compress(range(1, len(refs) + 1), map(cut.__getitem__, refs)))
        if not ends or ends[-1] != len(refs):
            ends.append(len(refs))
        out, start = [], 0
        for end in ends:
            run = tuple(refs[start:end])
            start = end
            if len(run) == 1:
                out.append(run[0])
                continue
            ref = self._seqs.get(run)
            if ref is None:
                ref = self._seqs[run] = self._add(compact({"t": "seq", "items": run}))
            out.append(ref)
        return out

    def _add(self, text: str) -> int:
        node = self.by_text.get(text)
        if node is None:
            node = self.by_text[text] = len(self.by_text)
            self.emit(text)
        return node


def _node(obj: Any, refs: list[int]) -> J:
    """The node of ``obj`` given the nodes of its children (``refs``, in order)."""
    if isinstance(obj, GEffect):
        out = _masks({"t": "effect"}, ("add", obj.add_facts), ("del", obj.delete_facts),
                     ("unknown", obj.unknown_facts))
        if obj.cost:
            out["cost"] = frac_to(obj.cost)
        n_whens = len(obj.whens)
        if n_whens:
            out["whens"] = refs[:n_whens]
        if obj.blocks:
            out["blocks"] = refs[n_whens:]
        return out
    if isinstance(obj, GroundCondition):
        out = _masks({"t": "cond"}, ("pos", obj.pos_facts), ("neg", obj.neg_facts))
        if obj.rest:
            out["rest"] = refs
        if obj.never:
            out["never"] = True
        return out
    if isinstance(obj, GLit):
        return {"t": "lit" if obj.positive else "not", "fact": obj.fact}
    if isinstance(obj, (GAnd, GOr)):
        return {"t": "and" if isinstance(obj, GAnd) else "or", "args": refs}
    if isinstance(obj, GProb):
        return {"t": "prob", "outcomes": [[frac_to(p), r] for (p, _), r in zip(obj.outcomes, refs)]}
    if isinstance(obj, tuple):
        return {"t": "when", "cond": refs[0], "effect": refs[1]}
    raise TypeError(f"not a grounded IR node: {obj!r}")


def _atom_to(a: GroundAtom) -> str:
    return compact([a.predicate, list(a.args)])


def _action_to(a: GroundAction, pre: int, effect: int) -> str:
    out: J = {"name": a.name, "args": list(a.args), "schema": a.schema, "pre": pre,
              "effect": effect, "base_cost": frac_to(a.base_cost)}
    if a.generated:
        out["generated"] = [{"generator": g.generator, "inputs": list(g.inputs),
                             "outputs": list(g.outputs)} for g in a.generated]
    if a.delete_wins:  # --conflicting-effects delete-wins (absent: the PDDL rule, add wins)
        out["delete_wins"] = True
    return compact(out)


def write_grounded(gm: GroundModel, header: J, write: Write,
                   write_lifted: Callable[[], None] | None) -> None:
    """Stream the grounded document; ``write_lifted`` writes the embedded lifted one."""
    write(compact(header)[:-1] + ',\n"facts":')
    write_items(write, (_atom_to(f) for f in gm.facts))
    write(',\n"objects":')
    write_items(write, (compact([n, t]) for n, t in gm.objects))
    write(',\n"static_facts":')
    write_items(write, (_atom_to(f) for f in gm.static_facts))
    write(',\n"nodes":[')
    first = [True]

    def emit(text: str) -> None:
        write("\n" if first[0] else ",\n")
        write(text)
        first[0] = False

    nodes = NodeWriter(emit)
    refs = [(nodes.intern(a.precondition), nodes.intern(a.effect)) for a in gm.actions]
    goal = nodes.intern(gm.goal)
    bodies = [nodes.intern(r.body) for r in gm.axioms.rules]
    write('],\n"actions":')
    write_items(write, (_action_to(a, p, e) for a, (p, e) in zip(gm.actions, refs)))
    if gm.axioms:  # 2.2: derived facts and their ground axioms (docs/ir.md)
        write(',\n"derived":' + compact(bits_to_list(gm.axioms.derived)) + ',\n"axioms":')
        write_items(write, (compact([r.head, b, r.stratum])
                            for r, b in zip(gm.axioms.rules, bodies)))
    write(',\n"init":' + compact(bits_to_list(gm.init)) + ',\n"goal":' + str(goal) +
          ',\n"horizon":' + compact(gm.horizon) + ',"has_costs":' + compact(gm.has_costs) +
          ',\n"lifted":')
    if write_lifted is None:
        write("null")
    else:
        write_lifted()
    write("}\n")


# ------------------------------------------------------------------ reading
class _Seq(tuple):
    """A ``seq`` node: a run of references spliced into the list that names it."""


_ANY_NODE = (GLit, GAnd, GOr, GroundCondition, tuple, GProb, GEffect)


class NodeReader:
    """Builds the node table's objects in order (each node refers only backwards)."""

    def __init__(self, n_facts: int) -> None:
        self.n = n_facts
        self.objs: list[Any] = []

    def read(self, nodes: Any) -> None:
        for x in _list(nodes):
            self.objs.append(self._node(x))

    def get(self, ref: Any, kind: type) -> Any:
        if isinstance(ref, bool) or not isinstance(ref, int) or not 0 <= ref < len(self.objs):
            raise ValueError(f"invalid node reference {ref!r}")
        obj = self.objs[ref]
        if type(obj) is not kind:
            raise ValueError(f"node {ref} is not a {kind.__name__}")
        return obj

    def _many(self, refs: Any, kinds: tuple[type, ...]) -> tuple:
        refs = _list(refs)
        if refs and (min(refs) < 0 or max(refs) >= len(self.objs)):
            raise ValueError("node reference out of range")
        objs = self.objs
        out = tuple([objs[r] for r in refs])
        if _Seq in set(map(type, out)):  # splice the runs in
            flat: list = []
            for o in out:
                if type(o) is _Seq:
                    flat.extend(o)
                else:
                    flat.append(o)
            out = tuple(flat)
        if not all(type(o) in kinds for o in out):
            raise ValueError(f"a reference does not point at a {kinds[0].__name__}")
        return out

    def _seq(self, items: Any) -> _Seq:
        run = self._many(items, _ANY_NODE)
        if len(run) < 2:
            raise ValueError("a seq node needs two or more items")
        return _Seq(run)

    def _node(self, x: J) -> Any:
        tag = x["t"]
        n = self.n
        if tag == "effect":
            return GEffect(
                add=_fact_set(x.get("add", []), n), delete=_fact_set(x.get("del", []), n),
                cost=frac_from(x.get("cost", "0")), unknown=_fact_set(x.get("unknown", []), n),
                whens=self._many(x.get("whens", []), (tuple,)),
                blocks=self._many(x.get("blocks", []), (GProb,)))
        if tag == "cond":
            return GroundCondition(_fact_set(x.get("pos", []), n),
                                   _fact_set(x.get("neg", []), n),
                                   self._many(x.get("rest", []), (GLit, GAnd, GOr)),
                                   bool(x.get("never", False)))
        if tag in ("lit", "not"):
            fact = x["fact"]
            if isinstance(fact, bool) or not isinstance(fact, int) or not 0 <= fact < n:
                raise ValueError(f"invalid fact index {fact!r}")
            return GLit(fact, tag == "lit")
        if tag in ("and", "or"):
            args = self._many(x["args"], (GLit, GAnd, GOr))
            return GAnd(args) if tag == "and" else GOr(args)
        if tag == "prob":
            return GProb(tuple((frac_from(p), self.get(e, GEffect)) for p, e in x["outcomes"]))
        if tag == "when":
            return (self.get(x["cond"], GroundCondition), self.get(x["effect"], GEffect))
        if tag == "seq":
            return self._seq(x["items"])
        raise ValueError(f"unknown node tag {tag!r}")


def _atom_from(x: Any) -> GroundAtom:
    pred, args = x
    return GroundAtom(str(pred), tuple(str(a) for a in _list(args)))


def _action_from(x: J, position: int, nodes: NodeReader) -> GroundAction:
    return GroundAction(
        index=position, name=str(x["name"]), args=tuple(str(a) for a in _list(x["args"])),
        precondition=nodes.get(x["pre"], GroundCondition),
        effect=nodes.get(x["effect"], GEffect),
        base_cost=frac_from(x["base_cost"]), schema=int(x["schema"]),
        generated=tuple(GroundGeneratorUse(str(g["generator"]), tuple(g["inputs"]),
                                           tuple(g["outputs"])) for g in x.get("generated", ())),
        delete_wins=x.get("delete_wins", False) is True)


def read_grounded(data: J, lifted: Any) -> GroundModel:
    """The model of a grounded document whose header has been checked."""
    facts = tuple(_atom_from(f) for f in _list(data["facts"]))
    nodes = NodeReader(len(facts))
    nodes.read(data["nodes"])
    horizon = data.get("horizon")
    if horizon is not None and (isinstance(horizon, bool) or not isinstance(horizon, int)):
        raise TypeError(f"horizon must be an integer, got {horizon!r}")
    return GroundModel(
        facts=facts,
        actions=tuple(_action_from(a, i, nodes) for i, a in enumerate(_list(data["actions"]))),
        init=list_to_bits(data["init"], len(facts)),
        goal=nodes.get(data["goal"], GroundCondition),
        objects=tuple((str(n), str(t)) for n, t in data["objects"]),
        static_facts=tuple(_atom_from(f) for f in data.get("static_facts", [])),
        horizon=horizon, has_costs=bool(data.get("has_costs", False)), lifted=lifted,
        axioms=_axioms_from(data, len(facts), nodes))


def _axioms_from(data: J, n_facts: int, nodes: NodeReader) -> AxiomProgram:
    if "derived" not in data:
        return NO_AXIOMS
    derived = list_to_bits(data["derived"], n_facts)
    rules = []
    for head, body, stratum in (_list(r) for r in _list(data.get("axioms", []))):
        if isinstance(head, bool) or not isinstance(head, int) or not (derived >> head) & 1:
            raise ValueError(f"axiom head {head!r} is not a derived fact")
        if isinstance(stratum, bool) or not isinstance(stratum, int) or stratum < 0:
            raise ValueError(f"invalid axiom stratum {stratum!r}")
        rules.append(GroundAxiom(head, nodes.get(body, GroundCondition), stratum))
    if [r.stratum for r in rules] != sorted(r.stratum for r in rules):
        raise ValueError("axioms must be listed by stratum")
    return AxiomProgram(tuple(rules), derived)
