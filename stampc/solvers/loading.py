"""Loading a ground model from the command line's input files."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Sequence

from stampc.diagnostics import SourceCache, StampcError, render_human, sort_key, summary_line
from stampc.ir.grounded import GroundModel
from stampc.ir.lifted import Model

PPDDL_SUFFIXES = (".pddl", ".ppddl")


def load_lifted(paths: Sequence[Path], lenient: bool = False) -> Model:
    """``.pddl``: the PPDDL importer (a problem-only file finds ``domain.pddl`` beside
    it; ``lenient``: see docs/ppddl.md); anything else: the stamp front end and lowering."""
    if paths[0].suffix.lower() in PPDDL_SUFFIXES:
        from stampc.backends.ppddl.importer import import_ppddl
        return import_ppddl(paths[0], paths[1] if len(paths) > 1 else None, lenient=lenient)
    from stampc.ir.lower import lower
    from stampc.semantics import api
    if len(paths) == 1:
        return lower(api.load(paths[0]))
    return lower(api.load_together(list(paths)))


def load_ground_model(paths: Sequence[str | Path], *, lenient: bool = False,
                      conflicting_effects: str = "add-wins") -> GroundModel:
    """Import or compile, then ground, printing warnings. On bad input print the located
    diagnostics and exit with status 1; on missing/unreadable files or a wrong file count
    exit with status 2. ``lenient`` / ``conflicting_effects``: see ``stampc.api``."""
    files = [Path(p) for p in paths]
    if not 1 <= len(files) <= 2:
        print(f"error: expected DOMAIN [PROBLEM] or one file, got {len(files)} files",
              file=sys.stderr)
        raise SystemExit(2)
    for f in files:
        if not f.is_file():
            print(f"error: no such file: {f}", file=sys.stderr)
            raise SystemExit(2)
    from stampc.ir.ground import ground
    try:
        lifted = load_lifted(files, lenient)
        grounded = ground(lifted, conflicting_effects=conflicting_effects)
    except StampcError as exc:
        sources = SourceCache()
        diags = sorted(exc.diagnostics, key=sort_key)
        for d in diags:
            print(render_human(d, sources), file=sys.stderr)
        print(summary_line(diags), file=sys.stderr)
        raise SystemExit(1) from None
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        raise SystemExit(2) from None
    sources = SourceCache()
    for d in sorted(lifted.diagnostics + grounded.diagnostics, key=sort_key):
        print(render_human(d, sources), file=sys.stderr)
    return grounded
