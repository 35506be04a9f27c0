"""`stampc lsp` driven by a real LSP client over stdio: diagnostics (the same codes and
spans as `stampc check`) on open and on change, hover, go-to-definition and references
(also across `use` modules and into problems), completion and formatting."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from lsprotocol import types as lsp

from .conftest import REPO, SERVER_ENV
from .helpers import change_document, document, open_document, position_of

DOMINO = REPO / "examples" / "domino" / "domain.stamp"
DOMINO_PROBLEM = REPO / "examples" / "domino" / "problem.stamp"
STDLIB = REPO / "stdlib" / "manipulation.stamp"
CLUTTERED = REPO / "examples" / "cluttered_table" / "domain.stamp"
BROKEN = """domain broken

use manipulation

type box < movable
predicate lid(b: box)

action open(b: box, x: thing)
    pre  lid(b)
         sealed(b)
    eff  not lid(b)
"""


def check_json(path) -> list[dict]:
    done = subprocess.run([sys.executable, "-m", "stampc", "check", str(path), "--format", "json"],
                          capture_output=True, text=True, env=SERVER_ENV, cwd=path.parent)
    return json.loads(done.stdout)


@pytest.mark.asyncio
async def test_diagnostics_on_open_match_check(client, tmp_path):
    path = tmp_path / "broken.stamp"
    path.write_text(BROKEN)
    got = await open_document(client, path)
    expected = check_json(path)
    assert {d["code"] for d in expected} >= {"E101", "E102"}  # undefined type and predicate
    assert sorted((d.code, d.range.start.line + 1, d.range.start.character + 1,
                   d.range.end.line + 1, d.range.end.character + 1) for d in got) == \
        sorted((d["code"], d["span"]["line"], d["span"]["col"], d["span"]["end_line"],
                d["span"]["end_col"]) for d in expected)
    undefined = next(d for d in got if d.code == "E102")
    assert "sealed" in undefined.message and undefined.source == "stampc"
    assert undefined.severity == lsp.DiagnosticSeverity.Error


@pytest.mark.asyncio
async def test_diagnostics_follow_changes(client, tmp_path):
    path = tmp_path / "broken.stamp"
    path.write_text(BROKEN)
    assert await open_document(client, path)
    fixed = BROKEN.replace("x: thing", "x: box").replace("         sealed(b)\n", "")
    assert await change_document(client, path, fixed, 2) == []
    broken_again = fixed.replace("lid(b)\n    eff", "lid(b, b)\n    eff")
    diags = await change_document(client, path, broken_again, 3)
    assert [d.code for d in diags] == ["E201"] and diags[0].range.start.line == 8  # arity


@pytest.mark.asyncio
async def test_hover_shows_declaration_and_comment(client):
    text = DOMINO.read_text()
    await open_document(client, DOMINO)
    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=document(DOMINO), position=position_of(text, "target(o)", "target")))
    assert "static predicate target(o: domino)" in hover.contents.value
    assert "the domino to pick" in hover.contents.value  # its comment
    # across `use`: a type of the stdlib module, with its comment
    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=document(DOMINO), position=position_of(text, "type domino", "movable")))
    assert "type movable" in hover.contents.value and "objects the robot can grasp" in \
        hover.contents.value and "manipulation.stamp" in hover.contents.value


@pytest.mark.asyncio
@pytest.mark.parametrize("line, word, file, declaration", [
    ("type domino", "movable", STDLIB, "type movable"),                       # type
    ("holding(o)", "holding", STDLIB, "predicate holding"),                   # predicate
    ("not toppled(o)", "toppled", DOMINO, "predicate toppled"),               # predicate here
    ("action notify", "notify", DOMINO, "action notify"),                     # action
])
async def test_definition(client, line, word, file, declaration):
    text = DOMINO.read_text()
    await open_document(client, DOMINO)
    found = await client.text_document_definition_async(lsp.DefinitionParams(
        text_document=document(DOMINO), position=position_of(text, line, word)))
    assert found and found[0].uri == file.resolve().as_uri()
    target_line = file.read_text().splitlines()[found[0].range.start.line]
    assert declaration in target_line
    start, end = found[0].range.start.character, found[0].range.end.character
    assert target_line[start:end] == word  # the declared name itself


@pytest.mark.asyncio
async def test_definition_and_hover_of_a_generator_and_a_parameter(client):
    text = CLUTTERED.read_text()
    await open_document(client, CLUTTERED)
    where = position_of(text, "sample t from motion4(q)", "motion4")
    found = await client.text_document_definition_async(lsp.DefinitionParams(
        text_document=document(CLUTTERED), position=where))
    assert text.splitlines()[found[0].range.start.line].startswith("generator motion4(")
    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=document(CLUTTERED), position=where))
    assert "generator motion4(q: config) -> (t: traj)" in hover.contents.value
    assert "The stdlib motion generator" in hover.contents.value  # the comment above it
    found = await client.text_document_definition_async(lsp.DefinitionParams(
        text_document=document(CLUTTERED), position=position_of(text, "sample t from motion4(q)", "q)")))
    assert text.splitlines()[found[0].range.start.line].startswith("action ")  # a parameter


@pytest.mark.asyncio
async def test_references_across_modules_and_problems(client):
    text = DOMINO.read_text()
    await open_document(client, DOMINO)
    refs = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=document(DOMINO), position=position_of(text, "not toppled(o)", "toppled"),
        context=lsp.ReferenceContext(include_declaration=True)))
    # the goal of the problem beside the domain uses it too
    assert {r.uri for r in refs} == {DOMINO.resolve().as_uri(), DOMINO_PROBLEM.resolve().as_uri()}
    problem_lines = [r.range.start.line for r in refs if r.uri == DOMINO_PROBLEM.resolve().as_uri()]
    assert [DOMINO_PROBLEM.read_text().splitlines()[n].count("toppled(") for n in problem_lines] == [1]
    in_domain = [r.range.start.line for r in refs if r.uri == DOMINO.resolve().as_uri()]
    expected = [i for i, line in enumerate(text.splitlines()) if "toppled(" in line]
    assert sorted(in_domain) == expected
    # a stdlib predicate: its declaration in the module, its uses here and in the problem
    refs = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=document(DOMINO), position=position_of(text, "holding(o)", "holding"),
        context=lsp.ReferenceContext(include_declaration=False)))
    assert {STDLIB.resolve().as_uri(), DOMINO.resolve().as_uri()} <= {r.uri for r in refs}
    assert all(STDLIB.read_text().splitlines()[r.range.start.line].strip() != "predicate holding(o: movable)"
               for r in refs if r.uri == STDLIB.resolve().as_uri())  # declaration left out


@pytest.mark.asyncio
async def test_completion_offers_names_in_scope(client):
    text = DOMINO.read_text()
    await open_document(client, DOMINO)
    line = next(i for i, l in enumerate(text.splitlines()) if l.startswith("action notify"))
    result = await client.text_document_completion_async(lsp.CompletionParams(
        text_document=document(DOMINO), position=lsp.Position(line=line + 1, character=9)))
    items = {i.label: i.kind for i in result.items}
    assert items["toppled"] == lsp.CompletionItemKind.Function      # this file
    assert items["holding"] == lsp.CompletionItemKind.Function      # the used module
    assert items["movable"] == lsp.CompletionItemKind.Class
    assert items["d"] == lsp.CompletionItemKind.Variable            # notify's parameter
    assert items["forall"] == lsp.CompletionItemKind.Keyword
    assert "o" not in items  # pick's parameter is not in scope in notify


@pytest.mark.asyncio
async def test_formatting_is_fmt(client, tmp_path):
    path = tmp_path / "messy.stamp"
    messy = "domain messy\ntype   box\npredicate   lid( b :box )\n"
    path.write_text(messy)
    await open_document(client, path)
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        text_document=document(path), options=lsp.FormattingOptions(tab_size=4, insert_spaces=True)))
    fmt = subprocess.run([sys.executable, "-m", "stampc", "fmt", str(path)], capture_output=True,
                         text=True, env=SERVER_ENV).stdout
    assert len(edits) == 1 and edits[0].new_text == fmt != messy
    assert edits[0].range.start == lsp.Position(line=0, character=0)


@pytest.mark.asyncio
async def test_formatting_leaves_unparsable_text_alone(client, tmp_path):
    path = tmp_path / "bad.stamp"
    path.write_text("domain bad\npredicate (\n")
    diags = await open_document(client, path)
    assert [d.code for d in diags] == ["E001"]
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        text_document=document(path), options=lsp.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert not edits
