"""Parallel refinement (``--workers N``): real worker processes with their own worlds
(plane2d, and PyBullet DIRECT on a small Keva tower), compared with the serial engine;
reproducible for a fixed (seed, N); failing workers give located diagnostics."""

from __future__ import annotations

from pathlib import Path

import pytest

import stampc
from stampc.cli import main
from stampc.diagnostics import StampcError
from stampc.refine import RefineOptions
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

DATA = Path(__file__).parent / "data"
SHELF = [DATA / "shelf.stamp", DATA / "shelf5.stamp"]
REPO = Path(__file__).resolve().parents[2]


def refine(files, workers: int, world: str = "plane2d", **options):
    return stampc.refine_policy(files, world=world, workers=workers,
                                options=RefineOptions(**{"time_limit": 120, **options}))


def counters(run) -> dict:
    """The parallel record but its times: the same for the same (seed, N)."""
    return {k: v for k, v in run.result.parallel.items() if not k.endswith("_s")}


def waited(monkeypatch, files, workers: int, **options):
    """A run whose first batch with work waits for the workers to be up, so that they
    answer every batch's other tasks (by default the engine answers them until then)."""
    with monkeypatch.context() as m:
        m.setenv("STAMPC_WAIT_FOR_WORKERS", "1")
        return refine(files, workers, **options)


def test_two_workers_cover_like_one_and_repeat_exactly(monkeypatch):
    serial = refine(SHELF, 1, seed=1)
    first, second = refine(SHELF, 2, seed=1), waited(monkeypatch, SHELF, 2, seed=1)
    assert serial.result.parallel is None
    assert first.result.coverage == pytest.approx(serial.result.coverage) == pytest.approx(1.0)
    # same (seed, N): same policy, whether the engine or a worker answered a task
    assert first.to_json()["nodes"] == second.to_json()["nodes"]
    assert [e.kind for e in first.result.events] == [e.kind for e in second.result.events]
    assert counters(first) == counters(second)
    stats = second.result.parallel
    assert stats["workers"] == 2 and stats["dispatched"] > stats["batches"]  # real batches
    assert stats["integrated"] + stats["discarded"] + stats["unused"] == stats["dispatched"]
    # the worker answered tasks beside the engine's: per batch the longest < the sum
    assert 0 < stats["critical_s"] < stats["worker_busy_s"]


def test_no_worker_starts_without_two_nodes_to_run(probe):
    from stampc.api import _build_worker, _open_pool
    from stampc.refine import run_refinement
    from stampc.refine.workers import WorkerSpec

    files = probe("fine", sure=True)  # one node to refine at a time
    model = stampc.load_model(files)
    scene = load_scene(model.problem, Path(files[-1]).parent)
    world = open_world("plane2d", scene, seed=0)
    pool = _open_pool(WorkerSpec(tuple(files), "plane2d", scene, 0, _build_worker), 1, None)
    try:
        run = run_refinement(stampc.ground(model), world, resolve_model(model, world.package),
                             RefineOptions(seed=0, time_limit=60), pool=pool)
    finally:
        pool.close()
        world.close()
    assert run.result.coverage == pytest.approx(1.0)
    assert run.result.parallel["dispatched"] == run.result.parallel["batches"] > 1
    assert not pool.started


def test_pybullet_keva_tower_in_parallel(tmp_path, monkeypatch):
    from examples.keva.scene import write_problem
    problem = write_problem(tmp_path / "tower3.stamp", seed=0, structure="tower", levels=3)
    files = [REPO / "examples" / "keva" / "domain.stamp", problem]
    serial = refine(files, 1, world="pybullet", seed=0)
    first = refine(files, 2, world="pybullet", seed=0)
    second = waited(monkeypatch, files, 2, world="pybullet", seed=0)
    assert first.result.coverage == pytest.approx(serial.result.coverage) == pytest.approx(1.0)
    assert first.to_json()["nodes"] == second.to_json()["nodes"]
    assert counters(first) == counters(second) and len(counters(first)) == 7
    assert second.result.parallel["critical_s"] < second.result.parallel["worker_busy_s"]
    assert first.result.parallel["dispatched"] > first.result.parallel["batches"]


# a coin toss, then a generated token on either side: two nodes to refine at once, the
# second one in a worker process
DOMAIN = """\
domain probe
type thing
continuous type token
predicate done(x: thing)
predicate tossed
predicate heads
static predicate made(x: thing, k: token)

generator make(x: thing) -> (k: token)
    certifies made(x, k)
    binds "workerkit_{tag}:make"

action toss()
    pre  not tossed
    eff  {toss}

action finish(x: thing, k: token)
    pre  tossed
         made(x, k)
    eff  done(x)
"""

