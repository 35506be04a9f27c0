"""``stampc refine``: anytime refinement of a domain/problem in a concrete world."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from stampc.commands.common import (EXIT_DONE, EXIT_INPUT, EXIT_STOPPED_SHORT, EXIT_USAGE,
                                    add_input_arguments, count, heuristic_weight,
                                    parse_scene_args, positive_float, positive_int, probability,
                                    prune_probability, ratio_or_none, reports_errors,
                                    sigterm_as_interrupt, target_coverage)

if TYPE_CHECKING:
    from stampc.refine import RefineOptions

HELP = "refine an abstract policy with concrete motions (ATM-MDP), anytime"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_input_arguments(parser)
    parser.add_argument("--world", default="plane2d", choices=("plane2d", "pybullet"),
                        help="concrete world backend (default: plane2d)")
    parser.add_argument("--time-limit", type=positive_float, default=60.0, metavar="S",
                        help="stop after S seconds (default 60); stopping below the target "
                             "coverage exits 3 (partial policy written)")
    parser.add_argument("--target-coverage", type=target_coverage, default=1.0, metavar="P",
                        help="stop once this probability mass is refined (default 1.0)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--horizon", type=positive_int, default=None, help="initial horizon")
    parser.add_argument("--update-probability", type=probability, default=0.5,
                        help="probability of UpdateAbstraction mode (default 0.5)")
    parser.add_argument("--explore-probability", type=probability, default=0.05,
                        help="probability of the explore step (default 0.05)")
    parser.add_argument("--ban-everywhere-after", type=count, default=3, metavar="K",
                        help="ban an action in every state once it found no usable sample in "
                             "K states and never worked (default 3; 0: off; docs/refine.md)")
    parser.add_argument("--accept-dead-end-after", type=count, default=3, metavar="K",
                        help="accept a proven dead end that learned facts leave below a node "
                             "once the same abstract state has met it K times, instead of "
                             "re-sampling ancestors again (default 3; 0: never; "
                             "docs/refine.md)")
    parser.add_argument("--heuristic", default="hadd", choices=("hadd", "hff", "hmax", "zero"),
                        help="abstract solver heuristic (default hadd, with an h_FF fallback "
                             "when it finds no way to the goal)")
    parser.add_argument("--weight", type=heuristic_weight, default=1.0,
                        help="heuristic weight of the abstract solver (default 1)")
    parser.add_argument("--prune-probability", type=prune_probability, default=None, metavar="P",
                        help="abstract solves leave outcomes reached with probability below P "
                             "unplanned until refinement gets there (default 0: plan every "
                             "outcome at once; docs/refine.md)")
    parser.add_argument("--no-resample-placers", action="store_true",
                        help="write an obstruction by an object the previous action just "
                             "placed into the abstract state, instead of re-sampling that "
                             "placement first (docs/refine.md)")
    parser.add_argument("--max-resample-loss", type=ratio_or_none, default=1.0, metavar="X",
                        help="re-sample a refined ancestor only while the covered mass below "
                             "it is at most X times the failing path's probability, or once "
                             "the refusals' failed work reaches the work below it (default "
                             "1; 'none': no limit; docs/refine.md)")
    parser.add_argument("--fewest-facts", action="store_true",
                        help="when every sample of a full search fails, write back the "
                             "sample with the fewest violated facts, even one that locks "
                             "an action (docs/refine.md)")
    parser.add_argument("--achievers-first", action="store_true",
                        help="re-sample the steps that made the failing action's "
                             "preconditions true before other ancestors (docs/refine.md)")
    parser.add_argument("--selection", default="unlocked", choices=("unlocked", "path"),
                        help="which uncovered path to refine next: the one that adds the "
                             "most coverage per estimated cost (default), or the paper's "
                             "best path probability per cost (docs/refine.md)")
    parser.add_argument("--solve-work-limit", type=positive_int, default=None, metavar="N",
                        help="cap on one abstract solve's work, in units of about one "
                             "h_add evaluation on the 25-can table (default 100,000: "
                             "about 10 s of CPU there, 15-20 s on 60 cans); unlike a time "
                             "cap, a work cap keeps runs whose solves hit it reproducible "
                             "(docs/refine.md, Determinism)")
    parser.add_argument("--fixed-solve-cap", action="store_true",
                        help="give every abstract solve the whole work cap, instead of "
                             "quartering it after a capped solve that a determinized plan "
                             "answered (docs/refine.md, Solve caps adapt)")
    parser.add_argument("--workers", type=positive_int, default=1, metavar="N",
                        help="concretize up to N independent nodes at a time: this "
                             "process and N-1 worker processes (default 1: no worker); "
                             "reproducible for a given seed and N (docs/refine.md)")
    parser.add_argument("--ray", nargs="?", const="", default=None, metavar="ADDRESS",
                        help="run the workers as Ray actors: on the cluster at ADDRESS "
                             "(host:port, or 'auto'), else Ray's default (RAY_ADDRESS or a "
                             "new local instance); needs the ray extra")
    parser.add_argument("--scene-arg", action="append", default=[], metavar="KEY=VALUE",
                        help="override a scene-builder argument (repeatable)")
    parser.add_argument("-o", "--output", metavar="DIR", help="write policy.json, coverage.csv, "
                        "coverage.svg, policy.dot, policy.svg, summary.json, prg.json here "
                        "(`stampc view DIR` makes an HTML report of them)")
    parser.add_argument("--quiet", action="store_true", help="no progress display")
    parser.add_argument("--verbose", action="store_true", help="let simulators print")


def refine_options(args: argparse.Namespace) -> RefineOptions:
    """The engine's options from the command line."""
    from stampc.refine import RefineOptions
    from stampc.refine.options import PRUNE_PROBABILITY, SOLVE_WORK_LIMIT
    from stampc.solvers import SolverOptions

    return RefineOptions(
        seed=args.seed, time_limit=args.time_limit, target_coverage=args.target_coverage,
        update_probability=args.update_probability,
        explore_probability=args.explore_probability, horizon=args.horizon,
        ban_everywhere_after=args.ban_everywhere_after,
        accept_dead_end_after=args.accept_dead_end_after,
        solve_work_limit=args.solve_work_limit or SOLVE_WORK_LIMIT,
        resample_placers=not args.no_resample_placers,
        learn_lock_free=not args.fewest_facts,
        max_resample_loss=args.max_resample_loss,
        achievers_first=args.achievers_first,
        selection=args.selection,
        adaptive_solve_cap=not args.fixed_solve_cap,
        solver=SolverOptions(heuristic=args.heuristic, weight=args.weight, seed=args.seed,
                             prune_probability=PRUNE_PROBABILITY if args.prune_probability
                             is None else args.prune_probability))


