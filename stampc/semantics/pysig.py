"""Read a bound Python function from its source with :mod:`ast` — never importing it.

Three questions ``check`` asks of a bound function (docs/language.md, "Bindings"):
- can it be called with the positional arguments the engine passes;
- which action parameters an executor reads by name (``arg(action, "o", ...)``,
  ``action.args["o"]``), following calls into functions of the same module;
- how many values a generator's ``yield``/``return`` literals hold.
Answers are conservative: anything the reader cannot see statically is accepted.
"""

from __future__ import annotations

import ast as py
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

FunctionNode = py.FunctionDef | py.AsyncFunctionDef


@dataclass(frozen=True)
class PyModule:
    path: Path
    tree: py.Module

    def function(self, name: str) -> FunctionNode | str | None:
        """The top-level ``def name``; ``"opaque"`` when ``name`` exists but is not a plain
        function (a class, an import, an assignment, a module ``__getattr__``); None when
        the module does not define it."""
        found: FunctionNode | str | None = None
        for node in _top_level(self.tree.body):
            if isinstance(node, (py.FunctionDef, py.AsyncFunctionDef)):
                if node.name == name:
                    found = node
                elif node.name == "__getattr__" and found is None:
                    found = "opaque"
            elif _binds_name(node, name):
                found = "opaque"
        return found


@dataclass(frozen=True)
class Read:
    """An action parameter an executor reads by name, and where."""

    key: str
    line: int
    col: int
    end_col: int


def parse_module(path: Path) -> PyModule | SyntaxError:
    try:
        text = path.read_text(encoding="utf-8")
        return PyModule(path, py.parse(text, filename=str(path)))
    except SyntaxError as exc:
        return exc
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        return SyntaxError(f"cannot read the file: {exc}")


def _top_level(body: list[py.stmt]) -> Iterator[py.stmt]:
    """Statements at module level, including those under ``if``/``try`` (optional
    imports, platform switches)."""
    for node in body:
        yield node
        if isinstance(node, py.If):
            yield from _top_level(node.body + node.orelse)
        elif isinstance(node, py.Try):
            yield from _top_level(node.body + node.orelse + node.finalbody
                                  + [s for h in node.handlers for s in h.body])


def _binds_name(node: py.stmt, name: str) -> bool:
    if isinstance(node, py.ClassDef):
        return node.name == name
    if isinstance(node, (py.Import, py.ImportFrom)):
        return any((a.asname or a.name.split(".")[0]) == name for a in node.names)
    if isinstance(node, (py.Assign, py.AnnAssign)):
        targets = node.targets if isinstance(node, py.Assign) else [node.target]
        return any(isinstance(t, py.Name) and t.id == name for t in targets)
    return False


# ------------------------------------------------------------------- arity
def positional_range(fn: FunctionNode) -> tuple[int, int | None]:
    """(fewest, most) positional arguments ``fn`` accepts; most is None with ``*args``."""
    args = fn.args
    positional = len(args.posonlyargs) + len(args.args)
    fewest = positional - len(args.defaults)
    return fewest, (None if args.vararg is not None else positional)


def accepts(fn: FunctionNode, n: int, keywords: tuple[str, ...] = ()) -> bool:
    """Can ``fn`` be called with ``n`` positional arguments (and, optionally, the
    keyword arguments ``keywords`` if it declares them)?"""
    fewest, most = positional_range(fn)
    if most is not None and n > most:
        return False
    names = parameter_names(fn)
    if any(name not in keywords for name in names[n:fewest]):
        return False  # a parameter without default that neither a position nor a keyword fills
    required_kw = [a.arg for a, d in zip(fn.args.kwonlyargs, fn.args.kw_defaults) if d is None]
    return all(k in keywords for k in required_kw)


def parameter_names(fn: FunctionNode) -> list[str]:
    return [a.arg for a in fn.args.posonlyargs + fn.args.args]


def declares(fn: FunctionNode, keyword: str) -> bool:
    names = parameter_names(fn) + [a.arg for a in fn.args.kwonlyargs]
    return keyword in names or fn.args.kwarg is not None


# --------------------------------------------------------- executor reads
def executor_reads(module: PyModule, fn: FunctionNode) -> tuple[list[Read], set[str]]:
    """Action parameters ``fn`` reads unconditionally (with where) and those it tests
    (``"t" in action.args``: read only when present). The action is ``fn``'s second
    parameter; calls passing it to functions of the same module are followed."""
    names = parameter_names(fn)
    if len(names) < 2:
        return [], set()
    reads: list[Read] = []
    optional: set[str] = set()
    _walk_reads(module, fn, names[1], reads, optional, set())
    return [r for r in reads if r.key not in optional], optional


