"""PPDDL import: files or texts → :class:`stampc.ir.lifted.Model`.

A source may hold a domain, one or several problems, or both. The importer collects
every definition from the given sources, picks the problem (by ``problem_name`` when
several) and the domain it names; a problem-only file finds its domain in
``domain.pddl`` beside it. Every input error is a located :class:`Diagnostic`
(codes ``P1xx``, see ``docs/ppddl.md``) raised as :class:`StampcError`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from stampc.backends.ppddl import codes
from stampc.backends.ppddl.context import Lowering
from stampc.backends.ppddl.lower_domain import lower_domain
from stampc.backends.ppddl.lower_problem import lower_problem, problem_domain_name
from stampc.backends.ppddl.parser import parse_text
from stampc.backends.ppddl.reader import LineIndex
from stampc.backends.ppddl.shape_base import Node
from stampc.diagnostics import Span, StampcError, error, has_errors, sort_key
from stampc.ir.lifted import Domain, Model
from stampc.gcpause import no_gc_pauses

DOMAIN_FILE = "domain.pddl"


@dataclass(frozen=True)
class _Definition:
    kind: str  # "domain" | "problem"
    name: str
    tree: Node
    file: str
    index: LineIndex


def import_ppddl(path: str | Path, problem_path: str | Path | None = None, *,
                 problem_name: str | None = None, lenient: bool = False) -> Model:
    """Import a PPDDL domain + problem from one file or two (in either order).

    Without a domain among the given files, ``domain.pddl`` beside ``path`` is used.
    ``problem_name`` selects a problem when the files hold several. ``lenient`` accepts
    what mdp-lib's mini-gpt parser accepts (undeclared predicates, problem objects in
    the domain, repeated declaration variables, no goal) with warnings (P2xx) in
    ``Model.diagnostics``.
    """
    paths = [Path(path)] + ([Path(problem_path)] if problem_path is not None else [])
    definitions = [d for p in paths for d in _parse(_read(p), str(p))]
    if not any(d.kind == "domain" for d in definitions):
        fallback = Path(path).parent / DOMAIN_FILE
        if fallback.is_file() and fallback.resolve() not in {p.resolve() for p in paths}:
            definitions += _parse(_read(fallback), str(fallback))
    return _build(definitions, problem_name, str(paths[0]), lenient)


def import_ppddl_text(text: str, filename: str = "<string>", *,
                      domain_text: str | None = None, domain_filename: str = "<domain>",
                      problem_name: str | None = None, lenient: bool = False) -> Model:
    """Like :func:`import_ppddl` for in-memory texts; ``domain_text`` is a second source
    (normally the domain when ``text`` holds only a problem)."""
    definitions = _parse(text, filename)
    if domain_text is not None:
        definitions += _parse(domain_text, domain_filename)
    return _build(definitions, problem_name, filename, lenient)


# ---------------------------------------------------------------- helpers
def _read(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise StampcError([error(codes.IO, f"cannot read {path}: {exc.strerror or exc}",
                                 Span.point(str(path)))]) from None


def _parse(text: str, filename: str) -> list[_Definition]:
    with no_gc_pauses():  # the trees are acyclic; GC scans made large files superlinear
        parsed = parse_text(text, filename)
    return [_Definition(node.data, str(node.children[0]), node, filename, parsed.index)
            for node in parsed.definitions]


def _build(definitions: list[_Definition], problem_name: str | None, main_file: str,
           lenient: bool) -> Model:
    problem = _select_problem(definitions, problem_name, main_file)
    domain_def = _select_domain(definitions, problem, main_file)
    cx = Lowering(domain_def.file, index=domain_def.index, lenient=lenient)
    domain = lower_domain(cx, domain_def.tree)
    _raise_if_errors(cx)
    pcx = Lowering(problem.file, types=dict(cx.types), objects=dict(cx.objects),
                   predicates=dict(cx.predicates), functions=dict(cx.functions),
                   index=problem.index, lenient=lenient, in_domain=False,
                   implicit_constants=set(cx.implicit_constants))
    with no_gc_pauses():
        lowered = lower_problem(pcx, problem.tree, domain)
    _raise_if_errors(pcx)
    domain = _with_problem_declarations(domain, pcx)
    return Model(domain, lowered, diagnostics=tuple(sorted(cx.diags + pcx.diags, key=sort_key)))


def _with_problem_declarations(domain: Domain, pcx: Lowering) -> Domain:
    """What --lenient learnt from the problem joins the domain: predicates first used
    there (static: no action changes them), as mini-gpt adds them to its domain, and the
    declared types of problem objects the domain used as constants."""
    if not pcx.lenient:
        return domain
    known = {p.name for p in domain.predicates}
    extra = tuple(replace(p, static=True) for p in pcx.predicates.values() if p.name not in known)
    constants = tuple(replace(c, type=pcx.objects[c.name].type)
                      if c.name in pcx.implicit_constants else c for c in domain.constants)
    return replace(domain, predicates=domain.predicates + extra, constants=constants)


def _raise_if_errors(cx: Lowering) -> None:
    if has_errors(cx.diags):
        raise StampcError(sorted(cx.diags, key=sort_key))


def _select_problem(definitions: list[_Definition], problem_name: str | None,
                    main_file: str) -> _Definition:
    problems = [d for d in definitions if d.kind == "problem"]
    where = Span.point(main_file)
    if problem_name is not None:
        wanted = problem_name.lower()  # names are case-insensitive
        matches = [d for d in problems if d.name == wanted]
        if not matches:
            available = ", ".join(d.name for d in problems) or "none"
            raise StampcError([error(codes.MISSING, f"no problem named '{problem_name}' "
                                     f"(problems found: {available})", where)])
        problems = matches
    if not problems:
        raise StampcError([error(codes.MISSING, "no (define (problem ...)) found", where,
                                 hint="pass the problem file as the second path")])
    if len(problems) > 1:
        names = ", ".join(d.name for d in problems)
        raise StampcError([error(codes.MISSING, f"several problems found ({names}); "
                                 "choose one with problem_name", where)])
    return problems[0]


def _select_domain(definitions: list[_Definition], problem: _Definition,
                   main_file: str) -> _Definition:
    domains = [d for d in definitions if d.kind == "domain"]
    wanted = problem_domain_name(problem.tree)
    named = [d for d in domains if d.name == wanted]
    if named:
        return named[0]
    if len(domains) == 1:
        return domains[0]  # a name mismatch is reported (P106) when lowering the problem
    if not domains:
        raise StampcError([error(codes.MISSING, f"no (define (domain {wanted or '...'})) found",
                                 Span.point(main_file),
                                 hint=f"put the domain in {DOMAIN_FILE} beside the problem "
                                      "or pass it as a second path")])
    names = ", ".join(d.name for d in domains)
    raise StampcError([error(codes.DOMAIN_MISMATCH, f"problem '{problem.name}' is for domain "
                             f"'{wanted}' but the domains found are {names}",
                             Span.point(problem.file))])


def import_domain_only(path: str | Path, *, lenient: bool = False) -> Domain:
    """Import just a domain (e.g. ``domain.pddl``); errors as for :func:`import_ppddl`."""
    definitions = _parse(_read(Path(path)), str(path))
    domains = [d for d in definitions if d.kind == "domain"]
    if not domains:
        raise StampcError([error(codes.MISSING, "no (define (domain ...)) found",
                                 Span.point(str(path)))])
    cx = Lowering(domains[0].file, index=domains[0].index, lenient=lenient)
    domain = lower_domain(cx, domains[0].tree)
    _raise_if_errors(cx)
    return domain
