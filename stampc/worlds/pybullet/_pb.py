"""Import PyBullet without its banner, and silence C-level output on demand.

PyBullet prints its build time on stderr when imported and chatter on connect/loadURDF;
every module of this package imports ``p`` from here so the banner never shows.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from typing import Iterator


def _flush_c_stdio() -> None:
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass


@contextlib.contextmanager
def quiet_stdout(enabled: bool) -> Iterator[None]:
    """Silence C-level writes to fd 1 and 2 (PyBullet prints build info on connect)."""
    if not enabled:
        yield
        return
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        yield
    finally:
        _flush_c_stdio()  # C stdio buffers: flush while the fds still point to /dev/null
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, devnull):
            os.close(fd)


with quiet_stdout(True):
    import pybullet as p
    import pybullet_data

__all__ = ["p", "pybullet_data", "quiet_stdout"]
