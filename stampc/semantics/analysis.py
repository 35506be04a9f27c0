"""Walks over formulas and effects shared by lints and lowering: which predicates are
read (with which polarity), added, deleted or made unknown (``?``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

from stampc.diagnostics import Span
from stampc.semantics.scope import DomainInfo
from stampc.syntax import ast


def formula_reads(f: ast.Formula | None, out: dict[str, set[bool]], positive: bool = True,
                  derived: Mapping[str, ast.Formula] | None = None) -> None:
    """Record ``predicate -> {polarities}`` for every atom read by ``f``; an atom of a
    derived predicate (in ``derived``) also reads its definition, with the polarity of
    the atom (so `?` facts read through a derived predicate get the right optimism)."""
    if f is None:
        return
    if isinstance(f, ast.Atom):
        name = f.predicate.name
        first = positive not in out.get(name, ())
        out.setdefault(name, set()).add(positive)
        if derived and first and name in derived:  # each (predicate, polarity) once: recursion ends
            formula_reads(derived[name], out, positive, derived)
    elif isinstance(f, ast.Not):
        formula_reads(f.arg, out, not positive, derived)
    elif isinstance(f, (ast.And, ast.Or)):
        for a in f.args:
            formula_reads(a, out, positive, derived)
    elif isinstance(f, ast.Implies):
        formula_reads(f.left, out, not positive, derived)
        formula_reads(f.right, out, positive, derived)
    elif isinstance(f, ast.Quantified):
        formula_reads(f.body, out, positive, derived)


def definitions(info: DomainInfo) -> dict[str, ast.Formula]:
    """Derived predicate -> its definition."""
    return {n: d.derived for n, d in info.predicates.items() if d.derived is not None}


@dataclass
class EffectFacts:
    """Predicates an effect adds, deletes, marks unknown (first span), reads in `when`."""

    adds: set[str] = field(default_factory=set)
    deletes: set[str] = field(default_factory=set)
    unknown: dict[str, Span] = field(default_factory=dict)
    when_reads: dict[str, set[bool]] = field(default_factory=dict)
    functions: set[str] = field(default_factory=set)


def effect_facts(e: ast.Effect | None, out: EffectFacts,
                 derived: Mapping[str, ast.Formula] | None = None) -> None:
    if e is None:
        return
    if isinstance(e, ast.Lit):
        (out.adds if e.positive else out.deletes).add(e.atom.predicate.name)
    elif isinstance(e, ast.Unknown):
        out.unknown.setdefault(e.atom.predicate.name, e.span)
    elif isinstance(e, ast.EffAnd):
        for x in e.effects:
            effect_facts(x, out, derived)
    elif isinstance(e, ast.When):
        formula_reads(e.condition, out.when_reads, True, derived)
        effect_facts(e.effect, out, derived)
    elif isinstance(e, ast.EffForall):
        effect_facts(e.effect, out, derived)
    elif isinstance(e, ast.Probabilistic):
        for o in e.outcomes:
            effect_facts(o.effect, out, derived)
    elif isinstance(e, ast.CostEffect):
        numexpr_functions(e.amount, out.functions)


def numexpr_functions(e: ast.NumExpr | None, out: set[str]) -> None:
    if isinstance(e, ast.FuncApp):
        out.add(e.function.name)
    elif isinstance(e, ast.BinOp):
        numexpr_functions(e.left, out)
        numexpr_functions(e.right, out)


@dataclass(frozen=True)
class DomainFacts:
    effects: EffectFacts
    pre_reads: dict[str, set[bool]]   # preconditions and `when` conditions


def domain_facts(info: DomainInfo) -> DomainFacts:
    effects = EffectFacts()
    reads: dict[str, set[bool]] = {}
    derived = definitions(info)
    for a in info.actions:
        formula_reads(a.pre, reads, True, derived)
        effect_facts(a.eff, effects, derived)
        numexpr_functions(a.cost, effects.functions)
    for pred, pols in effects.when_reads.items():
        reads.setdefault(pred, set()).update(pols)
    for name, decl in info.predicates.items():
        if decl.unknown:  # `? predicate`: unknown from the start, as if a `?` effect said so
            effects.unknown.setdefault(name, decl.name.span)
    return DomainFacts(effects, reads)


def optimistic_values(info: DomainInfo, goal: ast.Formula | None) -> dict[str, bool]:
    """For each ``?`` predicate, the value the abstraction assumes: False when read only
    negatively (or both ways, or never), True when read only positively."""
    facts = domain_facts(info)
    reads = {k: set(v) for k, v in facts.pre_reads.items()}
    formula_reads(goal, reads, True, definitions(info))
    return {p: reads.get(p, set()) == {True} for p in facts.effects.unknown}
