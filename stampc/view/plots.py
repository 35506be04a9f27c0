"""The coverage-over-time figure of the report: an inline SVG drawn with matplotlib.

The probability mass is split as the engine reports it: refined paths to the goal, to
proven dead ends, and the unrefined rest (coverage = goal + proven dead ends). A static
SVG rather than a plotting library's script: plotly's bundle alone is 4.8 MB, and the
whole report should stay well under 5 MB.
"""

from __future__ import annotations

import io
from typing import Sequence

from stampc.view.rundir import CoveragePoint

COLORS = {"goal": "#3a9d5d", "dead end (proven)": "#c0392b", "unrefined": "#d5d8dc"}


def changes(points: Sequence[CoveragePoint]) -> list[CoveragePoint]:
    """The points where the mass split changes, and the last one: a step plot of them
    is the same picture, and a run has thousands of events."""
    kept: list[CoveragePoint] = []
    for p in points:
        if not kept or (p.coverage, p.goal_probability) != (kept[-1].coverage,
                                                            kept[-1].goal_probability):
            kept.append(p)
    if points and kept[-1] is not points[-1]:
        kept.append(points[-1])
    return kept


def coverage_svg(points: Sequence[CoveragePoint], title: str = "") -> str:
    """The stacked mass split over time as an ``<svg>`` element (no XML prologue)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    points = changes(points)
    times = [p.time_s for p in points]
    goal = [p.goal_probability for p in points]
    dead = [max(0.0, p.coverage - p.goal_probability) for p in points]
    rest = [max(0.0, 1.0 - p.coverage) for p in points]
    fig, ax = plt.subplots(figsize=(7.5, 3.2), dpi=100)
    ax.stackplot(times, goal, dead, rest, step="post", labels=list(COLORS),
                 colors=list(COLORS.values()))
    ax.step(times, [p.coverage for p in points], where="post", color="black", linewidth=1.2,
            label="coverage")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("probability mass")
    ax.set_ylim(0, 1.0)
    ax.set_xlim(min(times), max(times) if max(times) > min(times) else min(times) + 1e-3)
    ax.set_title(title or "coverage over time")
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, frameon=False)
    fig.tight_layout()
    buffer = io.StringIO()
    with matplotlib.rc_context({"svg.fonttype": "none"}):  # <text>, not glyph outlines
        fig.savefig(buffer, format="svg")
    plt.close(fig)
    text = buffer.getvalue()
    return text[text.index("<svg"):]
