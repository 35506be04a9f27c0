"""SIGTERM stops ``stampc refine`` like Ctrl-C: the best policy so far is written and the
exit code is 3. Supervisors need this (bench/paper.py stops runs past their deadline with
SIGTERM): a job started in the background of a script ignores SIGINT."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from examples.cluttered_table import scene as ct

DOMAIN = Path(ct.__file__).with_name("domain.stamp")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_sigterm_writes_the_partial_policy_and_exits_3_even_with_sigint_ignored(tmp_path):
    problem = ct.write_problem(tmp_path / "p.stamp", 25, 5)
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "stampc", "refine", str(DOMAIN), str(problem), "--world", "pybullet", "--time-limit", "600", "-o", str(out)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, bufsize=1,
                            env={**os.environ, "PYTHONUNBUFFERED": "1"},
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    try:
        first = proc.stderr.readline()  # the progress display's first line: refining began
        assert "coverage" in first, first
        proc.send_signal(signal.SIGINT)  # ignored, as in a background job of a script
        proc.send_signal(signal.SIGTERM)
        stdout, rest = proc.communicate(timeout=120)
    finally:
        proc.kill()
    assert proc.returncode == 3, rest
    assert "stopped short" in rest and "(interrupted)" in stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["stop_reason"] == "interrupted"
    assert (out / "policy.json").is_file()
