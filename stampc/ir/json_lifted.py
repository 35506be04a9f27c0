"""JSON codec for the lifted IR (format documented in docs/ir.md).

Terms are strings (``"?x"`` is a variable, anything else an object; an object whose
name starts with ``?`` is written ``{"const": name}``). Tree nodes carry a ``"t"`` tag.
Fractions are strings such as ``"1/3"``. Spans are ``[file, line, col, end_line,
end_col]`` and omitted when absent. Decoding errors surface as KeyError/TypeError/
ValueError; :mod:`stampc.ir.json_io` turns them into diagnostics.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from stampc.diagnostics import Span
from stampc.ir import lifted as L

J = dict[str, Any]


# ----------------------------------------------------------------- scalars
def frac_to(x: Fraction) -> str:
    return str(Fraction(x))


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


# ---------------------------------------------------------------- formulas
def formula_to(f: L.Formula) -> J:
    if isinstance(f, L.Atom):
        return {"t": "atom", **atom_to(f)}
    if isinstance(f, L.Equals):
        return {"t": "eq", "args": [term_to(f.left), term_to(f.right)]}
    if isinstance(f, L.Not):
        return {"t": "not", "arg": formula_to(f.arg)}
    if isinstance(f, (L.And, L.Or)):
        return {"t": "and" if isinstance(f, L.And) else "or",
                "args": [formula_to(a) for a in f.args]}
    if isinstance(f, L.Imply):
        return {"t": "imply", "args": [formula_to(f.left), formula_to(f.right)]}
    if isinstance(f, (L.Forall, L.Exists)):
        return {"t": "forall" if isinstance(f, L.Forall) else "exists",
                "params": params_to(f.params), "body": formula_to(f.body)}
    if isinstance(f, L.Truth):
        return {"t": "truth", "value": f.value}
    raise TypeError(f"not a formula: {f!r}")


def formula_from(x: J) -> L.Formula:
    tag = x["t"]
    if tag == "atom":
        return atom_from(x)
    if tag == "eq":
        left, right = x["args"]
        return L.Equals(term_from(left), term_from(right))
    if tag == "not":
        return L.Not(formula_from(x["arg"]))
    if tag in ("and", "or"):
        args = tuple(formula_from(a) for a in x["args"])
        return L.And(args) if tag == "and" else L.Or(args)
    if tag == "imply":
        left, right = x["args"]
        return L.Imply(formula_from(left), formula_from(right))
    if tag in ("forall", "exists"):
        cls = L.Forall if tag == "forall" else L.Exists
        return cls(params_from(x["params"]), formula_from(x["body"]))
    if tag == "truth":
        return L.Truth(bool(x["value"]))
    raise ValueError(f"unknown formula tag {tag!r}")


def num_to(e: L.NumExpr) -> J:
    if isinstance(e, L.Num):
        return {"t": "num", "value": frac_to(e.value)}
    if isinstance(e, L.FuncTerm):
        return {"t": "func", "name": e.function, "args": [term_to(a) for a in e.args]}
    return {"t": "binop", "op": e.op, "left": num_to(e.left), "right": num_to(e.right)}


def num_from(x: J) -> L.NumExpr:
    tag = x["t"]
    if tag == "num":
        return L.Num(frac_from(x["value"]))
    if tag == "func":
        return L.FuncTerm(str(x["name"]), tuple(term_from(a) for a in x["args"]))
    if tag == "binop":
        return L.BinOp(str(x["op"]), num_from(x["left"]), num_from(x["right"]))
    raise ValueError(f"unknown numeric expression tag {tag!r}")


# ----------------------------------------------------------------- effects
def effect_to(e: L.Effect) -> J:
    if isinstance(e, L.Lit):
        return {"t": "lit", "atom": atom_to(e.atom), "positive": e.positive}
    if isinstance(e, L.Unknown):
        return {"t": "unknown", "atom": atom_to(e.atom)}
    if isinstance(e, L.EffAnd):
        return {"t": "and", "effects": [effect_to(s) for s in e.effects]}
    if isinstance(e, L.When):
        return {"t": "when", "cond": formula_to(e.condition), "effect": effect_to(e.effect)}
    if isinstance(e, L.EffForall):
        return {"t": "forall", "params": params_to(e.params), "effect": effect_to(e.effect)}
    if isinstance(e, L.Probabilistic):
        return {"t": "prob", "outcomes": [
            {"p": frac_to(o.probability), "effect": effect_to(o.effect), "label": o.label}
            for o in e.outcomes]}
    if isinstance(e, L.CostEffect):
        return {"t": "cost", "amount": num_to(e.amount)}
    raise TypeError(f"not an effect: {e!r}")


def effect_from(x: J) -> L.Effect:
    tag = x["t"]
    if tag == "lit":
        return L.Lit(atom_from(x["atom"]), bool(x["positive"]))
    if tag == "unknown":
        return L.Unknown(atom_from(x["atom"]))
    if tag == "and":
        return L.EffAnd(tuple(effect_from(s) for s in x["effects"]))
    if tag == "when":
        return L.When(formula_from(x["cond"]), effect_from(x["effect"]))
    if tag == "forall":
        return L.EffForall(params_from(x["params"]), effect_from(x["effect"]))
    if tag == "prob":
        return L.Probabilistic(tuple(
            L.Outcome(frac_from(o["p"]), effect_from(o["effect"]), o.get("label"))
            for o in x["outcomes"]))
    if tag == "cost":
        return L.CostEffect(num_from(x["amount"]))
    raise ValueError(f"unknown effect tag {tag!r}")


# ------------------------------------------------------------ declarations
def binding_to(b: L.Binding | None) -> J | None:
    return None if b is None else _with_span({"target": b.target}, b.span)


def binding_from(x: J | None) -> L.Binding | None:
    return None if x is None else L.Binding(str(x["target"]), span_from(x.get("span")))


def action_to(a: L.Action) -> J:
    return _with_span({
        "name": a.name, "params": params_to(a.params), "pre": formula_to(a.precondition),
        "effect": effect_to(a.effect), "cost": None if a.cost is None else num_to(a.cost),
        "generated": [{"generator": g.generator, "inputs": list(g.inputs),
                       "outputs": list(g.outputs)} for g in a.generated],
        "executes": binding_to(a.executes)}, a.span)


def action_from(x: J) -> L.Action:
    return L.Action(
        str(x["name"]), params_from(x["params"]), formula_from(x["pre"]),
        effect_from(x["effect"]), None if x.get("cost") is None else num_from(x["cost"]),
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
