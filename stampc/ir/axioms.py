"""Ground axiom programs: derived facts recomputed in every state (PDDL 2.2 axioms).

A recursive derived predicate that reads a fluent (``above(x, y) := on(x, y) or exists
(z) (on(x, z) and above(z, y))``) cannot be substituted away nor computed once, so
:func:`stampc.ir.derived.compile_derived` keeps its axioms and grounding turns them into
an :class:`AxiomProgram`: ground rules ``body -> head`` whose head is a *derived fact*,
grouped in strata (dependencies first). A body is a condition over basic facts, derived
facts of its own stratum (positively) and of lower strata (either polarity).

:meth:`AxiomProgram.close` gives a state's derived facts: all cleared, then each
stratum's rules fire to a fixpoint, in order — the least model of a stratified program,
as in Fast Downward. The initial state and every successor state are closed
(:meth:`stampc.ir.grounded.GroundAction.outcomes` and the solvers' successor cache), so
a state never holds a stale derived fact. Effects never touch derived facts (E311).
The program itself (:class:`stampc.ir.grounded.AxiomProgram`) lives with the grounded
IR; this module builds it.
"""

from __future__ import annotations




from stampc.ir import lifted as L
from stampc.ir.derived import stratify
from stampc.ir.ground_context import located
from stampc.ir.grounded import NO_AXIOMS, AxiomProgram, GOr, GroundAxiom
from stampc.ir.simplify import FactTable, Simplifier, to_condition


def ground_axioms(model: L.Model, simp: Simplifier, table: FactTable) -> AxiomProgram:
    """The ground program of ``model``'s kept axioms: one rule per disjunct of each
    reachable derived fact's simplified definition (conjunctive bodies, as the relaxed
    heuristics want them); rules whose body is false in every state are dropped."""
    axioms = {ax.predicate: ax for ax in model.domain.axioms}
    if not axioms:
        return NO_AXIOMS
    stratum = {name: k for k, group in enumerate(stratify(model)) for name in group}
    rules: list[GroundAxiom] = []
    derived = 0
    for i, (pred, args) in enumerate(table.facts):
        axiom = axioms.get(pred)
        if axiom is None:
            continue
        derived |= 1 << i
        simp.span = located(axiom.span, model)
        body = simp.formula(axiom.body, {p.name: a for p, a in zip(axiom.params, args)})
        for part in body.args if isinstance(body, GOr) else (body,):
            condition = to_condition(part)
            if not condition.never:
                rules.append(GroundAxiom(i, condition, stratum[pred]))
    rules.sort(key=lambda r: (r.stratum, r.head))
    return AxiomProgram(tuple(rules), derived)
