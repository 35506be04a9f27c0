"""``stampc fmt``: print stamp files in canonical layout (comments are kept)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from stampc.commands.common import EXIT_DONE, EXIT_INPUT, read_input, reports_errors
from stampc.diagnostics import SourceCache, StampcError, render_human, summary_line

HELP = "format stamp files canonically (prints to stdout unless --write or --check)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", metavar="FILE", help="stamp files to format")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("-w", "--write", action="store_true", help="rewrite the files in place")
    mode.add_argument("--check", action="store_true",
                      help="exit 1 (and list the files) if any file is not formatted")


@reports_errors("fmt")
def run(args: argparse.Namespace) -> int:
    from stampc.syntax.fmt import format_program
    from stampc.syntax.parser import parse_source

    status = EXIT_DONE
    for name in args.files:
        path = Path(name)
        try:
            text, shown = read_input(name)
        except StampcError as exc:  # binary or empty: say so, format the other files
            _print_diagnostics(exc.diagnostics, SourceCache())
            status = EXIT_INPUT
            continue
        program, diags = parse_source(text, shown)
        if diags:
            cache = SourceCache()
            cache.add(shown, text)
            _print_diagnostics(diags, cache)
            status = EXIT_INPUT
            continue
        formatted = format_program(program, text)
        if args.check:
            if formatted != text:
                print(f"would reformat {shown}")
                status = EXIT_INPUT
        elif args.write:
            if formatted != text:
                path.write_text(formatted, encoding="utf-8")  # OSError: exit 2 (reports_errors)
        else:
            sys.stdout.write(formatted)
    return status


def _print_diagnostics(diags, cache: SourceCache) -> None:
    for d in diags:
        print(render_human(d, cache) + "\n", file=sys.stderr)
    print(summary_line(diags), file=sys.stderr)
