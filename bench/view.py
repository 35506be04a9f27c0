"""`stampc view` reports: file size, load time in headless Chromium, and responsiveness.

For each run directory: the report's size, the time from navigation to the graph's
first drawing (the browser's clock, median of --loads page loads), the part of it
spent building the vis-network graph (last load; positions come precomputed), and the
time to select a node (detail panel filled, view centred on it, canvas redrawn). The default
runs are a synthetic policy of --nodes nodes (5,000), written by the real exporter, and
fresh refine runs of the examples named by --examples (default: domino; the paper's
four are `domino cluttered_table keva aircraft_inspection`).

    python bench/view.py
    python bench/view.py --examples domino cluttered_table keva aircraft_inspection
    python bench/view.py --nodes 20000 --examples

Targets (issue 16): each example's report < 5 MB and loaded in < 3 s; a 5,000-node policy
stays responsive. Needs Debian's chromium + chromium-driver and `pip install -e .[view,test]`.
"""

from __future__ import annotations

import argparse
import random
import statistics
import subprocess
import sys
import tempfile
import time
from fractions import Fraction
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "tests" / "view"))

PYBULLET = {"domino", "cluttered_table", "keva", "aircraft_inspection"}


def synthetic_run(out: Path, size: int, seed: int = 0) -> Path:
    """A refine output directory with a random policy of ``size`` nodes (a mix of
    refined, unrefined, goal, dead-end and horizon nodes over the shelf2d model),
    written by ``stampc.refine.export.write_outputs``."""
    import stampc
    from stampc.ir.grounded import Successor
    from stampc.refine.export import write_outputs
    from stampc.refine.graph import DEAD_END, GOAL, HORIZON, Edge, Node, PolicyGraph
    from stampc.refine.options import ProgressEvent, RefineResult

    shelf = REPO / "examples" / "shelf2d"
    model = stampc.ground(stampc.compile(shelf / "domain.stamp", shelf / "problem.stamp"))
    rng = random.Random(seed)
    noop = Successor(Fraction(1), 0, 0, Fraction(1))
    nodes: dict[int, Node] = {0: Node(0, model.init, 0)}
    frontier, next_uid = [0], 1
    while frontier:
        uid = frontier.pop(0)
        kids = rng.choice((1, 2, 2, 3)) if next_uid < size else 0
        kids = min(kids, size - next_uid)
        node = nodes[uid]
        if not kids:
            node.leaf = rng.choice((GOAL, GOAL, GOAL, DEAD_END, HORIZON))
            node.proven = node.leaf == DEAD_END and rng.random() < 0.5
            continue
        node.action = rng.randrange(len(model.actions))
        if rng.random() < 0.7:
            node.sigma = {f"t_{uid}": {"points": [[rng.random(), rng.random()] for _ in range(5)],
                                       "target": "can1", "held": None},
                          f"g_{uid}": {"angle": rng.uniform(-3, 3)}}
        for k in range(kids):
            child = Node(next_uid, model.init, node.depth + 1)
            nodes[next_uid] = child
            node.edges.append(Edge(1 / kids, k, noop, next_uid))
            frontier.append(next_uid)
            next_uid += 1
    events = tuple(ProgressEvent(t / 10, t / 20, t / 25, t, 1, 1, "refined") for t in range(11))
    result = RefineResult(0.5, 0.4, 1.0, 1.0, {}, 1, 1, size // 2, 1, seed, "time limit", events,
                          goal_mass=0.4, dead_end_mass=0.1, unrefined_mass=0.5)
    write_outputs(out, model, PolicyGraph(0, nodes), result, {}, {"domain": "synthetic",
                  "problem": f"{size} nodes", "world": "plane2d", "files": [],
                  "scene": {}})
    return out


def refine_example(name: str, out: Path) -> Path:
    folder = REPO / "examples" / name
    world = "pybullet" if name in PYBULLET else "plane2d"
    started = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "stampc", "refine", str(folder / "domain.stamp"),
                           str(folder / "problem.stamp"), "--world", world, "--time-limit", "120",
                           "--quiet", "-o", str(out)], cwd=REPO, capture_output=True, text=True)
    print(f"  refined {name} ({world}) in {time.perf_counter() - started:.1f} s, exit "
          f"{done.returncode}: {done.stdout.strip().splitlines()[0] if done.stdout else done.stderr}")
    return out


def measure(chrome, run_dir: Path, loads: int) -> dict:
    from browser import load_report

    from stampc.view import view_run

    started = time.perf_counter()
    report = view_run(run_dir)
    write_s = time.perf_counter() - started
    times = [load_report(chrome, report, timeout=120) for _ in range(loads)]
    nodes = chrome.execute_script("return stampcReport.nodeCount")
    marks = dict(chrome.execute_script(
        "return performance.getEntriesByType('mark').map(m => [m.name, m.startTime])"))
    network_s = (marks["stampc:network"] - marks["stampc:data"]) / 1000
    select_ms = chrome.execute_script("""
        const r = stampcReport, ids = r.network.body.nodeIndices, t = performance.now();
        for (let i = 0; i < 10; i++) { r.select(ids[(i * 7919) % ids.length], true); r.network.redraw(); }
        return (performance.now() - t) / 10;""")
    return {"run": run_dir.name, "nodes": nodes, "MB": report.stat().st_size / 1e6,
            "write_s": write_s, "load_s": statistics.median(times), "network_s": network_s,
            "select_ms": select_ms}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--nodes", type=int, default=5000, help="synthetic policy size (0: none)")
    parser.add_argument("--examples", nargs="*", default=["domino"])
    parser.add_argument("--loads", type=int, default=3)
    args = parser.parse_args()
    from browser import start_chromium, stop

    with tempfile.TemporaryDirectory() as tmp:
        runs = [refine_example(name, Path(tmp) / name) for name in args.examples]
        if args.nodes:
            runs.append(synthetic_run(Path(tmp) / f"synthetic{args.nodes}", args.nodes))
        chrome = start_chromium()
        try:
            rows = [measure(chrome, run, args.loads) for run in runs if (run / "policy.json").exists()]
        finally:
            stop(chrome)
    print(f"{'run':<22}{'nodes':>7}{'MB':>7}{'write s':>9}{'load s':>8}{'network s':>10}"
          f"{'select ms':>11}")
    for r in rows:
        print(f"{r['run']:<22}{r['nodes']:>7}{r['MB']:>7.2f}{r['write_s']:>9.2f}"
              f"{r['load_s']:>8.2f}{r['network_s']:>10.2f}{r['select_ms']:>11.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
