"""Compile derived and symmetric predicates away: ``compile_derived(model) -> model``.

Grounding and the PPDDL emitter (unless it keeps ``:derived-predicates``) work on the
result, which has no axioms and no symmetric flags but the same reachable state space
over the other predicates (docs/ir.md, "Derived and symmetric predicates"):

- **symmetric** ``p``: every init fact and every effect literal (added, deleted or
  ``?``) of ``p(a, b)`` also applies to ``p(b, a)``, so a state holds both or neither;
- **non-recursive** derived ``p``: each atom ``p(t1, ..., tn)`` in a precondition,
  ``when`` condition, goal or other definition is replaced by the definition with its
  parameters substituted (bound variables renamed apart, so nothing is captured);
- **recursive** derived predicates (a strongly connected group of the dependency graph)
  whose definitions read only facts no action changes are evaluated once, to a
  fixpoint over the initial state, and become static predicates with those facts in
  ``init``;
- a recursive group that reads a fluent (a fact some action changes, or a derived
  predicate kept this way) needs the fixpoint in every state: its axioms stay in
  ``Domain.axioms`` (bodies with the non-recursive definitions substituted, lower
  strata first) and grounding turns them into a ground axiom program
  (:mod:`stampc.ir.axioms`) that closes every state.

Recursion must be stratified: a cycle through a negation is G121. An action effect on a
derived predicate is G122 (the code used to report recursion over a fluent, which is
now supported).
"""

from __future__ import annotations

from dataclasses import replace
from itertools import count, product
from typing import Callable, Iterable, Iterator

from stampc.diagnostics import Diagnostic, StampcError, error
from stampc.ir import lifted as L
from stampc.ir.ground_context import located

Key = tuple[str, tuple[str, ...]]


def compile_derived(model: L.Model, *, keep_axioms: bool = False) -> L.Model:
    """``model`` with derived and symmetric predicates compiled away (itself if none);
    ``keep_axioms``: only symmetric ones (for a target that reads ``:derived``)."""
    domain = model.domain
    if not domain.axioms and not any(p.symmetric or p.derived for p in domain.predicates):
        return model
    model = _mirror_symmetric(model)
    return model if keep_axioms else _expand_axioms(model)


# ---------------------------------------------------------------- symmetric
def _mirror_symmetric(model: L.Model) -> L.Model:
    symmetric = {p.name for p in model.domain.predicates if p.symmetric}
    if not symmetric:
        return model
    init = list(dict.fromkeys(model.problem.init + tuple(
        L.Atom(a.predicate, a.args[::-1]) for a in model.problem.init
        if a.predicate in symmetric and len(a.args) == 2)))
    actions = tuple(replace(a, effect=_mirror(a.effect, symmetric)) for a in model.domain.actions)
    predicates = tuple(replace(p, symmetric=False) for p in model.domain.predicates)
    domain = replace(model.domain, actions=actions, predicates=predicates)
    return replace(model, domain=domain, problem=replace(model.problem, init=tuple(init)))


def _mirror(e: L.Effect, symmetric: set[str]) -> L.Effect:
    if isinstance(e, (L.Lit, L.Unknown)):
        a = e.atom
        if a.predicate not in symmetric or len(a.args) != 2 or a.args[0] == a.args[1]:
            return e
        return L.EffAnd((e, replace(e, atom=L.Atom(a.predicate, a.args[::-1]))))
    if isinstance(e, L.EffAnd):
        return L.EffAnd(tuple(_mirror(x, symmetric) for x in e.effects))
    if isinstance(e, (L.When, L.EffForall)):
        return replace(e, effect=_mirror(e.effect, symmetric))
    if isinstance(e, L.Probabilistic):
        return L.Probabilistic(tuple(replace(o, effect=_mirror(o.effect, symmetric))
                                     for o in e.outcomes))
    return e


# ------------------------------------------------------------------- axioms
def stratify(model: L.Model) -> list[list[str]]:
    """The derived predicates of ``model`` in strata, dependencies first (for a model
    :func:`compile_derived` already checked, so no diagnostics)."""
    return _strata(_merged(model, []), model, [])


