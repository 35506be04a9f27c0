"""Provenance of a refined policy: which inputs it was refined for, by content.

``stampc refine`` records in policy.json (key ``provenance``) the sha256 of

* every input file (domain, problem), under ``inputs`` (path relative to the policy file,
  absolute path as a fallback, hash);
* every module the domain ``use``s (stdlib or file), under ``modules`` (file name -> hash);
* the scene's source: the builder module's file (or the scene JSON file) with the
  builder's target, arguments and ``--scene-arg`` overrides, under ``scene_source``;
* the scene dict stored in the policy (canonical JSON) and the world, ``scene_sha256`` and
  ``world``.

``stampc execute`` resolves each input relative to the policy file's folder (the recorded
absolute path only when the relative one does not exist) and refuses any mismatch with a
located ``P0xx`` diagnostic (exit 1) — a policy moved next to another problem, an edited
domain, a swapped scene builder or an edited stored scene.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Any, Mapping, Sequence

from stampc.diagnostics import Diagnostic, Span, StampcError, error

VERSION = 1
CODES = {
    "P001": "the policy has no provenance record",
    "P002": "an input of the policy cannot be found",
    "P003": "an input's content differs from the one the policy was refined for",
    "P004": "the scene stored in the policy differs from the recorded one",
    "P005": "the world differs from the recorded one",
}


def sha256_bytes(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def sha256_file(path: Path) -> str:
    return sha256_bytes(path.read_bytes())


def scene_hash(scene: Any) -> str:
    """Hash of a scene dict, independent of key order and float formatting noise."""
    return sha256_bytes(json.dumps(scene, sort_keys=True, separators=(",", ":"),
                                   default=str).encode("utf-8"))


# ------------------------------------------------------------------ recording
def record(paths: Sequence[Path], world: str, scene: Mapping[str, Any],
           scene_source: Mapping[str, Any] | None) -> dict:
    """The provenance of a policy refined from ``paths`` (absolute paths recorded; made
    relative to the policy file by :func:`relative_to`)."""
    inputs = [{"path": str(p.resolve()), "absolute": str(p.resolve()),
               "sha256": sha256_file(p)} for p in paths]
    return {"version": VERSION, "inputs": inputs, "modules": used_modules(paths),
            "scene_source": dict(scene_source or {}), "scene_sha256": scene_hash(scene),
            "world": world}


def used_modules(paths: Sequence[Path]) -> dict[str, str]:
    """sha256 of every stamp source the inputs ``use`` (not the inputs themselves), by
    file name; PPDDL inputs use nothing."""
    if not paths or paths[0].suffix.lower() in (".pddl", ".ppddl"):
        return {}
    from stampc.semantics.api import load_together

    inputs = {p.resolve() for p in paths}
    out: dict[str, str] = {}
    for name, text in load_together(list(paths)).sources.items():
        path = Path(name)
        if path.resolve() in inputs or name.startswith("<"):
            continue
        out[path.name] = sha256_bytes(text.encode("utf-8"))
    return dict(sorted(out.items()))


def builder_source(ref: Any, base_dir: Path, overrides: Mapping[str, Any] | None) -> dict:
    """The ``scene_source`` entry of a problem's scene reference (file or builder)."""
    if ref is None:
        return {}
    if ref.kind == "file":
        path = (base_dir / ref.target).resolve()
        return {"kind": "file", "target": ref.target, **_file_entry(path)}
    from stampc.worlds.modules import import_bound_module

    module_name = ref.target.partition(":")[0]
    module = import_bound_module(module_name, base_dir)  # already loaded by load_scene
    entry: dict[str, Any] = {"kind": "builder", "target": ref.target,
                             "args": {k: v for k, v in dict(ref.args).items()},
                             "overrides": dict(overrides or {})}
    origin = getattr(module, "__file__", None)
    if origin:
        entry.update(_file_entry(Path(origin).resolve()))
    return entry


def _file_entry(path: Path) -> dict:
    return {"path": str(path), "absolute": str(path), "sha256": sha256_file(path)}


def relative_to(provenance: Mapping[str, Any], folder: Path) -> dict:
    """``provenance`` with its recorded paths relative to ``folder`` (the policy's)."""
    out = json.loads(json.dumps(provenance))
    for entry in out.get("inputs", []) + ([out["scene_source"]]
                                          if "path" in out.get("scene_source", {}) else []):
        entry["path"] = _relative(Path(entry["absolute"]), folder)
    return out


def _relative(path: Path, folder: Path) -> str:
    try:
        return Path(os.path.relpath(path, folder.resolve())).as_posix()
    except ValueError:  # another drive (Windows): keep it absolute
        return str(path)


