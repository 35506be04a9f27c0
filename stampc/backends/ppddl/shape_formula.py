"""Shaping of formulas (``gd``), effects and numeric expressions.

Nested ``and``/``or`` of the same kind are flattened with a work list, so chains of any
depth cost no recursion; every other construct recurses one level and stops with P108
beyond :data:`MAX_NESTING` levels, which keeps every later walk of the IR (lowering,
grounding, emission) far from Python's recursion limit.
"""

from __future__ import annotations

from typing import Callable

from stampc.backends.ppddl.reader import SList, Tok
from stampc.backends.ppddl.shape_base import (
    FOND_WORD, MAX_NESTING, TERM_START, UNSUPPORTED_WORDS, Node, ShapeBase, head, is_name,
    is_number, is_op, is_var,
)

_GD = "a formula: '(' or a name"
_EFFECT = "an effect: '(' or a name"
_CONNECTIVES = "a predicate name or one of and, or, not, imply, forall, exists, ="
_EFFECT_HEADS = ("a predicate name or one of and, not, when, forall, probabilistic, "
                 "increase, decrease")
_TERM = "a name, a variable such as ?x or ')'"


class FormulaShaper(ShapeBase):
    # ------------------------------------------------------------ formulas
    def gd(self, x, depth: int = 0) -> Node:
        if depth > MAX_NESTING:
            self.too_deep(x)
        if isinstance(x, Tok):
            if is_name(x):
                return Node("bare_atom", [x], x.start, x.end)
            self.fail(x, _GD)
        if not x.items:
            return Node("gd_true", [], x.start, x.end)
        word = head(x)
        if word in UNSUPPORTED_WORDS or word == FOND_WORD:
            self.fail(x.items[0], _CONNECTIVES)
        if word in ("and", "or"):
            return Node("gd_" + word, self._flat(x, word, self.gd, depth), x.start, x.end)
        if word == "not":
            body = self.gd(self.item(x, 1, _GD), depth + 1)
            self.check_end(x, 2)
            return Node("gd_not", [body], x.start, x.end)
        if word == "imply":
            left = self.gd(self.item(x, 1, _GD), depth + 1)
            right = self.gd(self.item(x, 2, _GD), depth + 1)
            self.check_end(x, 3)
            return Node("gd_imply", [left, right], x.start, x.end)
        if word in ("forall", "exists"):
            params = self.variables(x, 1)
            body = self.gd(self.item(x, 2, _GD), depth + 1)
            self.check_end(x, 3)
            return Node("gd_" + word, [params, body], x.start, x.end)
        if word == "=":
            left, right = self.term(x, 1, "a name or a variable"), self.term(x, 2, "a name or a variable")
            self.check_end(x, 3)
            return Node("gd_eq", [left, right], x.start, x.end)
        if is_name(x.items[0]):
            return self.atom(x)
        self.fail(x.items[0], _CONNECTIVES)

    def _flat(self, sl: SList, word: str, shape: Callable, depth: int) -> list[Node]:
        """Children of ``(word ...)`` with directly nested ``(word ...)`` spliced in."""
        out: list[Node] = []
        todo = sl.items[:0:-1]  # reversed, without the head word
        while todo:
            x = todo.pop()
            if isinstance(x, SList) and head(x) == word:
                todo.extend(x.items[:0:-1])
            else:
                out.append(shape(x, depth + 1))
        return out

    def variables(self, sl: SList, i: int) -> Node:
        x = self.item(sl, i, "'(' and variables")
        if not isinstance(x, SList):
            self.fail(x, "'(' and variables")
        return self.typed(x, 0, variables=True)

    def atom(self, sl: SList) -> Node:
        """``(name term*)``: the name word then term words (names or variables)."""
        items = sl.items
        for x in items[1:]:
            if type(x) is not Tok or x.text[0] not in TERM_START:
                self.fail(x, _TERM)
        return Node("atom", items, sl.start, sl.end)

    def term(self, sl: SList, i: int, expected: str) -> Tok:
        x = self.item(sl, i, expected)
        if not (is_name(x) or is_var(x)):
            self.fail(x, expected)
        return x

    # ------------------------------------------------------------- effects
    def effect(self, x, depth: int = 0) -> Node:
        if depth > MAX_NESTING:
            self.too_deep(x)
        if isinstance(x, Tok):
            if is_name(x):
                return Node("bare_atom", [x], x.start, x.end)
            self.fail(x, _EFFECT)
        if not x.items:
            return Node("eff_empty", [], x.start, x.end)
        word = head(x)
        if word in UNSUPPORTED_WORDS or word == FOND_WORD:
            self.fail(x.items[0], _EFFECT_HEADS)
        if word == "and":
            return Node("eff_and", self._flat(x, "and", self.effect, depth), x.start, x.end)
        if word == "not":
            target = self.item(x, 1, "an atom")
            self.check_end(x, 2)
            return Node("eff_not", [self._effect_atom(target)], x.start, x.end)
        if word == "when":
            cond = self.gd(self.item(x, 1, _GD), depth + 1)
            body = self.effect(self.item(x, 2, _EFFECT), depth + 1)
            self.check_end(x, 3)
            return Node("eff_when", [cond, body], x.start, x.end)
        if word == "forall":
            params = self.variables(x, 1)
            body = self.effect(self.item(x, 2, _EFFECT), depth + 1)
            self.check_end(x, 3)
            return Node("eff_forall", [params, body], x.start, x.end)
        if word == "probabilistic":
            return self._probabilistic(x, depth)
        if word in ("increase", "decrease"):
            fluent = self.fluent(self.item(x, 1, "a fluent such as (reward)"))
            amount = self.num_expr(self.item(x, 2, "a number or numeric expression"), depth + 1)
            self.check_end(x, 3)
            return Node("eff_" + word, [fluent, amount], x.start, x.end)
        if is_name(x.items[0]):
            return self.atom(x)
        self.fail(x.items[0], _EFFECT_HEADS)

    def _effect_atom(self, x) -> Node:
        if isinstance(x, Tok) and is_name(x):
            return Node("bare_atom", [x], x.start, x.end)
        if isinstance(x, SList) and x.items and is_name(x.items[0]):
            return self.atom(x)  # any name, as in the grammar: (not (and)) names a predicate
        self.fail(x.items[0] if isinstance(x, SList) and x.items else x, "an atom")

    def _probabilistic(self, x: SList, depth: int) -> Node:
        outcomes = []
        items = x.items
        self.item(x, 1, "a probability")
        for i in range(1, len(items), 2):
            prob = items[i]
            if not is_number(prob):
                self.fail(prob, "a probability or ')'")
            body = self.effect(self.item(x, i + 1, _EFFECT), depth + 1)
            outcomes.append(Node("outcome", [prob, body], prob.start, body.end))
        return Node("eff_prob", outcomes, x.start, x.end)

    def fluent(self, x) -> Node:
        if is_name(x):
            return Node("fluent", [x], x.start, x.end)
        if isinstance(x, SList):
            name = self.name(x, 0, "a fluent name such as reward")
            self.check_end(x, 1)
            return Node("fluent", [name], x.start, x.end)
        self.fail(x, "a fluent such as (reward)")

    def num_expr(self, x, depth: int) -> Node:
        if depth > MAX_NESTING:
            self.too_deep(x)
        if is_number(x):
            return Node("num", [x], x.start, x.end)
        if not isinstance(x, SList) or not x.items:
            self.fail(x, "a number or '('") if not isinstance(x, SList) else \
                self.missing(x, "an arithmetic operator or a function name")
        first = x.items[0]
        if is_op(first) and first.text != "=":
            left = self.num_expr(self.item(x, 1, "a number or '('"), depth + 1)
            right = self.num_expr(self.item(x, 2, "a number or '('"), depth + 1)
            self.check_end(x, 3)
            return Node("num_binop", [first, left, right], x.start, x.end)
        if is_name(first):
            return Node("num_func", self.atom(x).children, x.start, x.end)
        self.fail(first, "an arithmetic operator (+ - * /) or a function name")
