"""Lowering of a PPDDL ``(define (domain ...))`` parse tree to :class:`Domain`.

Sections may appear in any order (IPPC drive declares ``:constants`` after
``:predicates``), so they are processed by kind: requirements, types, constants,
predicates, functions, then actions.
"""

from __future__ import annotations

from dataclasses import replace

from stampc.backends.ppddl import codes
from stampc.backends.ppddl.context import ROOT_TYPE, Lowering, typed_items, typed_params
from stampc.backends.ppddl.lower_formula import effect, formula
from stampc.backends.ppddl.reader import Tok
from stampc.backends.ppddl.shape_base import Node
from stampc.ir.lifted import (
    NO_EFFECT, TRUE, Action, Axiom, Domain, EffAnd, EffForall, Effect, Function, Object,
    Predicate, Probabilistic, Type, Lit, Unknown, When,
)

#: Requirement flags of the IPPC PPDDL dialect (plus PDDL 3.1 action costs).
KNOWN_REQUIREMENTS = frozenset({
    ":strips", ":typing", ":equality", ":negative-preconditions",
    ":disjunctive-preconditions", ":existential-preconditions",
    ":universal-preconditions", ":quantified-preconditions", ":conditional-effects",
    ":adl", ":probabilistic-effects", ":rewards", ":mdp", ":action-costs",
    ":fluents", ":numeric-fluents", ":derived-predicates",
})
UNSUPPORTED_REQUIREMENTS = frozenset({
    ":durative-actions", ":timed-initial-literals",
    ":preferences", ":constraints", ":duration-inequalities", ":continuous-effects",
    ":non-deterministic", ":partial-observability", ":object-fluents",
})
#: What a domain without (:requirements ...) implicitly requires.
DEFAULT_REQUIREMENTS = (":strips",)

_SECTION_ORDER = ("requirements", "types", "constants", "predicates", "functions", "derived",
                  "action")


def lower_domain(cx: Lowering, tree: Node) -> Domain:
    name_tok, *items = tree.children
    by_kind: dict[str, list[Node]] = {k: [] for k in _SECTION_ORDER}
    for item in items:
        by_kind[item.data].append(item)
    requirements = _requirements(cx, by_kind["requirements"])
    cx.types.setdefault(ROOT_TYPE, Type(ROOT_TYPE))
    for section in by_kind["types"]:
        _types(cx, section)
    cx._ancestors.clear()  # the hierarchy is final from here on
    for section in by_kind["constants"]:
        declare_objects(cx, section, "constant")
    for section in by_kind["predicates"]:
        _predicates(cx, section)
    for section in by_kind["functions"]:
        _functions(cx, section)
    actions = _actions(cx, by_kind["action"])
    axioms = tuple(_axiom(cx, node) for node in by_kind["derived"])
    derived = {a.predicate for a in axioms}
    predicates = _mark_static(tuple(replace(p, derived=p.name in derived)
                                    for p in cx.predicates.values()), actions)
    cx.predicates = {p.name: p for p in predicates}
    return Domain(
        name=str(name_tok),
        types=tuple(cx.types.values()),
        constants=tuple(cx.objects.values()),
        predicates=predicates,
        functions=tuple(cx.functions.values()),
        actions=actions,
        requirements=requirements,
        span=cx.span(name_tok),
        axioms=axioms,
    )


# ----------------------------------------------------------- declarations
def _requirements(cx: Lowering, sections: list[Node]) -> tuple[str, ...]:
    if not sections:
        return DEFAULT_REQUIREMENTS
    flags: list[str] = []
    for section in sections:
        for tok in section.children:
            flag = str(tok)
            if flag in UNSUPPORTED_REQUIREMENTS:
                cx.err(codes.REQUIREMENT, f"unsupported requirement {flag}", tok,
                       hint="stampc reads the IPPC PPDDL dialect; see docs/ppddl.md")
            elif flag not in KNOWN_REQUIREMENTS:
                cx.err(codes.REQUIREMENT, f"unknown requirement {flag}", tok)
            if flag not in flags:
                flags.append(flag)
    return tuple(flags)


def _types(cx: Lowering, section: Node) -> None:
    """Declared types in order; parents used but not declared are added (parent object)."""
    implicit: dict[str, Tok] = {}
    for tok, parent, spec in typed_items(cx, section.children[0]):
        name = str(tok)
        if name == ROOT_TYPE:
            continue
        if name in cx.types:
            cx.err(codes.DUPLICATE, f"type '{name}' declared twice", tok)
            continue
        cx.types[name] = Type(name, parent, span=cx.span(tok))
        if isinstance(spec, Tok) and parent != ROOT_TYPE:
            implicit.setdefault(parent, spec)
    for parent, tok in implicit.items():
        if parent not in cx.types:
            cx.types[parent] = Type(parent, ROOT_TYPE, span=cx.span(tok))
    _check_cycles(cx)


def _check_cycles(cx: Lowering) -> None:
    for t in list(cx.types.values()):
        seen = {t.name}
        parent = t.parent
        while parent is not None and parent in cx.types:
            if parent in seen:
                cx.err(codes.TYPE_CYCLE, f"type '{t.name}' is its own ancestor",
                       t.span or cx.span(None))
                cx.types[t.name] = replace(t, parent=ROOT_TYPE)
                break
            seen.add(parent)
            parent = cx.types[parent].parent


