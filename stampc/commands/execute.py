"""``stampc execute``: replay a refined policy in its world, sampling outcomes."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from stampc.commands.common import EXIT_DONE, EXIT_STOPPED_SHORT, positive_int, reports_errors
from stampc.diagnostics import Span, StampcError, error

HELP = "replay a refined policy (policy.json) in its concrete world and report success"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("policy", metavar="POLICY.json")
    parser.add_argument("--runs", type=positive_int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--max-steps", type=positive_int, default=500,
                        help="step cap per run (default 500)")
    parser.add_argument("--render", metavar="DIR", help="write PNG frames and an animated GIF "
                        "of the first run here")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    parser.add_argument("--verbose", action="store_true")


def _load_policy(path: Path) -> dict:
    """The policy written by ``stampc refine -o``; I003 when the file is not one."""
    from stampc.inputs import display_name, read_input_text

    shown = display_name(path)
    text = read_input_text(path, shown)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise _not_a_policy(f"not valid JSON: {exc.msg}", Span.point(shown, exc.lineno, exc.colno))
    missing = [k for k in ("files", "world", "scene") if not isinstance(data, dict) or k not in data]
    if not missing and not (isinstance(data["files"], list)
                            and all(isinstance(f, str) for f in data["files"])):
        missing = ["files"]
    if not isinstance(data, dict) or data.get("format") != "stampc-policy" or missing:
        raise _not_a_policy("not a stampc policy file" + (f" (no {', '.join(missing)})"
                                                          if missing else ""), Span.point(shown))
    return data


def _not_a_policy(message: str, span: Span) -> StampcError:
    return StampcError([error("I003", message, span,
                              hint="pass the policy.json written by `stampc refine -o DIR`")])


@reports_errors("execute")
def run(args: argparse.Namespace) -> int:
    from stampc import api
    from stampc.refine.replay import replay
    from stampc.worlds.bindings import resolve_model
    from stampc.worlds.loading import SceneOrigin, open_world

    # bad input (StampcError, exit 1) and unreadable files (OSError, 2): reports_errors
    policy = _load_policy(Path(args.policy))
    try:
        model = api.load_model(policy["files"])
    except FileNotFoundError as exc:
        raise FileNotFoundError(f"{exc} (an input named by {args.policy})") from None
    origin = SceneOrigin(Span.point(args.policy), "in the scene stored in this policy")
    world = open_world(policy["world"], policy["scene"], seed=args.seed, verbose=args.verbose,
                       origin=origin)
    try:
        bindings = resolve_model(model, world.package)
        recorder = _Recorder(Path(args.render), world) if args.render else None
        report = replay(policy, world, bindings.executors, runs=args.runs, seed=args.seed,
                        max_steps=args.max_steps,
                        on_step=recorder.on_step if recorder else None)
        if recorder:
            recorder.finish()
    finally:
        world.close()
    _print(report, args.format)
    on_refined_ok = report.count("success") == report.on_refined - report.count("dead_end")
    return EXIT_DONE if on_refined_ok else EXIT_STOPPED_SHORT


class _Recorder:
    """Frames of the first run, written as PNGs plus one animated GIF."""

    def __init__(self, out: Path, world) -> None:
        self.out = out
        self.frames = []
        self.world = world
        out.mkdir(parents=True, exist_ok=True)
        self.frames.append(world.render())

    def on_step(self, run: int, step: int, world) -> None:
        if run == 0:
            self.frames.append(world.render())

    def finish(self) -> None:
        import imageio.v2 as imageio
        for i, frame in enumerate(self.frames):
            imageio.imwrite(self.out / f"frame_{i:03d}.png", frame)
        imageio.mimsave(self.out / "run.gif", self.frames, duration=0.6, loop=0)
        print(f"wrote {len(self.frames)} frames and run.gif to {self.out}")


def _print(report, fmt: str) -> None:
    summary = {
        "runs": len(report.runs), "success": report.count("success"),
        "failure": report.count("failure"), "dead_end": report.count("dead_end"),
        "unrefined": report.count("unrefined"), "success_rate": report.success_rate,
        "unrefined_rate": report.unrefined_rate,
        "success_rate_on_refined": report.success_rate_on_refined,
        "failures": [r.detail for r in report.runs if r.status == "failure"][:5],
    }
    if fmt == "json":
        print(json.dumps(summary, indent=2))
        return
    print(f"runs {summary['runs']}: success {summary['success']}, failure {summary['failure']}, "
          f"dead end {summary['dead_end']}, unrefined branch reached {summary['unrefined']}")
    print(f"success rate {report.success_rate:.3f}; on refined branches "
          f"{report.success_rate_on_refined:.3f}; unrefined-branch rate {report.unrefined_rate:.3f}")
    for detail in summary["failures"]:
        print(f"  failure: {detail}")
