"""stampc: stochastic task and motion planning (ATM-MDP) toolkit.

Public API: ``parse``, ``load``, ``check`` (front end); ``compile``, ``import_ppddl``,
``load_model``, ``ground``, ``to_ppddl`` (IR and PPDDL); ``solve`` (SSP solvers);
``refine_policy`` (anytime refinement; the engine itself is ``stampc.refine``). Stages are imported lazily so that ``stampc check``
stays fast and never touches simulators.
"""

from __future__ import annotations

from stampc.diagnostics import Diagnostic, Severity, Span, StampcError
from stampc.lazy import lazy_exports

__version__ = "0.1.0"

_LAZY = {
    "parse": "stampc.semantics.api", "load": "stampc.semantics.api",
    "check": "stampc.semantics.api",
    "compile": "stampc.api", "import_ppddl": "stampc.api", "load_model": "stampc.api",
    "ground": "stampc.api", "to_ppddl": "stampc.api", "solve": "stampc.api",
    "refine_policy": "stampc.api",
}

__all__ = ["Diagnostic", "Severity", "Span", "StampcError", "__version__", *_LAZY]
__getattr__, __dir__ = lazy_exports(globals(), _LAZY)
