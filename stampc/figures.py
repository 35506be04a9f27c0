"""The run's two drawings, written straight as SVG: the policy graph by depth
(policy.svg) and the probability mass over time (coverage.svg, and the figure of
``stampc view``'s report).

Why not matplotlib: importing it costs ~0.6 s, a third of a small run's whole process
(domino n10k2: 2.0 s, of which the engine takes 0.1 s), and both drawings are a few
dozen circles, lines and labels. Writing them directly is linear in the drawing; the
matplotlib policy drawing of 2 MB took about a minute.
"""

from __future__ import annotations

import math
from html import escape
from typing import Sequence

#: one drawn node: (uid or "+uid" marker, layer, label, fill colour)
DrawnNode = tuple[object, int, str, str]

_FONT = 'font-family="Helvetica, Arial, sans-serif"'
_SLOT, _ROW, _MARGIN, _RADIUS = 110, 64, 30, 7


def policy_svg(nodes: Sequence[DrawnNode], edges: Sequence[tuple[object, object]]) -> str:
    """A tidy tree: rows by layer (the root, the first node, on top), leaves side by side
    in depth-first order, each parent above the middle of its children (where branches
    merge, a node sits under the parent that reached it first); edges as straight lines,
    each label under its node (the full text in a tooltip)."""
    x_slot = _tree_slots(nodes, edges)
    layers = sorted({layer for _, layer, _, _ in nodes})
    row_of = {layer: i for i, layer in enumerate(layers)}
    width = max(480, (max(x_slot.values(), default=0) + 1) * _SLOT + 2 * _MARGIN)
    height = max(120, len(layers) * _ROW + 2 * _MARGIN)
    at = {uid: (_MARGIN + (x_slot[uid] + 0.5) * _SLOT, _MARGIN + row_of[layer] * _ROW)
          for uid, layer, _, _ in nodes}
    out = [_svg_open(width, height), '<g stroke="#555" stroke-width="1">']
    out += [f'<line x1="{at[a][0]:.1f}" y1="{at[a][1]:.1f}" x2="{at[b][0]:.1f}" '
            f'y2="{at[b][1]:.1f}"/>' for a, b in edges if a in at and b in at]
    out.append(f'</g><g {_FONT} font-size="9" text-anchor="middle">')
    for uid, _, label, fill in nodes:
        x, y = at[uid]
        short = label if len(label) <= 18 else label[:17] + "…"
        out.append(f'<g><title>{escape(label)}</title><circle cx="{x:.1f}" cy="{y:.1f}" '
                   f'r="{_RADIUS}" fill="{fill}" stroke="#333"/><text x="{x:.1f}" '
                   f'y="{y + 18:.1f}">{escape(short)}</text></g>')
    out.append("</g></svg>")
    return "\n".join(out) + "\n"


def _tree_slots(nodes: Sequence[DrawnNode], edges: Sequence[tuple[object, object]]
                ) -> dict[object, float]:
    """Each node's horizontal slot: leaves of the depth-first spanning tree take 0, 1, 2…;
    a parent takes the middle of its first and last child."""
    children: dict[object, list[object]] = {}
    for a, b in edges:
        children.setdefault(a, []).append(b)
    slot: dict[object, float] = {}
    next_leaf = 0.0
    for start, *_ in nodes:  # the root first; then anything it does not reach
        if start in slot:
            continue
        slot[start] = -1.0  # visited; set once its children are placed
        stack = [(start, iter(children.get(start, ())), [])]
        while stack:
            uid, pending, placed = stack[-1]
            child = next((c for c in pending if c not in slot), None)
            if child is not None:
                slot[child] = -1.0
                placed.append(child)
                stack.append((child, iter(children.get(child, ())), []))
                continue
            stack.pop()
            if placed:
                slot[uid] = (slot[placed[0]] + slot[placed[-1]]) / 2
            else:
                slot[uid], next_leaf = next_leaf, next_leaf + 1
    return slot


#: the mass split's areas, bottom to top, and their colours
MASS_COLORS = (("goal", "#3a9d5d"), ("dead end (proven)", "#c0392b"),
               ("unrefined", "#d5d8dc"))


