"""ATM-MDP (Alg. 1 of Shah et al.): anytime refinement of an abstract SSP policy.

The plan refinement graph (PRG, a networkx DiGraph) holds one policy graph per node.
Each iteration takes the current PRG node, selects the uncovered root-to-leaf path with
the best p/ĉ, and works on its first unrefined action:

- *Concretization*: a backtracking search over generator samples until the action's
  concrete ``?`` preconditions hold; on success the action is refined in place and its
  outcomes are executed in the world to give the children their concrete states;
- *UpdateAbstraction*: when no sample works, the true values of the violated ``?``
  literals are written into the abstract state at that node, the policy below it is
  discarded and the SSP is re-solved from there (a new PRG child), incrementally;
- *backtracking over refined ancestors*: when a node keeps failing with nothing to learn,
  an ancestor's generator values are re-drawn and the refinements below it invalidated
  (a new PRG child too); only after that is the action banned there.

Mode choice, the explore step and iterative-broadening DFS follow the paper; horizon
leaves are extended (dynamic horizon growth) when they are selected.
"""

from __future__ import annotations

import itertools
import math
import random
import time
from dataclasses import replace
from typing import Any, Iterable, Iterator

import networkx as nx

from stampc.ir.grounded import GroundModel
from stampc.refine.backtracking import Backtracking
from stampc.refine.concretize import DEFAULT_BUDGET, Concretizer, Failure, Success
from stampc.refine.fixed import fixed_facts
from stampc.refine.graph import (DEAD_END, GOAL, HORIZON, Concrete, Node, PolicyGraph,
                                 abstract_goal_probability, adopt, path_values)
from stampc.refine.options import ProgressEvent, RefineOptions
from stampc.refine.planner import AbstractPlanner
from stampc.refine.recall import FactMemory
from stampc.refine.reporting import THRESHOLDS, Reporting
from stampc.refine.selection import NodeCost, select_path, tracked_bounds
from stampc.refine.unlocking import better_ratio, select_unlocking
from stampc.refine.update import Updating
from stampc.worlds.bindings import ResolvedBindings


