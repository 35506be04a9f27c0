"""The warehouse floor for the plane2d world: one region per grid cell, named as the
problem's indexed objects (``cell_<i>_<j>``: column i, row j), a rack box in each rack
cell, and the disc robot (the world's ``uav``) starting in ``cell_0_0``."""

from __future__ import annotations


def _racks(text: str) -> set[tuple[int, int]]:
    """``"1,1;2,0"`` → {(1, 1), (2, 0)} (scene builder arguments are scalars)."""
    out = set()
    for item in filter(None, (s.strip() for s in text.split(";"))):
        i, j = (int(x) for x in item.split(","))
        out.add((i, j))
    return out


def grid(cols: int = 3, rows: int = 3, racks: str = "", size: float = 1.0) -> dict:
    """A ``cols`` x ``rows`` floor of ``size``-metre cells."""
    width, height = cols * size, rows * size
    regions = {}
    obstacles = []
    rack_cells = _racks(racks)
    for i in range(cols):
        for j in range(rows):
            x0, y0 = i * size, j * size
            margin = 0.1 * size
            regions[f"cell_{i}_{j}"] = {"x0": x0 + margin, "y0": y0 + margin,
                                        "x1": x0 + size - margin, "y1": y0 + size - margin}
            if (i, j) in rack_cells:
                obstacles.append({"name": f"rack_{i}_{j}", "shape": "box",
                                  "size": [0.8 * size, 0.8 * size],
                                  "x": x0 + size / 2, "y": y0 + size / 2, "theta": 0.0})
    box = {"x0": 0.0, "y0": 0.0, "x1": width, "y1": height}
    return {
        "table": dict(box), "workspace": dict(box),
        "robot": {"base": [size / 2, size / 2], "gripper_radius": 0.02, "reach": 0.1},
        "regions": regions, "obstacles": obstacles,
        "uav": {"start": "cell_0_0", "battery": 1000.0, "radius": 0.08 * size},
        "poses": {}, "meta": {"example": "warehouse", "racks": sorted(rack_cells)},
    }
