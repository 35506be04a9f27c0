"""The execution report: runs, successes with a 95 % Wilson interval, unrefined
branches, collisions, goal-check failures and per-action outcome frequencies against
the model's (and the truth's) probabilities; as text or JSON."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Mapping

from stampc.execute.runner import Run
from stampc.refine.replay import DEAD_END, FAILURE, SUCCESS, UNREFINED
from stampc.solvers.simulation import wilson_interval

Z99 = 2.5758293035489004  # two-sided 99 % normal quantile


@dataclass(frozen=True)
class ExecutionReport:
    runs: tuple[Run, ...]
    #: probability of success the policy promises under the truth model (exact)
    predicted: float
    coverage: float
    goal_probability: float
    truth: Mapping[str, float]

    def count(self, status: str) -> int:
        return sum(1 for r in self.runs if r.status == status)

    @property
    def success_rate(self) -> float:
        return self.count(SUCCESS) / len(self.runs) if self.runs else 0.0

    def interval(self, z: float | None = None) -> tuple[float, float]:
        n = len(self.runs)
        return wilson_interval(self.count(SUCCESS), n) if z is None else \
            wilson_interval(self.count(SUCCESS), n, z)

    @property
    def collisions(self) -> int:
        return sum(len(r.collisions) for r in self.runs)

    @property
    def goal_failures(self) -> int:
        return sum(1 for r in self.runs if r.goal_failures)

    @property
    def ok(self) -> bool:
        """No failure on a refined branch: every run that stayed on the refined policy
        reached the goal (or a proven dead end), without collisions."""
        return self.count(FAILURE) == 0 and self.collisions == 0

    def outcome_table(self) -> dict[str, dict[str, dict[str, float]]]:
        """action -> outcome -> {observed, model, truth} frequencies per execution."""
        table: dict[str, dict[str, dict[str, float]]] = {}
        executed: dict[str, int] = {}
        for run in self.runs:
            for s in run.steps:
                executed[s.schema] = executed.get(s.schema, 0) + 1
                row = table.setdefault(s.schema, {})
                for name in set(s.model) | set(s.truth) | {s.outcome}:
                    cell = row.setdefault(name, {"count": 0, "model": 0.0, "truth": 0.0})
                    cell["model"] += s.model.get(name, 0.0)
                    cell["truth"] += s.truth.get(name, 0.0)
                row[s.outcome]["count"] += 1
        out: dict[str, dict[str, dict[str, float]]] = {}
        for action, row in sorted(table.items()):
            n = executed[action]
            out[action] = {name: {"executions": n, "observed": c["count"] / n,
                                  "model": c["model"] / n, "truth": c["truth"] / n}
                           for name, c in sorted(row.items())}
        return out

    def to_json(self) -> dict[str, Any]:
        lo, hi = self.interval()
        return {
            "runs": len(self.runs), "success": self.count(SUCCESS),
            "success_rate": self.success_rate, "success_ci95": [lo, hi],
            "predicted_success": self.predicted, "coverage": self.coverage,
            "goal_probability": self.goal_probability,
            "coverage_x_goal_probability": self.coverage * self.goal_probability,
            "failure": self.count(FAILURE), "dead_end": self.count(DEAD_END),
            "unrefined": self.count(UNREFINED), "collisions": self.collisions,
            "goal_check_failures": self.goal_failures, "truth": dict(self.truth),
            "outcomes": self.outcome_table(),
            "failures": [{"run": i, "detail": r.detail, "collisions": list(r.collisions)}
                         for i, r in enumerate(self.runs)
                         if r.status == FAILURE or r.collisions][:20],
        }

    def text(self) -> str:
        d = self.to_json()
        lo, hi = d["success_ci95"]
        lines = [
            f"runs {d['runs']}: success {d['success']} ({d['success_rate']:.3f}, 95% Wilson "
            f"[{lo:.3f}, {hi:.3f}]), failure {d['failure']}, dead end {d['dead_end']}, "
            f"unrefined branch reached {d['unrefined']} (never counted as success)",
            f"predicted success under the truth model {d['predicted_success']:.3f}; coverage "
            f"{d['coverage']:.3f} x goal probability {d['goal_probability']:.3f} = "
            f"{d['coverage_x_goal_probability']:.3f}",
            f"collisions at 10x resolution {d['collisions']}; goal-check failures "
            f"{d['goal_check_failures']}"
            + (f"; truth {', '.join(f'{k}={v:g}' for k, v in d['truth'].items())}"
               if d["truth"] else ""),
            "outcome frequencies (observed / model / truth):",
        ]
        for action, row in d["outcomes"].items():
            n = next(iter(row.values()))["executions"]
            cells = ", ".join(f"{name} {c['observed']:.3f}/{c['model']:.3f}/{c['truth']:.3f}"
                              for name, c in row.items())
            lines.append(f"  {action} ({n}x): {cells}")
        for f in d["failures"][:5]:
            lines.append(f"  run {f['run']}: {f['detail'] or 'collision'}"
                         + (f" [{'; '.join(f['collisions'][:3])}]" if f["collisions"] else ""))
        return "\n".join(lines)

    def render(self, fmt: str) -> str:
        return json.dumps(self.to_json(), indent=2) if fmt == "json" else self.text()
