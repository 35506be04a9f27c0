"""Versioned JSON form of the lifted and grounded IR (format: docs/ir.md).

Every document carries ``"ir_version"`` (:data:`stampc.ir.lifted.IR_VERSION`) and
``"kind"`` (``"lifted"`` or ``"grounded"``). Fractions are strings (``"1/3"``), state
bitmasks are sorted lists of fact indices. Loading checks version and kind and reports
malformed input as located diagnostics (G190-G192), never as bare exceptions. A round
trip gives an equal object (``==``).
"""

from __future__ import annotations

from typing import Any, Callable, TypeVar

from stampc.diagnostics import Span, StampcError, error
from stampc.ir import lifted as L
from stampc.ir.grounded import (
    GAnd, GEffect, GFormula, GLit, GOr, GProb, GroundAction, GroundAtom, GroundCondition,
    GroundGeneratorUse, GroundModel)
from stampc.ir.json_lifted import J, frac_from, frac_to
from stampc.ir.json_model import domain_from, domain_to, problem_from, problem_to

__all__ = ["lifted_to_json", "lifted_from_json", "grounded_to_json", "grounded_from_json",
           "bits_to_list", "list_to_bits"]

T = TypeVar("T")


# ----------------------------------------------------------------- helpers
def bits_to_list(mask: int) -> list[int]:
    """Indices of the set bits of ``mask``, ascending."""
    out: list[int] = []
    i = 0
    while mask:
        low = mask & 0xFFFFFFFF  # 32-bit chunks keep this linear in the mask size
        while low:
            b = low & -low
            out.append(i + b.bit_length() - 1)
            low ^= b
        mask >>= 32
        i += 32
    return out


def list_to_bits(indices: list[int], n_facts: int | None = None) -> int:
    """Inverse of :func:`bits_to_list`; checks indices against ``n_facts`` when given."""
    mask = 0
    for i in indices:
        if isinstance(i, bool) or not isinstance(i, int) or i < 0 or \
                (n_facts is not None and i >= n_facts):
            raise ValueError(f"invalid fact index {i!r}")
        mask |= 1 << i
    return mask


def _check_header(data: Any, kind: str, source: str) -> None:
    span = Span.point(source)
    if not isinstance(data, dict):
        raise StampcError([error("G192", f"expected a JSON object for the {kind} IR, "
                                 f"got {type(data).__name__}", span)])
    version = data.get("ir_version")
    if version != L.IR_VERSION:
        raise StampcError([error(
            "G190", f"unsupported IR version {version!r} (this stampc reads {L.IR_VERSION!r})",
            span, "re-export the file with this version of stampc")])
    if data.get("kind") != kind:
        raise StampcError([error("G191", f"expected a {kind!r} IR document, "
                                 f"got kind {data.get('kind')!r}", span)])


def _decode(kind: str, source: str, fn: Callable[[], T]) -> T:
    try:
        return fn()
    except StampcError:
        raise
    except (KeyError, TypeError, ValueError, IndexError, AttributeError,
            ZeroDivisionError) as exc:
        detail = f"missing field {exc}" if isinstance(exc, KeyError) else str(exc)
        raise StampcError([error("G192", f"malformed {kind} IR document: {detail}",
                                 Span.point(source))]) from None


# ------------------------------------------------------------------ lifted
def lifted_to_json(model: L.Model) -> dict:
    return {"ir_version": L.IR_VERSION, "kind": "lifted",
            "domain": domain_to(model.domain), "problem": problem_to(model.problem)}


def lifted_from_json(data: dict, *, source: str = "<json>") -> L.Model:
    """Inverse of :func:`lifted_to_json`; ``source`` names the file in diagnostics."""
    _check_header(data, "lifted", source)
    return _decode("lifted", source,
                   lambda: L.Model(domain_from(data["domain"]), problem_from(data["problem"])))


# ---------------------------------------------------------------- grounded
def _gformula_to(f: GFormula) -> J:
    if isinstance(f, GLit):
        return {"lit": f.fact} if f.positive else {"not": f.fact}
    return {"and" if isinstance(f, GAnd) else "or": [_gformula_to(a) for a in f.args]}


def _gformula_from(x: J, n: int) -> GFormula:
    if "lit" in x or "not" in x:
        positive = "lit" in x
        fact = x["lit"] if positive else x["not"]
        if isinstance(fact, bool) or not isinstance(fact, int) or not 0 <= fact < n:
            raise ValueError(f"invalid fact index {fact!r}")
        return GLit(fact, positive)
    if "and" in x:
        return GAnd(tuple(_gformula_from(a, n) for a in x["and"]))
    return GOr(tuple(_gformula_from(a, n) for a in x["or"]))


