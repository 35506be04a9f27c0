"""Concretization of one abstract action: backtracking search over generator samples,
checking the concrete preconditions (the ``?`` literals) with the world's evaluators, and
applying the action's concrete effect per outcome.

Only preconditions on *unknowable* (``?``) predicates need a concrete check: certified
facts hold by construction of the generators, and the other fluents are tracked exactly
by the abstract state.
"""

from __future__ import annotations

import random
import time
from dataclasses import dataclass, replace
from typing import Any, Iterator, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.ir.grounded import GroundAction, GroundModel, Successor, bits
from stampc.ir.masks import indices
from stampc.refine.outcomes import outcome_labels
from stampc.worlds.base import ConcreteAction, Context, Outcome, call_executor
from stampc.worlds.bindings import ResolvedBindings

DEFAULT_BUDGET = 4


@dataclass(frozen=True)
class Success:
    sigma: Mapping[str, Any]


@dataclass(frozen=True)
class Failure:
    """No sample satisfied the action's concrete preconditions.

    ``violated`` holds the true values of the violated ``?`` literals for the best
    sample (fewest violations): what UpdateAbstraction writes back unless the engine
    prefers another of ``alternatives``. It is empty when the generators themselves
    produced nothing usable.
    """

    violated: tuple[tuple[int, bool], ...]
    sigma: Mapping[str, Any]
    samples: int
    #: the search stopped at its first complete sample (UpdateAbstraction's quick mode)
    #: instead of trying every one: ``violated`` speaks for that sample only
    quick: bool = False
    #: the distinct ``violated`` sets of every complete sample tried, fewest first
    #: (``violated`` among them): which one is written back is the engine's choice,
    #: since only the abstract model knows which facts leave it the cheaper way
    alternatives: tuple[tuple[tuple[int, bool], ...], ...] = ()


