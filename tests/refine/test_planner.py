"""Abstract (re)planning in the engine: timeouts vs horizon growth, incremental
re-solves after learned facts, proven dead ends, the run's time limit."""

from __future__ import annotations

import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import pytest

import stampc
from stampc.diagnostics import StampcError
from stampc.refine import Engine, RefineOptions
from stampc.refine.deadends import DeadEndProver
from stampc.refine.graph import HORIZON, PolicyGraph
from stampc.solvers import SolverOptions, solve
from stampc.solvers.space import ANY_STATE
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).resolve().parents[2]
SHELF = [DATA / "shelf.stamp", DATA / "shelf5.stamp"]


def engine_for(files, **options) -> Engine:
    model = stampc.load_model(files)
    world = open_world("plane2d", load_scene(model.problem, Path(files[-1]).parent), seed=0)
    return Engine(stampc.ground(model), world, resolve_model(model, world.package),
                  RefineOptions(**options))


def test_a_converged_solve_without_goal_in_reach_grows_the_horizon():
    engine = engine_for(SHELF, horizon=1)
    _, blocked, _ = _learned_shelf_states()  # can1 first: the goal is 3+ steps away
    graph = PolicyGraph(-1, {})
    graph.root = engine._graft_growing(graph, blocked, 0, None)
    assert engine.planner.last_converged and engine.horizon > 1
    assert any("horizon grown" in n for n in engine._notes)


def test_a_solver_timeout_leaves_the_horizon_unchanged():
    engine = engine_for(SHELF, horizon=1, solve_retries=1, timeout_plan=False)
    engine.planner.solve_work_limit = 1  # every solve is cut off at its first check
    _, blocked, _ = _learned_shelf_states()
    graph = PolicyGraph(-1, {})
    graph.root = engine._graft_growing(graph, blocked, 0, None)
    assert engine.horizon == 1
    assert engine.planner.timeouts >= 1
    notes = " | ".join(engine._notes)
    assert "solver timeout: retry with twice the budget" in notes and "horizon kept at 1" in notes


@pytest.mark.parametrize("prune", (0.0, 0.5))
def test_a_capped_solve_is_continued_as_a_partial_solve(prune):
    engine = engine_for(SHELF, horizon=8, solve_retries=1, timeout_prune_probability=prune,
                        timeout_plan=False)
    engine.planner.solve_work_limit = 1  # every solve is cut off at its first check
    engine.planner.log = []
    _, blocked, _ = _learned_shelf_states()
    engine._graft_growing(PolicyGraph(-1, {}), blocked, 0, None)
    first, retry = (entry[3].options.prune_probability for entry in engine.planner.log[:2])
    assert (first, retry) == (0.0, prune)
    assert ("left for later" in " | ".join(engine._notes)) == (prune > 0)


def test_a_timeout_prune_probability_outside_zero_one_is_refused():
    from stampc.refine import check_refine_options

    with pytest.raises(StampcError) as err:
        check_refine_options(RefineOptions(timeout_prune_probability=1.0))
    assert {d.code for d in err.value.diagnostics} == {"R003"}


def test_unplanned_tips_of_a_timed_out_solve_become_horizon_leaves():
    engine = engine_for(SHELF, horizon=8, solve_retries=0, timeout_plan=False)
    engine.planner.solve_work_limit = 1
    _, blocked, _ = _learned_shelf_states()
    graph = PolicyGraph(-1, {})
    graph.root = engine._graft_growing(graph, blocked, 0, None)
    assert not engine.planner.last_converged
    # no one-step lookahead expansions past the tips: the unplanned part waits to be
    # extended (or re-solved) when path selection gets there
    assert any(n.leaf == HORIZON for n in graph.nodes.values())


