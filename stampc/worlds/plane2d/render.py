"""Matplotlib rendering of a plane2d state to PNG (docs, ``stampc execute --render``).

Uses the non-interactive Agg canvas directly (no pyplot global state), so rendering is
safe in tests and worker processes.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Iterable, Sequence

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon, Rectangle

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.plane2d.geometry import Box, Disc
from stampc.worlds.plane2d.values import Traj2, as_traj

if TYPE_CHECKING:  # annotations only: the world imports this module to render itself
    from stampc.worlds.plane2d.world import Plane2DWorld, WorldState

_COLORS = {"surface": "#e8dcc8", "table": "#f4efe6", "region": "#dbe9f6",
           "object": "#4c78a8", "held": "#f58518", "static": "#7f7f7f",
           "gripper": "#e45756", "traj": "#54a24b", "uav": "#b279a2"}


def _draw_rect(ax, rect, color: str, label: str | None, alpha: float = 1.0) -> None:
    ax.add_patch(Rectangle((rect.x0, rect.y0), rect.x1 - rect.x0, rect.y1 - rect.y0,
                           facecolor=color, edgecolor="#999999", alpha=alpha, lw=0.8))
    if label:
        ax.text(rect.x0 + 0.01, rect.y1 - 0.01, label, fontsize=6, va="top", color="#555555")


def _draw_shape(ax, shape, color: str, label: str | None) -> None:
    if isinstance(shape, Disc):
        ax.add_patch(Circle((shape.x, shape.y), shape.radius, facecolor=color,
                            edgecolor="black", lw=0.6))
    elif isinstance(shape, Box):
        ax.add_patch(Polygon(shape.corners(), closed=True, facecolor=color,
                             edgecolor="black", lw=0.6))
    if label:
        ax.text(shape.x, shape.y, label, fontsize=6, ha="center", va="center", color="white")


def render_figure(world: Plane2DWorld, *, state: WorldState | None = None,
                  trajectories: Iterable[Traj2] = (), title: str | None = None,
                  size: Sequence[float] = (6.0, 4.5)) -> Figure:
    """A matplotlib Figure of ``state`` (default: the current one) with overlays."""
    saved = world.snapshot()
    if state is not None:
        world.restore(state)
    try:
        fig = Figure(figsize=tuple(size), dpi=120)
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(1, 1, 1)
        scene = world.scene
        _draw_rect(ax, scene.table, _COLORS["table"], None)
        for name, rect in scene.surfaces:
            if name != "table":
                _draw_rect(ax, rect, _COLORS["surface"], name)
        for name, rect in scene.regions:
            _draw_rect(ax, rect, _COLORS["region"], name, alpha=0.7)
        for spec, pose in scene.obstacles:
            _draw_shape(ax, spec.at(pose), _COLORS["static"], None)
        for name, pose in world.state.poses:
            color = _COLORS["held"] if name == world.held else _COLORS["object"]
            _draw_shape(ax, world.shape(name), color, name)
        paths = [as_traj(t).points for t in trajectories]
        if not paths and len(world.state.trace) > 1:
            paths = [world.state.trace]           # show the move that led here
        for points in paths:
            xs, ys = zip(*points)
            ax.plot(xs, ys, "-o", color=_COLORS["traj"], lw=1.2, ms=2)
        gx, gy = world.gripper
        ax.add_patch(Circle((gx, gy), scene.robot.gripper_radius, facecolor="none",
                            edgecolor=_COLORS["gripper"], lw=1.5))
        for _, (x, y) in scene.robot.bases:      # candidate bases of a mobile robot
            ax.plot([x], [y], marker="s", color="none", markeredgecolor="grey", ms=5)
        bx, by = world.base
        ax.plot([bx], [by], marker="s", color="black", ms=5)
        if world.uav is not None and scene.uav is not None:
            ax.add_patch(Circle(world.uav, scene.uav.radius, facecolor=_COLORS["uav"],
                                edgecolor="black", lw=0.6))
            ax.text(world.uav[0], world.uav[1] + scene.uav.radius * 1.6,
                    f"{world.battery:.2f}", fontsize=6, ha="center")
        w = scene.workspace
        ax.set_xlim(w.x0, w.x1)
        ax.set_ylim(w.y0, w.y1)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=6)
        if title:
            ax.set_title(title, fontsize=8)
        fig.subplots_adjust(left=0.08, right=0.98, bottom=0.08, top=0.93)
        return fig
    finally:
        world.restore(saved)


def render_array(world: Plane2DWorld, *, state: WorldState | None = None,
                 trajectories: Iterable[Traj2] = (), title: str | None = None) -> np.ndarray:
    """The rendering as an RGB uint8 array (fixed size, so frames stack into a GIF)."""
    fig = render_figure(world, state=state, trajectories=trajectories, title=title)
    canvas = fig.canvas
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[..., :3].copy()


def render_png(world: Plane2DWorld, path: str | Path, *, state: WorldState | None = None,
               trajectories: Iterable[Traj2] = (), title: str | None = None) -> Path:
    """Write a PNG of ``state`` (default: current) with trajectory overlays to ``path``."""
    fig = render_figure(world, state=state, trajectories=trajectories, title=title)
    out = Path(path)
    try:
        fig.savefig(out, format="png")
    except OSError as exc:
        raise StampcError([error("S280", f"cannot write image {str(out)!r}: {exc.strerror}",
                                 Span.point(str(out)))]) from None
    return out
