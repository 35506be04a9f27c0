"""Bans in every state: an action that found no usable sample in several abstract states
and never worked anywhere is banned everywhere, and the ban is lifted again when the
goal cannot be reached without it. Real plane2d world, real .stamp inputs."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

import stampc
from stampc.diagnostics import StampcError
from stampc.refine import Engine, RefineOptions
from stampc.refine.options import check_refine_options
from stampc.solvers.space import ANY_STATE
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

DATA = Path(__file__).parent / "data"
# the grasp may leave the can wet: the impossible cheap shelf is chosen in both outcomes
WET = [DATA / "store_wet.stamp", DATA / "store_wet1.stamp"]
PACK = [DATA / "pack.stamp", DATA / "pack2.stamp"]


def engine_run(files, **options):
    model = stampc.load_model(files)
    world = open_world("plane2d", load_scene(model.problem, DATA), seed=0)
    engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                    RefineOptions(**{"seed": 3, "explore_probability": 0.0,
                                     "time_limit": 60, **options}))
    try:
        events = list(engine.run())
    finally:
        world.close()
    return engine, events


def test_an_action_failing_in_two_states_is_banned_everywhere():
    plain, plain_events = engine_run(WET, ban_everywhere_after=0)
    engine, events = engine_run(WET, ban_everywhere_after=2)
    assert plain.result().coverage == pytest.approx(1.0)
    assert engine.result().coverage == pytest.approx(1.0)
    notes = [e.detail for e in events if "banned in every state" in e.detail]
    assert len(notes) == 1 and "store_cheap(can0, tiny" in notes[0]
    banned = [a for s, a in engine.planner.forbidden if s == ANY_STATE]
    assert [engine.model.actions[a].name for a in banned] == ["store_cheap"]
    # without it, the same action is tried (and banned) again in sibling states
    retries = Counter(e.kind for e in events)["retry"]
    plain_retries = Counter(e.kind for e in plain_events)["retry"]
    assert retries < plain_retries
    assert not any(s == ANY_STATE for s, _ in plain.planner.forbidden)
    # the final policy stores the can on the tray, never on the cheap shelf
    refined = {engine.model.actions[n.action].name
               for n in engine.best_graph.nodes.values() if n.refined}
    assert "store" in refined and "store_cheap" not in refined


def test_a_ban_everywhere_is_lifted_when_the_goal_needs_the_action():
    # pack: the second store finds no room only because of where the first can went;
    # banned everywhere after one failure, the replan finds no way without it, so the
    # ban is lifted and the first placement re-sampled
    engine, events = engine_run(PACK, seed=0, ban_everywhere_after=1)
    assert engine.result().coverage == pytest.approx(1.0, abs=1e-9)
    assert any("1 ban(s) in every state lifted" in e.detail for e in events)
    assert engine.result().resamples >= 1
    assert not any(s == ANY_STATE for s, _ in engine.planner.forbidden)


def test_negative_ban_threshold_is_refused():
    with pytest.raises(StampcError) as info:
        check_refine_options(RefineOptions(ban_everywhere_after=-1))
    assert info.value.diagnostics[0].code == "R003"


def test_command_line_option(tmp_path, capsys):
    from stampc.cli import main
    files = [str(f) for f in WET]
    code = main(["refine", *files, "--ban-everywhere-after", "2", "--seed", "3",
                 "--explore-probability", "0", "--quiet", "-o", str(tmp_path)])
    assert code == 0
    history = (tmp_path / "prg.json").read_text(encoding="utf-8")
    assert "banned in every state" in history
    capsys.readouterr()
    assert main(["refine", *files, "--ban-everywhere-after", "-1"]) == 2
    assert "--ban-everywhere-after" in capsys.readouterr().err
