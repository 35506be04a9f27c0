"""PDDL ``:derived`` (axioms): imported into the IR, grounded to the same reachable state
space as the hand-compiled domain (``derived/compiled*.pddl``), emitted compiled away."""

from __future__ import annotations

from pathlib import Path

import pytest

import stampc
from stampc.backends.ppddl import import_ppddl_text

from .states import reachable_fact_sets

HERE = Path(__file__).resolve().parent / "derived"


def imported(domain: str, problem: str):
    return import_ppddl_text((HERE / problem).read_text(), problem,
                             domain_text=(HERE / domain).read_text(), domain_filename=domain)


def states(gm) -> set[frozenset[str]]:
    return reachable_fact_sets(gm, {"on", "fixed"})


def test_derived_domain_imports_with_its_axioms():
    model = imported("domain.pddl", "problem.pddl")
    assert {a.predicate for a in model.domain.axioms} == {"clear", "stacked", "base", "heavier"}
    assert all(p.derived for p in model.domain.predicates if p.name in ("clear", "heavier"))
    assert ":derived-predicates" in model.domain.requirements


def test_same_reachable_state_space_as_the_compiled_away_form():
    derived = stampc.ground(imported("domain.pddl", "problem.pddl"))
    compiled = stampc.ground(imported("compiled.pddl", "compiled-problem.pddl"))
    space = states(derived)
    assert space == states(compiled) and len(space) > 5
    a, b = stampc.solve(derived), stampc.solve(compiled)
    assert a.expected_cost == b.expected_cost and a.goal_probability == b.goal_probability == 1.0


def test_emission_compiles_derived_predicates_away_and_reimports_equal():
    model = imported("domain.pddl", "problem.pddl")
    domain_text, problem_text = stampc.to_ppddl(model)
    assert ":derived" not in domain_text  # neither the section nor the requirement
    assert "(heavier c a)" in problem_text  # the recursive closure, listed
    again = import_ppddl_text(problem_text, "p.pddl", domain_text=domain_text,
                              domain_filename="d.pddl")
    assert states(stampc.ground(again)) == states(stampc.ground(model))


def test_keep_derived_writes_derived_sections_that_reimport_to_the_same_model():
    model = imported("domain.pddl", "problem.pddl")
    domain_text, problem_text = stampc.to_ppddl(model, keep_derived=True)
    assert ":derived-predicates" in domain_text and domain_text.count("(:derived ") == 4
    again = import_ppddl_text(problem_text, "p.pddl", domain_text=domain_text,
                              domain_filename="d.pddl")
    assert {a.predicate for a in again.domain.axioms} == {a.predicate for a in model.domain.axioms}
    assert states(stampc.ground(again)) == states(stampc.ground(model))


def test_stamp_example_with_derived_and_symmetric_predicates_emits_both_ways():
    from stampc.commands import compile as compile_cmd
    from tests.frontend.helpers import REPO, run_command
    files = [str(REPO / "examples" / "warehouse" / f) for f in ("domain.stamp", "problem.stamp")]
    code, out, _ = run_command(compile_cmd, files + ["--target", "ppddl", "--keep-derived"])
    assert code == 0 and "(:derived (open ?a - cell ?b - cell)" in out
    assert "(adjacent cell_1_0 cell_0_0)" in out  # symmetric facts are written both ways
    code, out, _ = run_command(compile_cmd, files + ["--target", "ppddl"])
    assert code == 0 and ":derived" not in out and "(not (rack ?b))" in out


def _ground_codes(domain_text: str) -> list[str]:
    problem = (HERE / "problem.pddl").read_text()
    model = import_ppddl_text(problem, "p.pddl", domain_text=domain_text, domain_filename="d.pddl")
    try:
        stampc.ground(model)
    except stampc.StampcError as exc:
        return [d.code for d in exc.diagnostics]
    return []


def test_unstratified_and_misdeclared_axioms_are_reported_when_grounding():
    domain = (HERE / "domain.pddl").read_text()
    loop = domain.replace("(:derived (base ?a - block) (on ?a table))",
                          "(:derived (base ?a - block) (not (stacked ?a ?a)))\n"
                          "  (:derived (stacked ?a - block ?b - block) (base ?a))")
    assert "G121" in _ground_codes(loop)
    model = imported("domain.pddl", "problem.pddl")
    from dataclasses import replace
    from stampc.ir.lifted import Axiom, Truth
    bad = replace(model, domain=replace(model.domain, axioms=model.domain.axioms + (
        Axiom("nowhere", (), Truth(True)),)))
    with pytest.raises(stampc.StampcError) as info:
        stampc.ground(bad)
    assert [d.code for d in info.value.diagnostics] == ["G120"]