COIN = """probabilistic
             1/2 as h:
                 tossed
                 heads
             1/2 as t: tossed"""

PROBLEM = """\
problem probe1 for probe
object a: thing
goal done(a)
scene builder "stampc.worlds.plane2d.scenes:cluttered"(n=1, seed=0, blockers=0)
"""

# only worker processes misbehave (the engine's own process has no parent process)
KITS = {
    "fine": "def make(ctx, x):\n    yield (42,)\n",
    "dies": ("import multiprocessing, os\n\ndef make(ctx, x):\n"
             "    if multiprocessing.parent_process() is not None:\n        os._exit(3)\n"
             "    yield (42,)\n"),
    "raises": ("import multiprocessing\n\ndef make(ctx, x):\n"
               "    if multiprocessing.parent_process() is not None:\n"
               "        raise ValueError('not in a worker')\n    yield (42,)\n"),
}


@pytest.fixture
def probe(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(tmp_path))  # spawned workers inherit sys.path

    def make(tag: str, sure: bool = False) -> list[str]:
        """The probe with kit ``tag``; ``sure``: the toss has one outcome (no two nodes
        to refine at once)."""
        name = f"probe_{tag}{'_sure' if sure else ''}.stamp"
        (tmp_path / f"workerkit_{tag}.py").write_text(KITS[tag])
        (tmp_path / name).write_text(DOMAIN.format(tag=tag, toss="tossed" if sure else COIN))
        (tmp_path / "problem.stamp").write_text(PROBLEM)
        return [str(tmp_path / name), str(tmp_path / "problem.stamp")]

    return make


def test_probe_sends_a_node_to_a_worker(probe, monkeypatch):
    run = waited(monkeypatch, probe("fine"), 2, seed=0)
    assert run.result.coverage == pytest.approx(1.0)
    assert run.result.parallel["dispatched"] > run.result.parallel["batches"]
    # the worker answered tasks, and the batches' critical path was recorded (both are
    # sub-millisecond here, rounded to 0.1 ms in the record: comparing them is noise)
    assert run.result.parallel["worker_busy_s"] > 0 and run.result.parallel["critical_s"] > 0


def test_the_work_of_replies_is_counted_per_node(probe, monkeypatch):
    """Every reply the engine integrates, a worker's or its own, adds its concretization
    work (samples drawn + evaluations, what re-sample refusals are weighed by) to the
    node it refined."""
    from stampc.refine.parallel import ParallelEngine

    counted: list[tuple[int, int]] = []
    account = ParallelEngine._account

    def recording(self, uid, work):
        counted.append((uid, work))
        account(self, uid, work)

    monkeypatch.setattr(ParallelEngine, "_account", recording)
    run = waited(monkeypatch, probe("fine"), 2, seed=0)
    assert len(counted) >= run.result.parallel["integrated"] > 0
    # toss() has no generator and no `?` check (0); each finish draws the one sample of
    # `make` (1), on either outcome
    assert sorted(work for _, work in counted) == [0, 1, 1]
    assert len({uid for uid, _ in counted}) == 3


def test_a_worker_that_dies_is_a_located_diagnostic(probe, capsys, monkeypatch):
    files = probe("dies")
    monkeypatch.setenv("STAMPC_WAIT_FOR_WORKERS", "1")  # the batch's second task: the worker
    with pytest.raises(StampcError) as info:
        refine(files, 2, seed=0)
    assert [d.code for d in info.value.diagnostics] == ["R206"]
    assert main(["refine", *files, "--quiet", "--workers", "2"]) == 1
    err = capsys.readouterr().err
    assert "R206" in err and "exit code 3" in err and "Traceback" not in err


def test_user_code_raising_in_a_worker_is_located_at_its_binding(probe, capsys, monkeypatch):
    files = probe("raises")
    monkeypatch.setenv("STAMPC_WAIT_FOR_WORKERS", "1")
    with pytest.raises(StampcError) as info:
        refine(files, 2, seed=0)
    assert [(d.code, d.span.line) for d in info.value.diagnostics] == [("R201", 11)]
    assert main(["refine", *files, "--quiet", "--workers", "2"]) == 1
    err = capsys.readouterr().err
    assert "not in a worker" in err and "Traceback" not in err


@pytest.mark.parametrize("value", ["0", "-2", "two"])
def test_workers_below_one_is_a_usage_error(value, capsys):
    assert main(["refine", *map(str, SHELF), "--workers", value]) == 2
    assert "--workers" in capsys.readouterr().err
