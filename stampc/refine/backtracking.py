"""Backtracking in the ATM-MDP engine: over refined ancestors (Alg. 1's re-sampling of
earlier generator values, with the bans it lifts) and over the PRG (iterative
broadening). A mixin of :class:`stampc.refine.engine.Engine`, kept apart so that each
file reads in one sitting; it uses the engine's PRG, planner, options and uid counter."""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Iterator

from stampc.ir.grounded import bits
from stampc.refine.fixed import needing_otherwise
from stampc.refine.graph import (GOAL, HORIZON, Node, PolicyGraph, adopt, covered_below,
                                 detach_subtree)
from stampc.solvers.space import ANY_STATE, banned_everywhere

if TYPE_CHECKING:
    import networkx as nx

    from stampc.ir.grounded import GroundModel
    from stampc.refine.options import RefineOptions
    from stampc.refine.planner import AbstractPlanner


#: PRG ancestors of the current node (beyond the root) whose policy graphs are kept for
#: backtracking; farther ones are released and skipped. Each re-sample gives its PRG node
#: an unrefined copy of the subtree below the re-drawn node (~10 MB per PRG node on
#: aircraft), so keeping every one grew aircraft seed 5 past 24 GB.
KEPT_ANCESTOR_GRAPHS = 32


def fact_labels(model: "GroundModel", facts) -> list[str]:
    """``fact=true`` / ``fact=false`` for each (fact, value) pair, as events show them."""
    return [f"{model.facts[f]}={'true' if value else 'false'}" for f, value in facts]


def has_way(graph: PolicyGraph, uid: int) -> bool:
    """Whether the policy below ``uid`` reaches a goal (or a horizon leaf, to be extended)."""
    return any(graph[u].leaf in (GOAL, HORIZON) for u in graph.reachable(uid))


