"""Bad lifted models give located G1xx diagnostics, never bare exceptions."""

from __future__ import annotations

from fractions import Fraction as F

import pytest
from ir_builders import AND, OR, action, add, atom, model, params, pred

from stampc.diagnostics import StampcError
from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.ir.ground_context import GroundingContext
from stampc.ir.reachability import skolem_name


def codes_of(m: L.Model) -> list[str]:
    with pytest.raises(StampcError) as exc:
        ground(m)
    assert all(d.span is not None for d in exc.value.diagnostics)
    return sorted(d.code for d in exc.value.diagnostics)


def test_unknown_type_predicate_arity_object_variable():
    m = model(
        types=(L.Type("loc"),),
        preds=(pred("at", "loc"),),
        actions=(action("go", params(("x", "place")),
                        AND(atom("at", "?x", "?x"), atom("nowhere"), atom("at", "mars"),
                            atom("at", "?y")),
                        add("at", "?x")),),
        objs="a - loc")
    assert codes_of(m) == ["G101", "G102", "G103", "G104", "G105"]


def test_diagnostic_is_located_at_the_action():
    m = model(preds=(pred("p"),), actions=(action("bad", (), atom("q"), add("p")),))
    with pytest.raises(StampcError) as exc:
        ground(m)
    (d,) = exc.value.diagnostics
    assert d.code == "G102" and d.span.file == "bad.stamp" and d.span.line == 3
    assert "'q'" in d.message


def test_missing_function_value_and_division_by_zero():
    fn = L.Function("w", params(("o", "object")))
    m = model(preds=(pred("p"),), functions=(fn,), objs="a b",
              actions=(action("a", params(("o", "object")), L.TRUE, add("p"),
                              cost=L.FuncTerm("w", (L.Var("o"),))),),
              init_values=((atom("w", "a"), F(1)),))
    assert codes_of(m) == ["G106"]
    m2 = model(preds=(pred("p"),),
               actions=(action("a", (), L.TRUE, L.CostEffect(
                   L.BinOp("/", L.Num(F(1)), L.Num(F(0))))),))
    assert codes_of(m2) == ["G110"]
    m3 = model(preds=(pred("p"),), actions=(action("a", (), L.TRUE, L.CostEffect(
        L.FuncTerm("nofn", ()))),))
    assert codes_of(m3) == ["G107"]


def test_type_cycle_and_conflicting_object_types():
    m = model(types=(L.Type("a", "b"), L.Type("b", "a")), objs="x - a")
    assert "G111" in codes_of(m)
    m2 = model(types=(L.Type("a"), L.Type("b")), objs="x - a x - b")
    assert codes_of(m2) == ["G112"]


def test_bad_generator_use_and_bad_probability():
    gen = L.Generator("g", params(("o", "object")), params(("t", "object")), (),
                      L.Binding(".m:g"))
    m = model(preds=(pred("p"),), generators=(gen,), objs="a",
              actions=(action("x", params(("o", "object"), ("t", "object")), L.TRUE, add("p"),
                              generated=(L.GeneratorUse("g", ("o", "zz"), ("t",)),
                                         L.GeneratorUse("nogen", (), ()))),
                       action("y", (), L.TRUE, L.Probabilistic(
                           (L.Outcome(F(-1, 2), add("p")),)))))
    assert codes_of(m) == ["G108", "G109", "G109", "G109"]


def test_skolem_name_clash_with_problem_object():
    gen = L.Generator("g", params(("o", "object")), params(("t", "object")), (),
                      L.Binding(".m:g"))
    clash = skolem_name("t", "x", ("a",))
    m = model(preds=(pred("p", "object"),), generators=(gen,), objs=f"a {clash}",
              actions=(action("x", params(("o", "object"), ("t", "object")), L.TRUE,
                              add("p", "?t"), generated=(L.GeneratorUse("g", ("o",), ("t",)),)),))
    assert codes_of(m) == ["G113"]


def test_context_type_tables():
    m = model(types=(L.Type("v"), L.Type("truck", "v")), objs="t - truck c - v o")
    ctx = GroundingContext(m)
    assert ctx.ancestors("truck") == ("truck", "v", "object")
    assert ctx.objects_of("v") == ("t", "c") and ctx.objects_of("object") == ("t", "c", "o")
    assert ctx.is_of_type("t", "v") and not ctx.is_of_type("c", "truck")


def test_too_many_actions_is_a_diagnostic_not_a_memory_blowup():
    m = model(types=(L.Type("n"),), preds=(pred("p", "n", "n"),),
              actions=(action("any", params(("a", "n"), ("b", "n")), L.TRUE,
                              add("p", "?a", "?b")),),
              objs=" ".join(f"o{i}" for i in range(20)) + " - n")
    assert len(ground(m).actions) == 400
    with pytest.raises(StampcError) as exc:
        ground(m, max_actions=399)
    (d,) = exc.value.diagnostics
    assert d.code == "G114" and d.span.file == "any.stamp" and "399" in d.message


def test_a_binding_derived_twice_counts_once_toward_max_actions():
    # each binding satisfies both disjuncts, so the fixpoint derives it twice (two rules);
    # 400 bindings fit a limit of 400 (they were counted as 800)
    objs = [f"o{i}" for i in range(20)]
    m = model(types=(L.Type("n"),), preds=(pred("p", "n"), pred("q", "n"), pred("r", "n", "n")),
              actions=(action("any", params(("a", "n"), ("b", "n")),
                              OR(atom("p", "?a"), atom("q", "?a")), add("r", "?a", "?b")),),
              objs=" ".join(objs) + " - n",
              init=tuple(atom(k, o) for o in objs for k in ("p", "q")))
    assert len(ground(m, max_actions=400).actions) == 400
    with pytest.raises(StampcError):
        ground(m, max_actions=399)
