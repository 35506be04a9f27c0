"""Ray backend: a local Ray cluster on 127.0.0.1 (a head node with 2 CPUs: two worker
processes) runs a refinement and a small benchmark; both match the local pool's results.
Marked ``ray`` (not in the default run): ``python -m pytest -m ray`` (.ci/run runs it)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.ray

REPO = Path(__file__).resolve().parents[2]
SHELF = [REPO / "tests" / "refine" / "data" / n for n in ("shelf.stamp", "shelf5.stamp")]


@pytest.fixture(scope="module")
def cluster():
    """A head node on 127.0.0.1 started (and stopped) by this process; its GCS address.
    Ray is imported here, so that the default run collects this file without it."""
    import ray

    ray.init(num_cpus=2, _node_ip_address="127.0.0.1", include_dashboard=False,
             log_to_driver=False)
    try:
        yield ray.get_runtime_context().gcs_address
    finally:
        ray.shutdown()


def _env() -> dict[str, str]:
    """This checkout first; the first batch with work waits for the actors (else the
    engine answers the batches itself while they start, and a short run never uses them)."""
    return {**os.environ, "STAMPC_WAIT_FOR_WORKERS": "1", "PYTHONPATH": os.pathsep.join(
        filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}


def _refine(out: Path, *extra: str) -> dict:
    cmd = [sys.executable, "-m", "stampc", "refine", *map(str, SHELF), "--quiet", "--seed", "1",
           "--workers", "3", "--time-limit", "120", "-o", str(out), *extra]
    proc = subprocess.run(cmd, cwd=REPO, env=_env(), capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return {name: json.loads((out / name).read_text()) for name in ("policy.json", "summary.json")}


def test_refine_on_ray_matches_the_local_pool(cluster, tmp_path):
    on_ray = _refine(tmp_path / "ray", "--ray", cluster)
    local = _refine(tmp_path / "local")
    assert on_ray["summary.json"]["parallel"]["backend"] == "ray"
    assert local["summary.json"]["parallel"]["backend"] == "local"
    assert on_ray["summary.json"]["coverage"] == local["summary.json"]["coverage"] == 1.0
    assert on_ray["policy.json"]["nodes"] == local["policy.json"]["nodes"]
    counters = ("batches", "dispatched", "integrated", "discarded")
    assert ({k: on_ray["summary.json"]["parallel"][k] for k in counters}
            == {k: local["summary.json"]["parallel"][k] for k in counters})
    stats = on_ray["summary.json"]["parallel"]
    assert stats["critical_s"] < stats["worker_busy_s"]  # the actors answered tasks


def _bench(out: Path, *extra: str) -> list[dict]:
    cmd = [sys.executable, str(REPO / "bench" / "paper.py"), "--classes", "^cluttered-15$",
           "--runs", "2", "--timeout", "120", "--out", str(out), *extra]
    proc = subprocess.run(cmd, cwd=REPO, env=_env(), capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    return json.loads((out / "runs.json").read_text())


def test_small_benchmark_on_ray_matches_the_local_pool(cluster, tmp_path):
    on_ray = _bench(tmp_path / "ray", "--ray", cluster)
    local = _bench(tmp_path / "local", "--jobs", "2")
    keys = ("cls", "run", "seed", "status", "coverage", "goal_probability", "work")
    assert [{k: r[k] for k in keys} for r in on_ray] == [{k: r[k] for k in keys} for r in local]
    assert [r["status"] for r in on_ray] == ["solved", "solved"]


def test_an_address_where_no_cluster_answers_is_R207(tmp_path):
    cmd = [sys.executable, "-m", "stampc", "refine", *map(str, SHELF), "--quiet", "--workers",
           "2", "--ray", "127.0.0.1:9"]
    proc = subprocess.run(cmd, cwd=REPO, env=_env(), capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1
    assert "R207" in proc.stderr and "127.0.0.1:9" in proc.stderr
    assert "Traceback" not in proc.stderr
