"""Learned facts of a `? predicate` hold in every state (stampc/refine/fixed.py): the
actions that need the other value are banned everywhere, and never lifted. On the Keva
example, whose `reaches(a, f)` says which arm reaches which feed (real PyBullet world)."""

from __future__ import annotations

from pathlib import Path

import stampc
from examples.keva import scene as kv
from stampc.refine import RefineOptions
from stampc.refine.engine import Engine
from stampc.refine.fixed import fixed_facts, needing_otherwise
from stampc.solvers.space import ANY_STATE
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import open_world

DOMAIN = Path(__file__).resolve().parents[2] / "examples" / "keva" / "domain.stamp"


def _keva_engine(tmp_path: Path) -> tuple[Engine, object]:
    problem = kv.write_problem(tmp_path / "p.stamp", "pi", 1, 0)
    model = stampc.load_model([DOMAIN, problem])
    world = open_world("pybullet", kv.build("pi", 1, 0), seed=0)
    engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                    RefineOptions(seed=0, time_limit=60))
    return engine, world


def test_only_unwritten_unknowable_facts_are_fixed(tmp_path):
    engine, world = _keva_engine(tmp_path)
    world.close()
    gm = engine.model
    fixed = {gm.facts[i].predicate for i in fixed_facts(gm)}
    assert fixed == {"reaches", "places"}  # `blocked` is unknowable too, but the puts' `?` write it
    assert any(gm.facts[i].predicate == "blocked" for i in range(len(gm.facts)))


def test_a_learned_fixed_fact_bans_its_actions_everywhere_for_good(tmp_path):
    engine, world = _keva_engine(tmp_path)
    world.close()
    gm = engine.model
    fact = next(i for i in fixed_facts(gm)
                if gm.facts[i].args == ("left", "feed2"))
    needing = needing_otherwise(gm, [(fact, False)])
    names = {(gm.actions[a].name, gm.actions[a].args[:2]) for a in needing}
    assert names == {("pick", ("left", "feed2"))}
    assert needing_otherwise(gm, [(fact, True)]) == set()  # nothing needs it false
    blocked = next(i for i, f in enumerate(gm.facts) if f.predicate == "blocked")
    # the fixed fact is no state bit (branches that learned it still merge with the
    # others); a learned `?` fact of an effect-written predicate is
    assert engine._ban_against_fixed_facts([(fact, False), (blocked, True)]) == ((blocked, True),)
    assert {(ANY_STATE, a) for a in needing} <= engine.planner.forbidden
    assert engine._bans_everywhere() == []  # not a guess: no replan lifts it
    engine._lift_bans_everywhere()
    assert {(ANY_STATE, a) for a in needing} <= engine.planner.forbidden
