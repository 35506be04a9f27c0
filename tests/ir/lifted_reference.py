"""A deliberately naive interpreter of the lifted semantics, used as a test oracle.

States are sets of (predicate, args) atoms (static atoms included). Quantifiers expand
over all objects of the type, effects are evaluated directly on the state: no
reachability, no static compilation, no memoisation - nothing shared with the grounder.
"""

from __future__ import annotations

from fractions import Fraction
from itertools import product

from stampc.ir import lifted as L

Atom = tuple[str, tuple[str, ...]]
Branch = tuple[Fraction, frozenset, frozenset, Fraction]  # p, adds, deletes, cost


class Reference:
    def __init__(self, model: L.Model):
        self.model = model
        parent = {t.name: (t.parent or "object") for t in model.domain.types}
        self.objects = [(o.name, o.type) for o in (*model.domain.constants, *model.problem.objects)]

        def ancestors(t: str) -> set[str]:
            out = {t, "object"}
            while t in parent and parent[t] != t and parent[t] not in out:
                t = parent[t]
                out.add(t)
            return out
        self.ancestors = ancestors
        self.values = {(a.predicate, tuple(t.name for t in a.args)): v
                       for a, v in model.problem.init_values}

    def of_type(self, type_name: str) -> list[str]:
        return [n for n, t in self.objects if type_name in self.ancestors(t)]

    def envs(self, params, env):
        for values in product(*(self.of_type(p.type) for p in params)):
            yield {**env, **{p.name: v for p, v in zip(params, values)}}

    @staticmethod
    def ground_atom(a: L.Atom, env) -> Atom:
        return (a.predicate, tuple(env[t.name] if isinstance(t, L.Var) else t.name
                                   for t in a.args))

    def holds(self, f: L.Formula, env, state: set[Atom]) -> bool:
        if isinstance(f, L.Atom):
            return self.ground_atom(f, env) in state
        if isinstance(f, L.Equals):
            val = [env[t.name] if isinstance(t, L.Var) else t.name for t in (f.left, f.right)]
            return val[0] == val[1]
        if isinstance(f, L.Not):
            return not self.holds(f.arg, env, state)
        if isinstance(f, L.And):
            return all(self.holds(a, env, state) for a in f.args)
        if isinstance(f, L.Or):
            return any(self.holds(a, env, state) for a in f.args)
        if isinstance(f, L.Imply):
            return not self.holds(f.left, env, state) or self.holds(f.right, env, state)
        if isinstance(f, L.Forall):
            return all(self.holds(f.body, e, state) for e in self.envs(f.params, env))
        if isinstance(f, L.Exists):
            return any(self.holds(f.body, e, state) for e in self.envs(f.params, env))
        return f.value

    def number(self, e: L.NumExpr, env) -> Fraction:
        if isinstance(e, L.Num):
            return Fraction(e.value)
        if isinstance(e, L.FuncTerm):
            return self.values[(e.function, tuple(env[t.name] if isinstance(t, L.Var)
                                                  else t.name for t in e.args))]
        left, right = self.number(e.left, env), self.number(e.right, env)
        return {"+": left + right, "-": left - right, "*": left * right}.get(
            e.op, left / right if right else Fraction(0))

    def branches(self, e: L.Effect, env, state) -> list[Branch]:
        none = frozenset()
        if isinstance(e, L.Lit):
            atom = frozenset([self.ground_atom(e.atom, env)])
            return [(Fraction(1), atom, none, Fraction(0)) if e.positive
                    else (Fraction(1), none, atom, Fraction(0))]
        if isinstance(e, L.CostEffect):
            return [(Fraction(1), none, none, self.number(e.amount, env))]
        if isinstance(e, L.When):
            return self.branches(e.effect, env, state) if self.holds(e.condition, env, state) \
                else [(Fraction(1), none, none, Fraction(0))]
        if isinstance(e, L.Probabilistic):
            out: list[Branch] = []
            rest = Fraction(1)
            for o in e.outcomes:
                rest -= o.probability
                out += [(o.probability * p, a, d, c)
                        for p, a, d, c in self.branches(o.effect, env, state)]
            return out + ([(rest, none, none, Fraction(0))] if rest > 0 else [])
        subs = [(sub, env) for sub in e.effects] if isinstance(e, L.EffAnd) else \
            [(e.effect, inner) for inner in self.envs(e.params, env)]
        result: list[Branch] = [(Fraction(1), none, none, Fraction(0))]
        for sub, sub_env in subs:
            result = [(p * q, a | a2, d | d2, c + c2) for p, a, d, c in result
                      for q, a2, d2, c2 in self.branches(sub, sub_env, state) if p * q > 0]
        return result

    def successors(self, action: L.Action, args: tuple[str, ...],
                   state: set[Atom]) -> dict[tuple[frozenset, Fraction], Fraction]:
        """{(next state, cost of the effects): probability}; deletes before adds."""
        env = {p.name: a for p, a in zip(action.params, args)}
        out: dict[tuple[frozenset, Fraction], Fraction] = {}
        for p, adds, dels, cost in self.branches(action.effect, env, state):
            key = (frozenset((state - dels) | adds), cost)
            out[key] = out.get(key, Fraction(0)) + p
        return out
