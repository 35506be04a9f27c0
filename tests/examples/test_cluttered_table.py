"""End-to-end tests of the cluttered-table example: the paper's scene (mobile base,
random target) refined on PyBullet + OMPL and on plane2d to full coverage and replayed;
the fixed-base scene with arranged blockers (learned obstructions) on PyBullet and
plane2d; determinism. Real worlds, no mocks."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from examples.cluttered_table import scene as ct
from stampc import refine_policy
from stampc.diagnostics import StampcError
from stampc.refine import RefineOptions

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "cluttered_table"
DOMAIN = EXAMPLE / "domain.stamp"
FIXED = EXAMPLE / "domain_fixed.stamp"


def _refine(problem: Path, world: str, seed: int = 0, limit: float = 90.0, domain=None):
    domain = domain or DOMAIN
    return refine_policy([domain, problem], world=world,
                         options=RefineOptions(seed=seed, time_limit=limit))


def _learned(policy: dict) -> list[tuple[str, bool]]:
    return [(item["fact"], item["value"]) for node in policy["nodes"]
            for item in node["learned"]]


@pytest.fixture(scope="module")
def pybullet_run():
    run = _refine(EXAMPLE / "problem.stamp", "pybullet")
    return run, run.to_json()


def test_problem_file_matches_generator():
    text = (EXAMPLE / "problem.stamp").read_text(encoding="utf-8")
    assert text == ct.problem_text(15, 0, "mid", "pybullet")
    text2d = (EXAMPLE / "problem2d.stamp").read_text(encoding="utf-8")
    assert text2d == ct.problem_text(15, 0, "mid", "plane2d")
    fixed2d = (EXAMPLE / "problem2d_fixed.stamp").read_text(encoding="utf-8")
    assert fixed2d == ct.problem_text(15, 0, "mid", "plane2d-fixed")
    fixed = (EXAMPLE / "problem_fixed.stamp").read_text(encoding="utf-8")
    assert fixed == ct.problem_text(15, 0, "mid", "pybullet-fixed")


def test_generator_variants_and_bad_input():
    low, high = ct.problem_text(20, 3, "low"), ct.problem_text(20, 3, "high")
    delicate = ct.delicate_cans(20, 3)
    assert len(delicate) == 4
    assert all(f"delicate_low({c})" in low and f"delicate_high({c})" in high for c in delicate)
    assert 'build_random"(n=20, seed=3)' in low
    assert 'scene:build"(n=20, seed=3)' in ct.problem_text(20, 3, "low", "pybullet-fixed")
    with pytest.raises(ValueError, match="crush variant"):
        ct.problem_text(15, 0, "extreme")
    with pytest.raises(ValueError, match="world"):
        ct.problem_text(15, 0, "mid", "mujoco")


def test_scenes_keep_every_can_and_are_seeded():
    for n in (15, 20, 25):
        scene = ct.build(n, seed=1)
        assert [o["name"] for o in scene["objects"]] == [f"can{i}" for i in range(n)]
        assert all(o["radius"] == 0.03 for o in scene["objects"])
        assert scene["meta"]["blockers"] and scene["meta"]["dropped"] == 0
    assert ct.build(15, 4) == ct.build(15, 4) != ct.build(15, 5)
    assert len(ct.build2d(15, 0)["objects"]) == 15


def test_pybullet_15_cans_full_coverage_and_replay(pybullet_run, replay_policy):
    run, policy = pybullet_run
    assert run.result.coverage == pytest.approx(1.0)
    assert run.result.goal_probability >= 0.9
    report = replay_policy(policy, "pybullet", runs=20, seed=1)
    assert report.count("unrefined") == 0
    assert report.count("failure") == 0, [r.detail for r in report.runs]
    assert report.count("success") == report.on_refined - report.count("dead_end")
    # the target (can12) is out of reach from the start base b0: the robot drives first
    actions = [a for r in report.runs for a in r.actions]
    assert any(a.startswith("move_base(b0, ") for a in actions)
    picks = [a for a in actions if a.startswith("pick(can12,")]
    assert picks and all(", b0," not in a for a in picks)


def test_picks_plan_from_the_base_they_name(pybullet_run):
    _, policy = pybullet_run
    bases = {b["name"]: b["base"] for b in policy["scene"]["robot"]["bases"]}
    checked = 0
    for node in policy["nodes"]:
        if node.get("action_name") == "pick" and node.get("sigma"):
            base = bases[node["args"]["b"]]
            for symbol in ("g", "q", "t"):
                value = node["sigma"][node["args"][symbol]]
                assert value["robot"] == "robot"
                assert value["base"]["pos"] == pytest.approx(base)
            checked += 1
    assert checked


def test_obstructed_target_cleared_and_executed_by_the_world(tmp_path):
    """Cluttered-25 seed 0: the target's side grasps are obstructed from every base the
    robot tries, so refinement learns blockers, and the policy moves one out of the way
    (placing it back on the table, or discarding it when crushed) before the pick.
    ``stampc execute`` then samples outcomes from the world, re-sweeps every trajectory
    at 10x resolution against the objects' actual poses and checks that the target is
    lifted: a place that left its can in the next pick's path was caught this way."""
    from stampc.execute.session import execute_file

    problem = ct.write_problem(tmp_path / "p25.stamp", 25, 0)
    run = _refine(problem, "pybullet")
    assert run.result.coverage == pytest.approx(1.0)
    policy = run.to_json()
    learned = [fact for fact, value in _learned(policy) if value]
    target = policy["scene"]["meta"]["target"]
    blockers = {f.split("(")[1].split(",")[0] for f in learned
                if f.startswith("collision(") and f"t_pick_{target}_" in f}
    assert blockers, "seed 0's target is obstructed: refinement must learn a blocker"
    moved = [n for n in policy["nodes"] if n.get("action_name") in ("place", "discard")]
    assert moved and {n["args"]["o"] for n in moved} <= blockers
    path = tmp_path / "policy.json"
    path.write_text(json.dumps(policy))
    report = execute_file(path, runs=20, seed=1)
    assert report.collisions == 0
    assert report.goal_failures == 0
    assert report.count("success") == 20


