"""Parsing stamp source text into an :class:`ast.Program` plus syntax diagnostics.

Lark compiles ``grammar/stamp.lark`` into an LALR(1) table, kept in an on-disk cache
(:mod:`stampc.grammar_cache`) so that most processes never import Lark; a small
driver here runs that table over the tokens of :mod:`stampc.syntax.layout` and shapes
children exactly as Lark's tree builder would (``?rule`` inlining, filtered anonymous
tokens, ``_rule`` splicing, ``[..]`` placeholders) before calling the AST callbacks of
:class:`Builder`. Running the table directly instead of ``Lark.parse`` (no parse tree,
no Lark tokens, unit reductions that only change the state) makes parsing about four
times faster, which matters for domains with thousands of actions.

Errors: the whole file is parsed in one go; if that fails, the file is split into
top-level chunks (a declaration starts at column 1, continuation lines are indented)
and every chunk is parsed on its own, so that one bad declaration does not hide errors
in the others. No Lark type leaves this module.
"""

from __future__ import annotations

import functools
import importlib.resources
import json
import operator
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator

from stampc.diagnostics import Diagnostic, Span, error
from stampc.grammar_cache import cache_key, cached, file_stamp, lark_version
from stampc.syntax import ast, layout
from stampc.syntax.build import Builder
from stampc.syntax.build_index import BuildError, build_errors
from stampc.syntax.depth import limit_nesting
from stampc.syntax.indentation import indentation_error
from stampc.gcpause import no_gc_pauses
from stampc.syntax.layout import LexError, LexerSpec, tokenize
from stampc.syntax.words import describe_expected, describe_token, hint_for

SYNTAX_ERROR = "E001"
BOM = "\ufeff"  # a UTF-8 byte-order mark, as decoded: dropped, so columns stay right


def grammar_text() -> str:
    """The grammar: ``<repo>/grammar/stamp.lark`` beside the package first, else the
    copy installed as package data (``stampc.grammar``)."""
    local = Path(__file__).resolve().parents[2] / "grammar" / "stamp.lark"
    if local.is_file():
        return local.read_text(encoding="utf-8")
    return importlib.resources.files("stampc.grammar").joinpath("stamp.lark").read_text(encoding="utf-8")


@dataclass(frozen=True)
class RulePlan:
    """How to shape one rule's children (mirrors Lark's tree builder for LALR)."""

    name: str                  # alias or rule name: the Builder callback
    origin: str                # nonterminal, for the goto
    size: int                  # symbols to pop
    keep: tuple[tuple[int, bool, int], ...]  # (index, splice?, placeholders before)
    trailing: int              # placeholders after the last kept child
    expand1: bool              # ``?rule``: a single child replaces the node


@dataclass(frozen=True)
class Tables:
    """Everything compiled from the grammar once per process (immutable after build).

    ``actions[state][terminal]`` is a state to shift to (``>= 0``) or ``-1 - r`` to reduce
    by ``plans[r]``; ``gotos[state][nonterminal]`` is the state after a reduction.
    """

    actions: tuple[dict[str, int], ...]
    gotos: tuple[dict[str, int], ...]
    plans: tuple[RulePlan, ...]
    start: int
    end: int
    lexer: LexerSpec
    pattern: re.Pattern


#: Bump when the stored form of :class:`Tables` changes (part of the cache key).
TABLES_FORMAT = "1"


@functools.lru_cache(maxsize=1)
def tables() -> Tables:
    """The compiled tables, from the on-disk cache when the grammar and Lark are unchanged
    (so most runs never import Lark; see :mod:`stampc.grammar_cache`)."""
    text = grammar_text()
    code = file_stamp(__file__, layout.__file__)  # an edited table builder rebuilds
    key = cache_key("stamp-tables", TABLES_FORMAT, lark_version(), code, text)
    return cached("stamp-tables", key, lambda: compile_tables(text), _tables_to_json,
                  _tables_from_json)


