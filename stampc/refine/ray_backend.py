"""Refinement workers as Ray actors (``stampc refine --ray [ADDRESS] --workers N``).

The only module of stampc that imports Ray (the optional ``ray`` extra), and only when a
pool is opened. Each actor holds one :class:`stampc.refine.workers.RefineWorker` (its own
model and world) and answers the same tasks as a local worker process, so a run gives the
same policy on either backend. The actors' Python path gets the directory stampc is
imported from and the caller's PYTHONPATH (Ray's ``runtime_env``): every node of a remote
cluster needs the same checkout and the stamp files at the same paths (docs/refine.md).
"""

from __future__ import annotations

import os
import socket
from pathlib import Path

from stampc.diagnostics import Span, StampcError, error
from stampc.refine.workers import (RefineWorker, WorkerSpec, WorkReply, WorkTask, answer,
                                   check_status, start_worker, worker_failure)


class _Actor:
    """A Ray actor around one refinement worker."""

    def __init__(self, spec: WorkerSpec):
        self.worker: RefineWorker | None
        self.worker, self._status = start_worker(spec)

    def status(self) -> tuple:
        return self._status

    def handle(self, task: WorkTask) -> WorkReply:
        assert self.worker is not None  # the engine checks the status first
        return answer(self.worker, task)


def _unavailable(reason: str) -> StampcError:
    return StampcError([error("R207", f"Ray backend unavailable: {reason}", Span.point("<--ray>"),
                              hint='install the extra (pip install -e ".[ray]") and give the '
                                   "address of a running cluster (ray start --head), or omit "
                                   "--ray to use local worker processes")])


def _reachable(address: str) -> None:
    """Fail fast (R207) when a host:port address does not accept connections: Ray itself
    keeps retrying an unreachable cluster for minutes."""
    host, sep, port = address.rpartition(":")
    if not sep or not port.isdigit():
        return  # "" or "auto": Ray finds the cluster itself
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=5.0).close()
    except OSError as exc:
        raise _unavailable(f"nothing answers at {address} ({exc.strerror or exc})") from None


def _python_path() -> str:
    import stampc
    root = str(Path(stampc.__file__).resolve().parents[1])
    return os.pathsep.join(filter(None, [root, os.environ.get("PYTHONPATH")]))


class RayPool:
    """``n`` actors on the Ray cluster at ``address`` ("": Ray's default)."""

    def __init__(self, spec: WorkerSpec, n: int, address: str, wait: bool = False):
        try:
            import ray
        except ImportError:
            raise _unavailable("the ray package is not installed") from None
        self._ray = ray
        _reachable(address)
        try:
            ray.init(address=address or None, include_dashboard=False, log_to_driver=False,
                     configure_logging=False,
                     runtime_env={"env_vars": {"PYTHONPATH": _python_path()}})
        except (ConnectionError, ValueError, RuntimeError) as exc:
            raise _unavailable(f"cannot connect to {address or 'the default cluster'}: "
                               f"{type(exc).__name__}: {exc}") from None
        self.size = n
        self.wait = wait  # as LocalPool's
        self._spec = spec
        self._actors: list = []
        self._status_refs: list = []
        self._ready = False
        self._refs: list = []

    def _get(self, refs: list):
        from ray.exceptions import RayActorError, RayTaskError
        try:
            return self._ray.get(refs)
        except (RayActorError, RayTaskError) as exc:
            raise worker_failure("(Ray actor)", f"{type(exc).__name__}: "
                                 f"{str(exc).splitlines()[0] if str(exc) else ''}") from None

    def ready(self, signature: tuple[int, int]) -> bool:
        """Whether every actor has started (without waiting: the first call creates them)."""
        if not self._actors:
            actor = self._ray.remote(num_cpus=1, max_restarts=0)(_Actor)
            self._actors = [actor.remote(self._spec) for _ in range(self.size)]
            self._status_refs = [a.status.remote() for a in self._actors]
        if not self._ready:
            done, _ = self._ray.wait(self._status_refs, num_returns=self.size,
                                     timeout=None if self.wait else 0)
            if len(done) == self.size:
                check_status(self._get(self._status_refs), signature)
                self._ready = True
        return self._ready

    def submit(self, tasks: list[WorkTask]) -> None:
        self._refs = [self._actors[i % self.size].handle.remote(t) for i, t in enumerate(tasks)]

    def collect(self) -> list[WorkReply]:
        return self._get(self._refs)

    def close(self) -> None:
        for a in self._actors:
            self._ray.kill(a)
        self._ray.shutdown()
