"""The dense solver (factored.py, product.py, krylov.py, dense.py, dense_api.py): exact
expectations, bounds that bracket the exact value, agreement with the search solvers."""

from __future__ import annotations

import dataclasses
import json
import random
import time
from fractions import Fraction

import numpy as np
import pytest
from ssp_builders import ModelBuilder, reference_from_above, reference_values

from stampc import api
from stampc.cli import main
from stampc.ir.grounded import GEffect, GProb, GroundModel
from stampc.solvers import SolverOptions, simulate
from stampc.solvers.bounds import solve_bounded
from stampc.solvers.dense import dense_solve
from stampc.solvers.factored import NotFactored, compile_factored
from stampc.solvers.product import expect, make_plan
from stampc.solvers.successors import SuccessorCache

D = 60.0
SYSADMIN = "ippc2008-sysadmin-slp"
SMALL_SYSADMIN = ("p01-n4-l1-s1.pddl", "p02-n5-l2-s2.pddl")  # the oracle uses Fractions: p03 takes 17 s


def test_expect_matches_enumeration():
    rng = np.random.default_rng(3)
    n = 6
    values = rng.random(1 << n)
    rows = np.arange(1 << n)
    # few distinct values per bit (as the plans assume), some deterministic bits
    q = rng.choice([0.0, 1.0, 0.25, 0.9], size=(len(rows), n))
    plan = make_plan(q, rows)
    got = expect(plan, values)
    nexts = np.arange(1 << n)
    bits = (nexts[:, None] >> np.arange(n)) & 1
    for r in range(len(rows)):
        probs = np.prod(np.where(bits == 1, q[r], 1.0 - q[r]), axis=1)
        assert got[r] == pytest.approx(float(probs @ values), abs=1e-12)
        own = (rows[r] >> np.arange(n)) & 1
        assert plan.stay[r] == pytest.approx(float(np.prod(np.where(own == 1, q[r], 1 - q[r]))))


def random_product_model(seed: int, n_facts: int = 5, n_actions: int = 6,
                         free_share: float = 0.0) -> GroundModel:
    """Random SSP whose every probabilistic block changes one fact: the product form,
    with `when` effects, add/delete conflicts and mini-gpt's delete-wins rule."""
    rng = random.Random(seed)
    names = [f"f{i}" for i in range(n_facts)]
    b = ModelBuilder(names)

    def block() -> GProb:
        fact = rng.choice(names)
        outs = [(Fraction(rng.randint(1, 3), 8), b.effect([fact], [], rng.randint(0, 1))),
                (Fraction(rng.randint(0, 2), 8), b.effect([], [fact]))]
        return GProb(tuple(o for o in outs if o[0] > 0))

    for k in range(n_actions):
        whens = [(b.cond(rng.sample(names, 1), []), GEffect(blocks=(block(),))),
                 (b.cond([], rng.sample(names, 1)), b.effect([], rng.sample(names, 1), 1))]
        effect = GEffect(add=b.mask(rng.sample(names, rng.randint(0, 1))),
                         delete=b.mask(rng.sample(names, rng.randint(0, 1))),
                         whens=tuple(whens), blocks=tuple(block() for _ in range(3)))
        free = rng.random() < free_share  # a zero-cost action (its effects cost 1 at most)
        index = b.action(f"p{k}", rng.sample(names, rng.randint(0, 1)), effect=effect,
                         cost=0 if free else rng.randint(1, 3))
        if rng.random() < 0.3:
            b.actions[index] = dataclasses.replace(b.actions[index], delete_wins=True)
    return b.build([n for n in names if rng.random() < 0.3], rng.sample(names, 2))


@pytest.mark.parametrize("first_sweeps", [1, 30])  # policy iteration at once / VI first
def test_dense_bounds_bracket_exact_value(first_sweeps):
    for seed in range(40):
        model = random_product_model(seed)
        exact = reference_values(model, D)[model.init]
        result = dense_solve(compile_factored(model, False), D, 1e-6,
                             first_sweeps=first_sweeps)
        assert result.certified, seed
        assert result.lower - 1e-9 <= exact <= result.upper + 1e-9, (seed, result.lower,
                                                                     exact, result.upper)


def test_zero_cost_actions_keep_the_bounds_valid():
    # value iteration from 0 only (no policy iteration, no δ bound): still a bracket of
    # the optimum where looping forever fails (the greatest fixed point below D)
    for seed in range(30):
        model = random_product_model(seed, free_share=0.5)
        exact = reference_from_above(model, D)[model.init]
        result = dense_solve(compile_factored(model, False), D, 1e-6,
                             deadline=time.perf_counter() + 5)
        assert result.lower - 1e-9 <= exact <= result.upper + 1e-9, seed


def test_dense_agrees_with_lao_on_random_models():
    for seed in range(20):
        model = random_product_model(seed)
        opts = SolverOptions(dead_end_cost=D, epsilon=1e-6)
        _, lao = solve_bounded(model, opts)
        sol, dense = solve_bounded(model, SolverOptions(algorithm="dense", dead_end_cost=D,
                                                        epsilon=1e-6))
        assert sol.table is not None and dense.certified
        assert dense.lower <= lao.upper + 1e-9 and lao.lower <= dense.upper + 1e-9
        # the returned policy is a real one: its simulated cost is near the bound
        assert sol.action(model.init) is None or model.actions[sol.action(model.init)] \
            .precondition.holds(model.init)


