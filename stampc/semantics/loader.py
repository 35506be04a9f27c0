"""Reading sources: parsing files, splitting them into domain and problem sections, and
resolving ``use`` (stdlib modules and relative files) and ``problem ... for DOMAIN``.

Never imports or runs user code: bindings stay strings.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from stampc.diagnostics import Diagnostic, Label
from stampc.semantics.codes import diag
from stampc.syntax import ast
from stampc.syntax.parser import parse_source

DOMAIN_DECLS = (ast.TypeDecl, ast.ConstantDecl, ast.PredicateDecl, ast.FunctionDecl,
                ast.GeneratorDecl, ast.EvaluatorDecl, ast.ActionDecl, ast.Use)
PROBLEM_DECLS = (ast.ObjectDecl, ast.InitDecl, ast.GoalDecl, ast.HorizonDecl, ast.SceneDecl)


def stdlib_dir() -> Path | None:
    """``<repo>/stdlib`` beside the package first, else the installed ``stampc.stdlib``."""
    local = Path(__file__).resolve().parents[2] / "stdlib"
    if local.is_dir():
        return local
    # installed: packaging maps stdlib/ to stampc/stdlib (a namespace package, so
    # importlib.resources would hand back a MultiplexedPath, not a directory)
    installed = Path(__file__).resolve().parents[1] / "stdlib"
    return installed if installed.is_dir() else None


@dataclass(frozen=True)
class Source:
    """One parsed file (or string)."""

    name: str
    path: Path | None
    text: str
    program: ast.Program
    diagnostics: tuple[Diagnostic, ...]


@dataclass(frozen=True)
class DomainSource:
    """A domain's declarations: its own (``local``) and those of used modules."""

    header: ast.DomainHeader | None
    decls: tuple[ast.Decl, ...]
    local_files: frozenset[str]
    file: str


@dataclass(frozen=True)
class ProblemSource:
    header: ast.ProblemHeader
    decls: tuple[ast.Decl, ...]
    file: str


@dataclass
class Sections:
    """Declarations of one file grouped by the header they follow."""

    domain: ast.DomainHeader | None = None
    domain_decls: list = field(default_factory=list)
    problem: ast.ProblemHeader | None = None
    problem_decls: list = field(default_factory=list)


def read_source(path: Path, name: str | None = None) -> Source:
    text = path.read_text(encoding="utf-8")
    return source_from_text(text, name or str(path), path)


def source_from_text(text: str, name: str, path: Path | None = None) -> Source:
    program, diags = parse_source(text, name)
    return Source(name, path, text, program, tuple(diags))


def split_sections(source: Source, diags: list[Diagnostic]) -> Sections:
    """Group declarations under ``domain``/``module``/``problem`` headers (E002 on misuse)."""
    s = Sections()
    section = "domain"
    for d in source.program.decls:
        if isinstance(d, ast.DomainHeader):
            if s.domain is not None or s.problem is not None:
                diags.append(diag("E002", "a file holds at most one domain, before its problem",
                                  d.span, labels=_first(s.domain, "first domain declared here")))
                section = "skip"
                continue
            s.domain, section = d, "domain"
        elif isinstance(d, ast.ModuleHeader):
            if s.problem is not None:
                diags.append(diag("E002", "`module` must come before any problem", d.span))
            section = "domain" if s.problem is None else "skip"
        elif isinstance(d, ast.ProblemHeader):
            if s.problem is not None:
                diags.append(diag("E002", "a file holds at most one problem", d.span,
                                  labels=_first(s.problem, "first problem declared here")))
                section = "skip"
                continue
            s.problem, section = d, "problem"
        elif section == "domain":
            if isinstance(d, PROBLEM_DECLS):
                diags.append(diag("E002", f"`{_keyword(d)}` belongs in a problem, not a domain",
                                  d.span, "start a problem with `problem NAME for DOMAIN`"))
            else:
                s.domain_decls.append(d)
        elif section == "problem":
            if isinstance(d, DOMAIN_DECLS):
                diags.append(diag("E002", f"`{_keyword(d)}` belongs in a domain, not a problem",
                                  d.span, "declare it in the domain (before `problem`)"))
            else:
                s.problem_decls.append(d)
    return s


