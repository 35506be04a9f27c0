"""The grammar, the layout rules and the AST shapes of every construct."""

from __future__ import annotations

import logging
from fractions import Fraction

import pytest
from lark import Lark, logger

from stampc.diagnostics import StampcError
from stampc.semantics.api import parse
from stampc.syntax import ast
from stampc.syntax.parser import grammar_text, parse_source


def only(text: str):
    program = parse(text)
    assert len(program.decls) >= 1
    return program.decls[-1]


def test_grammar_is_lalr_without_conflicts(caplog: pytest.LogCaptureFixture) -> None:
    logger.setLevel(logging.DEBUG)
    try:
        with caplog.at_level(logging.DEBUG, logger="lark"):
            Lark(grammar_text(), parser="lalr", lexer="basic", debug=True)
    finally:
        logger.setLevel(logging.WARNING)
    conflicts = [r.getMessage() for r in caplog.records if "conflict" in r.getMessage().lower()]
    assert conflicts == []


def test_type_hierarchy_constants_and_predicates() -> None:
    prog = parse("domain d\ntype can, bottle < movable\ncontinuous type pose\n"
                 "constant tray: surface\nstatic predicate on(x, y: block, p: pose)\n"
                 "predicate handempty\nfunction weight(o: can)\n")
    types = prog.decls[1]
    assert [n.name for n in types.names] == ["can", "bottle"] and types.parent.name == "movable"
    assert prog.decls[2].continuous and not types.continuous
    pred = prog.decls[4]
    assert pred.static and [(p.name.name, p.type.name) for p in pred.params] == \
        [("x", "block"), ("y", "block"), ("p", "pose")]
    assert prog.decls[5].params == ()
    assert isinstance(prog.decls[6], ast.FunctionDecl)


def test_generator_clauses_on_one_line_or_indented() -> None:
    one = only('generator g(o: m) -> (p: pose, q: conf) certifies r(o, p), s(q) binds ".w:g" budget 4\n')
    many = only('generator g(o: m) -> (p: pose, q: conf)\n    certifies r(o, p), s(q)\n'
                '    binds ".w:g"\n    budget 4\n')
    assert one == many
    assert [a.predicate.name for a in one.certifies] == ["r", "s"]
    assert one.binding.value == ".w:g"
    assert one.options[0].name.name == "budget" and one.options[0].value.value == 4


def test_precondition_operators_and_precedence() -> None:
    act = only("action a(x: t, y: t)\n    pre  p(x) or q(x) and not r(x) implies s(x), x != y,\n"
               "         forall (z: t) not p(z), exists (z: t) (p(z) and q(z))\n    eff  nothing\n")
    imp, neq, fa, ex = act.pre.args
    assert isinstance(imp, ast.Implies) and isinstance(imp.left, ast.Or)
    assert isinstance(imp.left.args[1], ast.And)
    assert isinstance(imp.left.args[1].args[1], ast.Not)
    assert isinstance(neq, ast.Not) and isinstance(neq.arg, ast.Eq)
    assert fa.kind == "forall" and isinstance(fa.body, ast.Not)
    assert ex.kind == "exists" and isinstance(ex.body, ast.And)
    assert act.eff == ast.EffAnd(())


def test_quantifier_body_binds_tightly() -> None:
    act = only("action a(x: t)\n    pre  forall (z: t) p(z) and q(x)\n")
    assert isinstance(act.pre, ast.And)
    assert isinstance(act.pre.args[0], ast.Quantified) and act.pre.args[0].body == ast.Atom(ast.Ident("p"), (ast.Ident("z"),))


def test_effects_probabilistic_when_forall_unknown_cost() -> None:
    act = only("""action a(o: m, t: traj)
    eff  holding(o), not free(o)
         ? forall (x: m) collision(x, t)
         when heavy(o): cost 2
         forall (x: m):
             when near(o, x): probabilistic 1/3 as topple: down(x)
         probabilistic
             0.8: at(o)
             0.15 as slip:
                 not at(o)
                 cost 1
    cost 1 + w(o) * 2
""")
    items = act.eff.effects
    assert items[0] == ast.Lit(ast.Atom(ast.Ident("holding"), (ast.Ident("o"),)))
    assert items[1].positive is False
    assert isinstance(items[2], ast.EffForall) and isinstance(items[2].effect, ast.Unknown)
    assert isinstance(items[3], ast.When) and isinstance(items[3].effect, ast.CostEffect)
    inner = items[4].effect
    assert isinstance(inner, ast.When) and inner.effect.outcomes[0].probability.value == Fraction(1, 3)
    assert inner.effect.outcomes[0].label.name == "topple"
    block = items[5]
    assert [o.probability.value for o in block.outcomes] == [Fraction(4, 5), Fraction(3, 20)]
    assert isinstance(block.outcomes[1].effect, ast.EffAnd) and len(block.outcomes[1].effect.effects) == 2
    assert isinstance(act.cost, ast.BinOp) and act.cost.op == "+"
    assert isinstance(act.cost.right, ast.BinOp) and act.cost.right.op == "*"


