"""Import the Python module a binding or scene builder names (``"pkg.module:function"``).

A module importable from ``sys.path`` is imported normally. Otherwise its file is looked
up relative to the folder of the stamp file that names it, then that folder's ancestors
(``examples.cluttered_table.scene`` from ``examples/cluttered_table/problem.stamp``
finds ``<checkout>/examples/cluttered_table/scene.py``), so examples work from a source
checkout with an installed ``stampc`` console script, from any working directory.

Such a file is loaded the way ``import`` would load it with its root folder on
``sys.path`` — without touching ``sys.path``: the module and each parent package are
registered in ``sys.modules`` under their dotted names. That registration is what
``@dataclass``, pickling, ``typing.get_type_hints`` and package-relative imports
(``from . import helpers``) need.

Registrations are checked on every later lookup, so one process never reuses a stale
module: when the same dotted name now resolves to a different file (another checkout, or
a second folder with its own top-level ``scene.py``) or the file changed on disk, the
file is loaded afresh and replaces the earlier entry. An unchanged file is reused, as
``import`` would. Modules imported from ``sys.path`` are never replaced.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import importlib.util
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType


@dataclass(frozen=True)
class FileLoaded:
    """Marks a module stampc loaded from a file (stored as its spec's ``loader_state``)."""

    origin: str  # the file, or the package folder of a namespace package
    mtime_ns: int


def import_bound_module(name: str, search_from: Path | None) -> ModuleType | None:
    """The module ``name``; None when it is neither importable nor found as a file.

    Exceptions raised by the module's own code (including a missing dependency) propagate.
    """
    if search_from is not None and _any_file_loaded(name):
        root = _root_folder(name, search_from)
        if root is not None:
            return _load_from_root(name, root)  # revalidates our earlier registration
    _forget_file_loaded(name)  # never let import_module reuse one we cannot revalidate
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if not _names_module_or_parent(exc.name, name):
            raise  # the module was found but one of its own imports is missing
    root = _root_folder(name, search_from) if search_from is not None else None
    return _load_from_root(name, root) if root is not None else None


def _names_module_or_parent(missing: str | None, name: str) -> bool:
    return missing is not None and (name == missing or name.startswith(missing + "."))


def _prefixes(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[: i + 1]) for i in range(len(parts))]


def _file_loaded(module: ModuleType | None) -> FileLoaded | None:
    spec = getattr(module, "__spec__", None)
    state = getattr(spec, "loader_state", None)
    return state if isinstance(state, FileLoaded) else None


def _any_file_loaded(name: str) -> bool:
    return any(_file_loaded(sys.modules.get(p)) is not None for p in _prefixes(name))


def _forget_file_loaded(name: str) -> None:
    for prefix in _prefixes(name):
        if _file_loaded(sys.modules.get(prefix)) is not None:
            del sys.modules[prefix]


def _root_folder(name: str, start: Path) -> Path | None:
    """The nearest of ``start`` and its ancestors holding ``a/b/c.py`` (or ``a/b/c/``
    as a package) for ``name == "a.b.c"``."""
    rel = Path(*name.split("."))
    start = start.resolve()
    for folder in (start, *start.parents):
        candidate = folder / rel
        if candidate.with_suffix(".py").is_file() or (candidate / "__init__.py").is_file():
            return folder
    return None


def _load_from_root(name: str, root: Path) -> ModuleType | None:
    """Import ``name`` and its parent packages as if ``root`` led ``sys.path``."""
    search = [str(root)]
    module: ModuleType | None = None
    for prefix in _prefixes(name):
        spec = importlib.machinery.PathFinder.find_spec(prefix, search)
        if spec is None:
            return None
        module = _current_or_fresh(prefix, spec)
        search = list(getattr(module, "__path__", []))
    return module


def _origin_of(spec: importlib.machinery.ModuleSpec) -> FileLoaded:
    if spec.origin and spec.has_location:
        return FileLoaded(spec.origin, Path(spec.origin).stat().st_mtime_ns)
    # a namespace package: pin its path (a live _NamespacePath would re-search sys.path)
    spec.submodule_search_locations = list(spec.submodule_search_locations or [])
    return FileLoaded("|".join(spec.submodule_search_locations), 0)


def _current_or_fresh(prefix: str, spec: importlib.machinery.ModuleSpec) -> ModuleType:
    """The registered module for ``prefix`` if it came from the same unchanged place,
    else a fresh load of ``spec`` registered in its stead."""
    origin = _origin_of(spec)
    current = sys.modules.get(prefix)
    if current is not None and _file_loaded(current) in (origin, None):
        return current  # ours and unchanged, or imported from sys.path: keep it
    for stale in [n for n in sys.modules if n.startswith(prefix + ".")]:
        del sys.modules[stale]  # submodules of the replaced package: its old incarnation's
    spec.loader_state = origin
    module = importlib.util.module_from_spec(spec)
    sys.modules[prefix] = module
    try:
        if spec.loader is not None:
            spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(prefix, None)
        raise
    parent, _, child = prefix.rpartition(".")
    if parent and parent in sys.modules:
        setattr(sys.modules[parent], child, module)  # as `import` binds submodules
    return module
