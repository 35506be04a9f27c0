"""Start-up stays small: the light commands never import simulators, plotting, graph or
template libraries, and a warm grammar cache means `check` never imports Lark.

Timing lives in bench/startup.py; these tests check the property that makes it fast
(which modules a command loads), in a fresh interpreter per command.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
HEAVY = {"pybullet", "ompl", "matplotlib", "networkx", "jinja2", "numpy", "rich", "imageio",
         "pygls", "lsprotocol", "pyvis", "selenium", "cattrs", "igraph"}
DOMINO = [str(REPO / "examples" / "domino" / f) for f in ("domain.stamp", "problem.stamp")]

PROBE = """
import json, sys
sys.path.insert(0, sys.argv[1])
from stampc.cli import main
try:
    code = main(sys.argv[2:])
except SystemExit as exc:
    code = exc.code
print(json.dumps({"code": code, "modules": sorted({m.split('.')[0] for m in sys.modules})}))
"""


def modules_after(argv: list[str], cache: Path | str, cwd: Path) -> tuple[int, set[str]]:
    env = {**os.environ, "STAMPC_CACHE_DIR": str(cache)}
    done = subprocess.run([sys.executable, "-c", PROBE, str(REPO), *argv], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)
    last = done.stdout.strip().splitlines()[-1]
    report = json.loads(last)
    return report["code"], set(report["modules"])


@pytest.mark.parametrize("argv", [
    ["--help"],
    ["check", *DOMINO],
    ["fmt", DOMINO[0]],
    ["solve", *DOMINO, "--unit-cost"],
    ["view", "--help"],
    ["lsp", "--help"],
], ids=["help", "check", "fmt", "solve-stamp", "view-help", "lsp-help"])
def test_light_commands_import_no_heavy_module(argv, tmp_path):
    code, modules = modules_after(argv, tmp_path / "cache", tmp_path)
    assert code == 0
    assert "stampc" in modules  # the probe really ran the command
    assert modules & HEAVY == set()


def test_solve_on_ppddl_imports_no_heavy_module(ppddl_benchmarks, tmp_path):
    problem = ppddl_benchmarks / "ippc2006-tireworld" / "p01.pddl"
    code, modules = modules_after(["solve", str(problem), "--unit-cost"], tmp_path / "c", tmp_path)
    assert code == 0
    assert "stampc" in modules  # the probe really ran the command
    assert "lark" not in modules and modules & HEAVY == set()  # the reader needs no Lark


def test_check_with_a_warm_grammar_cache_never_imports_lark(tmp_path):
    cache = tmp_path / "cache"
    _, first = modules_after(["check", *DOMINO], cache, tmp_path)
    code, second = modules_after(["check", *DOMINO], cache, tmp_path)
    assert "lark" in first          # the first run compiled the grammar ...
    assert any(cache.iterdir())     # ... and stored it
    assert code == 0 and "lark" not in second


def test_refine_still_loads_what_it_needs(tmp_path):
    """The other side of laziness: the modules are imported when really used."""
    code, modules = modules_after(["refine", str(REPO / "examples/shelf2d/domain.stamp"),
                                   str(REPO / "examples/shelf2d/problem.stamp"), "--quiet",
                                   "--time-limit", "20"], tmp_path / "cache", tmp_path)
    assert code in (0, 1)
    assert {"numpy", "networkx"} <= modules
