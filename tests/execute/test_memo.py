"""Memoised execution is the same execution: with and without the step memo, the same
seed gives the same runs (statuses, outcomes, collisions, goal-check reasons) and the
same concrete snapshot after every step — on plane2d and on PyBullet with physics
(the domino policy: toppled dominoes fall under gravity)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from stampc.execute.session import execute_file

from .test_pybullet_runs import domino  # noqa: F401  (the module-scoped fixture)


class Snapshots:
    """A recorder-shaped observer: the world's snapshot after every step of every run."""

    def __init__(self) -> None:
        self.after: list[tuple[int, Any]] = []

    def start(self, world: Any) -> None: ...
    def on_run_start(self, run: int) -> None: ...
    def frame(self, world: Any) -> None: ...
    def motion(self, world: Any, action: Any) -> None: ...

    def on_step(self, run: int, world: Any) -> None:
        self.after.append((run, world.snapshot()))


def both(policy: Path, runs: int, seed: int, **kw: Any):
    out = []
    for memo in (False, True):
        seen, memos = Snapshots(), []
        report = execute_file(policy, runs=runs, seed=seed, memo=memo, recorder=seen,
                              on_memo=memos.append, **kw)
        out.append((report, seen.after, memos))
    return out


def assert_same(plain, memoised) -> None:
    (r0, after0, _), (r1, after1, memos) = plain, memoised
    assert r0.runs == r1.runs
    assert r0.to_json() == r1.to_json()
    assert after0 == after1  # exact equality of every intermediate concrete state
    assert memos[0].hits > 0  # the memo did replay steps (the comparison is not vacuous)


def test_memoised_shelf_runs_equal_plain_ones(shelf: Path) -> None:
    plain, memoised = both(shelf / "full" / "policy.json", runs=40, seed=5,
                           truth=["crushed=0.4"])
    assert_same(plain, memoised)
    assert {r.status for r in plain[0].runs} >= {"success"}


def test_memoised_domino_runs_equal_plain_ones(domino: Path) -> None:  # noqa: F811
    plain, memoised = both(domino, runs=12, seed=2)
    assert_same(plain, memoised)
    assert any("topple" in s.outcome for r in plain[0].runs for s in r.steps)