class Concretizer:
    """Runs generators, evaluators and executors for ground actions of one model."""

    def __init__(self, model: GroundModel, bindings: ResolvedBindings, world: Any, seed: int):
        self.model = model
        self.bindings = bindings
        self.world = world
        self.seed = seed
        self._generators = {g.name: g for g in model.lifted.domain.generators}
        self._checks: dict[int, tuple[tuple[int, bool], ...]] = {}
        self._unknowable = unknowable_predicates(model)
        self._symbols = continuous_objects(model)
        self.samples_drawn = 0
        self.evaluations = 0
        #: the run's absolute deadline: no new sample is drawn past it, and bound
        #: functions see it as ``ctx.deadline``
        self.deadline: float | None = None

    @property
    def work(self) -> int:
        """Samples drawn plus evaluations so far: the search's work, counted the same on
        any machine (the engine weighs backtracking by it, ``Backtracking._affordable``)."""
        return self.samples_drawn + self.evaluations

    def past_deadline(self) -> bool:
        return self.deadline is not None and time.perf_counter() >= self.deadline

    # ----------------------------------------------------------- precondition
    def checks(self, action: GroundAction) -> tuple[tuple[int, bool], ...]:
        """(fact, required value) for the ``?`` literals of the action's precondition."""
        if action.index not in self._checks:
            pre = action.precondition
            out = [(bit, value) for value, facts in ((True, pre.pos_facts), (False, pre.neg_facts))
                   for bit in indices(facts) if self.model.facts[bit].predicate in self._unknowable]
            self._checks[action.index] = tuple(sorted(out))
        return self._checks[action.index]

    def _evaluate(self, ctx: Context, fact: int, values: Mapping[str, Any]) -> bool | None:
        atom = self.model.facts[fact]
        fn = self.bindings.evaluators.get(atom.predicate)
        if fn is None or any(a not in values and a in self._symbols for a in atom.args):
            return None  # cannot be decided here: keep the abstraction's assumption
        args = tuple(values.get(a, a) for a in atom.args)
        try:
            result = fn(ctx, *args)
        except Exception as exc:  # user code: report where it is bound
            raise self._user_error("R202", f"evaluator of {atom.predicate!r} raised "
                                   f"{type(exc).__name__}: {exc} (on {atom})",
                                   atom.predicate) from None
        if not isinstance(result, bool):
            raise self._user_error("R203", f"evaluator of {atom.predicate!r} returned "
                                   f"{type(result).__name__}, expected bool", atom.predicate)
        self.evaluations += 1
        return result

    def sampled_checks(self) -> frozenset[int]:
        """Facts checked by some action about a symbol that action samples itself (a
        ``collision`` with the trajectory it plans): a value bound earlier on the path
        says nothing about the action's own fresh sample."""
        out = set()
        for action in self.model.actions:
            outputs = {name for use in action.generated for name in use.outputs}
            out.update(fact for fact, _ in self.checks(action)
                       if outputs.intersection(self.model.facts[fact].args))
        return frozenset(out)

    def symbol_args(self, fact: int) -> tuple[str, ...]:
        """The fact's arguments that are continuous symbols (bound to concrete values)."""
        return tuple(a for a in self.model.facts[fact].args if a in self._symbols)

    def evaluate_at(self, concrete: Any, fact: int, values: Mapping[str, Any], *,
                    node_uid: int, attempt: int) -> bool | None:
        """The fact's evaluator in the concrete state ``concrete`` (a node's
        ``Concrete``); None when it cannot be decided there."""
        self.world.restore(concrete.snapshot)
        ctx = self._context(concrete.cache, values, node_uid, attempt, -1)
        return self._evaluate(ctx, fact, values)

    def violations(self, ctx: Context, action: GroundAction,
                   values: Mapping[str, Any]) -> list[tuple[int, bool]]:
        out = []
        for fact, required in self.checks(action):
            actual = self._evaluate(ctx, fact, values)
            if actual is not None and actual != required:
                out.append((fact, actual))
        return out

    # ------------------------------------------------------------- search
    def concretize(self, action: GroundAction, concrete_snapshot: Any, cache: dict,
                   values: Mapping[str, Any], *, node_uid: int, attempt: int,
                   quick: bool) -> Success | Failure:
        """Search generator samples for a concretization satisfying the ``?`` checks.

        ``quick`` takes the first complete sample (UpdateAbstraction mode); otherwise the
        search backtracks through every generator's budget (Concretization mode).
        """
        best: Failure | None = None
        seen: dict[tuple[tuple[int, bool], ...], None] = {}  # ordered: first met first
        samples = 0
        for sigma in self._assignments(action, concrete_snapshot, cache, values,
                                       node_uid, attempt, 0, {}):
            samples += 1
            self.world.restore(concrete_snapshot)
            ctx = self._context(cache, {**values, **sigma}, node_uid, attempt, -1)
            violated = self.violations(ctx, action, {**values, **sigma})
            if not violated:
                return Success(dict(sigma))
            seen.setdefault(tuple(violated))
            if best is None or len(violated) < len(best.violated):
                best = Failure(tuple(violated), dict(sigma), samples)
            if quick:
                break
        if best is None:
            # no sample at all: the ``?`` checks decidable without one (e.g. whether the
            # robot reaches the object from where it stands) may say why; learn them
            self.world.restore(concrete_snapshot)
            ctx = self._context(cache, values, node_uid, attempt, -1)
            return Failure(tuple(self.violations(ctx, action, values)), {}, samples)
        return Failure(best.violated, best.sigma, samples, quick,
                       tuple(sorted(seen, key=len)))

    def _assignments(self, action: GroundAction, snapshot: Any, cache: dict,
                     values: Mapping[str, Any], uid: int, attempt: int, i: int,
                     sigma: dict[str, Any]) -> Iterator[dict[str, Any]]:
        """Depth-first enumeration of generator outputs for ``action.generated[i:]``."""
        if i == len(action.generated):
            yield dict(sigma)
            return
        use = action.generated[i]
        gen = self._generators[use.generator]
        options = dict(gen.options)
        budget = int(options.get("budget", DEFAULT_BUDGET))
        env = {**values, **sigma}
        inputs = tuple(env.get(name, name) for name in use.inputs)
        ctx = self._context(cache, env, uid, attempt, i, options)
        self.world.restore(snapshot)
        try:
            stream = iter(self.bindings.generators[use.generator](ctx, *inputs))
        except Exception as exc:
            raise self._gen_error(gen, exc) from None
        for _ in range(budget):
            if self.past_deadline():
                return
            self.world.restore(snapshot)  # earlier branches may have moved the world
            try:
                sample = next(stream, None)
            except Exception as exc:
                raise self._gen_error(gen, exc) from None
            if sample is None:
                return
            self.samples_drawn += 1
            sample = tuple(sample) if isinstance(sample, (tuple, list)) else (sample,)
            if len(sample) != len(use.outputs):
                raise self._user_error("R204", f"generator {gen.name!r} yielded {len(sample)} "
                                       f"values, expected {len(use.outputs)}", gen_name=gen.name)
            sigma.update(zip(use.outputs, sample))
            yield from self._assignments(action, snapshot, cache, values, uid, attempt,
                                         i + 1, sigma)
            for name in use.outputs:
                sigma.pop(name, None)

    def _context(self, cache: dict, values: Mapping[str, Any], uid: int, attempt: int,
                 index: int, options: Mapping[str, Any] | None = None) -> Context:
        rng = random.Random(f"{self.seed}:{uid}:{attempt}:{index}")
        return Context(world=self.world, rng=rng, options=dict(options or {}),
                       cache=cache, values=values, deadline=self.deadline)

    # ------------------------------------------------------------ execution
    def execute(self, action: GroundAction, successor: Successor, outcome: int,
                snapshot: Any, cache: dict, values: Mapping[str, Any], uid: int,
                state: int) -> Any:
        """Apply the concrete effect of ``action``'s ``outcome`` (in abstract ``state``);
        return the new snapshot. An outcome without any literal effect (a slip that
        leaves everything as it was) leaves the concrete state as it was: the executor
        is not called, so the child can merge with its parent's concrete state."""
        self.world.restore(snapshot)
        fn = self.bindings.executors.get(action.name)
        if fn is None or not (successor.add or successor.delete):
            return snapshot  # a purely abstract action (e.g. notify), or a no-op outcome
        concrete = self.concrete_action(action, successor, outcome, values, state)
        ctx = self._context(cache, values, uid, 0, 1000 + outcome)
        try:
            call_executor(fn, ctx, concrete, outcome_of(concrete, float(successor.probability)))
        except StampcError as exc:  # the world's own diagnostic (e.g. S274): code and hint kept
            raise self._world_error(exc, action_name=action.name) from None
        except Exception as exc:
            raise self._user_error("R205", f"executor of {action.name!r} raised "
                                   f"{type(exc).__name__}: {exc}", action_name=action.name) from None
        return self.world.snapshot()

    def concrete_action(self, action: GroundAction, successor: Successor, outcome: int,
                        values: Mapping[str, Any], state: int | None = None) -> ConcreteAction:
        schema = self.model.lifted.domain.actions[action.schema]
        args = {p.name: values.get(a, a) for p, a in zip(schema.params, action.args)}
        labels = outcome_labels(action, state)[outcome] if state is not None else ()
        return ConcreteAction(
            name=action.name, args=args,
            adds=self._literals(successor.add, values),
            deletes=self._literals(successor.delete & ~successor.add, values),
            outcome=outcome, labels=labels)

    def _literals(self, mask: int, values: Mapping[str, Any]):
        facts = self.model.facts
        return tuple((facts[b].predicate, tuple(values.get(a, a) for a in facts[b].args))
                     for b in bits(mask))

    # --------------------------------------------------------------- errors
    def _gen_error(self, gen, exc: Exception) -> StampcError:
        return self._user_error("R201", f"generator {gen.name!r} raised "
                                f"{type(exc).__name__}: {exc}", gen_name=gen.name)

    def _user_error(self, code: str, message: str, predicate: str | None = None, *,
                    gen_name: str | None = None, action_name: str | None = None) -> StampcError:
        span = self._binding_span(predicate, gen_name, action_name)
        return StampcError([error(code, message, span or Span.point("<model>"),
                                  hint="this is raised by bound Python code; fix the function")])

    def _world_error(self, exc: StampcError, *, action_name: str) -> StampcError:
        """A world function's diagnostics, moved from its ``<...>`` placeholder location to
        the binding that called it (their own codes and hints say what to change)."""
        span = self._binding_span(None, None, action_name)
        if span is None:
            return exc
        return StampcError([replace(d, span=span) if d.span.file.startswith("<") else d
                            for d in exc.diagnostics])

    def _binding_span(self, predicate: str | None, gen_name: str | None,
                      action_name: str | None) -> Span | None:
        domain = self.model.lifted.domain
        if gen_name:
            return next((g.binding.span or g.span for g in domain.generators if g.name == gen_name), None)
        if predicate:
            return next((e.binding.span or e.span for e in domain.evaluators if e.predicate == predicate), None)
        if action_name:
            return next((a.executes.span if a.executes else a.span
                         for a in domain.actions if a.name == action_name), None)
        return None


def unknowable_predicates(model: GroundModel) -> frozenset[str]:
    """Names of the ``?`` predicates: their facts are decided by refinement."""
    return frozenset(p.name for p in model.lifted.domain.predicates if p.unknowable)


def continuous_objects(model: GroundModel) -> frozenset[str]:
    """The model's objects of continuous types: the symbols generators bind."""
    continuous = {t.name for t in model.lifted.domain.types if t.continuous}
    return frozenset(n for n, t in model.objects if t in continuous)


def outcome_of(action: ConcreteAction, probability: float) -> Outcome:
    """The outcome an outcome-aware executor receives for ``action``'s chosen outcome."""
    return Outcome("+".join(action.labels) or None, action.outcome, probability,
                   action.adds, action.deletes)
