"""``stampc execute``: run a refined policy in its world, the world deciding outcomes;
provenance, collisions and the goal are checked (see docs/execute.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from stampc.commands.common import EXIT_DONE, EXIT_STOPPED_SHORT, positive_int, reports_errors

HELP = ("run a refined policy (policy.json) in its world, the world sampling outcomes; "
        "checks provenance, collisions (10x) and the concrete goal, and reports")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("policy", metavar="POLICY.json")
    parser.add_argument("--runs", type=positive_int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--max-steps", type=positive_int, default=500,
                        help="step cap per run (default 500)")
    parser.add_argument("--truth", action="append", default=[], metavar="KEY=VALUE",
                        help="true probability of a labelled outcome, `NAME=P` (any action) "
                             "or `ACTION.NAME=P` (repeatable; default: the model's); see "
                             "docs/execute.md")
    parser.add_argument("--render", metavar="DIR", help="write PNG frames, an animated GIF "
                        "(and an MP4 with imageio-ffmpeg) of the first run here")
    parser.add_argument("--no-physics", action="store_true",
                        help="PyBullet: leave objects where executors put them (no settling "
                             "under gravity)")
    parser.add_argument("--no-memo", action="store_true",
                        help="simulate every step of every run, even one already computed "
                             "from the same concrete state (slower; same report)")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    parser.add_argument("--verbose", action="store_true")


@reports_errors("execute")
def run(args: argparse.Namespace) -> int:
    from stampc.execute.frames import Recorder
    from stampc.execute.session import execute_file

    # bad input (StampcError, exit 1) and unreadable files (OSError, 2): reports_errors
    recorder = Recorder(Path(args.render)) if args.render else None
    report = execute_file(Path(args.policy), runs=args.runs, seed=args.seed,
                          max_steps=args.max_steps, truth=args.truth, verbose=args.verbose,
                          physics=not args.no_physics, recorder=recorder,
                          memo=not args.no_memo)
    print(report.render(args.format))
    if recorder:
        written = recorder.finish()
        print(f"wrote {len(recorder.frames)} frames, {', '.join(p.name for p in written)} "
              f"to {args.render}", file=sys.stderr if args.format == "json" else sys.stdout)
    return EXIT_DONE if report.ok else EXIT_STOPPED_SHORT
