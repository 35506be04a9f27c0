"""Backtracking over refined ancestors (Alg. 1): a first placement that blocks the second."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

import stampc
from stampc.refine import Engine, RefineOptions
from stampc.refine.graph import coverage
from stampc.refine.options import check_refine_options
from stampc.refine.replay import replay
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

DATA = Path(__file__).parent / "data"
PACK = [DATA / "pack.stamp", DATA / "pack2.stamp"]
# seed 0: the first placement of can0 lands in the middle of the box, where can1 no
# longer fits (checked below: without re-sampling the run gets nowhere)
OPTIONS = dict(seed=0, explore_probability=0.0)


def run(**options):
    model = stampc.load_model(PACK)
    world = open_world("plane2d", load_scene(model.problem, DATA), seed=0)
    engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                    RefineOptions(**{**OPTIONS, **options}))
    try:
        events = list(engine.run())
    finally:
        world.close()
    return engine, events


def store_engine(**options):
    """An engine on the store domain (plane2d), not yet started, and its world."""
    model = stampc.load_model([DATA / "store.stamp", DATA / "store1.stamp"])
    world = open_world("plane2d", load_scene(model.problem, DATA), seed=0)
    return Engine(stampc.ground(model), world, resolve_model(model, world.package),
                  RefineOptions(**{**OPTIONS, **options})), world


def test_without_resampling_the_blocked_packing_is_never_refined():
    engine, _ = run(max_resamples=0, time_limit=3)
    assert engine.result().coverage == 0.0 and engine.resamples == 0


def test_resampling_an_ancestor_refines_the_blocked_packing():
    engine, events = run(time_limit=60)
    result = engine.result()
    assert result.coverage == pytest.approx(1.0, abs=1e-9) and result.resamples >= 1
    assert any(e.kind == "resample" for e in events)
    # the PRG records each backtracking step on an edge of its own kind
    kinds = [d.get("kind") for _, _, d in engine.prg.edges(data=True)]
    assert kinds.count("resample") == result.resamples
    # the second store was banned (no usable sample) before each re-sample; a ban comes
    # from the old generator values, so the re-sample that invalidated it lifted it
    assert not engine.planner.forbidden
    # every refined node lies on the final policy; its replay stores both cans
    model = stampc.load_model(PACK)
    world = open_world("plane2d", load_scene(model.problem, DATA), seed=0)
    try:
        policy = stampc.refine.RefinedPolicy(result, engine.best_graph, engine.model,
                                             engine.initial_values).to_json()
        report = replay(policy, world, resolve_model(model, world.package).executors,
                        runs=5, seed=1)
    finally:
        world.close()
    assert report.count("success") == 5


def test_a_resample_invalidates_the_subtree_below_the_ancestor():
    model = stampc.load_model(PACK)
    world = open_world("plane2d", load_scene(model.problem, DATA), seed=0)
    engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                    RefineOptions(**OPTIONS, time_limit=60))
    try:
        for event in engine.run():
            if event.kind == "resample":
                break
        # the new PRG node: the ancestor lost its values, and so did everything below it
        # (the children's concrete states came from those values)
        v = engine.current
        parent = engine.prg.nodes[v]["parent"]
        edge = engine.prg.edges[parent, v]
        graph = engine.prg.nodes[v]["graph"]
        anc = graph[edge["node"]]
        assert edge["kind"] == "resample" and not anc.refined and anc.resamples == 1
        below = graph.reachable(anc.uid)[1:]
        assert below and all(not graph[u].refined and graph[u].concrete is None for u in below)
        # the PRG node it came from still holds the refined values
        before = engine.prg.nodes[parent]["graph"]
        assert before[anc.uid].refined
    finally:
        world.close()



def test_an_action_that_can_never_work_is_banned_before_any_ancestor_is_resampled():
    """The cheap shelf is too small for any can: re-sampling the pick above it cannot
    help, so the engine bans store_cheap there and replans (the tray) without touching
    the refined pick — re-sampling is kept for when the replan finds no other way."""
    model = stampc.load_model([DATA / "store.stamp", DATA / "store1.stamp"])
    world = open_world("plane2d", load_scene(model.problem, DATA), seed=0)
    engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                    RefineOptions(**OPTIONS, update_probability=0.0, time_limit=60))
    try:
        kinds = [e.kind for e in engine.run()]
    finally:
        world.close()
    assert engine.result().coverage == pytest.approx(1.0, abs=1e-9)
    assert "ban" in kinds and engine.resamples == 0


def test_a_spent_prg_node_backtracks_instead_of_ending_the_run():
    """A PRG node with nothing left to select (here: every leaf given up; in Keva, merges
    after an explore step that closed a loop with no way out) is marked exhausted and
    the iterative broadening goes on from its ancestors; only the root's exhaustion
    stops the run."""
    from stampc.refine.graph import DEAD_END

    engine, world = store_engine(time_limit=60)
    try:
        events = engine.run()
        assert next(events).kind == "start"
        spent = engine.prg.nodes[0]["graph"].copy()
        for uid in [u for u, n in spent.nodes.items() if n.is_leaf]:
            node = spent.own(uid)
            node.leaf, node.given_up = DEAD_END, True
        engine.prg.add_node(1, graph=spent, parent=0, failed=False)
        engine.prg.add_edge(0, 1, node=spent.root, failed_preconditions=[])
        engine.current = 1
        kind, _ = engine.step()
        assert kind == "backtrack" and engine.current == 0
        assert engine.prg.nodes[1]["exhausted"]
        # the run then goes on from the root and still refines the store
        for event in events:
            pass
        assert engine.result().coverage == pytest.approx(1.0, abs=1e-9)
    finally:
        world.close()


def test_explore_may_pick_an_ancestor_resample_as_well_as_a_random_action():
    """With explore always on, failures at the second store are answered both ways the
    explore step has: re-sampling a refined ancestor (Alg. 1's backtracking) and a
    replan that forces a random action. Seeded: the same seed gives the same choices."""
    kinds = []
    for _ in range(2):
        engine, events = run(explore_probability=1.0, max_attempts=10, time_limit=20)
        kinds.append([e.kind for e in events])
    assert kinds[0] == kinds[1]
    assert "resample" in kinds[0] and "explore" in kinds[0]


def test_a_merge_that_closes_a_loop_with_no_way_out_is_refused_and_banned():
    """If the outcomes of a refined action would merge into a node from which no leaf is
    reachable (a hand-over that brings the state back to an ancestor's, on Keva), the
    refinement is not committed: the node keeps its old children and no sigma, the
    action is banned in its abstract state and the SSP replanned. The merge is forced
    here: every outcome's concrete state is taken to be the root's."""
    engine, world = store_engine(time_limit=60)
    try:
        events = engine.run()
        assert next(events).kind == "start"
        graph = engine.prg.nodes[engine.current]["graph"]
        root = graph[graph.root]
        children = [e.child for e in root.edges]
        assert children and root.uid not in children
        engine._merge_target = lambda graph, state, key: root.uid  # every outcome = root
        kind, _ = engine._refine(graph, (root.uid,))
        assert any("close a loop with no way out" in note for note in engine._notes)
        assert root.sigma is None and [e.child for e in root.edges] == children
        assert (root.state, root.action) in engine.planner.forbidden
        assert kind != "refined"
    finally:
        world.close()


def test_a_proven_dead_end_is_accepted_once_its_state_has_met_it_k_times():
    """Learned facts that leave only proven dead ends below a node are first taken for an
    unlucky sample (ancestors re-sampled); the K-th time the same abstract state meets
    them the dead end is accepted. An unproven leaf (the solver gave up) never is."""
    from stampc.refine.graph import DEAD_END, Edge, Node, PolicyGraph

    def graph(proven: bool) -> PolicyGraph:
        root = Node(1, 7, 0, action=0, edges=[Edge(1.0, 0, None, 2)])
        return PolicyGraph(1, {1: root, 2: Node(2, 8, 1, leaf=DEAD_END, proven=proven)})

    engine, world = store_engine(accept_dead_end_after=3)
    try:
        verdicts = [engine._dead_end_for_sure(graph(True), 1, state=42) for _ in range(4)]
        assert verdicts == [False, False, True, True]
        assert not engine._dead_end_for_sure(graph(True), 1, state=43)  # counted per state
        assert not any(engine._dead_end_for_sure(graph(False), 1, state=44) for _ in range(5))
    finally:
        world.close()
    never, world = store_engine(accept_dead_end_after=0)
    try:
        assert not any(never._dead_end_for_sure(graph(True), 1, state=42) for _ in range(5))
    finally:
        world.close()


SHELF = [DATA / "shelf.stamp", DATA / "shelf5.stamp"]


def shelf_run(**options):
    model = stampc.load_model(SHELF)
    world = open_world("plane2d", load_scene(model.problem, DATA), seed=0)
    engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                    RefineOptions(**{"seed": 7, "update_probability": 1.0, "time_limit": 60,
                                     **options}))
    try:
        events = list(engine.run())
    finally:
        world.close()
    return engine, events


def _obstructions_by_placed_can1(events) -> list[str]:
    """Updates that learn can1 in the way once can1 has been placed (refined)."""
    placed = next(i for i, e in enumerate(events)
                  if e.kind == "refined" and e.detail.startswith("place(can1"))
    return [e.detail for e in events[placed:]
            if e.kind == "update" and "collision(can1," in e.detail]


def test_a_can_placed_in_the_way_is_placed_again_before_anything_is_learned():
    """Shelf seed 7 (UpdateAbstraction mode): can1's first placement blocks the next
    pick's trajectory. The engine re-draws that placement (a resample of the place,
    whose learned obstruction names the can it placed) instead of writing the
    obstruction into the abstract state and replanning around the can."""
    engine, events = shelf_run()
    resampled = [e for e in events if e.kind == "resample"]
    assert resampled and all(e.detail.startswith("place(can1") for e in resampled)
    assert not _obstructions_by_placed_can1(events)
    assert engine.result().coverage == pytest.approx(1.0, abs=1e-9)
    # without the rule the same seed learns the obstruction and replans around it: one
    # more abstract solve, a pick of can1 from where it was placed
    plain, plain_events = shelf_run(resample_placers=False)
    assert not [e for e in plain_events if e.kind == "resample"]
    assert _obstructions_by_placed_can1(plain_events)
    assert plain.planner.solves > engine.planner.solves
    assert plain.result().coverage == pytest.approx(1.0, abs=1e-9)


def test_placements_are_re_drawn_at_most_max_resamples_times():
    engine, events = shelf_run(max_resamples=0)
    assert not [e for e in events if e.kind == "resample"] and engine.resamples == 0
    assert engine.result().coverage == pytest.approx(1.0, abs=1e-9)


def _refined_path_through(graph, model, label_prefix: str) -> tuple[int, ...]:
    """A root-to-leaf path of ``graph`` with a refined node whose action starts so."""
    def paths(uid, acc):
        acc = acc + (uid,)
        if not graph[uid].edges:
            yield acc
        for edge in graph[uid].edges:
            yield from paths(edge.child, acc)
    return next(p for p in paths(graph.root, ()) if any(
        graph[u].refined and graph[u].action is not None
        and model.actions[graph[u].action].label.startswith(label_prefix) for u in p))


def _fact(model, text: str) -> int:
    return next(i for i, f in enumerate(model.facts) if str(f) == text)


def test_only_the_nearest_refined_ancestor_is_taken_for_the_placer():
    """On a refined path pick(can1), place(can1), pick(can0): an obstruction of can0's
    pick by can1 names the nearest ancestor (the place); one by can2 (never placed on
    this path) names none; nor does can1's obstruction of a later step once another
    sampled action stands between; nor a fact learned false."""
    engine, _ = shelf_run()
    graph, model = engine.best_graph, engine.model
    path = _refined_path_through(graph, model, "place(can1")
    place = next(u for u in path if graph[u].action is not None
                 and model.actions[graph[u].action].label.startswith("place(can1"))
    pick = path[path.index(place) + 1]
    upto = path[:path.index(pick) + 1]
    by_can1 = _fact(model, "collision(can1, t_pick_can0_pose_can0)")
    by_can2 = _fact(model, "collision(can2, t_pick_can0_pose_can0)")
    assert engine._placer_of_blocker(graph, upto, [(by_can1, True)]) is graph[place]
    assert engine._placer_of_blocker(graph, upto, [(by_can2, True)]) is None
    assert engine._placer_of_blocker(graph, upto, [(by_can1, False)]) is None
    assert engine._placer_of_blocker(graph, upto[:-1] + (pick, pick), [(by_can1, True)]) is None
    # with a limit on what a re-sample may discard: the place has covered mass below it
    # (the policy is fully refined), so a limit of 0 refuses it
    assert _coverage_from(graph, place) > 0
    engine.options = replace(engine.options, max_resample_loss=0.0)
    assert engine._placer_of_blocker(graph, upto, [(by_can1, True)]) is None


def test_the_achievers_of_a_failing_action_are_the_nearest_steps_that_made_its_preconditions_true():
    """On a refined path pick(can2), discard(can2), pick(can1), place(can1), pick(can0):
    pick(can0) stands on the place (it made `handempty` true and, optimistically, can1
    out of the pick's way) and on the discard (can2 out of the way); pick(can1) and
    pick(can2) made some of those true too, but a nearer step did it again after them.
    The place stands on pick(can1) (`holding(can1)`). With ``achievers_first``, a
    re-sample for a failing pick(can0) is taken among its achievers before any other
    ancestor."""
    engine, _ = shelf_run(achievers_first=True, max_resample_loss=None)
    graph, model = engine.best_graph, engine.model
    path = _refined_path_through(graph, model, "place(can1")
    label = {u: model.actions[graph[u].action].label for u in path if graph[u].action is not None}
    place = next(u for u in path if label.get(u, "").startswith("place(can1"))
    pick1, pick0 = path[path.index(place) - 1], path[path.index(place) + 1]
    assert label[pick1].startswith("pick(can1") and label[pick0].startswith("pick(can0")
    discard = next(u for u in path if label.get(u, "").startswith("discard(can2"))
    upto_pick0 = path[:path.index(pick0) + 1]
    assert engine._achievers(graph, upto_pick0) == [graph[place], graph[discard]]
    assert graph[pick1] in engine._achievers(graph, path[:path.index(place) + 1])
    target = engine._resample_target(graph, upto_pick0)
    assert target in (graph[place], graph[discard])
    assert min(graph[place].resamples, graph[discard].resamples) == target.resamples



def _reach(graph, path, uid) -> float:
    """The probability of ``path``'s prefix up to ``uid``."""
    prob = 1.0
    for parent, child in zip(path, path[1:]):
        if parent == uid:
            break
        prob *= next(e.probability for e in graph[parent].edges if e.child == child)
    return prob


def _coverage_from(graph, uid) -> float:
    """The coverage of ``graph`` re-rooted at ``uid`` (a from-scratch sweep on a copy,
    not the engine's tracked masses)."""
    rooted = graph.copy(keep_values=False)
    rooted.root = uid
    return coverage(rooted)


def _refined_below(graph, uid) -> set[int]:
    """The refined nodes reachable from ``uid`` (itself included), found by a plain
    breadth-first walk of the edges."""
    seen, todo = {uid}, [uid]
    while todo:
        for edge in graph[todo.pop()].edges:
            if edge.child not in seen:
                seen.add(edge.child)
                todo.append(edge.child)
    return {u for u in seen if graph[u].refined}


def test_an_ancestor_is_re_sampled_only_while_its_covered_mass_is_worth_the_failing_path():
    """On the fully refined shelf policy, a failing pick(can0) below place(can1) and
    discard(can2): re-drawing the discard would throw away more covered mass than the
    pick's path could ever add, so the (nearer, cheaper) place is taken, although the
    discard was re-drawn less often; without the limit the discard is taken."""
    engine, _ = shelf_run(achievers_first=True, max_resample_loss=1.0)
    graph, model = engine.best_graph, engine.model
    path = _refined_path_through(graph, model, "place(can1")
    label = {u: model.actions[graph[u].action].label for u in path if graph[u].action is not None}
    place = next(u for u in path if label.get(u, "").startswith("place(can1"))
    discard = next(u for u in path if label.get(u, "").startswith("discard(can2"))
    upto_pick0 = path[:path.index(place) + 2]
    gain = _reach(graph, upto_pick0, upto_pick0[-1])
    lost_place = _reach(graph, upto_pick0, place) * _coverage_from(graph, place)
    lost_discard = _reach(graph, upto_pick0, discard) * _coverage_from(graph, discard)
    assert lost_place <= gain < lost_discard
    assert graph[discard].resamples < graph[place].resamples
    assert engine._resample_target(graph, upto_pick0) is graph[place]
    engine._notes.clear()
    assert engine._affordable(graph, upto_pick0, [graph[discard]]) == []
    assert len(engine._notes) == 1 and engine._notes[0].startswith(label[discard])
    assert "not re-sampled" in engine._notes[0]
    # where the failure left no way below it, a refusal repeats on the same path: once
    # the work of the failed concretizations behind its refusals reaches the
    # concretization work of the refined nodes below the discard (itself included),
    # its re-sample is granted
    assert sum(engine._work.values()) == engine.concretizer.work
    below = sum(engine._work.get(u, 0) for u in _refined_below(graph, discard))
    assert 0 < below < engine.concretizer.work
    engine._last_work = below - 1
    assert engine._affordable(graph, upto_pick0, [graph[discard]], insist=True) == []
    engine._last_work = 1
    assert engine._affordable(graph, upto_pick0, [graph[discard]], insist=True) == []
    assert engine._affordable(graph, upto_pick0, [graph[discard]], insist=True) == [graph[discard]]
    engine.options = replace(engine.options, max_resample_loss=None)
    assert engine._resample_target(graph, upto_pick0) is graph[discard]


@pytest.mark.parametrize("loss", [-0.5, float("nan")])
def test_a_negative_or_nan_resample_loss_limit_is_refused(loss):
    with pytest.raises(stampc.StampcError) as info:
        check_refine_options(RefineOptions(max_resample_loss=loss))
    assert [d.code for d in info.value.diagnostics] == ["R003"]
