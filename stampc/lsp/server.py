"""``stampc lsp``: the stamp language server (pygls) over stdio.

Diagnostics on open and change (those of ``stampc check`` on the editor's text, same
codes and spans), hover (declaration and comment), go-to-definition and references
(types, predicates, functions, generators, actions, constants, parameters; across
``use`` modules and a domain's problems), completion of names in scope, and formatting
(``stampc fmt``). The analysis lives in ``workspace.py``/``features.py``; this module
only translates between it and the protocol.
"""

from __future__ import annotations

from pathlib import Path

from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

from stampc import __version__
from stampc.diagnostics import Diagnostic, Severity, Span
from stampc.lsp.features import completion_candidates, formatted, hover_markdown
from stampc.lsp.workspace import Found, Workspace

SEVERITY = {Severity.ERROR: lsp.DiagnosticSeverity.Error,
            Severity.WARNING: lsp.DiagnosticSeverity.Warning}
COMPLETION_KIND = {
    "type": lsp.CompletionItemKind.Class, "predicate": lsp.CompletionItemKind.Function,
    "function": lsp.CompletionItemKind.Function, "generator": lsp.CompletionItemKind.Module,
    "action": lsp.CompletionItemKind.Method, "constant": lsp.CompletionItemKind.Constant,
    "param": lsp.CompletionItemKind.Variable, "keyword": lsp.CompletionItemKind.Keyword,
}


def span_range(span: Span) -> lsp.Range:
    return lsp.Range(start=lsp.Position(line=span.line - 1, character=span.col - 1),
                     end=lsp.Position(line=span.end_line - 1, character=span.end_col - 1))


def location(path: Path | None, span: Span) -> lsp.Location:
    """A span's place; display names are relative to the working directory."""
    return lsp.Location(uri=from_fs_path(str((path or Path(span.file)).resolve())),
                        range=span_range(span))


def to_lsp(d: Diagnostic, path: Path) -> lsp.Diagnostic:
    related = [lsp.DiagnosticRelatedInformation(
        location=location(path if label.span.file == d.span.file else None, label.span),
        message=label.message) for label in d.labels]
    message = d.message + (f"\nhelp: {d.hint}" if d.hint else "")
    return lsp.Diagnostic(range=span_range(d.span), message=message, code=d.code,
                          source="stampc", severity=SEVERITY.get(d.severity,
                                                                 lsp.DiagnosticSeverity.Information),
                          related_information=related or None)


def found_location(found: Found) -> lsp.Location:
    return location(found.source.path, found.occurrence.span)


def build_server() -> LanguageServer:
    server = LanguageServer("stampc", __version__)
    ws = Workspace()

    def path_of(uri: str) -> Path:
        return Path(to_fs_path(uri))

    def refresh(ls: LanguageServer, uri: str) -> None:
        path = path_of(uri)
        ws.set_text(path, ls.workspace.get_text_document(uri).source)
        ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
            uri=uri, diagnostics=[to_lsp(d, path) for d in ws.diagnostics(path)]))

    def found_at(uri: str, pos: lsp.Position) -> tuple[Path, Found | None]:
        path = path_of(uri)
        return path, ws.at(path, pos.line + 1, pos.character + 1)

    @server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: LanguageServer, params: lsp.DidOpenTextDocumentParams) -> None:
        refresh(ls, params.text_document.uri)

    @server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: LanguageServer, params: lsp.DidChangeTextDocumentParams) -> None:
        refresh(ls, params.text_document.uri)

    @server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: LanguageServer, params: lsp.DidCloseTextDocumentParams) -> None:
        ws.close(path_of(params.text_document.uri))
        ls.text_document_publish_diagnostics(lsp.PublishDiagnosticsParams(
            uri=params.text_document.uri, diagnostics=[]))

    @server.feature(lsp.TEXT_DOCUMENT_HOVER)
    def hover(params: lsp.HoverParams) -> lsp.Hover | None:
        path, found = found_at(params.text_document.uri, params.position)
        defs = ws.definitions(path, found) if found else []
        if not defs:
            return None
        return lsp.Hover(contents=lsp.MarkupContent(kind=lsp.MarkupKind.Markdown,
                                                    value=hover_markdown(found, defs[0])),
                         range=span_range(found.occurrence.span))

    @server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
    def definition(params: lsp.DefinitionParams) -> list[lsp.Location] | None:
        path, found = found_at(params.text_document.uri, params.position)
        defs = ws.definitions(path, found) if found else []
        return [found_location(f) for f in defs] or None

    @server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
    def references(params: lsp.ReferenceParams) -> list[lsp.Location] | None:
        path, found = found_at(params.text_document.uri, params.position)
        if found is None:
            return None
        refs = ws.references(path, found, params.context.include_declaration)
        return [found_location(f) for f in refs] or None

    @server.feature(lsp.TEXT_DOCUMENT_COMPLETION,
                    lsp.CompletionOptions(trigger_characters=["(", ",", " "]))
    def completion(params: lsp.CompletionParams) -> lsp.CompletionList:
        path = path_of(params.text_document.uri)
        items = [lsp.CompletionItem(label=label, kind=COMPLETION_KIND[kind], detail=detail)
                 for label, kind, detail in
                 completion_candidates(ws, path, params.position.line + 1)]
        return lsp.CompletionList(is_incomplete=False, items=items)

    @server.feature(lsp.TEXT_DOCUMENT_FORMATTING)
    def formatting(ls: LanguageServer,
                   params: lsp.DocumentFormattingParams) -> list[lsp.TextEdit] | None:
        document = ls.workspace.get_text_document(params.text_document.uri)
        text = document.source
        new = formatted(text, str(path_of(params.text_document.uri)))
        if new is None or new == text:
            return None if new is None else []
        end = lsp.Position(line=len(text.splitlines()) + 1, character=0)
        return [lsp.TextEdit(range=lsp.Range(start=lsp.Position(line=0, character=0), end=end),
                             new_text=new)]

    return server


def serve() -> None:
    build_server().start_io()
