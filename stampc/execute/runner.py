"""The execution loop: follow a refined policy in its world, the world deciding outcomes.

Each run starts from the initial concrete state and, at every action node,

1. samples the outcome from the :class:`~.truth.TruthModel` (never from the policy);
2. re-checks the action's trajectories against the current concrete state
   (:mod:`.recheck`) — each contact is a collision;
3. applies the concrete effect with the bound executor;
4. follows the policy edge of that outcome — an outcome the policy did not plan for ends
   the run on an unrefined branch.

At a goal leaf the concrete goal check (:mod:`.goals`) decides: a failed check is a
failed run with its reason.

Steps 2-3 and the goal check are deterministic functions of the concrete state, the
node, the outcome and the node's bound values (the executor's RNG is seeded from
``(seed, node, outcome)``), so by default they are memoised within one invocation
(:mod:`.memo`): identical prefixes of different runs are simulated once.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from stampc.execute.memo import StepMemo, StepResult
from stampc.execute.truth import TrueOutcome, TruthModel, planned_key
from stampc.refine.replay import (DEAD_END, FAILURE, SUCCESS, UNREFINED, concrete_action,
                                  decode_policy)
from stampc.refine.concretize import outcome_of
from stampc.worlds.base import Context, call_executor

#: (world, leaf node) -> reasons the concrete goal does not hold (empty: it holds)
GoalCheck = Callable[[Any, Mapping[str, Any]], list[str]]
#: (world, concrete action) -> names of bodies the action's trajectories touch
Recheck = Callable[[Any, Any], list[str]]


@dataclass(frozen=True)
class Step:
    action: str       # ground action label
    schema: str       # action name
    outcome: str      # the sampled outcome's name (see :func:`outcome_name`)
    planned: bool
    model: Mapping[str, float]  # outcome name -> the model's probability at this node
    truth: Mapping[str, float]  # outcome name -> the true probability at this node


@dataclass(frozen=True)
class Run:
    status: str
    steps: tuple[Step, ...]
    detail: str = ""
    collisions: tuple[str, ...] = ()
    goal_failures: tuple[str, ...] = ()


@dataclass(frozen=True)
class Hooks:
    """What execution calls besides the executors (all optional)."""

    goal_check: GoalCheck | None = None
    recheck: Recheck | None = None
    #: called after each executed action with (run index, world)
    on_step: Callable[[int, Any], None] | None = None
    #: run before each action (e.g. settle physics); ``(world, concrete action)``
    before_action: Callable[[Any, Any], None] | None = None
    after_action: Callable[[Any, Any], None] | None = None
    on_run_start: Callable[[int], None] | None = None


def execute_policy(policy: Mapping, world: Any, executors: Mapping[str, Callable],
                   truth: TruthModel, *, runs: int, seed: int, max_steps: int = 500,
                   hooks: Hooks = Hooks(), memo: StepMemo | None = None,
                   fresh_runs: int = 0) -> tuple[Run, ...]:
    """``runs`` seeded runs; with ``memo``, steps and goal checks already computed from
    the same state are replayed from it — except in the first ``fresh_runs`` runs,
    which compute (and store) every step, e.g. for the recorder's frames."""
    decoded = decode_policy(policy, world)
    initial = world.snapshot()
    rng = random.Random(seed)
    out = []
    for run in range(runs):
        world.restore(initial)
        if hooks.on_run_start is not None:
            hooks.on_run_start(run)
        loop = _RunLoop(decoded.nodes, decoded.sigmas, dict(decoded.initial_env), world,
                        executors, truth, hooks, random.Random(rng.random()), run, seed)
        loop.memo, loop.replay = memo, run >= fresh_runs
        out.append(loop.go(policy["root"], max_steps))
    world.restore(initial)
    return tuple(out)


