"""Opening documents and positions of words in them, for the language server tests."""

from __future__ import annotations

from pathlib import Path

from lsprotocol import types as lsp


async def open_document(client, path: Path, text: str | None = None) -> list[lsp.Diagnostic]:
    """Open ``path`` (with ``text`` instead of its content, if given) and wait for its
    diagnostics."""
    uri = path.resolve().as_uri()
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(text_document=lsp.TextDocumentItem(
        uri=uri, language_id="stamp", version=1,
        text=path.read_text(encoding="utf-8") if text is None else text)))
    await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return list(client.diagnostics[uri])


async def change_document(client, path: Path, text: str, version: int) -> list[lsp.Diagnostic]:
    uri = path.resolve().as_uri()
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
        content_changes=[lsp.TextDocumentContentChangeWholeDocument(text=text)]))
    await client.wait_for_notification(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return list(client.diagnostics[uri])


def position_of(text: str, line_contains: str, word: str, occurrence: int = 0) -> lsp.Position:
    """The position inside ``word`` on the first line containing ``line_contains``."""
    lines = text.splitlines()
    number = [i for i, line in enumerate(lines) if line_contains in line][occurrence]
    return lsp.Position(line=number, character=lines[number].index(word) + 1)


def document(path: Path) -> lsp.TextDocumentIdentifier:
    return lsp.TextDocumentIdentifier(uri=path.resolve().as_uri())
