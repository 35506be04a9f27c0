"""``stampc fmt``: print stamp files in canonical layout (comments are kept)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from stampc.commands.common import read_source
from stampc.diagnostics import SourceCache, render_human, summary_line

HELP = "format stamp files canonically (prints to stdout unless --write or --check)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", metavar="FILE", help="stamp files to format")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("-w", "--write", action="store_true", help="rewrite the files in place")
    mode.add_argument("--check", action="store_true",
                      help="exit 1 (and list the files) if any file is not formatted")


def run(args: argparse.Namespace) -> int:
    from stampc.semantics.loader import display_name
    from stampc.syntax.fmt import format_program
    from stampc.syntax.parser import parse_source

    status = 0
    for name in args.files:
        path = Path(name)
        text = read_source(name, "fmt")
        if text is None:
            return 2
        shown = display_name(path)
        program, diags = parse_source(text, shown)
        if diags:
            cache = SourceCache()
            cache.add(shown, text)
            for d in diags:
                print(render_human(d, cache) + "\n", file=sys.stderr)
            print(summary_line(diags), file=sys.stderr)
            status = 1
            continue
        formatted = format_program(program, text)
        if args.check:
            if formatted != text:
                print(f"would reformat {shown}")
                status = 1
        elif args.write:
            if formatted != text:
                try:
                    path.write_text(formatted, encoding="utf-8")
                except OSError as exc:
                    print(f"stampc fmt: error: cannot write {name}: {exc.strerror}", file=sys.stderr)
                    return 2
        else:
            sys.stdout.write(formatted)
    return status
