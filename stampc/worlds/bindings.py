"""Resolve ``"pkg.module:function"`` bindings to callables — the only place that does.

``check``/``compile`` never come here. A bound module that is not on ``sys.path`` is
found as a file beside the stamp file that binds it (see :mod:`stampc.worlds.modules`). Refinement and execution resolve every binding a
model declares up front, so that a missing module, a missing function or a signature that
cannot accept the declared arguments is reported as a located diagnostic before any
planning starts (and never as a traceback in the middle of a run).
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Mapping

from stampc.diagnostics import Diagnostic, Span, StampcError, error
from stampc.ir.lifted import Binding, Model
from stampc.worlds.modules import import_bound_module

WORLD_PACKAGES = {
    "plane2d": "stampc.worlds.plane2d",
    "pybullet": "stampc.worlds.pybullet",
}


@dataclass(frozen=True)
class ResolvedBindings:
    generators: Mapping[str, Callable]
    evaluators: Mapping[str, Callable]
    executors: Mapping[str, Callable]  # by action name


def qualified_target(target: str, world_package: str) -> str:
    """Expand a world-relative binding (leading ``.``) to an absolute import path."""
    module, _, func = target.partition(":")
    if module.startswith("."):
        module = world_package + module
    return f"{module}:{func}"


def _span(binding: Binding) -> Span:
    return binding.span or Span.point("<model>")


def _declaring_folder(binding: Binding) -> Path | None:
    """The folder of the stamp file that declares ``binding`` (where a module that is not
    on ``sys.path`` is looked up as a file); None for bindings made in code."""
    if binding.span is None or binding.span.file.startswith("<"):
        return None
    return Path(binding.span.file).parent


def resolve(binding: Binding, world_package: str, n_args: int, what: str,
            diags: list[Diagnostic]) -> Callable | None:
    """Import one binding; check it accepts ``ctx`` plus ``n_args`` positional arguments."""
    target = qualified_target(binding.target, world_package)
    module_name, sep, func_name = target.partition(":")
    if not sep or not module_name or not func_name:
        diags.append(error("B101", f"malformed binding {binding.target!r} for {what}",
                           _span(binding), hint='write "package.module:function"'))
        return None
    try:
        module = import_bound_module(module_name, _declaring_folder(binding))
    except Exception as exc:  # any import-time failure of user code is reported, not raised
        diags.append(error("B102", f"cannot import module {module_name!r} bound by {what}: "
                           f"{type(exc).__name__}: {exc}", _span(binding),
                           hint="check the module path and that it is importable"))
        return None
    if module is None:
        diags.append(error("B102", f"cannot find module {module_name!r} bound by {what}",
                           _span(binding), hint="make it importable, or place "
                           f"{module_name.replace('.', '/')}.py in the folder of the file "
                           "that binds it or one of its parents"))
        return None
    fn = getattr(module, func_name, None)
    if not callable(fn):
        diags.append(error("B103", f"module {module_name!r} has no function {func_name!r} "
                           f"(bound by {what})", _span(binding)))
        return None
    if not _accepts(fn, n_args + 1):
        diags.append(error("B104", f"{target} cannot be called with a context and {n_args} "
                           f"argument{'s' if n_args != 1 else ''} as {what} requires",
                           _span(binding), hint="signature must be f(ctx, "
                           + ", ".join(f"a{i}" for i in range(n_args)) + ")"))
        return None
    return fn


def _accepts(fn: Callable, n: int) -> bool:
    try:
        signature = inspect.signature(fn)
    except ValueError:  # builtins without signatures: trust them
        return True
    try:
        signature.bind(*range(n))
    except TypeError:
        try:  # an outcome-aware executor: f(ctx, action, outcome)
            signature.bind(*range(n), outcome=None)
        except TypeError:
            return False
    return True


def resolve_model(model: Model, world_package: str) -> ResolvedBindings:
    """Resolve every generator, evaluator and executor binding of ``model``."""
    diags: list[Diagnostic] = []
    domain = model.domain
    preds = {p.name: p for p in domain.predicates}
    generators = {}
    for g in domain.generators:
        fn = resolve(g.binding, world_package, len(g.inputs), f"generator {g.name!r}", diags)
        if fn is not None:
            generators[g.name] = fn
    evaluators = {}
    for ev in domain.evaluators:
        arity = len(preds[ev.predicate].params) if ev.predicate in preds else 0
        fn = resolve(ev.binding, world_package, arity, f"evaluator of {ev.predicate!r}", diags)
        if fn is not None:
            evaluators[ev.predicate] = fn
    executors = {}
    for a in domain.actions:
        if a.executes is not None:
            fn = resolve(a.executes, world_package, 1, f"action {a.name!r}", diags)
            if fn is not None:
                executors[a.name] = fn
    if diags:
        raise StampcError(diags)
    return ResolvedBindings(generators, evaluators, executors)


def world_package(name: str) -> str:
    if name not in WORLD_PACKAGES:
        raise StampcError([error("B100", f"unknown world {name!r}", Span.point("<command line>"),
                                 hint="choose one of: " + ", ".join(sorted(WORLD_PACKAGES)))])
    return WORLD_PACKAGES[name]
