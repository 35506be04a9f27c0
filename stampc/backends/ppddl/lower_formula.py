"""Lowering of PPDDL formulas, effects and numeric expressions to the lifted IR.

``scope`` maps variable names (without ``?``) to their types; quantifiers extend it.
Errors are collected on the :class:`Lowering` context and a best-effort value is
returned so one import reports as many problems as possible.
"""

from __future__ import annotations

from fractions import Fraction

from stampc.backends.ppddl import codes
from stampc.backends.ppddl.context import Lowering, parse_number, typed_params
from stampc.backends.ppddl.reader import Tok
from stampc.backends.ppddl.shape_base import Node
from stampc.ir.lifted import (
    TRUE, And, Atom, BinOp, Const, CostEffect, EffAnd, EffForall, Effect, Equals, Exists,
    Forall, Formula, FuncTerm, Imply, Lit, Not, Num, NumExpr, Object, Or, Outcome, Param,
    Predicate, Probabilistic, Term, Truth, Var, When,
)

FALSE = Truth(False)

Scope = dict[str, str]

#: Fluents the importer understands: PPDDL's reward and PDDL 3.1's action costs.
REWARD = "reward"
TOTAL_COST = "total-cost"


# ------------------------------------------------------------------- terms
def term(cx: Lowering, tok: Tok, scope: Scope, expected: str | None = None) -> tuple[Term, str]:
    """A term and its type (``object`` when unknown); ``expected`` is the type of the
    parameter it fills, which --lenient gives an implicit constant."""
    text = tok.text
    known = cx.const_terms.get(text)
    if known is not None:
        return known
    if text[0] == "?":
        name = text[1:]
        kind = scope.get(name)
        if kind is None:
            cx.err(codes.UNDEFINED_VARIABLE, f"undefined variable '{text}'", tok,
                   hint="variables must be action parameters or quantified")
            return Var(name), "object"
        return Var(name), kind
    obj = cx.objects.get(text)
    if obj is None:
        return Const(text), _undefined_object(cx, tok, expected)
    known = cx.const_terms[text] = (Const(text), obj.type)
    return known


def _undefined_object(cx: Lowering, tok: Tok, expected: str | None) -> str:
    name = tok.text
    if cx.lenient and cx.in_domain:
        kind = expected or "object"
        cx.objects[name] = Object(name, kind, span=cx.span(tok))
        cx.implicit_constants.add(name)
        cx.warn(codes.IMPLICIT_CONSTANT, f"'{name}' is not a declared constant; taken as a "
                f"constant of type '{kind}' (mini-gpt reads problem objects used in a domain "
                "this way)", tok)
        return kind
    cx.err(codes.UNDEFINED_OBJECT, f"undefined object or constant '{name}'", tok,
           hint=(f"declare it in (:constants ...), or {codes.LENIENT_HINT}"
                 if cx.in_domain else None))
    return "object"


def atom(cx: Lowering, node: Node, scope: Scope) -> Atom:
    """``atom`` / ``bare_atom`` node: the predicate name token, then term tokens."""
    name_tok, *arg_toks = node.children
    name = name_tok.text
    pred = cx.predicates.get(name)
    if pred is None:
        typed = [term(cx, t, scope) for t in arg_toks]
        args = tuple(t for t, _ in typed)
        _undefined_predicate(cx, name_tok, [kind for _, kind in typed])
        return Atom(name, args)
    params = pred.params
    if len(arg_toks) != len(params):
        args = tuple(term(cx, t, scope)[0] for t in arg_toks)
        cx.err(codes.ARITY, f"predicate '{name}' takes {len(params)} argument"
               f"{'' if len(params) == 1 else 's'}, got {len(args)}", node)
        return Atom(name, args)
    args = []
    for tok, param in zip(arg_toks, params):
        t, arg_type = term(cx, tok, scope, param.type)
        args.append(t)
        if arg_type != param.type and not cx.compatible(arg_type, param.type):
            cx.err(codes.TYPE_MISMATCH, f"argument {_term_text(t)} of type '{arg_type}' does "
                   f"not fit parameter ?{param.name} - {param.type} of '{name}'", tok)
    return Atom(name, tuple(args))


def _undefined_predicate(cx: Lowering, name_tok: Tok, arg_types: list[str]) -> None:
    name = name_tok.text
    if not cx.lenient:
        cx.err(codes.UNDEFINED_PREDICATE, f"undefined predicate '{name}'", name_tok,
               hint=f"declare it in (:predicates ...), or {codes.LENIENT_HINT}")
        return
    params = tuple(Param(f"x{i}", kind) for i, kind in enumerate(arg_types))
    cx.predicates[name] = Predicate(name, params, span=cx.span(name_tok))
    shown = " ".join(f"?{p.name} - {p.type}" for p in params)
    cx.warn(codes.IMPLICIT_PREDICATE, f"predicate '{name}' is used without declaration; "
            f"declared implicitly as ({name}{' ' + shown if shown else ''})", name_tok)


def _term_text(t: Term) -> str:
    return f"?{t.name}" if isinstance(t, Var) else t.name


def _extend(cx: Lowering, scope: Scope, vars_node: Node):
    params = typed_params(cx, vars_node)
    inner = dict(scope)
    inner.update({p.name: p.type for p in params})
    return params, inner


