"""The paper domains check cleanly and lower to the IR the rest of the pipeline expects."""

from __future__ import annotations

from fractions import Fraction

import pytest

from stampc.ir import lifted as ir
from stampc.ir.lower import lower
from stampc.semantics.api import check, load

from .helpers import EXAMPLES, REPO


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_checks_without_errors_or_warnings(name: str) -> None:
    folder = REPO / "examples" / name
    assert check(folder / "domain.stamp", folder / "problem.stamp") == []
    assert (folder / "README.md").is_file()


def model(name: str) -> ir.Model:
    return lower(load(REPO / "examples" / name / "problem.stamp"))


def outcomes(effect: ir.Effect) -> list[ir.Outcome]:
    found: list[ir.Outcome] = []
    stack = [effect]
    while stack:
        e = stack.pop()
        if isinstance(e, ir.Probabilistic):
            found.extend(e.outcomes)
            stack.extend(o.effect for o in e.outcomes)
        elif isinstance(e, ir.EffAnd):
            stack.extend(e.effects)
        elif isinstance(e, (ir.When, ir.EffForall)):
            stack.append(e.effect)
    return found


def test_cluttered_table_model() -> None:
    m = model("cluttered_table")
    objects = {o.name: o for o in m.problem.objects}
    assert [f"can{i}" for i in range(15)] == [o for o in objects if o.startswith("can")]
    assert objects["pose_can14"].symbolic and objects["pose_can14"].type == "pose"
    assert not objects["can3"].symbolic
    assert ir.Atom("at", (ir.Const("can7"), ir.Const("pose_can7"))) in m.problem.init
    scene = m.problem.scene
    assert (scene.kind, scene.target) == ("builder",
                                          "examples.cluttered_table.scene:build_random")
    assert dict(scene.args)["n"] == 15 and isinstance(dict(scene.args)["seed"], int)
    actions = {a.name: a for a in m.domain.actions}
    # the domain's pick/place override the stdlib's; the robot drives between base poses
    assert set(actions) == {"move_base", "pick", "place", "discard"}
    pick = actions["pick"]
    # the domain's grasp generator from the robot's base, then its motion generator
    assert pick.generated == (ir.GeneratorUse("base_grasp", ("b", "o", "p"), ("g", "q")),
                              ir.GeneratorUse("motion4", ("q",), ("t",)))
    crush = {o.probability for o in outcomes(pick.effect) if o.label == "crushed"}
    assert {Fraction(1, 20), Fraction(1, 2)} <= crush  # normal cans 0.05; delicate (mid) 0.5
    assert actions["discard"].cost == ir.Num(Fraction(5)) and pick.cost == ir.Num(Fraction(1))
    assert pick.executes == ir.Binding(".manipulation:pick")
    collision = next(p for p in m.domain.predicates if p.name == "collision")
    assert collision.unknowable and collision.optimistic is False
    assert {t.name for t in m.domain.types if t.continuous} == {"grasp", "config", "pose", "traj"}


def test_domino_topple_probabilities_fall_with_distance() -> None:
    m = model("domino")
    pick = next(a for a in m.domain.actions if a.name == "pick")
    probs = sorted((o.probability for o in outcomes(pick.effect)), reverse=True)
    assert len(probs) >= 2  # k >= 2 neighbours on each side
    assert probs == [Fraction(1, d + 1) for d in range(1, len(probs) + 1)]  # 1/(d+1) at distance d
    assert isinstance(m.problem.goal, ir.And)


def test_keva_feed_outcomes_sum_to_one() -> None:
    m = model("keva")
    bring = next(a for a in m.domain.actions if a.name == "bring")
    assert sum(o.probability for o in outcomes(bring.effect)) == 1
    assert [o.label for o in outcomes(bring.effect)] == ["feed1", "feed2"]
    assert [float(o.probability) for o in outcomes(bring.effect)] == [0.8, 0.2]  # the paper
    # feeds are named places (a discrete type); their poses live in the scene
    assert {c.name: c.type for c in m.domain.constants if c.type == "feed"} == {
        "feed1": "feed", "feed2": "feed", "buffer": "feed"}


def test_aircraft_battery_is_optimistically_true() -> None:
    m = model("aircraft_inspection")
    battery = next(p for p in m.domain.predicates if p.name == "has_battery")
    assert battery.unknowable and battery.optimistic is True
    fly = next(a for a in m.domain.actions if a.name == "fly")
    assert fly.generated == (ir.GeneratorUse("flight_path", ("u", "a", "b"), ("t",)),)
    drift = {o.label: o.probability for o in outcomes(fly.effect)}
    assert drift["drifted"] == Fraction(1, 20) and drift["arrived"] == Fraction(19, 20)
    inspect = next(a for a in m.domain.actions if a.name == "inspect")
    assert all(0 < o.probability < 1 for o in outcomes(inspect.effect))  # a miss is possible
    assert m.domain.evaluators == (ir.Evaluator("has_battery", ir.Binding(".aircraft:battery_suffices")),)


def test_docs_list_every_diagnostic_code() -> None:
    from stampc.semantics.codes import CODES

    text = (REPO / "docs" / "language.md").read_text(encoding="utf-8")
    assert [c for c in CODES if f"| {c} |" not in text] == []


def test_manipulation_stdlib_contract() -> None:
    """The names and signatures the world backends rely on (docs/stdlib.md)."""
    d = lower_domain_of(REPO / "stdlib" / "manipulation.stamp")
    sig = {p.name: (tuple((x.name, x.type) for x in p.params), p.static, p.unknowable)
           for p in d.predicates}
    assert sig == {
        "handempty": ((), False, False),
        "holding": ((("o", "movable"),), False, False),
        "at": ((("o", "movable"), ("p", "pose")), False, False),
        "can_grasp": ((("o", "movable"), ("p", "pose"), ("g", "grasp"), ("q", "config")), True, False),
        "can_place": ((("o", "movable"), ("s", "surface"), ("p", "pose"), ("q", "config")), True, False),
        "motion_to": ((("q", "config"), ("t", "traj")), True, False),
        "collision": ((("x", "movable"), ("t", "traj")), False, True),
    }
    gens = {g.name: (g.binding.target, dict(g.options)["budget"], len(g.inputs), len(g.outputs))
            for g in d.generators}
    assert gens == {"grasp": (".manipulation:grasp", 4, 2, 2),
                    "placement": (".manipulation:placement", 4, 2, 2),
                    "motion": (".manipulation:motion", 2, 1, 1)}
    assert d.evaluators == (ir.Evaluator("collision", ir.Binding(".manipulation:collision")),)
    acts = {a.name: a for a in d.actions}
    assert [p.name for p in acts["pick"].params] == ["o", "p", "g", "q", "t"]
    assert [p.name for p in acts["place"].params] == ["o", "s", "p", "q", "t"]
    assert acts["place"].generated == (ir.GeneratorUse("placement", ("o", "s"), ("p", "q")),
                                       ir.GeneratorUse("motion", ("q",), ("t",)))
    assert acts["pick"].executes.target == ".manipulation:pick"


def lower_domain_of(path) -> ir.Domain:
    from stampc.ir.lower import lower_domain

    return lower_domain(load(path))
