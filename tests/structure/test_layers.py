"""The package layering, read from the source: which stage may import which, and no
import cycles (lazy imports inside functions count; ``if TYPE_CHECKING:`` ones do not)."""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import networkx as nx

ROOT = Path(__file__).resolve().parents[2] / "stampc"

# Each area and the areas it may import (besides itself). Lower stages never reach up:
# the IR does not know the API, the solvers do not know input formats, worlds do not
# know each other.
BASE = {"diagnostics", "grammar_cache", "lazy", "inputs", "gcpause"}
ALLOWED = {
    "diagnostics": set(), "grammar_cache": set(), "lazy": set(), "inputs": {"diagnostics"}, "gcpause": set(),
    # the run's drawings as SVG text (refine writes them, the report shows them)
    "figures": set(),
    # content hashes of a run's inputs (stamp files, used modules, scene builder)
    "provenance": BASE | {"syntax", "semantics", "worlds.modules"},
    "syntax": BASE,
    "semantics": BASE | {"syntax"},
    "ir": BASE | {"syntax", "semantics"},
    "solvers": BASE | {"ir"},
    "backends.ppddl": BASE | {"ir"},
    "worlds.base": BASE | {"ir"},
    "worlds.modules": set(),
    "worlds.bindings": BASE | {"ir", "worlds.base", "worlds.modules"},
    "worlds.loading": BASE | {"ir", "worlds.base", "worlds.bindings", "worlds.modules"},
    "worlds.plane2d": BASE | {"worlds.base"},
    "worlds.pybullet": BASE | {"worlds.base"},
    "refine": BASE | {"ir", "solvers", "worlds.base", "worlds.bindings", "provenance", "figures"},
    # the report reads run directories as `execute` does; it never runs the engine
    "view": BASE | {"execute", "figures"},
    # the language server is the front end's: no IR, solver or world
    "lsp": BASE | {"syntax", "semantics", "commands"},
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def area(module: str) -> str:
    parts = module.split(".")
    if len(parts) >= 3 and parts[1] in ("backends", "worlds"):
        return ".".join(parts[1:3])
    return parts[1] if len(parts) > 1 else "stampc"


def imported(tree: ast.AST) -> list[str]:
    """Absolute ``stampc`` imports anywhere in the module, except under TYPE_CHECKING."""
    found: list[str] = []
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            continue
        if isinstance(node, ast.Import):
            found += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found += [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        found += imported(node)
    return [name for name in found if name == "stampc" or name.startswith("stampc.")]


@functools.lru_cache(maxsize=1)
def import_graph() -> nx.DiGraph:
    modules = {module_name(p): p for p in ROOT.rglob("*.py")}
    graph = nx.DiGraph()
    graph.add_nodes_from(modules)
    for name, path in modules.items():
        for target in imported(ast.parse(path.read_text(encoding="utf-8"))):
            # importing a submodule runs its packages' __init__: not a dependency on them
            if target in modules and target != name and not name.startswith(target + "."):
                graph.add_edge(name, target)
    return graph


def test_the_graph_sees_the_known_edges():
    graph = import_graph()
    assert graph.has_edge("stampc.ir.ground", "stampc.ir.lifted")
    assert graph.has_edge("stampc.api", "stampc.backends.ppddl.model_export")  # lazy import


def test_no_import_cycles():
    cycles = list(nx.simple_cycles(import_graph()))
    assert cycles == [], f"import cycles: {cycles[:5]}"


def test_stages_import_only_the_stages_below_them():
    wrong = sorted({(area(a), area(b), a, b) for a, b in import_graph().edges
                    if area(a) in ALLOWED and area(b) != area(a)
                    and area(b) not in ALLOWED[area(a)]})
    assert wrong == [], "\n".join(f"{x} -> {y}  ({a} imports {b})" for x, y, a, b in wrong)
