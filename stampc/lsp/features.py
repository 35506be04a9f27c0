"""The language features as plain text and names (no protocol types): hover text,
completion candidates and formatting. ``server.py`` turns them into LSP messages."""

from __future__ import annotations

from pathlib import Path

from stampc.lsp.workspace import Found, Workspace
from stampc.syntax import ast
from stampc.syntax.words import STRUCTURAL

KEYWORDS = tuple(sorted(STRUCTURAL | {"not", "and", "or", "forall", "exists", "as", "for",
                                      "from", "true", "false"}))
#: the words hover uses for each kind
KIND_WORDS = {"type": "type", "predicate": "predicate", "function": "function",
              "generator": "generator", "action": "action", "constant": "constant",
              "param": "parameter"}


def hover_markdown(found: Found, definition: Found) -> str:
    """The declaration's first line as a stamp code block, the comment above it (and at
    its end), and where it is declared."""
    occ, source = definition.occurrence, definition.source
    lines = source.text.splitlines()
    first = occ.decl.span.line
    code = lines[first - 1].rstrip() if 0 < first <= len(lines) else occ.name
    code, trailing = _split_comment(code)
    comment = _comment_above(lines, first) + ([trailing] if trailing else [])
    what = KIND_WORDS.get(occ.kind, occ.kind)
    where = source.name if source.path != found.source.path else "this file"
    text = [f"```stamp\n{code.strip()}\n```", f"{what} `{occ.name}` — declared in {where}"
            f" (line {occ.span.line})"]
    if comment:
        text.append("\n".join(comment))
    return "\n\n".join(text)


def _comment_above(lines: list[str], first: int) -> list[str]:
    out: list[str] = []
    i = first - 2
    while i >= 0 and lines[i].lstrip().startswith("#"):
        out.insert(0, lines[i].lstrip()[1:].strip())
        i -= 1
    return out


def _split_comment(line: str) -> tuple[str, str]:
    """``code  # comment`` -> (code, comment); a ``#`` inside a string is not one."""
    quoted = False
    for i, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif ch == "#" and not quoted:
            return line[:i], line[i + 1:].strip()
    return line, ""


def completion_candidates(ws: Workspace, path: Path, line: int) -> list[tuple[str, str, str]]:
    """(label, kind, detail) of every name declared in scope, the parameters of the
    declaration around ``line`` (1-based), and the keywords."""
    out = [(name, f.occurrence.kind, f"{KIND_WORDS[f.occurrence.kind]} ({f.source.name})")
           for name, f in sorted(ws.declared(path).items())]
    source = ws.source(path)
    decl = _declaration_at(source.program, line) if source is not None else None
    if decl is not None:
        from stampc.lsp.symbols import occurrences

        params = {o.name for o in occurrences(ast.Program((decl,)))
                  if o.kind == "param" and o.defines}
        out += [(name, "param", "parameter") for name in sorted(params)]
    out += [(word, "keyword", "keyword") for word in KEYWORDS]
    return out


def _declaration_at(program: ast.Program, line: int) -> ast.Decl | None:
    """The declaration whose lines hold ``line``, or the one just above it (the cursor is
    often on a new, still empty line of the declaration being written)."""
    best = None
    for decl in program.decls:
        if decl.span.line <= line:
            best = decl
    return best


def formatted(source_text: str, name: str) -> str | None:
    """The canonical layout (``stampc fmt``), or None when the text does not parse."""
    from stampc.syntax.fmt import format_program
    from stampc.syntax.parser import parse_source

    program, diags = parse_source(source_text, name)
    if diags:
        return None
    return format_program(program, source_text)
