"""The hand-written reader builds the same syntax trees as the reference grammar
``grammar/ppddl.lark`` (Lark LALR), and rejects what it rejects.

Trees are compared after the normalisations the reader applies by design: term
wrappers (``var``/``const``) dropped and directly nested ``and``/``or`` flattened.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import lark
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from stampc.backends.ppddl.parser import parse_text
from stampc.backends.ppddl.reader import Tok, fold_case
from stampc.diagnostics import StampcError
from tests.ppddl.test_import_errors import DOMAIN, PROBLEM

ROOT = Path(__file__).resolve().parents[2]
BENCHMARKS = ROOT.parent / "shared" / "benchmarks" / "ppddl"
_FLAT = {"gd_and", "gd_or", "eff_and"}


@lru_cache(maxsize=1)
def reference() -> lark.Lark:
    return lark.Lark((ROOT / "grammar" / "ppddl.lark").read_text(), parser="lalr",
                     lexer="contextual", maybe_placeholders=False)


def _from_lark(node):
    if isinstance(node, lark.Token):
        return str(node)
    if node.data in ("var", "const"):
        return str(node.children[0])
    kids = [_from_lark(c) for c in node.children]
    return (str(node.data), _flatten(str(node.data), kids))


def _from_reader(node):
    if isinstance(node, Tok):
        return node.text
    return (node.data, [_from_reader(c) for c in node.children])


def _flatten(data: str, kids: list) -> list:
    if data not in _FLAT:
        return kids
    out = []
    for k in kids:
        out.extend(k[1] if isinstance(k, tuple) and k[0] == data else [k])
    return out


def _both(text: str):
    folded = fold_case(text)
    try:
        expected = [_from_lark(d) for d in reference().parse(folded).children]
    except lark.exceptions.LarkError:
        expected = None
    try:
        got = [_from_reader(d) for d in parse_text(text, "t.pddl").definitions]
    except StampcError:
        got = None
    return expected, got


def _sample() -> list[Path]:
    if not BENCHMARKS.is_dir():
        return []
    files = []
    for d in sorted(p for p in BENCHMARKS.iterdir() if p.is_dir()):
        pddl = sorted(d.glob("*.pddl"), key=lambda p: p.stat().st_size)
        files += pddl[:2] + [p for p in pddl[2:] if p.name == "domain.pddl"]
    return files


@pytest.mark.parametrize("path", _sample(), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_benchmark_trees_match_the_reference_grammar(path):
    expected, got = _both(path.read_text())
    assert expected is not None and got == expected


def test_base_text_matches():
    expected, got = _both(DOMAIN + PROBLEM)
    assert expected is not None and got == expected


@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(min_value=0, max_value=len(DOMAIN + PROBLEM) - 1),
       st.sampled_from(["(", ")", "()", "?x", "-", "1/2", "and", "not", "x", ":effect",
                        "(either a b)", "- t", "=", "(p)", "(probabilistic 1/2"]))
def test_insertions_are_accepted_or_rejected_alike(position, insert):
    """Inserted words are padded with spaces: Lark's contextual lexer also splits glued
    text such as ``:actionmove`` into a keyword and a name, which the reader rejects."""
    base = DOMAIN + PROBLEM
    expected, got = _both(base[:position] + f" {insert} " + base[position:])
    assert got == expected
