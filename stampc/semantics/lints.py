"""Whole-model lints: unused declarations, `?` facts nobody reads, unreachable goals."""

from __future__ import annotations

from stampc.diagnostics import Diagnostic
from stampc.semantics.analysis import definitions, domain_facts, formula_reads
from stampc.semantics.check_problem import ProblemInfo
from stampc.semantics.codes import diag
from stampc.semantics.generators import Production
from stampc.semantics.scope import DomainInfo
from stampc.semantics.terms import quantified_params
from stampc.syntax import ast


def lint_domain(info: DomainInfo, productions: dict[str, Production], problem: ProblemInfo | None,
                diags: list[Diagnostic]) -> None:
    """Warnings about the domain; ``problem`` (checked with it, if any) counts as a user
    of types (its objects) and predicates (its goal)."""
    goal = problem.goal if problem is not None else None
    facts = domain_facts(info)
    used_preds = set(facts.pre_reads) | facts.effects.adds | facts.effects.deletes | set(facts.effects.unknown)
    used_preds |= {a.predicate.name for g in info.generators.values() for a in g.certifies}
    goal_reads: dict[str, set[bool]] = {}
    formula_reads(goal, goal_reads, True, definitions(info))
    used_preds |= set(goal_reads)
    for name, decl in info.predicates.items():
        if name not in used_preds and info.is_local(decl.name.span):
            diags.append(diag("W401", f"predicate `{name}` is never used", decl.name.span,
                              "remove it, or use it in a precondition, effect or goal"))
    _lint_types(info, problem, diags)
    used_gens = {u.generator for p in productions.values() for u in p.uses}
    for name, gen in info.generators.items():
        if name not in used_gens and info.is_local(gen.name.span):
            diags.append(diag("W403", f"generator `{name}` is never used by an action", gen.name.span,
                              "an action uses it when a precondition is one of its certified facts"))
    for pred, span in facts.effects.unknown.items():
        if not info.is_local(span):
            continue
        pols = facts.pre_reads.get(pred, set())
        if not pols:
            diags.append(diag("W404", f"`?` fact `{pred}` is never read by a precondition", span,
                              "refinement decides it, but no action depends on it"))
        pols = pols | goal_reads.get(pred, set())
        if pols == {True, False}:
            diags.append(diag("W405", f"`?` predicate `{pred}` is read both positively and negatively; "
                                      "the abstraction assumes it false", span))
    evaluated = {ev.predicate.name for ev in info.evaluators}
    for name, decl in info.predicates.items():
        if decl.unknown and name not in evaluated and info.is_local(decl.name.span):
            diags.append(diag("W408", f"`? predicate {name}` has no evaluator: refinement never "
                                      "decides its facts", decl.name.span,
                              f"bind one: `evaluator {name}` with `binds \"module:function\"`"))
    for ev in info.evaluators:
        if ev.predicate.name in info.predicates and ev.predicate.name not in facts.effects.unknown \
                and info.is_local(ev.predicate.span):
            diags.append(diag("W406", f"evaluator for `{ev.predicate.name}`, which no effect marks with `?`",
                              ev.predicate.span))


def _lint_types(info: DomainInfo, problem: ProblemInfo | None, diags: list[Diagnostic]) -> None:
    used: set[str] = {t.parent for t in info.types.values() if t.parent}
    used |= {c.type for c in info.constants.values()}
    if problem is not None:  # a type only problem objects have is used (by them)
        used |= {o.type for o in problem.objects.values()}
    params: list[ast.Param] = []
    for d in list(info.predicates.values()) + list(info.functions.values()):
        params.extend(d.params)
    for g in info.generators.values():
        params.extend(g.inputs + g.outputs)
    for a in info.actions:
        params.extend(a.params)
        params.extend(quantified_params(a.pre))
        params.extend(quantified_params(a.eff))
    used |= {p.type.name for p in params}
    for name, t in info.types.items():
        if name not in used and info.is_local(t.ident.span):
            diags.append(diag("W402", f"type `{name}` is never used", t.ident.span,
                              "no parameter, constant, subtype or object has it" if problem is not None else
                              "no parameter, constant or subtype has it (no problem was checked with the domain)"))


def lint_problem(p: ProblemInfo, info: DomainInfo, diags: list[Diagnostic]) -> None:
    """E308: a positive top-level goal atom that no action adds (or makes `?`) and init lacks."""
    if p.goal is None:
        return
    facts = domain_facts(info)
    producible = facts.effects.adds | set(facts.effects.unknown)
    init = {(a.predicate.name, tuple(x.name for x in a.args)) for a in p.init}
    parts = p.goal.args if isinstance(p.goal, ast.And) else (p.goal,)
    for atom in parts:
        if not isinstance(atom, ast.Atom) or atom.predicate.name not in info.predicates \
                or info.predicates[atom.predicate.name].derived is not None:
            continue  # a derived goal holds when its definition does
        key = (atom.predicate.name, tuple(x.name for x in atom.args))
        if atom.predicate.name not in producible and key not in init:
            text = f"{atom.predicate.name}({', '.join(key[1])})" if key[1] else atom.predicate.name
            diags.append(diag("E308", f"goal fact `{text}` is unreachable: no action adds "
                                      f"`{atom.predicate.name}` and init does not contain it", atom.span,
                              "add an action effect that makes it true, or drop it from the goal"))
