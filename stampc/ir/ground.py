"""Lifted IR -> grounded IR: ``ground(model) -> GroundModel``.

Pipeline (one module per responsibility):

1. :mod:`stampc.ir.validate` - well-formedness (G101-G112 diagnostics);
2. :mod:`stampc.ir.reachability` - relaxed reachability fixpoint (rules from
   :mod:`stampc.ir.relax`, evaluated by :mod:`stampc.ir.datalog`): reachable action
   bindings, fluent atoms, static facts, Skolem symbols for generated parameters;
3. :mod:`stampc.ir.simplify` / :mod:`stampc.ir.instantiate` - exact simplification of
   preconditions, effects and the goal against static facts and reachable fluents.

Output is deterministic: facts and actions are sorted, objects keep declaration order
with Skolem symbols appended in name order. Semantics are documented in docs/ir.md.
"""

from __future__ import annotations

from stampc.ir import lifted as L
from stampc.gcpause import no_gc_pauses
from stampc.ir.axioms import ground_axioms
from stampc.ir.derived import compile_derived
from stampc.ir.ground_checks import ADD_WINS, DELETE_WINS, check_rule, effect_conflicts, \
    grounding_warnings
from stampc.ir.ground_context import AtomKey, GroundingContext
from stampc.ir.grounded import AxiomProgram, GroundAction, GroundAtom, GroundModel
from stampc.ir.instantiate import ActionInstance, EffectGrounder, instantiate
from stampc.ir.masks import FactSet
from stampc.ir.reachability import (DEFAULT_MAX_ACTIONS, DEFAULT_MAX_SYMBOL_DEPTH, Reachable,
                                    explore)
from stampc.ir.scope import ScopeAnalysis
from stampc.ir.simplify import FactTable, Simplifier
from stampc.ir.validate import validate_model

__all__ = ["ground", "DEFAULT_MAX_ACTIONS", "DEFAULT_MAX_SYMBOL_DEPTH"]


def ground(model: L.Model, *, max_symbol_depth: int = DEFAULT_MAX_SYMBOL_DEPTH,
           max_actions: int = DEFAULT_MAX_ACTIONS,
           conflicting_effects: str = ADD_WINS) -> GroundModel:
    """Ground ``model``; raises :class:`stampc.diagnostics.StampcError` (G1xx) on bad input.

    ``max_symbol_depth`` bounds how deeply Skolem symbols may be generated from other
    symbols; more than ``max_actions`` reachable action bindings is an error (G114)
    rather than an out-of-memory crash (see :mod:`stampc.ir.reachability`).
    ``conflicting_effects`` (``add-wins`` or ``delete-wins``) decides a fact one outcome
    both adds and deletes. Warnings (G201-G203) land in ``GroundModel.diagnostics``.
    """
    check_rule(conflicting_effects)
    with no_gc_pauses():  # acyclic trees only; the collector's rescans grew with the model
        return _ground(model, max_symbol_depth, max_actions, conflicting_effects)


def _ground(model: L.Model, max_symbol_depth: int, max_actions: int,
            conflicting_effects: str) -> GroundModel:
    model = compile_derived(model)  # derived and symmetric predicates: docs/ir.md
    validate_model(model)
    ctx = GroundingContext(model)
    reach = explore(ctx, max_symbol_depth, max_actions)
    ctx.add_symbols(sorted((s.name, s.type) for s in reach.symbols.values()))
    scopes = ScopeAnalysis()
    fluents: set[AtomKey] = set(reach.fluents)
    while True:
        # Facts of optimistic unknowable predicates are only discovered while
        # simplifying; when some turn up, index them too and simplify again.
        table = FactTable(sorted(fluents), ctx)
        simp = Simplifier(ctx, reach.static, table, scopes)
        instances = _instantiate_all(ctx, reach, simp)
        axioms = ground_axioms(model, simp, table)
        simp.span = model.problem.span or simp.span
        goal = simp.condition(model.problem.goal, {})
        if not table.missing:
            break
        fluents |= table.missing
    return _assemble(model, ctx, reach, table, instances, goal, conflicting_effects, axioms)


def _instantiate_all(ctx: GroundingContext, reach: Reachable,
                     simp: Simplifier) -> list[ActionInstance]:
    effects = EffectGrounder(simp)
    out: list[ActionInstance] = []
    for schema in range(len(ctx.actions)):
        for binding in sorted(reach.bindings.get(schema, ())):
            inst = instantiate(ctx, simp, effects, schema, binding)
            if inst is not None:
                out.append(inst)
        simp.forget_nodes()
        effects.memo.clear()
    out.sort(key=lambda a: (a.name, a.args, a.schema))
    return out


def _assemble(model: L.Model, ctx: GroundingContext, reach: Reachable, table: FactTable,
              instances: list[ActionInstance], goal, rule: str,
              axioms: AxiomProgram) -> GroundModel:
    init = 0
    for atom in model.problem.init:
        i = table.index.get((atom.predicate, tuple(t.name for t in atom.args)))
        if i is not None:
            init |= 1 << i
    for i, (pred, _) in enumerate(table.facts):
        if pred in ctx.optimistic_true:
            init |= 1 << i  # unknowable facts start at their optimistic value
    init = axioms.close(init)
    conflicts: dict[int, tuple[GroundAction, FactSet]] = {}
    actions = []
    for k, a in enumerate(instances):
        mask = effect_conflicts(a.effect, len(table.facts))
        action = GroundAction(index=k, name=a.name, args=a.args, precondition=a.precondition,
                              effect=a.effect, base_cost=a.base_cost, schema=a.schema,
                              generated=a.generated,
                              delete_wins=bool(mask) and rule == DELETE_WINS)
        if mask and a.schema not in conflicts:
            conflicts[a.schema] = (action, mask)
        actions.append(action)
    facts = tuple(GroundAtom(p, args) for p, args in table.facts)
    return GroundModel(
        facts=facts,
        actions=tuple(actions),
        init=init,
        goal=goal,
        objects=ctx.all_objects,
        static_facts=tuple(GroundAtom(p, args) for p, args in sorted(reach.static)),
        horizon=model.problem.horizon,
        has_costs=ctx.costs.has_costs,
        lifted=model,
        diagnostics=tuple(grounding_warnings(model, tuple(actions), conflicts, facts, rule)),
        axioms=axioms,
    )