def _merged(model: L.Model, diags: list[Diagnostic]) -> dict[str, L.Axiom]:
    """One axiom per derived predicate (several rules: their disjunction), over the
    predicate's own parameter names."""
    preds = {p.name: p for p in model.domain.predicates}
    rules: dict[str, list[L.Formula]] = {}
    for ax in model.domain.axioms:
        pred = preds.get(ax.predicate)
        if pred is None or len(pred.params) != len(ax.params):
            what = "undeclared predicate" if pred is None else "predicate of another arity"
            diags.append(error("G120", f"axiom for {what} '{ax.predicate}'",
                               located(ax.span, model)))
            continue
        env = {p.name: L.Var(q.name) for p, q in zip(ax.params, pred.params)}
        rules.setdefault(ax.predicate, []).append(_substitute_vars(ax.body, env, count()))
    out = {}
    for name, bodies in rules.items():
        body = bodies[0] if len(bodies) == 1 else L.Or(tuple(bodies))
        out[name] = L.Axiom(name, preds[name].params, body, preds[name].span)
    return out


def _expand_axioms(model: L.Model) -> L.Model:
    diags: list[Diagnostic] = []
    axioms = _merged(model, diags)
    _check_not_written(model, axioms, diags)
    changed = _changed_predicates(model.domain.actions)
    defs: dict[str, L.Axiom] = {}          # non-recursive: substituted
    static_facts: set[Key] = {(a.predicate, tuple(t.name for t in a.args)) for a in model.problem.init}
    closed: set[str] = set()               # recursive: evaluated to static facts
    kept: list[L.Axiom] = []               # recursive over fluents: kept, by strata
    fresh = count()
    for group in _strata(axioms, model, diags):
        if len(group) == 1 and group[0] not in _reads(axioms[group[0]].body):
            name = group[0]
            defs[name] = replace(axioms[name], body=_substitute(axioms[name].body, defs, fresh))
            continue
        bodies = {n: _substitute(axioms[n].body, defs, fresh) for n in group}
        if {p for b in bodies.values() for p in _reads(b)} & changed:
            # recursion through a fluent: a per-state fixpoint, kept as axioms for
            # grounding (stampc.ir.axioms); lower strata stay ahead of it in ``kept``
            kept.extend(replace(axioms[n], body=bodies[n]) for n in group)
            changed.update(group)
            continue
        static_facts |= _fixpoint(bodies, axioms, model, static_facts)
        closed.update(group)
    if diags:
        raise StampcError(diags)
    return _rewrite(model, defs, closed, static_facts, fresh, tuple(kept))


def _check_not_written(model: L.Model, axioms: dict[str, L.Axiom],
                       diags: list[Diagnostic]) -> None:
    """G122: an effect on a derived predicate (stamp reports E311 earlier; PPDDL's
    ``:derived`` section does not stop an action from writing the predicate)."""
    for action in model.domain.actions:
        written = sorted(_changed_predicates((action,)) & set(axioms))
        if written:
            diags.append(error("G122", f"action '{action.name}' writes derived predicate "
                               f"'{written[0]}'", located(action.span, model),
                               "derived facts follow from their axioms in every state; "
                               "change the facts the definition reads instead"))


def _rewrite(model: L.Model, defs: dict[str, L.Axiom], closed: set[str], facts: set[Key],
             fresh: Iterator[int], kept: tuple[L.Axiom, ...]) -> L.Model:
    sub = lambda f: _substitute(f, defs, fresh)  # noqa: E731
    actions = tuple(replace(a, precondition=sub(a.precondition), effect=_effect_conditions(a.effect, sub))
                    for a in model.domain.actions)
    recursive = {ax.predicate for ax in kept}
    predicates = tuple(replace(p, derived=p.name in recursive, static=p.static or p.name in closed)
                       for p in model.domain.predicates if p.name not in defs)
    domain = replace(model.domain, actions=actions, predicates=predicates, axioms=kept)
    init = model.problem.init + tuple(L.Atom(p, tuple(L.Const(x) for x in args))
                                      for p, args in sorted(facts) if p in closed)
    problem = replace(model.problem, init=init, goal=sub(model.problem.goal))
    return replace(model, domain=domain, problem=problem)


