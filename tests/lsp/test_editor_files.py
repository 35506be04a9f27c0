"""The VS Code extension folder is wired up (every file it names exists, the grammar is
the one the language uses, the server command is `stampc lsp`), and the TextMate
grammar's expressions compile and cover every keyword of grammar/stamp.lark."""

from __future__ import annotations

import json
import re

import pytest

from .conftest import REPO

VSCODE = REPO / "editors" / "vscode"


def load(name: str) -> dict:
    return json.loads((VSCODE / name).read_text(encoding="utf-8"))


def grammar() -> dict:
    package = load("package.json")
    return load(package["contributes"]["grammars"][0]["path"])


def expressions(node) -> list[str]:
    if isinstance(node, dict):
        found = [node[k] for k in ("match", "begin", "end") if isinstance(node.get(k), str)]
        return found + [e for v in node.values() for e in expressions(v)]
    if isinstance(node, list):
        return [e for v in node for e in expressions(v)]
    return []


def test_package_names_existing_files_and_the_server():
    package = load("package.json")
    assert (VSCODE / package["main"]).is_file()
    language = package["contributes"]["languages"][0]
    assert language["extensions"] == [".stamp"]
    assert (VSCODE / language["configuration"]).is_file()
    contributed = package["contributes"]["grammars"][0]
    assert contributed["language"] == language["id"] == "stamp"
    assert grammar()["scopeName"] == contributed["scopeName"]
    command = package["contributes"]["configuration"]["properties"]["stamp.server.command"]
    assert command["default"] == ["stampc", "lsp"]
    script = (VSCODE / package["main"]).read_text(encoding="utf-8")
    assert "vscode-languageclient/node" in script and '"server.command"' in script
    assert "vscode-languageclient" in package["dependencies"]
    load("language-configuration.json")  # valid JSON


def test_grammar_expressions_compile():
    found = expressions(grammar())
    assert len(found) > 10
    for expression in found:
        re.compile(expression)  # the Oniguruma features used are in Python's re too


def lark_keywords() -> set[str]:
    text = (REPO / "grammar" / "stamp.lark").read_text(encoding="utf-8")
    return set(re.findall(r'"([a-z]+)"', text))


@pytest.mark.parametrize("word", sorted(lark_keywords()))
def test_every_keyword_is_highlighted(word):
    repo = grammar()["repository"]
    rules = repo["keyword"]["patterns"] + [repo["constant"]]
    assert any(re.fullmatch(rule["match"], word) for rule in rules), word


@pytest.mark.parametrize("line, token, scope", [
    ("action pick(o: domino, p: pose)", "pick", "entity.name.function.stamp"),
    ("static predicate near1(a: domino, b: domino)  # b next to a", "near1", "entity.name.function.stamp"),
    ("type domino < movable", "movable", "entity.name.type.stamp"),
    ("    1/2 as topple1: toppled(d)", "topple1", "entity.name.label.stamp"),
    ("    sample t from motion4(q)", "motion4", "entity.name.function.generator.stamp"),
])
def test_rules_capture_the_declared_names(line, token, scope):
    repo = grammar()["repository"]
    for rule in repo.values():
        if "captures" not in rule:
            continue
        match = re.search(rule["match"], line)
        if match is None:
            continue
        for group, capture in rule["captures"].items():
            if match.group(int(group)) == token and capture["name"] == scope:
                return
    pytest.fail(f"no rule gives {token!r} the scope {scope}")
