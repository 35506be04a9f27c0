"""``stampc view``: one self-contained HTML report of a refine run (docs/view.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from stampc.commands.common import EXIT_DONE, EXIT_USAGE, reports_errors

HELP = "write a self-contained HTML report of a refine run (policy graph, coverage, PRG history)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("run_dir", metavar="RUN_DIR",
                        help="the directory written by `stampc refine ... -o RUN_DIR`")
    parser.add_argument("-o", "--output", metavar="FILE",
                        help="write the report here (default RUN_DIR/report.html)")
    parser.add_argument("--open", action="store_true",
                        help="open the report in the default web browser")


@reports_errors("view")
def run(args: argparse.Namespace) -> int:
    from stampc.view import MissingViewExtra, view_run

    # bad run-dir content (StampcError, exit 1) and unreadable paths (OSError, 2): reports_errors
    try:
        out = view_run(args.run_dir, args.output)
    except MissingViewExtra as exc:
        print(f"stampc view: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    size = out.stat().st_size
    print(f"wrote {out} ({size / 1e6:.2f} MB)")
    if args.open:
        import webbrowser

        if not webbrowser.open(Path(out).resolve().as_uri()):
            print("stampc view: no web browser found; open the file yourself", file=sys.stderr)
    return EXIT_DONE