def declare_objects(cx: Lowering, section: Node, what: str) -> list[Object]:
    """Constants (domain) or objects (problem); both live in ``cx.objects``."""
    declared = []
    for tok, type_name, spec in typed_items(cx, section.children[0]):
        name = str(tok)
        if isinstance(spec, Tok):
            cx.check_type(spec)
        if name in cx.implicit_constants and not cx.in_domain:
            # --lenient made it a constant (P202), as mini-gpt does; the declared type wins
            cx.objects[name] = replace(cx.objects[name], type=type_name)
            continue
        if name in cx.objects:
            cx.err(codes.DUPLICATE, f"{what} '{name}' declared twice", tok)
            continue
        obj = Object(name, type_name, span=cx.span(tok))
        cx.objects[name] = obj
        declared.append(obj)
    return declared


def _predicates(cx: Lowering, section: Node) -> None:
    for decl in section.children:
        name_tok, vars_node = decl.children
        name = str(name_tok)
        params = typed_params(cx, vars_node, declaration=True)
        if name in cx.predicates:
            cx.err(codes.DUPLICATE, f"predicate '{name}' declared twice", name_tok)
            continue
        cx.predicates[name] = Predicate(name, params, span=cx.span(name_tok))


def _functions(cx: Lowering, section: Node) -> None:
    """Static numeric functions; ``(reward)``/``(total-cost)`` are built in, not recorded."""
    for decl in section.children:
        if decl.data != "atom_decl":
            continue  # a "- number" type mark
        name_tok, vars_node = decl.children
        name = str(name_tok)
        params = typed_params(cx, vars_node, declaration=True)
        if name in ("reward", "total-cost"):
            continue
        if name in cx.functions:
            cx.err(codes.DUPLICATE, f"function '{name}' declared twice", name_tok)
            continue
        cx.functions[name] = Function(name, params, span=cx.span(name_tok))


# ---------------------------------------------------------------- actions
def _actions(cx: Lowering, sections: list[Node]) -> tuple[Action, ...]:
    actions: dict[str, Action] = {}
    for node in sections:
        action = _action(cx, node)
        if action.name in actions:
            cx.err(codes.DUPLICATE, f"action '{action.name}' declared twice", node.children[0])
            continue
        actions[action.name] = action
    return tuple(actions.values())


def _action(cx: Lowering, node: Node) -> Action:
    name_tok, *parts = node.children
    by_kind: dict[str, list[Node]] = {"parameters": [], "precondition": [], "effect_part": []}
    for part in parts:
        by_kind[part.data].append(part)
    for kind, found in by_kind.items():
        if len(found) > 1:
            keyword = ":effect" if kind == "effect_part" else f":{kind}"
            cx.err(codes.DUPLICATE, f"{keyword} given twice in action '{name_tok}'", found[1])
    params = typed_params(cx, by_kind["parameters"][0].children[0]) if by_kind["parameters"] else ()
    scope = {p.name: p.type for p in params}
    precondition = (formula(cx, by_kind["precondition"][0].children[0], scope)
                    if by_kind["precondition"] else TRUE)
    eff = (effect(cx, by_kind["effect_part"][0].children[0], scope)
           if by_kind["effect_part"] else NO_EFFECT)
    return Action(str(name_tok), params, precondition, eff, cost=None, span=cx.span(name_tok))


def _axiom(cx: Lowering, node: Node) -> Axiom:
    """``(:derived (p ?x - t) GD)``: a rule of a declared predicate (P102 otherwise);
    stratification is checked when the model is grounded (G121)."""
    decl, body = node.children
    name_tok, typed = decl.children
    params = typed_params(cx, typed)
    pred = cx.predicates.get(str(name_tok))
    if pred is None:
        cx.err(codes.UNDEFINED_PREDICATE, f"derived predicate '{name_tok}' is not declared in :predicates",
               name_tok)
    elif len(pred.params) != len(params):
        cx.err(codes.ARITY, f"derived predicate '{name_tok}' takes {len(pred.params)} "
               f"argument(s), the rule has {len(params)}", name_tok)
    scope = {p.name: p.type for p in params}
    return Axiom(str(name_tok), params, formula(cx, body, scope), cx.span(name_tok))


def changed_predicates(eff: Effect) -> set[str]:
    """Predicates some literal (or ``?``) effect in ``eff`` mentions."""
    if isinstance(eff, (Lit, Unknown)):
        return {eff.atom.predicate}
    if isinstance(eff, EffAnd):
        return set().union(*(changed_predicates(e) for e in eff.effects))
    if isinstance(eff, (When, EffForall)):
        return changed_predicates(eff.effect)
    if isinstance(eff, Probabilistic):
        return set().union(*(changed_predicates(o.effect) for o in eff.outcomes))
    return set()


def _mark_static(predicates: tuple[Predicate, ...],
                 actions: tuple[Action, ...]) -> tuple[Predicate, ...]:
    changed = set().union(*(changed_predicates(a.effect) for a in actions))
    return tuple(replace(p, static=p.name not in changed and not p.derived) for p in predicates)
