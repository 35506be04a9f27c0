"""S-expressions → syntax tree of domain and problem definitions (see shape_base)."""

from __future__ import annotations

from stampc.backends.ppddl import codes
from stampc.backends.ppddl.reader import SList, Tok
from stampc.backends.ppddl.shape_base import Node, head, is_keyword, is_name, is_number
from stampc.backends.ppddl.shape_formula import FormulaShaper

_DOMAIN_SECTIONS = (":action", ":constants", ":derived", ":functions", ":predicates",
                    ":requirements", ":types")
_PROBLEM_SECTIONS = (":domain", ":goal", ":goal-reward", ":horizon", ":init", ":metric",
                     ":objects")
_ACTION_PARTS = "one of ':effect', ':parameters', ':precondition', ')'"


def _one_of(words) -> str:
    return "one of " + ", ".join(f"'{w}'" for w in words)


class Shaper(FormulaShaper):
    def definitions(self, items: list) -> list[Node]:
        return [self.definition(x) for x in items]

    def definition(self, x) -> Node:
        if not isinstance(x, SList):
            self.fail(x, "'(' or end of file")
        define = self.item(x, 0, "'define'")
        if not (isinstance(define, Tok) and define.text == "define"):
            self.fail(define, "'define'")
        header = self.item(x, 1, "'('")
        if not isinstance(header, SList):
            self.fail(header, "'('")
        kind = self.item(header, 0, "'domain' or 'problem'")
        if not (isinstance(kind, Tok) and kind.text in ("domain", "problem")):
            self.fail(kind, "'domain' or 'problem'")
        name = self.name(header, 1)
        self.check_end(header, 2)
        section = self.domain_item if kind.text == "domain" else self.problem_item
        children = [name] + [section(item) for item in x.items[2:]]
        return Node(kind.text, children, x.start, x.end)

    # -------------------------------------------------------------- domain
    def domain_item(self, x) -> Node:
        word = self._section_word(x, _DOMAIN_SECTIONS)
        if word == ":requirements":
            for flag in x.items[1:]:
                if not is_keyword(flag):
                    self.fail(flag, "a requirement flag such as :typing or ')'")
            return Node("requirements", x.items[1:], x.start, x.end)
        if word in (":types", ":constants"):
            return Node(word[1:], [self.typed(x, 1, variables=False)], x.start, x.end)
        if word == ":predicates":
            return Node("predicates", [self._decl(d) for d in x.items[1:]], x.start, x.end)
        if word == ":functions":
            return Node("functions", self._functions(x), x.start, x.end)
        if word == ":derived":  # (:derived (p ?x - t) GD)
            head_decl = self._decl(self.item(x, 1, "'('"))
            body = self.gd(self.item(x, 2, "a formula"))
            self.check_end(x, 3)
            return Node("derived", [head_decl, body], x.start, x.end)
        return self._action(x)

    def _section_word(self, x, words) -> str:
        if not isinstance(x, SList):
            self.fail(x, "'(' or ')'")
        first = self.item(x, 0, _one_of(words))
        if not (isinstance(first, Tok) and first.text in words):
            self.fail(first, _one_of(words))
        return first.text

    def _decl(self, d) -> Node:
        """``(name ?a ?b - t)`` in :predicates / :functions."""
        if not isinstance(d, SList):
            self.fail(d, "'(' or ')'")
        name = self.name(d, 0, "a predicate name")
        return Node("atom_decl", [name, self.typed(d, 1, variables=True)], d.start, d.end)

    def _functions(self, x: SList) -> list[Node]:
        out: list[Node] = []
        i = 1
        while i < len(x.items):
            d = x.items[i]
            if isinstance(d, Tok) and d.text == "-":  # "- number"
                spec = self.name(x, i + 1, "a type name")
                out.append(Node("type_mark", [spec], d.start, spec.end))
                i += 2
                continue
            out.append(self._decl(d))
            i += 1
        return out

    def _action(self, x: SList) -> Node:
        name = self.name(x, 1, "an action name")
        parts: list[Node] = []
        i = 2
        while i < len(x.items):
            key = x.items[i]
            word = key.text if isinstance(key, Tok) else None
            if word == ":parameters":
                value = self.variables(x, i + 1)
                parts.append(Node("parameters", [value], key.start, value.end))
            elif word == ":precondition":
                value = self.gd(self.item(x, i + 1, "a formula"))
                parts.append(Node("precondition", [value], key.start, value.end))
            elif word == ":effect":
                value = self.effect(self.item(x, i + 1, "an effect"))
                parts.append(Node("effect_part", [value], key.start, value.end))
            else:
                self.fail(key, _ACTION_PARTS)
            i += 2
        return Node("action", [name] + parts, x.start, x.end)

    # ------------------------------------------------------------- problem
    def problem_item(self, x) -> Node:
        word = self._section_word(x, _PROBLEM_SECTIONS)
        if word == ":objects":
            return Node("objects", [self.typed(x, 1, variables=False)], x.start, x.end)
        if word == ":init":
            return Node("init", [self._init_item(i) for i in x.items[1:]], x.start, x.end)
        if word == ":goal":
            value = self.gd(self.item(x, 1, "a formula"))
        elif word == ":domain":
            value = self.name(x, 1, "the domain name")
        elif word == ":metric":
            direction = self.name(x, 1, "maximize or minimize")
            fluent = self.fluent(self.item(x, 2, "a fluent such as (reward)"))
            self.check_end(x, 3)
            return Node("metric", [direction, fluent], x.start, x.end)
        else:  # :goal-reward, :horizon
            value = self.item(x, 1, "a number")
            if not is_number(value):
                self.fail(value, "a number")
        self.check_end(x, 2)
        kind = {":goal": "goal", ":domain": "problem_domain", ":goal-reward": "goal_reward",
                ":horizon": "horizon"}[word]
        return Node(kind, [value], x.start, x.end)

    def _init_item(self, x) -> Node:
        if type(x) is SList and x.items and is_name(x.items[0]) and \
                x.items[0].text != "probabilistic":  # the common case first
            return self.atom(x)
        if is_name(x):
            return Node("bare_atom", [x], x.start, x.end)
        if not isinstance(x, SList) or not x.items:
            self.fail(x, "an atom such as (p a b)") if not isinstance(x, SList) else \
                self.missing(x, "a predicate name")
        word = head(x)
        if word == "=":
            fluent = self.item(x, 1, "'(' and a function name")
            if not (isinstance(fluent, SList) and fluent.items and is_name(fluent.items[0])):
                self.fail(fluent, "'(' and a function name")
            value = self.item(x, 2, "a number")
            if not is_number(value):
                self.fail(value, "a number")
            self.check_end(x, 3)
            return Node("init_value", self.atom(fluent).children + [value], x.start, x.end)
        if word == "probabilistic":
            self.raise_at(codes.UNSUPPORTED, "unsupported construct: probabilistic initial states",
                          x.items[0].start, x.items[0].end,
                          hint="list the initial facts; stampc reads one initial state")
        self.fail(x.items[0], "a predicate name")