@pytest.mark.parametrize("prune", (0.0, 0.5))
def test_pruned_outcomes_are_planned_when_refinement_gets_there(prune):
    """With ``prune_probability`` 0.5 the crush (1/10) of a blocker's pick is left to a
    horizon leaf at first; the engine extends such leaves and still covers all the mass."""
    engine = engine_for(SHELF, seed=0, time_limit=60,
                        solver=SolverOptions(heuristic="hadd", prune_probability=prune))
    _, blocked, _ = _learned_shelf_states()  # can1 must be moved first: its pick may crush
    graph = PolicyGraph(-1, {})
    graph.root = engine._graft_growing(graph, blocked, 0, None)
    crushed_tips = [n for n in graph.nodes.values() if n.leaf == HORIZON]
    assert bool(crushed_tips) == (prune > 0)
    events = list(engine.run())
    assert events[-1].coverage == pytest.approx(1.0, abs=1e-9)
    assert events[-1].goal_probability == pytest.approx(1.0, abs=1e-9)
    extended = [e for e in events if e.kind == "extend"]
    assert bool(extended) == (prune > 0)


def test_a_capped_solve_refines_a_determinized_plan_first():
    """A solve cut off at its first check gets a plan on the all-outcomes determinization
    instead of retries: its path reaches the goal past the horizon, its actions are
    applicable, the outcomes off it wait as horizon leaves; the run still covers all."""
    engine = engine_for(SHELF, horizon=1, seed=0, time_limit=60)
    engine.planner.solve_work_limit = 1
    gm, blocked, _ = _learned_shelf_states()
    graph = PolicyGraph(-1, {})
    graph.root = engine._graft_growing(graph, blocked, 0, None)
    assert "plan on the all-outcomes determinization" in " | ".join(engine._notes)
    assert not any("retry" in n for n in engine._notes)
    steps = engine.planner.plan_steps
    assert steps >= 3  # can1 away, then can0: longer than the horizon of 1
    node, path = graph.nodes[graph.root], []
    while node.action is not None:  # follow the plan's outcomes (each planned child)
        assert gm.actions[node.action].precondition.holds(node.state)
        path.append(node.action)
        planned = [graph.nodes[e.child] for e in node.edges
                   if graph.nodes[e.child].leaf != HORIZON]
        assert planned, "every plan step has an outcome that stays on the plan"
        node = planned[0]
    assert node.leaf == "goal" and gm.is_goal(node.state) and len(path) == steps
    events = list(engine.run())
    assert events[-1].coverage == pytest.approx(1.0, abs=1e-9)


def _planner_at_blocked_shelf(**options):
    """A logging planner and the blocked shelf state (its solve needs 33 work units)."""
    planner = engine_for(SHELF, horizon=8, seed=0, **options).planner
    planner.log = []
    _, blocked, _ = _learned_shelf_states()
    return planner, blocked


def _work_limits(planner) -> list:
    return [entry[3].options.work_limit for entry in planner.log]


def _solve_twice(adaptive: bool, first_cap: int, second_cap: int) -> list:
    """Two solves from the blocked shelf state: the first with ``first_cap`` (16 work
    units cap it and a determinized plan answers it; it needs 33), then ``second_cap``."""
    planner, blocked = _planner_at_blocked_shelf(adaptive_solve_cap=adaptive)
    planner.solve_work_limit = first_cap
    planner.solve_from(blocked)
    shift = planner.cap_shift
    planner.solve_work_limit = second_cap
    planner.solve_from(blocked)
    return [shift, planner.cap_shift, _work_limits(planner)]


def test_a_capped_solve_answered_by_a_plan_quarters_the_next_cap():
    """... and the next solve, converging within its quarter, doubles the cap back."""
    shift, after, caps = _solve_twice(True, 16, 4000)
    assert (shift, after) == (2, 1)
    assert caps == [16, 1000]  # the second solve ran with a quarter of its cap


def test_a_fixed_solve_cap_never_shrinks():
    shift, after, caps = _solve_twice(False, 16, 4000)
    assert (shift, after) == (0, 0) and caps == [16, 4000]


def test_a_shrunk_cap_without_a_plan_continues_from_the_full_cap():
    """When neither the shrunk solve nor a plan answers, the retries double the *full*
    cap (the bet on a cheap answer lost) and the cap is whole again afterwards."""
    planner, blocked = _planner_at_blocked_shelf(solve_retries=1, timeout_plan=False)
    planner.cap_shift = 2
    planner.solve_work_limit = 16
    planner.solve_from(blocked)
    assert _work_limits(planner) == [4, 32]
    assert planner.cap_shift == 0
    assert any("adaptive cap" in note for note in planner.notes)


