"""The coverage-over-time figure of the report: the run's own figure
(:func:`stampc.figures.coverage_svg`: the mass split into goal, proven dead ends
and the unrefined rest), inline. A static SVG rather than a plotting library's script:
plotly's bundle alone is 4.8 MB, and the whole report should stay well under 5 MB.
"""

from __future__ import annotations

from typing import Sequence

from stampc import figures
from stampc.view.rundir import CoveragePoint


def coverage_svg(points: Sequence[CoveragePoint], title: str = "") -> str:
    """The stacked mass split over time as an ``<svg>`` element (no XML prologue)."""
    return figures.coverage_svg([p.time_s for p in points], [p.coverage for p in points],
                                [p.goal_probability for p in points], title)
