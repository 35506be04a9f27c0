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
        self._plans: dict[int, tuple[tuple[str, ...], tuple[EqPair, ...]]] = {}

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
        plan = self._plans.get(id(node))
        if plan is None:
            s = self.of(node)
            eqs = tuple(e for e in s.eqs if _vars(e) - s.struct)
            plan = self._plans[id(node)] = (tuple(sorted(s.struct)), eqs)
        struct, eqs = plan
        values = tuple([env[v] for v in struct])
        if not eqs:
            return (id(node), values)
        return (id(node), values, tuple([_term(a, env) == _term(b, env) for a, b in eqs]))


def _term(t: L.Term, env: dict[str, str]) -> str:
    return env[t.name] if isinstance(t, L.Var) else t.name
