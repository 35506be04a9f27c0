"""Facts of unknowable (``?``) predicates are decided by refinement in the world, not by
the actions: the grounder keeps them in preconditions even when no action can set them.
(Pruned as never-true, the domino pick's ``not collision(x, t)`` for the dominoes that no
action moves was never checked, and `stampc execute` found the fingers in the row.)"""

from __future__ import annotations

from pathlib import Path

import stampc
from examples.domino import scene as domino

REPO = Path(__file__).resolve().parents[2]


def test_collision_checks_survive_for_objects_no_action_moves(tmp_path):
    problem = domino.write_problem(tmp_path / "p.stamp", seed=2, n=10, k=2)
    gm = stampc.ground(stampc.compile(str(REPO / "examples" / "domino" / "domain.stamp"), str(problem)))
    facts = {i: f for i, f in enumerate(gm.facts)}
    picks = [a for a in gm.actions if a.name == "pick"]
    assert picks
    for a in picks:
        checked = {facts[i].args[0] for i in range(len(facts))
                   if a.precondition.neg_facts >> i & 1 and facts[i].predicate == "collision"}
        others = {o for o, t in gm.objects if t == "domino"} - {a.args[0]}
        assert others <= checked, f"unchecked: {sorted(others - checked)}"
    # they start false (the abstraction's optimistic value) until refinement learns them
    collision = [i for i, f in facts.items() if f.predicate == "collision"]
    assert collision and not any(gm.init >> i & 1 for i in collision)
