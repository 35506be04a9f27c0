"""PPDDL for a compiled model: grounding makes generated (continuous) parameters'
Skolem symbols and certified facts explicit, which a PPDDL planner needs to see."""

from __future__ import annotations

from stampc.backends.ppddl.emitter import emit_ppddl
from stampc.ir.ground import ground
from stampc.ir.lifted import Atom, Const, Model, Object


def model_to_ppddl(model: Model, *, keep_derived: bool = False) -> tuple[str, str]:
    """PPDDL (domain, problem) text. Generated parameters stay parameters; grounding
    supplies their Skolem symbols and the certified facts that bind them."""
    gm = ground(model)
    known = {o.name for o in model.problem.objects} | {c.name for c in model.domain.constants}
    symbols = tuple(Object(n, t, symbolic=True) for n, t in gm.objects if n not in known)
    certified = {a.predicate for g in model.domain.generators for a in g.certifies}
    # `?` facts assumed true (optimistic) start true: PPDDL needs them in :init
    assumed = {p.name for p in model.domain.predicates if p.unknowable and p.optimistic}
    initial = set(model.problem.init)
    facts = tuple(Atom(f.predicate, tuple(Const(a) for a in f.args))
                  for f in gm.static_facts if f.predicate in certified)
    facts += tuple(atom for atom in (Atom(f.predicate, tuple(Const(a) for a in f.args))
                                     for f in gm.state_facts(gm.init) if f.predicate in assumed)
                   if atom not in initial)
    return emit_ppddl(model, extra_objects=symbols, extra_init=facts, keep_derived=keep_derived)
