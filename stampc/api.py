"""The Python API: everything the CLI does, as functions.

    import stampc
    model = stampc.compile("examples/cluttered_table/domain.stamp", "examples/cluttered_table/problem.stamp")
    ground = stampc.ground(model)
    solution = stampc.solve(ground)
    run = stampc.refine_policy(["domain.stamp", "problem.stamp"], world="plane2d")

Bad input raises :class:`stampc.StampcError` carrying located diagnostics.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

from stampc.diagnostics import Span, StampcError, error
from stampc.ir.lifted import Model


def _paths(files: Sequence[str | Path]) -> list[Path]:
    """The input files; ``OSError`` for a missing path or a directory, ``StampcError``
    (I001/I002) for a binary, non-UTF-8 or empty file (see :mod:`stampc.inputs`)."""
    from stampc.inputs import check_input_files, existing_file

    return check_input_files([existing_file(Path(f)) for f in files])


def compile(domain: str | Path, problem: str | Path | None = None) -> Model:  # noqa: A001
    """Check and lower ``.stamp`` source(s) to the lifted IR (one file may hold both)."""
    from stampc.ir.lower import lower
    from stampc.semantics.api import load_together

    paths = _paths([domain] + ([problem] if problem is not None else []))
    return lower(load_together(paths))


def import_ppddl(path: str | Path, problem: str | Path | None = None, *,
                 lenient: bool = False) -> Model:
    """Import a PPDDL domain/problem (one file, or domain + problem files).

    ``lenient=True`` accepts what mdp-lib's mini-gpt parser accepts (undeclared
    predicates, problem objects in the domain, repeated declaration variables, no goal)
    with warnings in ``Model.diagnostics`` (docs/ppddl.md).
    """
    from stampc.backends.ppddl.importer import import_ppddl as _import

    paths = _paths([path] + ([problem] if problem is not None else []))
    return _import(paths[0], paths[1] if len(paths) > 1 else None, lenient=lenient)


def load_model(files: Sequence[str | Path], *, lenient: bool = False) -> Model:
    """Dispatch on the file suffix: ``.pddl``/``.ppddl`` import, anything else compiles.
    ``lenient`` applies to PPDDL input (see :func:`import_ppddl`)."""
    paths = _paths(files)
    if not paths or len(paths) > 2:
        raise StampcError([error("E001", f"expected 1 or 2 input files, got {len(paths)}",
                                 Span.point("<command line>"))])
    if paths[0].suffix.lower() in (".pddl", ".ppddl"):
        return import_ppddl(*paths, lenient=lenient)
    return compile(*paths)


def ground(model: Model, *, conflicting_effects: str = "add-wins"):
    """The grounded model. ``conflicting_effects`` says which wins when one outcome adds
    and deletes the same fact: ``"add-wins"`` (PDDL, MDPSim) or ``"delete-wins"``
    (mdp-lib's mini-gpt); either way a G203 warning names the rule applied."""
    from stampc.ir.ground import ground as _ground
    return _ground(model, conflicting_effects=conflicting_effects)


def solve(ground_model, options=None, **kwargs):
    from stampc.solvers import SolverOptions, solve as _solve
    return _solve(ground_model, options or SolverOptions(), **kwargs)


def to_ppddl(model: Model, *, keep_derived: bool = False) -> tuple[str, str]:
    """PPDDL (domain, problem) text (see ``stampc.backends.ppddl.model_export``);
    derived predicates are compiled away unless ``keep_derived``."""
    from stampc.backends.ppddl.model_export import model_to_ppddl
    return model_to_ppddl(model, keep_derived=keep_derived)


def refine_policy(files: Sequence[str | Path], *, world: str = "plane2d", options=None,
           on_event: Callable | None = None, scene_overrides: Mapping[str, Any] | None = None,
           verbose: bool = False, workers: int = 1, ray: str | None = None):
    """Compile, ground, open the world and run ATM-MDP; returns a ``RefinedPolicy``.

    ``workers`` > 1 concretizes that many nodes at a time in worker processes; ``ray``
    (a Ray address, or "" for Ray's default) runs those workers as Ray actors
    (``stampc.refine.parallel``, docs/refine.md "Parallel refinement")."""
    from stampc.provenance import builder_source, record
    from stampc.refine import RefineOptions, run_refinement
    from stampc.worlds.bindings import resolve_model
    from stampc.worlds.loading import load_scene, open_world, scene_origin

    options = options or RefineOptions()
    paths = _paths(files)
    model = load_model(paths)
    gm = ground(model)
    scene = load_scene(model.problem, paths[-1].parent, scene_overrides)
    w = open_world(world, scene, seed=options.seed, verbose=verbose,
                   origin=scene_origin(model.problem, paths[-1].parent), visuals=False)
    try:
        bindings = resolve_model(model, w.package)
        meta = {"domain": model.domain.name, "problem": model.problem.name, "world": world,
                "files": [str(p.resolve()) for p in paths], "scene": scene,
                "provenance": record(paths, world, scene, builder_source(
                    model.problem.scene, paths[-1].parent, scene_overrides))}
        pool = None
        if workers > 1:  # the engine is one of the workers: N - 1 more processes
            from stampc.refine.workers import WorkerSpec
            pool = _open_pool(WorkerSpec(tuple(meta["files"]), world, scene, options.seed,
                                         _build_worker, verbose), workers - 1, ray)
        try:
            return run_refinement(gm, w, bindings, options, on_event=on_event, meta=meta,
                                  pool=pool, backend="local" if ray is None else "ray")
        finally:
            if pool is not None:
                pool.close()
    finally:
        w.close()


def _build_worker(spec):
    """A refinement worker's (ground model, world, bindings), rebuilt from the same stamp
    files, scene dict and seed as the engine's (``stampc.refine.workers``)."""
    from stampc.worlds.bindings import resolve_model
    from stampc.worlds.loading import open_world

    model = load_model(_paths(spec.files))
    world = open_world(spec.world, dict(spec.scene), seed=spec.seed, verbose=spec.verbose,
                       visuals=False)
    return ground(model), world, resolve_model(model, world.package)


def _open_pool(spec, size: int, ray: str | None):
    """``size`` local worker processes, or Ray actors when ``ray`` is an address ("" for
    Ray's default: the cluster named by RAY_ADDRESS, else a new local one). They start
    with the first batch that has work for them; with STAMPC_WAIT_FOR_WORKERS=1 that
    batch waits for them (tests: the workers then answer every batch's other tasks)."""
    wait = os.environ.get("STAMPC_WAIT_FOR_WORKERS") == "1"
    if ray is None:
        from stampc.refine.workers import LocalPool
        return LocalPool(spec, size, wait)
    from stampc.refine.ray_backend import RayPool  # the only module that imports Ray
    return RayPool(spec, size, ray, wait)
