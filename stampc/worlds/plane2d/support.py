"""Helpers shared by the bound functions of plane2d (options, action arguments, effects)."""

from __future__ import annotations

import math
from typing import Any, Callable, TypeVar

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context, missing_parameter_hint
from stampc.worlds.plane2d.world import Plane2DWorld

T = TypeVar("T")


def world_of(ctx: Context) -> Plane2DWorld:
    if not isinstance(ctx.world, Plane2DWorld):
        raise StampcError([error("S272", "plane2d bound function called on a "
                                 f"{type(ctx.world).__name__}, not a plane2d world",
                                 Span.point("<plane2d world>"),
                                 hint="run this domain with --world plane2d or bind it to "
                                      "the functions of the world in use")])
    return ctx.world


def int_option(ctx: Context, key: str, default: int, *, minimum: int = 1) -> int:
    v = ctx.options.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or v != int(v) or v < minimum:
        raise StampcError([error("S273", f"plane2d: option {key!r} must be an integer ≥ "
                                 f"{minimum}, got {v!r}", Span.point("<plane2d options>"))])
    return int(v)


def float_option(ctx: Context, key: str, default: float) -> float:
    v = ctx.options.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        raise StampcError([error("S273", f"plane2d: option {key!r} must be a non-negative "
                                 f"number, got {v!r}", Span.point("<plane2d options>"))])
    return float(v)


def arg(action: ConcreteAction, name: str, convert: Callable[[Any], T]) -> T:
    """Action argument ``name`` converted by ``convert`` (e.g. ``as_pose``)."""
    if name not in action.args:
        raise StampcError([error("S274", f"plane2d executor of {action.name!r}: missing "
                                 f"argument {name!r} (has {', '.join(action.args) or 'none'})",
                                 Span.point("<plane2d executor>"),
                                 hint=missing_parameter_hint(action, name))])
    return convert(action.args[name])



def name_arg(value: Any) -> str:
    if not isinstance(value, str):
        raise StampcError([error("S274", f"plane2d: expected an object name, got {value!r}",
                                 Span.point("<plane2d executor>"))])
    return value


def mentions(literals: tuple[tuple[str, tuple[Any, ...]], ...], predicate: str,
             obj: str) -> bool:
    """Some literal of ``predicate`` has ``obj`` among its arguments."""
    return any(p == predicate and any(a == obj for a in args if isinstance(a, str))
               for p, args in literals)


def normalize_angle(a: float) -> float:
    """Map an angle to (-π, π]."""
    a = math.fmod(a + math.pi, 2 * math.pi)
    if a <= 0:
        a += 2 * math.pi
    return a - math.pi
