"""Read a refine run directory (``stampc refine -o DIR``) for the report.

policy.json is read as ``stampc execute`` reads it (``I003`` when it is not a refined
policy). The other files are optional — a run written by an older stampc has no prg.json,
and execute results or frames exist only when the user put them there — but a file that
is present and malformed is an ``I004`` at its line and column: the report never
silently leaves out what it could not read.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from stampc.diagnostics import Span, StampcError, error

CODES = {"I004": "a run-directory file is not what `stampc refine` / `execute` writes"}
HINT = "pass the directory written by `stampc refine ... -o DIR` (re-run it if a file is damaged)"
COVERAGE_COLUMNS = ("time_s", "coverage", "goal_probability", "refined_nodes", "prg_nodes",
                    "abstract_solves", "event")
#: where execute results are looked for: `stampc execute ... --format json > DIR/execute.json`
EXECUTE_GLOB = "execute*.json"
#: folders (the run dir and its sub-folders, two levels) searched for rendered frames
FRAME_GLOB = "frame_*.png"


@dataclass(frozen=True)
class CoveragePoint:
    time_s: float
    coverage: float
    goal_probability: float
    event: str


@dataclass(frozen=True)
class RunDir:
    path: Path
    policy: Mapping[str, Any]
    summary: Mapping[str, Any] | None
    coverage: tuple[CoveragePoint, ...]
    history: Mapping[str, Any] | None
    executions: tuple[tuple[str, Mapping[str, Any]], ...]
    frames: tuple[Path, ...]


def load_run_dir(path: Path) -> RunDir:
    """Everything ``stampc view`` shows; ``OSError`` (exit 2) when ``path`` is no
    directory, ``StampcError`` (exit 1) for content that is not a refine run's."""
    from stampc.execute.policyfile import load_policy

    if not path.is_dir():
        raise NotADirectoryError(f"cannot read {path}: " + (
            "no such directory" if not path.exists() else "not a directory (pass the folder "
            "given to `stampc refine -o`)"))
    policy_path = path / "policy.json"
    if not policy_path.exists():
        raise StampcError([error("I004", "no policy.json here: not a refine output directory",
                                 Span.point(str(path)), hint=HINT)])
    policy = load_policy(policy_path).data
    _check_nodes(policy, policy_path)
    return RunDir(
        path=path, policy=policy,
        summary=_optional_json(path / "summary.json", lambda d: "coverage" in d),
        coverage=_coverage(path / "coverage.csv"),
        history=_optional_json(path / "prg.json", lambda d: d.get("format") == "stampc-prg"),
        executions=tuple((p.name, _execution(p)) for p in sorted(path.glob(EXECUTE_GLOB))),
        frames=_frames(path))


def _check_nodes(policy: Mapping[str, Any], path: Path) -> None:
    """The node fields the report reads, beyond what ``execute`` checks (I004)."""
    def literals(value: Any) -> bool:
        return isinstance(value, list) and all(
            isinstance(x, dict) and isinstance(x.get("predicate"), str)
            and isinstance(x.get("args"), list) for x in value)

    for i, node in enumerate(policy["nodes"]):
        outcomes = node.get("outcomes", [])
        wrong = [name for name, ok in (
            ("state", isinstance(node.get("state", []), list)),
            ("depth", isinstance(node.get("depth", 0), int)),
            ("learned", isinstance(node.get("learned", []), list) and all(
                isinstance(f, dict) for f in node.get("learned", []))),
            ("sigma", isinstance(node.get("sigma") or {}, dict)),
            ("goal_facts", literals(node.get("goal_facts", []))),
            ("outcomes", isinstance(outcomes, list) and all(
                isinstance(o.get("probability"), (int, float)) and literals(o.get("adds", []))
                and literals(o.get("deletes", [])) for o in outcomes)),
        ) if not ok]
        if wrong:
            raise _bad(path, f"`nodes[{i}]` (id {node['id']}): `{wrong[0]}` is not as "
                             "`stampc refine` writes it")


def _optional_json(path: Path, looks_right) -> Mapping[str, Any] | None:
    if not path.exists():
        return None
    data = _json(path)
    if not isinstance(data, dict) or not looks_right(data):
        raise _bad(path, "not the file `stampc refine` writes under this name")
    return data


def _json(path: Path) -> Any:
    from stampc.inputs import json_problem, read_input_text

    text = read_input_text(path, str(path))
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise _bad(path, f"{json_problem(exc, text)}: {exc.msg}", exc.lineno, exc.colno) from None


def _execution(path: Path) -> Mapping[str, Any]:
    data = _json(path)
    if not isinstance(data, dict) or not {"runs", "success_rate", "outcomes"} <= set(data):
        raise _bad(path, "not an execution report (`stampc execute POLICY --format json`)")
    return data


def _coverage(path: Path) -> tuple[CoveragePoint, ...]:
    if not path.exists():
        return ()
    from stampc.inputs import read_input_text

    rows = list(csv.reader(read_input_text(path, str(path)).splitlines()))
    if tuple(rows[0]) != COVERAGE_COLUMNS:
        raise _bad(path, "unexpected header: expected " + ",".join(COVERAGE_COLUMNS), 1)
    points = []
    for line, row in enumerate(rows[1:], start=2):
        try:
            t, cov, goal = (float(x) for x in row[:3])
            points.append(CoveragePoint(t, cov, goal, row[6]))
        except (ValueError, IndexError):
            raise _bad(path, f"row {line - 1} is not time,coverage,goal_probability,...,event",
                       line) from None
    return tuple(points)


def _frames(path: Path) -> tuple[Path, ...]:
    """PNG frames of `stampc execute --render` in the run dir or a sub-folder (the first
    folder that has any, by name)."""
    for folder in [path, *sorted(p for p in path.iterdir() if p.is_dir()),
                   *sorted(p for p in path.glob("*/*") if p.is_dir())]:
        frames = sorted(folder.glob(FRAME_GLOB))
        if frames:
            return tuple(frames)
    return ()


def _bad(path: Path, message: str, line: int = 1, col: int = 1) -> StampcError:
    return StampcError([error("I004", message, Span.point(str(path), line, col), hint=HINT)])
