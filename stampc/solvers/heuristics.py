"""Heuristics over the delete relaxation of the all-outcomes determinization.

Every outcome of every action (and every conditional effect with its condition) becomes a
relaxed action whose precondition is the action's precondition literals (plus the
``when`` condition's) and whose effect is that outcome's literals. Negative literals are
facts of their own (fact ``i`` false is relaxed fact ``n + i``: reached initially when
``i`` is false, or by an effect deleting ``i``), so a goal or precondition needing a fact
that nothing can delete is recognised as unreachable — e.g. ``not crushed(target)`` after
the target was crushed, or ``not collision(x, t)`` with no action that moves ``x``.
Disjunctions contribute nothing — which, like the relaxation itself, only lowers costs.
Ground axioms (derived facts, docs/ir.md) are zero-cost relaxed actions, body -> head;
a derived fact's *falsity* costs nothing (it needs some body literal of every rule of
the fact to fail, a disjunction the relaxation drops), so bounds stay admissible.

- ``zero``: 0 everywhere (admissible).
- ``hmax``: max over preconditions (admissible when costs are non-negative).
- ``hff``: the cost of a relaxed plan extracted from h_max's best supporters (each
  relaxed action counted once, as in FF) — INADMISSIBLE; unlike h_add it does not
  double-count shared sub-goals, so long chains (stacking planks) are not overestimated.
- ``hadd``: sum over preconditions — INADMISSIBLE, usually much more informed; LAO* and
  LRTDP then return fast but possibly suboptimal policies.

A state whose relaxation cannot reach the goal is a dead end (value ``inf``), for every
heuristic except ``zero``. Values are cached per state.
"""

from __future__ import annotations

import heapq
import math
from fractions import Fraction
from typing import Callable

from stampc.ir.grounded import GAnd, GEffect, GFormula, GLit, GroundCondition, GroundModel
from stampc.ir.masks import indices
from stampc.solvers.layered import LayeredHmax
from stampc.solvers.names import ADMISSIBLE, HEURISTICS  # noqa: F401  (re-exported)
from stampc.solvers.open_view import OpenView
from stampc.solvers.successors import iter_bits

Heuristic = Callable[[int], float]


def _must_facts(formulas: tuple[GFormula, ...], n: int) -> set[int]:
    """Relaxed literals every model of the conjunction ``formulas`` must contain
    (``n + i`` stands for fact ``i`` being false)."""
    facts: set[int] = set()
    for f in formulas:
        if isinstance(f, GLit):
            facts.add(f.fact if f.positive else n + f.fact)
        elif isinstance(f, GAnd):
            facts |= _must_facts(f.args, n)
    return facts


def condition_facts(cond: GroundCondition, n: int) -> frozenset[int]:
    """Relaxed literals of a condition over a model with ``n`` facts."""
    return frozenset(set(indices(cond.pos_facts)) | {n + f for f in indices(cond.neg_facts)}
                     | _must_facts(cond.rest, n))


def relaxed_state(state: int, n: int, full: int) -> int:
    """The relaxed literals true in ``state``: its facts, and ``n + i`` for each false ``i``."""
    return state | ((full & ~state) << n)


def _min_cost(effect: GEffect) -> Fraction:
    """A lower bound on the cost contributed by ``effect`` in any joint outcome."""
    total = effect.cost
    for _, sub in effect.whens:
        total += min(Fraction(0), _min_cost(sub))
    for block in effect.blocks:
        options = [_min_cost(sub) for _, sub in block.outcomes]
        if sum(p for p, _ in block.outcomes) < 1:
            options.append(Fraction(0))
        total += min(options)
    return total


def _relaxed_adds(effect: GEffect, pre: frozenset[int], out: dict, n: int) -> None:
    """Collect (precondition literals -> achieved literals) pairs of every outcome."""
    achieved = effect.add | (effect.delete << n)
    if achieved:
        out.setdefault(pre, 0)
        out[pre] |= achieved
    for cond, sub in effect.whens:
        if not cond.never:
            _relaxed_adds(sub, pre | condition_facts(cond, n), out, n)
    for block in effect.blocks:
        for _, sub in block.outcomes:
            _relaxed_adds(sub, pre, out, n)


def relaxed_axioms(model: GroundModel, n: int) -> dict[frozenset[int], int]:
    """Zero-cost relaxed actions of the model's axioms: precondition literals -> added
    literals (a rule's head; and, unconditionally, every derived fact being false)."""
    out: dict[frozenset[int], int] = {}
    for rule in model.axioms.rules:
        pre = condition_facts(rule.body, n)
        out[pre] = out.get(pre, 0) | (1 << rule.head)
    if model.axioms.derived:
        out[frozenset()] = out.get(frozenset(), 0) | (model.axioms.derived << n)
    return out


