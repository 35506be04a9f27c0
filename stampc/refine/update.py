"""UpdateAbstraction in the ATM-MDP engine (Alg. 1): what a failed concretization leads
to. Violated ``?`` literals are written into the abstract state at the node and the SSP is
re-solved from there (a new PRG node); with nothing to learn the node retries, explores,
or bans its action and replans; a replan with no way to the goal revises an earlier
choice (backtracking.py). A mixin of :class:`stampc.refine.engine.Engine`, kept apart so
that each file reads in one sitting."""

from __future__ import annotations

import random
from typing import TYPE_CHECKING, Callable

from stampc.refine.backtracking import fact_labels, has_way
from stampc.refine.concretize import Failure
from stampc.refine.graph import Node, PolicyGraph
from stampc.refine.learning import LearningChoice
from stampc.solvers.heuristics import make_heuristic

if TYPE_CHECKING:
    from stampc.ir.grounded import GroundModel
    from stampc.refine.options import RefineOptions
    from stampc.refine.planner import AbstractPlanner
    from stampc.refine.recall import FactMemory


class Updating:
    model: "GroundModel"
    options: "RefineOptions"
    planner: "AbstractPlanner"
    memory: "FactMemory"
    rng: random.Random
    current: int
    _bans: dict[tuple[int, int], int]
    _notes: list[str]
    _full_search: set[int]
    #: (abstract state, action) pairs whose quick lock sent a node to a full search
    _lock_searched: set[tuple[int, int]]
    _dead_ends_met: dict[int, int]
    #: ``_to_learn``'s ranking, made on first use (its h_add cache lives with the run)
    _learning: "LearningChoice | None"
    _track: "Callable[[int, PolicyGraph], None]"

    def _on_failure(self, graph: PolicyGraph, path: tuple[int, ...],
                    failure: Failure, values) -> tuple[str, str]:
        node = graph[path[-1]]
        if failure.violated and self._locks_on_one_sample(node, failure):
            self._full_search.add(node.uid)
            return "retry", (f"{self.model.actions[node.action].label}: the quick sample's "
                             "facts would lock an action; every sample is searched first")
        if failure.violated:
            # facts of `? predicate`s become bans in every state instead of state bits,
            # so the branches that learned one still merge with those that did not
            learned = self._ban_against_fixed_facts(self._to_learn(node, failure))
            self.memory.remember(learned)
            placer = self._placer_of_blocker(graph, path, learned)
            if placer is not None:
                graph.own(node.uid).attempts += 1  # the failed node draws fresh samples too
                return self._resample(graph, placer, node)
            self._ban_no_progress(graph, path, learned)
            recalled = self._recall(node, learned, values)
            return self._update(graph, node, learned, "update", path, recalled,
                                quick=failure.quick)
        node = graph.own(node.uid)
        node.attempts += 1
        if self.rng.random() < self.options.explore_probability:
            # explore (Thm. 2's completeness): either revise an earlier choice — re-sample
            # a refined ancestor, Alg. 1's backtracking — or replan with a random action
            ancestor = self._resample_target(graph, path)
            if ancestor is not None and self.rng.random() < 0.5:
                return self._resample(graph, ancestor, node)
            return self._update(graph, node, (), "explore")
        if node.attempts < self.options.max_attempts:
            return "retry", f"{self.model.actions[node.action].label}: no usable sample"
        # nothing to learn and retries exhausted: give the action up here and replan
        # (cheap: every refinement above stays). Only when the replan finds no other way
        # does _update revise an earlier choice (Alg. 1's backtracking over refined
        # ancestors): re-sampling first thrashes where the action can never work from
        # here, e.g. an arm that cannot reach a feed (Keva 3pi: 0.29 after 198 re-samples
        # vs 1.0 in 8 s).
        self.planner.forbidden.add((node.state, node.action))
        self._bans[(node.state, node.action)] = node.uid
        self._ban_everywhere_if_hopeless(node.action, node.state)
        return self._update(graph, node, (), "ban", path)

    def _to_learn(self, node: Node, failure: Failure) -> tuple[tuple[int, bool], ...]:
        """Which sample's violated facts to write back at ``node`` (``learn_lock_free``;
        learning.py): one that locks no action, else the fewest facts."""
        options, choice = failure.alternatives, self._choice()
        if len(options) < 2 or choice is None or node.action is None:
            return failure.violated
        return choice.best(node.state, node.action, options, self._with_facts)

    def _locks_on_one_sample(self, node: Node, failure: Failure) -> bool:
        """Whether a quick failure's facts (one sample's) would lock an action: then
        the node searches every sample before anything is learned (``learn_lock_free``)."""
        choice = self._choice()
        if not failure.quick or node.uid in self._full_search or choice is None \
                or node.action is None or (node.state, node.action) in self._lock_searched:
            return False
        if not choice.locks(node.state, choice.objects_of(node.action), failure.violated):
            return False
        # once per abstract state and action: where every sample locks (a can whose
        # grasps all touch the target), searching again at each replanned node only
        # repeated the search (cluttered-20 seed 3: 255 retries in 2,400 s)
        self._lock_searched.add((node.state, node.action))
        return True

    def _choice(self) -> LearningChoice | None:
        if not self.options.learn_lock_free:
            return None
        if self._learning is None:
            cost = make_heuristic("hadd", self.planner.solve_model,
                                  self.options.solver.unit_cost)
            self._learning = LearningChoice(self.model, cost)
        return self._learning

    def _ban_no_progress(self, graph: PolicyGraph, path: tuple[int, ...], learned) -> None:
        """When the facts ``learned`` at the path's last node bring it back to the abstract
        state of an ancestor, the actions from that ancestor on made no abstract progress
        (e.g. a can picked and placed again only to block the same trajectory: the `?`
        effects of a placement promise a new pose, and the sampler found one in the way
        once more: cluttered-40 seed 3 learned that can31 blocks the same pick 17 times).
        Ban the ancestor's action in that state, so the replan takes another way; the ban
        is lifted with the ancestor when it is re-sampled."""
        state = self._with_facts(graph[path[-1]].state, learned)
        for k in range(len(path) - 2, -1, -1):
            ancestor = graph[path[k]]
            if not _nominal_step(graph, path[k], path[k + 1]):
                return  # chance brought it back (a drift, a slip): not the choice's doing
            if ancestor.state != state or ancestor.action is None:
                continue
            key = (state, ancestor.action)
            if key not in self.planner.forbidden:
                self.planner.forbidden.add(key)
                self._bans[key] = path[k]
                self._notes.append(f"{self.model.actions[ancestor.action].label}: no "
                                   "abstract progress since (its state came back), banned there")
            return

    def _with_facts(self, state: int, written) -> int:
        return with_facts(self.model, state, written)

    def _recall(self, node: Node, learned, values) -> tuple[tuple[int, bool], ...]:
        """Facts learned elsewhere that hold at ``node`` too (recall.py)."""
        if not self.options.recall_learned or node.concrete is None:
            return ()
        return self.memory.recall(_written(node.state, learned), node.concrete, values,
                                  node_uid=node.uid, attempt=node.attempts)

    def _update(self, graph: PolicyGraph, node: Node, learned, kind: str,
                path: tuple[int, ...] = (), recalled=(), quick: bool = False
                ) -> tuple[str, str]:
        """UpdateAbstraction: write the true facts at ``node`` (``learned`` there, and
        ``recalled`` from elsewhere), replan below it (new PRG node). ``quick``: the
        facts come from a quick concretization's one sample (``Failure.quick``)."""
        written = tuple(learned) + tuple(recalled)
        state = self._with_facts(node.state, written)
        forced = None
        if kind == "explore" or self.rng.random() < self.options.explore_probability:
            forced = self.planner.random_action(state, self.rng, exclude=node.action)
            kind = "explore" if forced is not None else kind
        masks = (sum(1 << f for f, v in written if v), sum(1 << f for f, v in written if not v))
        new_graph = self._replanned(graph, node.uid, state, forced,
                                    masks if any(masks) else None)
        new_graph.own(node.uid).learned = node.learned + written
        # learned facts that leave no way to the goal below this node most likely come
        # from an unlucky sample: backtrack rather than accept a dead end
        no_way = not has_way(new_graph, node.uid)
        if no_way and recalled:  # recalled facts never decide a dead end: without them
            return self._update(graph, node, learned, kind, path, quick=quick)
        if no_way and self._bans_everywhere():
            # the choice that led here (which arm took the plank) may lie above: replan
            # there without the banned actions before giving them up
            above = self._replan_above(graph, path) if not learned else None
            if above is not None:
                return above
            self._lift_bans_everywhere()
            return self._update(graph, node, learned, kind, path, quick=quick)
        # only then, and only after the same state met it a few times, is it a dead end
        accepted = no_way and self._dead_end_for_sure(new_graph, node.uid, state)
        # ... and never on the facts of a quick sample: the first sample of a domino pick
        # (the same grasp, drawn again at each retry) hit dominoes two places away and
        # "proved" a row unpickable that every other grasp picked. The node searches
        # every sample of its generators first; the dead end stands if that fails too.
        recheck = accepted and bool(learned) and quick
        if recheck:
            self._full_search.add(node.uid)
            self._notes.append("a dead end on the facts of one quick sample: the node "
                               "searches every sample before it is accepted")
        elif accepted:
            self._notes.append(f"a proven dead end accepted (met "
                               f"{self._dead_ends_met[state]} times in this abstract state)")
        failed = no_way and (not accepted or recheck)
        facts, others = fact_labels(self.model, learned), fact_labels(self.model, recalled)
        v = self._add_prg_node(new_graph, node.uid, failed, failed_preconditions=facts,
                               recalled=others,
                               concretization=sorted(map(str, (node.sigma or {}).keys())))
        if failed:
            # UpdateAbstraction cannot help: revise an earlier choice on the path first
            # (Alg. 1), then fall back to the PRG's iterative broadening
            ancestor = (self._resample_target(graph, path, insist=True)
                        if path and not recheck else None)
            if ancestor is not None:
                graph.own(node.uid).attempts += 1  # the failed node draws fresh samples too
                return self._resample(graph, ancestor, node)
            return self._backtrack(node.uid)
        self.current = v
        self._track(v, new_graph)
        detail = ", ".join(facts) or "action banned"
        return kind, detail + (f" (+{len(others)} recalled)" if others else "")


def _nominal_step(graph: PolicyGraph, parent: int, child: int) -> bool:
    """Whether ``child`` is reached from ``parent`` by one of its likeliest outcomes."""
    edges = graph[parent].edges
    top = max((e.probability for e in edges), default=0.0)
    return any(e.child == child and e.probability >= top for e in edges)


def with_facts(model: "GroundModel", state: int, written) -> int:
    """``state`` with the facts ``written`` ((fact, value) pairs), derived facts closed."""
    return model.axioms.close(_written(state, written))


def _written(state: int, written) -> int:
    """``state`` with the facts ``written`` ((fact, value) pairs) set as given."""
    for fact, value in written:
        state = state | (1 << fact) if value else state & ~(1 << fact)
    return state
