"""Successor generation over a :class:`GroundModel`, shared by solvers and the engine.

States are int bitsets. Fractions become floats once: state-independent actions get a
float outcome list on first use (from ``GroundAction.static_outcomes``); actions with
conditional effects are compiled once to a float effect tree (``float_effects``) and
enumerated per state. Transitions are cached per state.

Applicable actions are found through an index on one positive precondition fact per
action (the fact shared by the fewest actions), so a state only tests the actions
triggered by its true facts instead of scanning every action.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

from stampc.ir.grounded import bits as iter_bits  # noqa: F401  (re-exported)
from stampc.ir.grounded import GroundAction, GroundModel
from stampc.ir.masks import FactSet, indices
from stampc.solvers.float_effects import branches, compile_effect, condition_check, sample

#: the most memory the int precondition masks of ``SuccessorCache`` may take
DENSE_CHECK_BYTES = 64 << 20

if TYPE_CHECKING:
    from stampc.solvers.relevance import Relevance
    from stampc.solvers.symmetry import ObjectSymmetry

#: A solver transition: (action index, expected cost, probabilities, next states).
Transition = tuple[int, float, tuple[float, ...], tuple[int, ...]]
#: Raw outcome list of one action in one state, aligned with ``action.outcomes(state)``:
#: (probability, next state, cost) per outcome.
Outcome = tuple[float, int, float]

_UNSET = object()

#: Self-loop probabilities this close to 1 make an action a no-op in that state.
_NOOP_TOLERANCE = 1e-12


class SuccessorCache:
    """State -> applicable actions -> float outcome lists, cached per state.

    ``unit_cost=True`` makes every action cost 1 whatever the model declares (the
    convention of the C++ reference solver and of IPPC-2006 goal-probability domains).
    ``symmetry`` (``symmetry.ObjectSymmetry``) replaces every next state by the
    representative of its orbit under interchangeable objects (same optimal value);
    ``relevance`` (``relevance.Relevance``) first clears its irrelevant facts (same too).
    """

    def __init__(self, model: GroundModel, unit_cost: bool = False,
                 symmetry: ObjectSymmetry | None = None,
                 relevance: Relevance | None = None):
        self.model = model
        self.unit_cost = unit_cost
        self.symmetry = symmetry if symmetry else None
        self.relevance = relevance
        #: the orbit representative of a state, or None without symmetry
        self.canonical = self.symmetry.canonical if self.symmetry else None
        # Preconditions as int masks even when their fact sets are sparse, unless those
        # ints would be large in total: a cluttered-25 model (5,463 facts, 220 actions)
        # rebuilt 178 ints per applicability test (132 -> 68 us per test with the ints).
        dense = 2 * len(model.actions) * (len(model.facts) // 8 + 1) <= DENSE_CHECK_BYTES
        self._checks = [condition_check(a.precondition, dense) for a in model.actions]
        # Float outcome lists of state-independent actions, built on first use: models such
        # as rectangle-tireworld ground 10^5 actions of which a search touches few.
        self._static: list = [_UNSET] * len(model.actions)
        self._compiled: dict[int, tuple] = {}  # float effects of state-dependent actions
        self._by_fact, self._unindexed = self._build_index(model)
        self._applicable: dict[int, tuple[int, ...]] = {}
        self._trans: dict[int, tuple[Transition, ...]] = {}
        self._trans_raw: dict[int, tuple[Transition, ...]] = {}
        self._goal: dict[int, bool] = {}
        # Derived facts (docs/ir.md, "Derived and symmetric predicates"): every next
        # state is closed under the model's axioms before anyone sees it.
        self._close = model.axioms.close if model.axioms else None

    # ------------------------------------------------------------ building
    def _float_static(self, action: GroundAction):
        outs = action.static_outcomes()
        if outs is None:
            return None
        return tuple((float(o.probability), o.add, ~o.delete,
                      1.0 if self.unit_cost else float(o.cost)) for o in outs)

    def _static_of(self, action: int):
        static = self._static[action]
        if static is _UNSET:
            static = self._static[action] = self._float_static(self.model.actions[action])
        return static

    @staticmethod
    def _build_index(model: GroundModel) -> tuple[dict[int, list[int]], list[int]]:
        usage: dict[int, int] = {}
        facts_of: dict[FactSet, Sequence[int]] = {}  # many actions share a precondition mask
        for action in model.actions:
            pos = action.precondition.pos_facts
            facts = facts_of.get(pos)
            if facts is None:
                facts = facts_of[pos] = indices(pos)
            for f in facts:
                usage[f] = usage.get(f, 0) + 1
        by_fact: dict[int, list[int]] = {}
        unindexed: list[int] = []
        for index, action in enumerate(model.actions):
            pre = action.precondition
            if pre.never:
                continue  # never applicable: simply not indexed
            facts = facts_of[pre.pos_facts]
            if not facts:
                unindexed.append(index)
                continue
            trigger = min(facts, key=lambda f: (usage[f], f))
            by_fact.setdefault(trigger, []).append(index)
        return by_fact, unindexed

    # ------------------------------------------------------------- queries
    def is_goal(self, state: int) -> bool:
        g = self._goal.get(state)
        if g is None:
            g = self._goal[state] = self.model.goal.holds(state)
        return g

    def applicable(self, state: int) -> tuple[int, ...]:
        """Indices of the actions applicable in ``state``, ascending."""
        cached = self._applicable.get(state)
        if cached is not None:
            return cached
        checks = self._checks
        found = []
        candidates = list(self._unindexed)
        by_fact = self._by_fact
        mask = state
        while mask:
            low = mask & -mask
            bucket = by_fact.get(low.bit_length() - 1)
            if bucket:
                candidates.extend(bucket)
            mask ^= low
        for a in candidates:
            pos, neg, rest = checks[a]
            if (state & pos) == pos and not (state & neg) and (rest is None or rest.holds(state)):
                found.append(a)
        found.sort()
        result = self._applicable[state] = tuple(found)
        return result

    def outcomes(self, state: int, action: int) -> tuple[Outcome, ...]:
        """Raw outcomes (probability, next state, cost), aligned with
        ``model.actions[action].outcomes(state)``."""
        static = self._static[action]
        if static is _UNSET:
            static = self._static_of(action)
        if static is not None:
            close = self._close
            if close is not None:
                outs = tuple((p, close((state & keep) | add), c) for p, add, keep, c in static)
            else:
                outs = tuple((p, (state & keep) | add, c) for p, add, keep, c in static)
        else:
            unit = self.unit_cost
            outs = tuple((float(o.probability), o.apply(state), 1.0 if unit else float(o.cost))
                         for o in self.model.actions[action].outcomes(state))
        if self.relevance is None and self.symmetry is None:
            return outs
        return tuple(self._reduce(state, outs))

    def transitions(self, state: int, *, eliminate_self_loops: bool = True) -> tuple[Transition, ...]:
        """Solver transitions of ``state``: identical next states merged, expected cost.

        With ``eliminate_self_loops`` (stationary SSPs) an outcome returning to
        ``state`` is folded in analytically: repeating the action until it leaves gives
        cost ``C/(1-p_self)`` and the renormalised distribution over the other outcomes.
        The Bellman fixed point is unchanged, convergence is much faster; actions that
        never leave the state are dropped (their Q-value is infinite).
        """
        table = self._trans if eliminate_self_loops else self._trans_raw
        cached = table.get(state)
        if cached is not None:
            return cached
        result = []
        for a in self.applicable(state):
            t = self._transition(state, a, eliminate_self_loops)
            if t is not None:
                result.append(t)
        out = table[state] = tuple(result)
        return out

    def float_outcomes(self, state: int, action: int) -> list[Outcome]:
        """Outcomes with float arithmetic (for sampling: conditional effects are not
        enumerated with ``Fraction``; order may differ from :meth:`outcomes`)."""
        return self._float_outcomes(state, action)

    def _float_outcomes(self, state: int, action: int):
        """Like :meth:`outcomes` but with float arithmetic for conditional effects (not
        necessarily in the model's outcome order; solvers merge by next state anyway)."""
        outs = self._float_basic_outcomes(state, action)
        close = self._close
        if close is not None:
            outs = [(p, close(nxt), c) for p, nxt, c in outs]
        if self.relevance is None and self.symmetry is None:
            return outs
        return self._reduce(state, outs)

    def _reduce(self, state: int, outs: Sequence[Outcome]) -> Sequence[Outcome]:
        """The next states searched instead of ``state``'s: irrelevant facts cleared,
        then each one's orbit representative (both keep V*)."""
        if self.relevance is not None:
            outs = self.relevance.reduce(state, outs)
        if self.symmetry is None:
            return outs
        rep = self.symmetry.successor
        return [(p, rep(state, nxt), c) for p, nxt, c in outs]

    def sample_outcome(self, state: int, action: int, rng) -> tuple[int, float]:
        """(next state, cost) of one outcome drawn block by block (``float_effects.sample``),
        without enumerating the joint outcomes."""
        ground = self.model.actions[action]
        add, delete, cost = sample(self._compiled_effect(action), state, rng)
        if ground.delete_wins:  # mini-gpt's rule for facts an outcome adds and deletes
            nxt = (state | add) & ~delete
        else:
            nxt = (state & ~delete) | add
        base = 1.0 if self.unit_cost else float(ground.base_cost)
        if self._close is not None:
            nxt = self._close(nxt)
        if self.relevance is None and self.symmetry is None:
            return nxt, base + cost
        return self._reduce(state, [(1.0, nxt, 0.0)])[0][1], base + cost

    def _compiled_effect(self, action: int):
        compiled = self._compiled.get(action)
        if compiled is None:
            compiled = self._compiled[action] = compile_effect(
                self.model.actions[action].effect, self.unit_cost)
        return compiled

    def _float_basic_outcomes(self, state: int, action: int):
        static = self._static[action]
        if static is _UNSET:
            static = self._static_of(action)
        if static is not None:
            return [(p, (state & keep) | add, c) for p, add, keep, c in static]
        compiled = self._compiled_effect(action)
        ground = self.model.actions[action]
        base = 1.0 if self.unit_cost else float(ground.base_cost)
        if ground.delete_wins:  # mini-gpt's rule for facts an outcome adds and deletes
            return [(p, (state | a) & ~d, base + c) for p, a, d, c in branches(compiled, state)]
        return [(p, (state & ~d) | a, base + c) for p, a, d, c in branches(compiled, state)]

    def _transition(self, state: int, action: int, eliminate: bool) -> Transition | None:
        merged: dict[int, float] = {}
        expected = 0.0
        for p, nxt, c in self._float_outcomes(state, action):
            expected += p * c
            merged[nxt] = merged.get(nxt, 0.0) + p
        if eliminate and state in merged:
            stay = merged.pop(state)
            if stay >= 1.0 - _NOOP_TOLERANCE or not merged:
                return None
            scale = 1.0 / (1.0 - stay)
            return (action, expected * scale, tuple(p * scale for p in merged.values()),
                    tuple(merged))
        return (action, expected, tuple(merged.values()), tuple(merged))

    @property
    def states_cached(self) -> int:
        return len(self._applicable)
