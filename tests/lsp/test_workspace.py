"""The language server's analysis on text being typed: every prefix of a real domain
(syntax errors, half-written declarations) gets diagnostics and answers every look-up
without raising, and the scope of a file is what `check` resolves."""

from __future__ import annotations

from pathlib import Path

from stampc.lsp.features import completion_candidates, formatted
from stampc.lsp.workspace import Workspace

from .conftest import REPO

DOMINO = REPO / "examples" / "domino" / "domain.stamp"


def test_scope_follows_use_and_problems():
    ws = Workspace()
    names = {s.path.name for s in ws.scope(DOMINO)}
    assert names == {"domain.stamp", "problem.stamp", "manipulation.stamp"}
    problem = REPO / "examples" / "cluttered_table" / "problem_fixed.stamp"
    scope = {s.path.name for s in ws.scope(problem)}
    assert "domain_fixed.stamp" in scope and "domain.stamp" not in scope  # its own domain


def test_every_prefix_of_a_domain_is_answered(tmp_path):
    text = DOMINO.read_text()
    path = tmp_path / "domain.stamp"
    ws = Workspace()
    errors = 0
    for end in range(0, len(text), 37):
        ws.set_text(path, text[:end])
        diags = ws.diagnostics(path)
        errors += any(d.is_error for d in diags)
        lines = text[:end].splitlines() or [""]
        for line_no in range(1, len(lines) + 1, 5):
            for col in range(1, len(lines[line_no - 1]) + 2, 7):
                found = ws.at(path, line_no, col)
                if found is not None:
                    ws.definitions(path, found)
                    ws.references(path, found, True)
        completion_candidates(ws, path, len(lines))
        formatted(text[:end], str(path))
    assert errors > 0  # the prefixes really were broken ones


def test_an_open_document_wins_over_the_file(tmp_path):
    path = tmp_path / "d.stamp"
    path.write_text("domain d\npredicate p\n")
    ws = Workspace()
    assert [d.code for d in ws.diagnostics(path)] == ["W401"]  # p is never used
    ws.set_text(path, "domain d\npredicate p\naction a()\n    pre  q\n    eff  p\n")
    assert [d.code for d in ws.diagnostics(path)] == ["E102"]
    ws.close(path)
    assert [d.code for d in ws.diagnostics(path)] == ["W401"]


def test_a_blank_document_is_i002_as_in_check(tmp_path):
    path = tmp_path / "blank.stamp"
    ws = Workspace()
    ws.set_text(path, "  \n")
    assert [(d.code, d.span.line) for d in ws.diagnostics(path)] == [("I002", 1)]


def test_unreadable_files_are_no_crash(tmp_path):
    ws = Workspace()
    missing = tmp_path / "missing.stamp"
    assert ws.diagnostics(missing) == [] and ws.scope(missing) == []
    assert ws.at(missing, 1, 1) is None
    binary = tmp_path / "b.stamp"
    binary.write_bytes(b"\xff\xfe\x00")
    assert ws.source(binary) is None
    assert completion_candidates(ws, Path(binary), 1)  # keywords at least


def test_derived_predicates_and_comprehension_names_resolve():
    """The language features of issue 14 in the editor: a derived predicate used in a
    precondition goes to its `derived predicate` declaration, a symmetric one used in a
    problem comprehension to its domain declaration, and the comprehension's index
    variables are not mistaken for objects."""
    domain = REPO / "examples" / "warehouse" / "domain.stamp"
    problem = REPO / "examples" / "warehouse" / "problem.stamp"
    ws = Workspace()
    dlines = domain.read_text().splitlines()
    use = next(i for i, l in enumerate(dlines, 1) if l.strip() == "open(a, b)")
    found = ws.at(domain, use, dlines[use - 1].index("open") + 1)
    assert found is not None and found.occurrence.kind == "predicate"
    [target] = ws.definitions(domain, found)
    assert target.occurrence.defines and target.occurrence.span.line == next(
        i for i, l in enumerate(dlines, 1) if l.startswith("derived predicate open"))
    plines = problem.read_text().splitlines()
    row = next(i for i, l in enumerate(plines, 1) if "forall (i: 0..1" in l)
    found = ws.at(problem, row, plines[row - 1].index("adjacent") + 1)
    assert found is not None
    [target] = ws.definitions(problem, found)
    assert target.source.path.name == "domain.stamp"
    assert not [d for d in ws.diagnostics(problem) if d.is_error]
