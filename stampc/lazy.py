"""Lazy public names for packages: resolved (imported) on first use, so importing a
package for one light name does not load its heavy stages (start-up time)."""

from __future__ import annotations

from importlib import import_module
from typing import Any, Callable


def lazy_exports(namespace: dict[str, Any],
                 table: dict[str, str]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """A module ``__getattr__`` and ``__dir__`` for the module whose globals are
    ``namespace``: ``table`` maps each public name to the module that defines it."""
    package = namespace["__name__"]

    def __getattr__(name: str) -> Any:
        if name not in table:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(table[name]), name)
        namespace[name] = value  # resolved once; also wins over a same-named submodule
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__