def _cond_to(c: GroundCondition) -> J:
    out: J = {}
    if c.pos:
        out["pos"] = bits_to_list(c.pos)
    if c.neg:
        out["neg"] = bits_to_list(c.neg)
    if c.rest:
        out["rest"] = [_gformula_to(f) for f in c.rest]
    if c.never:
        out["never"] = True
    return out


def _cond_from(x: J, n: int) -> GroundCondition:
    return GroundCondition(list_to_bits(x.get("pos", []), n), list_to_bits(x.get("neg", []), n),
                           tuple(_gformula_from(f, n) for f in x.get("rest", [])),
                           bool(x.get("never", False)))


def _effect_to(e: GEffect) -> J:
    out: J = {}
    for key, mask in (("add", e.add), ("del", e.delete), ("unknown", e.unknown)):
        if mask:
            out[key] = bits_to_list(mask)
    if e.cost:
        out["cost"] = frac_to(e.cost)
    if e.whens:
        out["whens"] = [[_cond_to(c), _effect_to(s)] for c, s in e.whens]
    if e.blocks:
        out["blocks"] = [[[frac_to(p), _effect_to(s)] for p, s in b.outcomes] for b in e.blocks]
    return out


def _effect_from(x: J, n: int) -> GEffect:
    return GEffect(
        add=list_to_bits(x.get("add", []), n), delete=list_to_bits(x.get("del", []), n),
        cost=frac_from(x.get("cost", "0")), unknown=list_to_bits(x.get("unknown", []), n),
        whens=tuple((_cond_from(c, n), _effect_from(s, n)) for c, s in x.get("whens", [])),
        blocks=tuple(GProb(tuple((frac_from(p), _effect_from(s, n)) for p, s in b))
                     for b in x.get("blocks", [])))


def _action_to(a: GroundAction) -> J:
    return {"index": a.index, "name": a.name, "args": list(a.args), "schema": a.schema,
            "pre": _cond_to(a.precondition), "effect": _effect_to(a.effect),
            "base_cost": frac_to(a.base_cost),
            "generated": [{"generator": g.generator, "inputs": list(g.inputs),
                           "outputs": list(g.outputs)} for g in a.generated]}


def _action_from(x: J, position: int, n: int) -> GroundAction:
    if x["index"] != position:
        raise ValueError(f"action at position {position} has index {x['index']}")
    return GroundAction(
        index=position, name=str(x["name"]), args=tuple(str(a) for a in x["args"]),
        precondition=_cond_from(x["pre"], n), effect=_effect_from(x["effect"], n),
        base_cost=frac_from(x["base_cost"]), schema=int(x["schema"]),
        generated=tuple(GroundGeneratorUse(str(g["generator"]), tuple(g["inputs"]),
                                           tuple(g["outputs"])) for g in x["generated"]))


def _atom_to(a: GroundAtom) -> list:
    return [a.predicate, list(a.args)]


def _atom_from(x: list) -> GroundAtom:
    pred, args = x
    return GroundAtom(str(pred), tuple(str(a) for a in args))


def grounded_to_json(gm: GroundModel, *, include_lifted: bool = True) -> dict:
    """JSON form of ``gm``; embeds the lifted model (if any) unless told not to."""
    return {
        "ir_version": L.IR_VERSION, "kind": "grounded",
        "facts": [_atom_to(f) for f in gm.facts],
        "actions": [_action_to(a) for a in gm.actions],
        "init": bits_to_list(gm.init),
        "goal": _cond_to(gm.goal),
        "objects": [[n, t] for n, t in gm.objects],
        "static_facts": [_atom_to(f) for f in gm.static_facts],
        "horizon": gm.horizon,
        "has_costs": gm.has_costs,
        "lifted": lifted_to_json(gm.lifted) if include_lifted and gm.lifted is not None else None,
    }


def grounded_from_json(data: dict, *, source: str = "<json>") -> GroundModel:
    """Inverse of :func:`grounded_to_json`; ``source`` names the file in diagnostics."""
    _check_header(data, "grounded", source)

    def build() -> GroundModel:
        lifted = data.get("lifted")
        facts = tuple(_atom_from(f) for f in data["facts"])
        n = len(facts)
        return GroundModel(
            facts=facts,
            actions=tuple(_action_from(a, i, n) for i, a in enumerate(data["actions"])),
            init=list_to_bits(data["init"], n),
            goal=_cond_from(data["goal"], n),
            objects=tuple((str(n), str(t)) for n, t in data["objects"]),
            static_facts=tuple(_atom_from(f) for f in data.get("static_facts", [])),
            horizon=data.get("horizon"),
            has_costs=bool(data.get("has_costs", False)),
            lifted=None if lifted is None else lifted_from_json(lifted, source=source))

    return _decode("grounded", source, build)