def _tables_to_json(t: Tables) -> bytes:
    plans = [[p.name, p.origin, p.size, p.keep, p.trailing, p.expand1] for p in t.plans]
    return json.dumps({"actions": t.actions, "gotos": t.gotos, "plans": plans, "start": t.start,
                       "end": t.end, "keywords": t.lexer.keywords,
                       "punctuation": t.lexer.punctuation}).encode("utf-8")


def _tables_from_json(data: bytes) -> Tables:
    raw = json.loads(data)
    plans = tuple(RulePlan(name, origin, size, tuple(tuple(k) for k in keep), trailing, expand1)
                  for name, origin, size, keep, trailing, expand1 in raw["plans"])
    spec = LexerSpec(dict(raw["keywords"]), dict(raw["punctuation"]))
    return Tables(tuple(map(dict, raw["actions"])), tuple(map(dict, raw["gotos"])), plans,
                  int(raw["start"]), int(raw["end"]), spec, spec.pattern())


def compile_tables(grammar: str) -> Tables:
    """Lark's LALR(1) compilation of ``grammar``, reshaped for :func:`_drive`."""
    from lark import Lark
    from lark.parsers.lalr_analysis import Shift

    lark = Lark(grammar, parser="lalr", lexer="basic", maybe_placeholders=True)
    table = lark.parser.parser.parser.parse_table  # Lark's compiled LALR(1) table
    rule_index = {rule: i for i, rule in enumerate(lark.rules)}
    nonterminals = {str(rule.origin.name) for rule in lark.rules}
    size = max(table.states) + 1
    actions: list[dict[str, int]] = [{} for _ in range(size)]
    gotos: list[dict[str, int]] = [{} for _ in range(size)]
    for state, row in table.states.items():
        for symbol, (action, arg) in row.items():
            symbol = str(symbol)
            if symbol in nonterminals:
                gotos[state][symbol] = arg
            else:
                actions[state][symbol] = arg if action is Shift else -1 - rule_index[arg]
    keywords, punctuation = {}, {}
    for term in lark.terminals:
        if term.pattern.type == "str":
            value = term.pattern.value
            (keywords if value.isidentifier() else punctuation)[value] = term.name
    spec = LexerSpec(keywords, punctuation)
    plans = tuple(_plan(rule) for rule in lark.rules)
    return Tables(tuple(actions), tuple(gotos), plans, table.start_states["start"],
                  table.end_states["start"], spec, spec.pattern())


def _plan(rule) -> RulePlan:
    expansion = rule.expansion
    empty = rule.options.empty_indices
    if empty:
        bits = "".join(str(int(b)) for b in empty)
        nones = [len(ones) for ones in bits.split("0")]
    else:
        nones = [0] * (len(expansion) + 1)
    keep: list[tuple[int, bool, int]] = []
    pending = 0
    for i, sym in enumerate(expansion):
        pending += nones[i]
        if rule.options.keep_all_tokens or not (sym.is_term and sym.filter_out):
            keep.append((i, not sym.is_term and sym.name.startswith("_"), pending))
            pending = 0
    pending += nones[len(expansion)]
    return RulePlan(str(rule.alias or rule.origin.name), str(rule.origin.name), len(expansion),
                    tuple(keep), pending, bool(rule.options.expand1) and not rule.alias)


class ParseFailure(Exception):
    """Internal: a syntax error at the ``index``-th token ``token``."""

    def __init__(self, token: tuple, index: int):
        super().__init__(token[0])
        self.token, self.index = token, index
        self.expected: frozenset[str] = frozenset()


class _Splice(list):
    """Children of an inlined ``_rule``, spliced into the parent's children."""


def _shape(plan: RulePlan, popped: list) -> list:
    children: list = []
    for index, splice, before in plan.keep:
        if before:
            children.extend([None] * before)
        if splice:
            if children:
                children.extend(popped[index])
            else:  # left recursion (``item*``): grow the inlined list in place
                children = popped[index]
        else:
            children.append(popped[index])
    if plan.trailing:
        children.extend([None] * plan.trailing)
    return children


