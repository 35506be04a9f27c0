"""stampc.backends.ppddl: PPDDL (IPPC 2006/2008 dialect) import and emission.

- :func:`import_ppddl` / :func:`import_ppddl_text`: PPDDL → lifted IR ``Model``;
- :func:`emit_ppddl`: lifted IR ``Model`` → (domain text, problem text).

See docs/ppddl.md for the dialect, name mangling, cost conventions and diagnostics.
Names are loaded on first use, so importing PPDDL does not load the emitter's Jinja2.
"""

from __future__ import annotations

import importlib

_HOMES = {"emit_ppddl": "stampc.backends.ppddl.emitter",
          "import_domain_only": "stampc.backends.ppddl.importer",
          "import_ppddl": "stampc.backends.ppddl.importer",
          "import_ppddl_text": "stampc.backends.ppddl.importer"}

__all__ = sorted(_HOMES)


def __getattr__(name: str):
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(_HOMES[name]), name)