class RelaxedModel:
    """Relaxed actions in flat arrays: preconditions, adds, costs, and fact -> actions."""

    def __init__(self, model: GroundModel, unit_cost: bool):
        # Relaxed actions with the same precondition facts and cost are merged (their adds
        # OR-ed): exact for h_max and h_add, and far fewer counters to maintain per state.
        n = len(model.facts)
        self.n, self.full = n, (1 << n) - 1
        merged: dict[tuple[frozenset[int], float], int] = {}
        pre_cache: dict[GroundCondition, frozenset[int]] = {}
        for action in model.actions:
            if action.precondition.never:
                continue
            cost = 1.0 if unit_cost else max(0.0, float(action.base_cost + _min_cost(action.effect)))
            pairs: dict[frozenset[int], int] = {}
            pre_facts = pre_cache.get(action.precondition)
            if pre_facts is None:
                pre_facts = pre_cache[action.precondition] = condition_facts(action.precondition, n)
            _relaxed_adds(action.effect, pre_facts, pairs, n)
            for pre, add in pairs.items():
                key = (pre, cost)
                merged[key] = merged.get(key, 0) | add
        for pre, add in relaxed_axioms(model, n).items():
            merged[(pre, 0.0)] = merged.get((pre, 0.0), 0) | add
        pres = [tuple(sorted(pre)) for pre, _ in merged]
        costs = [cost for _, cost in merged]
        adds = [tuple(iter_bits(add)) for add in merged.values()]
        self.pres, self.adds, self.costs = pres, adds, costs
        self.add_masks = list(merged.values())
        #: The common cost when all relaxed actions cost the same (layered h_max applies).
        self.uniform_cost = costs[0] if costs and all(c == costs[0] for c in costs) else None
        self.counts = [len(p) for p in pres]
        self.free = [i for i, p in enumerate(pres) if not p]
        self.pre_masks = [sum(1 << f for f in p) for p in pres]
        self.users: list[list[int]] = [[] for _ in range(2 * n)]
        for i, pre in enumerate(pres):
            for f in pre:
                self.users[f].append(i)
        goal = model.goal
        self.goal_never = goal.never
        self.goal_facts = tuple(sorted(condition_facts(goal, n)))
        self.goal_mask = sum(1 << g for g in self.goal_facts)
        #: literals some precondition or the goal needs: the only ones worth propagating
        self.useful = self.goal_mask
        for m in self.pre_masks:
            self.useful |= m
        #: literal -> 1 if useful (an index beats a shift of a thousands-of-bits mask)
        self.useful_flags = bytearray(2 * n)
        for g in iter_bits(self.useful):
            self.useful_flags[g] = 1
        #: open-precondition counts of the initial state (the first view, open_view.py)
        self.ref_state = model.init & self.full
        self.ref_counts = _count_lacking(self, relaxed_state(self.ref_state, n, self.full))
        #: the useful literals the initial state lacks
        self.ref_open = frozenset(iter_bits(self.useful & ~relaxed_state(self.ref_state, n,
                                                                         self.full)))
        #: useful literal -> the relaxed actions adding it, in index order
        self.adders: dict[int, list[int]] = {}
        for i, add in enumerate(self.add_masks):
            for g in iter_bits(add & self.useful):
                self.adders.setdefault(g, []).append(i)
        #: h_max by layers when every relaxed action costs the same positive amount
        self.layered = (LayeredHmax(self, self.uniform_cost)
                        if self.uniform_cost is not None and self.uniform_cost > 0 else None)
        #: the open literals, counts and adds of the state evaluated last (open_view.py)
        self.view = OpenView(self)
        #: the work of every evaluation so far beyond one unit each, in units of about one
        #: h_add evaluation on the 25-can cluttered table (``EFFORT_UNIT``): deterministic,
        #: and added to one unit per generated node it makes ``Search.work`` about
        #: proportional to CPU time on large models too
        self.effort = 0.0
        self.effort_per_evaluation = (EFFORT_BASE + len(costs)) / EFFORT_UNIT


def _count_lacking(rm: RelaxedModel, literals: int) -> list[int]:
    """Per relaxed action, how many of its precondition literals ``literals`` lacks."""
    lacking = ~literals
    return [(m & lacking).bit_count() for m in rm.pre_masks]


#: An evaluation costs about ``EFFORT_BASE`` + one per relaxed action (its counter is
#: copied and scanned) + one per counter update, in units of ``EFFORT_UNIT`` (an h_add
#: evaluation on the 25-can cluttered table: 220 relaxed actions, ~450 updates, ~130 µs,
#: where the solve caps were sized). Fitted to CPU time (µs ≈ 11.3 + 0.173·actions +
#: 0.180·updates) on the 25- and 60-can tables and two random models, within 5 %.
#: ``RelaxedModel.effort`` sums what evaluations cost beyond one unit each (~1.7 per
#: evaluation on 60 cans; cheaper ones count one unit, as they always did).
EFFORT_BASE = 63
EFFORT_UNIT = 730