class Backtracking:
    prg: "nx.DiGraph"
    planner: "AbstractPlanner"
    options: "RefineOptions"
    current: int
    breadth: int
    resamples: int
    model: "GroundModel"
    uids: "Iterator[int]"
    _bans: dict[tuple[int, int], int]
    _worked: set[int]
    _exhausted: dict[int, set[int]]
    #: facts of `? predicate`s, and the actions banned for good by their learned values
    _fixed_facts: frozenset[int]
    _fact_bans: set[int]
    _notes: list[str]
    #: PRG nodes whose graphs are kept (``_release_far_graphs``)
    _holding: set[int]
    #: per abstract state (learned facts written): replans that found only proven dead
    #: ends below it (``_dead_end_for_sure``)
    _dead_ends_met: dict[int, int]
    #: per refined ancestor: the work of the failed concretizations behind the refusals
    #: of its re-sample for its covered mass, where the failure left no way to the goal
    #: (``_affordable``)
    _refused: dict[int, int]
    #: concretization work per policy node, and the latest one's (``Engine._account``)
    _work: dict[int, int]
    _last_work: int
    #: the engine's best-policy bookkeeping (``Engine._track``)
    _track: "Callable[[int, PolicyGraph], None]"

    def _dead_end_for_sure(self, graph: PolicyGraph, uid: int, state: int) -> bool:
        """Whether the replanned policy below ``uid`` (no way to the goal) is to be
        accepted: every leaf is a dead end proven in the abstract model with everything
        learned, and the abstract state ``state`` has met that
        ``accept_dead_end_after`` times (earlier, re-sampling ancestors may still change
        the concrete state that made the facts true)."""
        after = self.options.accept_dead_end_after
        if not after or not all(graph[u].proven for u in graph.reachable(uid)
                                if graph[u].is_leaf):
            return False
        met = self._dead_ends_met[state] = self._dead_ends_met.get(state, 0) + 1
        return met >= after

    def _resample_target(self, graph: PolicyGraph, path: tuple[int, ...],
                         insist: bool = False) -> Node | None:
        """The refined ancestor (with generated values) to re-sample: among those that
        generated a value the failing action takes as an argument (the placement of the
        can it must pick: cluttered-40 seed 3 re-drew unrelated ancestors 460 times while
        the placed can stayed out of reach), else (with ``achievers_first``) among the
        achievers of its preconditions (``_achievers``), else among all, the one
        re-sampled least often so far, the nearest among equals: which of them blocks
        the failing action is not known, so the re-draws are spread over them instead
        of exhausting the nearest one first (tried: nearest-first did worse on Keva
        tower-12 seed 2, coverage 0.24 vs 0.99 in 240-300 s). ``insist``: see
        ``_affordable``."""
        candidates = [graph[u] for u in reversed(path[:-1])
                      if graph[u].refined and graph[u].sigma
                      and graph[u].resamples < self.options.max_resamples]
        failing = graph[path[-1]].action
        uses = set(self.model.actions[failing].args) if failing is not None else set()
        relevant = [n for n in candidates if uses & set(map(str, n.sigma))]
        if not relevant and self.options.achievers_first:
            achievers = {n.uid for n in self._achievers(graph, path)}
            relevant = [n for n in candidates if n.uid in achievers]
        pool = self._affordable(graph, path, relevant or candidates, insist)
        return min(pool, key=lambda n: n.resamples) if pool else None

    def _affordable(self, graph: PolicyGraph, path: tuple[int, ...],
                    nodes: list[Node], insist: bool = False) -> list[Node]:
        """Those of ``nodes`` (ancestors on ``path``) whose re-sample throws away no more
        covered mass than ``max_resample_loss`` times the failing path's probability
        (what its refinement could add at most). A re-sample discards every refinement
        below the node: cluttered-25 seed 5 re-drew a can's placement for a re-pick of
        it below, and its working graph fell from 0.9087 to 0.5337 covered and had
        regained only 0.668 400 s later.

        ``insist``: the failure left no way to the goal below its node, so a refusal
        sends the PRG back a step, where the same path is selected again. Refusing goes
        on while the work of the failed concretizations behind an ancestor's refusals so
        far (each refusal adds the latest concretization's work: the failing node's, or
        where its action was given up without one, the step before's) is less than the
        work its re-sample would throw away (the concretization work of the refined nodes
        below it, itself included); then it is granted (ski rental: at most about twice
        the cheaper of the two). Without this, aircraft seed 4 went back to the same PRG
        node 139 times in 60 s for a 0.00017 path below a flight with 0.018 covered under
        it, cheap to refine again. A fixed count of 3 refusals left cluttered-20 seed 3
        and cluttered-25 seed 5, whose placements carry costly subtrees, at 0.9981 and
        0.8965; counting all the work since the first refusal granted at once where a
        refusal came back after other work (0.9987 and 0.8965); this rent solved the
        first and raised the second to 0.9706."""
        limit = self.options.max_resample_loss
        if limit is None or not nodes:
            return nodes
        reach, prob = {}, 1.0
        for k, uid in enumerate(path):
            reach[uid] = prob
            if k + 1 < len(path):
                prob *= next((e.probability for e in graph[uid].edges
                              if e.child == path[k + 1]), 0.0)
        lost = {n.uid: reach[n.uid] * covered_below(graph, n.uid) for n in nodes}
        kept = [n for n in nodes if lost[n.uid] <= limit * prob + 1e-12
                or (insist and self._rent_paid(graph, n.uid))]
        if insist:
            for n in nodes:
                if n not in kept:
                    self._refused[n.uid] = self._refused.get(n.uid, 0) + self._last_work
        if not kept:
            nearest = max(nodes, key=lambda n: path.index(n.uid))
            self._notes.append(f"{self.model.actions[nearest.action].label}: not re-sampled "
                               f"({lost[nearest.uid]:.4g} covered below it, the failing "
                               f"path {prob:.4g})")
        return kept

    def _rent_paid(self, graph: PolicyGraph, uid: int) -> bool:
        """Whether the failed work behind ``uid``'s refusals so far (``_affordable``) is
        at least the work its re-sample would throw away."""
        paid = self._refused.get(uid)
        if paid is None:
            return False
        below = sum(self._work.get(u, 0) for u in graph.reachable(uid) if graph[u].refined)
        return paid >= below

    def _achievers(self, graph: PolicyGraph, path: tuple[int, ...]) -> list[Node]:
        """For each precondition fact of the path's failing action that some step of the
        path made true (added, or deleted for a negated one), the nearest such step: the
        choices the failing action stands on (the pick that gave the arm its grasp, the
        put-downs of the planks it rests on, the move that took a blocker out of the
        way). Re-drawing any ancestor instead walked down a 24-level Keva tower (seeds 2
        and 9), re-drawing put-downs up to 40 planks below the failing one, each throwing
        away every refinement above it."""
        failing = graph[path[-1]].action
        if failing is None:
            return []
        condition = self.model.actions[failing].precondition
        pos, neg = condition.pos, condition.neg
        found = []
        for k in range(len(path) - 2, -1, -1):
            if not pos and not neg:
                break
            node = graph[path[k]]
            step = next((e.successor for e in node.edges if e.child == path[k + 1]), None)
            if step is None:
                continue
            made_true, made_false = pos & step.add, neg & step.delete
            if made_true or made_false:
                found.append(node)
                pos, neg = pos & ~made_true, neg & ~made_false
        return found

    def _placer_of_blocker(self, graph: PolicyGraph, path: tuple[int, ...],
                           learned) -> Node | None:
        """The failing node's nearest refined ancestor with generated values, when it put
        an object a fact learned true names at a value it sampled itself
        (``place(can0, table, p, ...)`` adding ``at(can0, p)``, when ``collision(can0,
        t)`` is learned just below it) and may still be re-sampled. Its choice is what
        failed, not the abstraction: writing the obstruction into the abstract state
        instead makes the replan work around a can the policy just put in the way
        (cluttered-25 seed 5: a 0.45 branch replanned through three more blockers and two
        base moves, unrefined after 2,400 s). Only the nearest such ancestor: re-drawing
        farther placements (any on the path) threw away the refinements between them
        and the failure (docs/refine.md, "Placements in the way")."""
        if not self.options.resample_placers:
            return None
        named = {a for f, value in learned if value for a in self.model.facts[f].args}
        node = next((graph[u] for u in reversed(path[:-1])
                     if graph[u].refined and graph[u].sigma), None)
        if node is None or node.action is None or node.resamples >= self.options.max_resamples:
            return None
        sampled = set(map(str, node.sigma))
        for outcome in self.model.actions[node.action].outcomes(node.state):
            for fact in bits(outcome.add):
                args = set(self.model.facts[fact].args)
                if args & named and args & sampled:
                    # ... and only if re-drawing it is worth what it throws away
                    return node if self._affordable(graph, path, [node]) else None
        return None

    def _resample(self, graph: PolicyGraph, ancestor: Node, failed: Node) -> tuple[str, str]:
        """Backtrack: draw fresh generator values for ``ancestor``. Every refinement below
        it is invalidated (its subtree becomes an unrefined copy); a new PRG node records
        the step."""
        self._lift_bans(graph.reachable(ancestor.uid))
        self._refused.pop(ancestor.uid, None)
        new_graph = graph.copy()
        target = new_graph.own(ancestor.uid)
        new_graph.touch(target.uid)
        target.sigma = None
        target.attempts += 1  # the next concretization draws from fresh generator streams
        target.resamples += 1
        detach_subtree(new_graph, target.uid, self.uids)
        self.resamples += 1
        v = self._add_prg_node(new_graph, ancestor.uid, kind="resample",
                               failed_node=failed.uid, failed_preconditions=[],
                               concretization=sorted(map(str, (ancestor.sigma or {}).keys())))
        self.current = v
        self._track(v, new_graph)
        label = self.model.actions[ancestor.action].label
        return "resample", (f"{label}: new generator values (no refinement of "
                            f"{self.model.actions[failed.action].label} below it)")

    def _replanned(self, graph: PolicyGraph, uid: int, state: int,
                   forced: int | None = None,
                   learned: tuple[int, int] | None = None) -> PolicyGraph:
        """A copy of ``graph`` whose node ``uid`` gets the policy planned from ``state``
        (``forced``: its first action; ``learned``: masks for the incremental re-solve)."""
        new_graph = graph.copy()
        target = new_graph[uid]
        sub = self._graft_growing(new_graph, state, target.depth, forced, learned)
        adopt(new_graph, target, new_graph[sub])
        new_graph.prune()
        return new_graph

    def _add_prg_node(self, graph: PolicyGraph, node: int, failed: bool = False,
                      **edge) -> int:
        """A new PRG node holding ``graph``, a child of the current one; the edge records
        the policy node the step was at and what it did (``edge``). A failed one is
        never worked on: its graph is not kept (the node stays, as a record)."""
        v = self.prg.number_of_nodes()
        self.prg.add_node(v, graph=None if failed else graph, parent=self.current,
                          failed=failed)
        self.prg.add_edge(self.current, v, node=node, **edge)
        if not failed:
            self._release_far_graphs(v)
        return v

    def _release_far_graphs(self, newest: int) -> None:
        """Keep the graphs of the root, of ``newest`` and of its nearest
        ``KEPT_ANCESTOR_GRAPHS`` PRG ancestors only: backtracking can go back to no other
        PRG node (it climbs from the current one), and it skips released ones."""
        keep, u = {0, newest}, self.prg.nodes[newest]["parent"]
        while u is not None and len(keep) < KEPT_ANCESTOR_GRAPHS + 2:
            keep.add(u)
            u = self.prg.nodes[u]["parent"]
        for u in self._holding - keep:
            self.prg.nodes[u]["graph"] = None
        self._holding = keep

    def _lift_bans(self, invalidated) -> None:
        """Bans recorded at nodes whose concrete state a re-sample invalidates came from
        the old generator values: the action may work from the new ones."""
        gone = set(invalidated)
        for key, uid in list(self._bans.items()):
            if uid in gone:
                self.planner.forbidden.discard(key)
                del self._bans[key]

    def _ban_everywhere_if_hopeless(self, action: int, state: int) -> None:
        """An action that exhausted its attempts in ``ban_everywhere_after`` abstract
        states and never worked anywhere is banned in every state. A per-state ban only
        moves the policy to a sibling state (the other feed, one more plank aside) where
        the same action is chosen and fails again: Keva tower-12 seed 2 spent 571 tries
        on one arm's put-down that its grips could never reach, over 240 s."""
        limit = self.options.ban_everywhere_after
        if not limit or action in self._worked:
            return
        states = self._exhausted.setdefault(action, set())
        states.add(state)
        if len(states) >= limit and (ANY_STATE, action) not in self.planner.forbidden:
            self.planner.forbidden.add((ANY_STATE, action))
            self._notes.append(f"{self.model.actions[action].label}: banned in every state "
                               f"(no usable sample in {len(states)} states, never refined)")

    def _ban_against_fixed_facts(self, learned) -> tuple[tuple[int, bool], ...]:
        """A learned fact of a ``? predicate`` holds everywhere (fixed.py): ban, in every
        state and for good, the actions that need its other value. Returns the other
        learned facts (those an abstract state records)."""
        facts = [(f, v) for f, v in learned if f in self._fixed_facts]
        if not facts:
            return tuple(learned)
        banned = needing_otherwise(self.model, facts) - self._fact_bans
        if banned:  # a fact learned again (a worker's reply) bans nothing new
            self._fact_bans |= banned
            self.planner.forbidden.update((ANY_STATE, a) for a in banned)
            learned_now = ", ".join(fact_labels(self.model, facts))
            self._notes.append(f"{learned_now} holds everywhere: {len(banned)} action(s) "
                               "banned in every state")
        return tuple((f, v) for f, v in learned if f not in self._fixed_facts)

    def _bans_everywhere(self) -> list[int]:
        """The actions banned in every state (the planner's ``(ANY_STATE, a)`` pairs),
        except those a learned fixed fact rules out (never lifted)."""
        return [a for a in banned_everywhere(self.planner.forbidden) if a not in self._fact_bans]

    def _replan_above(self, graph: PolicyGraph, path: tuple[int, ...]) -> tuple[str, str] | None:
        """With actions banned in every state, replan at the nearest of the last
        ``replan_above`` ancestors on ``path`` from which the goal is still reachable;
        its subtree is replaced (new PRG node). None if none of them has a way."""
        for uid in list(reversed(path[:-1]))[:self.options.replan_above]:
            new_graph = self._replanned(graph, uid, graph[uid].state)
            if not has_way(new_graph, uid):
                continue
            self._lift_bans(graph.reachable(uid))  # they came from concrete states now gone
            v = self._add_prg_node(new_graph, uid, kind="replan", failed_preconditions=[],
                                   concretization=[])
            self.current = v
            self._track(v, new_graph)
            before = graph[uid].action
            label = self.model.actions[before].label if before is not None else "a leaf"
            return "update", f"replanned at {label} without the actions banned everywhere"
        return None

    def _lift_bans_everywhere(self) -> None:
        """Lift every ban in every state (a replan found no way to the goal without the
        banned actions). Each needs as many fresh failures to return. (Lifting only the
        newest and replanning did worse on Keva tower-12 seed 2: 0.107 vs 0.769.)"""
        lifted = self._bans_everywhere()
        for action in lifted:
            self.planner.forbidden.discard((ANY_STATE, action))
            self._exhausted.pop(action, None)
        self._notes.append(f"{len(lifted)} ban(s) in every state lifted (no way to the goal "
                           "without them)")

    def _backtrack(self, uid: int | None) -> tuple[str, str]:
        """Iterative broadening: return to the deepest PRG ancestor with spare breadth
        (never to one found exhausted)."""
        u = self.current
        while u is not None:
            graph = self.prg.nodes[u]["graph"]
            if graph is None:  # released (too far up to keep)
                u = self.prg.nodes[u]["parent"]
                continue
            if uid is not None and uid in graph.nodes:
                graph.own(uid).attempts += 1  # next visit draws fresh samples
            if self.prg.out_degree(u) < self.breadth and not self.prg.nodes[u].get("exhausted"):
                self.current = u
                return "backtrack", f"to PRG node {u}"
            u = self.prg.nodes[u]["parent"]
        self.breadth += self.options.breadth_step
        self.current = 0
        return "backtrack", f"breadth {self.breadth}"