def _effect_conditions(e: L.Effect, sub) -> L.Effect:
    if isinstance(e, L.When):
        return L.When(sub(e.condition), _effect_conditions(e.effect, sub))
    if isinstance(e, L.EffAnd):
        return L.EffAnd(tuple(_effect_conditions(x, sub) for x in e.effects))
    if isinstance(e, L.EffForall):
        return replace(e, effect=_effect_conditions(e.effect, sub))
    if isinstance(e, L.Probabilistic):
        return L.Probabilistic(tuple(replace(o, effect=_effect_conditions(o.effect, sub))
                                     for o in e.outcomes))
    return e


def _changed_predicates(actions: Iterable[L.Action]) -> set[str]:
    out: set[str] = set()
    stack: list[L.Effect] = [a.effect for a in actions]
    while stack:
        e = stack.pop()
        if isinstance(e, (L.Lit, L.Unknown)):
            out.add(e.atom.predicate)
        elif isinstance(e, L.EffAnd):
            stack.extend(e.effects)
        elif isinstance(e, (L.When, L.EffForall)):
            stack.append(e.effect)
        elif isinstance(e, L.Probabilistic):
            stack.extend(o.effect for o in e.outcomes)
    return out


def _reads(f: L.Formula, positive: bool = True) -> dict[str, set[bool]]:
    """Predicate -> polarities of its atoms in ``f``."""
    out: dict[str, set[bool]] = {}
    stack: list[tuple[L.Formula, bool]] = [(f, positive)]
    while stack:
        node, pol = stack.pop()
        if isinstance(node, L.Atom):
            out.setdefault(node.predicate, set()).add(pol)
        elif isinstance(node, L.Not):
            stack.append((node.arg, not pol))
        elif isinstance(node, (L.And, L.Or)):
            stack.extend((a, pol) for a in node.args)
        elif isinstance(node, L.Imply):
            stack.extend([(node.left, not pol), (node.right, pol)])
        elif isinstance(node, (L.Forall, L.Exists)):
            stack.append((node.body, pol))
    return out


