"""Lifted IR → PPDDL text (IPPC 2006/2008 dialect), through jinja2 templates.

Conventions (see docs/ppddl.md):
- names are mangled to legal PDDL (:mod:`stampc.backends.ppddl.mangle`);
- costs become rewards: a cost k is ``(decrease (reward) k)``, a negative cost
  ``(increase (reward) k)``; ``Action.cost`` (the base cost) is prepended to the effect as
  such a conjunct. A model whose ``Domain.requirements`` is empty did not come from
  PPDDL (stamp models), so its default base cost 1 is made explicit;
- ``?`` effects are emitted as their optimistic literal under a ``; ?`` comment;
- generators, evaluators, bindings, horizon and scene are dropped with a comment;
- requirements are computed from the constructs used.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction
from functools import lru_cache
from itertools import groupby
from pathlib import Path
from typing import Iterable

import jinja2

from stampc.backends.ppddl import render
from stampc.backends.ppddl.mangle import mangle_model
from stampc.backends.ppddl.requirements import required_flags
from stampc.ir.derived import compile_derived
from stampc.ir.grounded import GroundAtom
from stampc.ir.lifted import (
    TRUE, Action, Atom, Const, CostEffect, EffAnd, Effect, Model, Num, NumExpr, Object,
)

TEMPLATES = Path(__file__).resolve().parent / "templates"
REWARD_METRIC = "maximize (reward)"
_OBJECTS_PER_LINE = 10


@lru_cache(maxsize=1)
def _environment() -> jinja2.Environment:
    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(TEMPLATES)),
                              autoescape=False, trim_blocks=True, lstrip_blocks=True,
                              keep_trailing_newline=True, undefined=jinja2.StrictUndefined)


def emit_ppddl(model: Model, *, extra_objects: Iterable[Object | tuple[str, str]] = (),
               extra_init: Iterable[Atom | GroundAtom] = (),
               keep_derived: bool = False) -> tuple[str, str]:
    """Emit ``model`` as PPDDL ``(domain text, problem text)``.

    ``extra_objects``/``extra_init`` add objects (e.g. Skolem symbols) and true facts
    (e.g. certified atoms) produced by grounding to the problem. Derived predicates are
    compiled away (IPPC PPDDL has none; docs/ir.md) unless ``keep_derived``, which
    writes them as ``(:derived ...)`` with ``:derived-predicates``.
    """
    model = compile_derived(model, keep_axioms=keep_derived)
    stamp_origin = not model.domain.requirements
    costed, explicit_costs = _fold_base_costs(model, stamp_origin)
    mangled = mangle_model(costed, tuple(_as_object(o) for o in extra_objects),
                           tuple(_as_atom(a) for a in extra_init))
    m = mangled.model
    typed = bool(m.domain.types)
    requirements = required_flags(m, explicit_costs=explicit_costs)
    metric = None
    if m.problem.metric is not None or (stamp_origin and ":rewards" in requirements):
        metric = REWARD_METRIC  # costs are emitted as rewards, whatever the source metric
    env = _environment()
    domain_text = env.get_template("domain.pddl.j2").render(
        comments=_domain_comments(model, mangled.renames),
        name=m.domain.name, requirements=requirements,
        # stamp root types have no parent; PPDDL needs every type declared (under object)
        types=[f"{t.name} - {t.parent or 'object'}" for t in m.domain.types
               if t.name != "object"],
        constants=_object_lines(m.domain.constants, typed),
        predicates=[render.flat(_declaration(p.name, p.params, typed))
                    for p in m.domain.predicates],
        functions=[render.flat(_declaration(f.name, f.params, typed))
                   for f in m.domain.functions],
        derived=[(render.flat(_declaration(ax.predicate, ax.params, typed)),
                  render.text(render.formula(ax.body, typed), indent=4))
                 for ax in m.domain.axioms],
        actions=[_action_context(a, orig, m, typed)
                 for a, orig in zip(m.domain.actions, model.domain.actions)],
    )
    problem_text = env.get_template("problem.pddl.j2").render(
        comments=_problem_comments(m),
        name=m.problem.name, domain=m.domain.name,
        objects=_object_lines(m.problem.objects, typed),
        init=[render.flat(render.atom(a)) for a in m.problem.init]
        + [f"(= {render.flat(render.atom(a))} {render.number(v)})"
           for a, v in m.problem.init_values],
        goal=render.text(render.formula(m.problem.goal, typed), indent=9),
        goal_reward=None if m.problem.goal_reward is None else render.number(m.problem.goal_reward),
        metric=metric,
    )
    return domain_text, problem_text


# ------------------------------------------------------------------ costs
def _fold_base_costs(model: Model, stamp_origin: bool) -> tuple[Model, bool]:
    """Move every base cost into its action's effect (the IPPC way); the flag tells
    whether some action got a cost conjunct."""
    actions = tuple(_fold(a, stamp_origin) for a in model.domain.actions)
    if all(a is b for a, b in zip(actions, model.domain.actions)):
        return model, False
    added = any(a.effect is not b.effect for a, b in zip(actions, model.domain.actions))
    return replace(model, domain=replace(model.domain, actions=actions)), added


def _fold(action: Action, stamp_origin: bool) -> Action:
    base: NumExpr | None = action.cost
    if base is None and stamp_origin:
        base = Num(Fraction(1))  # the stamp default, made explicit for PPDDL solvers
    if base is None:
        return action
    if isinstance(base, Num) and base.value == 0:
        return replace(action, cost=None)
    cost = CostEffect(base)
    effects: tuple[Effect, ...] = (
        action.effect.effects if isinstance(action.effect, EffAnd) else (action.effect,))
    return replace(action, cost=None, effect=EffAnd((cost,) + effects))


# --------------------------------------------------------------- contexts
def _as_object(o: Object | tuple[str, str]) -> Object:
    return o if isinstance(o, Object) else Object(o[0], o[1], symbolic=True)


def _as_atom(a: Atom | GroundAtom) -> Atom:
    if isinstance(a, Atom):
        return a
    return Atom(a.predicate, tuple(Const(x) for x in a.args))


def _declaration(name: str, params, typed: bool) -> render.Doc:
    return f"({name} {render.params(params, typed)})" if params else f"({name})"


def _object_lines(objects: tuple[Object, ...], typed: bool) -> list[str]:
    lines = []
    for type_name, run in groupby(objects, key=lambda o: o.type):
        names = [o.name for o in run]
        for i in range(0, len(names), _OBJECTS_PER_LINE):
            chunk = " ".join(names[i:i + _OBJECTS_PER_LINE])
            lines.append(f"{chunk} - {type_name}" if typed else chunk)
    return lines


def _action_context(a: Action, original: Action, m: Model, typed: bool) -> dict:
    optimistic = {p.name: p.optimistic for p in m.domain.predicates}
    prefix = 4 + len(":precondition ")
    return {
        "name": a.name,
        "comments": _action_comments(original),
        "parameters": render.params(a.params, typed),
        "precondition": (None if a.precondition == TRUE else
                         render.text(render.formula(a.precondition, typed), indent=prefix)),
        "effect": render.text(render.effect(a.effect, optimistic, typed),
                              indent=4 + len(":effect ")),
    }


def _action_comments(a: Action) -> list[str]:
    lines = [f"generated: {', '.join('?' + o for o in g.outputs)} by {g.generator}"
             f"({', '.join('?' + i for i in g.inputs)}) [Skolem symbols come from grounding]"
             for g in a.generated]
    if a.executes is not None:
        lines.append(f"executes {a.executes.target} [binding dropped]")
    return lines


def _domain_comments(model: Model, renames) -> list[str]:
    d = model.domain
    lines = [f"renamed {kind} {old!r} -> {new}" for kind, old, new in renames]
    lines += [f"type {t.name} is continuous (entity-abstracted); emitted as an ordinary type"
              for t in d.types if t.continuous]
    lines += [f"predicate {p.name} is unknowable: '?' effects are emitted as its optimistic "
              f"value ({str(p.optimistic).lower()})" for p in d.predicates if p.unknowable]
    for g in d.generators:
        ins = " ".join(f"?{p.name} - {p.type}" for p in g.inputs)
        outs = " ".join(f"?{p.name} - {p.type}" for p in g.outputs)
        certs = " ".join(render.flat(render.atom(x)) for x in g.certifies)
        lines.append(f"generator {g.name} ({ins}) -> ({outs}) certifies {certs} "
                     f"[binding {g.binding.target} dropped]")
    lines += [f"evaluator for {e.predicate} [binding {e.binding.target} dropped]"
              for e in d.evaluators]
    return lines


def _problem_comments(model: Model) -> list[str]:
    p = model.problem
    lines = []
    symbolic = [o.name for o in p.objects if o.symbolic]
    if symbolic:
        lines.append("symbolic objects (continuous values): " + " ".join(symbolic))
    if p.horizon is not None:
        lines.append(f"horizon {p.horizon} [not expressible in IPPC PPDDL; dropped]")
    if p.scene is not None:
        lines.append(f"scene {p.scene.kind} {p.scene.target} [dropped]")
    return lines
