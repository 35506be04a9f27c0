"""Replay a refined policy (policy.json) in a concrete world, sampling outcomes.

Each run starts from the initial world state, follows the policy from its root, samples
each action's outcome with the policy's probabilities, applies the concrete effect with
the action's bound executor, and stops at a leaf, at an unrefined node, or when the
world reports that a concrete step or goal check failed.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from stampc.refine.concretize import outcome_of
from stampc.worlds.base import ConcreteAction, Context, call_executor

SUCCESS, FAILURE, UNREFINED, DEAD_END = "success", "failure", "unrefined", "dead_end"


@dataclass(frozen=True)
class RunRecord:
    status: str
    steps: int
    actions: tuple[str, ...]
    detail: str = ""


@dataclass(frozen=True)
class ReplayReport:
    runs: tuple[RunRecord, ...]

    def count(self, status: str) -> int:
        return sum(1 for r in self.runs if r.status == status)

    @property
    def on_refined(self) -> int:
        return len(self.runs) - self.count(UNREFINED)

    @property
    def success_rate(self) -> float:
        return self.count(SUCCESS) / len(self.runs) if self.runs else 0.0

    @property
    def success_rate_on_refined(self) -> float:
        return self.count(SUCCESS) / self.on_refined if self.on_refined else 0.0

    @property
    def unrefined_rate(self) -> float:
        return self.count(UNREFINED) / len(self.runs) if self.runs else 0.0


def _decode(world: Any, data: Any) -> Any:
    decode = getattr(world, "decode", None)
    return decode(data) if decode is not None else data


def _decoded(world: Any, values: Mapping[str, Any]) -> dict[str, Any]:
    return {name: _decode(world, data) for name, data in values.items()}


@dataclass(frozen=True)
class DecodedPolicy:
    """A policy's nodes by id and its bound values decoded for one world (shared by
    :func:`replay` and :func:`stampc.execute.runner.execute_policy`)."""

    nodes: Mapping[int, Mapping]
    sigmas: Mapping[int, Mapping[str, Any]]  # node id -> the values it binds
    initial_env: Mapping[str, Any]           # the values bound before the root


def decode_policy(policy: Mapping, world: Any) -> DecodedPolicy:
    return DecodedPolicy(
        nodes={n["id"]: n for n in policy["nodes"]},
        sigmas={n["id"]: _decoded(world, n["sigma"]) for n in policy["nodes"] if "sigma" in n},
        initial_env=_decoded(world, policy.get("initial_values", {})))


def concrete_action(node: Mapping, outcome_index: int, env: Mapping[str, Any]) -> ConcreteAction:
    """The node's action with its symbols replaced by their values in ``env``."""
    def value(name: str) -> Any:
        return env.get(name, name)

    outcome = node["outcomes"][outcome_index]

    def literals(items):
        return tuple((lit["predicate"], tuple(value(a) for a in lit["args"])) for lit in items)

    name = outcome.get("name")
    return ConcreteAction(name=node["action_name"],
                          args={p: value(a) for p, a in node["args"].items()},
                          adds=literals(outcome["adds"]), deletes=literals(outcome["deletes"]),
                          outcome=outcome_index, labels=tuple(name.split("+")) if name else ())


def replay(policy: Mapping, world: Any, executors: Mapping[str, Callable], *, runs: int,
           seed: int, max_steps: int = 500,
           on_step: Callable[[int, int, Any], None] | None = None) -> ReplayReport:
    """Run the policy ``runs`` times; ``on_step(run, step, world)`` is called after
    each executed action (e.g. to render frames)."""
    decoded = decode_policy(policy, world)
    initial = world.snapshot()
    rng = random.Random(seed)
    records = []
    for run in range(runs):
        world.restore(initial)
        records.append(_one_run(decoded.nodes, decoded.sigmas, dict(decoded.initial_env),
                                policy["root"], world, executors, rng, run, max_steps, on_step))
    world.restore(initial)
    return ReplayReport(tuple(records))


def _one_run(nodes, sigmas, env, root, world, executors, rng, run, max_steps,
             on_step) -> RunRecord:
    node = nodes[root]
    done: list[str] = []
    for step in range(max_steps):
        if node["leaf"] is not None:
            status = {"goal": SUCCESS, "dead_end": DEAD_END}.get(node["leaf"], UNREFINED)
            if status == SUCCESS and not _goal_holds(world, node):
                return RunRecord(FAILURE, step, tuple(done), "goal facts do not hold concretely")
            return RunRecord(status, step, tuple(done))
        if not node["refined"]:
            return RunRecord(UNREFINED, step, tuple(done), node["action"])
        env.update(sigmas.get(node["id"], {}))
        weights = [o["probability"] for o in node["outcomes"]]
        k = rng.choices(range(len(weights)), weights=weights)[0]
        fn = executors.get(node["action_name"])
        action = concrete_action(node, k, env)
        if fn is not None and (action.adds or action.deletes):  # no-op outcomes change nothing
            ctx = Context(world=world, rng=random.Random(rng.random()), options={}, cache={})
            try:
                call_executor(fn, ctx, action, outcome_of(action, weights[k]))
            except Exception as exc:  # a concrete step failing is a failed run, not a crash
                return RunRecord(FAILURE, step, tuple(done), f"{node['action']}: {exc}")
        done.append(node["action"])
        if on_step is not None:
            on_step(run, step, world)
        node = nodes[node["outcomes"][k]["child"]]
    return RunRecord(UNREFINED, max_steps, tuple(done), "step limit")


def _goal_holds(world: Any, node: Mapping) -> bool:
    """Ask the world to confirm the goal leaf's facts it knows how to check."""
    check = getattr(world, "check_fact", None)
    if check is None:
        return True
    for fact in node.get("goal_facts", ()):
        verdict = check(fact["predicate"], tuple(fact["args"]))
        if verdict is False:
            return False
    return True