def _first(header, message: str) -> tuple[Label, ...]:
    return (Label(header.span, message),) if header is not None else ()


def _keyword(d: ast.Decl) -> str:
    names = {ast.ObjectDecl: "object", ast.InitDecl: "init", ast.GoalDecl: "goal",
             ast.HorizonDecl: "horizon", ast.SceneDecl: "scene", ast.TypeDecl: "type",
             ast.ConstantDecl: "constant", ast.PredicateDecl: "predicate",
             ast.FunctionDecl: "function", ast.GeneratorDecl: "generator",
             ast.EvaluatorDecl: "evaluator", ast.ActionDecl: "action", ast.Use: "use"}
    return names.get(type(d), "declaration")


class Resolver:
    """Resolves ``use`` transitively; each file is read and parsed once."""

    def __init__(self) -> None:
        self.sources: dict[str, Source] = {}
        self.diagnostics: list[Diagnostic] = []

    def source(self, path: Path) -> Source | None:
        key = str(path.resolve())
        if key not in self.sources:
            try:
                self.sources[key] = read_source(path, _display(path))
            except (OSError, UnicodeDecodeError):
                return None
            self.diagnostics.extend(self.sources[key].diagnostics)
        return self.sources[key]

    def domain(self, main: Source, sections: Sections) -> DomainSource:
        decls: list = []
        seen: set[str] = set()
        if main.path is not None:
            seen.add(str(main.path.resolve()))
        self._expand(sections.domain_decls, main, decls, seen)
        local = frozenset({main.name})
        return DomainSource(sections.domain, tuple(decls), local, main.name)

    def _expand(self, items: list, owner: Source, out: list, seen: set[str]) -> None:
        for d in items:
            if not isinstance(d, ast.Use):
                out.append(d)
                continue
            path = self._locate(d, owner)
            if path is None:
                what = f'file "{d.target}"' if d.is_path else f"module `{d.target}`"
                hint = ("paths are relative to the file that uses them" if d.is_path else
                        "stdlib modules live in stdlib/<name>.stamp; use \"path.stamp\" for a file")
                self.diagnostics.append(diag("E003", f"cannot find {what}", d.span, hint))
                continue
            key = str(path.resolve())
            if key in seen:
                continue
            seen.add(key)
            used = self.source(path)
            if used is None:
                self.diagnostics.append(diag("E003", f"cannot read {path}", d.span))
                continue
            sub = split_sections(used, self.diagnostics)
            if sub.problem is not None:
                self.diagnostics.append(diag("E002", f"a used file must not contain a problem ({used.name})",
                                             d.span))
            self._expand(sub.domain_decls, used, out, seen)

    @staticmethod
    def _locate(use: ast.Use, owner: Source) -> Path | None:
        base = owner.path.parent if owner.path is not None else Path.cwd()
        if use.is_path:
            candidate = (base / use.target)
            return candidate if candidate.is_file() else None
        for folder in (base, stdlib_dir()):
            if folder is not None and (folder / f"{use.target}.stamp").is_file():
                return folder / f"{use.target}.stamp"
        return None


def locate_use(use: ast.Use, owner: Source) -> Path | None:
    """The file ``use`` names from ``owner`` (a stdlib module or a relative path), or
    None; what ``check`` resolves, for tools such as the language server."""
    return Resolver._locate(use, owner)


def find_domain_file(problem: ast.ProblemHeader, owner: Source) -> Path | None:
    """``DOMAIN.stamp`` or ``domain.stamp`` beside the problem file."""
    if owner.path is None:
        return None
    folder = owner.path.parent
    for name in (f"{problem.domain.name}.stamp", "domain.stamp"):
        candidate = folder / name
        if candidate.is_file() and candidate.resolve() != owner.path.resolve():
            return candidate
    return None


def _display(path: Path) -> str:
    """Paths below the working directory are shown relative to it (stable diagnostics)."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def display_name(path: Path) -> str:
    return _display(path)


def missing_domain(problem: ast.ProblemHeader) -> Diagnostic:
    return diag("E107", f"cannot find domain `{problem.domain.name}`", problem.domain.span,
                f"put it in {problem.domain.name}.stamp or domain.stamp beside the problem, "
                "or pass both files")
