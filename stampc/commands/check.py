"""``stampc check``: parse, resolve and type-check stamp files; print diagnostics."""

from __future__ import annotations

import argparse
from pathlib import Path

from stampc.commands.common import EXIT_DONE, EXIT_INPUT, read_input, reports_errors
from stampc.diagnostics import Severity, SourceCache, StampcError, render_human, render_json, summary_line

HELP = "check stamp domains and problems for errors and warnings"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help="domain and/or problem files (a problem's domain is found via `for DOMAIN`)")
    parser.add_argument("--format", choices=("human", "json"), default="human",
                        help="output format (default: human)")
    parser.add_argument("--strict", action="store_true", help="treat warnings as failures")


@reports_errors("check")
def run(args: argparse.Namespace) -> int:
    from stampc.semantics.api import analyze, unique_sorted
    from stampc.semantics.loader import source_from_text

    sources, unreadable = [], []
    for name in args.files:
        try:
            text, shown = read_input(name)
        except StampcError as exc:  # binary or empty: reported with the other diagnostics
            unreadable.extend(exc.diagnostics)
            continue
        sources.append(source_from_text(text, shown, Path(name)))
    try:
        programs = analyze(sources, bindings=True) if sources else []
    except StampcError as exc:  # defensive: the analysis reports problems as diagnostics
        programs = []
        diags = list(exc.diagnostics)
    else:
        diags = [d for p in programs for d in p.diagnostics]
    diags = unique_sorted(unreadable + diags)
    cache = SourceCache()
    for program in programs:
        for file, text in program.sources.items():
            cache.add(file, text)
    if args.format == "json":
        print(render_json(diags))
    else:
        for d in diags:
            print(render_human(d, cache))
            print()
        print(summary_line(diags))
    failed = any(d.severity is Severity.ERROR for d in diags)
    if args.strict:
        failed = failed or any(d.severity is Severity.WARNING for d in diags)
    return EXIT_INPUT if failed else EXIT_DONE
