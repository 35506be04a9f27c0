"""``stampc solve``: solve the abstract SSP of a stamp or PPDDL problem."""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import asdict
from pathlib import Path

from stampc.commands.common import (EXIT_DONE, EXIT_STOPPED_SHORT, add_import_options, count,
                                    heuristic_weight, positive_float, positive_int,
                                    print_warnings, reports_errors)
from stampc.diagnostics import StampcError

#: Seconds the simulation may run past ``--time-limit`` (counted from the start).
SIMULATION_GRACE_S = 0.5

HELP = "solve the abstract SSP (LAO*, LRTDP or VI) and write the policy"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from stampc.solvers import ALGORITHMS, HEURISTICS

    parser.add_argument("files", nargs="+", metavar="FILE",
                        help="DOMAIN [PROBLEM] (.stamp), one .pddl file (problem-only files find "
                             "domain.pddl beside them), or domain.pddl problem.pddl")
    parser.add_argument("--algorithm", choices=ALGORITHMS, default="lao")
    parser.add_argument("--heuristic", choices=HEURISTICS, default="hmax",
                        help="zero, hmax (admissible), hadd or hff (INADMISSIBLE, faster)")
    parser.add_argument("--weight", type=heuristic_weight, default=1.0,
                        help="heuristic weight (weighted LAO*; default 1)")
    parser.add_argument("--epsilon", type=positive_float, default=1e-4,
                        help="target gap between the certified lower and upper bounds on the "
                             "optimal cost (relative: upper - lower <= eps * upper; see "
                             "--absolute-gap); without bounds, the Bellman residual")
    parser.add_argument("--absolute-gap", action="store_true",
                        help="stop when upper - lower <= eps (default: relative gap)")
    parser.add_argument("--no-bounds", action="store_true",
                        help="one run to Bellman residual eps, no certified bounds")
    parser.add_argument("--dead-end-cost", type=positive_float, default=500.0,
                        help="give-up cost D: dead ends cost D and every Q-value is capped at D")
    parser.add_argument("--unit-cost", action="store_true",
                        help="every action costs 1, ignoring declared costs/rewards")
    parser.add_argument("--horizon", type=positive_int, default=None,
                        help="finite horizon (time-indexed values; default: the problem's own)")
    parser.add_argument("--time-limit", type=positive_float, default=None,
                        help="seconds; stopping before convergence exits 3 (policy written)")
    parser.add_argument("--seed", type=int, default=0, help="seed for LRTDP and simulation")
    parser.add_argument("--no-symmetry", action="store_true",
                        help="do not merge states that differ by a permutation of "
                             "interchangeable objects (default: merged, exact; the policy "
                             "graph then lists one state per orbit)")
    parser.add_argument("--no-relevance", action="store_true",
                        help="do not clear the facts no reachable action reads from the "
                             "states searched (default: cleared, exact; see "
                             "docs/solvers.md)")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    parser.add_argument("-o", "--output", metavar="FILE", help="write the policy as JSON")
    parser.add_argument("--dot", metavar="FILE", help="write the policy graph as Graphviz DOT")
    parser.add_argument("--simulate", type=count, default=0, metavar="N",
                        help="simulate N runs of the policy (seeded by --seed)")
    parser.add_argument("--max-steps", type=positive_int, default=1000,
                        help="step cap per simulated run")
    add_import_options(parser)


def _report(args, solution, bounds, sim, parse_ground_s: float, total_s: float,
            cpu_s: float) -> dict:
    from stampc.solvers.export import summary

    out = {"files": args.files, **summary(solution), "parse_ground_s": parse_ground_s,
           "total_time_s": total_s, "cpu_time_s": cpu_s}
    if bounds is not None:
        out.update(bounds.as_json())
    if sim is not None:
        out["simulation"] = asdict(sim)
    return out


