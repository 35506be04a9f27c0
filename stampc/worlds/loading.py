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
import re
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Mapping

from stampc.diagnostics import Diagnostic, Span, StampcError, error
from stampc.inputs import display_name, read_input_text
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
        path = base_dir / ref.target
        try:
            text = read_input_text(path, display_name(path))  # binary: I001 in the scene file
        except OSError as exc:
            _fail("S101", f"cannot read scene file: {exc}", ref)
        try:
            return json.loads(text)
        except json.JSONDecodeError as exc:
            raise StampcError([error("S101", f"scene file is not valid JSON: {exc.msg}",
                                     Span.point(display_name(path), exc.lineno, exc.colno))])
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


@dataclass(frozen=True)
class SceneOrigin:
    """Where a scene dict came from, so that the world's complaints about it point there."""

    span: Span               # the scene file, or the problem's `scene builder` line
    what: str                # e.g. "in the scene built by examples.x.scene:build"
    text: str | None = None  # a scene file's JSON, to find the line of a section


def scene_origin(problem: Problem, base_dir: Path) -> SceneOrigin | None:
    """The origin of ``problem``'s scene (read by :func:`load_scene`)."""
    ref = problem.scene
    if ref is None:
        return None
    if ref.kind == "file":
        path = base_dir / ref.target
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            text = None
        return SceneOrigin(Span.point(display_name(path)), "in this scene file", text)
    span = ref.span or Span.point("<problem>")
    return SceneOrigin(span, f"in the scene built by {ref.target}")


def open_world(name: str, scene: Mapping[str, Any], *, seed: int, verbose: bool = False,
               origin: SceneOrigin | None = None, visuals: bool = True):
    """Instantiate world backend ``name`` on ``scene``; diagnostics about the scene point
    at ``origin`` (its file and the line of the offending section where it can tell).
    ``visuals=False``: a world that will never render (the refinement's) may skip what
    only drawing needs."""
    package = importlib.import_module(world_package(name))
    try:
        return package.open_world(scene, seed=seed, verbose=verbose, visuals=visuals)
    except StampcError as exc:
        if origin is None:
            raise
        raise StampcError([_relocated(d, origin) for d in exc.diagnostics]) from None
    except (KeyError, ValueError, TypeError) as exc:
        d = error("S107", f"invalid scene for world {name!r}: {type(exc).__name__}: {exc}",
                  Span.point("<scene>"))
        raise StampcError([_relocated(d, origin) if origin else d]) from None


_PLANE2D_KEY = re.compile(r"^scene ([A-Za-z_]\w*)")


def _relocated(d: Diagnostic, origin: SceneOrigin) -> Diagnostic:
    """``d`` moved from a ``<scene ...>`` placeholder to the scene's real origin."""
    if not d.span.file.startswith("<scene"):
        return d
    section = d.span.file[len("<scene"):-1].strip()  # pybullet: "<scene objects>", line = entry
    message = f"scene {section} entry {d.span.line}: {d.message}" if section else d.message
    key = section or next(iter(_PLANE2D_KEY.findall(d.message)), "")
    return replace(d, span=_key_span(origin, key), message=f"{message} ({origin.what})")


def _key_span(origin: SceneOrigin, key: str) -> Span:
    """The line of ``"key":`` in a scene file; the origin itself otherwise."""
    if origin.text is None or not key:
        return origin.span
    for lineno, line in enumerate(origin.text.splitlines(), 1):
        col = line.find(f'"{key}"')
        if col >= 0:
            return Span(origin.span.file, lineno, col + 1, lineno, col + len(key) + 3)
    return origin.span