# ------------------------------------------------------------------ verifying
def verify(policy: Mapping[str, Any], policy_path: Path, text: str) -> list[Path]:
    """The policy's input files, resolved and checked against their recorded hashes;
    :class:`StampcError` (P001-P005) on any mismatch. ``text`` is the policy file's
    JSON, to locate each complaint on its line."""
    shown = str(policy_path)
    prov = policy.get("provenance")
    if not isinstance(prov, Mapping) or not isinstance(prov.get("inputs"), list):
        raise StampcError([error("P001", "the policy has no provenance record, so nothing "
                                 "shows which problem it belongs to", Span.point(shown),
                                 hint="refine again with this version of stampc: "
                                      "`stampc refine ... -o DIR` records it")])
    folder = policy_path.resolve().parent
    diags: list[Diagnostic] = []
    files = [_check_entry(e, folder, text, shown, diags, "input") for e in prov["inputs"]]
    source = prov.get("scene_source") or {}
    if isinstance(source, Mapping) and "sha256" in source:
        _check_entry(source, folder, text, shown, diags,
                     "scene builder module" if source.get("kind") == "builder" else "scene file")
    if files and all(f is not None for f in files) and not diags:
        _check_modules(prov, [f for f in files if f is not None], text, shown, diags)
    if prov.get("scene_sha256") != scene_hash(policy.get("scene")):
        diags.append(error("P004", "the scene stored in this policy is not the scene it was "
                           "refined in (its hash differs)", _locate(text, shown, '"scene"'),
                           hint="the policy's `scene` was edited or swapped: refine again "
                                "on the scene you want to execute in"))
    if prov.get("world") != policy.get("world"):
        diags.append(error("P005", f"the policy names world {policy.get('world')!r} but was "
                           f"refined in {prov.get('world')!r}", _locate(text, shown, '"world"'),
                           hint="refine again with `--world` set to the world to execute in"))
    if diags:
        raise StampcError(diags)
    return [f for f in files if f is not None]


def _check_entry(entry: Any, folder: Path, text: str, shown: str, diags: list[Diagnostic],
                 what: str) -> Path | None:
    if not isinstance(entry, Mapping) or not isinstance(entry.get("path"), str):
        diags.append(error("P001", f"malformed provenance entry for an {what}: {entry!r}",
                           _locate(text, shown, '"provenance"')))
        return None
    here = _locate(text, shown, json.dumps(entry["path"]))
    path = resolve(entry, folder)
    if path is None:
        diags.append(error("P002", f"{what} {entry['path']!r} (relative to the policy file) "
                           "not found", here,
                           hint=f"keep the policy beside its inputs; also tried "
                                f"{entry.get('absolute')!r}"))
        return None
    if sha256_file(path) != entry.get("sha256"):
        diags.append(error("P003", f"{what} {path} differs from the one this policy was "
                           "refined for (sha256 mismatch)", here,
                           hint="the policy belongs to another problem or an older version "
                                "of this file: refine again, or execute the policy "
                                "refined for this file"))
    return path


def resolve(entry: Mapping[str, Any], folder: Path) -> Path | None:
    """The recorded path relative to ``folder`` if it is a file, else the absolute one."""
    for candidate in (folder / entry["path"], Path(str(entry.get("absolute", "")))):
        if str(candidate) and candidate.is_file():
            return candidate
    return None


def _check_modules(prov: Mapping[str, Any], files: list[Path], text: str, shown: str,
                   diags: list[Diagnostic]) -> None:
    recorded = prov.get("modules", {})
    try:
        current = used_modules(files)
    except StampcError as exc:
        diags.extend(exc.diagnostics)
        return
    for name in sorted(set(recorded) | set(current)):
        if recorded.get(name) != current.get(name):
            state = ("is no longer used" if name not in current else
                     "was not used when the policy was refined" if name not in recorded
                     else "changed since the policy was refined")
            diags.append(error("P003", f"used module {name} {state} (sha256 mismatch)",
                               _locate(text, shown, '"modules"'),
                               hint="refine again against the current stdlib and modules"))


def _locate(text: str, shown: str, needle: str) -> Span:
    """The line and column of ``needle`` in the policy's JSON text."""
    offset = text.find(needle)
    if offset < 0:
        return Span.point(shown)
    line = text.count("\n", 0, offset) + 1
    col = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return Span(shown, line, col, line, col + len(needle))


def anchored(meta: Mapping[str, Any], folder: Path) -> dict:
    """A policy's ``meta`` as written into ``folder``: provenance paths and ``files``
    relative to it (the absolute paths stay in ``provenance`` as the fallback)."""
    out = dict(meta)
    if isinstance(meta.get("provenance"), Mapping):
        out["provenance"] = relative_to(meta["provenance"], folder)
        out["files"] = [e["path"] for e in out["provenance"]["inputs"]]
    return out
