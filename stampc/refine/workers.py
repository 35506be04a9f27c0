"""Refinement workers: processes that each own a world and concretize one node at a time.

A worker is built from a :class:`WorkerSpec` — the stamp files, the world backend, the
scene dict and the seed, i.e. what ``stampc refine`` itself starts from — so it compiles
and grounds the same model (the same action and fact indices) and opens the same world.
It receives plain data (:class:`WorkTask`: the node's concrete snapshot and scratch cache,
the generator values above it, its uid, attempt and mode) and returns plain data
(:class:`WorkReply`: the concretization or the failure with its learned facts, the
outcomes' concrete snapshots on success, the updated cache). The reply depends on the
task only, never on which worker ran it or what it ran before: every generator call's
RNG derives from (seed, node, attempt, generator) as in the engine, and the world is
restored to the task's snapshot before each call.

Two backends run workers: :class:`LocalPool` (processes of this machine, the default) and
``stampc.refine.ray_backend.RayPool`` (Ray actors, local or on a cluster). Both answer a
batch of tasks in task order.
"""

from __future__ import annotations

import multiprocessing
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

from stampc.diagnostics import Diagnostic, Span, StampcError, error


@dataclass(frozen=True)
class WorkerSpec:
    """What a worker needs to rebuild the engine's model and world: ``build(spec)``
    returns (ground model, world, resolved bindings) — a module-level function, so that
    it pickles by name (``stampc.api`` passes its own; the engine layer does not compile)."""

    files: tuple[str, ...]
    world: str
    scene: Mapping[str, Any]
    seed: int
    build: Callable[["WorkerSpec"], tuple[Any, Any, Any]]
    verbose: bool = False


@dataclass(frozen=True)
class WorkTask:
    action: int          # ground action index
    state: int           # the node's abstract state (outcome labels)
    snapshot: Any        # the node's concrete state
    cache: dict          # the node's scratch cache (a copy)
    values: dict         # generator values of the refined ancestors
    uid: int
    attempt: int
    quick: bool          # UpdateAbstraction mode: first complete sample only
    #: (successor, outcome) of each edge, executed on success (the children's states)
    edges: tuple
    #: seconds left in the run (None: no limit); the worker sets its own deadline
    remaining: float | None


@dataclass(frozen=True)
class WorkReply:
    result: Any = None                    # Success | Failure
    snapshots: list | None = None         # one per edge, on success
    cache: dict = field(default_factory=dict)
    busy_s: float = 0.0                   # time in generators, evaluators, executors
    work: int = 0                         # samples drawn + evaluations (Concretizer.work)
    diagnostics: tuple[Diagnostic, ...] = ()  # a located error instead of a result


class RefineWorker:
    """One worker's model, world and concretizer (a plain class: Ray wraps it as an actor)."""

    def __init__(self, spec: WorkerSpec):
        from stampc.refine.concretize import Concretizer

        self.model, self.world, bindings = spec.build(spec)
        self.concretizer = Concretizer(self.model, bindings, self.world, spec.seed)

    def signature(self) -> tuple[int, int]:
        """(actions, facts) of the grounded model: must equal the engine's."""
        return len(self.model.actions), len(self.model.facts)

    def handle(self, task: WorkTask) -> WorkReply:
        try:
            return self._handle(task)
        except StampcError as exc:  # bound user code failed: its located diagnostic
            return WorkReply(diagnostics=tuple(exc.diagnostics))

    def _handle(self, task: WorkTask) -> WorkReply:
        c = self.concretizer
        c.deadline = None if task.remaining is None else time.perf_counter() + task.remaining
        return handle_task(self.model, c, task)

    def close(self) -> None:
        close = getattr(self.world, "close", None)
        if close is not None:
            close()


def handle_task(model, concretizer, task: WorkTask) -> WorkReply:
    """Concretize the task's node from its snapshot (with a copy of its cache) and, on
    success, execute its outcomes: a function of the task only (the engine runs one task
    of each batch itself with this, the workers the others)."""
    from stampc.refine.concretize import Success

    start, work = time.perf_counter(), concretizer.work
    action = model.actions[task.action]
    cache = dict(task.cache)
    result = concretizer.concretize(action, task.snapshot, cache, task.values,
                                    node_uid=task.uid, attempt=task.attempt, quick=task.quick)
    snapshots = None
    if isinstance(result, Success):
        env = {**task.values, **result.sigma}
        snapshots = [concretizer.execute(action, successor, outcome, task.snapshot, cache,
                                         env, task.uid, task.state)
                     for successor, outcome in task.edges]
    return WorkReply(result, snapshots, cache, time.perf_counter() - start,
                     work=concretizer.work - work)


def worker_failure(which: str, reason: str) -> StampcError:
    """R206: a worker stopped or could not start (not the user's code failing)."""
    return StampcError([error(
        "R206", f"refinement worker {which} failed: {reason}", Span.point("<refine worker>"),
        hint="rerun with --workers 1 to refine in this process; a worker that died may "
             "have run out of memory or crashed inside a simulator")])


