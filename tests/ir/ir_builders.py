"""Small builders for hand-written lifted models used by the grounding tests.

Terms are strings: ``"?x"`` is a variable, anything else an object name.
"""

from __future__ import annotations

from fractions import Fraction

from stampc.diagnostics import Span
from stampc.ir import lifted as L
from stampc.ir.grounded import GroundAtom, GroundModel


def term(s: str) -> L.Term:
    return L.Var(s[1:]) if s.startswith("?") else L.Const(s)


def atom(pred: str, *args: str) -> L.Atom:
    return L.Atom(pred, tuple(term(a) for a in args))


def params(*pairs: tuple[str, str]) -> tuple[L.Param, ...]:
    return tuple(L.Param(n.lstrip("?"), t) for n, t in pairs)


def pred(name: str, *types: str, unknowable: bool = False,
         optimistic: bool = False) -> L.Predicate:
    return L.Predicate(name, tuple(L.Param(f"a{i}", t) for i, t in enumerate(types)),
                       unknowable=unknowable, optimistic=optimistic)


def AND(*fs: L.Formula) -> L.And:
    return L.And(tuple(fs))


def OR(*fs: L.Formula) -> L.Or:
    return L.Or(tuple(fs))


def NOT(f: L.Formula) -> L.Not:
    return L.Not(f)


def add(pred_name: str, *args: str) -> L.Lit:
    return L.Lit(atom(pred_name, *args), True)


def delete(pred_name: str, *args: str) -> L.Lit:
    return L.Lit(atom(pred_name, *args), False)


def EFF(*es: L.Effect) -> L.EffAnd:
    return L.EffAnd(tuple(es))


def prob(*pairs: tuple[str | Fraction, L.Effect]) -> L.Probabilistic:
    return L.Probabilistic(tuple(L.Outcome(Fraction(p), e) for p, e in pairs))


def action(name: str, ps: tuple[L.Param, ...] = (), pre: L.Formula = L.TRUE,
           eff: L.Effect = L.NO_EFFECT, **kw) -> L.Action:
    return L.Action(name, ps, pre, eff, span=Span(f"{name}.stamp", 3, 1, 3, 10), **kw)


def objects(spec: str) -> tuple[L.Object, ...]:
    """``"a b - block  t - table"`` -> typed objects (PDDL-style typed list)."""
    out: list[L.Object] = []
    pending: list[str] = []
    tokens = spec.split()
    i = 0
    while i < len(tokens):
        if tokens[i] == "-":
            out.extend(L.Object(n, tokens[i + 1]) for n in pending)
            pending = []
            i += 2
        else:
            pending.append(tokens[i])
            i += 1
    out.extend(L.Object(n, "object") for n in pending)
    return tuple(out)


def model(*, types: tuple[L.Type, ...] = (), preds: tuple[L.Predicate, ...] = (),
          actions: tuple[L.Action, ...] = (), objs: str = "", init: tuple[L.Atom, ...] = (),
          goal: L.Formula = L.TRUE, functions: tuple[L.Function, ...] = (),
          init_values: tuple = (), requirements: tuple[str, ...] = (),
          generators: tuple[L.Generator, ...] = (), constants: tuple[L.Object, ...] = (),
          horizon: int | None = None, name: str = "t") -> L.Model:
    domain = L.Domain(name, types, constants, preds, functions, actions, generators,
                      requirements=requirements, span=Span("domain.stamp", 1, 1, 1, 5))
    problem = L.Problem(f"{name}-p", name, objects(objs), init, init_values, goal, horizon,
                        span=Span("problem.stamp", 1, 1, 1, 5))
    return L.Model(domain, problem)


def fact(gm: GroundModel, pred_name: str, *args: str) -> int:
    """Bit of a fact in ``gm``."""
    return 1 << gm.fact_index(GroundAtom(pred_name, tuple(args)))


def state(gm: GroundModel, *atoms: tuple[str, ...]) -> int:
    return gm.state_of(GroundAtom(a[0], tuple(a[1:])) for a in atoms)


def find(gm: GroundModel, label: str):
    matches = [a for a in gm.actions if a.label == label]
    assert len(matches) == 1, f"{label}: {[a.label for a in gm.actions]}"
    return matches[0]


def labels(gm: GroundModel) -> list[str]:
    return [a.label for a in gm.actions]