def test_blocks_changing_several_facts_do_not_fit():
    b = ModelBuilder(["a", "b"])
    b.action("both", outcomes=[(Fraction(1, 2), ["a", "b"], [])])
    with pytest.raises(NotFactored):
        compile_factored(b.build([], ["a", "b"]), True)


def _sysadmin(benchmarks, name):
    folder = benchmarks / SYSADMIN
    return api.ground(api.load_model([str(folder / name)]))


@pytest.mark.parametrize("name", SMALL_SYSADMIN)
def test_sysadmin_bounds_bracket_vi_and_agree_with_vi_solver(ppddl_benchmarks, name):
    model = _sysadmin(ppddl_benchmarks, name)
    exact = reference_values(model, 500.0, unit_cost=True)[model.init]
    options = SolverOptions(algorithm="dense", unit_cost=True, epsilon=1e-4)
    sol, dense = solve_bounded(model, options)
    assert dense.lower - 1e-9 <= exact <= dense.upper + 1e-9
    assert dense.certified and sol.converged
    _, vi = solve_bounded(model, SolverOptions(algorithm="vi", unit_cost=True,
                                               dead_end_cost=500.0, epsilon=1e-4))
    assert abs(sol.expected_cost - vi.lower) <= 1e-4 * vi.upper


def test_sysadmin_p04_agrees_with_search(ppddl_benchmarks):
    model = _sysadmin(ppddl_benchmarks, "p04-n8-l4-s4.pddl")
    # LAO* asked; 2n + 1 = 17 blocks per action: the dense solver is chosen
    sol, dense = solve_bounded(model, SolverOptions(unit_cost=True, epsilon=1e-6))
    _, vi = solve_bounded(model, SolverOptions(algorithm="vi", unit_cost=True, epsilon=1e-6))
    assert sol.table is not None
    assert dense.lower <= vi.upper + 1e-9 and vi.lower <= dense.upper + 1e-9
    assert dense.upper == pytest.approx(16.730252885, abs=1e-6)  # LAO*'s certified value


def test_search_models_keep_lao(ppddl_benchmarks):
    model = api.ground(api.load_model([str(ppddl_benchmarks / "ippc2006-tireworld/p03.pddl")]))
    sol, _ = solve_bounded(model, SolverOptions(unit_cost=True))
    assert sol.table is None
    few_blocks = _sysadmin(ppddl_benchmarks, "p01-n4-l1-s1.pddl")  # 7 blocks: LAO* is fine
    assert solve_bounded(few_blocks, SolverOptions(unit_cost=True))[0].table is None


def test_block_sampling_follows_the_distribution(ppddl_benchmarks):
    model = _sysadmin(ppddl_benchmarks, "p01-n4-l1-s1.pddl")
    cache = SuccessorCache(model, unit_cost=True)
    state = model.init | 0b0110 << min(i for i, f in enumerate(model.facts)
                                       if f.predicate == "up")
    action = 0
    exact: dict[int, float] = {}
    for p, nxt, _ in cache.float_outcomes(state, action):
        exact[nxt] = exact.get(nxt, 0.0) + p
    rng, counts, runs = random.Random(0), {}, 20_000
    for _ in range(runs):
        nxt, cost = cache.sample_outcome(state, action, rng)
        assert cost == 1.0
        counts[nxt] = counts.get(nxt, 0) + 1
    assert set(counts) <= set(exact)
    for nxt, p in exact.items():
        assert counts.get(nxt, 0) / runs == pytest.approx(p, abs=0.015)


def test_simulation_of_a_dense_policy(ppddl_benchmarks):
    model = _sysadmin(ppddl_benchmarks, "p03-n6-l3-s3.pddl")
    sol, bounds = solve_bounded(model, SolverOptions(unit_cost=True))
    sim = simulate(model, sol, runs=300, seed=1)
    assert sim.goal_rate == 1.0
    assert sim.cost_ci95[0] - 1.0 <= bounds.upper <= sim.cost_ci95[1] + 1.0


def test_cli_dense_json_and_misfit(ppddl_benchmarks, capsys, tmp_path):
    path = ppddl_benchmarks / SYSADMIN / "p02-n5-l2-s2.pddl"
    out = tmp_path / "policy.json"
    code = main(["solve", str(path), "--algorithm", "dense", "--unit-cost", "--format", "json",
                 "-o", str(out)])
    report = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert code == 0 and report["method"] == "dense" and report["certified"]
    policy = json.loads(out.read_text())["policy"]
    assert len(policy) == 32 and policy[0]["state"] == []  # every state, init first
    assert sum(e["status"] == "goal" for e in policy) == 1
    assert all(e["action"].startswith("reboot(") for e in policy if e["status"] == "act")
    assert report["lower_bound"] <= report["upper_bound"] <= report["lower_bound"] * (1 + 1e-4)
    other = ppddl_benchmarks / "ippc2008-blocksworld/p02.pddl"
    code = main(["solve", str(other), "--algorithm", "dense", "--unit-cost"])
    err = capsys.readouterr().err
    assert code == 1 and "S009" in err and "Traceback" not in err
