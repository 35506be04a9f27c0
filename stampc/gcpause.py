"""Keeping the cyclic garbage collector out of AST construction.

Parsing and checking a large domain allocates hundreds of thousands of small,
long-lived, acyclic objects (spans, identifiers, nodes). With the collector running,
each young generation collection rescans them; with it merely disabled, the first
allocation after re-enabling triggers one young-generation pass over *all* of them
(about 0.15 s for a 2,000-action domain). Neither pass can free anything: the trees
hold no cycles and die by reference counting.

:func:`no_gc_pauses` therefore disables the collector and, on the way out, moves the
objects allocated meanwhile straight into the oldest generation with
``gc.freeze()`` + ``gc.unfreeze()`` (two list splices, O(1)): they are then scanned
only by full collections, like any other long-lived data. This is skipped when the
process already uses ``gc.freeze`` for its own purposes (a non-empty permanent
generation), so that we never unfreeze someone else's objects.
"""

from __future__ import annotations

import contextlib
import gc
from typing import Iterator


@contextlib.contextmanager
def no_gc_pauses() -> Iterator[None]:
    """Suspend the cyclic GC while building large acyclic trees (restores its state)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            _promote_young_objects()
            gc.enable()


def _promote_young_objects() -> None:
    """Move every tracked object of the young generations into the oldest one, resetting
    the young-generation allocation count (so enabling the GC triggers no scan)."""
    if gc.get_freeze_count() == 0:
        gc.freeze()
        gc.unfreeze()