def _getter(plan: RulePlan):
    """A fast child selector for rules that only drop tokens (no splicing, no
    placeholders): returns a sequence of the kept children; ``None`` otherwise."""
    if plan.trailing or any(splice or before for _, splice, before in plan.keep):
        return None
    indices = tuple(index for index, _, _ in plan.keep)
    if len(indices) == 1:
        only = indices[0]
        return lambda popped: (popped[only],)
    if not indices:
        return lambda popped: ()
    return operator.itemgetter(*indices)


def _is_plain(plan: RulePlan) -> bool:
    """Children are exactly the popped symbols (no filtering, splicing or placeholders)."""
    return plan.trailing == 0 and tuple(k[0] for k in plan.keep) == tuple(range(plan.size)) \
        and not any(splice or before for _, splice, before in plan.keep)


def _drive(tokens: Iterator[tuple], t: Tables, builder: Builder) -> Any:
    """Run the LALR(1) automaton; the hot loop of the front end, hence the local names.

    Reductions by unit rules (``?rule`` with one child) only change the state; other
    reductions pop their symbols, select the kept children and call the rule's callback.
    """
    actions, gotos, end = t.actions, t.gotos, t.end
    reductions = [_reduction(p, builder) for p in t.plans]
    state = t.start
    states = [state]
    values: list = []
    push_state, push_value = states.append, values.append
    for tok in tokens:
        kind = tok[0]
        while True:
            step = actions[state].get(kind)
            if step is None:
                raise ParseFailure(tok, -1)
            if step >= 0:
                push_state(step)
                push_value(tok)
                state = step
                break
            unit, size, origin, select, expand1, callback = reductions[~step]
            if unit:  # replace the top state; the value stays as it is
                state = states[-1] = gotos[states[-2]][origin]
                if state == end and kind == "$END":
                    return values[-1]
                continue
            if size:
                popped = values[-size:]
                del values[-size:]
                del states[-size:]
            else:
                popped = []
            children = popped if select is None else select(popped)
            if expand1 and len(children) == 1:
                push_value(children[0])
            elif callback is None:  # reuse a list grown in place (``item*``): no copy
                push_value(children if type(children) is _Splice else _Splice(children))
            else:
                push_value(callback(*children))
            state = gotos[states[-1]][origin]
            push_state(state)
            if state == end and kind == "$END":
                return values[-1]
    raise ParseFailure(("$END", "", 1, 1, 1, 2), -1)


def _reduction(plan: RulePlan, builder: Builder) -> tuple:
    """(unit?, size, origin, child selector or None, expand1, callback) for one rule."""
    plain = _is_plain(plan)
    unit = plan.expand1 and plain and plan.size == 1
    select = None if plain else (_getter(plan) or functools.partial(_shape, plan))
    return (unit, plan.size, plan.origin, select, plan.expand1, builder.callback(plan.name))


def _run(states: list[int], kind: str, t: Tables) -> bool:
    """Feed one terminal to a copy of the automaton: True if it is eventually shifted."""
    states = list(states)
    while True:
        step = t.actions[states[-1]].get(kind)
        if step is None:
            return False
        if step >= 0:
            return True
        plan = t.plans[-1 - step]
        if plan.size:
            del states[-plan.size:]
        states.append(t.gotos[states[-1]][plan.origin])


def expected_at(tokens: list[tuple], index: int, t: Tables) -> frozenset[str]:
    """Terminals that can really follow ``tokens[:index]``: LALR tables merge lookaheads,
    so the failing state's row alone would list terminals that lead to an error later."""
    states = [t.start]
    for tok in tokens[:index]:
        while True:
            step = t.actions[states[-1]][tok[0]]
            if step >= 0:
                states.append(step)
                break
            plan = t.plans[-1 - step]
            if plan.size:
                del states[-plan.size:]
            states.append(t.gotos[states[-1]][plan.origin])
    candidates = set(t.actions[states[-1]])
    return frozenset(k for k in candidates if _run(states, k, t))


