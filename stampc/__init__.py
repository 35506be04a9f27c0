"""stampc: stochastic task and motion planning (ATM-MDP) toolkit.

Public API (see docs/): ``parse``, ``load``, ``check``, ``compile``, ``import_ppddl``,
``solve``, ``refine``. Heavy stages are imported lazily so that ``stampc check`` stays
fast and never touches simulators.
"""

from __future__ import annotations

from stampc.diagnostics import Diagnostic, Severity, Span, StampcError

__version__ = "0.1.0"

__all__ = ["Diagnostic", "Severity", "Span", "StampcError", "__version__"]
