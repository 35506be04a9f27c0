"""``bench/paper.py --ray [ADDRESS]``: the benchmark's runs as Ray tasks on a cluster.

Each run is one task (one CPU) that calls ``paper.run_job`` — the same function the local
``ProcessPoolExecutor`` calls — so a run's record and output folder are the same on either
backend; the records come back in job order. The tasks import ``paper`` (and the
examples' generators) from this checkout: the task's PYTHONPATH names the repository and
``bench/`` (Ray's ``runtime_env``), so every node needs the checkout at the same path, and
the output folder (``--out``) should be on a file system the nodes share.
"""

from __future__ import annotations

import os
from dataclasses import asdict
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]


def _run(job: dict[str, Any]) -> dict[str, Any]:
    import paper  # on the worker: from the runtime_env's PYTHONPATH
    from paper_classes import CLASSES

    cls = next(c for c in CLASSES if c.name == job["cls"])
    return asdict(paper.run_job(paper.Job(cls, job["run"], job["seed"], job["timeout_s"],
                                          job["out_dir"], tuple(job["refine_args"]))))


def run_on_ray(jobs: list, address: str) -> list[dict[str, Any]]:
    """The records (as dicts) of ``jobs`` run as Ray tasks, in job order."""
    import ray

    path = os.pathsep.join(filter(None, [str(REPO), str(REPO / "bench"),
                                         os.environ.get("PYTHONPATH")]))
    ray.init(address=address or None, include_dashboard=False, log_to_driver=False,
             runtime_env={"env_vars": {"PYTHONPATH": path}})
    try:
        task = ray.remote(num_cpus=1)(_run)
        refs = [task.remote({"cls": j.cls.name, "run": j.run, "seed": j.seed,
                             "timeout_s": j.timeout_s, "out_dir": j.out_dir,
                             "refine_args": list(j.refine_args)}) for j in jobs]
        return ray.get(refs)
    finally:
        ray.shutdown()
