"""Free-variable analysis that lets the grounder share ground sub-trees.

The ground form of a lifted sub-formula/sub-effect depends only on the values of its
free variables. Better still, a free variable used *only* in equalities whose other side
is also known at that node (``(not (= ?d ?x))`` in SysAdmin's reboot) matters only
through the truth values of those equalities. :func:`memo_key` builds the smallest key
capturing that, so e.g. the per-computer body of SysAdmin's ``forall`` is ground twice
per computer instead of once per (computer, rebooted computer) pair.
"""

from __future__ import annotations

from dataclasses import dataclass
from operator import itemgetter
from typing import Callable

from stampc.ir import lifted as L

EqPair = tuple[L.Term, L.Term]


@dataclass(frozen=True)
class Scope:
    free: frozenset[str]
    #: free variables used outside evaluable equalities (their values enter the key)
    struct: frozenset[str]
    #: equalities whose variables are all free here (their truth values enter the key)
    eqs: tuple[EqPair, ...]


EMPTY = Scope(frozenset(), frozenset(), ())


def _vars(terms) -> frozenset[str]:
    return frozenset(t.name for t in terms if isinstance(t, L.Var))


def _union(scopes) -> Scope:
    free: set[str] = set()
    struct: set[str] = set()
    eqs: list[EqPair] = []
    for s in scopes:
        free |= s.free
        struct |= s.struct
        eqs.extend(s.eqs)
    return Scope(frozenset(free), frozenset(struct), tuple(dict.fromkeys(eqs)))


def _bind(inner: Scope, params: tuple[L.Param, ...]) -> Scope:
    bound = {p.name for p in params}
    kept, struct = [], set(inner.struct - bound)
    for eq in inner.eqs:
        names = _vars(eq)
        if names & bound:
            struct |= names - bound  # no longer evaluable above the binder
        else:
            kept.append(eq)
    return Scope(inner.free - bound, frozenset(struct), tuple(kept))


class ScopeAnalysis:
    """Caches :class:`Scope` per node (by identity: nodes live as long as the model)."""

    def __init__(self) -> None:
        self._cache: dict[int, Scope] = {}
        self._keyers: dict[int, Callable[[dict[str, str]], tuple]] = {}

    def clear(self) -> None:
        """Forget every node (callers that are done with a part of the model)."""
        self._cache.clear()
        self._keyers.clear()

    def of(self, node) -> Scope:
        s = self._cache.get(id(node))
        if s is None:
            s = self._cache[id(node)] = self._compute(node)
        return s

    def _compute(self, n) -> Scope:
        if isinstance(n, (L.Atom, L.FuncTerm)):
            names = _vars(n.args)
            return Scope(names, names, ())
        if isinstance(n, L.Equals):
            names = _vars((n.left, n.right))
            return Scope(names, frozenset(), ((n.left, n.right),) if names else ())
        if isinstance(n, L.Not):
            return self.of(n.arg)
        if isinstance(n, (L.And, L.Or)):
            return _union(self.of(a) for a in n.args)
        if isinstance(n, L.Imply):
            return _union((self.of(n.left), self.of(n.right)))
        if isinstance(n, (L.Forall, L.Exists)):
            return _bind(self.of(n.body), n.params)
        if isinstance(n, (L.Lit, L.Unknown)):
            return self.of(n.atom)
        if isinstance(n, L.EffAnd):
            return _union(self.of(e) for e in n.effects)
        if isinstance(n, L.When):
            return _union((self.of(n.condition), self.of(n.effect)))
        if isinstance(n, L.EffForall):
            return _bind(self.of(n.effect), n.params)
        if isinstance(n, L.Probabilistic):
            return _union(self.of(o.effect) for o in n.outcomes)
        if isinstance(n, L.CostEffect):
            return self.of(n.amount)
        if isinstance(n, L.BinOp):
            return _union((self.of(n.left), self.of(n.right)))
        return EMPTY  # Truth, Num

    def memo_key(self, node, env: dict[str, str]) -> tuple:
        return self.keyer(node)(env)

    def keyer(self, node) -> Callable[[dict[str, str]], tuple]:
        """``memo_key`` for ``node`` as a function of the environment (for hot loops)."""
        keyer = self._keyers.get(id(node))
        if keyer is None:
            keyer = self._keyers[id(node)] = self._compile_key(node)
        return keyer

    def _compile_key(self, node) -> Callable[[dict[str, str]], tuple]:
        # Grounding calls this once per (node, binding): quadratic on SysAdmin-like
        # domains, so the key is built by a closure specialised to the node's shape.
        s = self.of(node)
        nid = id(node)
        struct = tuple(sorted(s.struct))
        eqs = tuple(e for e in s.eqs if _vars(e) - s.struct)
        values = _values_getter(struct)
        if not eqs:
            return lambda env: (nid, values(env))
        tests = tuple(_equality_test(a, b) for a, b in eqs)
        if len(tests) == 1:
            (test,) = tests
            return lambda env: (nid, values(env), (test(env),))
        return lambda env: (nid, values(env), tuple([t(env) for t in tests]))


def _values_getter(names: tuple[str, ...]) -> Callable[[dict[str, str]], tuple]:
    if not names:
        return lambda env: ()
    if len(names) == 1:
        (name,) = names
        return lambda env: (env[name],)
    return itemgetter(*names)  # a tuple for two or more names


def _equality_test(a: L.Term, b: L.Term) -> Callable[[dict[str, str]], bool]:
    if isinstance(a, L.Var) and isinstance(b, L.Var):
        x, y = a.name, b.name
        return lambda env: env[x] == env[y]
    if isinstance(b, L.Var):
        a, b = b, a
    if isinstance(a, L.Var):
        x, c = a.name, b.name
        return lambda env: env[x] == c
    same = a.name == b.name
    return lambda env: same
