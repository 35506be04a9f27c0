"""The manipulation domain of stdlib/manipulation.stamp (built directly in the lifted IR,
so the test does not depend on the front end) refined by the engine on a shelf scene
whose target is blocked by two cans, then replayed from the exported policy JSON."""

from __future__ import annotations

import re
from fractions import Fraction

from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.refine import RefineOptions, run_refinement
from stampc.refine.replay import replay
from stampc.worlds.bindings import resolve_model
from stampc.worlds.plane2d import open_world
from stampc.worlds.plane2d.scenes import cluttered


def _atom(pred: str, *args: str) -> L.Atom:
    return L.Atom(pred, tuple(L.Var(a[1:]) if a.startswith("?") else L.Const(a) for a in args))


def _params(*pairs: str) -> tuple[L.Param, ...]:
    return tuple(L.Param(*p.split(":")) for p in pairs)


def _pred(name: str, *pairs: str, **kw) -> L.Predicate:
    return L.Predicate(name, _params(*pairs), **kw)


def _gen(name: str, ins, outs, certifies: L.Atom, budget: int) -> L.Generator:
    return L.Generator(name, _params(*ins), _params(*outs), (certifies,),
                       L.Binding(f".manipulation:{name}"), (("budget", budget),))


def manipulation_domain() -> L.Domain:
    types = (L.Type("movable"), L.Type("surface")) + tuple(
        L.Type(t, continuous=True) for t in ("grasp", "config", "pose", "traj"))
    preds = (_pred("handempty"), _pred("holding", "o:movable"),
             _pred("at", "o:movable", "p:pose"),
             _pred("can_grasp", "o:movable", "p:pose", "g:grasp", "q:config", static=True),
             _pred("can_place", "o:movable", "s:surface", "p:pose", "q:config", static=True),
             _pred("motion_to", "q:config", "t:traj", static=True),
             _pred("collision", "x:movable", "t:traj", unknowable=True, optimistic=False))
    gens = (_gen("grasp", ("o:movable", "p:pose"), ("g:grasp", "q:config"),
                 _atom("can_grasp", "?o", "?p", "?g", "?q"), 4),
            _gen("placement", ("o:movable", "s:surface"), ("p:pose", "q:config"),
                 _atom("can_place", "?o", "?s", "?p", "?q"), 4),
            _gen("motion", ("q:config",), ("t:traj",), _atom("motion_to", "?q", "?t"), 2))
    clear = L.Forall(_params("x:movable"), L.Not(_atom("collision", "?x", "?t")))
    moved = L.EffForall(_params("t2:traj"), L.Unknown(_atom("collision", "?o", "?t2")))
    grasped = L.EffAnd((L.Lit(_atom("holding", "?o")), L.Lit(_atom("handempty"), False),
                        L.Lit(_atom("at", "?o", "?p"), False), moved))
    pick = L.Action(
        "pick", _params("o:movable", "p:pose", "g:grasp", "q:config", "t:traj"),
        L.And((_atom("handempty"), _atom("at", "?o", "?p"),
               _atom("can_grasp", "?o", "?p", "?g", "?q"), _atom("motion_to", "?q", "?t"), clear)),
        L.Probabilistic((L.Outcome(Fraction(9, 10), grasped, "grasped"),)),   # 1/10: slip
        generated=(L.GeneratorUse("grasp", ("o", "p"), ("g", "q")),
                   L.GeneratorUse("motion", ("q",), ("t",))),
        executes=L.Binding(".manipulation:pick"))
    place = L.Action(
        "place", _params("o:movable", "s:surface", "p:pose", "q:config", "t:traj"),
        L.And((_atom("holding", "?o"), _atom("can_place", "?o", "?s", "?p", "?q"),
               _atom("motion_to", "?q", "?t"), clear)),
        L.EffAnd((L.Lit(_atom("holding", "?o"), False), L.Lit(_atom("handempty")),
                  L.Lit(_atom("at", "?o", "?p")), moved)),
        generated=(L.GeneratorUse("placement", ("o", "s"), ("p", "q")),
                   L.GeneratorUse("motion", ("q",), ("t",))),
        executes=L.Binding(".manipulation:place"))
    return L.Domain("manipulation", types, (), preds, (), (pick, place), gens,
                    (L.Evaluator("collision", L.Binding(".manipulation:collision")),))


def test_engine_moves_the_blockers_then_picks_the_target():
    scene = cluttered(5, 2, blockers=2, shelf=True)
    cans = [o["name"] for o in scene["objects"]]
    objects = tuple(L.Object(c, "movable") for c in cans) + (L.Object("tray", "surface"),) \
        + tuple(L.Object(f"pose_{c}", "pose") for c in cans)
    init = (_atom("handempty"),) + tuple(_atom("at", c, f"pose_{c}") for c in cans)
    model = L.Model(manipulation_domain(),
                    L.Problem("clear_shelf", "manipulation", objects, init,
                              goal=_atom("holding", "can0")))
    world = open_world(scene, seed=0)
    bindings = resolve_model(model, world.package)
    refined = run_refinement(ground(model), world, bindings,
                             RefineOptions(seed=0, time_limit=60))
    assert refined.result.coverage > 0.99
    policy = refined.to_json()
    learned = [f["fact"] for n in policy["nodes"] for f in n.get("learned", ()) if f["value"]]
    blamed = {m.group(1) for f in learned for m in [re.match(r"collision\((\w+),", f)] if m}
    assert blamed and blamed <= {"can1", "can2"}          # only the real blockers are blamed
    actions = [n["action"] for n in policy["nodes"] if n.get("action")]
    assert any(a.startswith("place(can1, tray") for a in actions)
    assert any(a.startswith("place(can2, tray") for a in actions)
    report = replay(policy, world, bindings.executors, runs=10, seed=1)
    assert report.count("success") == 10
