"""Find the source file of a bound Python module without importing anything.

``importlib.util.find_spec("a.b")`` imports package ``a`` to read its ``__path__``; user
code must not run during ``check``. So the lookup walks folders by hand, in the order
the loader (:mod:`stampc.worlds.modules`) uses: ``sys.path`` entries first, then the
folder of the stamp file that binds the module and that folder's ancestors. Only a
*top-level* name is ever handed to ``importlib.util.find_spec`` (which imports nothing
for a name without a parent), to follow import hooks such as editable installs.
"""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import dataclass
from pathlib import Path

COMPILED_SUFFIXES = (".so", ".pyd", ".pyc")


@dataclass(frozen=True)
class Found:
    """Where a module is: ``path`` of its ``.py`` source, or ``opaque`` with the reason
    its source cannot be read without importing (built in, compiled, an import hook)."""

    path: Path | None = None
    opaque: str | None = None


def world_folders() -> dict[str, Path]:
    """The world packages shipped with stampc (``stampc/worlds/<name>/``), by name: a
    world-relative binding (``".manipulation:grasp"``) is looked up in each of them."""
    root = Path(__file__).resolve().parents[1] / "worlds"
    return {p.name: p for p in sorted(root.iterdir()) if (p / "__init__.py").is_file()}


def find_module(name: str, search_from: Path | None) -> Found | None:
    """The module ``name`` (dotted, absolute); None when it is nowhere to be found."""
    parts = name.split(".")
    if not all(p.isidentifier() for p in parts):
        return None
    if len(parts) == 1 and name in sys.builtin_module_names:
        return Found(opaque=f"`{name}` is a built-in module")
    for root in _roots(search_from):
        found = _under(root, parts)
        if found is not None:
            return found
    return _via_hooks(parts)


def find_in_folder(folder: Path, dotted: str) -> Found | None:
    """Module ``dotted`` below package folder ``folder`` (for world-relative bindings)."""
    parts = dotted.split(".")
    if not all(p.isidentifier() for p in parts):
        return None
    return _under(folder, parts)


def _roots(search_from: Path | None) -> list[Path]:
    roots = [Path(p) if p else Path.cwd() for p in sys.path if isinstance(p, str)]
    if search_from is not None:
        start = search_from.resolve()
        roots += [start, *start.parents]
    return roots


def _under(root: Path, parts: list[str]) -> Found | None:
    """``a/b/c.py`` or ``a/b/c/__init__.py`` below ``root`` for ``a.b.c``, every parent
    a package folder (regular or namespace)."""
    folder = root
    for part in parts[:-1]:
        folder = folder / part
        if not folder.is_dir():
            return None
    return _module_in(folder, parts[-1])


def _module_in(folder: Path, leaf: str) -> Found | None:
    source = folder / f"{leaf}.py"
    if source.is_file():
        return Found(path=source)
    package = folder / leaf / "__init__.py"
    if package.is_file():
        return Found(path=package)
    try:
        compiled = [p for p in folder.glob(f"{leaf}.*") if p.suffix in COMPILED_SUFFIXES]
    except OSError:
        compiled = []
    if compiled:
        return Found(opaque=f"`{leaf}` is a compiled module ({compiled[0].name})")
    return None


def _via_hooks(parts: list[str]) -> Found | None:
    """Follow a top-level name through the import system's finders (editable installs,
    zip imports) — finding a spec for a top-level name imports nothing."""
    try:
        spec = importlib.util.find_spec(parts[0])
    except (ImportError, ValueError):
        return None
    if spec is None:
        return None
    rest = parts[1:]
    locations = list(spec.submodule_search_locations or [])
    if not rest:
        origin = spec.origin or ""
        if origin.endswith(".py") and Path(origin).is_file():
            return Found(path=Path(origin))
        return Found(opaque=f"`{parts[0]}` is not a Python source file ({spec.origin or 'no file'})")
    for location in locations:
        found = _under(Path(location), rest)
        if found is not None:
            return found
    if not locations:
        return None
    return Found(opaque=f"package `{parts[0]}` is installed by an import hook; "
                 f"`{'.'.join(parts)}` is not a plain file below it")
