"""The problem classes of ``bench/paper.py``: the paper's table and the classes beyond it.

Each class names an example folder and the arguments of its generator
(``examples/<name>/scene.py:write_problem(path, seed=..., **kwargs)``), with the paper's
figures where the paper has them. Keva rows belong to the keva example (its generator's
arguments are its own); edit only those rows there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

PAPER_SETUP = ("paper: Fetch (cluttered table), ABB YuMi (domino, Keva), a UAV; OpenRAVE, "
               "Python 2.7, the authors' hardware. Here: Franka Panda(s) (a mobile-base "
               "Panda for the table, two Pandas for Keva), PyBullet 3.2 + OMPL 2.0, Python "
               "3.11, 2 shared cores")


@dataclass(frozen=True)
class ProblemClass:
    """One row: an example folder plus generator arguments, and the paper's figures."""

    name: str
    example: str
    kwargs: tuple[tuple[str, Any], ...]
    paper_solved: float | None  # fraction solved in the paper (None: not attempted)
    paper_time_s: float | None  # the paper's average time (None: not attempted)
    timeout_s: float = 2400.0
    #: how our instances differ from the paper's (printed under the table)
    note: str = ""

    @property
    def beyond(self) -> bool:
        return self.paper_time_s is None


CLUTTERED_NOTE = ("cans uniform at random (0.90 × 0.90 m table; 2.235 × 0.94 m from 30 "
                  "cans), random target, 4 (6 on the large table) base poses 0.23–0.3 m "
                  "from the edges (the Panda reaches ~0.8 m, the Fetch ~1.1 m), delicate "
                  "cans 20 % at 0.5 (mid), others 0.05")
DOMINO_NOTE = ("pybullet_data dominoes 3 cm apart, target drawn among those with k "
               "neighbours on each side, topple 1/(d+1)")
AIRCRAFT_NOTE = "miss 0.10 (mid), any flight drifts with 0.05, battery learned"


def _classes() -> tuple[ProblemClass, ...]:
    out = [ProblemClass(f"cluttered-{n}", "cluttered_table", (("n", n),), solved, t,
                        note=CLUTTERED_NOTE)
           for n, solved, t in ((15, 0.95, 1094.0), (20, 0.79, 1145.0), (25, 0.74, 1393.0))]
    domino = {(10, 2): 99.0, (10, 3): 351.0, (15, 2): 180.0, (15, 3): 632.0,
              (20, 2): 351.0, (20, 3): 591.0}
    out += [ProblemClass(f"domino-n{n}k{k}", "domino", (("n", n), ("k", k)), 1.0, t,
                         note=DOMINO_NOTE)
            for (n, k), t in domino.items()]
    # --- keva rows: owned by the keva example (examples/keva/scene.py:write_problem)
    out += [ProblemClass(name, "keva", (("structure", s), ("levels", levels)), solved, t,
                         4000.0)
            for name, s, levels, solved, t in (("keva-3pi", "pi", 3, 1.0, 1313.0),
                                               ("keva-tower-12", "tower", 12, 1.0, 1900.0),
                                               ("keva-twisted-12", "twisted", 12, 0.98, 1984.0))]
    # --- end of the keva rows
    out.append(ProblemClass("aircraft", "aircraft_inspection", (), 1.0, 1457.0,
                            note=AIRCRAFT_NOTE))
    # beyond the paper (timeouts: the paper's for the domain)
    out += [ProblemClass(f"cluttered-{n}", "cluttered_table", (("n", n),), None, None,
                         note=CLUTTERED_NOTE) for n in (40, 60)]
    out.append(ProblemClass("domino-n40k3", "domino", (("n", 40), ("k", 3)), None, None,
                            note=DOMINO_NOTE))
    # --- keva beyond-paper rows (keva example)
    out += [ProblemClass(name, "keva", (("structure", s), ("levels", levels)), None, None,
                         4000.0)
            for name, s, levels in (("keva-tower-24", "tower", 24),
                                    ("keva-3towers", "3towers", 4))]  # 3 towers x 4 levels
    # --- end of the keva rows
    out.append(ProblemClass("aircraft-2x", "aircraft_inspection", (("parts", 2),), None, None,
                            note=AIRCRAFT_NOTE + "; twice the parts (18), still 3 suspects"))
    return tuple(out)


CLASSES = _classes()
