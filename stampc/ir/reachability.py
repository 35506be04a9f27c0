"""Relaxed reachability: which ground actions, fluent atoms and Skolem symbols matter.

Runs the relaxed rules of :mod:`stampc.ir.relax` to a fixpoint. Whenever the
non-generated parameters of a schema with generator uses become reachable, one Skolem
symbol per generated parameter is minted (``<param>_<action>_<non-generated args>``),
typed with the parameter's type, and the generators' certified atoms for it are added as
static facts; the symbols then feed other actions' selected parameters (fixpoint).

Symbol nesting is bounded: a symbol's depth is one more than the deepest symbol among
the arguments it was generated from (problem objects have depth 0); bindings that would
mint a symbol deeper than ``max_symbol_depth`` are not instantiated, which keeps the
fixpoint finite when generators feed each other (place -> pick -> place ...).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from stampc.diagnostics import StampcError, error
from stampc.ir import lifted as L
from stampc.ir.datalog import FactBase, fixpoint
from stampc.ir.ground_context import AtomKey, GroundingContext, located
from stampc.ir.relax import Rule, act_rel, action_rules, axiom_rules, effect_rules, type_rel

DEFAULT_MAX_SYMBOL_DEPTH = 3
#: Reachable action bindings allowed before grounding gives up (G114) instead of
#: exhausting memory (rectangle-tireworld p15 would have about 13 million).
DEFAULT_MAX_ACTIONS = 1_000_000


@dataclass(frozen=True)
class Symbol:
    name: str
    type: str
    depth: int
    #: (schema index, non-generated argument names) of the ground action minting it
    origin: tuple[int, tuple[str, ...]]


@dataclass
class Reachable:
    """Result of the relaxed exploration."""

    fluents: set[AtomKey] = field(default_factory=set)
    static: set[AtomKey] = field(default_factory=set)
    #: schema index -> reachable bindings of all its parameters (parameter order)
    bindings: dict[int, set[tuple[str, ...]]] = field(default_factory=dict)
    symbols: dict[str, Symbol] = field(default_factory=dict)


def skolem_name(param: str, action: str, args: tuple[str, ...]) -> str:
    return "_".join((param, action, *args))


class _Explorer:
    def __init__(self, ctx: GroundingContext, max_symbol_depth: int, max_actions: int):
        self.ctx = ctx
        self.max_depth = max_symbol_depth
        self.max_actions = max_actions
        self.n_actions = 0
        self.counted: set[tuple[str, tuple[str, ...]]] = set()
        self.kb = FactBase()
        self.symbols: dict[str, Symbol] = {}

    def seed(self) -> None:
        problem = self.ctx.model.problem
        for atom in problem.init:
            self.kb.add(atom.predicate, tuple(t.name for t in atom.args))
        for name, type_name in self.ctx.base_objects:
            for t in self.ctx.ancestors(type_name):
                self.kb.add(type_rel(t), (name,))

    def static_holds(self, rel: str, tup: tuple[str, ...]) -> bool:
        return tup in self.kb.relation(rel)

    def on_head(self, rule: Rule, head: tuple[str, ...], pending: list) -> None:
        pending.append((rule.head_rel, head))
        if rule.head_rel.startswith("@"):
            # the fixpoint may derive one binding several times before it is stored (one
            # rule per disjunct, one run per new body fact in the same round): count and
            # instantiate it once (rectangle-tireworld p13 counted 816,844 bindings twice)
            key = (rule.head_rel, head)
            if key in self.counted:
                return
            self.counted.add(key)
            if rule.head_rel.startswith("@pre:"):
                self._instantiate_generated(int(rule.head_rel[5:]), head, pending)
            self.n_actions += 1
            if self.n_actions > self.max_actions:
                self._too_many(int(rule.head_rel[5:]))

    def _too_many(self, schema: int) -> None:
        action = self.ctx.actions[schema]
        raise StampcError([error(
            "G114", f"grounding exceeds {self.max_actions} reachable actions "
            f"(last found: '{action.name}')", located(action.span, self.ctx.model),
            "add static preconditions that restrict the parameters, or raise max_actions")])

    def _depth(self, name: str) -> int:
        sym = self.symbols.get(name)
        return sym.depth if sym is not None else 0

    def _instantiate_generated(self, schema: int, selected: tuple[str, ...],
                               pending: list) -> None:
        action = self.ctx.actions[schema]
        generated = [o for use in action.generated for o in use.outputs]
        depth = 1 + max((self._depth(a) for a in selected), default=0)
        if depth > self.max_depth:
            return
        values = dict(zip((p.name for p in action.params if p.name not in generated), selected))
        types = {p.name: p.type for p in action.params}
        for out in generated:
            name = skolem_name(out, action.name, selected)
            self._mint(Symbol(name, types[out], depth, (schema, selected)), action, pending)
            values[out] = name
        for use in action.generated:
            gen = self.ctx.generators[use.generator]
            bind = {p.name: values[a] for p, a in zip(gen.inputs, use.inputs)}
            bind.update({p.name: values[a] for p, a in zip(gen.outputs, use.outputs)})
            for atom in gen.certifies:
                args = tuple(bind[t.name] if isinstance(t, L.Var) else t.name for t in atom.args)
                pending.append((atom.predicate, args))
        pending.append((act_rel(schema), tuple(values[p.name] for p in action.params)))

    def _mint(self, sym: Symbol, action: L.Action, pending: list) -> None:
        existing = self.symbols.get(sym.name)
        if existing is None and sym.name in self.ctx.object_type:
            self._collision(sym, action, "a problem object")
        if existing is not None:
            if existing.origin != sym.origin or existing.type != sym.type:
                self._collision(sym, action, "another generated symbol")
            return
        self.symbols[sym.name] = sym
        for t in self.ctx.ancestors(sym.type):
            pending.append((type_rel(t), (sym.name,)))

    def _collision(self, sym: Symbol, action: L.Action, other: str) -> None:
        raise StampcError([error(
            "G113", f"Skolem symbol '{sym.name}' generated by action '{action.name}' "
            f"clashes with {other} of the same name", located(action.span, self.ctx.model),
            "rename the object or the action parameter")])


def explore(ctx: GroundingContext, max_symbol_depth: int = DEFAULT_MAX_SYMBOL_DEPTH,
            max_actions: int = DEFAULT_MAX_ACTIONS) -> Reachable:
    """Relaxed reachability fixpoint over the lifted model in ``ctx``."""
    explorer = _Explorer(ctx, max_symbol_depth, max_actions)
    explorer.seed()
    rules: list[Rule] = []
    shared: dict = {}
    for schema in range(len(ctx.actions)):
        rules.extend(action_rules(ctx, schema, shared))
        rules.extend(effect_rules(ctx, schema, shared))
    for axiom in ctx.model.domain.axioms:
        rules.extend(axiom_rules(ctx, axiom, shared))
    fixpoint(explorer.kb, rules, explorer.static_holds, explorer.on_head)
    result = Reachable(symbols=explorer.symbols)
    for rel, tuples in explorer.kb.rels.items():
        if rel.startswith("@act:"):
            result.bindings[int(rel[5:])] = tuples
        elif rel.startswith("@"):
            continue
        elif ctx.is_static(rel):
            result.static.update((rel, t) for t in tuples)
        else:
            result.fluents.update((rel, t) for t in tuples)
    return result
