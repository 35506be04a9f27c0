"""The front end's Python API: ``parse``, ``load``, ``check``.

``parse`` and ``load`` raise :class:`StampcError` (carrying every diagnostic) on errors;
``check`` returns the diagnostics. None of them imports or runs bound Python code.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence, Union

from stampc.diagnostics import Diagnostic, Span, StampcError, has_errors, sort_key
from stampc.semantics.bindings import check_bindings
from stampc.semantics.check_domain import check_domain
from stampc.semantics.check_problem import ProblemInfo, build_problem, check_problem, check_problem_domain
from stampc.semantics.codes import diag
from stampc.semantics.generators import Production
from stampc.semantics.lints import lint_domain, lint_problem
from stampc.semantics.loader import (ProblemSource, Resolver, Source, display_name, find_domain_file,
                                     missing_domain, source_from_text, split_sections)
from stampc.semantics.scope import DomainInfo, build_domain
from stampc.syntax import ast
from stampc.syntax.parser import no_gc_pauses, parse_source

PathOrText = Union[str, Path]
# syntax errors, over-deep nesting and misplaced index variables drop declarations
PARTIAL_AST = frozenset({"E001", "E006", "E007", "E008"})


@dataclass(frozen=True)
class LoadedProgram:
    """A resolved and checked domain (and problem, if any) with all diagnostics."""

    domain: DomainInfo | None
    problem: ProblemInfo | None
    productions: Mapping[str, Production] = field(default_factory=dict)
    diagnostics: tuple[Diagnostic, ...] = ()
    sources: Mapping[str, str] = field(default_factory=dict)

    @property
    def has_errors(self) -> bool:
        return has_errors(self.diagnostics)


def parse(text: str, filename: str = "<string>") -> ast.Program:
    """Parse one source text; raises :class:`StampcError` on syntax errors."""
    program, diags = parse_source(text, filename)
    if diags:
        raise StampcError(diags)
    return program


def load(path: PathOrText) -> LoadedProgram:
    """Load a domain and/or problem file, resolving ``use`` and the problem's domain.

    Raises :class:`StampcError` when there is any error; warnings stay in
    ``LoadedProgram.diagnostics``.
    """
    programs = analyze([_as_source(path)])
    loaded = programs[0]
    if loaded.has_errors:
        raise StampcError(loaded.diagnostics)
    return loaded


def check(*paths_or_texts: PathOrText) -> list[Diagnostic]:
    """Check files (``Path`` or a string naming an existing ``.stamp`` file) or source
    texts together: a problem is checked against a domain given alongside it."""
    sources = [_as_source(x) for x in paths_or_texts]
    diags: list[Diagnostic] = []
    for loaded in analyze(sources, bindings=True):
        diags.extend(loaded.diagnostics)
    return unique_sorted(diags)


def _as_source(item: PathOrText) -> Source:
    if isinstance(item, Path) or ("\n" not in item and item.endswith(".stamp")):
        path = Path(item)
        name = display_name(path)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
            raise StampcError([diag("E003", f"cannot read {name}: {reason}", Span.point(name))]) from None
        return source_from_text(text, name, path)
    return source_from_text(str(item), "<string>")


def unique_sorted(diags: Sequence[Diagnostic]) -> list[Diagnostic]:
    seen: set = set()
    out: list[Diagnostic] = []
    for d in sorted(diags, key=sort_key):
        key = (d.code, d.span, d.message)
        if key not in seen:
            seen.add(key)
            out.append(d)
    return out


def analyze(sources: list[Source], bindings: bool = False) -> list[LoadedProgram]:
    """Group sources (domains with the problems for them) and check every group;
    ``bindings``: also read the bound Python functions' signatures (``check`` does)."""
    with no_gc_pauses():
        return _analyze(sources, bindings)


def _analyze(sources: list[Source], bindings: bool) -> list[LoadedProgram]:
    resolver = Resolver()
    diags: list[Diagnostic] = []
    split = [(s, split_sections(s, diags)) for s in sources]
    domains = {sec.domain.name.name: (s, sec) for s, sec in split if sec.domain is not None}
    results: list[LoadedProgram] = []
    paired: set[str] = set()
    for s, sec in split:
        if sec.problem is None:
            continue
        if sec.domain is not None:
            dom_source, dom_sec = s, sec
        elif sec.problem.domain.name in domains:
            dom_source, dom_sec = domains[sec.problem.domain.name]
        else:
            path = find_domain_file(sec.problem, s)
            found = resolver.source(path) if path is not None else None
            if found is None:
                results.append(_failed(s, [missing_domain(sec.problem)] + list(s.diagnostics)))
                continue
            dom_source, dom_sec = found, split_sections(found, diags)
        paired.add(dom_source.name)
        results.append(_check_group(resolver, dom_source, dom_sec, s, sec, sources, bindings))
    for s, sec in split:
        if sec.problem is None and s.name not in paired:
            results.append(_check_group(resolver, s, sec, None, None, sources, bindings))
    if diags and results:
        first = results[0]
        results[0] = LoadedProgram(first.domain, first.problem, first.productions,
                                   tuple(unique_sorted(list(first.diagnostics) + diags)), first.sources)
    return results


def _failed(s: Source, diags: list[Diagnostic]) -> LoadedProgram:
    return LoadedProgram(None, None, {}, tuple(unique_sorted(diags)), {s.name: s.text})


def _check_group(resolver: Resolver, dom_source: Source, dom_sec, prob_source: Source | None,
                 prob_sec, inputs: list[Source], bindings: bool = False) -> LoadedProgram:
    diags: list[Diagnostic] = list(dom_source.diagnostics)
    before = len(resolver.diagnostics)
    dsrc = resolver.domain(dom_source, dom_sec)
    info = build_domain(dsrc, diags)
    productions = check_domain(info, diags)
    problem = None
    if prob_source is not None and prob_sec is not None:
        if prob_source is not dom_source:
            diags.extend(prob_source.diagnostics)
        psrc = ProblemSource(prob_sec.problem, tuple(prob_sec.problem_decls), prob_source.name)
        problem = build_problem(psrc, info, diags)
        diags.extend(check_problem_domain(problem, info, prob_sec.problem))
        check_problem(problem, info, diags)
    diags.extend(resolver.diagnostics[before:])
    if not any(d.code in PARTIAL_AST for d in diags):  # lints on a partial AST only mislead
        if problem is not None:
            lint_problem(problem, info, diags)
        lint_domain(info, productions, problem, diags)
        if bindings:
            check_bindings(info, diags)
    texts = {s.name: s.text for s in inputs}
    texts.update({s.name: s.text for s in resolver.sources.values()})
    texts[dom_source.name] = dom_source.text
    return LoadedProgram(info, problem, productions, tuple(unique_sorted(diags)), texts)


def load_together(paths: Sequence[PathOrText]) -> LoadedProgram:
    """Load a domain file and a problem file (or one file holding both) as one program.

    Returns the program holding the problem (or the first one if there is no problem),
    with that program's own diagnostics; raises :class:`StampcError` carrying the errors
    of every file when any file has an error."""
    programs = analyze([_as_source(p) for p in paths])
    with_problem = [p for p in programs if p.problem is not None]
    loaded = (with_problem or programs)[0]
    errors = [d for p in programs for d in p.diagnostics if d.is_error]
    if errors:
        raise StampcError(unique_sorted(errors))
    return loaded
