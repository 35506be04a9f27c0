"""stampc.backends.ppddl: PPDDL (IPPC 2006/2008 dialect) import and emission.

- :func:`import_ppddl` / :func:`import_ppddl_text`: PPDDL → lifted IR ``Model``;
- :func:`emit_ppddl`: lifted IR ``Model`` → (domain text, problem text).

See docs/ppddl.md for the dialect, name mangling, cost conventions and diagnostics.
"""

from stampc.backends.ppddl.emitter import emit_ppddl
from stampc.backends.ppddl.importer import import_domain_only, import_ppddl, import_ppddl_text

__all__ = ["emit_ppddl", "import_domain_only", "import_ppddl", "import_ppddl_text"]
