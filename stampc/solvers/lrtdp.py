"""Labelled RTDP (Bonet & Geffner 2003).

Trials follow the greedy policy from the initial node, sampling outcomes with a seeded
``random.Random``, and back up every node they visit; on the way back ``check_solved``
labels a node solved once every node of its greedy subgraph has a residual below ε.
"""

from __future__ import annotations

import random

from stampc.solvers.core import Search

#: Trials longer than this stop early (values still improve; labelling decides).
MAX_TRIAL_LENGTH = 10_000


def lrtdp(search: Search, init: int, epsilon: float, seed: int) -> None:
    """Run LRTDP from ``init`` until it is labelled solved or the deadline passes."""
    rng = random.Random(seed)
    search.seed(init)
    solved: set[int] = set(search.terminal)
    trials = 0
    while init not in solved:
        trials += 1
        search.iterations += 1
        if trials % 32 == 0:
            search.check_limits()
        path = _trial(search, init, solved, rng)
        while path:
            x = path.pop()
            if not _check_solved(search, x, solved, epsilon):
                break


def _ensure_expanded(search: Search, x: int) -> None:
    if x not in search.expanded:
        search.expand(x)


def _trial(search: Search, init: int, solved: set[int], rng: random.Random) -> list[int]:
    path: list[int] = []
    x = init
    while x not in solved and len(path) < MAX_TRIAL_LENGTH:
        path.append(x)
        if x in search.terminal:
            break
        _ensure_expanded(search, x)
        if x in search.terminal:
            break
        search.backup(x)
        bi = search.best[x]
        if bi < 0:
            break  # giving up is the best choice: the trial ends here
        _, _, probs, nexts = search.expanded[x][bi]
        r = rng.random()
        acc = 0.0
        for p, n in zip(probs, nexts):
            acc += p
            if r < acc:
                x = n
                break
        else:
            x = nexts[-1]  # rounding: probabilities summed just below r
    return path


def _check_solved(search: Search, x: int, solved: set[int], epsilon: float) -> bool:
    if x in solved:
        return True
    rv = True
    open_ = [x]
    closed: list[int] = []
    seen = {x}
    V, terminal = search.V, search.terminal
    choice: dict[int, int] = {}
    while open_:
        s = open_.pop()
        closed.append(s)
        if s in terminal:
            continue
        before = V[s]
        _ensure_expanded(search, s)
        if s in terminal:  # just found to be a dead end: its value jumped to D
            if V[s] - before > epsilon:
                rv = False
            continue
        q, bi = search.greedy(s)
        if abs(q - V[s]) > epsilon:
            rv = False
            continue
        choice[s] = bi
        if bi < 0:
            continue
        for n in search.expanded[s][bi][3]:
            if n not in solved and n not in seen:
                seen.add(n)
                open_.append(n)
    if rv:
        # Record the greedy choices the label certifies (values are left as they are).
        search.best.update(choice)
        solved.update(closed)
    else:
        for s in reversed(closed):
            if s not in terminal:
                search.backup(s)
    return rv
