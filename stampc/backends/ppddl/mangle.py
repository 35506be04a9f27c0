"""Name mangling: any lifted-IR name → a legal, unambiguous PDDL name.

Scheme (deterministic; documented in docs/ppddl.md):

1. lower-case (PPDDL is case-insensitive);
2. every character outside ``[a-z0-9_-]`` becomes ``_``;
3. a name not starting with a letter gets the prefix ``x``;
4. a reserved PPDDL word gets the suffix ``_``;
5. collisions inside one namespace are resolved with ``-2``, ``-3``, ... in declaration
   order; names that are already legal always keep their spelling.

Namespaces: types, predicates + functions, actions, objects (constants, problem objects,
extra objects), and the variables of each action / generator / goal. Every renaming is
listed in a ``; renamed`` comment of the emitted text, so the mapping can be reversed.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from typing import Iterable

from stampc.backends.ppddl.rename import Renaming, effect_vars, formula_vars
from stampc.ir.lifted import (
    Action, Atom, Axiom, Domain, Evaluator, Generator, GeneratorUse, Model, Object,
)

_LEGAL = re.compile(r"[a-z][a-z0-9_-]*\Z")
_ILLEGAL_CHAR = re.compile(r"[^a-z0-9_-]")

#: Words a PPDDL reader may treat as keywords where a name is expected.
RESERVED = frozenset({
    "and", "or", "not", "imply", "forall", "exists", "when", "probabilistic", "increase",
    "decrease", "assign", "either", "define", "domain", "problem", "reward", "total-cost",
    "oneof",
})


def legal_name(name: str) -> str:
    """Steps 1-4 of the scheme (no collision handling)."""
    out = _ILLEGAL_CHAR.sub("_", name.lower())
    if not out or not out[0].isalpha() or not out[0].isascii():
        out = "x" + out
    if out in RESERVED:
        out += "_"
    return out


def is_legal(name: str) -> bool:
    return bool(_LEGAL.match(name)) and name not in RESERVED


class NameTable:
    """One namespace's mapping, built in one go so that legal names keep priority."""

    def __init__(self, names: Iterable[str]):
        ordered = list(dict.fromkeys(names))
        self.mapping: dict[str, str] = {n: n for n in ordered if is_legal(n)}
        used = set(self.mapping.values())
        for name in ordered:
            if name in self.mapping:
                continue
            base = candidate = legal_name(name)
            k = 2
            while candidate in used:
                candidate, k = f"{base}-{k}", k + 1
            self.mapping[name] = candidate
            used.add(candidate)

    def __call__(self, name: str) -> str:
        # Names outside the table (undeclared in the IR) still come out legal.
        return self.mapping.get(name) or legal_name(name)

    def renamed(self) -> list[tuple[str, str]]:
        return [(a, b) for a, b in self.mapping.items() if a != b]


@dataclass(frozen=True)
class Mangled:
    model: Model
    #: (namespace, original, emitted) for every name that changed
    renames: tuple[tuple[str, str, str], ...]


def mangle_model(model: Model, extra_objects: Iterable[Object] = (),
                 extra_init: Iterable[Atom] = ()) -> Mangled:
    """A copy of ``model`` (with ``extra_objects``/``extra_init`` appended to the
    problem) whose every name is legal PPDDL."""
    d, p = model.domain, model.problem
    p = replace(p, objects=p.objects + tuple(extra_objects), init=p.init + tuple(extra_init))
    types = NameTable(["object"] + [t.name for t in d.types])
    preds = NameTable([x.name for x in d.predicates] + [f.name for f in d.functions])
    actions = NameTable(a.name for a in d.actions)
    objects = NameTable([o.name for o in d.constants] + [o.name for o in p.objects])
    base = Renaming(predicate=preds, function=preds, obj=objects, type=types)
    renames = [("type", a, b) for a, b in types.renamed()]
    renames += [("predicate", a, b) for a, b in preds.renamed()]
    renames += [("action", a, b) for a, b in actions.renamed()]
    renames += [("object", a, b) for a, b in objects.renamed()]

    def objs(items: tuple[Object, ...]) -> tuple[Object, ...]:
        return tuple(replace(o, name=objects(o.name), type=types(o.type)) for o in items)

    domain = Domain(
        name=legal_name(d.name),
        types=tuple(replace(t, name=types(t.name),
                            parent=None if t.parent is None else types(t.parent))
                    for t in d.types),
        constants=objs(d.constants),
        predicates=tuple(replace(x, name=preds(x.name), params=_params(base, x.params))
                         for x in d.predicates),
        functions=tuple(replace(f, name=preds(f.name), params=_params(base, f.params))
                        for f in d.functions),
        actions=tuple(_action(base, actions, a) for a in d.actions),
        generators=tuple(_generator(base, g) for g in d.generators),
        evaluators=tuple(Evaluator(preds(e.predicate), e.binding, e.span) for e in d.evaluators),
        requirements=d.requirements,
        span=d.span,
        axioms=tuple(_axiom(base, x) for x in d.axioms),
    )
    goal_vars = Renaming(predicate=preds, function=preds, obj=objects, type=types,
                         var=NameTable(formula_vars(p.goal)))
    problem = replace(
        p, name=legal_name(p.name), domain=domain.name, objects=objs(p.objects),
        init=tuple(base.atom(a) for a in p.init),
        init_values=tuple((base.atom(a), v) for a, v in p.init_values),
        goal=goal_vars.formula(p.goal),
    )
    return Mangled(Model(domain, problem), tuple(renames))


def _params(r: Renaming, params):
    """Declaration parameters: variable names are made legal individually."""
    table = NameTable(q.name for q in params)
    return tuple(replace(q, name=table(q.name), type=r.type(q.type)) for q in params)


def _action(base: Renaming, actions: NameTable, a: Action) -> Action:
    names = [q.name for q in a.params] + formula_vars(a.precondition) + effect_vars(a.effect)
    r = replace(base, var=NameTable(names))
    return replace(
        a, name=actions(a.name), params=r.params(a.params),
        precondition=r.formula(a.precondition), effect=r.effect(a.effect),
        cost=None if a.cost is None else r.num(a.cost),
        generated=tuple(GeneratorUse(g.generator, tuple(r.var(x) for x in g.inputs),
                                     tuple(r.var(x) for x in g.outputs)) for g in a.generated),
    )


def _axiom(base: Renaming, a: Axiom) -> Axiom:
    r = replace(base, var=NameTable([q.name for q in a.params] + formula_vars(a.body)))
    return replace(a, predicate=base.predicate(a.predicate), params=r.params(a.params),
                   body=r.formula(a.body))


def _generator(base: Renaming, g: Generator) -> Generator:
    r = replace(base, var=NameTable([q.name for q in g.inputs + g.outputs]))
    return replace(g, inputs=r.params(g.inputs), outputs=r.params(g.outputs),
                   certifies=tuple(r.atom(x) for x in g.certifies))
