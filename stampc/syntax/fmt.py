"""Canonical stamp source from an AST: ``parse(format_program(p)) == p`` up to spans.

Layout rules: one declaration per line group; clauses of generators and actions on
indented lines; each top-level conjunct, effect and init fact on its own line aligned
after the clause keyword; a blank line around multi-line declarations. Comments are
not part of the AST: :func:`format_source` carries them over from the original text.
"""

from __future__ import annotations

import bisect
from fractions import Fraction

from stampc.syntax import ast
from stampc.syntax.fmt_index import init_forall_text, object_item_text

PREC_IMPLIES, PREC_OR, PREC_AND, PREC_NOT = 0, 1, 2, 3
CLAUSE = "    "
HANG = " " * 9  # column of the first item after "    pre  " / "    eff  "


# ------------------------------------------------------------------- atoms
def fmt_number(n: ast.Number) -> str:
    if n.text:
        return n.text
    v = n.value
    return str(v.numerator) if v.denominator == 1 else f"{v.numerator}/{v.denominator}"


def fmt_string(s: ast.String) -> str:
    return '"' + s.value.replace("\\", "\\\\").replace('"', '\\"') + '"'


def fmt_value(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, ast.Number):
        return fmt_number(v)
    if isinstance(v, ast.String):
        return fmt_string(v)
    if isinstance(v, Fraction):
        return fmt_number(ast.Number(v))
    return str(v)


def fmt_params(params: tuple[ast.Param, ...]) -> str:
    return "(" + ", ".join(f"{p.name.name}: {p.type.name}" for p in params) + ")"


def fmt_atom(a: ast.Atom) -> str:
    if not a.args:
        return a.predicate.name
    return f"{a.predicate.name}({', '.join(x.name for x in a.args)})"


# ---------------------------------------------------------------- formulas
def fmt_formula(f: ast.Formula, prec: int = PREC_IMPLIES) -> str:
    text, own = _formula(f)
    return f"({text})" if own < prec else text


def _formula(f: ast.Formula) -> tuple[str, int]:
    if isinstance(f, ast.Atom):
        return fmt_atom(f), 4
    if isinstance(f, ast.Eq):
        return f"{f.left.name} = {f.right.name}", 4
    if isinstance(f, ast.Truth):
        return ("true" if f.value else "false"), 4
    if isinstance(f, ast.Not):
        if isinstance(f.arg, ast.Eq):
            return f"{f.arg.left.name} != {f.arg.right.name}", 4
        return "not " + fmt_formula(f.arg, PREC_NOT), PREC_NOT
    if isinstance(f, ast.Quantified):
        return f"{f.kind} {fmt_params(f.params)} {fmt_formula(f.body, PREC_NOT)}", PREC_NOT
    if isinstance(f, ast.And):
        if not f.args:
            return "true", 4
        return " and ".join(fmt_formula(a, PREC_NOT) for a in f.args), PREC_AND
    if isinstance(f, ast.Or):
        if not f.args:
            return "false", 4
        return " or ".join(fmt_formula(a, PREC_AND) for a in f.args), PREC_OR
    assert isinstance(f, ast.Implies)
    return f"{fmt_formula(f.left, PREC_OR)} implies {fmt_formula(f.right, PREC_IMPLIES)}", PREC_IMPLIES


def conjuncts(f: ast.Formula) -> list[ast.Formula]:
    return list(f.args) if isinstance(f, ast.And) and f.args else [f]


# ----------------------------------------------------------------- numbers
def fmt_num(e: ast.NumExpr, prec: int = 0) -> str:
    if isinstance(e, ast.Number):
        return fmt_number(e)
    if isinstance(e, ast.FuncApp):
        if not e.args:
            return e.function.name
        return f"{e.function.name}({', '.join(a.name for a in e.args)})"
    own = 1 if e.op in "+-" else 2
    text = f"{fmt_num(e.left, own)} {e.op} {fmt_num(e.right, own + 1)}"
    return f"({text})" if own < prec else text


# ----------------------------------------------------------------- effects
def is_simple(e: ast.Effect) -> bool:
    if isinstance(e, (ast.Lit, ast.Unknown, ast.CostEffect)):
        return True
    if isinstance(e, ast.EffAnd):
        return not e.effects
    if isinstance(e, ast.EffForall):
        return is_simple(e.effect) and not isinstance(e.effect, ast.EffAnd)
    return False


def fmt_simple(e: ast.Effect) -> str:
    if isinstance(e, ast.Lit):
        return fmt_atom(e.atom) if e.positive else "not " + fmt_atom(e.atom)
    if isinstance(e, ast.Unknown):
        return "? " + fmt_atom(e.atom)
    if isinstance(e, ast.CostEffect):
        return "cost " + fmt_num(e.amount)
    if isinstance(e, ast.EffAnd):
        return "nothing"
    assert isinstance(e, ast.EffForall)
    if isinstance(e.effect, ast.Unknown):
        return f"? forall {fmt_params(e.params)} {fmt_atom(e.effect.atom)}"
    return f"forall {fmt_params(e.params)} {fmt_simple(e.effect)}"


