"""``stampc lsp``: the stamp language server over stdio (docs/lsp.md)."""

from __future__ import annotations

import argparse
import sys

from stampc.commands.common import EXIT_DONE, EXIT_USAGE

HELP = "run the stamp language server (LSP over stdio) for editors"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--stdio", action="store_true",
                        help="talk LSP over stdin/stdout (the default and only transport; "
                             "accepted because editors pass it)")


def run(args: argparse.Namespace) -> int:
    try:
        from stampc.lsp.server import serve
    except ImportError as exc:
        print(f"stampc lsp: error: the language server needs pygls ({exc.name} is missing): "
              "pip install 'stampc[lsp]'", file=sys.stderr)
        return EXIT_USAGE
    serve()
    return EXIT_DONE
