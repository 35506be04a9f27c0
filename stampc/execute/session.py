"""``execute_file``: everything ``stampc execute`` does, as one function.

Read the policy (:mod:`.policyfile`), check its provenance (:mod:`.provenance`), load the
model from the verified inputs, build the truth model (scene ``meta.truth`` overridden by
``--truth``), open the world on the stored scene, bind the goal check and the re-check,
run, and return the :class:`~.report.ExecutionReport`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Sequence

from stampc.diagnostics import Span
from stampc.execute.report import ExecutionReport


def execute_file(path: Path, *, runs: int, seed: int, max_steps: int = 500,
                 truth: Sequence[str] | Mapping[str, Any] = (), verbose: bool = False,
                 physics: bool = True, recorder: Any = None, memo: bool = True,
                 on_memo: Any = None) -> ExecutionReport:
    """Execute the policy at ``path``; ``recorder`` (:class:`.frames.Recorder`) records
    the first run; ``physics`` lets PyBullet objects settle under gravity; ``memo``
    replays steps already computed from the same concrete state (:mod:`.memo`), and
    ``on_memo(memo)`` sees the memo at the end (its hit and miss counts)."""
    from stampc import api
    from stampc.execute.goals import goal_check_for
    from stampc.execute.memo import StepMemo
    from stampc.execute.policyfile import load_policy
    from stampc.provenance import verify
    from stampc.execute.recheck import recheck_for
    from stampc.execute.runner import execute_policy
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
    world = open_world(policy["world"], scene, seed=seed, verbose=verbose, origin=origin,
                       visuals=recorder is not None)
    try:
        bindings = resolve_model(model, world.package)
        hooks = _hooks(world, recorder, physics, goal_check_for(world, scene, files[-1].parent),
                       recheck_for(world))
        if recorder is not None:
            recorder.start(world)
        steps = StepMemo() if memo else None
        results = execute_policy(policy, world, bindings.executors, true_model, runs=runs,
                                 seed=seed, max_steps=max_steps, hooks=hooks, memo=steps,
                                 fresh_runs=1 if recorder is not None else 0)
        if on_memo is not None and steps is not None:
            on_memo(steps)
    finally:
        world.close()
    return ExecutionReport(results, predicted_success(policy, true_model),
                           float(policy.get("coverage", 0.0)),
                           float(policy.get("goal_probability", 0.0)),
                           {k: float(v) for k, v in overrides.items()})


def _hooks(world: Any, recorder: Any, physics: bool, goal_check, recheck):
    """The runner's hooks: physics settling (PyBullet) and the recorder's frames."""
    from stampc.execute.runner import Hooks

    settle = None
    if physics and hasattr(world, "body"):
        from stampc.worlds.pybullet.physics import Physics
        settle = Physics(world, on_frame=recorder.frame if recorder is not None else None)

    def before(w: Any, action: Any) -> None:
        if recorder is not None:
            recorder.motion(w, action)
        if settle is not None:
            settle.before_action(w, action)

    return Hooks(goal_check=goal_check, recheck=recheck, before_action=before,
                 after_action=settle.after_action if settle is not None else None,
                 on_step=recorder.on_step if recorder is not None else None,
                 on_run_start=recorder.on_run_start if recorder is not None else None)
