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

DATA = Path(__file__).parent / "data"
SHELF = [DATA / "shelf.stamp", DATA / "shelf5.stamp"]
REPO = Path(__file__).resolve().parents[2]


def refine(files, workers: int, world: str = "plane2d", **options):
    return stampc.refine_policy(files, world=world, workers=workers,
                                options=RefineOptions(**{"time_limit": 120, **options}))


def test_two_workers_cover_like_one_and_repeat_exactly():
    serial = refine(SHELF, 1, seed=1)
    first, second = refine(SHELF, 2, seed=1), refine(SHELF, 2, seed=1)
    assert serial.result.parallel is None
    assert first.result.coverage == pytest.approx(serial.result.coverage) == pytest.approx(1.0)
    assert first.to_json()["nodes"] == second.to_json()["nodes"]   # same (seed, N): same policy
    assert [e.kind for e in first.result.events] == [e.kind for e in second.result.events]
    stats = first.result.parallel
    assert stats["workers"] == 2 and stats["dispatched"] > stats["batches"]  # real batches
    assert stats["integrated"] + stats["discarded"] + stats["unused"] == stats["dispatched"]
    assert 0 < stats["critical_s"] <= stats["worker_busy_s"]  # longest per batch <= sum


def test_pybullet_keva_tower_in_parallel(tmp_path):
    from examples.keva.scene import write_problem
    problem = write_problem(tmp_path / "tower3.stamp", seed=0, structure="tower", levels=3)
    files = [REPO / "examples" / "keva" / "domain.stamp", problem]
    serial = refine(files, 1, world="pybullet", seed=0)
    first = refine(files, 2, world="pybullet", seed=0)
    second = refine(files, 2, world="pybullet", seed=0)
    assert first.result.coverage == pytest.approx(serial.result.coverage) == pytest.approx(1.0)
    assert first.to_json()["nodes"] == second.to_json()["nodes"]
    counters = [{k: v for k, v in run.result.parallel.items() if not k.endswith("_s")}
                for run in (first, second)]  # all but the times
    assert counters[0] == counters[1] and len(counters[0]) == 7
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
    eff  probabilistic
             1/2 as h:
                 tossed
                 heads
             1/2 as t: tossed

action finish(x: thing, k: token)
    pre  tossed
         made(x, k)
    eff  done(x)
"""

PROBLEM = """\
problem probe1 for probe
object a: thing
goal done(a)
scene builder "stampc.worlds.plane2d.scenes:cluttered"(n=1, seed=0, blockers=0)
"""

# only worker processes misbehave (the engine's own process has no parent process). The
# workers start with the first batch that has work for them, and the engine answers the
# whole batch itself until they are up: its own task here waits for a worker of this run
# to have imported the kit (a marker file named by the worker's pid; then it only reports
# ready), so that the batch's second task goes to the worker.
UP = """\
import multiprocessing, os, time
from pathlib import Path

UP = Path(__file__).with_name("workers_up")
if multiprocessing.parent_process() is not None:
    UP.mkdir(exist_ok=True)
    (UP / str(os.getpid())).touch()


def wait_for_a_worker():
    for _ in range(1200):
        if any((UP / str(p.pid)).exists() for p in multiprocessing.active_children()):
            time.sleep(2.0)
            return
        time.sleep(0.1)

"""
KITS = {
    "fine": "def make(ctx, x):\n    yield (42,)\n",
    "dies": UP + ("def make(ctx, x):\n"
                  "    if multiprocessing.parent_process() is not None:\n        os._exit(3)\n"
                  "    wait_for_a_worker()\n    yield (42,)\n"),
    "raises": UP + ("def make(ctx, x):\n"
                    "    if multiprocessing.parent_process() is not None:\n"
                    "        raise ValueError('not in a worker')\n"
                    "    wait_for_a_worker()\n    yield (42,)\n"),
}


@pytest.fixture
def probe(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(tmp_path))  # spawned workers inherit sys.path

    def make(tag: str) -> list[str]:
        (tmp_path / f"workerkit_{tag}.py").write_text(KITS[tag])
        (tmp_path / f"probe_{tag}.stamp").write_text(DOMAIN.format(tag=tag))
        (tmp_path / "problem.stamp").write_text(PROBLEM)
        return [str(tmp_path / f"probe_{tag}.stamp"), str(tmp_path / "problem.stamp")]

    return make


def test_probe_sends_a_node_to_a_worker(probe):
    run = refine(probe("fine"), 2, seed=0)
    assert run.result.coverage == pytest.approx(1.0)
    assert run.result.parallel["dispatched"] > run.result.parallel["batches"]


def test_a_worker_that_dies_is_a_located_diagnostic(probe, capsys):
    files = probe("dies")
    with pytest.raises(StampcError) as info:
        refine(files, 2, seed=0)
    assert [d.code for d in info.value.diagnostics] == ["R206"]
    assert main(["refine", *files, "--quiet", "--workers", "2"]) == 1
    err = capsys.readouterr().err
    assert "R206" in err and "exit code 3" in err and "Traceback" not in err


def test_user_code_raising_in_a_worker_is_located_at_its_binding(probe, capsys):
    files = probe("raises")
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
