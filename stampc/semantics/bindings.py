"""Static checks of ``binds``/``executes`` bindings, run by ``stampc check``.

The bound module's source is found by hand (:mod:`stampc.semantics.pyfind`) and read
with :mod:`ast` (:mod:`stampc.semantics.pysig`): nothing is imported or run. A binding is
checked against the arguments the engine passes (``stampc/worlds/base.py``):

    generator(ctx, *inputs) -> iterable of output tuples
    evaluator(ctx, *predicate_args) -> bool
    executor(ctx, action[, outcome=...])   # reads action parameters by name

A world-relative binding (``".manipulation:pick"``) is checked on every world package
that has the module; it is an error only when it fails on all of them (the domain may be
meant for one world only; ``refine --world W`` checks that world again when it runs).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from stampc.diagnostics import Diagnostic, Label, Span
from stampc.semantics import pysig
from stampc.semantics.codes import diag
from stampc.semantics.loader import display_name
from stampc.semantics.pyfind import Found, find_in_folder, find_module, world_folders
from stampc.semantics.scope import DomainInfo, suggest
from stampc.syntax import ast


@dataclass(frozen=True)
class BoundUse:
    """One binding and what the engine passes to it."""

    binding: ast.String
    what: str                     # "generator `grasp`", "action `pick`", ...
    kind: str                     # "generator" | "evaluator" | "executor"
    params: tuple[str, ...]       # declared inputs / predicate parameters / action parameters
    outputs: int = 0              # generators: values per sample


def binding_uses(info: DomainInfo) -> list[BoundUse]:
    uses: list[BoundUse] = []
    for g in info.generators.values():
        if g.binding is not None:
            uses.append(BoundUse(g.binding, f"generator `{g.name.name}`", "generator",
                            tuple(p.name.name for p in g.inputs), len(g.outputs)))
    for ev in info.evaluators:
        pred = info.predicates.get(ev.predicate.name)
        if ev.binding is not None and pred is not None:
            uses.append(BoundUse(ev.binding, f"evaluator of `{ev.predicate.name}`", "evaluator",
                            tuple(p.name.name for p in pred.params)))
    for a in info.actions:
        if a.executes is not None:
            uses.append(BoundUse(a.executes, f"action `{a.name.name}`", "executor",
                            tuple(p.name.name for p in a.params)))
    return uses


def check_bindings(info: DomainInfo, diags: list[Diagnostic]) -> None:
    """Append a diagnostic for every binding that cannot work (E601–E605), that is
    suspicious (W407) or that cannot be read without importing (N601)."""
    modules: dict[Path, pysig.PyModule | SyntaxError] = {}
    for use in binding_uses(info):
        module, sep, func = use.binding.value.partition(":")
        if not sep or not module or not func or not info.is_local(use.binding.span):
            continue  # malformed: E306 already; used modules: checked where they live
        if module.startswith("."):
            _check_relative(use, module[1:], func, modules, diags)
        else:
            found = find_module(module, _stamp_folder(use.binding.span))
            if found is None:
                diags.append(diag("E601", f"cannot find module `{module}` bound by {use.what}",
                                  use.binding.span, f"place {module.replace('.', '/')}.py in the "
                                  "folder of this file or one of its parents, or make it importable"))
            else:
                diags.extend(_check_found(use, module, func, found, modules))


def _stamp_folder(span: Span) -> Path | None:
    return None if span.file.startswith("<") else Path(span.file).parent


def _check_relative(use: BoundUse, module: str, func: str, modules: dict,
                    diags: list[Diagnostic]) -> None:
    worlds = world_folders()
    per_world = {w: find_in_folder(folder, module) for w, folder in worlds.items()}
    found = {w: f for w, f in per_world.items() if f is not None}
    if not found:
        diags.append(diag("E601", f"no world provides module `.{module}` bound by {use.what}",
                          use.binding.span, "a leading `.` names a module of the world package "
                          f"(worlds: {', '.join(worlds)}); write \"package.module:function\" "
                          "for your own code"))
        return
    results = {w: _check_found(use, f".{module}", func, f, modules, w) for w, f in found.items()}
    if any(not problems for problems in results.values()):
        return  # works on some world: the domain may be meant for that one
    first = next(iter(results))
    diags.extend(results[first])


def _check_found(use: BoundUse, module: str, func: str, found: Found, modules: dict,
                 world: str | None = None) -> list[Diagnostic]:
    where = f" (world {world})" if world else ""
    if found.path is None:
        return [diag("N601", f"cannot read the binding of {use.what} without importing it: "
                     f"{found.opaque}; it is checked when refine imports it", use.binding.span)]
    parsed = modules.get(found.path)
    if parsed is None:
        parsed = modules[found.path] = pysig.parse_module(found.path)
    shown = display_name(found.path)
    if isinstance(parsed, SyntaxError):
        at = Span.point(shown, parsed.lineno or 1, parsed.offset or 1)
        return [diag("E601", f"module `{module}` bound by {use.what} has a syntax error{where}: "
                     f"{parsed.msg}", use.binding.span, labels=(Label(at, "here"),))]
    fn = parsed.function(func)
    if fn is None:
        return [diag("E602", f"module `{module}` has no function `{func}`{where} "
                     f"(bound by {use.what})", use.binding.span,
                     _suggest_function(parsed, func),
                     labels=(Label(Span.point(shown), "the module"),))]
    if isinstance(fn, str):
        return [diag("N601", f"`{module}:{func}` is not a plain `def`{where}; its signature "
                     "is checked when refine imports it", use.binding.span)]
    return _signature(use, fn, parsed, shown, where)


def _suggest_function(module: pysig.PyModule, func: str) -> str | None:
    names = [n.name for n in module.tree.body if isinstance(n, (pysig.py.FunctionDef,
                                                               pysig.py.AsyncFunctionDef))]
    return suggest(func, names)


def _py_span(shown: str, line: int, col: int, end_col: int) -> Span:
    return Span(shown, line, col, line, max(end_col, col + 1))


def _def_label(fn: pysig.FunctionNode, shown: str) -> Label:
    return Label(_py_span(shown, fn.lineno, fn.col_offset + 1, fn.col_offset + 4 + len(fn.name) + 1),
                 f"`{fn.name}` is defined here")


def _signature(use: BoundUse, fn: pysig.FunctionNode, module: pysig.PyModule, shown: str,
               where: str) -> list[Diagnostic]:
    out: list[Diagnostic] = []
    label = (_def_label(fn, shown),)
    if use.kind == "executor":
        keywords = ("outcome",) if pysig.declares(fn, "outcome") else ()
        if not pysig.accepts(fn, 2, keywords):
            out.append(diag("E603", f"`{fn.name}`{where} cannot be called as the executor of "
                            f"{use.what}: executors take (ctx, action) or (ctx, action, outcome)",
                            use.binding.span, "define it as `def "
                            f"{fn.name}(ctx, action, outcome=None)`", label))
            return out
        return out + _executor_reads(use, fn, module, shown, where)
    n = len(use.params) + 1
    if not pysig.accepts(fn, n):
        args = ", ".join(("ctx",) + use.params)
        out.append(diag("E603", f"`{fn.name}`{where} cannot be called with a context and "
                        f"{len(use.params)} argument{'s' if len(use.params) != 1 else ''} as "
                        f"{use.what} requires", use.binding.span,
                        f"the engine calls {fn.name}({args}); its parameters are "
                        f"({', '.join(pysig.parameter_names(fn))})", label))
        return out
    names = tuple(pysig.parameter_names(fn)[1:n])
    if names != use.params and sorted(names) == sorted(use.params):
        out.append(diag("W407", f"`{fn.name}`{where} takes ({', '.join(names)}) but {use.what} "
                        f"passes ({', '.join(use.params)}): arguments are passed by position",
                        use.binding.span, "reorder the parameters on one side", label))
    if use.kind == "generator":
        out.extend(_shapes(use, fn, shown, where))
    return out


def _executor_reads(use: BoundUse, fn: pysig.FunctionNode, module: pysig.PyModule, shown: str,
                    where: str) -> list[Diagnostic]:
    reads, _optional = pysig.executor_reads(module, fn)
    out: list[Diagnostic] = []
    reported: set[str] = set()
    for r in reads:
        if r.key in use.params or r.key in reported:
            continue
        reported.add(r.key)
        out.append(diag("E604", f"executor `{fn.name}`{where} reads action parameter `{r.key}`, "
                        f"but {use.what} has ({', '.join(use.params) or 'none'})",
                        use.binding.span, f"executors read action parameters by name: rename the "
                        f"parameter that holds this value to `{r.key}`",
                        (Label(_py_span(shown, r.line, r.col, r.end_col), f"`{r.key}` is read here"),)))
    return out


def _shapes(use: BoundUse, fn: pysig.FunctionNode, shown: str, where: str) -> list[Diagnostic]:
    out = []
    for s in pysig.sample_shapes(fn, use.outputs):
        at = _py_span(shown, s.line, s.col, s.end_col)
        if s.returns_one_tuple:
            message = (f"generator `{fn.name}`{where} returns one tuple of {s.size} values, but "
                       f"{use.what} outputs {use.outputs} per sample: the engine iterates the "
                       "return value, one sample per item")
            hint = "yield each sample (`yield (p, t)`) or return a list of them (`return [(p, t)]`)"
        else:
            message = (f"generator `{fn.name}`{where} produces samples of {s.size} "
                       f"value{'s' if s.size != 1 else ''}, but {use.what} declares "
                       f"{use.outputs} output{'s' if use.outputs != 1 else ''}")
            hint = "one value per declared output, in the declared order"
        out.append(diag("E605", message, use.binding.span, hint, (Label(at, "this sample"),)))
    return out
