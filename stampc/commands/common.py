"""Small helpers shared by the CLI subcommands."""

from __future__ import annotations

import argparse
import ast
import sys
from pathlib import Path

from stampc.diagnostics import SourceCache, StampcError, render_human, sort_key, summary_line


def add_input_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help="DOMAIN [PROBLEM] (.stamp), or one .pddl file (domain.pddl beside it "
                             "for problem-only files), or domain.pddl problem.pddl")


def read_source(name: str, command: str) -> str | None:
    """The text of file ``name``, or None after printing why it cannot be read (exit 2)."""
    try:
        return Path(name).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else "not UTF-8 text"
        print(f"stampc {command}: error: cannot read {name}: {reason}", file=sys.stderr)
        return None


def fail_with(exc: StampcError) -> int:
    """Print an error's diagnostics the way `stampc check` does; exit code 1."""
    sources = SourceCache()
    diags = sorted(exc.diagnostics, key=sort_key)
    for d in diags:
        print(render_human(d, sources), file=sys.stderr)
    print(summary_line(diags), file=sys.stderr)
    return 1


def parse_scene_args(pairs: list[str]) -> dict[str, object]:
    """``key=value`` pairs; values are Python literals when they parse as one."""
    out: dict[str, object] = {}
    for pair in pairs:
        key, sep, raw = pair.partition("=")
        if not sep or not key.isidentifier():
            raise ValueError(f"expected KEY=VALUE, got {pair!r}")
        try:
            out[key] = ast.literal_eval(raw)
        except (ValueError, SyntaxError):
            out[key] = raw
    return out


def add_import_options(parser: argparse.ArgumentParser) -> None:
    """Options of PPDDL import and grounding shared by ``compile`` and ``solve``."""
    parser.add_argument("--lenient", action="store_true",
                        help="PPDDL: accept what mdp-lib's mini-gpt accepts (undeclared "
                             "predicates, problem objects in the domain, repeated declaration "
                             "variables, no goal) with warnings")
    parser.add_argument("--conflicting-effects", choices=("add-wins", "delete-wins"),
                        default="add-wins",
                        help="when one outcome adds and deletes the same fact: add-wins "
                             "(PDDL, MDPSim; default) or delete-wins (mdp-lib's mini-gpt)")


def print_warnings(diags) -> None:
    """Warnings of a successful run, located, on standard error."""
    sources = SourceCache()
    for d in sorted(diags, key=sort_key):
        print(render_human(d, sources), file=sys.stderr)
