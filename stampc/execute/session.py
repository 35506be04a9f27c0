"""``execute_file``: everything ``stampc execute`` does, as one function.

Read the policy (:mod:`.policyfile`), check its provenance (:mod:`.provenance`), load the
model from the verified inputs, build the truth model (scene ``meta.truth`` overridden by
``--truth``), open the world on the stored scene, bind the goal check and the re-check,
run, and return the :class:`~.report.ExecutionReport`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

from stampc.diagnostics import Span
from stampc.execute.report import ExecutionReport


def execute_file(path: Path, *, runs: int, seed: int, max_steps: int = 500,
                 truth: Sequence[str] | Mapping[str, Any] = (), verbose: bool = False,
                 on_step: Callable[[int, Any], None] | None = None,
                 on_open: Callable[[Any], None] | None = None) -> ExecutionReport:
    from stampc import api
    from stampc.execute.goals import goal_check_for
    from stampc.execute.policyfile import load_policy
    from stampc.execute.provenance import verify
    from stampc.execute.recheck import recheck_for
    from stampc.execute.runner import Hooks, execute_policy
    from stampc.execute.truth import build_truth, parse_overrides, predicted_success
    from stampc.worlds.bindings import resolve_model
    from stampc.worlds.loading import SceneOrigin, open_world

    pf = load_policy(path)
    policy = pf.data
    files = verify(policy, path, pf.text)
    model = api.load_model(files)
    scene = policy["scene"]
    meta = scene.get("meta") if isinstance(scene.get("meta"), Mapping) else {}
    overrides = parse_overrides(meta.get("truth", {}), Span.point(str(path)))
    overrides.update(parse_overrides(truth, Span.point("<command line>")))
    true_model = build_truth(model, overrides, Span.point("<command line>" if truth
                                                          else str(path)))
    origin = SceneOrigin(Span.point(str(path)), "in the scene stored in this policy")
    world = open_world(policy["world"], scene, seed=seed, verbose=verbose, origin=origin)
    try:
        bindings = resolve_model(model, world.package)
        hooks = Hooks(goal_check=goal_check_for(world, scene, path.parent),
                      recheck=recheck_for(world), on_step=on_step)
        if on_open is not None:
            on_open(world)
        results = execute_policy(policy, world, bindings.executors, true_model, runs=runs,
                                 seed=seed, max_steps=max_steps, hooks=hooks)
    finally:
        world.close()
    return ExecutionReport(results, predicted_success(policy, true_model),
                           float(policy.get("coverage", 0.0)),
                           float(policy.get("goal_probability", 0.0)),
                           {k: float(v) for k, v in overrides.items()})
