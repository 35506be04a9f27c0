"""Input files, checked the same way for every command and API entry point.

A path that does not exist or is not a regular file is an I/O problem: ``OSError``
(``FileNotFoundError``, ``IsADirectoryError``), which the CLI reports with exit 2. A file
whose content cannot be a source text is an input error: :class:`StampcError` with a
located diagnostic (exit 1) —

* ``I001`` not text: bytes that are not UTF-8, or a NUL byte (no text file holds one);
  located at the offending byte's line and column, and the raw bytes are never echoed;
* ``I002`` empty: nothing but white space (a file with only comments is left to the
  front end: it can be a deliberate placeholder module).

A leading UTF-8 byte-order mark is accepted and dropped.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Iterable

from stampc.diagnostics import Span, StampcError, error

BOM = "\ufeff"
CODES = {"I001": "input is not UTF-8 text", "I002": "input file is empty"}


def existing_file(path: Path) -> Path:
    """``path`` itself; ``OSError`` naming the problem when it is not a readable file."""
    if path.is_dir():
        raise IsADirectoryError(f"cannot read {path}: it is a directory, not a file")
    if not path.is_file():
        raise FileNotFoundError(f"cannot read {path}: " + ("no such file" if not path.exists()
                                                           else "not a regular file"))
    return path


def read_input_text(path: Path, shown: str | None = None) -> str:
    """The text of input file ``path`` (``shown`` names it in diagnostics)."""
    shown = shown or str(path)
    data = existing_file(path).read_bytes()
    bad = _first_bad_byte(data)
    if bad is not None:
        offset, what = bad
        raise StampcError([error("I001", f"not UTF-8 text: {what} at byte offset {offset}",
                                 _span_of_offset(shown, data, offset),
                                 hint="stamp and PPDDL inputs are UTF-8 text files; "
                                      "was a binary or differently encoded file passed?")])
    return checked_text(data.decode("utf-8"), shown)


def checked_text(text: str, shown: str) -> str:
    """``text`` without a byte-order mark; ``I002`` when it is blank (also for text that
    never was a file: an editor's buffer in the language server)."""
    text = text[1:] if text.startswith(BOM) else text
    if not text.strip():
        raise StampcError([error("I002", "empty file: nothing to read", Span.point(shown),
                                 hint="write a `domain`, `module` or `problem` in it, or "
                                      "pass the file that holds one")])
    return text


def check_input_files(paths: Iterable[Path]) -> list[Path]:
    """Check every file as :func:`read_input_text` does; all I001/I002 problems at once."""
    checked, diags = [], []
    for path in paths:
        try:
            read_input_text(path, display_name(path))
        except StampcError as exc:
            diags.extend(exc.diagnostics)
        checked.append(path)
    if diags:
        raise StampcError(diags)
    return checked


def _first_bad_byte(data: bytes) -> tuple[int, str] | None:
    nul = data.find(b"\0")
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as exc:
        if nul < 0 or exc.start < nul:
            return exc.start, f"byte 0x{data[exc.start]:02x}"
    return (nul, "NUL byte") if nul >= 0 else None


def _span_of_offset(shown: str, data: bytes, offset: int) -> Span:
    """Line and column (in characters of the valid prefix) of byte ``offset``."""
    before = data[:offset]
    line = before.count(b"\n") + 1
    line_start = before.rfind(b"\n") + 1
    col = len(before[line_start:].decode("utf-8", errors="replace")) + 1
    return Span.point(shown, line, col)


def display_name(path: Path) -> str:
    """Paths below the working directory relative to it, like the front end's names."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def json_problem(exc: json.JSONDecodeError, text: str) -> str:
    """"truncated JSON" when the text ends before the document does (the parser stopped
    at its end, or inside a string it never closed), else "not valid JSON"."""
    cut = exc.pos >= len(text.rstrip()) or exc.msg.startswith("Unterminated string")
    return "truncated JSON" if cut else "not valid JSON"
