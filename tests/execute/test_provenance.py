"""Provenance: a policy runs only with the inputs it was refined for (P001-P005), its
paths resolve from the policy's folder, and non-policy JSON is a located I003."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from stampc.cli import main

from .conftest import refine



def execute(policy: Path, *extra: str) -> int:
    return main(["execute", str(policy), "--runs", "3", "--seed", "0", *extra])


def test_paths_are_stored_relative_to_the_policy(shelf: Path) -> None:
    data = json.loads((shelf / "full" / "policy.json").read_text())
    assert data["files"] == ["../domain.stamp", "../problem.stamp"]
    inputs = data["provenance"]["inputs"]
    assert [Path(e["absolute"]) for e in inputs] == [shelf / "domain.stamp",
                                                     shelf / "problem.stamp"]
    assert "manipulation.stamp" in data["provenance"]["modules"]


def test_a_moved_folder_still_executes(shelf: Path, tmp_path: Path, capsys) -> None:
    moved = tmp_path / "moved"
    shutil.copytree(shelf, moved)
    shutil.move(str(shelf / "full"), str(tmp_path / "aside"))  # no absolute fallback
    try:
        assert execute(moved / "full" / "policy.json") == 0
    finally:
        shutil.move(str(tmp_path / "aside"), str(shelf / "full"))
    assert "runs 3: success 3" in capsys.readouterr().out


def test_policy_from_another_problem_is_refused(shelf: Path, tmp_path: Path, capsys) -> None:
    other = tmp_path / "other"
    other.mkdir()
    shutil.copy(shelf / "domain.stamp", other / "domain.stamp")
    text = (shelf / "problem.stamp").read_text().replace("seed=2", "seed=3")
    (other / "problem.stamp").write_text(text)
    (other / "out").mkdir()
    shutil.copy(shelf / "full" / "policy.json", other / "out" / "policy.json")
    assert execute(other / "out" / "policy.json") == 1
    err = capsys.readouterr().err
    assert "P003" in err and "problem.stamp" in err and "sha256 mismatch" in err
    assert "policy.json:" in err  # located in the policy file


def test_edited_stored_scene_is_refused(shelf: Path, tmp_path: Path, capsys) -> None:
    data = json.loads((shelf / "full" / "policy.json").read_text())
    data["scene"]["objects"][0]["x"] = data["scene"]["objects"][0].get("x", 0) + 0.1
    target = shelf / "full" / "swapped.json"
    target.write_text(json.dumps(data, indent=1))
    try:
        assert execute(target) == 1
    finally:
        target.unlink()
    assert "P004" in capsys.readouterr().err


def test_policy_without_provenance_is_refused(shelf: Path, capsys) -> None:
    data = json.loads((shelf / "full" / "policy.json").read_text())
    del data["provenance"]
    target = shelf / "full" / "old.json"
    target.write_text(json.dumps(data))
    try:
        assert execute(target) == 1
    finally:
        target.unlink()
    assert "P001" in capsys.readouterr().err


def test_truncated_policy_is_located(shelf: Path, tmp_path: Path, capsys) -> None:
    """A cut file is called truncated wherever the cut falls: between tokens or inside a
    string (which the parser reports where the string starts); a damaged one is not."""
    text = (shelf / "full" / "policy.json").read_text()
    bad = tmp_path / "policy.json"
    inside = text.index('": "', len(text) // 2) + 5  # inside a string value
    between = text.index(",", len(text) // 2) + 1
    for cut in (inside, between, len(text) // 3):
        bad.write_text(text[:cut])
        assert execute(bad) == 1
        err = capsys.readouterr().err
        assert "I003" in err and "truncated JSON" in err and "policy.json:" in err
    bad.write_text(text[:between] + " ]] " + text[between:])
    assert execute(bad) == 1
    err = capsys.readouterr().err
    assert "I003" in err and "not valid JSON" in err


def test_abstract_policy_from_solve_is_named(shelf: Path, tmp_path: Path, capsys) -> None:
    out = tmp_path / "abstract.json"
    assert main(["solve", str(shelf / "domain.stamp"), str(shelf / "problem.stamp"),
                 "-o", str(out)]) == 0
    capsys.readouterr()
    assert execute(out) == 1
    err = capsys.readouterr().err
    assert "I003" in err and "stampc solve" in err and "refine it first" in err


def test_swapped_scene_builder_is_refused(shelf: Path, tmp_path: Path, capsys) -> None:
    folder = tmp_path / "own"
    folder.mkdir()
    shutil.copy(shelf / "domain.stamp", folder / "domain.stamp")
    builder = "from stampc.worlds.plane2d.scenes import cluttered as build\n"
    (folder / "myscene.py").write_text(builder)
    text = (shelf / "problem.stamp").read_text().replace(
        "stampc.worlds.plane2d.scenes:cluttered", "myscene:build")
    (folder / "problem.stamp").write_text(text)
    policy = refine(folder, "out")
    capsys.readouterr()
    (folder / "myscene.py").write_text(builder + "# another scene\n")
    assert execute(policy) == 1
    err = capsys.readouterr().err
    assert "P003" in err and "scene builder module" in err and "myscene.py" in err
