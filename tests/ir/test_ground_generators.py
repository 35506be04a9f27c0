"""Entity abstraction: Skolem symbols for generated parameters, certified facts."""

from __future__ import annotations

from ir_builders import AND, EFF, NOT, action, add, atom, delete, find, labels, model, params, pred

from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.ir.grounded import GroundAtom, GroundGeneratorUse

G1 = "g_pick_can3_pose_can3"
T1 = "t_pick_can3_pose_can3"
P2 = f"p_place_can3_{G1}"


def pick_place() -> L.Model:
    types = (L.Type("obj"), L.Type("conf", continuous=True), L.Type("pose", "conf", True),
             L.Type("grasp", continuous=True), L.Type("traj", continuous=True))
    preds = (pred("at", "obj", "pose"), pred("holding", "obj", "grasp"), pred("handempty"),
             pred("grasp_ok", "obj", "grasp"), pred("kin", "obj", "pose", "grasp", "traj"),
             pred("placeable", "obj", "pose"),
             pred("collides", "traj", unknowable=True, optimistic=False))
    gens = (
        L.Generator("sample_grasp", params(("o", "obj")), params(("g", "grasp")),
                    (atom("grasp_ok", "?o", "?g"),), L.Binding(".manip:grasp")),
        L.Generator("ik", params(("o", "obj"), ("p", "pose"), ("g", "grasp")),
                    params(("t", "traj")), (atom("kin", "?o", "?p", "?g", "?t"),),
                    L.Binding(".manip:ik"), (("budget", 8),)),
        L.Generator("sample_place", params(("o", "obj")), params(("p", "pose")),
                    (atom("placeable", "?o", "?p"),), L.Binding(".manip:place")))
    pick = action(
        "pick", params(("o", "obj"), ("p", "pose"), ("g", "grasp"), ("t", "traj")),
        AND(atom("at", "?o", "?p"), atom("handempty"), atom("grasp_ok", "?o", "?g"),
            atom("kin", "?o", "?p", "?g", "?t"), NOT(atom("collides", "?t"))),
        EFF(add("holding", "?o", "?g"), delete("at", "?o", "?p"), delete("handempty"),
            L.Unknown(atom("collides", "?t"))),
        generated=(L.GeneratorUse("sample_grasp", ("o",), ("g",)),
                   L.GeneratorUse("ik", ("o", "p", "g"), ("t",))))
    place = action(
        "place", params(("o", "obj"), ("g", "grasp"), ("p", "pose"), ("t", "traj")),
        AND(atom("holding", "?o", "?g"), atom("placeable", "?o", "?p"),
            atom("kin", "?o", "?p", "?g", "?t")),
        EFF(add("at", "?o", "?p"), add("handempty"), delete("holding", "?o", "?g")),
        generated=(L.GeneratorUse("sample_place", ("o",), ("p",)),
                   L.GeneratorUse("ik", ("o", "p", "g"), ("t",))))
    return model(types=types, preds=preds, actions=(pick, place), generators=gens,
                 objs="can3 - obj pose_can3 - pose",
                 init=(atom("at", "can3", "pose_can3"), atom("handempty")),
                 goal=atom("handempty"))


def test_skolem_symbols_names_types_and_certified_facts():
    gm = ground(pick_place(), max_symbol_depth=1)
    assert labels(gm) == [f"pick(can3, pose_can3, {G1}, {T1})"]
    pick = gm.actions[0]
    assert pick.args == ("can3", "pose_can3", G1, T1)
    assert pick.generated == (GroundGeneratorUse("sample_grasp", ("can3",), (G1,)),
                              GroundGeneratorUse("ik", ("can3", "pose_can3", G1), (T1,)))
    objects = dict(gm.objects)
    assert objects[G1] == "grasp" and objects[T1] == "traj"
    assert list(gm.objects)[:2] == [("can3", "obj"), ("pose_can3", "pose")]
    assert GroundAtom("grasp_ok", ("can3", G1)) in gm.static_facts
    assert GroundAtom("kin", ("can3", "pose_can3", G1, T1)) in gm.static_facts
    # certified atoms are static-true, so only fluent conditions remain
    assert pick.precondition.holds(gm.init)
    collides = gm.fact_index(GroundAtom("collides", (T1,)))
    assert pick.effect.unknown == 1 << collides and pick.precondition.neg == 1 << collides


def test_symbols_feed_other_actions_selected_parameters():
    gm = ground(pick_place())  # default depth 3
    place = find(gm, f"place(can3, {G1}, {P2}, t_place_can3_{G1})")
    assert place.generated[0] == GroundGeneratorUse("sample_place", ("can3",), (P2,))
    assert dict(gm.objects)[P2] == "pose"
    # the placed pose is a new pose the object can be picked from again (depth 3) ...
    g3 = f"g_pick_can3_{P2}"
    assert find(gm, f"pick(can3, {P2}, {g3}, t_pick_can3_{P2})")
    # ... but placing that grasp again would need depth 4
    assert not any(a.name == "place" and a.args[1] == g3 for a in gm.actions)
    names = [n for n, _ in gm.objects]
    assert names[2:] == sorted(names[2:])


def test_symbol_depth_bound_controls_growth():
    sizes = [len(ground(pick_place(), max_symbol_depth=d).actions) for d in (1, 2, 3, 4)]
    assert sizes == [1, 2, 3, 4]
