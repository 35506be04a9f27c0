"""``stampc view``: a self-contained HTML report of a refine run (docs/view.md).

``rundir`` reads the run directory, ``model`` turns the policy into the page's data
(tree layout by igraph), ``plots`` draws the coverage figure, ``page`` inlines
everything into one HTML file (vis-network from the ``view`` extra draws the graph).
"""

from __future__ import annotations

from pathlib import Path

from stampc.view.page import MissingViewExtra, render_report, write_report
from stampc.view.rundir import RunDir, load_run_dir

__all__ = ["MissingViewExtra", "RunDir", "load_run_dir", "render_report", "write_report",
           "view_run"]


def view_run(run_dir: str | Path, out: str | Path | None = None) -> Path:
    """Write the report of ``run_dir`` (default ``RUN_DIR/report.html``); its path."""
    run = load_run_dir(Path(run_dir))
    return write_report(run, Path(out) if out else Path(run_dir) / "report.html")
