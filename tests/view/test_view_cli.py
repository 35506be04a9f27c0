"""`stampc view RUN_DIR`: one self-contained HTML file (nothing fetched when it opens),
written next to the run's outputs, and located diagnostics for a damaged run dir."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

from stampc.cli import main
from stampc.view import load_run_dir
from stampc.view.page import render_report


def page_data(html: str) -> dict:
    match = re.search(r'<script id="report-data" type="application/json">(.*?)</script>', html, re.S)
    assert match, "the report carries its data"
    return json.loads(match.group(1))


def test_report_is_written_next_to_the_run_and_self_contained(shelf_run, capsys):
    assert main(["view", str(shelf_run)]) == 0
    report = shelf_run / "report.html"
    assert f"wrote {report}" in capsys.readouterr().out
    html = report.read_text(encoding="utf-8")
    assert len(html.encode()) < 5_000_000
    # offline: no script, style, image or frame from anywhere else
    assert not re.search(r"<(script|img|iframe|link)[^>]+(src|href)=", html)
    assert not re.search(r"@@(TITLE|CSS|VIS_CSS|COVERAGE_SVG|VIS_JS|DATA|JS)@@", html)
    assert "vis.Network" in html and "<svg" in html  # the graph library and the figure


def test_report_data_matches_the_run(shelf_run):
    policy = json.loads((shelf_run / "policy.json").read_text())
    history = json.loads((shelf_run / "prg.json").read_text())
    data = page_data(render_report(load_run_dir(shelf_run)))
    assert [n["id"] for n in data["graph"]["nodes"]] == [n["id"] for n in policy["nodes"]]
    assert data["summary"]["coverage"] == pytest.approx(policy["coverage"])
    assert history["revisions"], "shelf2d learns obstructions: its PRG has revisions"
    assert data["history"]["revisions"] == history["revisions"]
    refined = next(n for n in data["graph"]["nodes"] if n.get("v"))
    assert any(v.startswith("trajectory: ") for v in refined["v"].values())


def test_prg_history_names_the_policy_nodes_it_revised(shelf_run):
    history = json.loads((shelf_run / "prg.json").read_text())
    assert [r["to"] for r in history["revisions"]] == list(range(1, len(history["nodes"])))
    update = next(r for r in history["revisions"] if r["kind"] == "update")
    assert update["facts"] and all("=" in f for f in update["facts"])
    assert isinstance(update["node"], int) and update["time_s"] is not None


def test_execution_results_and_frames_are_included(domino_run, tmp_path):
    out = tmp_path / "r.html"
    assert main(["view", str(domino_run), "-o", str(out)]) == 0
    data = page_data(out.read_text(encoding="utf-8"))
    assert data["executions"][0]["file"] == "execute.json"
    assert data["executions"][0]["runs"] == 3
    assert data["frames"] and all(f.startswith("data:image/png;base64,") for f in data["frames"])
    assert data["frames_dir"] == "frames"
    assert out.stat().st_size < 5_000_000


def copy_run(run: Path, tmp_path: Path) -> Path:
    target = tmp_path / "run"
    shutil.copytree(run, target, ignore=shutil.ignore_patterns("report.html"))
    return target


@pytest.mark.parametrize("name, text, where", [
    ("summary.json", '{"coverage": 1.0,\n  "notes": [', "summary.json:2:13"),
    ("prg.json", '{"format": "something else"}', "prg.json:1:1"),
    ("coverage.csv", "time_s,coverage,goal_probability,refined_nodes,prg_nodes,abstract_solves,"
                     "event\n0.1,0.5,0.5,1,1,1,start\nhalf,way\n", "coverage.csv:3:1"),
    ("execute.json", '{"runs": 3}', "execute.json:1:1"),
])
def test_damaged_run_files_are_located_input_errors(shelf_run, tmp_path, capsys, name, text, where):
    run = copy_run(shelf_run, tmp_path)
    (run / name).write_text(text)
    assert main(["view", str(run)]) == 1
    err = capsys.readouterr().err
    assert f"{where}: I004" in err and "stampc refine" in err  # location, code, hint
    assert not (run / "report.html").exists()


def test_a_damaged_policy_is_i003(shelf_run, tmp_path, capsys):
    run = copy_run(shelf_run, tmp_path)
    (run / "policy.json").write_text('{"format": "stampc-policy", "nodes": [')
    assert main(["view", str(run)]) == 1
    assert "policy.json:1:" in capsys.readouterr().err


@pytest.mark.parametrize("field, value", [
    ("state", 3), ("learned", "x"), ("sigma", [1]), ("outcomes", "half")])
def test_a_policy_node_the_report_cannot_read_is_i004(shelf_run, tmp_path, capsys, field, value):
    run = copy_run(shelf_run, tmp_path)
    policy = json.loads((run / "policy.json").read_text())
    if field == "outcomes":  # a probability that is no number, the child still valid
        policy["nodes"][1]["outcomes"][0]["probability"] = value
    else:
        policy["nodes"][1][field] = value
    (run / "policy.json").write_text(json.dumps(policy))
    assert main(["view", str(run)]) == 1
    err = capsys.readouterr().err
    assert "policy.json:1:1: I004" in err and "`nodes[1]`" in err and f"`{field}`" in err


def test_a_folder_without_policy_is_i004(tmp_path, capsys):
    assert main(["view", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "I004" in err and "no policy.json" in err


@pytest.mark.parametrize("what", ["missing", "file"])
def test_a_path_that_is_no_directory_is_a_usage_error(tmp_path, capsys, what):
    path = tmp_path / "nothing"
    if what == "file":
        path.write_text("x")
    assert main(["view", str(path)]) == 2
    err = capsys.readouterr().err
    assert "stampc view: error:" in err and "Traceback" not in err


def test_an_unwritable_output_is_a_usage_error(shelf_run, tmp_path, capsys):
    assert main(["view", str(shelf_run), "-o", str(tmp_path / "no" / "such" / "r.html")]) == 2
    assert "stampc view: error:" in capsys.readouterr().err


def test_open_hands_the_report_to_the_web_browser(shelf_run, tmp_path, monkeypatch, capsys):
    opened = []
    monkeypatch.setattr("webbrowser.open", lambda url: opened.append(url) or True)
    out = tmp_path / "r.html"
    assert main(["view", str(shelf_run), "-o", str(out), "--open"]) == 0
    assert opened == [out.resolve().as_uri()]
    monkeypatch.setattr("webbrowser.open", lambda url: False)  # no browser on this machine
    assert main(["view", str(shelf_run), "-o", str(out), "--open"]) == 0
    assert "no web browser found" in capsys.readouterr().err
