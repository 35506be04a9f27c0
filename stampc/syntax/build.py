"""Grammar rule callbacks → stamp AST nodes (called by the LALR driver in parser.py)."""

from __future__ import annotations

import functools
from dataclasses import replace
from fractions import Fraction

from stampc.diagnostics import Span
from stampc.syntax import ast
from stampc.syntax.build_index import IndexBuilder
from stampc.syntax.spans import (Args, Clause, conj, fast_constructor, flat, is_token, make_span, merge,
                                 seq, span_of)

# the nodes made once per name or atom: built without the frozen dataclass ``__init__``
_Ident = fast_constructor(ast.Ident)
_Param = fast_constructor(ast.Param)
_Atom = fast_constructor(ast.Atom)
_Lit = fast_constructor(ast.Lit)
_Args = fast_constructor(Args)


@functools.lru_cache(maxsize=256)
def _fraction(text: str) -> Fraction:
    """``Fraction(text)`` parses a string with a regex; domains repeat the same few
    numbers, and fractions are immutable, so equal literals share one value."""
    return Fraction(text)


class Builder(IndexBuilder):
    """Rule callbacks building AST nodes; tokens are tuples from :mod:`stampc.syntax.layout`.

    ``callback(rule)`` is the method called with a rule's (filtered) children as arguments.
    """

    def __init__(self, file: str):
        super().__init__()
        self.file = file

    def callback(self, name: str):
        return None if name.startswith("_") else getattr(self, name, None)

    # -------------------------------------------------------------- helpers
    def tspan(self, tok: tuple) -> Span:
        return make_span(self.file, tok[2], tok[3], tok[4], tok[5])

    def ident(self, tok: tuple) -> ast.Ident:
        return _Ident(tok[1], make_span(self.file, tok[2], tok[3], tok[4], tok[5]))

    def number(self, tok: tuple) -> ast.Number:
        return ast.Number(_fraction(tok[1]), tok[1], self.tspan(tok))

    def string(self, tok: tuple) -> ast.String:
        raw = tok[1][1:-1]
        return ast.String(raw.replace('\\"', '"').replace("\\\\", "\\"), self.tspan(tok))

    # -------------------------------------------------------------- program
    def start(self, *items):
        return list(items)

    def domain_header(self, name):
        return ast.DomainHeader(self.ident(name), self.tspan(name))

    def problem_header(self, name, domain):
        return ast.ProblemHeader(self.ident(name), self.ident(domain), self.tspan(name))

    def module_header(self, name):
        return ast.ModuleHeader(self.ident(name), self.tspan(name))

    def use_module(self, kw, name):
        return ast.Use(name[1], False, merge(self.tspan(kw), self.tspan(name)))

    def use_file(self, kw, tok):
        return ast.Use(self.string(tok).value, True, merge(self.tspan(kw), self.tspan(tok)))

    # --------------------------------------------------------- declarations
    def type_decl(self, *children):
        continuous = is_token(children[0], "CONTINUOUS")
        rest = children[1:] if continuous else children
        names, _less, parent = rest
        parent_ident = self.ident(parent) if parent is not None else None
        return ast.TypeDecl(tuple(names), parent_ident, continuous, span_of(names))

    def constant_decl(self, names, type_):
        return ast.ConstantDecl(tuple(names), self.ident(type_), span_of(names))

    def predicate_decl(self, *children):
        static = is_token(children[0], "STATIC")
        rest = children[1:] if static else children
        symmetric = is_token(rest[0], "SYMMETRIC")
        name, params = rest[1:] if symmetric else rest
        return ast.PredicateDecl(self.ident(name), tuple(params or ()), static, self.tspan(name),
                                 symmetric)

    def unknown_predicate_decl(self, *children):
        decl = self.predicate_decl(*children)
        return replace(decl, unknown=True)

    def derived_decl(self, _kw, name, params, _define, body):
        return ast.PredicateDecl(self.ident(name), tuple(params or ()), False, self.tspan(name),
                                 derived=body)

    def function_decl(self, name, params):
        return ast.FunctionDecl(self.ident(name), tuple(params or ()), self.tspan(name))

    def name_list(self, *names):
        return [self.ident(n) for n in names]

    def param_list(self, *groups):
        return flat(groups)

    def param_group(self, *names):
        type_ = self.ident(names[-1])
        end_line, end_col = type_.span.end_line, type_.span.end_col
        file, ident, param = self.file, _Ident, _Param
        # span: from the parameter's name to its type (``merge`` without the extra span)
        return [param(ident(n[1], make_span(file, n[2], n[3], n[4], n[5])), type_,
                      make_span(file, n[2], n[3], end_line, end_col))
                for n in names[:-1]]

    def generator_decl(self, name, inputs, _arrow, outputs, *clauses):
        found = self._clauses(flat(clauses))
        return ast.GeneratorDecl(self.ident(name), tuple(inputs), tuple(outputs),
                                 tuple(found["certifies"]), found["binds"],
                                 tuple(found["option"]), self.tspan(name))

    def evaluator_decl(self, name, *clauses):
        found = self._clauses(flat(clauses))
        return ast.EvaluatorDecl(self.ident(name), found["binds"], tuple(found["option"]),
                                 self.tspan(name))

    @staticmethod
    def _clauses(clauses: list) -> dict:
        found: dict = {"certifies": [], "binds": None, "option": []}
        for clause in clauses:
            kind, value = clause.kind, clause.value
            if kind == "certifies":
                found["certifies"].extend(value)
            elif kind == "binds":
                found["binds"] = found["binds"] or value
            else:
                found["option"].append(value)
        return found

    def clause_block(self, *clauses):
        return list(clauses)

    def certifies(self, *atoms):
        return Clause("certifies", list(atoms))

    def binds(self, tok):
        return Clause("binds", self.string(tok))

    def budget(self, tok):
        span = self.tspan(tok)
        return Clause("option", ast.Option(ast.Ident("budget", span), self.number(tok), span))

    def option(self, name, value):
        return Clause("option", ast.Option(self.ident(name), value, merge(self.tspan(name), span_of(value))))

    def action_decl(self, name, params, *clauses):
        found: dict = {"pre": [], "eff": [], "cost": None, "executes": None, "sample": []}
        for clause in clauses:
            kind, value = clause.kind, clause.value
            if kind in ("pre", "eff", "sample"):
                found[kind].append(value)
            else:
                found[kind] = found[kind] or value
        pre = conj(found["pre"]) if found["pre"] else None
        eff = seq(found["eff"]) if found["eff"] else None
        return ast.ActionDecl(self.ident(name), tuple(params), pre, eff, found["cost"],
                              found["executes"], tuple(found["sample"]), self.tspan(name))

    def pre_clause(self, formula):
        return Clause("pre", formula)

    def eff_clause(self, effect):
        return Clause("eff", effect)

    def cost_clause(self, expr):
        return Clause("cost", expr)

    def executes_clause(self, tok):
        return Clause("executes", self.string(tok))

    def sample_clause(self, outputs, generator, args):
        gen = self.ident(generator)
        return Clause("sample", ast.Sample(tuple(outputs), gen, args.idents, merge(span_of(outputs), gen.span)))

    # ------------------------------------------------------------- formulas
    def formula_lines(self, *parts):
        formulas = flat(parts)
        return conj(formulas) if formulas else ast.Truth(True)

    def formula_block(self, *lists):
        return flat(lists)

    def formula_list(self, *formulas):
        return list(formulas)

    def implies_f(self, left, right):
        return ast.Implies(left, right, merge(left.span, right.span))

    def or_f(self, first, *rest):
        # a parenthesised disjunction in front joins the chain (``(a or b) or c``)
        args = (first.args if isinstance(first, ast.Or) else (first,)) + rest
        return ast.Or(args, merge(first.span, rest[-1].span))

    def and_f(self, *parts):
        return conj(list(parts))

    def not_f(self, kw, arg):
        return ast.Not(arg, merge(self.tspan(kw), arg.span))

    def forall_f(self, params, body):
        return ast.Quantified("forall", tuple(params), body, merge(span_of(params), body.span))

    def exists_f(self, params, body):
        return ast.Quantified("exists", tuple(params), body, merge(span_of(params), body.span))

    def eq_f(self, left, right):
        return ast.Eq(self.ident(left), self.ident(right), merge(self.tspan(left), self.tspan(right)))

    def neq_f(self, left, right):
        eq = self.eq_f(left, right)
        return ast.Not(eq, eq.span)

    def true_f(self, tok):
        return ast.Truth(True, self.tspan(tok))

    def false_f(self, tok):
        return ast.Truth(False, self.tspan(tok))

    def atom(self, name, args=None):
        pred = self.ident(name)
        if args is None:
            return _Atom(pred, (), pred.span)
        rpar = args.rpar  # the atom runs from its name to the closing parenthesis
        return _Atom(pred, args.idents, make_span(self.file, name[2], name[3], rpar[4], rpar[5]))

    def args(self, *tokens):
        """``( a, b )`` → identifiers, with the ``)`` token (where the atom ends)."""
        # tokens are "(" NAME... ")" (the commas are filtered), or "(" None ")" when empty
        ident, file = _Ident, self.file
        idents = tuple([ident(t[1], make_span(file, t[2], t[3], t[4], t[5])) if type(t) is tuple else t
                        for t in tokens[1:-1] if t is not None and (type(t) is not tuple or t[0] == "NAME")])
        return _Args(idents, tokens[-1])

    # -------------------------------------------------------------- effects
    def effect_lines(self, *parts):
        return seq(flat(parts))

    def effect_block(self, *lines):
        return flat(lines)

    def effect_list(self, *effects):
        return list(effects)

    def effect_body(self, part):
        return seq(flat([part]))

    def add_effect(self, atom):
        return _Lit(atom, True, atom.span)

    def del_effect(self, atom):
        return _Lit(atom, False, atom.span)

    def unknown_effect(self, atom):
        return ast.Unknown(atom, atom.span)

    def unknown_forall(self, params, atom):
        inner = ast.Unknown(atom, atom.span)
        return ast.EffForall(tuple(params), inner, merge(span_of(params), atom.span))

    def forall_effect(self, params, effect):
        return ast.EffForall(tuple(params), effect, merge(span_of(params), effect.span))

    forall_block = forall_effect

    def cost_effect(self, expr):
        return ast.CostEffect(expr, span_of(expr))

    def nothing_effect(self, tok):
        return ast.EffAnd((), self.tspan(tok))

    def prob_effect(self, *outcomes):
        return ast.Probabilistic(tuple(outcomes), span_of(list(outcomes)))

    def when_effect(self, condition, effect):
        return ast.When(condition, effect, merge(condition.span, effect.span))

    def outcome(self, prob, label, effect):
        label_ident = self.ident(label) if label is not None else None
        return ast.Outcome(prob, effect, label_ident, merge(prob.span, effect.span))

    def probability(self, tok):
        return self.number(tok)

    # -------------------------------------------------------------- numbers
    def _binop(self, op: str, left, right):
        return ast.BinOp(op, left, right, merge(span_of(left), span_of(right)))

    def add(self, left, right):
        return self._binop("+", left, right)

    def sub(self, left, right):
        return self._binop("-", left, right)

    def mul(self, left, right):
        return self._binop("*", left, right)

    def div(self, left, right):
        return self._binop("/", left, right)

    def num(self, tok):
        return self.number(tok)

    def func(self, name, args=None):
        fn = self.ident(name)
        if args is None:
            return ast.FuncApp(fn, (), fn.span)
        rpar = args.rpar
        return ast.FuncApp(fn, args.idents, make_span(self.file, name[2], name[3], rpar[4], rpar[5]))

    # ------------------------------------------------------------- problems
    def object_decl(self, kw, *children):
        items, type_ = children[:-1], self.ident(children[-1])
        return ast.ObjectDecl(tuple(items), type_, merge(self.tspan(kw), type_.span))

    def object_name(self, tok):
        return self.ident(tok)

    def object_range(self, first, last):
        return ast.ObjectRange(self.ident(first), self.ident(last),
                               merge(self.tspan(first), self.tspan(last)))

    def init_decl(self, kw, *parts):
        facts = flat(parts)
        return ast.InitDecl(tuple(facts), merge(self.tspan(kw), span_of(facts)))

    def init_block(self, *lists):
        return flat(lists)

    def init_list(self, *items):
        return list(items)

    def init_value(self, atom, tok):
        value = self.number(tok)
        return ast.InitValue(atom, value, merge(atom.span, value.span))

    def goal_decl(self, kw, formula):
        return ast.GoalDecl(formula, merge(self.tspan(kw), formula.span))

    def horizon_decl(self, kw, tok):
        value = self.number(tok)
        return ast.HorizonDecl(value, merge(self.tspan(kw), value.span))

    def scene_file(self, kw, tok):
        target = self.string(tok)
        return ast.SceneDecl("file", target, (), merge(self.tspan(kw), target.span))

    def scene_builder(self, kw, tok, *args):
        target = self.string(tok)
        return ast.SceneDecl("builder", target, tuple(a for a in args if a is not None),
                             merge(self.tspan(kw), target.span))

    def scene_arg(self, name, value):
        return ast.Option(self.ident(name), value, merge(self.tspan(name), span_of(value)))

    def lit_number(self, tok):
        return self.number(tok)

    def lit_negative(self, tok):
        n = self.number(tok)
        return ast.Number(-n.value, "-" + n.text, n.span)

    def lit_string(self, tok):
        return self.string(tok)

    def lit_true(self, tok):
        return True

    def lit_false(self, tok):
        return False