@reports_errors("refine")
def run(args: argparse.Namespace) -> int:
    from stampc import api

    try:
        overrides = parse_scene_args(args.scene_arg)
    except ValueError as exc:
        print(f"stampc refine: {exc}", file=sys.stderr)
        return EXIT_USAGE
    options = refine_options(args)
    # bad input (StampcError, exit 1) and unreadable files (OSError, 2): reports_errors
    with sigterm_as_interrupt(), _progress(args.quiet) as on_event:
        run_ = api.refine_policy(args.files, world=args.world, options=options, on_event=on_event,
                                 scene_overrides=overrides, verbose=args.verbose,
                                 workers=args.workers, ray=args.ray)
    result = run_.result
    print(f"coverage {result.coverage:.4f} (goal {result.goal_mass:.4f} + proven dead ends "
          f"{result.dead_end_mass:.4f}; unrefined {result.unrefined_mass:.4f})  "
          f"goal probability {result.goal_probability:.4f}  "
          f"time {result.wall_time_s:.2f}s  PRG nodes {result.prg_nodes}  "
          f"abstract solves {result.abstract_solves}  ({result.stop_reason})")
    if result.stop_reason == "abstract goal unreachable":
        print("stampc refine: the goal is unreachable in the abstract model from the initial "
              "state (no policy reaches it with probability > 0)", file=sys.stderr)
        return EXIT_INPUT
    if args.output:
        notes = run_.write(Path(args.output))
        print(f"wrote {args.output}/policy.json, coverage.csv, coverage.svg, policy.dot, "
              "policy.svg, summary.json, prg.json" + (", error.txt" if run_.error else ""))
        for note in notes:
            print(f"note: {note}")
    if run_.error is not None:
        where = (f"with {args.output}/error.txt; the partial policy is written" if args.output
                 else "(with -o DIR the traceback is kept in DIR/error.txt)")
        print(f"stampc refine: the run stopped on a bug in stampc ({result.stop_reason}); "
              f"please report it {where}", file=sys.stderr)
        return EXIT_STOPPED_SHORT
    if result.coverage >= args.target_coverage - 1e-9:
        return EXIT_DONE
    print(f"stampc refine: stopped short of the target coverage {args.target_coverage:g} "
          f"({result.stop_reason})" + ("; the partial policy is written" if args.output else ""),
          file=sys.stderr)
    return EXIT_STOPPED_SHORT


class _progress:
    """A live coverage bar (rich) on terminals; milestone lines otherwise."""

    def __init__(self, quiet: bool):
        self.quiet = quiet
        self.progress = None
        self.task = None
        self.last_decile = -1

    def __enter__(self):
        if self.quiet:
            return None
        if sys.stderr.isatty():
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
            self.progress = Progress(
                TextColumn("coverage"), BarColumn(), TextColumn("{task.percentage:>5.1f}%"),
                TextColumn("goal {task.fields[goal]:.3f}  dead end {task.fields[dead]:.3f}  "
                           "refined {task.fields[refined]}  "
                           "PRG {task.fields[prg]}"), TimeElapsedColumn(), transient=False)
            self.progress.start()
            self.task = self.progress.add_task("refine", total=1.0, goal=0.0, dead=0.0,
                                               refined=0, prg=1)
        return self.on_event

    def on_event(self, event) -> None:
        if self.progress is not None:
            self.progress.update(self.task, completed=event.coverage, goal=event.goal_probability,
                                 dead=event.dead_end_mass, refined=event.refined_nodes,
                                 prg=event.prg_nodes)
            return
        decile = int(event.coverage * 10 + 1e-9)
        if decile > self.last_decile or event.kind == "done":
            self.last_decile = decile
            print(f"[{event.time_s:8.2f}s] coverage {event.coverage:.3f}  goal "
                  f"{event.goal_probability:.3f}  dead end {event.dead_end_mass:.3f}  "
                  f"refined {event.refined_nodes}  "
                  f"PRG {event.prg_nodes}  {event.kind}", file=sys.stderr)

    def __exit__(self, *exc) -> None:
        if self.progress is not None:
            self.progress.stop()
