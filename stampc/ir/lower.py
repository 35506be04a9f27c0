"""Lowering a checked stamp program (:class:`LoadedProgram`) to the lifted IR.

Follows docs/architecture.md: continuous types and symbolic objects, ``unknowable``
predicates with their ``optimistic`` value, factored effects, default cost 1, and
``Action.generated`` from the front end's generator inference (dependency order).
"""

from __future__ import annotations

from fractions import Fraction

from stampc.diagnostics import Diagnostic, Span, StampcError
from stampc.ir import lifted as ir
from stampc.gcpause import no_gc_pauses
from stampc.semantics.analysis import domain_facts, optimistic_values
from stampc.semantics.api import LoadedProgram
from stampc.semantics.check_problem import ProblemInfo
from stampc.semantics.codes import diag
from stampc.semantics.scope import DomainInfo
from stampc.syntax import ast

DEFAULT_COST = ir.Num(Fraction(1))


class _Unlowerable(Exception):
    def __init__(self, diagnostic: Diagnostic):
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic


def lower(loaded: LoadedProgram) -> ir.Model:
    """Domain + problem → :class:`lifted.Model`; raises :class:`StampcError` on errors."""
    with no_gc_pauses():  # the collector made lowering non-linear (8k actions: 5x CPU)
        return _lower(loaded)


def _lower(loaded: LoadedProgram) -> ir.Model:
    _require_clean(loaded)
    if loaded.problem is None or loaded.domain is None:
        span = loaded.domain.span if loaded.domain else Span.point("<input>")
        raise StampcError([diag("E501", "no problem to lower: the input holds only a domain", span,
                                "add `problem NAME for DOMAIN` or pass the problem file")])
    try:
        domain = _domain(loaded, loaded.problem.goal)
        return ir.Model(domain, _problem(loaded.problem, loaded.domain))
    except _Unlowerable as exc:
        raise StampcError([exc.diagnostic]) from None


def lower_domain(loaded: LoadedProgram) -> ir.Domain:
    """The domain alone (``optimistic`` values from preconditions, plus the goal if a
    problem was loaded)."""
    _require_clean(loaded)
    if loaded.domain is None:
        raise StampcError([diag("E501", "no domain to lower", Span.point("<input>"))])
    try:
        return _domain(loaded, loaded.problem.goal if loaded.problem else None)
    except _Unlowerable as exc:
        raise StampcError([exc.diagnostic]) from None


def _require_clean(loaded: LoadedProgram) -> None:
    if loaded.has_errors:
        raise StampcError(loaded.diagnostics)


# ------------------------------------------------------------------- domain
def _domain(loaded: LoadedProgram, goal: ast.Formula | None) -> ir.Domain:
    info = loaded.domain
    assert info is not None
    facts = domain_facts(info)
    optimistic = optimistic_values(info, goal)
    types = tuple(ir.Type(t.name, t.parent, info.is_continuous(t.name), t.ident.span)
                  for t in info.types.values())
    constants = tuple(ir.Object(c.name, c.type, info.is_continuous(c.type), c.ident.span)
                      for c in info.constants.values())
    predicates = tuple(
        ir.Predicate(p.name.name, _params(p.params), p.static, p.name.name in facts.effects.unknown,
                     optimistic.get(p.name.name, False), p.name.span, p.symmetric,
                     p.derived is not None)
        for p in info.predicates.values())
    axioms = tuple(ir.Axiom(p.name.name, _params(p.params),
                            _formula(p.derived, frozenset(x.name.name for x in p.params)), p.name.span)
                   for p in info.predicates.values() if p.derived is not None)
    functions = tuple(ir.Function(f.name.name, _params(f.params), f.name.span)
                      for f in info.functions.values())
    generators = tuple(_generator(g) for g in info.generators.values())
    evaluators = tuple(ir.Evaluator(e.predicate.name, _binding(e.binding), e.predicate.span)
                       for e in info.evaluators)
    actions = tuple(_action(a, loaded) for a in info.actions)
    return ir.Domain(info.name, types, constants, predicates, functions, actions,
                     generators, evaluators, (), info.span, axioms)


def _params(params: tuple[ast.Param, ...]) -> tuple[ir.Param, ...]:
    return tuple(ir.Param(p.name.name, p.type.name) for p in params)


def _binding(s: ast.String | None) -> ir.Binding:
    if s is None:  # the checker reports E306 first; kept total for safety
        raise _Unlowerable(diag("E501", "missing binding", Span.point("<input>")))
    return ir.Binding(s.value, s.span)


def _scalar(v: object) -> object:
    if isinstance(v, ast.Number):
        return int(v.value) if v.value.denominator == 1 else float(v.value)
    if isinstance(v, ast.String):
        return v.value
    return v


def _generator(g: ast.GeneratorDecl) -> ir.Generator:
    scope = {p.name.name for p in g.inputs + g.outputs}
    certifies = tuple(_atom(a, scope) for a in g.certifies)
    options = tuple((o.name.name, _scalar(o.value)) for o in g.options)
    return ir.Generator(g.name.name, _params(g.inputs), _params(g.outputs), certifies,
                        _binding(g.binding), options, g.name.span)


