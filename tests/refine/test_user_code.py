"""Bound user code that is missing, mis-shaped or failing is reported as a located
diagnostic — never a traceback — both through the API and the CLI."""

from __future__ import annotations

import pytest

import stampc
from stampc.cli import main
from stampc.diagnostics import StampcError
from stampc.refine import RefineOptions

DOMAIN = """\
domain probe
type thing
continuous type token
predicate done(x: thing)
static predicate made(x: thing, k: token)

generator make(x: thing) -> (k: token)
    certifies made(x, k)
    binds "userkit_{tag}:make"

action finish(x: thing, k: token)
    pre  made(x, k)
    eff  done(x)
"""

PROBLEM = """\
problem probe1 for probe
object a: thing
goal done(a)
scene builder "{builder}"(n=1, seed=0, blockers=0)
"""

KITS = {
    "raises": "def make(ctx, x):\n    raise ValueError('no tokens today')\n",
    "arity": "def make(ctx, x):\n    yield (1, 2)\n",
    "signature": "def make(ctx):\n    yield (1,)\n",
    "fine": "def make(ctx, x):\n    yield (42,)\n",
}


@pytest.fixture
def probe(tmp_path, monkeypatch):
    """Write the probe domain bound to the kit ``tag``; returns the two paths."""
    monkeypatch.syspath_prepend(str(tmp_path))

    def make(tag: str, builder: str = "stampc.worlds.plane2d.scenes:cluttered"):
        (tmp_path / f"userkit_{tag}.py").write_text(KITS[tag])
        domain = tmp_path / f"probe_{tag}.stamp"
        domain.write_text(DOMAIN.format(tag=tag))
        problem = tmp_path / "problem.stamp"
        problem.write_text(PROBLEM.format(builder=builder))
        return [domain, problem]

    return make


def codes_of(files) -> list[tuple[str, int]]:
    with pytest.raises(StampcError) as info:
        stampc.refine_policy(files, world="plane2d", options=RefineOptions(time_limit=20))
    return [(d.code, d.span.line) for d in info.value.diagnostics]


def test_a_fine_kit_refines(probe):
    run = stampc.refine_policy(probe("fine"), world="plane2d",
                               options=RefineOptions(time_limit=20))
    assert run.result.coverage == pytest.approx(1.0)
    sigma = [n["sigma"] for n in run.to_json()["nodes"] if n.get("sigma")]
    assert sigma == [{"k_finish_a": 42}]


def test_generator_raising_is_located_at_its_binding(probe):
    assert codes_of(probe("raises")) == [("R201", 9)]


def test_generator_yielding_the_wrong_arity(probe):
    assert codes_of(probe("arity")) == [("R204", 9)]


def test_signature_mismatch_is_found_before_planning(probe):
    assert codes_of(probe("signature")) == [("B104", 9)]


def test_failing_scene_builder_is_located_in_the_problem(probe, tmp_path):
    # a module name no other test writes: `probe` puts tmp_path on sys.path, so the import
    # stays in sys.modules for the rest of the session
    (tmp_path / "dividing_builder.py").write_text("def build(**kw):\n    return 1 / 0\n")
    assert codes_of(probe("fine", builder="dividing_builder:build")) == [("S105", 4)]


def test_cli_prints_the_diagnostic_and_exits_1(probe, capsys):
    files = [str(p) for p in probe("raises")]
    assert main(["refine", *files, "--quiet", "--time-limit", "20"]) == 1
    err = capsys.readouterr().err
    assert "R201" in err and "no tokens today" in err and "Traceback" not in err
    assert 'binds "userkit_raises:make"' in err      # the quoted source line