def _relaxed_cost(rm: RelaxedModel, state: int, mode: str) -> float:
    """Generalised Dijkstra over the literals not yet true; stops once every goal literal
    is settled. ``mode``: "max" (h_max), "add" (h_add) or "ff" (relaxed plan cost).

    Only *open* literals (useful ones — in some precondition or the goal — that the state
    lacks) are ever touched: each action's open adds come from the open literals' adders
    (``rm.view``, open_view.py) rather than from masking its adds, since a 60-can table
    has ~570 adds per relaxed action over 72,000 literals, nearly all already true, and
    walking the bits of a masked big int costs a 9 kB operation per bit."""
    if rm.goal_never:
        return math.inf
    if mode == "max" and rm.layered is not None:
        return rm.layered(state)
    # h_FF takes its supporters from the h_max propagation (as FF's planning graph does):
    # a max costs O(1) per relaxed action where a sum walks every precondition
    additive = mode == "add"
    view = rm.view
    view.move(state)
    open_literals = view.open
    goal = [g for g in rm.goal_facts if g in open_literals]
    if not goal:
        return 0.0
    counts = list(view.counts)
    adds = view.adds
    costs, users = rm.costs, rm.users
    settled = [0.0] * len(costs)  # h_add: summed costs of each action's settled preconditions
    best: dict[int, float] = {}
    supporter: dict[int, int] = {}
    heap: list[tuple[float, int]] = []
    for i, c in enumerate(counts):
        if not c:
            ci = costs[i]
            for g in adds.get(i, ()):
                if ci < best.get(g, math.inf):
                    best[g], supporter[g] = ci, i
                    heap.append((ci, g))
    heapq.heapify(heap)
    goal_set = set(goal)
    remaining = len(goal)
    total = 0.0
    heappop, heappush, inf = heapq.heappop, heapq.heappush, math.inf
    updates = 0
    while heap:
        c, f = heappop(heap)
        if c > best[f]:
            continue  # a stale entry: f was reached more cheaply (and settled then)
        best[f] = -1.0  # settled: no later (non-negative) cost is below it
        if f in goal_set:
            total = total + c if additive else c
            remaining -= 1
            if remaining == 0:
                rm.effort += _effort(rm, updates)
                return _relaxed_plan_cost(rm, goal, supporter) if mode == "ff" else total
        users_f = users[f]
        updates += len(users_f)
        for i in users_f:
            left = counts[i] - 1
            counts[i] = left
            if additive:  # only open preconditions cost anything; settled costs are final
                settled[i] += c
            if left:
                continue
            base = costs[i] + settled[i] if additive else c + costs[i]
            for g in adds.get(i, ()):
                if base < best.get(g, inf):
                    best[g] = base
                    supporter[g] = i
                    heappush(heap, (base, g))
    rm.effort += _effort(rm, updates)
    return math.inf


def _effort(rm: RelaxedModel, updates: int) -> float:
    """One evaluation's work units beyond the one every generated node counts already
    (``Search.work``): the excess of its fitted cost over one unit, or 0."""
    units = rm.effort_per_evaluation + updates / EFFORT_UNIT
    return units - 1.0 if units > 1.0 else 0.0


def _relaxed_plan_cost(rm: RelaxedModel, goal: list[int], supporter: dict[int, int]) -> float:
    """Cost of the relaxed plan formed by the best supporters of the goal literals and,
    recursively, of their open preconditions — each relaxed action counted once."""
    plan: set[int] = set()
    seen = set(goal)
    stack = list(goal)
    while stack:
        i = supporter[stack.pop()]
        if i in plan:
            continue
        plan.add(i)
        for p in rm.pres[i]:
            if p not in seen and p in supporter:  # open literals are exactly the supported ones
                seen.add(p)
                stack.append(p)
    return sum(rm.costs[i] for i in plan)


def make_heuristic(name: str, model: GroundModel, unit_cost: bool,
                   weight: float = 1.0) -> Heuristic:
    """A cached state -> cost-to-go estimate (``inf`` marks a recognised dead end)."""
    if name == "zero":
        return lambda state: 0.0
    if name not in ("hmax", "hadd", "hff"):
        raise ValueError(f"unknown heuristic {name!r}; choose one of {', '.join(HEURISTICS)}")
    rm = RelaxedModel(model, unit_cost)
    mode = {"hmax": "max", "hadd": "add", "hff": "ff"}[name]
    cache: dict[int, float] = {}

    def h(state: int) -> float:
        v = cache.get(state)
        if v is None:
            v = cache[state] = weight * _relaxed_cost(rm, state, mode)
        return v

    h.effort = lambda: rm.effort  # type: ignore[attr-defined]  (read by Search.work)
    return h