def _action(a: ast.ActionDecl, loaded: LoadedProgram) -> ir.Action:
    scope = frozenset(p.name.name for p in a.params)
    pre = _formula(a.pre, scope) if a.pre is not None else ir.TRUE
    eff = _effect(a.eff, scope) if a.eff is not None else ir.NO_EFFECT
    cost = _num(a.cost, scope) if a.cost is not None else DEFAULT_COST
    production = loaded.productions.get(a.name.name)
    generated = tuple(ir.GeneratorUse(u.generator, u.inputs, u.outputs)
                      for u in (production.uses if production else ()))
    executes = ir.Binding(a.executes.value, a.executes.span) if a.executes else None
    return ir.Action(a.name.name, _params(a.params), pre, eff, cost, generated, executes, a.name.span)


# ----------------------------------------------------------------- formulas
def _term(ident: ast.Ident, scope: frozenset[str] | set[str]) -> ir.Term:
    return ir.Var(ident.name) if ident.name in scope else ir.Const(ident.name)


def _atom(a: ast.Atom, scope) -> ir.Atom:
    return ir.Atom(a.predicate.name, tuple(_term(x, scope) for x in a.args))


def _formula(f: ast.Formula, scope: frozenset[str]) -> ir.Formula:
    if isinstance(f, ast.Atom):
        return _atom(f, scope)
    if isinstance(f, ast.Eq):
        return ir.Equals(_term(f.left, scope), _term(f.right, scope))
    if isinstance(f, ast.Not):
        return ir.Not(_formula(f.arg, scope))
    if isinstance(f, ast.And):
        return ir.And(tuple(_formula(x, scope) for x in f.args))
    if isinstance(f, ast.Or):
        return ir.Or(tuple(_formula(x, scope) for x in f.args))
    if isinstance(f, ast.Implies):
        return ir.Imply(_formula(f.left, scope), _formula(f.right, scope))
    if isinstance(f, ast.Quantified):
        inner = scope | {p.name.name for p in f.params}
        kind = ir.Forall if f.kind == "forall" else ir.Exists
        return kind(_params(f.params), _formula(f.body, inner))
    if isinstance(f, ast.Truth):
        return ir.Truth(f.value)
    raise _Unlowerable(diag("E501", f"cannot lower formula {type(f).__name__}", getattr(f, "span", Span.point("?"))))


def _num(e: ast.NumExpr, scope: frozenset[str]) -> ir.NumExpr:
    if isinstance(e, ast.Number):
        return ir.Num(e.value)
    if isinstance(e, ast.FuncApp):
        return ir.FuncTerm(e.function.name, tuple(_term(x, scope) for x in e.args))
    if isinstance(e, ast.BinOp):
        return ir.BinOp(e.op, _num(e.left, scope), _num(e.right, scope))
    raise _Unlowerable(diag("E501", "cannot lower numeric expression", getattr(e, "span", Span.point("?"))))


def _effect(e: ast.Effect, scope: frozenset[str]) -> ir.Effect:
    if isinstance(e, ast.Lit):
        return ir.Lit(_atom(e.atom, scope), e.positive)
    if isinstance(e, ast.Unknown):
        return ir.Unknown(_atom(e.atom, scope))
    if isinstance(e, ast.EffAnd):
        return ir.EffAnd(tuple(_effect(x, scope) for x in e.effects))
    if isinstance(e, ast.When):
        return ir.When(_formula(e.condition, scope), _effect(e.effect, scope))
    if isinstance(e, ast.EffForall):
        inner = scope | {p.name.name for p in e.params}
        return ir.EffForall(_params(e.params), _effect(e.effect, inner))
    if isinstance(e, ast.Probabilistic):
        return ir.Probabilistic(tuple(
            ir.Outcome(o.probability.value, _effect(o.effect, scope), o.label.name if o.label else None)
            for o in e.outcomes))
    if isinstance(e, ast.CostEffect):
        return ir.CostEffect(_num(e.amount, scope))
    raise _Unlowerable(diag("E501", f"cannot lower effect {type(e).__name__}", getattr(e, "span", Span.point("?"))))


# ------------------------------------------------------------------ problem
def _problem(p: ProblemInfo, info: DomainInfo) -> ir.Problem:
    objects = tuple(ir.Object(o.name, o.type, info.is_continuous(o.type), o.ident.span)
                    for o in p.objects.values())
    init = tuple(ir.Atom(a.predicate.name, tuple(ir.Const(x.name) for x in a.args)) for a in p.init)
    values = tuple((ir.Atom(v.atom.predicate.name, tuple(ir.Const(x.name) for x in v.atom.args)), v.value.value)
                   for v in p.init_values)
    goal = _formula(p.goal, frozenset()) if p.goal is not None else ir.TRUE
    scene = None
    if p.scene is not None:
        args = tuple((a.name.name, _scalar(a.value)) for a in p.scene.args)
        scene = ir.SceneRef(p.scene.kind, p.scene.target.value, args, p.scene.span)
    return ir.Problem(p.name, p.domain, objects, init, values, goal, p.horizon, scene, span=p.span)

