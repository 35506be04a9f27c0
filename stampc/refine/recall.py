"""Recalling facts learned elsewhere in the run (an extension of UpdateAbstraction).

UpdateAbstraction writes the violated ``?`` facts into the abstract state of the node
where refinement failed, so only the policy *below* that node knows them. Sibling
branches — typically the outcomes of one stochastic action, e.g. "the blocker was
placed aside" and "the blocker was crushed and binned" — were planned before the fact
was learned, and each would learn it again, one UpdateAbstraction round (one abstract
re-solve) per fact. On a cluttered table every crushed can opens such a branch:
cluttered-15 seed 6 learned 217 facts of which only 128 were distinct.

So the engine remembers every learned fact with the concrete values of its arguments
when it was learned (e.g. the trajectory that met the can). At the next UpdateAbstraction
it re-evaluates each remembered fact whose value the node's abstract state still gets
wrong — in *that node's* concrete state, with the node's own values for the symbols bound
on its path and the remembered ones for the rest — and writes those that still hold
together with the facts just learned: one re-solve instead of one per fact. The evidence
is of the same kind as a quick UpdateAbstraction sample (a concrete motion for the
symbol meets that can here); a recalled fact is never used to prove a dead end (the
engine replans without the recalled facts when they leave no way to the goal).
"""

from __future__ import annotations

from typing import Any, Iterable, Iterator, Mapping

from stampc.refine.concretize import Concretizer
from stampc.refine.graph import Concrete


class FactMemory:
    """Every fact learned in the run, with the concrete argument values it was learned with.

    Facts whose arguments were all bound before the failing action (a can's pose: the
    reach of a grasp there) are exact wherever those values hold, so all are kept. Facts
    about a value the action itself *sampled* (the trajectory that met these cans) are
    kept as one group per symbol, the latest sample's: the union of the cans met by
    different samples of one motion is more than any one motion meets."""

    def __init__(self, concretizer: Concretizer):
        self._concretizer = concretizer
        #: fact -> (its learned value, the concrete values of its symbol arguments)
        self._bound: dict[int, tuple[bool, dict[str, Any]]] = {}
        #: sampled symbols -> {fact: (value, evidence)} learned with the latest sample
        self._sampled: dict[tuple[str, ...], dict[int, tuple[bool, dict[str, Any]]]] = {}
        self.recalled = 0  # facts written back by recall (the run's total)
        self.evaluations = 0

    def remember(self, violated: Iterable[tuple[int, bool]], values: Mapping[str, Any],
                 sigma: Mapping[str, Any]) -> None:
        """Record facts learned at a node with path ``values`` and the sample ``sigma``."""
        env = {**values, **sigma}
        groups: dict[tuple[str, ...], dict[int, tuple[bool, dict[str, Any]]]] = {}
        for fact, value in violated:
            args = self._concretizer.symbol_args(fact)
            entry = (value, {a: env[a] for a in args if a in env})
            key = tuple(a for a in args if a in sigma)
            if key:
                groups.setdefault(key, {})[fact] = entry
            else:
                self._bound[fact] = entry
        self._sampled.update(groups)  # a new sample of a symbol replaces the old one's facts

    def _facts(self) -> Iterator[tuple[int, tuple[bool, dict[str, Any]]]]:
        yield from self._bound.items()
        for group in self._sampled.values():
            yield from group.items()

    def recall(self, state: int, concrete: Concrete, values: Mapping[str, Any], *,
               node_uid: int, attempt: int) -> tuple[tuple[int, bool], ...]:
        """Remembered facts that ``state`` (the node's abstract state) gets wrong and that
        hold in the node's concrete state: the node's ``values`` win over remembered ones."""
        out: dict[int, bool] = {}
        for fact, (value, evidence) in self._facts():
            if bool(state >> fact & 1) == value or fact in out:
                continue
            self.evaluations += 1
            actual = self._concretizer.evaluate_at(concrete, fact, {**evidence, **values},
                                                   node_uid=node_uid, attempt=attempt)
            if actual == value:
                out[fact] = value
        self.recalled += len(out)
        return tuple(out.items())
