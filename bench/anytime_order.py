"""How early could a refinement order have covered 50 / 80 / 90 % of the mass?

    python bench/anytime_order.py RESULT_DIR [RESULT_DIR ...]

Reads each run's final ``policy.json`` and, taking its refined nodes as the work that had
to be done, orders them greedily: each step refines the uncovered root-to-leaf path whose
unrefined nodes add the most coverage per node, as an oracle that knows the final graph
would. Prints, per run, the share of the refined nodes after which 50 / 80 / 90 % of the
mass was covered in that order, beside the share the run itself needed (from
``coverage.csv``). A node count is a proxy for time: nodes differ in cost.

It tells whether an anytime target ("80 % of the mass within 30 % of the run") is missed
because of the selection rule or because of the policy's shape: when even this order needs
far more than 30 % of the nodes for 80 %, a better rule will not meet it on that policy
(the greedy order is not a proven optimum, so a margin is needed). Paths are
enumerated, so policies with more than ``MAX_PATHS`` root-to-leaf paths are skipped.
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

MAX_PATHS = 5_000
LEVELS = (0.5, 0.8, 0.9)


def _coverage(nodes: dict, root: int, refined: set[int]) -> float:
    memo: dict[int, float] = {}

    def cov(uid: int) -> float:
        if uid not in memo:
            n = nodes[uid]
            if n["leaf"] is not None:
                memo[uid] = 1.0 if n["leaf"] == "goal" else 0.0
            elif uid not in refined:
                memo[uid] = 0.0
            else:
                memo[uid] = sum(o["probability"] * cov(o["child"]) for o in n["outcomes"])
        return memo[uid]
    return cov(root)


def _paths(nodes: dict, root: int) -> list[tuple[int, ...]] | None:
    out: list[tuple[int, ...]] = []
    stack = [(root, (root,))]
    while stack:
        uid, path = stack.pop()
        n = nodes[uid]
        if n["leaf"] is not None:
            out.append(path)
            if len(out) > MAX_PATHS:
                return None
            continue
        stack.extend((o["child"], path + (o["child"],)) for o in n["outcomes"]
                     if o["child"] not in path)
    return out


def greedy_order(policy: dict) -> list[tuple[int, float]] | None:
    """(refined nodes so far, coverage) after each greedy step; None if too many paths."""
    nodes = {n["id"]: n for n in policy["nodes"]}
    root = policy["root"]
    paths = _paths(nodes, root)
    if paths is None:
        return None
    work = [[u for u in p if nodes[u]["leaf"] is None and nodes[u]["refined"]] for p in paths]
    refined: set[int] = set()
    covered, steps = 0.0, []
    while True:
        best = None
        for todo in work:
            new = [u for u in todo if u not in refined]
            if not new:
                continue
            gain = _coverage(nodes, root, refined | set(new)) - covered
            if best is None or gain / len(new) > best[0]:
                best = (gain / len(new), new)
        if best is None or best[0] <= 0:
            return steps
        refined |= set(best[1])
        covered = _coverage(nodes, root, refined)
        steps.append((len(refined), covered))


def _share(steps: list[tuple[int, float]], level: float, total: int) -> float | None:
    return next((k / total for k, c in steps if c >= level - 1e-12), None)


def _run_shares(run: Path, total: int) -> list[float | None]:
    """The run's own share of its refined nodes at each level (coverage.csv)."""
    rows = list(csv.DictReader((run / "coverage.csv").open()))
    return [next((int(r["refined_nodes"]) / total for r in rows
                  if float(r["coverage"]) >= level - 1e-12), None) for level in LEVELS]


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    fmt = lambda v: "—" if v is None else f"{v:.0%}"  # noqa: E731
    print("| run | refined nodes | greedy order: 50 / 80 / 90 % | the run: 50 / 80 / 90 % |")
    print("|---|---|---|---|")
    for arg in argv:
        run = Path(arg)
        policy = json.loads((run / "policy.json").read_text())
        total = sum(1 for n in policy["nodes"] if n["leaf"] is None and n["refined"])
        steps = greedy_order(policy)
        if steps is None or total == 0:
            print(f"| {run} | {total} | more than {MAX_PATHS} paths | |")
            continue
        greedy = " / ".join(fmt(_share(steps, lv, total)) for lv in LEVELS)
        own = " / ".join(fmt(v) for v in _run_shares(run, total))
        print(f"| {run} | {total} | {greedy} | {own} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