def _walk_reads(module: PyModule, fn: FunctionNode, var: str, reads: list[Read],
                optional: set[str], seen: set[tuple[str, str]]) -> None:
    if (fn.name, var) in seen:
        return
    seen.add((fn.name, var))
    for node in _own_nodes(fn):
        if isinstance(node, py.Compare) and _is_args_of(node.comparators[0] if node.comparators else None, var):
            key = _const_str(node.left)
            if key is not None and isinstance(node.ops[0], (py.In, py.NotIn)):
                optional.add(key)
        elif isinstance(node, py.Subscript) and _is_args_of(node.value, var):
            _add_read(reads, node.slice, node)
        elif isinstance(node, py.Call):
            _call_reads(module, node, var, reads, optional, seen)


def _call_reads(module: PyModule, call: py.Call, var: str, reads: list[Read],
                optional: set[str], seen: set[tuple[str, str]]) -> None:
    func = call.func
    if isinstance(func, py.Attribute) and func.attr == "get" and _is_args_of(func.value, var):
        key = _const_str(call.args[0]) if call.args else None
        if key is not None:
            optional.add(key)
        return
    for i, a in enumerate(call.args):
        if not (isinstance(a, py.Name) and a.id == var):
            continue
        if i + 1 < len(call.args) and _const_str(call.args[i + 1]) is not None:
            _add_read(reads, call.args[i + 1], call.args[i + 1])  # arg(action, "o", ...)
        callee = module.function(func.id) if isinstance(func, py.Name) else None
        if isinstance(callee, (py.FunctionDef, py.AsyncFunctionDef)):
            params = parameter_names(callee)
            if i < len(params):
                _walk_reads(module, callee, params[i], reads, optional, seen)


def _add_read(reads: list[Read], key_node: py.AST, where: py.AST) -> None:
    key = _const_str(key_node)
    if key is not None:
        reads.append(Read(key, where.lineno, where.col_offset + 1,
                          (where.end_col_offset or where.col_offset) + 1))


def _is_args_of(node: py.AST | None, var: str) -> bool:
    return (isinstance(node, py.Attribute) and node.attr == "args"
            and isinstance(node.value, py.Name) and node.value.id == var)


def _const_str(node: py.AST | None) -> str | None:
    return node.value if isinstance(node, py.Constant) and isinstance(node.value, str) else None


def _own_nodes(fn: FunctionNode) -> Iterator[py.AST]:
    """Every node of ``fn``'s body, not descending into nested functions or classes."""
    stack: list[py.AST] = list(reversed(fn.body))
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, (py.FunctionDef, py.AsyncFunctionDef, py.ClassDef, py.Lambda)):
            continue
        stack.extend(reversed(list(py.iter_child_nodes(node))))


# ---------------------------------------------------------- generator shape
@dataclass(frozen=True)
class Shape:
    """A ``yield``/``return`` literal whose samples hold ``size`` values."""

    size: int
    line: int
    col: int
    end_col: int
    returns_one_tuple: bool = False  # `return (p, t)`: the engine iterates it value by value


def sample_shapes(fn: FunctionNode, n_outputs: int) -> list[Shape]:
    """Literal samples of generator ``fn`` whose size cannot be ``n_outputs``."""
    nodes = list(_own_nodes(fn))
    is_generator = any(isinstance(n, (py.Yield, py.YieldFrom)) for n in nodes)
    bad: list[Shape] = []
    for node in nodes:
        if isinstance(node, py.Yield) and node.value is not None:
            size = _literal_size(node.value)
            if size is not None and size != n_outputs:
                bad.append(_shape(size, node.value))
        elif isinstance(node, py.Return) and node.value is not None and not is_generator:
            bad.extend(_returned(node.value, n_outputs))
    return bad


def _returned(value: py.expr, n_outputs: int) -> list[Shape]:
    if isinstance(value, (py.List, py.Tuple, py.Set)):
        elements = value.elts
        if (isinstance(value, py.Tuple) and n_outputs > 1 and elements
                and not all(isinstance(e, (py.Tuple, py.List)) for e in elements)):
            return [_shape(len(elements), value, returns_one_tuple=True)]
    elif isinstance(value, (py.ListComp, py.GeneratorExp, py.SetComp)):
        elements = [value.elt]
    else:
        return []
    out = []
    for e in elements:
        size = _literal_size(e)
        if size is not None and size != n_outputs:
            out.append(_shape(size, e))
    return out


def _literal_size(value: py.expr) -> int | None:
    """Values in one sample: a tuple/list literal's length, 1 for a constant."""
    if isinstance(value, (py.Tuple, py.List)):
        if any(isinstance(e, py.Starred) for e in value.elts):
            return None
        return len(value.elts)
    if isinstance(value, py.Constant) and value.value is not None:
        return 1
    return None


def _shape(size: int, node: py.expr, returns_one_tuple: bool = False) -> Shape:
    return Shape(size, node.lineno, node.col_offset + 1,
                 (node.end_col_offset or node.col_offset) + 1, returns_one_tuple)