class Engine(Updating, Backtracking, Reporting):
    def __init__(self, model: GroundModel, world: Any, bindings: ResolvedBindings,
                 options: RefineOptions = RefineOptions()):
        self.model = model
        self.world = world
        self.options = options
        self.rng = random.Random(options.seed)
        self.uids = itertools.count()
        self.planner = AbstractPlanner(model, options.solver, self.uids, options.fallback_solver)
        self.planner.max_retries = options.solve_retries
        self.planner.timeout_prune = options.timeout_prune_probability
        self.planner.warm_state_limit = options.warm_state_limit
        self.planner.timeout_plan = options.timeout_plan
        self.planner.solve_work_limit = options.solve_work_limit
        self.planner.adaptive_cap = options.adaptive_solve_cap
        self.concretizer = Concretizer(model, bindings, world, options.seed)
        self.memory = FactMemory(self.concretizer)
        self.initial_values = dict(world.initial_values())
        self.prg = nx.DiGraph()
        self.current = 0
        self.breadth = options.breadth
        self.horizon = options.horizon or model.horizon or 8
        self.best_graph: PolicyGraph | None = None
        #: the graph the last step worked on: the only one whose kept values are kept
        self._working: PolicyGraph | None = None
        self._holding: set[int] = {0}
        self._dead_ends_met: dict[int, int] = {}
        self._refused: dict[int, int] = {}
        #: concretization work (samples drawn + evaluations) per policy node, and the
        #: latest concretization's (``_account``): a deterministic measure, unlike seconds
        self._work: dict[int, int] = {}
        self._last_work = 0
        #: nodes that must search every sample next (``_concretize_quickly``)
        self._full_search: set[int] = set()
        self._learning = None
        self._lock_searched: set[tuple[int, int]] = set()
        self.best_prg = 0
        self.best = (-1.0, -1.0)
        self.events: list[ProgressEvent] = []
        self.crossed: dict[str, float | None] = {str(t): None for t in THRESHOLDS}
        self.stop_reason = "running"
        self._action_costs: dict[int, float] = {}
        #: what the current step did beyond its kind (solver retries, fallbacks...)
        self._notes: list[str] = []
        self.resamples = 0
        #: (abstract state, action) bans and the node whose failures caused each
        self._bans: dict[tuple[int, int], int] = {}
        #: actions refined at least once; per action, the states where it was banned
        self._worked: set[int] = set()
        self._exhausted: dict[int, set[int]] = {}
        self._fixed_facts = fixed_facts(model)
        self._fact_bans: set[int] = set()
        self._start = time.perf_counter()
        self._stopped: float | None = None

    # ------------------------------------------------------------- driving
    def run(self) -> Iterator[ProgressEvent]:
        """Anytime loop: yields a progress event per iteration until a stop condition."""
        self._start = time.perf_counter()
        if self.options.time_limit is not None:
            self.planner.deadline = self._start + self.options.time_limit
            self.concretizer.deadline = self.planner.deadline
        self.planner.solve_time_limit = self.options.solve_time_limit
        self.planner.solve_work_limit = self.options.solve_work_limit
        self._stopped = None
        initial = self.world.snapshot()
        try:
            yield from self._loop()
        finally:
            self._stopped = time.perf_counter()
            self.world.restore(initial)  # leave the world as we found it

    def _loop(self) -> Iterator[ProgressEvent]:
        if not self._initialise():
            self.stop_reason = "abstract goal unreachable"
            yield self._event("done", self.stop_reason)
            return
        yield self._event("start")
        opts = self.options
        for _ in range(opts.max_iterations):
            if self.best[0] >= opts.target_coverage - 1e-9:  # fixed points of cycles converge from below
                self.stop_reason = "target coverage reached"
                break
            if opts.time_limit is not None and self.elapsed() >= opts.time_limit:
                self.stop_reason = "time limit"
                break
            kind, detail = self.step()
            if kind == "exhausted":
                self.stop_reason = detail
                break
            yield self._event(kind, detail)
        else:
            self.stop_reason = "iteration limit"
        yield self._event("done", self.stop_reason)

    def elapsed(self) -> float:
        """Seconds in the engine's loop: frozen when the loop ends, so the summary's time
        is the one ``time_limit`` applies to (not the reporting after it)."""
        end = self._stopped if self._stopped is not None else time.perf_counter()
        return end - self._start

    # ---------------------------------------------------------- initialise
    def _initialise(self) -> bool:
        """Solve at the root, growing the horizon until the goal has probability > 0."""
        snapshot = self.world.snapshot()
        graph = PolicyGraph(-1, {})
        graph.root = self._graft_growing(graph, self.model.init, 0, None)
        key = self.world.fingerprint(snapshot) if hasattr(self.world, "fingerprint") else None
        graph.nodes[graph.root].concrete = Concrete(snapshot, key)
        self.prg.add_node(0, graph=graph, parent=None, failed=False)
        self._track(0, graph)
        return abstract_goal_probability(graph) > 0

    def _graft_growing(self, graph: PolicyGraph, state: int, depth: int,
                       forced: int | None, learned: tuple[int, int] | None = None) -> int:
        """Plan from ``state`` and graft the policy unrolled for one horizon. The horizon
        is doubled only when a *converged* solve has no goal within it (dynamic horizon
        growth); a solve cut off by its time cap leaves the horizon as it is."""
        while True:
            timeouts = self.planner.timeouts
            scratch = PolicyGraph(-1, {})
            scratch.root = self.planner.graft(scratch, state, depth, depth + self.horizon,
                                              forced_action=forced, learned=learned)
            self._notes += self.planner.notes
            learned = None  # a regrown solve continues from the same tables
            leaves = {n.leaf for n in scratch.nodes.values() if n.is_leaf}
            converged = self.planner.timeouts == timeouts
            if (GOAL in leaves or HORIZON not in leaves or not converged
                    or self.horizon >= self.options.max_horizon):
                if not converged and GOAL not in leaves and HORIZON in leaves:
                    self._notes.append(f"horizon kept at {self.horizon}: the solve timed out")
                graph.nodes.update(scratch.nodes)
                return scratch.root
            self.horizon = min(2 * self.horizon, self.options.max_horizon)
            self._notes.append(f"horizon grown to {self.horizon}: no goal within it")

    # ----------------------------------------------------------------- step
    def step(self) -> tuple[str, str]:
        graph = self._current_graph()
        return self._act(graph, self._select(graph))

    def _current_graph(self) -> PolicyGraph:
        """The current PRG node's graph. The kept values of the graph worked on before
        are dropped when the engine moves on (a failed replan's, or an abandoned PRG
        node's): they are rebuilt if it comes back, and a run keeps one set, not one per
        PRG node it has visited."""
        graph: PolicyGraph = self.prg.nodes[self.current]["graph"]
        if self._working is not None and self._working is not graph:
            self._working.caches.clear()
        self._working = graph
        return graph

    def _select(self, graph: PolicyGraph, cost: NodeCost | None = None,
                changed: Iterable[int] = ()):
        """The best uncovered path: by the mass it unlocks (unlocking.py) where branches
        merge, unless p/ĉ's exact search finds a better ratio; else by its probability
        (selection.py). The values are kept on the graph (ĉ depends on the node and the
        horizon only); ``cost`` differing from ĉ on the ``changed`` nodes only (a
        parallel batch's taken ones) is computed aside."""
        cost = cost or self._node_cost

        def by_path():
            return select_path(graph, cost,
                               bounds=tracked_bounds(graph, cost, self.horizon, changed))

        if self.options.selection == "unlocked":
            found = select_unlocking(graph, cost, self.horizon, changed)
            if found is None:
                return None  # nothing left to gain
            if found is not False:
                return better_ratio(found, by_path())
        return by_path()

    def _act(self, graph: PolicyGraph, selected) -> tuple[str, str]:
        """Work on the selected path: extend its open leaf or refine its first unrefined action."""
        if selected is None:
            # nothing selectable here (given-up leaves, or merges that closed a loop with
            # no way out, e.g. after an explore step): this PRG node is spent, but its
            # ancestors may still broaden — only the root's exhaustion ends the run
            self.prg.nodes[self.current]["exhausted"] = True
            if self.current == 0:
                return "exhausted", "no uncovered path can be refined"
            return self._backtrack(None)
        _, _, path = selected
        for i, uid in enumerate(path):
            node = graph[uid]
            if node.is_leaf:
                if node.leaf == HORIZON or (node.leaf == DEAD_END and not node.proven
                                            and not node.given_up):
                    return self._extend(graph, node)
                break
            if not node.refined:
                return self._refine(graph, path[: i + 1])
        return "exhausted", "selected path has nothing to refine"

    def _node_cost(self, node: Node) -> float:
        """ĉ: estimated refinement cost of one node (0 once refined).

        As in the paper's analysis, an action costs the size of its generators' joint
        domain — the product of their budgets, which is what the backtracking search of
        Concretization enumerates in the worst case (1 without generators). A horizon
        leaf or an unproven dead end costs one horizon (a replan); a dead end that
        replanning could not leave is never selected again (infinite cost)."""
        if node.is_leaf:
            if node.leaf == HORIZON or (node.leaf == DEAD_END and not node.proven):
                return math.inf if node.given_up else float(self.horizon)
            return 0.0
        if node.refined:
            return 0.0
        cost = self._action_costs.get(node.action)
        if cost is None:
            budgets = {g.name: int(dict(g.options).get("budget", DEFAULT_BUDGET))
                       for g in self.model.lifted.domain.generators}
            action = self.model.actions[node.action]
            cost = self._action_costs[node.action] = float(math.prod(
                budgets[u.generator] for u in action.generated))
        return cost

    def _extend(self, graph: PolicyGraph, leaf: Node) -> tuple[str, str]:
        """Dynamic horizon growth: replace a horizon leaf (or an unproven dead end, where
        the solver gave up) by a freshly planned subtree."""
        was_dead_end = leaf.leaf == DEAD_END
        sub = self._graft_growing(graph, leaf.state, leaf.depth, None)
        leaf = adopt(graph, leaf, graph[sub])
        if was_dead_end and leaf.leaf == DEAD_END and not leaf.proven:
            leaf.given_up = True  # replanning found no way out either: stays unrefined
            self._track(self.current, graph)
            return "give-up", f"node {leaf.uid}: no way to the goal found, not proven a dead end"
        self._track(self.current, graph)
        return "extend", f"node {leaf.uid} at depth {leaf.depth}"

    def _refine(self, graph: PolicyGraph, path: tuple[int, ...]) -> tuple[str, str]:
        node = graph[path[-1]]
        action = self.model.actions[node.action]
        if node.action in self._fact_bans:  # planned before a fixed fact ruled it out
            self._notes.append(f"{action.label}: needs the other value of a learned fixed fact")
            return self._update(graph, node, (), "update", path)
        values = path_values(graph, path[:-1], self.initial_values)
        quick = self._concretize_quickly(node, self.rng.random())
        before = self.concretizer.work
        result = self.concretizer.concretize(
            action, node.concrete.snapshot, node.concrete.cache, values,
            node_uid=node.uid, attempt=node.attempts, quick=quick)
        self._account(node.uid, self.concretizer.work - before)
        return self._integrate(graph, path, result, values)

    def _account(self, uid: int, work: int) -> None:
        """Record ``work`` (samples drawn + evaluations) spent concretizing node ``uid``."""
        self._work[uid] = self._work.get(uid, 0) + work
        self._last_work = work

    def _concretize_quickly(self, node: Node, draw: float) -> bool:
        """Whether ``node``'s concretization takes UpdateAbstraction's quick mode (the
        first complete sample only): when ``draw`` < ``update_probability``, except for a
        node whose quick sample's facts were about to prove a dead end, which searches
        every sample of its generators first (``Updating._update``)."""
        return draw < self.options.update_probability and node.uid not in self._full_search

    def _integrate(self, graph: PolicyGraph, path: tuple[int, ...], result: Success | Failure,
                   values, snapshots: list | None = None) -> tuple[str, str]:
        """Act on the concretization ``result`` of the path's last node (``snapshots``:
        its outcomes' concrete states when a worker executed them already)."""
        node = graph[path[-1]]
        action = self.model.actions[node.action]
        if not isinstance(result, Success) and self.concretizer.past_deadline():
            return "stopped", f"{action.label}: time limit reached while sampling"
        if isinstance(result, Success):
            if not self._commit(graph, node, result.sigma, values, snapshots):
                # its outcomes would merge into a loop with no way out: the policy above
                # was planned before later bans; give the action up here and replan
                self._notes.append(f"{action.label}: its outcomes close a loop with no way out")
                self.planner.forbidden.add((node.state, node.action))
                self._bans[(node.state, node.action)] = node.uid
                return self._update(graph, node, (), "ban", path)
            self._worked.add(node.action)
            self._track(self.current, graph)
            return "refined", action.label
        return self._on_failure(graph, path, result, values)

    def _commit(self, graph: PolicyGraph, node: Node, sigma, values,
                snapshots: list | None = None) -> bool:
        """Refine ``node`` with ``sigma``; execute each outcome to get child states.
        Children equal to existing nodes are merged into them — unless that would leave
        ``node`` in a loop with no way out (no leaf reachable): then nothing is committed
        and False is returned."""
        node = graph.own(node.uid)
        before = list(node.edges)
        graph.touch(node.uid)
        node.sigma = sigma
        action = self.model.actions[node.action]
        env = {**values, **sigma}
        merge = getattr(self.world, "fingerprint", None)
        for k, edge in enumerate(node.edges):
            snap = snapshots[k] if snapshots is not None else self.concretizer.execute(
                action, edge.successor, edge.outcome, node.concrete.snapshot,
                node.concrete.cache, env, node.uid, node.state)
            key = merge(snap) if merge else None
            target = self._merge_target(graph, graph[edge.child].state, key)
            if target is None:
                target = self._claim(graph, edge.child, snap, key)
            if target != edge.child:
                node.edges[k] = replace(edge, child=target)
        trapped = any(e.child != b.child for e, b in zip(node.edges, before)) \
            and not graph.reaches_leaf(node.uid)
        if trapped:
            node.sigma, node.edges = None, before
        graph.prune()
        return not trapped

    def _claim(self, graph: PolicyGraph, uid: int, snap: Any, key: Any) -> int:
        """Give node ``uid`` the concrete state ``snap``; if another parent already gave
        it a different one, split off a copy (copy-on-write of shared subtrees)."""
        child = graph[uid]
        if child.concrete is None:
            graph.own(uid).concrete = Concrete(snap, key)
            return uid
        clone = replace(child, uid=next(self.uids), edges=list(child.edges),
                        concrete=Concrete(snap, key), sigma=None)
        graph.nodes[clone.uid] = clone
        return clone.uid

    @staticmethod
    def _merge_target(graph: PolicyGraph, state: int, key: Any) -> int | None:
        """A node with the same abstract and concrete state whose policy can be shared."""
        if key is None:
            return None
        for other in graph.nodes.values():
            if other.state == state and other.concrete is not None and other.concrete.key == key:
                return other.uid
        return None
