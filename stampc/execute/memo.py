"""Memoised steps: identical prefixes of different runs are simulated once.

Within one ``execute`` invocation, what an action does to the concrete world is a
deterministic function of

* the world's concrete state before it (``world.snapshot()``: poses, arm states, held
  object and grip, UAV pose and battery, removed objects *and where physics let them
  rest* — everything the world keeps between actions), with the active robot;
* the policy node and the sampled outcome ``k`` (which fix the ground action and its
  literal effects);
* the concrete values bound to the node's symbols (the decoded values of the policy's
  ``sigma``; they live as long as the invocation, so their identities name them);
* the executor's RNG, seeded from ``(seed, node, k)`` by the runner, not drawn from the
  run's stream.

The step — the 10× re-check, the executor, physics settling (PyBullet DIRECT, the
same calls from the same state) — is therefore stored under that key as
:class:`StepResult` (the snapshot after it, the bodies the re-check hit, a failure
message) and replayed by restoring the snapshot. Likewise the concrete goal check at
a goal leaf is a function of (leaf, state). Every *distinct* state is still simulated,
re-checked and goal-checked by the world; states are compared exactly (no rounding),
so a cache hit is never an approximation. Outcomes are always sampled afresh by the
truth model: the memo only decides how a sampled step is computed, never which one.
``tests/execute/test_memo.py`` runs policies with and without the memo and compares
every run and every intermediate snapshot.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Hashable, Mapping


@dataclass(frozen=True)
class StepResult:
    after: Any                      # the world's snapshot after the action (and physics)
    collisions: tuple[str, ...]     # bodies the re-check hit
    failure: str                    # "" when the step went through


@dataclass
class StepMemo:
    steps: dict[Hashable, StepResult] = field(default_factory=dict)
    goals: dict[Hashable, tuple[str, ...]] = field(default_factory=dict)
    hits: int = 0
    misses: int = 0

    def step_key(self, world: Any, node: Mapping[str, Any], k: int,
                 env: Mapping[str, Any]) -> Hashable:
        outcome = node["outcomes"][k]
        names = list(node["args"].values())
        names += [a for lit in (*outcome["adds"], *outcome["deletes"]) for a in lit["args"]]
        bound = tuple((n, id(env[n])) for n in dict.fromkeys(names) if n in env)
        return (node["id"], k, bound) + _state_key(world)

    def goal_key(self, world: Any, leaf: Mapping[str, Any]) -> Hashable:
        return (leaf["id"],) + _state_key(world)

    def lookup_step(self, key: Hashable) -> StepResult | None:
        found = self.steps.get(key)
        if found is None:
            self.misses += 1
        else:
            self.hits += 1
        return found


def _state_key(world: Any) -> tuple:
    state = world.snapshot()
    return (state, getattr(state, "active", None))