def _print_text(report: dict) -> None:
    print(f"expected cost     {report['expected_cost']:.6f}")
    print(f"goal probability  {report['goal_probability']:.6f}")
    if "upper_bound" in report:
        _print_bounds(report)
    print(f"states expanded   {report['states_expanded']} "
          f"(generated {report['states_generated']})")
    print(f"time              solve {report['solve_time_s']:.3f} s, parse+ground "
          f"{report['parse_ground_s']:.3f} s, total {report['total_time_s']:.3f} s")
    if not report["converged"]:
        print("warning: not converged (time limit reached before convergence, or the gap "
              "stayed above the target); values are bounds, see above")
    sim = report.get("simulation")
    if sim:
        lo, hi = sim["cost_ci95"]
        glo, ghi = sim["goal_rate_ci95"]
        print(f"simulation        {sim['runs']} runs (seed {sim['seed']}): cost "
              f"{sim['mean_cost']:.4f} [95% CI {lo:.4f}, {hi:.4f}], goal rate "
              f"{sim['goal_rate']:.4f} [{glo:.4f}, {ghi:.4f}]")


def _print_bounds(report: dict) -> None:
    if report["lower_bound"] is None:
        print(f"policy cost       {report['upper_bound']:.6f} (evaluated; inadmissible "
              f"mode: no optimality claim), goal probability "
              f"{report['policy_goal_probability']:.6f}")
        return
    print(f"bounds on V*      [{report['lower_bound']:.6f}, {report['upper_bound']:.6f}] "
          f"gap {report['gap']:.3g} ({report['gap_mode']}: {report['relative_gap']:.3g} "
          f"relative){'' if report['certified'] else ' NOT certified'}")


@reports_errors("solve")
def run(args: argparse.Namespace) -> int:
    from stampc import api
    from stampc.solvers import SolverOptions, check_options, simulate, solve
    from stampc.solvers.export import write_policy_dot, write_policy_json
    from stampc.inputs import check_input_files, existing_file

    options = SolverOptions(algorithm=args.algorithm, heuristic=args.heuristic,
                            epsilon=args.epsilon, dead_end_cost=args.dead_end_cost,
                            unit_cost=args.unit_cost, horizon=args.horizon,
                            time_limit=args.time_limit, seed=args.seed, weight=args.weight,
                            symmetry=not args.no_symmetry,
                            relevance=not args.no_relevance)
    start, cpu_start = time.perf_counter(), time.process_time()
    try:
        check_options(options)
    except StampcError as exc:
        for d in exc.diagnostics:
            print(f"error: {d.message}" + (f" ({d.hint})" if d.hint else ""), file=sys.stderr)
        return 2
    if not 1 <= len(args.files) <= 2:
        print(f"stampc solve: error: expected DOMAIN [PROBLEM] or one file, got "
              f"{len(args.files)} files", file=sys.stderr)
        return 2
    check_input_files([existing_file(Path(f)) for f in args.files])  # I/O: exit 2, I00x: 1
    # StampcError: exit 1 (reports_errors); warnings (lenient import, grounding) on stderr
    lifted = api.load_model(args.files, lenient=args.lenient)
    model = api.ground(lifted, conflicting_effects=args.conflicting_effects)
    print_warnings(lifted.diagnostics + model.diagnostics)
    parse_ground_s = time.perf_counter() - start
    bounds = None
    if args.no_bounds:
        solution = solve(model, options)
    else:
        from stampc.solvers.bounds import solve_bounded
        solution, bounds = solve_bounded(model, options, relative=not args.absolute_gap)
    total_s = time.perf_counter() - start
    cpu_s = time.process_time() - cpu_start  # robust to other load on a shared machine
    sim = None
    if args.simulate:
        # with a time limit the simulation gets SIMULATION_GRACE_S past it, then reports
        # the runs done (an unfinished policy is simulated with lookahead searches)
        deadline = (None if args.time_limit is None
                    else start + args.time_limit + SIMULATION_GRACE_S)
        sim = simulate(model, solution, runs=args.simulate, seed=args.seed,
                       max_steps=args.max_steps, deadline=deadline)
        if sim.stopped_at_deadline:
            print(f"note: simulation stopped at the time limit after {sim.runs} of "
                  f"{args.simulate} runs", file=sys.stderr)
        if not sim.runs:
            sim = None
    report = _report(args, solution, bounds, sim, parse_ground_s, total_s, cpu_s)
    try:
        if args.output:
            write_policy_json(args.output, model, solution)
        if args.dot:
            note = write_policy_dot(args.dot, model, solution)
            if note:
                print(f"note: {note}", file=sys.stderr)
    except OSError as exc:
        print(f"error: cannot write output: {exc}", file=sys.stderr)
        return 2
    if args.format == "json":
        print(json.dumps(report))
    else:
        _print_text(report)
    return EXIT_DONE if solution.converged else EXIT_STOPPED_SHORT
