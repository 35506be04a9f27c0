"""Type checking of domain declarations: predicates, generators, evaluators, actions."""

from __future__ import annotations

import re
from dataclasses import replace
from fractions import Fraction

from stampc.diagnostics import Diagnostic, Label
from stampc.semantics.analysis import domain_facts
from stampc.semantics.codes import diag
from stampc.semantics.derived import check_derived, effect_on_derived
from stampc.semantics.generators import Production, infer
from stampc.semantics.scope import DomainInfo, suggest
from stampc.semantics.terms import (Ctx, check_args, check_atom, check_formula, check_numexpr,
                                    check_params, quantified_params)
from stampc.semantics.scope_hints import binder_hints, effect_hints
from stampc.syntax import ast

BINDING = re.compile(r"^\.?[A-Za-z_]\w*(\.[A-Za-z_]\w*)*:[A-Za-z_]\w*(\.[A-Za-z_]\w*)*$")
BINDING_HINT = 'write "package.module:function" (a leading "." is relative to the world package)'


def check_binding(binding: ast.String | None, owner: ast.Ident, what: str, diags: list[Diagnostic]) -> None:
    if binding is None:
        diags.append(diag("E306", f"{what} `{owner.name}` has no `binds` clause", owner.span, BINDING_HINT))
    elif not BINDING.match(binding.value):
        diags.append(diag("E306", f'malformed binding "{binding.value}"', binding.span, BINDING_HINT))


def check_domain(info: DomainInfo, diags: list[Diagnostic]) -> dict[str, Production]:
    """All domain checks; returns the generator production of every action."""
    base = Ctx(info, diags, {c.name: c.type for c in info.constants.values()})
    for c in info.constants.values():
        if c.type not in info.types:
            diags.append(diag("E101", f"undefined type `{c.type}`", c.ident.span,
                              suggest(c.type, info.types)))
    for decl in info.functions.values():
        check_params(decl.params, base)
    for decl in info.predicates.values():
        if decl.derived is None:
            check_params(decl.params, base)
    check_derived(info, base)
    for gen in info.generators.values():
        _check_generator(gen, base)
    for ev in info.evaluators:
        if ev.predicate.name not in info.predicates:
            diags.append(diag("E102", f"evaluator for undefined predicate `{ev.predicate.name}`",
                              ev.predicate.span, suggest(ev.predicate.name, info.predicates)))
        check_binding(ev.binding, ev.predicate, "evaluator", diags)
        _check_options(ev.options, diags)
    unknowable = frozenset(domain_facts(info).effects.unknown)
    productions: dict[str, Production] = {}
    for action in info.actions:
        productions[action.name.name] = _check_action(action, base, unknowable)
    return productions


def _check_options(options: tuple[ast.Option, ...], diags: list[Diagnostic]) -> None:
    for opt in options:
        if opt.name.name == "budget":
            v = opt.value
            if not isinstance(v, ast.Number) or v.value.denominator != 1 or v.value < 1:
                diags.append(diag("E004", "`budget` must be a positive integer", opt.span))


def _check_generator(gen: ast.GeneratorDecl, base: Ctx) -> None:
    info, diags = base.info, base.diags
    env = check_params(gen.inputs + gen.outputs, base)
    for out in gen.outputs:
        if out.type.name in info.types and not info.is_continuous(out.type.name):
            diags.append(diag("E309", f"generator output `{out.name.name}` has the non-continuous type "
                                      f"`{out.type.name}`", out.type.span,
                              "generators produce values of `continuous type`s (poses, grasps, ...)"))
    names = {p.name.name for p in gen.outputs}
    for atom in gen.certifies:
        decl = check_atom(atom, env, base)
        if decl is not None and decl.derived is not None:
            diags.append(effect_on_derived(decl, atom, "generator certifies"))
        names -= {a.name for a in atom.args}
    for missing in names:
        out = next(p for p in gen.outputs if p.name.name == missing)
        diags.append(diag("E105", f"output `{missing}` of generator `{gen.name.name}` is not certified by any "
                                  "atom", out.name.span, "list a fact about it after `certifies`"))
    check_binding(gen.binding, gen.name, "generator", diags)
    _check_options(gen.options, diags)


def _check_action(action: ast.ActionDecl, base: Ctx, unknowable: frozenset[str]) -> Production:
    info, diags = base.info, base.diags
    bound = quantified_params(action.pre) + quantified_params(action.eff)
    ctx = Ctx(info, diags, base.symbols, "E105", binder_hints(action, bound))
    env = check_params(action.params, ctx)
    if action.pre is not None:
        check_formula(action.pre, env, ctx)
    if action.eff is not None:
        check_effect(action.eff, env, ctx)
    if action.cost is not None:
        check_numexpr(action.cost, env, ctx)
    if action.executes is not None:
        check_binding(action.executes, action.name, "action", diags)
    for s in action.samples:
        _check_sample(s, env, ctx)
    production = infer(action, info, unknowable)
    for p in production.unproduced:
        diags.append(diag(
            "E305", f"continuous parameter `{p.name.name}: {p.type.name}` of `{action.name.name}` is "
                    "neither generated nor selected", p.name.span,
            "add a precondition certified by a generator whose inputs are other parameters, "
            "or a precondition atom that selects it (e.g. `at(o, " + p.name.name + ")`)"))
    return production


