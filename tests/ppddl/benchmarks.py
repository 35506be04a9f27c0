"""The PPDDL benchmark instances listed in ../shared/benchmarks/ppddl/MANIFEST.tsv.

Parametrisation happens at collection time, before fixtures run, so the list is read
here; when the folder is absent a single placeholder is returned and the tests' use
of the ``ppddl_benchmarks`` fixture (tests/conftest.py) skips them with a clear message.
"""

from __future__ import annotations

import csv
from pathlib import Path

BENCHMARKS = Path(__file__).resolve().parents[2].parent / "shared" / "benchmarks" / "ppddl"
MISSING = "<benchmark folder missing>"


def manifest_rows() -> list[dict[str, str]]:
    manifest = BENCHMARKS / "MANIFEST.tsv"
    if not manifest.is_file():
        return []
    with manifest.open(encoding="utf-8", newline="") as fh:
        return list(csv.DictReader(fh, delimiter="\t"))


def instances() -> list[str]:
    """Relative paths of every file holding a problem (problem-only or domain+problem)."""
    rows = [r["path"] for r in manifest_rows() if r["kind"] in ("problem", "domain+problem")]
    return rows or [MISSING]


def domains() -> list[str]:
    rows = [r["path"] for r in manifest_rows() if r["kind"] == "domain"]
    return rows or [MISSING]


def ground_instances(per_directory: int = 10) -> list[str]:
    """The ``per_directory`` instances with the fewest objects (MANIFEST ``objects``
    column; ties in manifest order) of every benchmark directory."""
    rows = [r for r in manifest_rows() if r["kind"] in ("problem", "domain+problem")]
    by_directory: dict[str, list[tuple[int, int, str]]] = {}
    for order, r in enumerate(rows):
        objects = int(r["objects"]) if r["objects"].strip().isdigit() else 0
        by_directory.setdefault(r["path"].split("/")[0], []).append((objects, order, r["path"]))
    chosen = [rel for group in by_directory.values() for _, _, rel in sorted(group)[:per_directory]]
    return chosen or [MISSING]