def _strata(axioms: dict[str, L.Axiom], model: L.Model, diags: list[Diagnostic]) -> list[list[str]]:
    """Strongly connected groups of derived predicates, dependencies first (Tarjan);
    G121 for a group with a negative edge inside it (not stratified)."""
    graph = {n: {p: pols for p, pols in _reads(a.body).items() if p in axioms}
             for n, a in axioms.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    groups: list[list[str]] = []

    def visit(v: str) -> None:  # depth is bounded by the number of derived predicates
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                group.append(w)
                if w == v:
                    break
            groups.append(sorted(group))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    for group in groups:
        if any(False in graph[v].get(w, ()) for v in group for w in group):
            diags.append(error("G121", f"derived predicate '{group[0]}' depends on itself through "
                               "a negation (not stratified)", located(axioms[group[0]].span, model)))
    return groups


# ------------------------------------------------------------ substitution
def _substitute(f: L.Formula, defs: dict[str, L.Axiom], fresh: Iterator[int]) -> L.Formula:
    """``f`` with every atom of a predicate in ``defs`` replaced by its definition."""
    if not defs:
        return f
    if isinstance(f, L.Atom):
        ax = defs.get(f.predicate)
        if ax is None:
            return f
        env = {p.name: t for p, t in zip(ax.params, f.args)}
        return _substitute_vars(ax.body, env, fresh)
    if isinstance(f, (L.Forall, L.Exists)):
        return type(f)(f.params, _substitute(f.body, defs, fresh))
    return _map_connective(f, lambda g: _substitute(g, defs, fresh))


def _substitute_vars(f: L.Formula, env: dict[str, L.Term], fresh: Iterator[int]) -> L.Formula:
    """``f`` with free variables replaced by ``env``; bound variables get fresh names
    (``c`` becomes ``c__d3``), so an argument named like one is never captured."""
    if isinstance(f, L.Atom):
        return L.Atom(f.predicate, tuple(_term(t, env) for t in f.args))
    if isinstance(f, L.Equals):
        return L.Equals(_term(f.left, env), _term(f.right, env))
    if isinstance(f, (L.Forall, L.Exists)):
        n = next(fresh)
        params = tuple(L.Param(f"{p.name}__d{n}", p.type) for p in f.params)
        inner = {**env, **{p.name: L.Var(q.name) for p, q in zip(f.params, params)}}
        return type(f)(params, _substitute_vars(f.body, inner, fresh))
    return _map_connective(f, lambda g: _substitute_vars(g, env, fresh))


def _map_connective(f: L.Formula, sub: Callable[[L.Formula], L.Formula]) -> L.Formula:
    """``f`` with ``sub`` applied to the operands of its connective (not, and, or,
    implies); any other formula as it is."""
    if isinstance(f, L.Not):
        return L.Not(sub(f.arg))
    if isinstance(f, (L.And, L.Or)):
        return type(f)(tuple(sub(a) for a in f.args))
    if isinstance(f, L.Imply):
        return L.Imply(sub(f.left), sub(f.right))
    return f


def _term(t: L.Term, env: dict[str, L.Term]) -> L.Term:
    return env.get(t.name, t) if isinstance(t, L.Var) else t


# --------------------------------------------------------------- fixpoint
def _fixpoint(bodies: dict[str, L.Formula], axioms: dict[str, L.Axiom], model: L.Model,
              facts: set[Key]) -> set[Key]:
    """The least set of facts of the group's predicates closed under their definitions
    (naive iteration; the group is positive, lower strata are already in ``facts``)."""
    objects = _objects_by_type(model)
    facts = set(facts)
    new: set[Key] = set()
    changed = True
    while changed:
        changed = False
        for name, body in bodies.items():
            params = axioms[name].params
            for args in product(*(objects.get(p.type, ()) for p in params)):
                key = (name, args)
                if key in facts:
                    continue
                env = {p.name: a for p, a in zip(params, args)}
                if _holds(body, env, facts, objects):
                    facts.add(key)
                    new.add(key)
                    changed = True
    return new


def _objects_by_type(model: L.Model) -> dict[str, list[str]]:
    parents = {t.name: t.parent for t in model.domain.types}
    out: dict[str, list[str]] = {"object": []}
    for o in (*model.domain.constants, *model.problem.objects):
        t: str | None = o.type
        seen: set[str] = set()
        while t is not None and t not in seen:
            seen.add(t)
            out.setdefault(t, []).append(o.name)
            t = parents.get(t)
        if "object" not in seen:
            out["object"].append(o.name)
    return {t: list(dict.fromkeys(names)) for t, names in out.items()}


def _holds(f: L.Formula, env: dict[str, str], facts: set[Key], objects) -> bool:
    if isinstance(f, L.Atom):
        return (f.predicate, tuple(env.get(t.name, t.name) if isinstance(t, L.Var) else t.name
                                   for t in f.args)) in facts
    if isinstance(f, L.Equals):
        name = lambda t: env.get(t.name, t.name) if isinstance(t, L.Var) else t.name  # noqa: E731
        return name(f.left) == name(f.right)
    if isinstance(f, L.Not):
        return not _holds(f.arg, env, facts, objects)
    if isinstance(f, L.And):
        return all(_holds(a, env, facts, objects) for a in f.args)
    if isinstance(f, L.Or):
        return any(_holds(a, env, facts, objects) for a in f.args)
    if isinstance(f, L.Imply):
        return not _holds(f.left, env, facts, objects) or _holds(f.right, env, facts, objects)
    if isinstance(f, (L.Forall, L.Exists)):
        combos = (dict(zip((p.name for p in f.params), c))
                  for c in product(*(objects.get(p.type, ()) for p in f.params)))
        test = all if isinstance(f, L.Forall) else any
        return test(_holds(f.body, {**env, **c}, facts, objects) for c in combos)
    if isinstance(f, L.Truth):
        return f.value
    return False