def test_the_determinized_plan_is_refused_when_no_outcome_sequence_reaches_the_goal():
    from stampc.solvers.determinized import with_greedy_plan
    gm, blocked, _ = _learned_shelf_states()
    # ban every pick of can1, the only way to clear can0's trajectories: no plan exists
    bans = frozenset((ANY_STATE, a.index) for a in gm.actions
                     if a.name == "pick" and a.args[0] == "can1")
    assert bans
    cut = solve(gm, SolverOptions(heuristic="hadd", forbidden=bans), init=blocked,
                stop=lambda search, node: True)
    assert with_greedy_plan(replace(cut, converged=False), 5.0) is None
    # no guidance (h = 0): the search expands nodes off the plan too
    free = solve(gm, SolverOptions(heuristic="zero"), init=blocked,
                 stop=lambda search, node: True)
    planned, steps = with_greedy_plan(replace(free, converged=False), 5.0)
    assert steps >= 3 and planned.goal_probability > 0 and not planned.converged
    # the tables stay a warm start LAO* can continue: every expanded node has a choice
    search = planned.search
    assert all(x in search.best for x in search.expanded)
    assert len(search.expanded) > steps
    again = solve(gm, SolverOptions(heuristic="zero"), init=blocked, warm=planned)
    assert again.converged and again.goal_probability == pytest.approx(1.0)


def _learned_shelf_states():
    """The shelf problem, with can1 learned to block every trajectory that picks can0 and
    then can2 learned to block them too."""
    gm = stampc.ground(stampc.load_model(SHELF))
    facts = [str(f) for f in gm.facts]
    first = sum(1 << i for i, f in enumerate(facts) if f.startswith("collision(can1, t_pick_can0"))
    second = sum(1 << i for i, f in enumerate(facts) if f.startswith("collision(can2, t_pick_can0"))
    assert first and second
    return gm, gm.init | first, second


def test_incremental_resolve_reuses_the_previous_solution():
    gm, state, learned = _learned_shelf_states()
    options = SolverOptions(heuristic="hadd")
    previous = solve(gm, options, init=state)
    scratch = solve(gm, options, init=state | learned)
    incremental = solve(gm, options, init=state | learned, warm=previous, learned=(learned, 0))
    assert incremental.converged and incremental.goal_probability == pytest.approx(1.0)
    assert scratch.goal_probability == pytest.approx(1.0)
    # the values of states the learned facts do not touch are carried over (no heuristic
    # evaluation for them), and nothing needs more expansions than from scratch
    assert incremental.search.space.transferred > 0
    assert scratch.search.space.transferred == 0
    assert incremental.states_expanded <= scratch.states_expanded
    # the previous solution's tables are copied, not modified
    assert state | learned not in previous.search.expanded


@pytest.mark.parametrize("limit", (None, 1))
def test_warm_tables_past_their_state_limit_are_dropped(limit):
    """The engine's re-solves reuse the previous tables unless they hold more states than
    ``warm_state_limit``: then the re-solve starts cold (bounded memory over long runs)
    and still finds the same policy value."""
    gm, state, learned = _learned_shelf_states()
    model = stampc.load_model(SHELF)
    world = open_world("plane2d", load_scene(model.problem, SHELF[-1].parent), seed=0)
    engine = Engine(gm, world, resolve_model(model, world.package),
                    RefineOptions(warm_state_limit=limit))
    planner = engine.planner
    first = planner.solve_from(state)
    second = planner.solve_from(state | learned, (learned, 0))
    cold = solve(gm, SolverOptions(heuristic="hadd"), init=state | learned)
    assert second.value(state | learned) == pytest.approx(cold.value(state | learned))
    assert planner.cold_starts == (1 if limit == 1 else 0)
    assert (second.search.space.transferred == 0) == (limit == 1)
    assert len(first.search.V) > 1
    assert any("warm tables dropped" in n for n in planner.notes) == (limit == 1)