@pytest.fixture(scope="module")
def fixed_run():
    problem = EXAMPLE / "problem_fixed.stamp"
    return _refine(problem, "pybullet", domain=FIXED).to_json()


def test_learned_obstructions_are_real_blockers(fixed_run):
    policy = fixed_run
    learned = _learned(policy)
    assert learned, "the target starts obstructed: refinement must learn a collision"
    blockers = set(policy["scene"]["meta"]["blockers"])
    target_traj = [fact for fact, value in learned
                   if value and fact.endswith("t_pick_can0_pose_can0)")]
    assert target_traj
    named = {fact.split("(")[1].split(",")[0] for fact in target_traj}
    assert named <= blockers, f"{named} are not among the scene's blockers {blockers}"
    # and the policy moves one of them before grasping the target
    root = {n["id"]: n for n in policy["nodes"]}[policy["root"]]
    assert root["action"].split("(")[1].split(",")[0] in blockers


def test_plane2d_fixed_variant(replay_policy):
    run = _refine(EXAMPLE / "problem2d_fixed.stamp", "plane2d", domain=FIXED)
    assert run.result.coverage == pytest.approx(1.0)
    policy = run.to_json()
    named = {f.split("(")[1].split(",")[0] for f, v in _learned(policy)
             if v and f.endswith("t_pick_can0_pose_can0)")}
    assert named and named <= set(policy["scene"]["meta"]["blockers"])
    report = replay_policy(policy, "plane2d", runs=20, seed=2)
    assert report.count("failure") == 0 and report.count("unrefined") == 0


def _base_sequence_ok(actions: list[str], start: str) -> int:
    """Every pick names the base the robot stands at (tracked through move_base);
    returns how many picks were checked."""
    base, picks = start, 0
    for action in actions:
        name, args = action.split("(")[0], action.split("(")[1].rstrip(")").split(", ")
        if name == "move_base":
            assert args[0] == base, f"{action} while standing at {base}"
            base = args[1]
        elif name == "pick":
            assert args[2] == base, f"{action} while standing at {base}"
            picks += 1
    return picks


@pytest.mark.parametrize("seed", [0, 1])
def test_plane2d_mobile_scene(tmp_path, seed, replay_policy):
    """The paper's scene on plane2d (domain.stamp). In seed 1 two cans stand between the
    start base and the target: refinement learns those collisions and the policy drives
    to another base (cost 2) rather than clearing them."""
    problem = EXAMPLE / "problem2d.stamp" if seed == 0 else \
        ct.write_problem(tmp_path / "p.stamp", 15, seed, "mid", world="plane2d")
    run = _refine(problem, "plane2d")
    assert run.result.coverage == pytest.approx(1.0)
    policy = run.to_json()
    start, target = policy["scene"]["robot"]["start"], policy["scene"]["meta"]["target"]
    report = replay_policy(policy, "plane2d", runs=20, seed=2)
    assert report.count("failure") == 0 and report.count("unrefined") == 0
    assert report.count("success") == 20
    for r in report.runs:
        assert _base_sequence_ok(list(r.actions), start) >= 1
        assert any(a.startswith(f"pick({target},") for a in r.actions)
    if seed == 1:
        blocked = [f for f, v in _learned(policy) if v and f.startswith("collision(")
                   and f.endswith(f"t_pick_{target}_pose_{target}_{start})")]
        assert len(blocked) >= 1
        assert all(r.actions[0].startswith(f"move_base({start}, ") for r in report.runs)


def test_same_seed_same_policy(pybullet_run):
    _, first = pybullet_run
    second = _refine(EXAMPLE / "problem.stamp", "pybullet").to_json()
    assert json.dumps(first, sort_keys=True) == json.dumps(second, sort_keys=True)


def test_missing_scene_builder_is_located(tmp_path):
    bad = tmp_path / "problem.stamp"
    bad.write_text(ct.problem_text(15, 0).replace("scene:build_random", "scene:nope"),
                   encoding="utf-8")
    with pytest.raises(StampcError) as info:
        _refine(bad, "pybullet")
    diag = info.value.diagnostics[0]
    assert diag.code == "S104" and "nope" in diag.message
