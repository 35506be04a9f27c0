"""One golden test per diagnostic code: a small bad input and its exact human output."""

from __future__ import annotations

from pathlib import Path

import pytest

from stampc.commands import check as check_cmd
from stampc.semantics.codes import CODES

from .helpers import REPO, run_command

GOLDEN = Path(__file__).resolve().parent / "golden"
CASES = sorted(GOLDEN.glob("*.stamp"))
LOWERING_ONLY = {"E501"}  # raised by stampc.ir.lower, covered in test_lower.py


@pytest.mark.parametrize("case", CASES, ids=[c.stem for c in CASES])
def test_golden_output(case: Path) -> None:
    expected = case.with_suffix(".expected").read_text(encoding="utf-8")
    code, out, err = run_command(check_cmd, [str(case.relative_to(REPO))])
    assert err == ""
    assert out == expected
    has_error = not expected.rstrip().splitlines()[-1].startswith("0 errors")
    assert code == (1 if has_error else 0)


def test_every_code_has_a_golden_case() -> None:
    covered = {c.name.split("_", 1)[0] for c in CASES}
    assert set(CODES) - LOWERING_ONLY == covered


def test_golden_case_shows_its_own_code() -> None:
    for case in CASES:
        code = case.name.split("_", 1)[0]
        assert f": {code} " in case.with_suffix(".expected").read_text(encoding="utf-8"), case.name
