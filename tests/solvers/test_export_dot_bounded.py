"""A policy DOT file stays bounded: above its node limit the rest is counted, not drawn."""

from __future__ import annotations

import re
from pathlib import Path

import stampc
from stampc.solvers import SolverOptions, solve
from stampc.solvers.export import policy_dot, write_policy_dot

REPO = Path(__file__).resolve().parents[2]


def test_dot_is_cut_at_its_limit_and_says_so(tmp_path):
    shelf = REPO / "examples" / "shelf2d"
    model = stampc.ground(stampc.compile(shelf / "domain.stamp", shelf / "problem.stamp"))
    solution = solve(model, SolverOptions())
    total = len(solution.policy_nodes())
    assert total >= 2
    limit = total // 2
    full = policy_dot(model, solution)
    assert len(re.findall(r"^  n\d+ \[", full, re.M)) == total and "more" not in full
    cut = policy_dot(model, solution, limit=limit)
    assert len(re.findall(r"^  n\d+ \[", cut, re.M)) == limit
    assert f"+{total - limit} more states not shown" in cut
    assert write_policy_dot(str(tmp_path / "all.dot"), model, solution) is None
    note = write_policy_dot(str(tmp_path / "cut.dot"), model, solution, limit=limit)
    assert note is not None and f"first {limit} of {total}" in note