def test_dead_ends_are_proven_by_reachability_not_by_the_solver():
    gm = stampc.ground(stampc.load_model(SHELF))
    prover = DeadEndProver(gm)
    assert not prover.proven(gm.init)
    crushed_target = next(i for i, f in enumerate(gm.facts) if str(f) == "crushed(can0)")
    # holding nothing, with the target crushed: it can still be picked (the goal only
    # needs holding(can0)), so this is no dead end either
    assert not prover.proven(gm.init | 1 << crushed_target)
    # with every pick of can0 blocked by a can that nothing can move (learned facts on
    # every trajectory of every can), the goal is unreachable: proven
    blocked = sum(1 << i for i, f in enumerate(gm.facts)
                  if str(f).startswith("collision(can1, ") and "t_pick_can0" in str(f))
    everything = sum(1 << i for i, f in enumerate(gm.facts) if str(f).startswith("collision("))
    assert not prover.proven(gm.init | blocked)        # can1 can be moved out of the way
    assert prover.proven(gm.init | everything)          # nothing can move at all


def test_time_limit_is_honoured_on_a_hard_instance(tmp_path):
    """A 2 s limit on the 25-can PyBullet table: the run stops within max(1 s, 2 %) of
    it and writes its partial result (exit 3 or 1 when short of coverage, never a kill)."""
    sys.path.insert(0, str(ROOT))
    from examples.cluttered_table.scene import write_problem
    problem = write_problem(tmp_path / "c25.stamp", 25, 2, "mid")
    out = tmp_path / "out"
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "stampc", "refine",
                           str(ROOT / "examples" / "cluttered_table" / "domain.stamp"),
                           str(problem), "--world", "pybullet", "--time-limit", "2", "--quiet",
                           "-o", str(out)], capture_output=True, text=True, cwd=ROOT, timeout=300)
    wall = time.perf_counter() - start
    import json
    summary = json.loads((out / "summary.json").read_text())
    # the engine's own clock: limit + max(1 s, 2 %); the process adds start-up (imports,
    # compiling, grounding, opening PyBullet) and writing the outputs
    assert summary["wall_time_s"] <= 2.0 + 1.0, summary
    assert wall < 180, wall  # no run-away (start-up alone takes seconds on a loaded machine)
    assert proc.returncode != 0 or summary["coverage"] >= 1.0 - 1e-9


def test_learning_the_way_back_to_an_ancestors_state_bans_its_action_there():
    """pick(can1) then place(can1), and the placed can blocks the same trajectory again:
    the node is back in the state where the pick was chosen. That pick is banned in that
    state (and only there); facts that make a new state ban nothing, and neither does a
    way back that went through an unlikely outcome (chance, not the choice)."""
    from stampc.refine.graph import Edge, Node
    gm, blocked, _ = _learned_shelf_states()
    facts = {str(f): i for i, f in enumerate(gm.facts)}
    action = {a.label: a.index for a in gm.actions}
    pick = action["pick(can1, pose_can1, g_pick_can1_pose_can1, q_pick_can1_pose_can1, "
                  "t_pick_can1_pose_can1)"]
    place = next(i for label, i in action.items() if label.startswith("place(can1, table"))
    again = facts[next(f for f in facts if f.startswith("collision(can1, t_pick_can0"))]
    placed = blocked & ~(1 << again)  # the re-placed can: its collisions unknown again
    holding = blocked | (1 << facts["holding(can1)"])

    def graph_with(p_held: float) -> PolicyGraph:
        ok, crushed = gm.actions[pick].outcomes(blocked)[:2]
        nodes = {0: Node(0, blocked, 0, action=pick,
                         edges=[Edge(p_held, 0, ok, 1), Edge(1 - p_held, 1, crushed, 3)]),
                 1: Node(1, holding, 1, action=place,
                         edges=[Edge(1.0, 0, gm.actions[place].outcomes(holding)[0], 2)]),
                 2: Node(2, placed, 2, action=pick), 3: Node(3, blocked, 1, leaf="horizon")}
        return PolicyGraph(0, nodes)

    engine = engine_for(SHELF)
    engine._ban_no_progress(graph_with(0.9), (0, 1, 2), ((again, False),))
    assert not engine.planner.forbidden  # a new state: progress
    engine._ban_no_progress(graph_with(0.1), (0, 1, 2), ((again, True),))
    assert not engine.planner.forbidden  # back through a 1-in-10 outcome: chance
    engine._ban_no_progress(graph_with(0.9), (0, 1, 2), ((again, True),))
    assert engine.planner.forbidden == {(blocked, pick)}
    assert engine._bans == {(blocked, pick): 0}
    assert any("no abstract progress" in n for n in engine._notes)