def coverage_svg(times: Sequence[float], coverage: Sequence[float],
                 goal: Sequence[float], title: str = "") -> str:
    """The probability mass over time as the engine splits it, stacked: refined paths to
    the goal, to proven dead ends (coverage − goal), and the unrefined rest, with the
    coverage as a line. Steps hold each value until the next event."""
    times, coverage, goal = _changes(times, coverage, goal)
    width, height = 740, 330
    left, right, top, bottom = 56, 150, 34, 46
    x_max = _nice_ceiling(max(times, default=0.0))
    plot_w, plot_h = width - left - right, height - top - bottom

    def px(t: float) -> float:
        return left + plot_w * t / x_max

    def py(v: float) -> float:
        return top + plot_h * (1.0 - v)

    def point(t: float, v: float) -> str:
        return f"{px(t):.1f},{py(v):.1f}"

    def steps(values: Sequence[float]) -> list[str]:
        out = []
        for i, (t, v) in enumerate(zip(times, values)):
            if i:
                out.append(point(t, values[i - 1]))
            out.append(point(t, v))
        return out

    out = [_svg_open(width, height)]
    ones = [1.0] * len(times)
    bounds = ([0.0] * len(times), list(goal), list(coverage), ones)
    for (name, color), low, high in zip(MASS_COLORS, bounds, bounds[1:]):
        if times:
            area = steps(high) + steps(low)[::-1]
            out.append(f'<polygon points="{" ".join(area)}" fill="{color}" stroke="none">'
                       f"<title>{name}</title></polygon>")
    if times:
        out.append(f'<polyline points="{" ".join(steps(coverage))}" fill="none" '
                   'stroke="black" stroke-width="1.2"><title>coverage</title></polyline>')
    out += [f'<g {_FONT} font-size="11" fill="#222">',
            f'<text x="{left + plot_w / 2}" y="20" text-anchor="middle" font-size="13">'
            f"{escape(title or 'coverage over time')}</text>",
            f'<text x="{left + plot_w / 2}" y="{height - 10}" text-anchor="middle">'
            "time (s)</text>",
            f'<text transform="translate(16 {top + plot_h / 2}) rotate(-90)" '
            'text-anchor="middle">probability mass</text>']
    for v in (0.0, 0.2, 0.4, 0.6, 0.8, 1.0):
        out.append(_grid_line(left, py(v), left + plot_w, py(v)))
        out.append(f'<text x="{left - 6}" y="{py(v) + 4:.1f}" text-anchor="end">{v:.1f}</text>')
    for t in _ticks(x_max):
        out.append(_grid_line(px(t), top, px(t), top + plot_h))
        out.append(f'<text x="{px(t):.1f}" y="{top + plot_h + 16}" text-anchor="middle">'
                   f"{t:g}</text>")
    legend = [*MASS_COLORS, ("coverage", "black")]
    for i, (name, color) in enumerate(legend):
        y = top + 10 + 20 * i
        out.append(f'<rect x="{left + plot_w + 14}" y="{y - 8}" width="14" height="10" '
                   f'fill="{color}"/><text x="{left + plot_w + 34}" y="{y + 1}">{name}</text>')
    out.append(f'</g><rect x="{left}" y="{top}" width="{plot_w}" height="{plot_h}" '
               'fill="none" stroke="#222"/></svg>')
    return "\n".join(out) + "\n"


def _changes(times: Sequence[float], coverage: Sequence[float], goal: Sequence[float]
             ) -> tuple[list[float], list[float], list[float]]:
    """The events where the mass split changes, and the last: a step plot of them is the
    same picture, and a run has thousands of events."""
    kept = [i for i in range(len(times))
            if i in (0, len(times) - 1) or (coverage[i], goal[i]) != (coverage[i - 1], goal[i - 1])]
    return ([times[i] for i in kept], [coverage[i] for i in kept], [goal[i] for i in kept])


def _svg_open(width: float, height: float) -> str:
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
            f'viewBox="0 0 {width:.0f} {height:.0f}"><rect width="100%" height="100%" '
            'fill="white"/>')


def _grid_line(x1: float, y1: float, x2: float, y2: float) -> str:
    return (f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" '
            'stroke="#000" stroke-opacity="0.15"/>')


def _tick_step(span: float) -> float:
    """1, 2 or 5 × 10^k: about five ticks over ``span``."""
    raw = span / 5
    power = 10 ** math.floor(math.log10(raw))
    return next(m * power for m in (1, 2, 5, 10) if m * power >= raw)


def _nice_ceiling(value: float) -> float:
    """The axis end: ``value`` rounded up to a tick (1 for an empty or instant run)."""
    if not value > 0 or not math.isfinite(value):
        return 1.0
    step = _tick_step(value)
    return step * math.ceil(value / step - 1e-9)


def _ticks(end: float) -> list[float]:
    step = _tick_step(end)
    return [round(i * step, 10) for i in range(int(end / step + 1e-9) + 1)]