def effect_items(e: ast.Effect) -> list[ast.Effect]:
    return list(e.effects) if isinstance(e, ast.EffAnd) and e.effects else [e]


def effect_lines(e: ast.Effect) -> list[str]:
    """Lines for a sequence of effects, relative to the column of the first effect."""
    lines: list[str] = []
    for item in effect_items(e):
        lines.extend(_effect_line(item))
    return lines


def _indented(lines: list[str]) -> list[str]:
    return ["    " + line for line in lines]


def _body(header: str, e: ast.Effect) -> list[str]:
    items = effect_items(e)
    if all(is_simple(x) for x in items):
        return [f"{header} {', '.join(fmt_simple(x) for x in items)}"]
    return [header] + _indented(effect_lines(e))


def _effect_line(e: ast.Effect) -> list[str]:
    if is_simple(e):
        return [fmt_simple(e)]
    if isinstance(e, ast.Probabilistic):
        lines = ["probabilistic"]
        for o in e.outcomes:
            label = f" as {o.label.name}" if o.label else ""
            lines.extend(_indented(_body(f"{fmt_number(o.probability)}{label}:", o.effect)))
        return lines
    if isinstance(e, ast.When):
        return _body(f"when {fmt_formula(e.condition)}:", e.effect)
    if isinstance(e, ast.EffForall):
        return _body(f"forall {fmt_params(e.params)}:", e.effect)
    assert isinstance(e, ast.EffAnd)  # nested sequence: print its items in place
    return effect_lines(e)


def _hanging(keyword: str, lines: list[str]) -> list[str]:
    """``    pre  first`` then the other lines aligned under ``first``."""
    head = f"{CLAUSE}{keyword:<4} {lines[0]}".rstrip()
    return [head] + [HANG + line for line in lines[1:]]


# ------------------------------------------------------------ declarations
def format_decl(d: ast.Decl) -> list[str]:
    if isinstance(d, ast.DomainHeader):
        return [f"domain {d.name.name}"]
    if isinstance(d, ast.ProblemHeader):
        return [f"problem {d.name.name} for {d.domain.name}"]
    if isinstance(d, ast.ModuleHeader):
        return [f"module {d.name.name}"]
    if isinstance(d, ast.Use):
        return [f"use {fmt_string(ast.String(d.target)) if d.is_path else d.target}"]
    if isinstance(d, ast.TypeDecl):
        parent = f" < {d.parent.name}" if d.parent else ""
        prefix = "continuous " if d.continuous else ""
        return [f"{prefix}type {', '.join(n.name for n in d.names)}{parent}"]
    if isinstance(d, ast.ConstantDecl):
        return [f"constant {', '.join(n.name for n in d.names)}: {d.type.name}"]
    if isinstance(d, ast.PredicateDecl):
        params = fmt_params(d.params) if d.params else ""
        if d.derived is not None:
            return _hanging_derived(f"derived predicate {d.name.name}{params} :=",
                                    [fmt_formula(c) for c in conjuncts(d.derived)])
        modifiers = ("? " if d.unknown else "") + ("static " if d.static else "") \
            + ("symmetric " if d.symmetric else "")
        return [f"{modifiers}predicate {d.name.name}{params}"]
    if isinstance(d, ast.FunctionDecl):
        return [f"function {d.name.name}{fmt_params(d.params) if d.params else ''}"]
    if isinstance(d, ast.GeneratorDecl):
        head = f"generator {d.name.name}{fmt_params(d.inputs)} -> {fmt_params(d.outputs)}"
        return [head] + _binding_clauses(d.certifies, d.binding, d.options)
    if isinstance(d, ast.EvaluatorDecl):
        return [f"evaluator {d.predicate.name}"] + _binding_clauses((), d.binding, d.options)
    if isinstance(d, ast.ActionDecl):
        return _action(d)
    if isinstance(d, ast.ObjectDecl):
        items = [object_item_text(i) for i in d.items]
        return [f"object {', '.join(items)}: {d.type.name}"]
    if isinstance(d, ast.InitDecl):
        facts = [fmt_atom(f) if isinstance(f, ast.Atom) else init_forall_text(f)
                 if isinstance(f, ast.InitForall) else
                 f"{fmt_atom(f.atom)} = {fmt_number(f.value)}" for f in d.facts]
        if not facts:
            return ["init"]
        return [f"init {facts[0]}"] + ["     " + f for f in facts[1:]]
    if isinstance(d, ast.GoalDecl):
        parts = [fmt_formula(c) for c in conjuncts(d.formula)]
        return [f"goal {parts[0]}"] + ["     " + p for p in parts[1:]]
    if isinstance(d, ast.HorizonDecl):
        return [f"horizon {fmt_number(d.value)}"]
    assert isinstance(d, ast.SceneDecl)
    if d.kind == "file":
        return [f"scene {fmt_string(d.target)}"]
    args = ", ".join(f"{a.name.name}={fmt_value(a.value)}" for a in d.args)
    return [f"scene builder {fmt_string(d.target)}({args})"]


