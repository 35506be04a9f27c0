"""Assemble the self-contained report: one HTML file with every script, style, figure
and frame inlined, so it opens offline and can be mailed or archived as it is.

The graph is drawn by vis-network, whose build ships inside the ``pyvis`` package (the
``view`` extra); it is read from the installed package, never fetched.
"""

from __future__ import annotations

import base64
import html
import importlib.util
import json
import re
from pathlib import Path
from typing import Any, Mapping

from stampc.view.model import page_data
from stampc.view.plots import coverage_svg
from stampc.view.rundir import RunDir

ASSETS = Path(__file__).parent / "assets"
VIS_DIR = ("templates", "lib", "vis-9.1.2")
#: frames inlined at most (evenly spaced over the run) and their byte budget
MAX_FRAMES, FRAME_BUDGET = 40, 2_500_000
SUMMARY_KEYS = ("coverage", "goal_mass", "dead_end_mass", "unrefined_mass",
                "goal_probability", "abstract_goal_probability", "wall_time_s",
                "refined_nodes", "refined_paths", "prg_nodes", "abstract_solves",
                "resamples", "solver_timeouts", "stop_reason", "seed")


class MissingViewExtra(RuntimeError):
    """vis-network is not installed: ``pip install 'stampc[view]'``."""


def vis_network_files() -> tuple[str, str]:
    """The vis-network script and stylesheet shipped inside the installed pyvis package
    (located without importing pyvis, which pulls in IPython)."""
    spec = importlib.util.find_spec("pyvis")
    missing = [name for name, found in (("pyvis", spec is not None and spec.submodule_search_locations),
                                        ("igraph", importlib.util.find_spec("igraph")))
               if not found]
    if missing:
        raise MissingViewExtra(f"stampc view needs {' and '.join(missing)} (vis-network is "
                               "shipped inside pyvis; igraph lays the graph out): "
                               "pip install 'stampc[view]'")
    folder = Path(next(iter(spec.submodule_search_locations))).joinpath(*VIS_DIR)
    return ((folder / "vis-network.min.js").read_text(encoding="utf-8"),
            (folder / "vis-network.css").read_text(encoding="utf-8"))


def render_report(run: RunDir) -> str:
    """The whole report as one HTML string."""
    vis_js, vis_css = vis_network_files()
    policy = run.policy
    title = f"{policy.get('domain', '?')} / {policy.get('problem', '?')}"
    data = {
        "title": title, "world": policy.get("world"), "seed": policy.get("seed"),
        "summary": _summary(run), "notes": list((run.summary or {}).get("notes", [])),
        "graph": page_data(policy), "history": run.history,
        "executions": [{"file": name, **report} for name, report in run.executions],
        "frames": _frames(run), "frames_dir": _frames_dir(run),
    }
    figure = coverage_svg(run.coverage, title) if run.coverage else ""
    page = (ASSETS / "report.html").read_text(encoding="utf-8")
    parts = {
        "TITLE": html.escape(f"stampc report: {title}"),
        "VIS_CSS": vis_css, "CSS": (ASSETS / "report.css").read_text(encoding="utf-8"),
        "COVERAGE_SVG": figure or "<p class='muted'>no coverage.csv in the run directory</p>",
        "VIS_JS": vis_js, "DATA": _script_json(data),
        "JS": (ASSETS / "report.js").read_text(encoding="utf-8"),
    }
    # one pass: text inlined for one placeholder is never searched for another
    return re.sub(r"@@([A-Z_]+)@@", lambda m: parts[m.group(1)], page)


def _summary(run: RunDir) -> dict[str, Any]:
    source: Mapping[str, Any] = run.summary or {
        "coverage": run.policy.get("coverage"),
        "goal_probability": run.policy.get("goal_probability"), "seed": run.policy.get("seed")}
    return {k: source[k] for k in SUMMARY_KEYS if k in source}


def _frames(run: RunDir) -> list[str]:
    """PNG data URIs of at most ``MAX_FRAMES`` frames, evenly spaced, within the budget."""
    frames = list(run.frames)
    if len(frames) > MAX_FRAMES:
        step = (len(frames) - 1) / (MAX_FRAMES - 1)
        frames = [frames[round(i * step)] for i in range(MAX_FRAMES)]
    out, used = [], 0
    for path in frames:
        data = path.read_bytes()
        if used + len(data) > FRAME_BUDGET:
            break
        used += len(data)
        out.append("data:image/png;base64," + base64.b64encode(data).decode("ascii"))
    return out


def _frames_dir(run: RunDir) -> str | None:
    if not run.frames:
        return None
    folder = run.frames[0].parent
    return str(folder.relative_to(run.path)) if folder != run.path else "."


def _script_json(data: Any) -> str:
    """JSON safe inside a <script> element (no "</" can close it early)."""
    return json.dumps(data, separators=(",", ":")).replace("</", "<\\/")


def write_report(run: RunDir, out: Path) -> Path:
    out.write_text(render_report(run), encoding="utf-8")
    return out
