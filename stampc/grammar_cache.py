"""An on-disk cache for what stampc compiles from its own grammars (start-up time).

Compiling a Lark grammar into LALR(1) tables costs 0.1–0.4 s per process, more than
the rest of a small ``stampc check`` or ``stampc solve``. The compiled form is stored
in the user's cache directory and reused while the grammar text, the Lark version and
the code that shapes the stored form are unchanged: all of it (the entry's *key*) is
stored in the entry and compared exactly on load; a checksum of the key names the file.

Safety: files are written to a temporary file in the same directory and renamed into
place (readers never see a partial file); a file that fails to load is rebuilt; an
unwritable or missing directory only costs the rebuild. Pickled Lark parsers are loaded
only from a directory owned by the current user and not writable by others.

``STAMPC_CACHE_DIR`` chooses the directory (empty: no cache); the default is
``$XDG_CACHE_HOME/stampc`` or ``~/.cache/stampc``.
"""

from __future__ import annotations

import importlib.util
import os
import re
import tempfile
import zlib
from pathlib import Path
from typing import Callable, TypeVar

T = TypeVar("T")

_VERSION_LINE = re.compile(r"""^__version__\s*(?::\s*str\s*)?=\s*["']([^"']+)["']""", re.M)


def cache_dir() -> Path | None:
    """The cache directory (not created here), or None when caching is switched off."""
    chosen = os.environ.get("STAMPC_CACHE_DIR")
    if chosen is not None:
        return Path(chosen) if chosen.strip() else None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "stampc"


def lark_version() -> str:
    """Lark's version, read from its ``__init__.py`` without importing Lark (importing it
    is what the cache saves) or scanning installed distributions (slower still)."""
    spec = importlib.util.find_spec("lark")
    if spec is None or not spec.origin:
        return "absent"
    try:
        text = Path(spec.origin).read_text(encoding="utf-8")
    except OSError:
        return "unreadable"
    found = _VERSION_LINE.search(text)
    if found:
        return found.group(1)
    st = os.stat(spec.origin)  # unknown layout: any change to the file changes the key
    return f"{spec.origin}:{st.st_size}:{st.st_mtime_ns}"


def file_stamp(*paths: str | Path) -> str:
    """Size and modification time of source files, for keys of entries whose form depends
    on code (an edited module must not reuse what its old version stored)."""
    stamps = []
    for path in paths:
        try:
            st = os.stat(path)
            stamps.append(f"{st.st_size}:{st.st_mtime_ns}")
        except OSError:
            stamps.append("?")
    return ",".join(stamps)


def cache_key(*parts: str) -> str:
    """The key of an entry: every part, verbatim (not a digest: compared exactly)."""
    return "\0".join(parts)


def read_entry(name: str) -> bytes | None:
    folder = cache_dir()
    if folder is None:
        return None
    try:
        return (folder / name).read_bytes()
    except OSError:
        return None


def write_entry(name: str, data: bytes) -> bool:
    """Store ``data`` atomically; False (and nothing written) when that is not possible."""
    folder = cache_dir()
    if folder is None:
        return False
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{name}.", dir=folder)
        try:
            with os.fdopen(fd, "wb") as handle:
                handle.write(data)
            os.replace(tmp, folder / name)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    except OSError:
        return False
    return True


def _split(data: bytes, key: bytes) -> bytes | None:
    """The payload of an entry ``<len(key)>\\n<key><payload>`` stored under ``key``."""
    size, newline, rest = data.partition(b"\n")
    if not newline or not size.isdigit() or rest[:int(size)] != key or int(size) != len(key):
        return None
    return rest[len(key):]


def cached(name: str, key: str, build: Callable[[], T], dump: Callable[[T], bytes],
           load: Callable[[bytes], T]) -> T:
    """``load`` of the stored entry for ``key``, else ``build()`` (stored via ``dump``).
    An entry whose stored key differs, or that ``load`` rejects (any ``Exception``), is
    rebuilt and replaced."""
    raw_key = key.encode("utf-8")
    entry = f"{name}-{zlib.crc32(raw_key):08x}{len(raw_key):06x}"
    data = read_entry(entry)
    payload = _split(data, raw_key) if data is not None else None
    if payload is not None:
        try:
            return load(payload)
        except Exception:  # a corrupt entry: rebuild below
            pass
    value = build()
    try:
        payload = dump(value)
    except Exception:  # an unpicklable value must not break parsing
        return value
    write_entry(entry, b"%d\n" % len(raw_key) + raw_key + payload)
    return value
