"""stampc.backends.ppddl: PPDDL (IPPC 2006/2008 dialect) import and emission.

- :func:`import_ppddl` / :func:`import_ppddl_text`: PPDDL → lifted IR ``Model``;
- :func:`emit_ppddl`: lifted IR ``Model`` → (domain text, problem text);
- :func:`model_to_ppddl`: the same for a compiled stamp model (generated symbols and
  certified facts made explicit).

See docs/ppddl.md for the dialect, name mangling, cost conventions and diagnostics.
Names resolve lazily, so importing PPDDL does not load the emitter's jinja2 templates.
"""

from __future__ import annotations

from stampc.lazy import lazy_exports

_LAZY = {name: f"stampc.backends.ppddl.{module}" for name, module in {
    "emit_ppddl": "emitter", "model_to_ppddl": "model_export", "import_domain_only": "importer",
    "import_ppddl": "importer", "import_ppddl_text": "importer",
}.items()}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = lazy_exports(globals(), _LAZY)
