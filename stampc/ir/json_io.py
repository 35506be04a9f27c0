"""Versioned JSON form of the lifted and grounded IR (format: docs/ir.md).

Every document carries ``"ir_version"`` (:data:`stampc.ir.lifted.IR_VERSION`) and
``"kind"`` (``"lifted"`` or ``"grounded"``). Fractions are strings (``"1/3"``), state
bitmasks are sorted lists of fact indices; grounded documents keep the IR factored in a
shared node table (:mod:`stampc.ir.json_grounded`). :func:`write_lifted_json` and
:func:`write_grounded_json` stream to a text file; the ``*_to_json`` functions give the
same document as a dict. Loading checks version and kind and reports malformed input as
located diagnostics (G190-G192), never as bare exceptions. A round trip gives an equal
object (``==``); neither direction recurses on the input's nesting.
"""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any, Callable, TextIO, TypeVar

from stampc.diagnostics import Span, StampcError, error
from stampc.ir import lifted as L
from stampc.gcpause import no_gc_pauses
from stampc.ir.grounded import GroundModel
from stampc.ir.json_grounded import bits_to_list, list_to_bits, read_grounded, write_grounded
from stampc.ir.json_model import read_lifted, write_lifted
from stampc.ir.json_v1 import V1, upgrade

__all__ = ["lifted_to_json", "lifted_from_json", "grounded_to_json", "grounded_from_json",
           "write_lifted_json", "write_grounded_json", "read_ir_json",
           "bits_to_list", "list_to_bits"]

T = TypeVar("T")
V2_0 = "2.0"  # 2.1 and 2.2 only added optional fields (docs/ir.md, "Format versions")
V2_1 = "2.1"

def _check_header(data: Any, kind: str, source: str) -> Any:
    """``data`` as a current document of ``kind`` (1.0 documents are upgraded)."""
    span = Span.point(source)
    if not isinstance(data, dict):
        raise StampcError([error("G192", f"expected a JSON object for the {kind} IR, "
                                 f"got {type(data).__name__}", span)])
    version = data.get("ir_version")
    if version not in (L.IR_VERSION, V2_1, V2_0, V1):
        raise StampcError([error(
            "G190", f"unsupported IR version {version!r} (this stampc reads "
            f"{L.IR_VERSION!r}, {V2_1!r}, {V2_0!r} and {V1!r})", span,
            "recompile the source with `stampc compile --target ir` "
            "(docs/ir.md, 'Format versions')")])
    if data.get("kind") != kind:
        raise StampcError([error("G191", f"expected a {kind!r} IR document, "
                                 f"got kind {data.get('kind')!r}", span)])
    if version == V1:
        return _decode(kind, source, lambda: upgrade(data, L.IR_VERSION))
    return data


def _decode(kind: str, source: str, fn: Callable[[], T]) -> T:
    try:
        return fn()
    except StampcError:
        raise
    except (KeyError, TypeError, ValueError, IndexError, AttributeError,
            ZeroDivisionError) as exc:
        detail = f"missing field {exc}" if isinstance(exc, KeyError) else str(exc)
        raise StampcError([error("G192", f"malformed {kind} IR document: {detail}",
                                 Span.point(source))]) from None


def _header(kind: str) -> dict:
    return {"ir_version": L.IR_VERSION, "kind": kind}


# ------------------------------------------------------------------ writing
def write_lifted_json(model: L.Model, out: TextIO) -> None:
    """Stream the lifted document of ``model`` to ``out`` (one action per line)."""
    with no_gc_pauses():
        write_lifted(model, _header("lifted"), out.write)
    out.write("\n")


def write_grounded_json(gm: GroundModel, out: TextIO, *, include_lifted: bool = True) -> None:
    """Stream the grounded document of ``gm`` to ``out``; embeds the lifted model (if any)
    unless told not to."""
    lifted = gm.lifted if include_lifted else None
    with no_gc_pauses():
        write_grounded(gm, _header("grounded"), out.write, None if lifted is None else
                       lambda: write_lifted(lifted, _header("lifted"), out.write))


def lifted_to_json(model: L.Model) -> dict:
    """The lifted document as a dict (what :func:`write_lifted_json` writes)."""
    buf = io.StringIO()
    write_lifted_json(model, buf)
    return json.loads(buf.getvalue())


def grounded_to_json(gm: GroundModel, *, include_lifted: bool = True) -> dict:
    """The grounded document as a dict (what :func:`write_grounded_json` writes)."""
    buf = io.StringIO()
    write_grounded_json(gm, buf, include_lifted=include_lifted)
    return json.loads(buf.getvalue())


# ------------------------------------------------------------------ reading
def lifted_from_json(data: dict, *, source: str = "<json>") -> L.Model:
    """Inverse of :func:`lifted_to_json`; ``source`` names the file in diagnostics."""
    data = _check_header(data, "lifted", source)
    with no_gc_pauses():
        return _decode("lifted", source, lambda: read_lifted(data))


def grounded_from_json(data: dict, *, source: str = "<json>") -> GroundModel:
    """Inverse of :func:`grounded_to_json`; ``source`` names the file in diagnostics."""
    data = _check_header(data, "grounded", source)
    lifted = data.get("lifted")
    model = None if lifted is None else lifted_from_json(lifted, source=source)
    with no_gc_pauses():
        return _decode("grounded", source, lambda: read_grounded(data, model))


def read_ir_json(path: str | Path) -> L.Model | GroundModel:
    """Load an IR document from ``path``, lifted or grounded by its ``kind``.

    Unreadable files raise ``OSError``; anything else wrong is a G19x diagnostic.
    """
    source = str(path)
    with open(path, encoding="utf-8") as f:
        try:
            with no_gc_pauses():
                data = json.load(f)
        except (ValueError, RecursionError) as exc:  # RecursionError: absurd nesting
            raise StampcError([error("G192", f"not a JSON IR document: {exc}",
                                     Span.point(source))]) from None
    kind = data.get("kind") if isinstance(data, dict) else None
    if kind == "grounded":
        return grounded_from_json(data, source=source)
    return lifted_from_json(data, source=source)