def test_problem_constructs() -> None:
    prog = parse('problem p for d\nobject can0..can14, extra: can\ninit on(a, b), w(a) = 1/2\n'
                 '     clear(b)\ngoal on(a, b)\nhorizon 20\n'
                 'scene builder "pkg.scene:build"(n=15, seed=0, name="x", flag=true, k=-2)\n'
                 'problem q for d\nscene "scenes/table.json"\n')
    objects = prog.decls[1]
    assert isinstance(objects.items[0], ast.ObjectRange) and objects.items[1].name == "extra"
    init = prog.decls[2]
    assert isinstance(init.facts[1], ast.InitValue) and init.facts[1].value.value == Fraction(1, 2)
    assert len(init.facts) == 3
    scene = prog.decls[5]
    assert scene.kind == "builder" and scene.target.value == "pkg.scene:build"
    values = {o.name.name: o.value for o in scene.args}
    assert values["n"].value == 15 and values["name"].value == "x" and values["flag"] is True
    assert values["k"].value == -2
    assert prog.decls[7] == ast.SceneDecl("file", ast.String("scenes/table.json"))


def test_use_module_and_file() -> None:
    prog = parse('domain d\nuse manipulation\nuse "../common.stamp"\n')
    assert prog.decls[1] == ast.Use("manipulation", False)
    assert prog.decls[2] == ast.Use("../common.stamp", True)


def test_spans_are_one_based_and_point_at_names() -> None:
    act = only("domain d\n\naction pick(o: m)\n    pre  holding(o)\n")
    assert (act.name.span.line, act.name.span.col, act.name.span.end_col) == (3, 8, 12)
    atom = act.pre
    assert (atom.span.line, atom.span.col, atom.span.end_col) == (4, 10, 20)


def test_comments_and_blank_lines_are_ignored() -> None:
    a = parse("# head\ndomain d   # trailing\n\n# between\ntype t\n")
    b = parse("domain d\ntype t\n")
    assert a == b


def test_syntax_errors_are_collected_per_declaration() -> None:
    _, diags = parse_source("domain d\npredicate p(x: t\ntype t\naction a(x: t)\n    pre p(x) and\n"
                            "type u <\n", "f")
    assert [d.code for d in diags] == ["E001", "E001", "E001"]
    assert [d.span.line for d in diags] == [2, 5, 6]


def test_parse_raises_stampc_error_with_diagnostics() -> None:
    with pytest.raises(StampcError) as info:
        parse("domain d\ntype [x]\n")
    assert info.value.diagnostics[0].code == "E001"
    assert "unexpected character `[`" in info.value.diagnostics[0].message


def test_keyword_as_name_gets_a_hint() -> None:
    _, diags = parse_source("domain d\npredicate for(x: t)\n", "f")
    assert diags[0].hint == "`for` is a keyword and cannot be used as a name"


def test_every_grammar_rule_has_a_builder_callback() -> None:
    """Rules without a callback would leak raw lists into the AST."""
    from stampc.syntax.build import Builder
    from stampc.syntax.parser import tables

    missing = {p.name for p in tables().plans
               if not p.name.startswith("_") and not p.expand1 and Builder("f").callback(p.name) is None}
    assert missing == set()


def test_make_span_equals_the_dataclass_constructor() -> None:
    from stampc.diagnostics import Span
    from stampc.syntax.spans import make_span

    made = make_span("f.stamp", 3, 4, 3, 9)
    assert made == Span("f.stamp", 3, 4, 3, 9) and hash(made) == hash(Span("f.stamp", 3, 4, 3, 9))
    assert str(made) == "f.stamp:3:4"


def test_code_blocks_of_the_language_docs_parse() -> None:
    import re

    from .helpers import REPO

    text = (REPO / "docs" / "language.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```\n(.*?)```", text, re.S)
    assert len(blocks) >= 6
    for block in blocks:
        source = "action x(o: t)\n" + block if block.startswith("    ") else block
        _, diags = parse_source(source, "docs")
        assert diags == [], (block.splitlines()[0], diags)