def test_resampling_prefers_the_ancestor_that_generated_the_failing_actions_argument():
    """pick(can1, p_place_can1_table, ...) finds no sample: the place that generated
    p_place_can1_table is re-drawn, though it was re-drawn more often than a nearer,
    unrelated ancestor; without such an ancestor the least re-drawn one is."""
    from stampc.refine.graph import Node
    engine = engine_for(SHELF)
    gm = stampc.ground(stampc.load_model(SHELF))
    action = {a.label: a.index for a in gm.actions}
    place1 = next(i for label, i in action.items() if label.startswith("place(can1, table"))
    place2 = next(i for label, i in action.items() if label.startswith("place(can2, table"))
    pick1 = next(i for label, i in action.items() if label.startswith("pick(can1, p_place_can1_table"))
    pick0 = next(i for label, i in action.items() if label.startswith("pick(can0, pose_can0"))
    nodes = {0: Node(0, gm.init, 0, action=place1, sigma={"p_place_can1_table": 1}, resamples=1),
             1: Node(1, gm.init, 1, action=place2, sigma={"p_place_can2_table": 2}),
             2: Node(2, gm.init, 2, action=pick1), 3: Node(3, gm.init, 2, action=pick0)}
    graph = PolicyGraph(0, nodes)
    assert engine._resample_target(graph, (0, 1, 2)).uid == 0
    assert engine._resample_target(graph, (0, 1, 3)).uid == 1  # nothing relevant: least
    nodes[0].resamples = engine.options.max_resamples  # exhausted: the others remain
    assert engine._resample_target(graph, (0, 1, 2)).uid == 1


def test_runs_whose_solves_hit_the_work_cap_are_reproducible():
    """A work cap (not a time cap) decides where a capped solve stops: two runs of a seed
    whose solves hit it take the same steps to the same coverage."""
    def run():
        engine = engine_for(SHELF, seed=3, solve_work_limit=20)
        steps = [(e.kind, e.detail, e.coverage, e.abstract_solves) for e in engine.run()]
        return steps, engine.planner.timeouts

    first, second = run(), run()
    assert first[1] >= 2  # the cap did bind (a determinized plan, a retry)
    assert any("solver timeout" in detail for _, detail, _, _ in first[0])
    assert first == second
    assert first[0][-1][2] == pytest.approx(1.0)


def test_the_time_guard_still_caps_a_solve_without_a_work_limit():
    engine = engine_for(SHELF, horizon=1, solve_retries=1, timeout_plan=False,
                        solve_work_limit=None)
    engine.planner.solve_time_limit = 1e-9
    _, blocked, _ = _learned_shelf_states()
    engine._graft_growing(PolicyGraph(-1, {}), blocked, 0, None)
    notes = " | ".join(engine._notes)
    assert engine.planner.timeouts >= 1 and "retry with twice the budget (2e-09 s," in notes


@pytest.mark.parametrize("bad", ({"solve_work_limit": 0}, {"solve_time_limit": 0.0}))
def test_solve_caps_below_one_unit_are_refused(bad):
    from stampc.refine import check_refine_options

    with pytest.raises(StampcError) as err:
        check_refine_options(RefineOptions(**bad))
    assert {d.code for d in err.value.diagnostics} == {"R003"}
