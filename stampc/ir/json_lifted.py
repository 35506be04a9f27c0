"""JSON codec for the lifted IR's leaves and declarations (format: docs/ir.md).

Formula, effect and numeric trees are coded by :mod:`stampc.ir.json_tree`. Terms are
strings (``"?x"`` is a variable, anything else an object; an object whose name starts
with ``?`` is written ``{"const": name}``). Fractions are strings such as ``"1/3"``. Spans are ``[file, line, col, end_line,
end_col]`` and omitted when absent. Decoding errors surface as KeyError/TypeError/
ValueError; :mod:`stampc.ir.json_io` turns them into diagnostics.
"""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING, Any

from stampc.diagnostics import Span
from stampc.ir import lifted as L

if TYPE_CHECKING:  # json_tree builds on this module
    from stampc.ir.json_tree import TreeDecoder, TreeEncoder

J = dict[str, Any]


# ----------------------------------------------------------------- scalars
def frac_to(x: Fraction) -> str:
    return str(x) if type(x) is Fraction else str(Fraction(x))


def frac_from(s: Any) -> Fraction:
    if not isinstance(s, (str, int)) or isinstance(s, bool):
        raise TypeError(f"expected a fraction string, got {s!r}")
    return Fraction(s)


def span_to(s: Span | None) -> list | None:
    return None if s is None else [s.file, s.line, s.col, s.end_line, s.end_col]


def span_from(x: Any) -> Span | None:
    return None if x is None else Span(str(x[0]), int(x[1]), int(x[2]), int(x[3]), int(x[4]))


def _with_span(d: J, span: Span | None) -> J:
    if span is not None:
        d["span"] = span_to(span)
    return d


def value_to(v: Any) -> Any:
    return [value_to(x) for x in v] if isinstance(v, (tuple, list)) else v


def value_from(v: Any) -> Any:
    """JSON lists come back as tuples so decoded models stay hashable and ``==``."""
    return tuple(value_from(x) for x in v) if isinstance(v, list) else v


def pairs_to(items: tuple[tuple[str, object], ...]) -> list:
    return [[k, value_to(v)] for k, v in items]


def pairs_from(x: list) -> tuple[tuple[str, object], ...]:
    return tuple((str(k), value_from(v)) for k, v in x)


# ------------------------------------------------------------------- terms
def term_to(t: L.Term) -> Any:
    if isinstance(t, L.Var):
        return "?" + t.name
    return {"const": t.name} if t.name.startswith("?") else t.name


def term_from(x: Any) -> L.Term:
    if isinstance(x, dict):
        return L.Const(str(x["const"]))
    if not isinstance(x, str):
        raise TypeError(f"expected a term string, got {x!r}")
    return L.Var(x[1:]) if x.startswith("?") else L.Const(x)


def params_to(ps: tuple[L.Param, ...]) -> list:
    return [[p.name, p.type] for p in ps]


def params_from(x: list) -> tuple[L.Param, ...]:
    return tuple(L.Param(str(n), str(t)) for n, t in x)


def atom_to(a: L.Atom) -> J:
    return {"pred": a.predicate, "args": [term_to(t) for t in a.args]}


def atom_from(x: J) -> L.Atom:
    return L.Atom(str(x["pred"]), tuple(term_from(t) for t in x["args"]))


# ------------------------------------------------------------ declarations
def binding_to(b: L.Binding | None) -> J | None:
    return None if b is None else _with_span({"target": b.target}, b.span)


def binding_from(x: J | None) -> L.Binding | None:
    return None if x is None else L.Binding(str(x["target"]), span_from(x.get("span")))


def action_to(a: L.Action, trees: "TreeEncoder") -> J:
    return _with_span({
        "name": a.name, "params": params_to(a.params), "pre": trees.encode(a.precondition),
        "effect": trees.encode(a.effect), "cost": None if a.cost is None else trees.encode(a.cost),
        "generated": [{"generator": g.generator, "inputs": list(g.inputs),
                       "outputs": list(g.outputs)} for g in a.generated],
        "executes": binding_to(a.executes)}, a.span)


def action_from(x: J, trees: "TreeDecoder") -> L.Action:
    return L.Action(
        str(x["name"]), params_from(x["params"]), trees.formula(x["pre"]),
        trees.effect(x["effect"]), None if x.get("cost") is None else trees.num(x["cost"]),
        tuple(L.GeneratorUse(str(g["generator"]), tuple(g["inputs"]), tuple(g["outputs"]))
              for g in x.get("generated", ())),
        binding_from(x.get("executes")), span_from(x.get("span")))


def generator_to(g: L.Generator) -> J:
    return _with_span({
        "name": g.name, "inputs": params_to(g.inputs), "outputs": params_to(g.outputs),
        "certifies": [atom_to(a) for a in g.certifies], "binding": binding_to(g.binding),
        "options": pairs_to(g.options)}, g.span)


def generator_from(x: J) -> L.Generator:
    return L.Generator(str(x["name"]), params_from(x["inputs"]), params_from(x["outputs"]),
                       tuple(atom_from(a) for a in x["certifies"]),
                       binding_from(x["binding"]), pairs_from(x.get("options", [])),
                       span_from(x.get("span")))