def _hanging_derived(head: str, parts: list[str]) -> list[str]:
    """A one-conjunct definition on the header line; several on indented lines."""
    if len(parts) == 1:
        return [f"{head} {parts[0]}"]
    return [head] + [CLAUSE + p for p in parts]


def _binding_clauses(certifies, binding, options) -> list[str]:
    lines = []
    if certifies:
        lines.append(f"{CLAUSE}certifies {', '.join(fmt_atom(a) for a in certifies)}")
    if binding is not None:
        lines.append(f"{CLAUSE}binds {fmt_string(binding)}")
    for opt in options:
        if opt.name.name == "budget" and isinstance(opt.value, ast.Number):
            lines.append(f"{CLAUSE}budget {fmt_number(opt.value)}")
        else:
            lines.append(f"{CLAUSE}option {opt.name.name} = {fmt_value(opt.value)}")
    return lines


def _action(d: ast.ActionDecl) -> list[str]:
    lines = [f"action {d.name.name}{fmt_params(d.params)}"]
    for s in d.samples:
        outs = ", ".join(o.name for o in s.outputs)
        lines.append(f"{CLAUSE}sample {outs} from {s.generator.name}({', '.join(i.name for i in s.inputs)})")
    if d.pre is not None:
        lines.extend(_hanging("pre", [fmt_formula(c) for c in conjuncts(d.pre)]))
    if d.eff is not None:
        lines.extend(_hanging("eff", effect_lines(d.eff)))
    if d.cost is not None:
        lines.append(f"{CLAUSE}cost {fmt_num(d.cost)}")
    if d.executes is not None:
        lines.append(f"{CLAUSE}executes {fmt_string(d.executes)}")
    if len(lines) == 1:  # an action needs at least one clause
        lines.append(f"{CLAUSE}pre  true")
    return lines


def format_program(program: ast.Program, text: str | None = None) -> str:
    """Canonical text for ``program``; with the original ``text``, its comments are kept
    (above their declaration, or at the end of a one-line declaration)."""
    above, trailing, tail = attach_comments(text, program) if text is not None else ({}, {}, [])
    out: list[str] = []
    previous: list[str] | None = None
    prev_kind = None
    for index, decl in enumerate(program.decls):
        lines = format_decl(decl)
        if index in trailing and len(lines) == 1:
            lines = [f"{lines[0]}  {trailing.pop(index)}"]
        comments = above.get(index, []) + ([trailing[index]] if index in trailing else [])
        kind = type(decl)
        if previous is not None and (len(lines) > 1 or len(previous) > 1 or kind is not prev_kind
                                     or comments):
            out.append("")
        out.extend(comments)
        out.extend(lines)
        previous, prev_kind = lines, kind
    if tail:
        out.extend([""] + tail if out else tail)
    return "\n".join(out) + "\n" if out else ""


# ------------------------------------------------------------------ comments
def find_comment(line: str) -> int:
    """Column index of a ``#`` comment outside string literals, or -1."""
    in_string = escaped = False
    for i, ch in enumerate(line):
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch == "#":
            return i
    return -1


def attach_comments(text: str, program: ast.Program) -> tuple[dict[int, list[str]], dict[int, str], list[str]]:
    """Comments above declarations, trailing comments of one-line declarations, and
    comments after the last declaration. Declaration ``k`` starts at the ``k``-th line
    that begins at column 1 (the layout rule of the language)."""
    lines = text.removeprefix("\ufeff").replace("\r\n", "\n").split("\n")
    starts = [i + 1 for i, line in enumerate(lines)
              if line and not line[0].isspace() and not line.startswith("#")]
    if len(starts) != len(program.decls):
        starts = [d.span.line for d in program.decls]
    above: dict[int, list[str]] = {}
    trailing: dict[int, str] = {}
    tail: list[str] = []
    for number, line in enumerate(lines, start=1):
        col = find_comment(line)
        if col < 0:
            continue
        comment = line[col:].rstrip()
        full_line = not line[:col].strip()
        after = bisect.bisect_right(starts, number)  # starts are ascending: no scan per comment
        following = after if after < len(starts) else None
        current = after - 1 if after > 0 else None
        if full_line and (col == 0 or current is None):
            if following is None:
                tail.append(comment)
            else:
                above.setdefault(following, []).append(comment)
        elif not full_line and current is not None and starts[current] == number and current not in trailing:
            trailing[current] = comment
        else:
            target = current if current is not None else 0
            above.setdefault(target, []).append(comment)
    return above, trailing, tail
