"""JSON codec for lifted domains, problems and models (built on :mod:`json_lifted`).

:func:`write_lifted` streams a document: one action per line, so a 165k-action domain
is never held as one dict or one string.
"""

from __future__ import annotations

import json
from dataclasses import replace
from typing import Any, Callable

from stampc.ir import lifted as L
from stampc.ir.json_lifted import (
    J, _with_span, action_from, action_to, atom_from, atom_to, binding_from, binding_to,
    frac_from, frac_to, generator_from, generator_to, pairs_from, pairs_to, params_from,
    params_to, span_from)
from stampc.ir.json_tree import TreeDecoder, TreeEncoder

Write = Callable[[str], Any]


def compact(x: Any) -> str:
    """One JSON value as compact text (the IR writers' single formatting choice)."""
    return json.dumps(x, separators=(",", ":"))


def write_items(write: Write, texts) -> None:
    """A JSON array of already-encoded items, one per line."""
    write("[")
    sep = "\n"
    for text in texts:
        write(sep)
        write(text)
        sep = ",\n"
    write("]")


def _object_to(o: L.Object) -> J:
    return _with_span({"name": o.name, "type": o.type, "symbolic": o.symbolic}, o.span)


def _object_from(x: J) -> L.Object:
    return L.Object(str(x["name"]), str(x["type"]), bool(x.get("symbolic", False)),
                    span_from(x.get("span")))


def domain_to(d: L.Domain, trees: TreeEncoder) -> J:
    return _with_span({
        "name": d.name,
        "types": [_with_span({"name": t.name, "parent": t.parent, "continuous": t.continuous},
                             t.span) for t in d.types],
        "constants": [_object_to(o) for o in d.constants],
        "predicates": [_with_span({"name": p.name, "params": params_to(p.params),
                                   "static": p.static, "unknowable": p.unknowable,
                                   "optimistic": p.optimistic, "symmetric": p.symmetric,
                                   "derived": p.derived}, p.span)
                       for p in d.predicates],
        "axioms": [_with_span({"predicate": a.predicate, "params": params_to(a.params),
                               "body": trees.encode(a.body)}, a.span) for a in d.axioms],
        "functions": [_with_span({"name": f.name, "params": params_to(f.params)}, f.span)
                      for f in d.functions],
        "actions": [action_to(a, trees) for a in d.actions],
        "generators": [generator_to(g) for g in d.generators],
        "evaluators": [_with_span({"predicate": e.predicate, "binding": binding_to(e.binding)},
                                  e.span) for e in d.evaluators],
        "requirements": list(d.requirements)}, d.span)


def domain_from(x: J, trees: TreeDecoder) -> L.Domain:
    return L.Domain(
        name=str(x["name"]),
        types=tuple(L.Type(str(t["name"]), t.get("parent"), bool(t.get("continuous", False)),
                           span_from(t.get("span"))) for t in x["types"]),
        constants=tuple(_object_from(o) for o in x["constants"]),
        predicates=tuple(L.Predicate(str(p["name"]), params_from(p["params"]),
                                     bool(p.get("static", False)),
                                     bool(p.get("unknowable", False)),
                                     bool(p.get("optimistic", False)),
                                     span_from(p.get("span")), bool(p.get("symmetric", False)),
                                     bool(p.get("derived", False))) for p in x["predicates"]),
        functions=tuple(L.Function(str(f["name"]), params_from(f["params"]),
                                   span_from(f.get("span"))) for f in x["functions"]),
        actions=tuple(action_from(a, trees) for a in x["actions"]),
        generators=tuple(generator_from(g) for g in x.get("generators", ())),
        evaluators=tuple(L.Evaluator(str(e["predicate"]), binding_from(e["binding"]),
                                     span_from(e.get("span")))
                         for e in x.get("evaluators", ())),
        requirements=tuple(str(r) for r in x.get("requirements", ())),
        span=span_from(x.get("span")),
        axioms=tuple(L.Axiom(str(a["predicate"]), params_from(a["params"]),
                             trees.formula(a["body"]), span_from(a.get("span")))
                     for a in x.get("axioms", ())))


def problem_to(p: L.Problem, trees: TreeEncoder) -> J:
    scene = None if p.scene is None else _with_span(
        {"kind": p.scene.kind, "target": p.scene.target, "args": pairs_to(p.scene.args)},
        p.scene.span)
    return _with_span({
        "name": p.name, "domain": p.domain,
        "objects": [_object_to(o) for o in p.objects],
        "init": [atom_to(a) for a in p.init],
        "init_values": [[atom_to(a), frac_to(v)] for a, v in p.init_values],
        "goal": trees.encode(p.goal), "horizon": p.horizon, "scene": scene,
        "goal_reward": None if p.goal_reward is None else frac_to(p.goal_reward),
        "metric": p.metric}, p.span)


def problem_from(x: J, trees: TreeDecoder) -> L.Problem:
    s = x.get("scene")
    scene = None if s is None else L.SceneRef(str(s["kind"]), str(s["target"]),
                                              pairs_from(s.get("args", [])),
                                              span_from(s.get("span")))
    horizon = x.get("horizon")
    if horizon is not None and (isinstance(horizon, bool) or not isinstance(horizon, int)):
        raise TypeError(f"horizon must be an integer, got {horizon!r}")
    reward = x.get("goal_reward")
    return L.Problem(
        name=str(x["name"]), domain=str(x["domain"]),
        objects=tuple(_object_from(o) for o in x["objects"]),
        init=tuple(atom_from(a) for a in x["init"]),
        init_values=tuple((atom_from(a), frac_from(v)) for a, v in x.get("init_values", ())),
        goal=trees.formula(x["goal"]), horizon=horizon, scene=scene,
        goal_reward=None if reward is None else frac_from(reward),
        metric=x.get("metric"), span=span_from(x.get("span")))


def write_lifted(model: L.Model, header: J, write: Write) -> None:
    """Stream the lifted document: ``header`` fields, domain, problem, subtrees."""
    trees = TreeEncoder()
    domain = domain_to(replace(model.domain, actions=()), trees)
    del domain["actions"]
    write(compact(header)[:-1] + ',\n"domain":' + compact(domain)[:-1] + ',"actions":')
    write_items(write, (compact(action_to(a, trees)) for a in model.domain.actions))
    write('},\n"problem":' + compact(problem_to(model.problem, trees)) + ',\n"subtrees":')
    write_items(write, (compact(t) for t in trees.subtrees))
    write("}")


def read_lifted(data: J) -> L.Model:
    """The model of a lifted document whose header has been checked."""
    trees = TreeDecoder(data.get("subtrees", []))
    return L.Model(domain_from(data["domain"], trees), problem_from(data["problem"], trees))
