"""A bug in the engine does not lose the run: the best policy so far is written with the
traceback in error.txt, the stop reason names the error, and the exit code is 3 (stopped
short) without a traceback on the terminal."""

from __future__ import annotations

import json
from pathlib import Path

from stampc.cli import main
from stampc.refine.engine import Engine

SHELF = Path(__file__).resolve().parents[2] / "examples" / "shelf2d"


def _failing_after(calls: int, monkeypatch):
    real = Engine._refine
    seen = {"n": 0}

    def refine(self, graph, path):
        seen["n"] += 1
        if seen["n"] > calls:
            raise KeyError(1 << 40_000)  # str() of this key fails, as a state's did
        return real(self, graph, path)

    monkeypatch.setattr(Engine, "_refine", refine)
    return seen


def test_an_engine_bug_writes_the_partial_policy_and_exits_3(tmp_path, monkeypatch, capsys):
    seen = _failing_after(2, monkeypatch)
    out = tmp_path / "out"
    code = main(["refine", str(SHELF / "domain.stamp"), str(SHELF / "problem.stamp"),
                 "--world", "plane2d", "--seed", "0", "--quiet", "-o", str(out)])
    err = capsys.readouterr().err
    assert seen["n"] == 3 and code == 3
    assert "bug in stampc" in err and "error.txt" in err and "Traceback" not in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stop_reason"].startswith("internal error: KeyError")
    kinds = [e["kind"] for e in json.loads((out / "prg.json").read_text())["events"]]
    assert len(kinds) >= 3 and kinds[0] == "start"  # the steps before the bug are kept
    trace = (out / "error.txt").read_text()
    assert trace.startswith("Traceback") and "KeyError" in trace and "_refine" in trace
    assert json.loads((out / "policy.json").read_text())["nodes"]


def test_without_an_output_folder_the_bug_is_reported_without_a_traceback(monkeypatch, capsys):
    _failing_after(0, monkeypatch)
    code = main(["refine", str(SHELF / "domain.stamp"), str(SHELF / "problem.stamp"),
                 "--world", "plane2d", "--seed", "0", "--quiet"])
    err = capsys.readouterr().err
    assert code == 3 and "bug in stampc" in err and "-o DIR" in err and "Traceback" not in err
