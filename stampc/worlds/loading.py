"""Open a concrete world for a problem: resolve its scene reference and the backend.

A scene reference is either a JSON file (relative to the problem file) or a bound
scene builder ``"pkg.module:function"(key=value, ...)`` returning the scene dict. A
builder module that is not importable from ``sys.path`` is looked up as a file relative
to the problem's folder and its ancestors (so ``examples.cluttered_table.scene:build``
works from a source checkout without installing the examples).
"""

from __future__ import annotations

import importlib
import json
from pathlib import Path
from typing import Any, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.ir.lifted import Problem, SceneRef
from stampc.worlds.bindings import world_package
from stampc.worlds.modules import import_bound_module


def _fail(code: str, message: str, ref: SceneRef | None, hint: str | None = None):
    span = (ref.span if ref and ref.span else Span.point("<problem>"))
    raise StampcError([error(code, message, span, hint=hint)])


def _import_builder(ref: SceneRef, base_dir: Path):
    module_name, sep, func_name = ref.target.partition(":")
    if not sep or not module_name or not func_name:
        _fail("S102", f"malformed scene builder {ref.target!r}", ref, 'write "package.module:function"')
    try:
        module = import_bound_module(module_name, base_dir)
    except Exception as exc:  # user code failing at import time is reported, not raised
        _fail("S103", f"scene builder module {module_name!r} failed to load: "
              f"{type(exc).__name__}: {exc}", ref)
    if module is None:
        _fail("S103", f"cannot find scene builder module {module_name!r}", ref,
              f"make it importable, or place {module_name.replace('.', '/')}.py in the "
              "problem file's folder or one of its parents")
    fn = getattr(module, func_name, None)
    if not callable(fn):
        _fail("S104", f"module {module_name!r} has no function {func_name!r}", ref)
    return fn


def load_scene(problem: Problem, base_dir: Path, overrides: Mapping[str, Any] | None = None) -> dict:
    """Return the scene dict of ``problem`` (``overrides`` replace builder arguments)."""
    ref = problem.scene
    if ref is None:
        _fail("S100", f"problem {problem.name!r} has no scene", None,
              'add `scene "scene.json"` or `scene builder "pkg.mod:build"(...)`')
    if ref.kind == "file":
        path = (base_dir / ref.target).resolve()
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except OSError as exc:
            _fail("S101", f"cannot read scene file {str(path)!r}: {exc.strerror}", ref)
        except json.JSONDecodeError as exc:
            _fail("S101", f"scene file {str(path)!r} is not valid JSON: {exc}", ref)
    fn = _import_builder(ref, base_dir)
    kwargs = dict(ref.args)
    kwargs.update(overrides or {})
    try:
        scene = fn(**kwargs)
    except Exception as exc:  # a failing builder is user code: report it where it is bound
        _fail("S105", f"scene builder {ref.target} raised {type(exc).__name__}: {exc}", ref)
    if not isinstance(scene, Mapping):
        _fail("S106", f"scene builder {ref.target} returned {type(scene).__name__}, not a dict", ref)
    return dict(scene)


def open_world(name: str, scene: Mapping[str, Any], *, seed: int, verbose: bool = False):
    """Instantiate world backend ``name`` on ``scene``."""
    package = importlib.import_module(world_package(name))
    try:
        return package.open_world(scene, seed=seed, verbose=verbose)
    except StampcError:
        raise
    except (KeyError, ValueError, TypeError) as exc:
        raise StampcError([error("S107", f"invalid scene for world {name!r}: "
                                 f"{type(exc).__name__}: {exc}", Span.point("<scene>"))]) from None
