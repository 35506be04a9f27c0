"""Lowering of a PPDDL ``(define (problem ...))`` parse tree to :class:`Problem`."""

from __future__ import annotations

from fractions import Fraction

from stampc.backends.ppddl import codes
from stampc.backends.ppddl.context import Lowering, parse_number
from stampc.backends.ppddl.lower_domain import declare_objects
from stampc.backends.ppddl.lower_formula import REWARD, TOTAL_COST, atom, formula, term
from stampc.backends.ppddl.reader import Tok
from stampc.backends.ppddl.shape_base import Node
from stampc.ir.lifted import Atom, Domain, Object, Problem, Truth

#: The metrics that mean "minimise expected cost" under stampc's cost convention.
SUPPORTED_METRICS = {("maximize", REWARD), ("minimize", TOTAL_COST)}

_KINDS = ("problem_domain", "objects", "init", "goal", "goal_reward", "metric", "horizon")


def problem_domain_name(tree: Node) -> str | None:
    """The ``(:domain X)`` a problem tree names, if any (used to pick its domain)."""
    for item in tree.children[1:]:
        if item.data == "problem_domain":
            return str(item.children[0])
    return None


def lower_problem(cx: Lowering, tree: Node, domain: Domain) -> Problem:
    """``cx`` must hold the domain's symbol tables (types, constants, predicates)."""
    name_tok, *items = tree.children
    by_kind: dict[str, list[Node]] = {k: [] for k in _KINDS}
    for item in items:
        by_kind[item.data].append(item)
    for kind, found in by_kind.items():
        if len(found) > 1 and kind != "objects":
            cx.err(codes.DUPLICATE, f"(:{kind.replace('_', '-')} ...) given twice", found[1])
    _check_domain(cx, by_kind["problem_domain"], domain, tree)
    objects: list[Object] = []
    for section in by_kind["objects"]:
        objects.extend(declare_objects(cx, section, "object"))
    init, values = _init(cx, by_kind["init"])
    goal = (formula(cx, by_kind["goal"][0].children[0], {}) if by_kind["goal"]
            else _no_goal(cx, name_tok))
    goal_reward = (parse_number(cx, by_kind["goal_reward"][0].children[0])
                   if by_kind["goal_reward"] else None)
    metric = _metric(cx, by_kind["metric"][0]) if by_kind["metric"] else None
    horizon = _horizon(cx, by_kind["horizon"][0]) if by_kind["horizon"] else None
    return Problem(
        name=str(name_tok), domain=domain.name, objects=tuple(objects), init=init,
        init_values=values, goal=goal, horizon=horizon, goal_reward=goal_reward,
        metric=metric, span=cx.span(name_tok),
    )


def _no_goal(cx: Lowering, name_tok: Tok) -> Truth:
    """mini-gpt's goal is false until (:goal ...) sets it; --lenient keeps that."""
    if cx.lenient:
        cx.warn(codes.GOAL_FALSE, f"problem '{name_tok}' has no (:goal ...); the goal is "
                "taken as false, as mini-gpt does: no state is a goal, so the task is only "
                "to avoid costs until the horizon or dead-end cost", name_tok)
    else:
        cx.err(codes.NO_GOAL, f"problem '{name_tok}' has no (:goal ...)", name_tok,
               hint=f"add (:goal ...), or {codes.LENIENT_HINT} (goal false)")
    return Truth(False)


def _check_domain(cx: Lowering, found: list[Node], domain: Domain, tree: Node) -> None:
    if not found:
        cx.err(codes.DOMAIN_MISMATCH, "problem does not name its domain with (:domain ...)",
               tree.children[0])
        return
    tok = found[0].children[0]
    if str(tok) != domain.name:
        cx.err(codes.DOMAIN_MISMATCH,
               f"problem is for domain '{tok}' but the domain read is '{domain.name}'", tok)


def _init(cx: Lowering, sections: list[Node]):
    atoms: list[Atom] = []
    values: list[tuple[Atom, Fraction]] = []
    for section in sections:
        for item in section.children:
            if item.data == "init_value":
                values.append(_init_value(cx, item))
            else:
                atoms.append(atom(cx, item, {}))
    return tuple(atoms), tuple(values)


def _init_value(cx: Lowering, node: Node) -> tuple[Atom, Fraction]:
    name_tok: Tok = node.children[0]
    args = tuple(term(cx, c, {})[0] for c in node.children[1:-1])
    func = cx.functions.get(str(name_tok))
    if func is None:
        cx.err(codes.UNDEFINED_FUNCTION, f"undefined numeric function '{name_tok}'", name_tok)
    elif len(func.params) != len(args):
        cx.err(codes.ARITY, f"function '{name_tok}' takes {len(func.params)} arguments, "
               f"got {len(args)}", node)
    return Atom(str(name_tok), args), parse_number(cx, node.children[-1])


def _metric(cx: Lowering, node: Node) -> str:
    direction_tok, fluent_node = node.children
    fluent = str(fluent_node.children[0])
    if (str(direction_tok), fluent) not in SUPPORTED_METRICS:
        cx.err(codes.NUMERIC, f"unsupported metric {direction_tok} ({fluent})", node,
               hint="use (:metric maximize (reward)) or (:metric minimize (total-cost))")
    return f"{direction_tok} ({fluent})"


def _horizon(cx: Lowering, node: Node) -> int | None:
    value = parse_number(cx, node.children[0])
    if value.denominator != 1 or value < 0:
        cx.err(codes.BAD_NUMBER, f"horizon must be a non-negative integer, got {value}", node)
        return None
    return int(value)