def _check_sample(s: ast.Sample, env: dict[str, str], ctx: Ctx) -> None:
    gen = ctx.info.generators.get(s.generator.name)
    if gen is None:
        ctx.diags.append(diag("E104", f"undefined generator `{s.generator.name}`", s.generator.span,
                              suggest(s.generator.name, ctx.info.generators)))
        return
    check_args("generator", s.generator, s.inputs, gen.inputs, gen.name.span, env, ctx)
    if len(s.outputs) != len(gen.outputs):
        ctx.diags.append(diag("E201", f"generator `{gen.name.name}` produces {len(gen.outputs)} values, "
                                      f"{len(s.outputs)} named", s.generator.span,
                              labels=(Label(gen.name.span, "declared here"),)))
        return
    for out, p in zip(s.outputs, gen.outputs):
        t = env.get(out.name)
        if t is None:
            ctx.diags.append(diag("E105", f"`{out.name}` is not a parameter of this action", out.span,
                                  "sampled values must be action parameters"))
        elif t in ctx.info.types and p.type.name in ctx.info.types and not ctx.info.is_subtype(p.type.name, t):
            ctx.diags.append(diag("E202", f"`{out.name}` has type `{t}` but `{gen.name.name}` produces "
                                          f"`{p.type.name}`", out.span))


def check_effect(e: ast.Effect, env: dict[str, str], ctx: Ctx) -> None:
    if isinstance(e, ast.Lit):
        decl = check_atom(e.atom, env, ctx)
        if decl is not None and decl.derived is not None:
            ctx.diags.append(effect_on_derived(decl, e.atom, "effect on"))
        elif decl is not None and decl.static:
            ctx.diags.append(diag("E304", f"effect on static predicate `{decl.name.name}`", e.atom.predicate.span,
                                  "static facts never change; drop `static` from its declaration if actions "
                                  "change it", (Label(decl.name.span, "declared static here"),)))
    elif isinstance(e, ast.Unknown):
        decl = check_atom(e.atom, env, ctx)
        if decl is not None and decl.derived is not None:
            ctx.diags.append(effect_on_derived(decl, e.atom, "`?` on"))
        elif decl is not None and decl.static:
            ctx.diags.append(diag("E303", f"`?` on static predicate `{decl.name.name}`", e.atom.predicate.span,
                                  "a static fact cannot become unknown; drop `static` or the `?`",
                                  (Label(decl.name.span, "declared static here"),)))
    elif isinstance(e, ast.EffAnd):
        for i, x in enumerate(e.effects):
            check_effect(x, env, ctx)
            if type(x) is ast.EffForall and i + 1 < len(e.effects):  # `forall (..) a, b`: b is outside
                ctx = replace(ctx, quantified=effect_hints(x, e.effects[i + 1:], ctx.quantified))
    elif isinstance(e, ast.When):
        check_formula(e.condition, env, ctx)
        check_effect(e.effect, env, ctx)
    elif isinstance(e, ast.EffForall):
        check_effect(e.effect, check_params(e.params, ctx, env, "quantified variable"), ctx)
    elif isinstance(e, ast.Probabilistic):
        _check_probabilities(e, ctx.diags)
        for o in e.outcomes:
            check_effect(o.effect, env, ctx)
    elif isinstance(e, ast.CostEffect):
        check_numexpr(e.amount, env, ctx)


def _check_probabilities(e: ast.Probabilistic, diags: list[Diagnostic]) -> None:
    total = Fraction(0)
    for o in e.outcomes:
        p = o.probability.value
        if p < 0 or p > 1:
            diags.append(diag("E301", f"probability {o.probability.text or p} is outside [0, 1]",
                              o.probability.span))
        total += p
    if total > 1 and all(0 <= o.probability.value <= 1 for o in e.outcomes):
        shown = " + ".join(o.probability.text or str(o.probability.value) for o in e.outcomes)
        diags.append(diag("E302", f"outcome probabilities sum to {_show(total)} ({shown}), above 1",
                          e.outcomes[0].probability.span,
                          "probabilities of one block must sum to at most 1; the rest means nothing happens",
                          tuple(Label(o.probability.span, "outcome") for o in e.outcomes[1:])))


def _show(x: Fraction) -> str:
    if x.denominator == 1:
        return str(x.numerator)
    as_float = float(x)
    return f"{as_float:g}" if Fraction(str(as_float)) == x else f"{x.numerator}/{x.denominator}"
