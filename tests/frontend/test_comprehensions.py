"""Problem comprehensions: indexed object names, grids of objects, `init forall`."""

from __future__ import annotations

from hypothesis import given, settings, strategies as st

from stampc.ir.lower import lower
from stampc.semantics.api import check, load, parse
from stampc.syntax import ast
from stampc.syntax.fmt import format_program

DOMAIN = """domain grid
type cell, robot
predicate at(r: robot, c: cell)
predicate adjacent(a, b: cell)
predicate shelf(c: cell)
action move(r: robot, a: cell, b: cell)
    pre  at(r, a), adjacent(a, b)
    eff  not at(r, a), at(r, b)
action stock(r: robot, c: cell)
    pre  at(r, c), not shelf(c)
    eff  shelf(c)
"""

PROBLEM = DOMAIN + """problem p for grid
object cell(0..4, 0..3): cell
object bot: robot
init forall (i: 0..3, j: 0..3) adjacent(cell(i, j), cell(i + 1, j))
     forall (i: 1..4, j: 0..3) adjacent(cell(i, j), cell(i - 1, j))
     forall (i: 0..4, j: 0..3) when j < 3: adjacent(cell(i, j), cell(i, j + 1))
     forall (i: 0..4, j: 0..3) when j > 0: adjacent(cell(i, j), cell(i, j - 1))
     at(bot, cell(0, 0))
goal at(bot, cell(4, 3)), shelf(cell_4_3)
"""


def test_grid_objects_and_adjacency_expand() -> None:
    model = lower(load(PROBLEM))
    objects = [o.name for o in model.problem.objects if o.type == "cell"]
    assert objects[:5] == ["cell_0_0", "cell_0_1", "cell_0_2", "cell_0_3", "cell_1_0"]
    assert len(objects) == 20
    adjacent = {tuple(a.name for a in f.args) for f in model.problem.init if f.predicate == "adjacent"}
    assert len(adjacent) == 2 * (4 * 4 + 5 * 3)  # both directions of every grid edge
    assert all((b, a) in adjacent for a, b in adjacent)
    assert ("cell_3_2", "cell_4_2") in adjacent and ("cell_4_2", "cell_5_2") not in adjacent


def test_dependent_ranges_and_filters() -> None:
    text = PROBLEM.replace("     at(bot, cell(0, 0))",
                           "     forall (i: 0..3, j: i..3) when i != j: shelf(cell(i, j))\n"
                           "     at(bot, cell(0, 0))")
    model = lower(load(text))
    shelves = sorted(f.args[1 - 1].name for f in model.problem.init if f.predicate == "shelf")
    assert shelves == sorted(f"cell_{i}_{j}" for i in range(4) for j in range(i + 1, 4))


def test_indices_outside_a_comprehension_are_located() -> None:
    bad = DOMAIN.replace("    eff  shelf(c)", "    eff  shelf(c), shelf(cell(i, 0))")
    diags = check(bad)
    assert [d.code for d in diags] == ["E007"]
    assert (diags[0].span.line, diags[0].span.col) == (11, 26)


def test_non_integer_index_and_huge_ranges() -> None:
    assert [d.code for d in check(PROBLEM.replace("cell(0, 0))", "cell(1.5, 0))"))] == ["E008"]
    huge = PROBLEM.replace("forall (i: 0..3, j: 0..3)", "forall (i: 0..3000, j: 0..3000)")
    assert "E008" in [d.code for d in check(huge)]
    assert [d.code for d in check(PROBLEM.replace("cell(0..4, 0..3)", "cell(4..0, 0..3)"))][:1] == ["E005"]


def test_fmt_prints_comprehensions_canonically() -> None:
    program = parse(PROBLEM)
    text = format_program(program)
    assert "forall (i: 0..4, j: 0..3) when j < 3: adjacent(cell(i, j), cell(i, j + 1))" in text
    assert "object cell(0..4, 0..3): cell" in text and "at(bot, cell_0_0)" in text
    assert parse(text) == program


def _exprs(depth: int, names: tuple[str, ...] = ("i", "j")) -> st.SearchStrategy:
    leaf = st.one_of(st.builds(ast.IndexNum, st.integers(0, 9)),
                     st.builds(ast.IndexVar, st.sampled_from(names)))
    if depth == 0:
        return leaf
    sub = _exprs(depth - 1, names)
    return st.one_of(leaf, st.builds(ast.IndexOp, st.sampled_from(["+", "-", "*"]), sub, sub))


@settings(max_examples=60, deadline=None)
@given(_exprs(3), _exprs(2, ("i",)), st.sampled_from(["=", "!=", "<", "<=", ">", ">="]))
def test_parse_fmt_roundtrip_of_index_expressions(index, bound, op) -> None:
    atom = ast.IndexedAtom(ast.Ident("shelf"), (ast.IndexedName("cell", (index, ast.IndexVar("j"))),))
    forall = ast.InitForall((ast.IndexRange("i", ast.IndexNum(0), ast.IndexNum(3)),
                             ast.IndexRange("j", ast.IndexVar("i"), bound)),
                            (ast.IndexCond(op, index, bound),), atom)
    program = ast.Program((ast.ProblemHeader(ast.Ident("p"), ast.Ident("grid")),
                           ast.InitDecl((forall,))))
    assert parse(format_program(program)) == program


DERIVED = """domain d
type cell
symmetric predicate adjacent(a, b: cell)
static symmetric predicate wall(a, b: cell)
predicate blocked(c: cell)
derived predicate open(a, b: cell) := adjacent(a, b) and not blocked(b) and not wall(a, b)
derived predicate linked(a, b: cell) :=
    open(a, b) or exists (c: cell) (open(a, c) and linked(c, b))
    not blocked(a)
"""


def test_fmt_prints_derived_and_symmetric_predicates_canonically() -> None:
    program = parse(DERIVED)
    text = format_program(program)
    assert "static symmetric predicate wall(a: cell, b: cell)" in text
    # a conjunction is one conjunct per line, as in `pre`
    assert "derived predicate open(a: cell, b: cell) :=\n    adjacent(a, b)\n    not blocked(b)" in text
    assert "derived predicate linked(a: cell, b: cell) :=\n    open(a, b) or exists" in text
    assert parse(text) == program
    assert format_program(parse(text)) == text


def test_deep_index_chains_are_limited_not_crashing() -> None:
    deep = PROBLEM.replace("adjacent(cell(i, j), cell(i + 1, j))",
                           "adjacent(cell(i, j), cell(i" + " + 0" * 3000 + " + 1, j))")
    assert [d.code for d in check(deep)] == ["E006"]
    literal = PROBLEM.replace("at(bot, cell(0, 0))", "at(bot, cell(1 - 1" + " + 0" * 3000 + ", 0))")
    assert check(literal) == []  # whole-number indices are computed while parsing
    assert [d.code for d in check(PROBLEM.replace("cell(4, 3))", "cell(4, 3 - 4))"))] == ["E008"]
