"""The protocol between the refinement engine and a concrete world backend.

A world owns one concrete simulation (a 2-D geometry, a PyBullet client...). The engine
talks to it only through this small surface:

- ``snapshot()`` / ``restore(state)``: cheap, opaque copies of the concrete state;
- bound *generators* produce concrete values for symbolic action arguments;
- bound *evaluators* decide ``?`` predicates in the current concrete state;
- bound *executors* apply an action's concrete effect for a chosen outcome.

Bound functions are plain Python callables resolved from ``"pkg.module:function"``
strings (a leading ``.`` is relative to the world's own package). Their signatures:

    generator(ctx: Context, *inputs) -> Iterable[tuple]     # one tuple of outputs per sample
    evaluator(ctx: Context, *args) -> bool
    executor(ctx: Context, action: ConcreteAction) -> None  # mutates the current state
    executor(ctx: Context, action: ConcreteAction, outcome: Outcome) -> None  # outcome-aware

``inputs``/``args`` are, position by position, object names (``str``) for discrete
types and concrete values for continuous ones. Concrete values must be JSON-friendly via
:func:`to_json` (numbers, sequences of numbers, dicts, or objects with ``to_json()``).
"""

from __future__ import annotations

import inspect
import json
import random
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Protocol, runtime_checkable

from stampc.diagnostics import Span, StampcError, error
from stampc.ir.grounded import GroundAtom


@dataclass(frozen=True)
class ConcreteAction:
    """An abstract ground action with its symbolic arguments replaced by values."""

    name: str
    #: parameter name -> object name (discrete) or concrete value (continuous)
    args: Mapping[str, Any]
    #: the chosen outcome's literal effects, arguments already concrete
    adds: tuple[tuple[str, tuple[Any, ...]], ...] = ()
    deletes: tuple[tuple[str, tuple[Any, ...]], ...] = ()
    #: index of the chosen joint outcome and its label(s), if any
    outcome: int = 0
    labels: tuple[str, ...] = ()


@dataclass(frozen=True)
class Outcome:
    """The sampled outcome of an action, as an outcome-aware executor receives it.

    ``name``: the outcome's ``as NAME`` label(s) joined by ``+`` (several independent
    blocks may fire together), ``None`` if unnamed; ``adds``/``deletes``: its literal
    effects with concrete arguments (as in :class:`ConcreteAction`)."""

    name: str | None
    index: int
    probability: float
    adds: tuple[tuple[str, tuple[Any, ...]], ...] = ()
    deletes: tuple[tuple[str, tuple[Any, ...]], ...] = ()

    @property
    def changes_nothing(self) -> bool:
        """No literal effect at all (e.g. a slip that leaves the robot where it was)."""
        return not self.adds and not self.deletes


def accepts_outcome(fn: Callable) -> bool:
    """Does executor ``fn`` declare an ``outcome`` parameter (or ``**kwargs``)?"""
    try:
        params = inspect.signature(fn).parameters.values()
    except (TypeError, ValueError):
        return False
    return any(p.name == "outcome" or p.kind is p.VAR_KEYWORD for p in params)


def call_executor(fn: Callable, ctx: "Context", action: ConcreteAction, outcome: Outcome) -> None:
    """Call an executor: outcome-aware ones (``def ex(ctx, action, outcome)``) get the
    sampled outcome; the two-argument form of earlier worlds is called as before."""
    if accepts_outcome(fn):
        fn(ctx, action, outcome=outcome)
    else:
        fn(ctx, action)


@dataclass
class Context:
    """What a bound function sees: the world, a seeded RNG, options and a scratch cache.

    ``cache`` lives as long as the concrete state it was created for; worlds use it to
    memoise expensive checks (e.g. the set of bodies a trajectory sweeps through).
    """

    world: "World"
    rng: random.Random
    options: Mapping[str, Any] = field(default_factory=dict)
    cache: dict = field(default_factory=dict)
    #: symbol name -> concrete value for every symbol bound so far on this path
    values: Mapping[str, Any] = field(default_factory=dict)
    #: absolute ``time.perf_counter()`` deadline of the run (``--time-limit``), if any:
    #: long computations (motion planning, IK restarts) should not run past it
    deadline: float | None = None

    def time_left(self, cap: float) -> float:
        """``cap`` seconds, or less if the run's deadline is nearer (never below 10 ms,
        so a call made at the deadline still returns promptly with what it has)."""
        if self.deadline is None:
            return cap
        return max(0.01, min(cap, self.deadline - time.perf_counter()))


@runtime_checkable
class World(Protocol):
    """A concrete world backend."""

    #: package used to resolve relative bindings, e.g. "stampc.worlds.plane2d"
    package: str

    def snapshot(self) -> Any:
        """Return an opaque, immutable copy of the current concrete state."""

    def restore(self, state: Any) -> None:
        """Make ``state`` (from :meth:`snapshot`) current."""

    def initial_values(self) -> Mapping[str, Any]:
        """Concrete values of the problem's continuous objects (e.g. initial poses)."""

    def close(self) -> None:
        """Release resources (simulator clients, planners)."""


BoundFunction = Callable[..., Any]


def to_json(value: Any) -> Any:
    """Convert a concrete value into JSON-compatible data."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if hasattr(value, "to_json"):
        return value.to_json()
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        return value.tolist()
    if isinstance(value, Mapping):
        return {str(k): to_json(v) for k, v in value.items()}
    if isinstance(value, Iterable):
        return [to_json(v) for v in value]
    raise TypeError(f"concrete value of type {type(value).__name__} is not JSON-friendly")


def atom_args(atom: GroundAtom, values: Mapping[str, Any]) -> tuple[Any, ...]:
    """Replace symbols in a ground atom by their concrete values (others stay names)."""
    return tuple(values.get(a, a) for a in atom.args)


def scene_argument(scene: Mapping[str, Any] | str | Path, seed: Any, *, read_code: str,
                   seed_code: str, world: str) -> tuple[Mapping[str, Any], str]:
    """Shared front door of the worlds' ``open_world``: accept a scene dict or the path of a
    JSON scene file (read errors and bad seeds become located diagnostics with the
    world's own codes); returns the scene dict and its source name."""
    source = "<scene>"
    if isinstance(scene, (str, Path)):
        source = str(scene)
        try:
            scene = json.loads(Path(scene).read_text(encoding="utf-8"))
        except OSError as exc:
            raise StampcError([error(read_code, f"cannot read scene file {source!r}: "
                                     f"{exc.strerror}", Span.point(source))]) from None
        except json.JSONDecodeError as exc:
            raise StampcError([error(read_code, f"scene file is not valid JSON: {exc.msg}",
                                     Span.point(source, exc.lineno, exc.colno))]) from None
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise StampcError([error(seed_code, f"{world}: seed must be an integer, got {seed!r}",
                                 Span.point(f"<{world} world>"))])
    return scene, source


def missing_parameter_hint(action: ConcreteAction, name: str) -> str:
    """Executors read action parameters by name: name both sides of the mismatch."""
    params = ", ".join(f"`{p}`" for p in action.args) or "none"
    return (f"the executor reads the action parameter `{name}`, but action "
            f"{action.name!r} declares {params}: in the stamp file, rename the parameter "
            f"that holds this value to `{name}` (executor parameter names are listed in "
            "the world's docs)")
