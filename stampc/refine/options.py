"""Public types of the refinement engine: options, progress events, results."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

from stampc.diagnostics import Diagnostic, Span, StampcError, error
from stampc.solvers import SolverOptions

#: Abstract solves plan every outcome the policy reaches with at least this probability
#: (from the solve's root); rarer ones stay horizon leaves until refinement gets there.
#: Off by default: it makes each solve cheaper but the run slower (cluttered-20 seed 3:
#: coverage 0.72 with 0.05 against 0.97 without at 300 s; docs/refine.md).
PRUNE_PROBABILITY = 0.0
#: The abstract solver's default work cap per solve (``Search.work`` units): about 10 s
#: of CPU of 25-can re-solves on the benchmark machine, 15-20 s on 60 cans
#: (stampc/solvers/core.py)
SOLVE_WORK_LIMIT = 100_000
#: ... except in the continuation of a solve that hit its cap (cluttered-40 seed 0 at
#: 180 s: coverage 0.47 with partial solves, 0.0 with full ones that never fit)
TIMEOUT_PRUNE_PROBABILITY = 0.05
#: path selection rules (``RefineOptions.selection``)
SELECTIONS = ("unlocked", "path")


@dataclass(frozen=True)
class RefineOptions:
    seed: int = 0
    time_limit: float | None = 60.0
    target_coverage: float = 1.0
    #: probability of choosing UpdateAbstraction (quick sample, learn, replan) over a full
    #: backtracking Concretization search when refining a node (Alg. 1, line 6)
    update_probability: float = 0.5
    #: probability of the explore step (replace the replanned action by a random one);
    #: non-zero keeps the search probabilistically complete (Thm. 2)
    explore_probability: float = 0.05
    #: initial horizon; None: the problem's horizon, else grown from 8 until the goal
    #: has probability > 0
    horizon: int | None = None
    max_horizon: int = 512
    #: refinement attempts at one node before the action is banned there and replanned
    max_attempts: int = 3
    #: an action banned (attempts exhausted) in this many abstract states that never
    #: worked anywhere is banned in every state; lifted when a replan finds no way to the
    #: goal without it. 0 turns this off. Default 3: per-state bans alone let an arm that
    #: never reaches a feed be tried in every feed outcome of a tall tower, and the
    #: explore steps of those failures re-sampled puts far up the tower (Keva tower-24
    #: seed 0: 0.586 after 300 s, solved in 88 s with 3; docs/refine.md).
    ban_everywhere_after: int = 3
    #: learned facts that leave only proven dead ends below a node are taken for an
    #: unlucky sample, and ancestors re-sampled, until the same abstract state (facts
    #: written) has met them this many times; then the dead end is accepted — after a
    #: full search over the node's samples when the last try was a quick one. 0: never.
    #: Without it a drifted UAV with no battery left for any flight was re-sampled for
    #: good (aircraft seed 5: 621 re-draws of the first flight, 0.979 after 600 s).
    accept_dead_end_after: int = 3
    #: how many ancestors up a replan without actions banned everywhere is tried (the
    #: choice that led to them, e.g. which arm took the plank, lies above the failure)
    replan_above: int = 6
    #: iterative-broadening DFS over the PRG: initial breadth and its increment
    breadth: int = 5
    breadth_step: int = 5
    max_iterations: int = 100_000
    #: cap on one abstract (re)solve's work (``Search.work``, about one unit per
    #: heuristic evaluation; None: none); a solve that hits it returns its best partial
    #: policy (a replan without a way to the goal then backtracks). A work cap stops a
    #: solve at the same point on any machine and under any load, so runs whose solves
    #: hit it stay reproducible for a seed (docs/refine.md, "Determinism").
    solve_work_limit: int | None = SOLVE_WORK_LIMIT
    #: cap on one abstract (re)solve, in seconds: a guard for machines much slower (or
    #: more loaded) than the work cap assumes (where it binds, the run depends on the
    #: machine's speed; docs/refine.md, "Determinism")
    solve_time_limit: float = 30.0
    #: after a capped solve that a determinized plan answered, the next solve gets a
    #: quarter of the cap (down to 1/16); a solve converging within its cap doubles it
    #: back. Where the model outgrew the cap, every update no longer pays the whole cap
    #: before its plan (cluttered-40 seed 3: ~19 s per update; docs/refine.md, "Solve caps adapt")
    adaptive_solve_cap: bool = True
    #: a capped solve is continued this many times, doubling its cap, before its
    #: partial policy is used (a timeout is not a verdict on the horizon)
    solve_retries: int = 2
    #: those continuations plan only outcomes reached with at least this probability
    #: (partial solves, docs/refine.md): where a full contingent solve does not fit its
    #: cap, the likely branches get a policy now and the rare ones when selected
    timeout_prune_probability: float = TIMEOUT_PRUNE_PROBABILITY
    #: a capped solve first tries a greedy plan on the all-outcomes determinization
    #: (FF-Replan's planner; stampc/solvers/determinized.py): its path is refined now and
    #: the outcomes off it are planned when refinement gets there. The retries above
    #: follow only when no plan is found within the cap.
    timeout_plan: bool = True
    #: backtracking over refined ancestors (Alg. 1): how often one node's generator
    #: values may be re-drawn because an action below it found no usable sample
    max_resamples: int = 3
    #: ... and, when set, only while the covered mass below it (its path probability ×
    #: the coverage of its subtree) is at most this many times the failing path's
    #: probability: a re-sample discards every refinement below the node (cluttered-25
    #: seed 5 re-drew a placement with 0.375 of the mass covered below it). Otherwise the
    #: failure is learned, explored or broadened as with no ancestor to re-sample; where
    #: the failure left no way to the goal, a refusal is rented until the failed work
    #: behind it reaches the work below the ancestor (``Backtracking._affordable``).
    #: None: no limit. 1.0 solved cluttered-20 seed 3 (996 s) and raised cluttered-25
    #: seed 5 from 0.9087 to 0.9706, every other paper run solved (docs/benchmarks.md).
    max_resample_loss: float | None = 1.0
    #: a fact learned true that names an object the failing node's nearest refined
    #: ancestor put at a value it sampled (a can just placed in the way) re-samples that
    #: ancestor, up to ``max_resamples`` times, instead of being written into the
    #: abstract state (docs/refine.md, "Placements in the way")
    resample_placers: bool = True
    #: of the facts a failed full search could write back (one set per sample tried),
    #: one that leaves the goal a relaxed way and locks no action (an obstruction by an
    #: object whose own action the failing one's object already obstructs), then the
    #: fewest facts, then the lowest h_add (stampc/refine/learning.py): cluttered-60
    #: seed 9 accepted a false dead end on two such locks. Off: the fewest facts only.
    learn_lock_free: bool = True
    #: a re-sample with no ancestor generating a value of the failing action is taken
    #: among the achievers of its preconditions first (docs/refine.md). Off by default:
    #: it solved Keva tower-24 seed 9 (0.0002 → solved in 92 s; with the keva `places`
    #: predicate, tower-24 10/10 with it, 9/10 without) but lost cluttered-20 seed 3
    #: (solved in 422 s → 0.9979 after 2,400 s)
    achievers_first: bool = False
    #: which uncovered path is refined next: "unlocked" — the one whose refinement adds
    #: the most coverage per estimated cost (stampc/refine/unlocking.py); "path" — the
    #: paper's best path probability per cost (selection.py), which takes a branch whose
    #: continuations are already refined no earlier than a lone path of its probability
    selection: str = "unlocked"
    #: memory bound of the abstract solver's warm tables (states): a re-solve whose
    #: previous tables hold more starts cold (≈2.5 KB per state on the cluttered table)
    warm_state_limit: int | None = 400_000
    #: UpdateAbstraction also writes back facts learned elsewhere in the run that still
    #: hold in the node's concrete state (re-evaluated there; stampc/refine/recall.py)
    recall_learned: bool = True
    #: The abstract solver used for every (re)plan: LAO* with h_add — inadmissible, but
    #: its strong guidance keeps the hundreds of re-solves of a run fast (a 25-can state
    #: with two learned obstructions: 13 expansions, where h_max needs ~2,400); the policy
    #: need not be cost-optimal to be refined (heuristic="hmax" gives optimal policies).
    solver: SolverOptions = field(default_factory=lambda: SolverOptions(
        heuristic="hadd", prune_probability=PRUNE_PROBABILITY))
    #: Tried when ``solver`` finds no way to the goal: h_add double-counts shared
    #: sub-goals and can overestimate long chains (a 12-level Keva tower) beyond the
    #: dead-end cost; the relaxed-plan heuristic h_FF does not.
    fallback_solver: SolverOptions | None = field(
        default_factory=lambda: SolverOptions(heuristic="hff"))


def check_refine_options(options: RefineOptions) -> None:
    """Raise ``StampcError`` (R001–R003) for limits no run can honour: the API refuses
    what the CLI refuses (``time_limit`` 0, negative or nan; ``inf`` means none)."""
    span = Span.point("<options>")
    problems = []
    limit = options.time_limit
    if limit is not None and not (limit > 0 and not math.isnan(limit)):
        problems.append(error("R001", f"time limit must be positive, got {limit}", span,
                              hint="use None for no limit"))
    if not 0.0 < options.target_coverage <= 1.0:
        problems.append(error("R002", "target coverage must be within (0, 1], got "
                              f"{options.target_coverage}", span))
    for name in ("update_probability", "explore_probability"):
        value = getattr(options, name)
        if not 0.0 <= value <= 1.0:
            problems.append(error("R003", f"{name} must be within [0, 1], got {value}", span))
    if not 0.0 <= options.timeout_prune_probability < 1.0:
        problems.append(error("R003", "timeout_prune_probability must be within [0, 1), got "
                              f"{options.timeout_prune_probability}", span))
    if options.accept_dead_end_after < 0:
        problems.append(error("R003", "accept_dead_end_after must be 0 (never) or positive, "
                              f"got {options.accept_dead_end_after}", span))
    if options.ban_everywhere_after < 0:
        problems.append(error("R003", "ban_everywhere_after must be 0 (off) or positive, "
                              f"got {options.ban_everywhere_after}", span))
    if options.solve_work_limit is not None and options.solve_work_limit < 1:
        problems.append(error("R003", "solve_work_limit must be positive or None, got "
                              f"{options.solve_work_limit}", span))
    if not options.solve_time_limit > 0:
        problems.append(error("R003", "solve_time_limit must be positive, got "
                              f"{options.solve_time_limit}", span))
    if options.warm_state_limit is not None and options.warm_state_limit < 1:
        problems.append(error("R003", "warm_state_limit must be positive or None, got "
                              f"{options.warm_state_limit}", span))
    loss = options.max_resample_loss
    if loss is not None and not loss >= 0:
        problems.append(error("R003", f"max_resample_loss must be 0 or more, or None, got "
                              f"{loss}", span))
    if options.selection not in SELECTIONS:
        problems.append(error("R003", f"selection must be one of {', '.join(SELECTIONS)}, got "
                              f"{options.selection!r}", span))
    if options.horizon is not None and options.horizon < 1:
        problems.append(error("R003", f"horizon must be at least 1, got {options.horizon}",
                              span))
    if problems:
        raise StampcError(problems)


@dataclass(frozen=True)
class ProgressEvent:
    time_s: float
    coverage: float
    goal_probability: float
    refined_nodes: int
    prg_nodes: int
    abstract_solves: int
    #: "start" | "refined" | "retry" | "update" | "explore" | "ban" | "extend" |
    #: "give-up" | "resample" | "backtrack" | "done"
    kind: str
    detail: str = ""
    #: refined mass ending in proven dead ends (coverage = goal_probability + this)
    dead_end_mass: float = 0.0


@dataclass(frozen=True)
class RefineResult:
    coverage: float
    goal_probability: float
    abstract_goal_probability: float
    wall_time_s: float
    time_to_coverage: dict[str, float | None]
    prg_nodes: int
    refined_paths: int
    refined_nodes: int
    abstract_solves: int
    seed: int
    stop_reason: str
    events: tuple[ProgressEvent, ...]
    diagnostics: tuple[Diagnostic, ...] = ()
    #: the probability mass split: goal_mass (refined paths to the goal, = goal
    #: probability) + dead_end_mass (refined paths to *proven* dead ends) = coverage;
    #: unrefined_mass = 1 - coverage (unrefined, horizon or given-up leaves)
    goal_mass: float = 0.0
    dead_end_mass: float = 0.0
    unrefined_mass: float = 1.0
    #: abstract solves that hit their cap (work or time); generator values re-drawn by
    #: backtracking
    solver_timeouts: int = 0
    resamples: int = 0
    #: facts learned elsewhere and written back at UpdateAbstraction (recall.py)
    recalled_facts: int = 0
    #: counters of a parallel run (``--workers N``, N > 1; ``stampc.refine.parallel``)
    parallel: dict | None = None


def options_record(options: RefineOptions) -> dict[str, Any]:
    """``options`` as plain JSON values (sets sorted into lists, non-finite numbers as
    strings), written beside a run's results so that the settings that produced them
    travel with them (summary.json, policy.json)."""
    return _plain(asdict(options))


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (set, frozenset)):
        return sorted((_plain(v) for v in value), key=repr)
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return value