class _RunLoop:
    def __init__(self, nodes, sigmas, env, world, executors, truth, hooks, rng, run, seed):
        self.nodes, self.sigmas, self.env = nodes, sigmas, env
        self.world, self.executors, self.truth = world, executors, truth
        self.hooks, self.rng, self.run, self.seed = hooks, rng, run, seed
        self.steps: list[Step] = []
        self.collisions: list[str] = []
        self.memo: StepMemo | None = None
        self.replay = False  # read the memo (else compute every step, still storing it)

    def result(self, status: str, detail: str = "", goal_failures=()) -> Run:
        return Run(status, tuple(self.steps), detail, tuple(self.collisions),
                   tuple(goal_failures))

    def go(self, root: int, max_steps: int) -> Run:
        node = self.nodes[root]
        for _ in range(max_steps):
            if node["leaf"] is not None:
                return self.leaf(node)
            if not node["refined"]:
                return self.result(UNREFINED, f"unrefined node: {node['action']}")
            self.env.update(self.sigmas.get(node["id"], {}))
            sampled = self.truth.sample(node, self.rng)
            self.steps.append(_step(node, sampled, self.truth))
            if sampled.planned is None:
                return self.result(UNREFINED, f"{node['action']}: outcome "
                                   f"{self.steps[-1].outcome} was not planned for")
            failure = self.memoised_act(node, sampled.planned)
            if failure:
                return self.result(FAILURE, failure)
            node = self.nodes[node["outcomes"][sampled.planned]["child"]]
        return self.result(UNREFINED, "step limit")

    def leaf(self, node: Mapping[str, Any]) -> Run:
        if node["leaf"] == "dead_end":
            return self.result(DEAD_END)
        if node["leaf"] != "goal":
            return self.result(UNREFINED, f"{node['leaf']} leaf")
        reasons = self.goal_reasons(node)
        if reasons:
            return self.result(FAILURE, "concrete goal check failed: " + "; ".join(reasons),
                               reasons)
        return self.result(SUCCESS)

    def goal_reasons(self, leaf: Mapping[str, Any]) -> tuple[str, ...]:
        if self.hooks.goal_check is None:
            return ()
        if self.memo is None:
            return tuple(self.hooks.goal_check(self.world, leaf))
        key = self.memo.goal_key(self.world, leaf)
        if not self.replay or key not in self.memo.goals:
            self.memo.goals[key] = tuple(self.hooks.goal_check(self.world, leaf))
        return self.memo.goals[key]

    def memoised_act(self, node: Mapping[str, Any], k: int) -> str:
        """:meth:`act`, or its stored result for the same state, node, outcome, values."""
        if self.memo is None:
            result = self.act(node, k)
        else:
            key = self.memo.step_key(self.world, node, k, self.env)
            result = self.memo.lookup_step(key) if self.replay else None
            if result is None:
                result = self.memo.steps[key] = self.act(node, k)
            else:
                self.world.restore(result.after)
        self.collisions.extend(f"{node['action']}: {h}" for h in result.collisions)
        if self.hooks.on_step is not None and not result.failure:
            self.hooks.on_step(self.run, self.world)
        return result.failure

    def act(self, node: Mapping[str, Any], k: int) -> StepResult:
        action = concrete_action(node, k, self.env)
        fn = self.executors.get(node["action_name"])
        hits: list[str] = []
        try:
            if self.hooks.recheck is not None:
                hits = self.hooks.recheck(self.world, action)
            if self.hooks.before_action is not None:
                self.hooks.before_action(self.world, action)
            if fn is not None and (action.adds or action.deletes):  # no-op outcomes: as is
                # seeded by the step, not the run: same step, same controller choices
                ctx = Context(world=self.world, options={}, cache={},
                              rng=random.Random(f"{self.seed}:{node['id']}:{k}"))
                probability = float(node["outcomes"][k]["probability"])
                call_executor(fn, ctx, action, outcome_of(action, probability))
            if self.hooks.after_action is not None:
                self.hooks.after_action(self.world, action)
        except Exception as exc:  # a concrete step failing is a failed run, not a crash
            return StepResult(self.world.snapshot(), tuple(hits),
                              f"{node['action']}: {type(exc).__name__}: {exc}")
        return StepResult(self.world.snapshot(), tuple(hits), "")


def _step(node: Mapping[str, Any], sampled: TrueOutcome, truth: TruthModel) -> Step:
    true = truth.distribution(node)
    names = outcome_names(node, true)
    model: dict[str, float] = {}
    for o in node["outcomes"]:  # outcomes sharing a name (e.g. +toppled) add up
        name = names[planned_key(o)]
        model[name] = model.get(name, 0.0) + float(o["probability"])
    truth_p: dict[str, float] = {}
    for o in true:
        truth_p[names[o.key]] = truth_p.get(names[o.key], 0.0) + o.probability
    return Step(node["action"], node["action_name"], names[sampled.key],
                sampled.planned is not None, model, truth_p)


def outcome_names(node: Mapping[str, Any], true: tuple[TrueOutcome, ...]) -> dict:
    """A readable name per outcome of a node: its ``as NAME`` label when the policy
    records one, else what sets it apart from the node's other outcomes
    (``+crushed``, ``+toppled×2``; ``nominal`` when nothing does)."""
    keys = list(dict.fromkeys([o.key for o in true] + [planned_key(o) for o in node["outcomes"]]))
    labels = {planned_key(o): o.get("name") for o in node["outcomes"]}
    common_add = frozenset.intersection(*[k[0] for k in keys]) if keys else frozenset()
    common_del = frozenset.intersection(*[k[1] for k in keys]) if keys else frozenset()
    names = {}
    for key in keys:
        names[key] = labels.get(key) or _difference(key, common_add, common_del)
    return names


def _difference(key, common_add, common_del) -> str:
    parts = []
    for sign, facts in (("+", key[0] - common_add), ("-", key[1] - common_del)):
        counts: dict[str, int] = {}
        for fact in facts:
            pred = fact.partition("(")[0]
            counts[pred] = counts.get(pred, 0) + 1
        parts += [f"{sign}{p}" + (f"×{n}" if n > 1 else "") for p, n in sorted(counts.items())]
    return " ".join(parts) or "nominal"