def start_worker(spec: WorkerSpec) -> tuple[RefineWorker | None, tuple]:
    """(worker, ("ready", signature)), or (None, ("error", diagnostics)) if it cannot start."""
    try:
        worker = RefineWorker(spec)
    except StampcError as exc:
        return None, ("error", tuple(exc.diagnostics))
    except Exception as exc:  # noqa: BLE001 - reported to the engine as R206, not raised
        return None, ("error", tuple(worker_failure("start", f"{type(exc).__name__}: {exc}")
                                     .diagnostics))
    return worker, ("ready", worker.signature())


def answer(worker: RefineWorker, task: WorkTask) -> WorkReply:
    """The worker's reply; a bug outside bound user code becomes a located R206 too."""
    try:
        return worker.handle(task)
    except Exception as exc:  # noqa: BLE001 - a worker bug: located R206, no traceback
        return WorkReply(diagnostics=tuple(worker_failure(
            "task", f"{type(exc).__name__}: {exc}").diagnostics))


def _serve(spec: WorkerSpec, conn) -> None:
    """A local worker process: build, report the model's signature, then answer tasks."""
    worker, status = start_worker(spec)
    conn.send(status)
    if worker is None:
        return
    try:
        while (task := conn.recv()) is not None:
            conn.send(answer(worker, task))
    except EOFError:
        pass  # the engine went away
    finally:
        worker.close()


def check_status(statuses: list[tuple], signature: tuple[int, int]) -> None:
    """Raise the first worker's start-up diagnostics, or R206 if it grounded another model."""
    for i, (kind, data) in enumerate(statuses):
        if kind == "error":
            raise StampcError(list(data))
        if tuple(data) != tuple(signature):
            raise worker_failure(str(i + 1), f"it grounded another model ({data} "
                                 f"actions, facts; the engine {signature})")


class LocalPool:
    """``n`` worker processes of this machine (spawned: no simulator state is forked),
    started on the first :meth:`ready` (the first batch with work for them); ``wait``: that
    call waits until they are up (tests: every batch's other tasks then reach a worker).

    Task ``i`` of a batch goes to worker ``i mod n``; replies come back in task order."""

    def __init__(self, spec: WorkerSpec, n: int, wait: bool = False):
        self.size = n
        self.wait = wait
        self._spec = spec
        self._conns: list = []
        self._procs: list = []
        self._status: list[tuple] = []  # the start-up reports received so far
        self._ready = False
        self._sent = 0

    def ready(self, signature: tuple[int, int]) -> bool:
        """Whether every worker has started (without waiting: the first call starts them,
        and they build their model and world meanwhile); raises a worker's start-up
        diagnostics, or R206 if it grounded another model than ``signature``."""
        if not self._procs:
            self._start()
        while not self._ready and (self.wait or self._conns[len(self._status)].poll()):
            i = len(self._status)
            self._status.append(self._recv(i, self._conns[i]))
            if len(self._status) == self.size:
                check_status(self._status, signature)
                self._ready = True
        return self._ready

    @property
    def started(self) -> bool:
        return bool(self._procs)

    def _start(self) -> None:
        ctx = multiprocessing.get_context("spawn")
        for _ in range(self.size):
            parent, child = ctx.Pipe()
            proc = ctx.Process(target=_serve, args=(self._spec, child), daemon=True)
            proc.start()
            child.close()
            self._conns.append(parent)
            self._procs.append(proc)

    def submit(self, tasks: list[WorkTask]) -> None:
        """Send task ``i`` to worker ``i mod n`` (answered by :meth:`collect`)."""
        for i, task in enumerate(tasks):
            self._send(i % self.size, task)
        self._sent = len(tasks)

    def collect(self) -> list[WorkReply]:
        """The replies to the last :meth:`submit`, in task order."""
        return [self._recv(i % self.size, self._conns[i % self.size]) for i in range(self._sent)]

    def _send(self, i: int, task: WorkTask) -> None:
        try:
            self._conns[i].send(task)
        except (BrokenPipeError, ConnectionResetError, OSError) as exc:
            raise self._died(i, exc) from None

    def _recv(self, i: int, conn):
        try:
            return conn.recv()
        except (EOFError, ConnectionResetError, OSError) as exc:
            raise self._died(i, exc) from None

    def _died(self, i: int, exc: Exception) -> StampcError:
        proc = self._procs[i]
        proc.join(timeout=1.0)
        code = proc.exitcode
        return worker_failure(str(i + 1), f"its process stopped (exit code {code}; "
                              f"{type(exc).__name__})")

    def close(self) -> None:
        if not self._ready:  # never used (still starting, or never started)
            for proc in self._procs:
                proc.terminate()
        for conn in self._conns:
            try:
                conn.send(None)
            except (BrokenPipeError, ConnectionResetError, OSError):
                pass  # already gone
            conn.close()
        for proc in self._procs:
            proc.join(timeout=5.0)
            if proc.is_alive():
                proc.terminate()
                proc.join(timeout=1.0)
