"""Small helpers shared by the CLI subcommands: exit codes, option types, input files."""

from __future__ import annotations

import argparse
import ast
import functools
import contextlib
import math
import signal
import sys
import threading
from pathlib import Path
from typing import Callable, Iterator

from stampc.diagnostics import SourceCache, StampcError, render_human, sort_key, summary_line

#: exit codes, the same for every command (README "Command line", ``stampc CMD --help``)
EXIT_DONE, EXIT_INPUT, EXIT_USAGE, EXIT_STOPPED_SHORT = 0, 1, 2, 3
EXIT_CODES_HELP = ("exit codes: 0 done; 1 input errors (located diagnostics); 2 usage or I/O "
                   "errors; 3 ran but stopped short (time limit before convergence, or below "
                   "the target coverage), with the partial result written")


def add_input_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help="DOMAIN [PROBLEM] (.stamp), or one .pddl file (domain.pddl beside it "
                             "for problem-only files), or domain.pddl problem.pddl")


def reports_errors(command: str):
    """Decorate a command's ``run``: ``StampcError`` prints its located diagnostics (exit
    1), ``OSError`` one line naming the file (exit 2) — never a traceback for either."""
    def decorate(run: Callable[[argparse.Namespace], int]):
        @functools.wraps(run)
        def guarded(args: argparse.Namespace) -> int:
            try:
                return run(args)
            except StampcError as exc:
                return fail_with(exc)
            except BrokenPipeError:
                raise
            except OSError as exc:
                print(io_error_message(command, exc), file=sys.stderr)
                return EXIT_USAGE
        return guarded
    return decorate


def io_error_message(command: str, exc: OSError) -> str:
    """``stampc CMD: error: FILE: reason`` for a file that cannot be read or written."""
    if exc.strerror is None:  # raised with a whole message (stampc.inputs)
        return f"stampc {command}: error: {exc}"
    where = f"{exc.filename}: " if exc.filename else ""
    return f"stampc {command}: error: {where}{exc.strerror}"


# ---------------------------------------------------------------- option value types
# argparse turns an ArgumentTypeError into "argument --x: <message>" and exit 2.

def _number(text: str, convert: Callable[[str], float]) -> float:
    try:
        return convert(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def positive_float(text: str) -> float:
    """Seconds, costs, tolerances: finite and > 0 (0, -5, nan and inf are usage errors)."""
    value = _number(text, float)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text!r}")
    return value


def ratio_or_none(text: str) -> float | None:
    """A limit given as a multiple: finite and >= 0, or "none" for no limit."""
    if text.strip().lower() == "none":
        return None
    value = _number(text, float)
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0 or 'none', got {text!r}")
    return value


def positive_int(text: str) -> int:
    """Counts and horizons: an integer >= 1."""
    value = _number(text, int)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}")
    return int(value)


def count(text: str) -> int:
    """A count where 0 means none: an integer >= 0."""
    value = _number(text, int)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {text!r}")
    return int(value)


def probability(text: str) -> float:
    value = _number(text, float)
    if not 0.0 <= value <= 1.0:  # also rejects nan
        raise argparse.ArgumentTypeError(f"must be a probability within [0, 1], got {text!r}")
    return value


def prune_probability(text: str) -> float:
    value = _number(text, float)
    if not 0.0 <= value < 1.0:  # also rejects nan; 1 would prune the root's own outcomes
        raise argparse.ArgumentTypeError(f"must be within [0, 1), got {text!r}")
    return value


def target_coverage(text: str) -> float:
    value = _number(text, float)
    if not 0.0 < value <= 1.0:
        raise argparse.ArgumentTypeError(f"must be within (0, 1], got {text!r}")
    return value


def heuristic_weight(text: str) -> float:
    value = _number(text, float)
    if not (math.isfinite(value) and value >= 1.0):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 1, got {text!r}")
    return value


def read_input(name: str) -> tuple[str, str]:
    """(text, shown name) of an input file; ``OSError`` (exit 2) when it cannot be read,
    ``StampcError`` I001/I002 (exit 1) when it is not text or empty."""
    from stampc.inputs import display_name, read_input_text

    path = Path(name)
    shown = display_name(path)
    return read_input_text(path, shown), shown


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


@contextlib.contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """Within the block SIGTERM stops the run like Ctrl-C (KeyboardInterrupt), so that
    anytime commands write what they have. A job started in the background of a script
    ignores SIGINT, so supervisors (bench/paper.py) stop runs with SIGTERM instead."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum, frame):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
