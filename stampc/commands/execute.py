"""``stampc execute``: replay a refined policy in its world, sampling outcomes."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from stampc.commands.common import EXIT_DONE, EXIT_STOPPED_SHORT, positive_int, reports_errors

HELP = "replay a refined policy (policy.json) in its concrete world and report success"


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
    parser.add_argument("--render", metavar="DIR", help="write PNG frames and an animated GIF "
                        "of the first run here")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    parser.add_argument("--verbose", action="store_true")


@reports_errors("execute")
def run(args: argparse.Namespace) -> int:
    from stampc.execute.session import execute_file

    # bad input (StampcError, exit 1) and unreadable files (OSError, 2): reports_errors
    recorder = _Recorder(Path(args.render)) if args.render else None
    report = execute_file(Path(args.policy), runs=args.runs, seed=args.seed,
                          max_steps=args.max_steps, truth=args.truth, verbose=args.verbose,
                          on_step=recorder.on_step if recorder else None,
                          on_open=recorder.start if recorder else None)
    if recorder:
        recorder.finish()
    print(report.render(args.format))
    return EXIT_DONE if report.ok else EXIT_STOPPED_SHORT


class _Recorder:
    """Frames of the first run, written as PNGs plus one animated GIF."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.frames: list = []
        out.mkdir(parents=True, exist_ok=True)

    def start(self, world) -> None:
        self.frames.append(world.render())

    def on_step(self, run: int, world) -> None:
        if run == 0:
            self.frames.append(world.render())

    def finish(self) -> None:
        import imageio.v2 as imageio
        for i, frame in enumerate(self.frames):
            imageio.imwrite(self.out / f"frame_{i:03d}.png", frame)
        imageio.mimsave(self.out / "run.gif", self.frames, duration=0.6, loop=0)
        print(f"wrote {len(self.frames)} frames and run.gif to {self.out}")
