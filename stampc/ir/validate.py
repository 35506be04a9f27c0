"""Well-formedness checks run before grounding (diagnostic codes G101-G112).

The front end and the importer already check most of this, but the grounder accepts any
hand-built or JSON-loaded lifted model, so it re-checks what it relies on and reports
every problem at once, located at the enclosing declaration.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Iterable

from stampc.diagnostics import Diagnostic, Span, StampcError, error, has_errors
from stampc.ir import lifted as L
from stampc.ir.ground_context import ROOT_TYPE, located


class _Checker:
    def __init__(self, model: L.Model):
        self.model = model
        self.diags: list[Diagnostic] = []
        domain = model.domain
        self.types = {ROOT_TYPE} | {t.name for t in domain.types}
        self.predicates = {p.name: p for p in domain.predicates}
        self.functions = {f.name: f for f in domain.functions}
        self.generators = {g.name: g for g in domain.generators}
        self.objects: dict[str, str] = {}

    def report(self, code: str, message: str, span: Span | None, hint: str | None = None) -> None:
        self.diags.append(error(code, message, located(span, self.model), hint))

    # ---------------------------------------------------------- declarations
    def check_types(self) -> None:
        parents = {t.name: t.parent for t in self.model.domain.types}
        for t in self.model.domain.types:
            if t.parent is not None and t.parent not in self.types:
                self.report("G101", f"type '{t.name}' has unknown parent type '{t.parent}'", t.span)
            seen, cur = {t.name}, t.parent
            while cur is not None and cur in parents:
                if cur in seen:
                    self.report("G111", f"type '{t.name}' is part of a cycle in the type hierarchy",
                                t.span, "make the hierarchy a tree rooted at 'object'")
                    break
                seen.add(cur)
                cur = parents[cur]

    def check_type_name(self, type_name: str, what: str, span: Span | None) -> None:
        if type_name not in self.types:
            self.report("G101", f"{what} has unknown type '{type_name}'", span,
                        "declare the type in the domain's types")

    def check_objects(self) -> None:
        domain, problem = self.model.domain, self.model.problem
        for obj in (*domain.constants, *problem.objects):
            self.check_type_name(obj.type, f"object '{obj.name}'", obj.span or problem.span)
            previous = self.objects.get(obj.name)
            if previous is not None and previous != obj.type:
                self.report("G112", f"object '{obj.name}' declared with types '{previous}' "
                            f"and '{obj.type}'", obj.span or problem.span)
            self.objects.setdefault(obj.name, obj.type)

    def check_params(self, params: Iterable[L.Param], what: str, span: Span | None) -> None:
        for p in params:
            self.check_type_name(p.type, f"parameter '{p.name}' of {what}", span)

    # ------------------------------------------------------------- formulas
    def check_terms(self, terms: tuple[L.Term, ...], scope: set[str], what: str,
                    span: Span | None) -> None:
        for term in terms:
            if isinstance(term, L.Var):
                if term.name not in scope:
                    self.report("G105", f"variable '{term.name}' is not bound in {what}", span)
            elif term.name not in self.objects:
                self.report("G104", f"unknown object '{term.name}' in {what}", span)

    def check_atom(self, atom: L.Atom, scope: set[str], what: str, span: Span | None) -> None:
        pred = self.predicates.get(atom.predicate)
        if pred is None:
            self.report("G102", f"unknown predicate '{atom.predicate}' in {what}", span)
        elif len(pred.params) != len(atom.args):
            self.report("G103", f"predicate '{atom.predicate}' takes {len(pred.params)} "
                        f"argument(s), got {len(atom.args)} in {what}", span)
        self.check_terms(atom.args, scope, what, span)

    def check_formula(self, f: L.Formula, scope: set[str], what: str, span: Span | None) -> None:
        if isinstance(f, L.Atom):
            self.check_atom(f, scope, what, span)
        elif isinstance(f, L.Equals):
            self.check_terms((f.left, f.right), scope, what, span)
        elif isinstance(f, L.Not):
            self.check_formula(f.arg, scope, what, span)
        elif isinstance(f, (L.And, L.Or)):
            for sub in f.args:
                self.check_formula(sub, scope, what, span)
        elif isinstance(f, L.Imply):
            self.check_formula(f.left, scope, what, span)
            self.check_formula(f.right, scope, what, span)
        elif isinstance(f, (L.Forall, L.Exists)):
            self.check_params(f.params, what, span)
            self.check_formula(f.body, scope | {p.name for p in f.params}, what, span)

    def check_num(self, expr: L.NumExpr, scope: set[str], what: str, span: Span | None) -> None:
        if isinstance(expr, L.FuncTerm):
            fn = self.functions.get(expr.function)
            if fn is None:
                self.report("G107", f"unknown function '{expr.function}' in {what}", span)
            elif len(fn.params) != len(expr.args):
                self.report("G103", f"function '{expr.function}' takes {len(fn.params)} "
                            f"argument(s), got {len(expr.args)} in {what}", span)
            self.check_terms(expr.args, scope, what, span)
        elif isinstance(expr, L.BinOp):
            if expr.op not in "+-*/" or len(expr.op) != 1:
                self.report("G110", f"unknown arithmetic operator '{expr.op}' in {what}", span)
            self.check_num(expr.left, scope, what, span)
            self.check_num(expr.right, scope, what, span)

    def check_effect(self, e: L.Effect, scope: set[str], what: str, span: Span | None) -> None:
        if isinstance(e, (L.Lit, L.Unknown)):
            self.check_atom(e.atom, scope, what, span)
        elif isinstance(e, L.EffAnd):
            for sub in e.effects:
                self.check_effect(sub, scope, what, span)
        elif isinstance(e, L.When):
            self.check_formula(e.condition, scope, what, span)
            self.check_effect(e.effect, scope, what, span)
        elif isinstance(e, L.EffForall):
            self.check_params(e.params, what, span)
            self.check_effect(e.effect, scope | {p.name for p in e.params}, what, span)
        elif isinstance(e, L.Probabilistic):
            total = Fraction(0)
            for outcome in e.outcomes:
                if not 0 <= outcome.probability <= 1:
                    self.report("G108", f"probability {outcome.probability} outside [0, 1] "
                                f"in {what}", span)
                total += outcome.probability
                self.check_effect(outcome.effect, scope, what, span)
            if total > 1:
                self.report("G108", f"outcome probabilities sum to {total} > 1 in {what}", span,
                            "probabilities of one probabilistic block must sum to at most 1")
        elif isinstance(e, L.CostEffect):
            self.check_num(e.amount, scope, what, span)

    # --------------------------------------------------------------- actions
    def check_generator_uses(self, action: L.Action, what: str) -> None:
        names = {p.name for p in action.params}
        outputs: set[str] = set()
        for use in action.generated:
            gen = self.generators.get(use.generator)
            if gen is None:
                self.report("G109", f"{what} uses unknown generator '{use.generator}'", action.span)
                continue
            if len(gen.inputs) != len(use.inputs) or len(gen.outputs) != len(use.outputs):
                self.report("G109", f"generator '{gen.name}' takes {len(gen.inputs)} input(s) and "
                            f"{len(gen.outputs)} output(s); {what} uses "
                            f"{len(use.inputs)} and {len(use.outputs)}", action.span)
            for name in (*use.inputs, *use.outputs):
                if name not in names:
                    self.report("G109", f"generator use '{gen.name}' in {what} refers to "
                                f"unknown parameter '{name}'", action.span)
            for name in use.outputs:
                if name in outputs:
                    self.report("G109", f"parameter '{name}' of {what} is generated twice",
                                action.span)
                outputs.add(name)

    def check_actions(self) -> None:
        for action in self.model.domain.actions:
            what = f"action '{action.name}'"
            self.check_params(action.params, what, action.span)
            scope = {p.name for p in action.params}
            self.check_formula(action.precondition, scope, what, action.span)
            self.check_effect(action.effect, scope, what, action.span)
            if action.cost is not None:
                self.check_num(action.cost, scope, what, action.span)
            self.check_generator_uses(action, what)

    def check_axioms(self) -> None:
        # only the recursive-over-fluents axioms reach here (the rest are compiled away)
        for axiom in self.model.domain.axioms:
            what = f"derived predicate '{axiom.predicate}'"
            self.check_params(axiom.params, what, axiom.span)
            self.check_formula(axiom.body, {p.name for p in axiom.params}, what, axiom.span)

    def check_generators(self) -> None:
        for gen in self.model.domain.generators:
            what = f"generator '{gen.name}'"
            self.check_params((*gen.inputs, *gen.outputs), what, gen.span)
            scope = {p.name for p in (*gen.inputs, *gen.outputs)}
            for atom in gen.certifies:
                self.check_atom(atom, scope, what, gen.span)

    def check_problem(self) -> None:
        problem = self.model.problem
        for atom in problem.init:
            self.check_atom(atom, set(), "the initial state", problem.span)
        for atom, _ in problem.init_values:
            self.check_num(L.FuncTerm(atom.predicate, atom.args), set(),
                           "the initial function values", problem.span)
        self.check_formula(problem.goal, set(), "the goal", problem.span)

    def check_predicates(self) -> None:
        for pred in self.model.domain.predicates:
            self.check_params(pred.params, f"predicate '{pred.name}'", pred.span)


def validate_model(model: L.Model) -> None:
    """Raise :class:`StampcError` with every G1xx problem found in ``model``."""
    checker = _Checker(model)
    checker.check_types()
    checker.check_objects()
    checker.check_predicates()
    checker.check_actions()
    checker.check_axioms()
    checker.check_generators()
    checker.check_problem()
    if has_errors(checker.diags):
        raise StampcError(checker.diags)
