"""The ``stampc`` command line: one subcommand per pipeline stage.

Each subcommand lives in ``stampc/commands/<name>.py`` and exposes
``HELP: str``, ``add_arguments(parser)`` and ``run(args) -> int``. Exit codes, the same
for every command: 0 done, 1 input errors, 2 usage or I/O errors, 3 ran but stopped short
(partial result written). A command reports bad input by raising :class:`StampcError`
(exit 1) and unreadable or unwritable files by raising ``OSError`` (exit 2); its ``run``
is wrapped in ``commands.common.reports_errors``, which prints both.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import sys

from stampc import __version__
from stampc.commands.common import EXIT_CODES_HELP, EXIT_USAGE

COMMANDS = ("check", "fmt", "compile", "solve", "refine", "execute", "view", "lsp")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="stampc",
        description="stampc: stochastic task and motion planning toolkit",
        epilog=EXIT_CODES_HELP,
    )
    parser.add_argument("--version", action="version", version=f"stampc {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        module_name = f"stampc.commands.{name}"
        if importlib.util.find_spec(module_name) is None:
            continue  # command not part of this build
        module = importlib.import_module(module_name)
        cmd = sub.add_parser(name, help=module.HELP, description=module.HELP,
                             epilog=EXIT_CODES_HELP)
        module.add_arguments(cmd)
        cmd.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (exit 2), --help and --version (0)
        return int(exc.code or 0)
    if not getattr(args, "_run", None):
        parser.print_help()
        return EXIT_USAGE
    try:
        return int(args._run(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