# ---------------------------------------------------------------- formulas
def formula(cx: Lowering, node: Node, scope: Scope) -> Formula:
    kind = node.data
    if kind in ("atom", "bare_atom"):
        return atom(cx, node, scope)
    if kind == "gd_true":
        return TRUE
    # Empty (and)/(or) are the constants true/false, so they survive a round trip.
    if kind == "gd_and":
        return And(tuple(formula(cx, c, scope) for c in node.children)) if node.children else TRUE
    if kind == "gd_or":
        return Or(tuple(formula(cx, c, scope) for c in node.children)) if node.children else FALSE
    if kind == "gd_not":
        return Not(formula(cx, node.children[0], scope))
    if kind == "gd_imply":
        return Imply(formula(cx, node.children[0], scope), formula(cx, node.children[1], scope))
    if kind in ("gd_forall", "gd_exists"):
        params, inner = _extend(cx, scope, node.children[0])
        body = formula(cx, node.children[1], inner)
        return Forall(params, body) if kind == "gd_forall" else Exists(params, body)
    if kind == "gd_eq":
        (left, _), (right, _) = (term(cx, c, scope) for c in node.children)
        return Equals(left, right)
    cx.err(codes.UNSUPPORTED, f"unsupported formula '{kind}'", node)
    return TRUE


# ----------------------------------------------------------------- effects
def effect(cx: Lowering, node: Node, scope: Scope) -> Effect:
    kind = node.data
    if kind in ("atom", "bare_atom"):
        return Lit(formula(cx, node, scope), True)
    if kind == "eff_empty":
        return EffAnd(())
    if kind == "eff_and":
        return EffAnd(tuple(effect(cx, c, scope) for c in node.children))
    if kind == "eff_not":
        return Lit(formula(cx, node.children[0], scope), False)
    if kind == "eff_when":
        return When(formula(cx, node.children[0], scope), effect(cx, node.children[1], scope))
    if kind == "eff_forall":
        params, inner = _extend(cx, scope, node.children[0])
        return EffForall(params, effect(cx, node.children[1], inner))
    if kind == "eff_prob":
        return probabilistic(cx, node, scope)
    if kind in ("eff_increase", "eff_decrease"):
        return cost_effect(cx, node, scope)
    cx.err(codes.UNSUPPORTED, f"unsupported effect '{kind}'", node)
    return EffAnd(())


def probabilistic(cx: Lowering, node: Node, scope: Scope) -> Probabilistic:
    outcomes = []
    total = Fraction(0)
    for outcome in node.children:
        prob_tok, eff_node = outcome.children
        p = parse_number(cx, prob_tok)
        if not 0 <= p <= 1:
            cx.err(codes.PROBABILITY_RANGE, f"probability {prob_tok} is outside [0, 1]", prob_tok)
        total += p
        outcomes.append(Outcome(p, effect(cx, eff_node, scope)))
    if total > 1:
        cx.err(codes.PROBABILITY_SUM, f"outcome probabilities sum to {_show(total)}, above 1",
               node, hint="the probabilities of one probabilistic effect must sum to at most 1")
    return Probabilistic(tuple(outcomes))


def _show(value: Fraction) -> str:
    return str(value.numerator) if value.denominator == 1 else f"{value} (= {float(value):g})"


def cost_effect(cx: Lowering, node: Node, scope: Scope) -> CostEffect:
    """``(decrease (reward) k)`` / ``(increase (total-cost) k)`` cost k; ``(increase
    (reward) k)`` cost -k."""
    fluent_node, amount_node = node.children
    fluent_tok: Tok = fluent_node.children[0]
    fluent = str(fluent_tok)
    amount = num_expr(cx, amount_node, scope)
    increase = node.data == "eff_increase"
    if fluent == REWARD:
        return CostEffect(_negate(amount) if increase else amount)
    if fluent == TOTAL_COST:
        if not increase:
            cx.err(codes.NUMERIC, "(decrease (total-cost) ...) is not allowed", node,
                   hint="action costs only increase total-cost")
        return CostEffect(amount if increase else _negate(amount))
    if fluent in cx.functions:
        cx.err(codes.NUMERIC, f"numeric effects on function '{fluent}' are not supported; "
               "only (reward) and (total-cost) may change", fluent_tok)
    else:
        cx.err(codes.UNDEFINED_FUNCTION, f"undefined numeric fluent '{fluent}'", fluent_tok,
               hint="use (reward) or (total-cost)")
    return CostEffect(amount)


def _negate(amount: NumExpr) -> NumExpr:
    if isinstance(amount, Num):
        return Num(-amount.value)
    return BinOp("-", Num(Fraction(0)), amount)


def num_expr(cx: Lowering, node: Node, scope: Scope) -> NumExpr:
    if node.data == "num":
        return Num(parse_number(cx, node.children[0]))
    if node.data == "num_binop":
        op_tok, left, right = node.children
        return BinOp(str(op_tok), num_expr(cx, left, scope), num_expr(cx, right, scope))
    name_tok: Tok = node.children[0]
    name = str(name_tok)
    args = tuple(term(cx, c, scope)[0] for c in node.children[1:])
    func = cx.functions.get(name)
    if func is None:
        cx.err(codes.UNDEFINED_FUNCTION, f"undefined numeric function '{name}'", name_tok)
    elif len(func.params) != len(args):
        cx.err(codes.ARITY, f"function '{name}' takes {len(func.params)} arguments, "
               f"got {len(args)}", node)
    return FuncTerm(name, args)
