"""PPDDL import throughput: tokens per second at small, medium and large sizes.

Usage: ``python bench/ppddl_import.py [--repeat R] [--sizes 1000,10000,70000]``.
Generates a graph problem with N objects and 4N ``(edge a b)`` init facts (N = 70,000
is a 6.8 MB file), then the largest files of ``../shared/benchmarks/ppddl`` if present.
Prints, per input, bytes, tokens (words and parentheses), the best of R wall-clock and
CPU times of ``import_ppddl`` (read + shape + lower to the lifted IR) and tokens per
second on both clocks. Target (issue 10): >= 100k tokens/s. A cost that grows faster
than the input shows as falling tokens/s down the sizes.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from stampc.backends.ppddl import import_ppddl  # noqa: E402

DOMAIN = """(define (domain graph)
 (:requirements :typing :probabilistic-effects :rewards)
 (:types node)
 (:predicates (edge ?a ?b - node) (at ?a - node) (visited ?a - node))
 (:action move :parameters (?a ?b - node)
   :precondition (and (at ?a) (edge ?a ?b))
   :effect (and (probabilistic 0.9 (and (not (at ?a)) (at ?b) (visited ?b)))
                (decrease (reward) 1))))
"""
_TOKENS = re.compile(r"[()]|[^\s();]+")
BENCHMARKS = Path(__file__).resolve().parents[2] / "shared" / "benchmarks" / "ppddl"
LARGEST = ("ippc2008-sysadmin-slp/p15-n1920-l960-s15.pddl",
           "ippc2008-sysadmin-slp/p14-n960-l480-s14.pddl", "ippc2006-drive/p15.pddl")


def generated_problem(n: int) -> str:
    objects = " ".join(f"n{i}" for i in range(n))
    init = "\n".join(f"  (edge n{i} n{(7 * i + j) % n})" for i in range(n) for j in (1, 2, 3, 5))
    return (DOMAIN + f"(define (problem p{n}) (:domain graph) (:objects {objects} - node)\n"
            f" (:init (at n0)\n{init})\n (:goal (visited n{n - 1})))\n")


def measure(path: Path, repeat: int) -> tuple[float, float]:
    best_wall = best_cpu = float("inf")
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        import_ppddl(path)
        best_wall = min(best_wall, time.perf_counter() - wall)
        best_cpu = min(best_cpu, time.process_time() - cpu)
    return best_wall, best_cpu


def report(label: str, path: Path, repeat: int) -> None:
    text = path.read_text()
    tokens = len(_TOKENS.findall(text))
    wall, cpu = measure(path, repeat)
    print(f"{label:<34} {len(text) / 1e6:7.2f} MB {tokens:>9,d} tokens  wall {wall:7.3f} s "
          f"({tokens / wall / 1e3:6.0f}k tok/s)  cpu {cpu:7.3f} s ({tokens / cpu / 1e3:6.0f}k tok/s)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sizes", default="1000,10000,70000",
                        help="object counts of the generated problems")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for n in (int(s) for s in args.sizes.split(",")):
            path = Path(tmp) / f"graph{n}.pddl"
            path.write_text(generated_problem(n))
            report(f"generated, {n:,d} objects", path, args.repeat)
    for name in LARGEST:
        path = BENCHMARKS / name
        if path.is_file():
            report(name.split("/")[0][:14] + "/" + path.name[:19], path, args.repeat)


if __name__ == "__main__":
    main()
