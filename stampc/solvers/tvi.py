"""Topological value iteration (Dai, Mausam, Weld & Goldsmith 2011).

Every node reachable from the initial node is generated (as in VI), the graph over all
actions is split into strongly connected components (iterative Tarjan), and the
components are solved one at a time in reverse topological order — successors first — by
Gauss-Seidel sweeps until the component's residual is below ε. A value leaves its
component only once it has converged, so acyclic parts cost one backup per node and
each cyclic part is swept only as often as it itself needs. Values start from the
heuristic, so with an admissible heuristic they stay lower bounds (``bounds.py``).
"""

from __future__ import annotations

from stampc.solvers.core import Search
from stampc.solvers.vi import reachable, sweep_until_converged


def components(search: Search, nodes: list[int],
               edges: dict[int, set[int]] | None = None) -> list[list[int]]:
    """Strongly connected components of the expanded ``nodes`` (all actions, or the given
    ``edges``), successors' components before their predecessors'."""
    expanded = search.expanded
    inner = set(nodes)
    if edges is not None:  # in the shape of transitions, for _succ
        expanded = {x: ((None, 0.0, (), tuple(nexts)),) for x, nexts in edges.items()}
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on_stack: set[int] = set()
    stack: list[int] = []
    out: list[list[int]] = []
    for root in nodes:
        if root in index:
            continue
        work = [(root, _succ(expanded, root, inner), )]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            x, it = work[-1]
            advanced = False
            for n in it:
                if n not in index:
                    index[n] = low[n] = len(index)
                    stack.append(n)
                    on_stack.add(n)
                    work.append((n, _succ(expanded, n, inner)))
                    advanced = True
                    break
                if n in on_stack and index[n] < low[x]:
                    low[x] = index[n]
            if advanced:
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                if low[x] < low[parent]:
                    low[parent] = low[x]
            if low[x] == index[x]:
                comp = []
                while True:
                    n = stack.pop()
                    on_stack.discard(n)
                    comp.append(n)
                    if n == x:
                        break
                out.append(comp)
    return out


def _succ(expanded, x: int, inner: set[int]):
    return iter({n for _, _, _, nexts in expanded.get(x, ()) for n in nexts if n in inner})


def topological_vi(search: Search, init: int, epsilon: float) -> None:
    nodes = reachable(search, init)
    for comp in components(search, nodes):
        if len(comp) == 1 and comp[0] not in _self_successors(search, comp[0]):
            search.backup(comp[0])
            continue
        sweep_until_converged(search, comp, epsilon)
        search.check_limits()


def _self_successors(search: Search, x: int) -> set[int]:
    return {n for _, _, _, nexts in search.expanded[x] for n in nexts}
