"""Recalling facts learned elsewhere in the run (an extension of UpdateAbstraction).

UpdateAbstraction writes the violated ``?`` facts into the abstract state of the node
where refinement failed, so only the policy *below* that node knows them. Sibling
branches — typically the outcomes of one stochastic action, e.g. "the blocker was
placed aside" and "the blocker was crushed and binned" — were planned before the fact
was learned, and each would learn it again, one UpdateAbstraction round (one abstract
re-solve) per fact. On a cluttered table every crushed can opens such a branch:
cluttered-15 seed 6 learned 217 facts of which only 128 were distinct.

So the engine remembers the learned facts that can be decided before an action samples
anything: those about values bound when the action starts, such as the reach of a grasp
of a can at its pose (``reaches(b0, can5, pose_can5)`` was learned 13 times in that
run). At the next UpdateAbstraction it re-evaluates, in the failing node's concrete
state, each remembered fact that the node's abstract state still gets wrong and whose
arguments the node's path binds, and writes those that hold together with the facts
just learned: one re-solve instead of one per fact. These are exactly the facts the
node would learn by trying those actions.

Facts about a value the checking action samples itself (the trajectory that met these
cans) are not remembered: another node's trajectory — or one bound earlier on the path —
says nothing about the fresh motion the action will plan, and recalling them made the
measured runs worse (docs/refine.md, "Recalling learned facts").
"""

from __future__ import annotations

from typing import Any, Iterable, Mapping

from stampc.refine.concretize import Concretizer
from stampc.refine.graph import Concrete


class FactMemory:
    """Every fact learned in the run, recalled where it can be decided exactly."""

    def __init__(self, concretizer: Concretizer):
        self._concretizer = concretizer
        self._facts: dict[int, bool] = {}  # fact -> the value it was last learned with
        self._sampled: frozenset[int] | None = None  # built on first use
        self.recalled = 0  # facts written back by recall (the run's total)
        self.evaluations = 0

    def remember(self, violated: Iterable[tuple[int, bool]]) -> None:
        if self._sampled is None:
            self._sampled = self._concretizer.sampled_checks()
        self._facts.update((f, v) for f, v in violated if f not in self._sampled)

    def recall(self, state: int, concrete: Concrete, values: Mapping[str, Any], *,
               node_uid: int, attempt: int) -> tuple[tuple[int, bool], ...]:
        """Remembered facts that ``state`` (the node's abstract state) gets wrong, whose
        arguments ``values`` (the node's path) all bind, and that hold in the node's
        concrete state."""
        out = []
        for fact, value in self._facts.items():
            if bool(state >> fact & 1) == value or not self._decidable(fact, values):
                continue
            self.evaluations += 1
            actual = self._concretizer.evaluate_at(concrete, fact, values,
                                                   node_uid=node_uid, attempt=attempt)
            if actual == value:
                out.append((fact, value))
        self.recalled += len(out)
        return tuple(out)

    def _decidable(self, fact: int, values: Mapping[str, Any]) -> bool:
        return all(a in values for a in self._concretizer.symbol_args(fact))
