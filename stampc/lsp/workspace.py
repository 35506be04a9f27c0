"""What the language server knows: the open documents' texts over the files on disk,
each parsed once per text, and for a file the set of files its names can come from.

A file's *scope* is itself, the modules it ``use``s (transitively: stdlib modules and
relative paths, resolved as ``check`` resolves them), the domain a problem is ``for``
(the file beside it that declares that domain, else the one ``check`` finds) and the
problems beside a domain that are for it. Names
are looked up over the scope; diagnostics come from ``stampc.semantics`` itself.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

from stampc.diagnostics import Diagnostic, StampcError
from stampc.lsp.symbols import RESOLVES_TO, Occurrence, at_position, enclosing_param, occurrences
from stampc.semantics.loader import (Source, display_name, find_domain_file, locate_use,
                                     source_from_text)
from stampc.syntax import ast


@dataclass(frozen=True)
class Found:
    """An occurrence and the source it is in."""

    source: Source
    occurrence: Occurrence


def header(source: Source) -> ast.Decl | None:
    return next((d for d in source.program.decls
                 if isinstance(d, (ast.DomainHeader, ast.ProblemHeader, ast.ModuleHeader))), None)


class Workspace:
    def __init__(self) -> None:
        self.open: dict[Path, str] = {}
        self._parsed: dict[Path, Source] = {}

    # ------------------------------------------------------------ documents
    def set_text(self, path: Path, text: str) -> None:
        self.open[path.resolve()] = text

    def close(self, path: Path) -> None:
        self.open.pop(path.resolve(), None)

    def source(self, path: Path) -> Source | None:
        """The parsed file (the editor's text when open), or None when unreadable."""
        path = path.resolve()
        text = self.open.get(path)
        if text is None:
            try:
                text = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                return None
        cached = self._parsed.get(path)
        if cached is None or cached.text != text:
            cached = source_from_text(text, display_name(path), path)
            self._parsed[path] = cached
        return cached

    # ------------------------------------------------------------ analysis
    def diagnostics(self, path: Path) -> list[Diagnostic]:
        """What ``stampc check FILE`` reports for this file, on the editor's text."""
        from stampc.semantics.api import analyze, unique_sorted

        from stampc.inputs import checked_text

        source = self.source(path)
        if source is None:
            return []
        try:
            checked_text(source.text, source.name)
        except StampcError as exc:  # a blank document: I002, as `check` says of the file
            return list(exc.diagnostics)
        diags = [d for p in analyze([source]) for d in p.diagnostics]
        return [d for d in unique_sorted(diags) if d.span.file == source.name]

    def scope(self, path: Path) -> list[Source]:
        start = self.source(path)
        if start is None:
            return []
        seen: dict[Path, Source] = {}
        queue = [start]
        while queue:
            source = queue.pop()
            if source.path is None or source.path in seen:
                continue
            seen[source.path] = source
            queue.extend(self._neighbours(source))
        return list(seen.values())

    def _neighbours(self, source: Source) -> Iterator[Source]:
        for decl in source.program.decls:
            if isinstance(decl, ast.Use):
                target = locate_use(decl, source)
                if target is not None and (used := self.source(target)) is not None:
                    yield used
        head = header(source)
        if isinstance(head, ast.ProblemHeader):
            domain = self._sibling(source, ast.DomainHeader, head.domain.name)
            target = find_domain_file(head, source) if domain is None else None
            if domain is None and target is not None:
                domain = self.source(target)
            if domain is not None:
                yield domain
        elif isinstance(head, ast.DomainHeader):
            yield from self._siblings(source, ast.ProblemHeader, head.name.name)

    def _siblings(self, source: Source, kind: type, domain: str) -> Iterator[Source]:
        """The .stamp files beside ``source`` whose header is ``kind`` for ``domain``."""
        if source.path is None:
            return
        for sibling in sorted(source.path.parent.glob("*.stamp")):
            other = self.source(sibling)
            head = header(other) if other is not None else None
            if isinstance(head, kind) and (head.domain.name if kind is ast.ProblemHeader
                                           else head.name.name) == domain:
                yield other

    def _sibling(self, source: Source, kind: type, domain: str) -> Source | None:
        """The domain file beside a problem that declares its domain (a folder may hold
        several domains; ``check`` on the problem alone finds the one by file name)."""
        return next(self._siblings(source, kind, domain), None)

    # ------------------------------------------------------------ names
    def at(self, path: Path, line: int, col: int) -> Found | None:
        source = self.source(path)
        if source is None:
            return None
        occ = at_position(source.program, line, col)
        return Found(source, occ) if occ is not None else None

    def definitions(self, path: Path, found: Found) -> list[Found]:
        """Where the name at ``found`` is declared: a parameter in its declaration, else
        every declaration of that name and kind in scope (this file's first)."""
        occ = found.occurrence
        if occ.defines and occ.kind == "param":
            return [found]
        if occ.kind in ("term", "param"):
            param = enclosing_param(occ)
            if param is not None:
                return [Found(found.source, param)]
        kinds = RESOLVES_TO[occ.kind]
        hits = [f for f in self._all(path) if f.occurrence.defines
                and f.occurrence.name == occ.name and f.occurrence.kind in kinds
                and f.occurrence.kind != "param"]
        return sorted(hits, key=lambda f: f.source.path != found.source.path)

    def references(self, path: Path, found: Found, include_declaration: bool) -> list[Found]:
        """Every use (and declaration) of the same type, predicate, function, generator,
        action or constant in scope; a parameter's uses within its declaration."""
        defs = self.definitions(path, found)
        if not defs:
            return []
        target = defs[0].occurrence
        if target.kind == "param":
            pool = [Found(found.source, o) for o in occurrences(ast.Program((target.decl,)))]
            hits = [f for f in pool if f.occurrence.name == target.name
                    and f.occurrence.kind in ("param", "term")]
        else:
            hits = [f for f in self._all(path) if f.occurrence.name == target.name
                    and target.kind in RESOLVES_TO[f.occurrence.kind]
                    and not (f.occurrence.kind == "term" and enclosing_param(f.occurrence))]
        return [f for f in hits if include_declaration or not f.occurrence.defines]

    def declared(self, path: Path) -> dict[str, Found]:
        """Every name declared in scope (not parameters), first declaration wins."""
        names: dict[str, Found] = {}
        for f in self._all(path):
            if f.occurrence.defines and f.occurrence.kind != "param":
                names.setdefault(f.occurrence.name, f)
        return names

    def _all(self, path: Path) -> Iterator[Found]:
        for source in self.scope(path):
            for occ in occurrences(source.program):
                yield Found(source, occ)
