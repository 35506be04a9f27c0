"""Expectations under product distributions, for many states at once.

For a set of rows (states) each with its own product distribution over next states,
``q[r, j] = P(bit j of the next state is 1)``, :func:`expect` computes ``E[V(s')]`` for
every row without enumerating the 2^n next states of each. Bits are summed out one at a
time: after summing out bits 0..j-1, the partial sums depend on the row only through
``q[r, 0..j-1]``, and rows sharing that prefix share one partial-sum vector. The number
of distinct prefixes stays small when each ``q[:, j]`` takes few values (SysAdmin: 3),
so the work is ``Σ_j (distinct prefixes of length j+1) · 2^(n-j-1)`` instead of
``rows · 2^n``. Bits with the fewest distinct values go first.

The grouping depends only on ``q``, so it is computed once (:func:`make_plan`) and reused
by every sweep of value iteration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Plan:
    perm: np.ndarray          # V index in the plan's bit order -> V index
    steps: tuple[tuple[np.ndarray, np.ndarray], ...]  # (parent group, q value) per bit
    group: np.ndarray         # row -> final group
    stay: np.ndarray          # row -> P(next state = the row's own state)
    work: int                 # multiply-adds per call


def _order(q: np.ndarray) -> list[int]:
    distinct = [len(np.unique(q[:, j])) for j in range(q.shape[1])]
    return sorted(range(q.shape[1]), key=lambda j: (distinct[j], j))


def _permutation(order: list[int]) -> np.ndarray:
    k = np.arange(1 << len(order), dtype=np.int64)
    perm = np.zeros_like(k)
    for t, j in enumerate(order):
        perm |= ((k >> t) & 1) << j
    return perm


def make_plan(q: np.ndarray, rows: np.ndarray, max_work: float = float("inf")) -> Plan | None:
    """The plan for ``rows`` (state indices) with bit probabilities ``q``; ``None`` if it
    would cost more than ``max_work`` multiply-adds per call."""
    m, n = q.shape
    order = _order(q)
    group = np.zeros(m, dtype=np.int64)
    steps, work, groups = [], 0, 1
    for t, j in enumerate(order):
        values, code = np.unique(q[:, j], return_inverse=True)
        key = group * len(values) + code.reshape(-1)
        uniq, inverse = np.unique(key, return_inverse=True)
        steps.append((uniq // len(values), values[uniq % len(values)]))
        group, groups = inverse.reshape(-1), len(uniq)
        work += groups << (n - t - 1) if n - t - 1 >= 0 else groups
        if work > max_work:
            return None
    own = ((rows[:, None] >> np.arange(n)) & 1).astype(bool)
    stay = np.prod(np.where(own, q, 1.0 - q), axis=1) if n else np.ones(m)
    return Plan(perm=_permutation(order), steps=tuple(steps), group=group, stay=stay,
                work=work)


def expect(plan: Plan, values: np.ndarray) -> np.ndarray:
    """``E[values(s')]`` for each row of ``plan``."""
    partial = values[plan.perm][None, :]
    for parent, q in plan.steps:
        pairs = partial.reshape(partial.shape[0], -1, 2)[parent]
        low = pairs[:, :, 0]
        partial = low + q[:, None] * (pairs[:, :, 1] - low)
    return partial[plan.group, 0]
