"""Shared fixtures: location of the external PPDDL benchmark set (../shared), and
replaying a refined policy in a freshly opened world."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
BENCHMARKS = (REPO.parent / "shared" / "benchmarks" / "ppddl").resolve()


def _replay_policy(policy: dict, world_name: str, *, runs: int, seed: int,
                   world_seed: int | None = None, on_step=None):
    """Replay ``policy`` (``RefinedPolicy.to_json()``) ``runs`` times in a new
    ``world_name`` world built from its own files and scene (``world_seed``: default
    ``seed``; ``on_step`` as in ``replay``), closing the world afterwards; the
    ``ReplayReport``."""
    import stampc
    from stampc.refine.replay import replay
    from stampc.worlds.bindings import resolve_model
    from stampc.worlds.loading import open_world

    model = stampc.load_model(policy["files"])
    world = open_world(world_name, policy["scene"], seed=seed if world_seed is None else world_seed)
    try:
        executors = resolve_model(model, world.package).executors
        return replay(policy, world, executors, runs=runs, seed=seed, on_step=on_step)
    finally:
        world.close()


@pytest.fixture(scope="session")
def replay_policy():
    """``replay_policy(policy, world_name, runs=, seed=, world_seed=None, on_step=None)``."""
    return _replay_policy


@pytest.fixture(scope="session")
def ppddl_benchmarks() -> Path:
    if not BENCHMARKS.is_dir():
        pytest.skip(f"PPDDL benchmark folder not found at {BENCHMARKS} "
                    "(expected ../shared/benchmarks/ppddl beside the checkout)")
    return BENCHMARKS
