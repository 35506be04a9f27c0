"""A small semi-naive Datalog evaluator for the relaxed reachability rules.

Facts are tuples of object names grouped by relation. Each round joins every rule with
at least one body atom restricted to the facts that are new since the previous round
(the *delta*), so long relaxed plans (chains of 2,000 actions) cost one cheap round each
instead of a full re-evaluation. Joins use hash indexes built on demand per
(relation, bound positions).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterable

from stampc.ir.relax import Filter, Rule

Env = dict[str, str]


class FactBase:
    """Relations with incrementally maintained hash indexes."""

    def __init__(self) -> None:
        self.rels: dict[str, set[tuple[str, ...]]] = {}
        self._indexes: dict[str, dict[tuple[int, ...], dict[tuple, list]]] = {}

    def relation(self, rel: str) -> set[tuple[str, ...]]:
        return self.rels.get(rel, set())

    def add(self, rel: str, tup: tuple[str, ...]) -> bool:
        facts = self.rels.setdefault(rel, set())
        if tup in facts:
            return False
        facts.add(tup)
        for positions, index in self._indexes.get(rel, {}).items():
            index.setdefault(tuple(tup[p] for p in positions), []).append(tup)
        return True

    def lookup(self, rel: str, positions: tuple[int, ...], key: tuple) -> Iterable[tuple]:
        by_pos = self._indexes.setdefault(rel, {})
        index = by_pos.get(positions)
        if index is None:
            index = {}
            for tup in self.rels.get(rel, ()):
                index.setdefault(tuple(tup[p] for p in positions), []).append(tup)
            by_pos[positions] = index
        return index.get(key, ())


@dataclass(frozen=True)
class _Step:
    atom: int                        # position of the step's atom in the rule body
    bound: tuple[int, ...]           # positions whose value is known before this step
    key_terms: tuple[tuple[bool, str], ...]
    binds: tuple[tuple[int, str], ...]   # first occurrences of new variables
    checks: tuple[tuple[int, str], ...]  # repeated new variables inside this atom
    full: bool                       # every position bound: a membership test
    filters: tuple[Filter, ...]      # filters that become checkable after this step


def _plan(rule: Rule, anchor: int | None) -> tuple[tuple[_Step, ...], tuple[Filter, ...]]:
    """Greedy join order: anchor first, then the atom with most bound positions."""
    bound: set[str] = set()
    remaining = list(range(len(rule.body)))
    order: list[int] = []
    if anchor is not None:
        order.append(anchor)
        remaining.remove(anchor)
        bound |= {n for v, n in rule.body[anchor].terms if v}
    def score(i: int) -> tuple:
        terms = rule.body[i].terms
        nbound = sum(1 for v, n in terms if not v or n in bound)
        return (nbound == len(terms), nbound, not rule.body[i].rel.startswith("@type"), -i)

    while remaining:
        # Fully bound atoms bind nothing: take them all at once, in the greedy order,
        # so bodies with thousands of ground literals plan in O(n log n), not O(n^2).
        full = sorted((i for i in remaining if score(i)[0]), key=score, reverse=True)
        if full:
            order.extend(full)
            taken = set(full)
            remaining = [i for i in remaining if i not in taken]
            continue
        best = max(remaining, key=score)
        remaining.remove(best)
        order.append(best)
        bound |= {n for v, n in rule.body[best].terms if v}
    pending = list(rule.filters)
    initial = tuple(f for f in pending if not any(v for v, _ in f.terms))
    pending = [f for f in pending if f not in initial]
    steps: list[_Step] = []
    known: set[str] = set()
    for i in order:
        pat = rule.body[i]
        bpos, binds, checks, seen_new = [], [], [], set()
        for pos, (is_var, name) in enumerate(pat.terms):
            if not is_var or name in known:
                bpos.append(pos)
            elif name in seen_new:
                checks.append((pos, name))
            else:
                binds.append((pos, name))
                seen_new.add(name)
        known |= seen_new
        ready = tuple(f for f in pending if all(n in known for v, n in f.terms if v))
        pending = [f for f in pending if f not in ready]
        steps.append(_Step(i, tuple(bpos), tuple(pat.terms[p] for p in bpos), tuple(binds),
                           tuple(checks), len(bpos) == len(pat.terms), ready))
    return tuple(steps), initial


def _value(term: tuple[bool, str], env: Env) -> str:
    return env[term[1]] if term[0] else term[1]


class RuleRunner:
    """Evaluates one rule, fully or anchored on delta facts, calling ``emit(env)``."""

    __slots__ = ("rule", "static_holds", "_plans", "_shared")  # one per rule: 10^5 of them

    def __init__(self, rule: Rule, static_holds: Callable[[str, tuple[str, ...]], bool],
                 shared_plans: dict[tuple, tuple] | None = None):
        self.rule = rule
        self.static_holds = static_holds
        #: plans by anchor (None: slot 0, body atom i: slot i + 1)
        self._plans: list[tuple | None] = [None] * (len(rule.body) + 1)
        #: plans by body shape: generated domains repeat one body over many schemas
        self._shared = {} if shared_plans is None else shared_plans

    def plan(self, anchor: int | None) -> tuple:
        slot = 0 if anchor is None else anchor + 1
        p = self._plans[slot]
        if p is None:
            p = self._plans[slot] = self._shared_plan(anchor)
        return p

    def _shared_plan(self, anchor: int | None) -> tuple:
        # A plan depends on the body's terms, on which atoms are type atoms and on the
        # filters, not on relation names (steps refer to atoms by position): effect rules
        # of copies of one schema differ only in their "@act:<schema>" atom.
        rule = self.rule
        key = (tuple((p.terms, p.rel.startswith("@type")) for p in rule.body), rule.filters,
               anchor)
        p = self._shared.get(key)
        if p is None:
            p = self._shared[key] = _plan(rule, anchor)
        return p

    def check(self, f: Filter, env: Env) -> bool:
        if f.kind == "eq":
            return _value(f.terms[0], env) == _value(f.terms[1], env)
        if f.kind == "neq":
            return _value(f.terms[0], env) != _value(f.terms[1], env)
        return not self.static_holds(f.rel, tuple(_value(t, env) for t in f.terms))

    def run(self, kb: FactBase, emit: Callable[[Env], None], anchor: int | None = None,
            delta: Iterable[tuple] = ()) -> None:
        steps, initial = self.plan(anchor)
        env: Env = {}
        if not all(self.check(f, env) for f in initial):
            return
        if anchor is None:
            self._join(kb, steps, 0, env, emit)
            return
        first = steps[0]
        for tup in delta:
            if self._match(first, tup, env):
                self._join(kb, steps, 1, env, emit)

    def _match(self, step: _Step, tup: tuple, env: Env) -> bool:
        for pos, (is_var, name) in zip(step.bound, step.key_terms):
            if tup[pos] != (env[name] if is_var else name):
                return False
        for pos, name in step.binds:
            env[name] = tup[pos]
        for pos, name in step.checks:
            if tup[pos] != env[name]:
                return False
        return all(self.check(f, env) for f in step.filters)

    def _join(self, kb: FactBase, steps: tuple[_Step, ...], k: int, env: Env,
              emit: Callable[[Env], None]) -> None:
        # Fully bound steps are membership tests: a loop, not recursion, so bodies with
        # thousands of literals (10,000-conjunct preconditions) stay within the stack.
        body = self.rule.body
        while k < len(steps) and steps[k].full:
            step = steps[k]
            key = tuple(env[n] if v else n for v, n in step.key_terms)
            if key not in kb.relation(body[step.atom].rel) or \
                    not all(self.check(f, env) for f in step.filters):
                return
            k += 1
        if k == len(steps):
            emit(env)
            return
        step = steps[k]
        key = tuple(env[n] if v else n for v, n in step.key_terms)
        rel = body[step.atom].rel
        candidates = kb.lookup(rel, step.bound, key) if step.bound else list(kb.relation(rel))
        for tup in candidates:
            if self._match(step, tup, env):
                self._join(kb, steps, k + 1, env, emit)


def head_tuple(rule: Rule, env: Env) -> tuple[str, ...]:
    return tuple(env[n] if v else n for v, n in rule.head_terms)


def fixpoint(kb: FactBase, rules: list[Rule], static_holds: Callable,
             on_head: Callable[[Rule, tuple[str, ...], list], None]) -> None:
    """Run ``rules`` to a fixpoint. ``on_head(rule, head, pending)`` appends the facts
    a derived head produces to ``pending`` as (relation, tuple) pairs."""
    shared_plans: dict[tuple, tuple] = {}
    runners = [RuleRunner(r, static_holds, shared_plans) for r in rules]
    # relation -> (runners, positions) of the body atoms over it: two flat lists, not a
    # pair per atom (generated domains have several body atoms per schema)
    by_rel: dict[str, tuple[list[RuleRunner], list[int]]] = {}
    for runner in runners:
        for i, pat in enumerate(runner.rule.body):
            users = by_rel.get(pat.rel)
            if users is None:
                users = by_rel[pat.rel] = ([], [])
            users[0].append(runner)
            users[1].append(i)
    pending: list[tuple[str, tuple[str, ...]]] = []
    for runner in runners:
        _run_collect(runner, kb, on_head, pending, None, ())
    while pending:
        delta: dict[str, list[tuple]] = {}
        for rel, tup in pending:
            if kb.add(rel, tup):
                delta.setdefault(rel, []).append(tup)
        pending = []
        for rel, tuples in delta.items():
            for runner, i in zip(*by_rel.get(rel, ((), ()))):
                _run_collect(runner, kb, on_head, pending, i, tuples)


def _run_collect(runner: RuleRunner, kb: FactBase, on_head: Callable, pending: list,
                 anchor: int | None, delta: Iterable[tuple]) -> None:
    seen: set[tuple[str, ...]] = set()
    rule = runner.rule
    existing = kb.relation(rule.head_rel)

    def emit(env: Env) -> None:
        head = head_tuple(rule, env)
        if head not in seen and head not in existing:
            seen.add(head)
            on_head(rule, head, pending)

    runner.run(kb, emit, anchor, delta)
