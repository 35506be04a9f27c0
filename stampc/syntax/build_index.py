"""Builder callbacks for integer-indexed names and problem comprehensions.

Index variables are bound only by ``init forall (i: a..b, ...)``. The builder cannot
know, when it reduces ``cell(i, j)`` bottom-up, whether a comprehension encloses it, so
every indexed name with variables is recorded as *loose* until the enclosing
``init_forall`` claims it; whatever is left when a declaration is done is an ``E007``
(:func:`loose_diagnostics`), and the parser drops that declaration as it drops one
with a syntax error.
"""

from __future__ import annotations

from stampc.diagnostics import Diagnostic, Span, error
from stampc.syntax import ast
from stampc.syntax.indexed import evaluate, index_vars, indexed_name
from stampc.syntax.spans import make_span, merge

UNBOUND_INDEX = "E007"
BAD_INDEX = "E008"


class BuildError(Exception):
    """Raised by a callback for input the grammar accepts but the language does not
    (a non-integer index); the parser reports it like a syntax error."""

    def __init__(self, diagnostics: list[Diagnostic]):
        super().__init__(diagnostics[0].message)
        self.diagnostics = diagnostics


class IndexBuilder:
    """Mixin of :class:`stampc.syntax.build.Builder` (which provides ``file``,
    ``tspan`` and ``ident``)."""

    file: str

    def __init__(self) -> None:
        self.loose: dict[int, ast.IndexedName] = {}
        self.errors: list[Diagnostic] = []  # reported once the declaration is built

    def tspan(self, tok: tuple) -> Span: ...  # provided by Builder

    # ------------------------------------------------------------ indices
    def index_num(self, tok):
        text = tok[1]
        if not text.isdigit():
            raise BuildError([error(BAD_INDEX, f"an index must be a whole number, not {text}",
                                    self.tspan(tok), "indices count objects: 0, 1, 2, ...")])
        return ast.IndexNum(int(text), self.tspan(tok))

    def index_var(self, tok):
        return ast.IndexVar(tok[1], self.tspan(tok))

    def _index_op(self, op: str, left, right):
        return ast.IndexOp(op, left, right, merge(left.span, right.span))

    def index_add(self, left, right):
        return self._index_op("+", left, right)

    def index_sub(self, left, right):
        return self._index_op("-", left, right)

    def index_mul(self, left, right):
        return self._index_op("*", left, right)

    def indexed(self, name, *indices):
        last = indices[-1].span
        span = make_span(self.file, name[2], name[3], last.end_line, last.end_col + 1)
        if not any(index_vars(i) for i in indices):  # whole numbers: the name itself
            values = tuple(evaluate(i, {}) for i in indices)
            if any(v < 0 for v in values):
                raise BuildError([error(BAD_INDEX, f"index {min(values)} is negative", span,
                                        "indices count objects: 0, 1, 2, ...")])
            return ast.Ident(indexed_name(name[1], values), span)
        node = ast.IndexedName(name[1], tuple(indices), span)
        self.loose[id(node)] = node
        return node

    # ------------------------------------------------------ comprehensions
    def index_range(self, var, first, last):
        return ast.IndexRange(var[1], first, last, merge(self.tspan(var), last.span))

    def index_filter(self, *conds):
        return list(conds)

    def _cond(self, op: str, left, right):
        return ast.IndexCond(op, left, right, merge(left.span, right.span))

    def cond_eq(self, left, right):
        return self._cond("=", left, right)

    def cond_ne(self, left, right):
        return self._cond("!=", left, right)

    def cond_lt(self, left, _less, right):
        return self._cond("<", left, right)

    def cond_le(self, left, right):
        return self._cond("<=", left, right)

    def cond_gt(self, left, right):
        return self._cond(">", left, right)

    def cond_ge(self, left, right):
        return self._cond(">=", left, right)

    def init_forall(self, *children):
        ranges, conds, atom = list(children[:-2]), children[-2] or [], children[-1]
        bound: dict[str, ast.IndexRange] = {}
        errors: list[Diagnostic] = []
        for r in ranges:
            if r.var in bound:
                errors.append(error("E204", f"index variable `{r.var}` is bound twice", r.span))
            _check_bound(list(index_vars(r.first)) + list(index_vars(r.last)), bound, errors)
            bound[r.var] = r
        for c in conds:
            _check_bound(index_vars(c.left) + index_vars(c.right), bound, errors)
        for arg in atom.args:
            if isinstance(arg, ast.IndexedName):
                self.loose.pop(id(arg), None)
                for i in arg.indices:
                    _check_bound(index_vars(i), bound, errors)
        self.errors.extend(errors)
        body = ast.IndexedAtom(atom.predicate, tuple(atom.args), atom.span)
        span = merge(ranges[0].span, atom.span)
        return ast.InitForall(tuple(ranges), tuple(conds), body, span)

    def object_grid(self, name, *ranges):
        return ast.ObjectGrid(name[1], tuple(b for b, _ in ranges),
                              merge(self.tspan(name), ranges[-1][1]))

    def int_range(self, first, last):
        lo, hi = (self.index_num(first).value, self.index_num(last).value)
        return (lo, hi), self.tspan(last)


def _check_bound(used: list[ast.IndexVar], bound: dict, errors: list[Diagnostic]) -> None:
    for v in used:
        if v.name not in bound:
            errors.append(error(UNBOUND_INDEX, f"index variable `{v.name}` is not bound",
                                v.span, _hint(v.name, bound)))


def _hint(name: str, bound: dict) -> str:
    if bound:
        return (f"add a range for it to the comprehension (`{name}: 0..N`); a range may use "
                "only the variables before it")
    return f"bind it with `init forall ({name}: 0..N) ...`"


def build_errors(builder: IndexBuilder) -> list[Diagnostic]:
    """The comprehension errors of a parse, and E007 for indexed names with variables
    outside any ``init forall``."""
    out = list(builder.errors)
    for node in builder.loose.values():
        names = sorted({v.name for i in node.indices for v in index_vars(i)})
        out.append(error(UNBOUND_INDEX, f"index variable{'s' if len(names) > 1 else ''} "
                         f"{', '.join(f'`{n}`' for n in names)} not bound here", node.span,
                         "only `init forall (i: 0..N, ...) atom` binds index variables; "
                         "elsewhere write whole numbers: `cell(4, 3)` is `cell_4_3`"))
    return out
