"""Ground the shared IPPC PPDDL benchmarks (smallest instances of every domain)."""

from __future__ import annotations

from collections import deque
from fractions import Fraction
from pathlib import Path

import pytest

from stampc.ir.ground import ground
from stampc.ir.grounded import GroundModel, outcome_distribution
from stampc.ir.json_io import grounded_from_json, grounded_to_json

importer = pytest.importorskip("stampc.backends.ppddl.importer")

def problem_files(root: Path, per_domain: int) -> list[Path]:
    """The first ``per_domain`` (sorted) problem files of every domain directory."""
    out = []
    for d in sorted(p for p in root.iterdir() if p.is_dir()):
        files = sorted(f for f in d.glob("*.pddl") if f.name not in ("domain.pddl", "sample.pddl"))
        out.extend(files[:per_domain])
    return out


def check_invariants(gm: GroundModel) -> None:
    n = len(gm.facts)
    assert list(gm.facts) == sorted(gm.facts) and len(set(gm.facts)) == n
    assert gm.init >> n == 0
    assert [a.index for a in gm.actions] == list(range(len(gm.actions)))
    assert [(a.name, a.args) for a in gm.actions] == sorted((a.name, a.args) for a in gm.actions)
    for a in gm.actions:
        assert not a.precondition.never
        assert (a.precondition.pos | a.precondition.neg) >> n == 0
        assert a.precondition.pos & a.precondition.neg == 0
        total = sum((s.probability for s in outcome_distribution(a, gm.init)), Fraction(0))
        assert total == 1, a.label


# One problem per domain by default; three (about a minute) in the slow run.
@pytest.mark.parametrize("per_domain", [1, pytest.param(3, marks=pytest.mark.slow)])
def test_every_domain_grounds_with_invariants(ppddl_benchmarks, per_domain):
    files = problem_files(ppddl_benchmarks, per_domain)
    assert len({f.parent for f in files}) >= 20 and len(files) >= 13 * per_domain
    for path in files:
        gm = ground(importer.import_ppddl(path))
        assert gm.actions, path
        check_invariants(gm)


def test_tireworld_p03_counts_match_road_graph(ppddl_benchmarks):
    """Independent count: BFS over the problem's roads from the start location."""
    model = importer.import_ppddl(ppddl_benchmarks / "ippc2006-tireworld" / "p03.pddl")
    gm = ground(model)
    init = [(a.predicate, tuple(t.name for t in a.args)) for a in model.problem.init]
    roads = [args for p, args in init if p == "road"]
    spares = {args[0] for p, args in init if p == "spare-in"}
    (start,) = [args[0] for p, args in init if p == "vehicle-at"]
    seen, todo = {start}, deque([start])
    while todo:
        here = todo.popleft()
        for a, b in roads:
            if a == here and b not in seen:
                seen.add(b)
                todo.append(b)
    moves = sum(1 for a, _ in roads if a in seen)
    counts = {name: sum(1 for a in gm.actions if a.name == name)
              for name in ("move-car", "loadtire", "changetire")}
    assert counts == {"move-car": moves, "loadtire": len(seen & spares), "changetire": 1}
    # facts: vehicle-at for reachable locations, spare-in from init, two flags
    assert len(gm.facts) == len(seen) + len(spares) + 2
    assert len(gm.actions) < 200 and len(gm.facts) < 50


def test_benchmark_grounding_is_deterministic_and_json_round_trips(ppddl_benchmarks):
    for rel in ("ippc2008-boxworld/p01-b10-c5-dc0-fc0-dr0-gr1.pddl",
                "ippc2008-sysadmin-slp/p02-n5-l2-s2.pddl"):
        model = importer.import_ppddl(ppddl_benchmarks / rel)
        gm = ground(model)
        assert ground(model) == gm
        assert grounded_from_json(grounded_to_json(gm)) == gm