def _parse_chunk(text: str, file: str, offset: int) -> list:
    t = tables()
    builder = Builder(file)
    try:
        decls = _drive(tokenize(text, t.lexer, t.pattern, offset), t, builder)
    except ParseFailure as exc:
        tokens = list(tokenize(text, t.lexer, t.pattern, offset))
        exc.index = tokens.index(exc.token) if exc.token in tokens else len(tokens) - 1
        exc.expected = expected_at(tokens, exc.index, t)
        raise
    if builder.loose or builder.errors:  # e.g. index variables outside any `init forall`
        raise BuildError(build_errors(builder))
    return decls


def parse_source(text: str, file: str = "<string>") -> tuple[ast.Program, list[Diagnostic]]:
    """Parse ``text``; returns the (possibly partial) program and syntax diagnostics.
    Declarations nested deeper than :data:`depth.MAX_NESTING` are left out (``E006``)."""
    with no_gc_pauses():
        program, diags = _parse_source(text, file)
        program, too_deep = limit_nesting(program)
        return program, diags + too_deep


def _parse_source(text: str, file: str) -> tuple[ast.Program, list[Diagnostic]]:
    text = text.removeprefix(BOM).replace("\r\n", "\n").replace("\r", "\n")
    try:
        return ast.Program(tuple(_parse_chunk(text, file, 0)), file), []
    except (ParseFailure, LexError, BuildError):
        pass
    decls: list = []
    diags: list[Diagnostic] = []
    for offset, chunk in split_chunks(text):
        try:
            decls.extend(_parse_chunk(chunk, file, offset))
        except BuildError as exc:
            diags.extend(exc.diagnostics)
        except (ParseFailure, LexError) as exc:
            diags.append(_syntax_diagnostic(exc, chunk, file, offset))
    return ast.Program(tuple(decls), file), diags


def split_chunks(text: str) -> list[tuple[int, str]]:
    """Top-level chunks as (line offset, text); comment and blank lines never start one."""
    lines = text.split("\n")
    starts = [i for i, line in enumerate(lines)
              if line and not line[0].isspace() and not line.startswith("#")]
    if not starts or starts[0] != 0:
        starts.insert(0, 0)
    bounds = starts + [len(lines)]
    return [(a, "\n".join(lines[a:b])) for a, b in zip(bounds, bounds[1:])]


def _syntax_diagnostic(exc: Exception, chunk: str, file: str, offset: int) -> Diagnostic:
    if isinstance(exc, LexError):
        span = Span(file, exc.line, exc.col, exc.line, exc.col + 1)
        return error(SYNTAX_ERROR, f"unexpected character `{exc.char}`", span,
                     hint_for(exc.char, frozenset()))
    assert isinstance(exc, ParseFailure)
    tok = exc.token
    layout = indentation_error(tok, exc.expected, chunk.split("\n"), file, offset)
    if layout is not None:
        return layout
    end = _end_span(chunk, file, offset)
    if tok[0] in ("$END", "_DEDENT") or (tok[0] in ("_NL", "_INDENT") and tok[2] > end.line):
        span = end
    else:
        span = Span(file, tok[2], tok[3], tok[4], tok[5])
    message = f"unexpected {describe_token(tok)}; expected {describe_expected(exc.expected)}"
    return error(SYNTAX_ERROR, message, span, hint_for(tok, exc.expected))


def _end_span(chunk: str, file: str, offset: int) -> Span:
    lines = chunk.rstrip("\n").split("\n")
    last = len(lines)
    while last > 1 and not lines[last - 1].strip():
        last -= 1
    col = len(lines[last - 1]) + 1
    return Span(file, last + offset, col, last + offset, col + 1)
