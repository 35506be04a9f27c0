"""The kitchen counter for the plane2d world: the world's shelf scene (a target disc in
a U-shaped cupboard open towards the robot, blockers in front of it), with the names of
the kitchen problem: cups ``cup_<i>``, their poses ``pose_cup_<i>``, the table as
``counter`` and the tray as ``sink``."""

from __future__ import annotations

from stampc.worlds.plane2d.scenes import cluttered

RENAMED_SURFACES = {"table": "counter", "tray": "sink"}


def _cup(name: str) -> str:
    return "cup_" + name.removeprefix("can") if name.startswith("can") else name


def kitchen(n: int = 4, seed: int = 2, blockers: int = 2) -> dict:
    """``n`` cups, ``cup_0`` in the cupboard behind ``blockers`` others."""
    scene = cluttered(n, seed, blockers=blockers, shelf=True)
    scene["surfaces"] = {RENAMED_SURFACES.get(k, k): v for k, v in scene["surfaces"].items()}
    for obj in scene["objects"]:
        obj["name"] = _cup(obj["name"])
    scene["poses"] = {f"pose_{_cup(obj)}": _cup(obj) for obj in scene["poses"].values()}
    meta = scene["meta"]
    meta["target"] = _cup(meta["target"])
    meta["blockers"] = [_cup(b) for b in meta["blockers"]]
    meta["example"] = "kitchen"
    return scene
