"""The wheel ships every package: pyproject.toml lists packages by name, so a new
sub-package that is not listed would be missing from a regular (non-editable) install."""

from __future__ import annotations

import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_every_stampc_package_is_listed_in_pyproject():
    listed = set(tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
                 ["tool"]["setuptools"]["packages"])
    on_disk = {".".join(p.parent.relative_to(REPO).parts)
               for p in (REPO / "stampc").rglob("__init__.py")}
    assert on_disk, "no packages found: the test looks in the wrong place"
    assert on_disk - listed == set()
