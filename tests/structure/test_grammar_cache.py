"""The on-disk grammar cache (stampc.grammar_cache): exact keys, atomic entries, and
graceful fallback when the cache is corrupt, foreign, shared or unwritable."""

from __future__ import annotations


import pytest

from stampc import grammar_cache
from stampc.syntax import parser

TEXT = "domain d\n"


def fresh_tables():
    return parser.tables.__wrapped__()  # bypass the per-process lru_cache


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("STAMPC_CACHE_DIR", str(folder))
    return folder


def test_tables_round_trip_through_the_cache(cache):
    built = fresh_tables()
    entries = list(cache.iterdir())
    assert len(entries) == 1 and entries[0].name.startswith("stamp-tables-")
    assert oct(cache.stat().st_mode & 0o777) == oct(0o700)
    assert fresh_tables() == built  # exactly what was stored
    # Lark may number states differently per compilation: compare what does not depend on it
    compiled = parser.compile_tables(parser.grammar_text())
    assert len(compiled.actions) == len(built.actions) and compiled.plans == built.plans
    assert compiled.lexer == built.lexer


def test_a_corrupt_entry_is_rebuilt_and_replaced(cache):
    good = fresh_tables()
    (entry,) = cache.iterdir()
    data = entry.read_bytes()
    entry.write_bytes(data[: len(data) // 2])  # a truncated file
    rebuilt = fresh_tables()
    assert rebuilt.plans == good.plans and len(rebuilt.actions) == len(good.actions)
    assert len(entry.read_bytes()) > len(data) // 2  # replaced by a whole entry ...
    assert fresh_tables() == rebuilt                 # ... that loads


def test_an_entry_for_another_key_is_never_used(cache):
    calls = []
    value = grammar_cache.cached("t", "key-1", lambda: calls.append(1) or "one",
                                 str.encode, bytes.decode)
    assert value == "one" and calls == [1]
    assert grammar_cache.cached("t", "key-1", lambda: "rebuilt", str.encode, bytes.decode) == "one"
    (entry,) = cache.iterdir()
    # same file name, different stored key (as after a checksum collision): rebuilt
    entry.write_bytes(entry.read_bytes().replace(b"key-1", b"key-2"))
    assert grammar_cache.cached("t", "key-1", lambda: "rebuilt", str.encode, bytes.decode) == "rebuilt"


def test_unwritable_or_disabled_cache_still_parses(tmp_path, monkeypatch):
    blocker = tmp_path / "not-a-dir"
    blocker.write_text("a file where the cache directory should be")
    monkeypatch.setenv("STAMPC_CACHE_DIR", str(blocker / "stampc"))
    program, diags = parser.parse_source(TEXT, "x.stamp")
    assert fresh_tables() is not None and diags == []
    monkeypatch.setenv("STAMPC_CACHE_DIR", "")
    assert grammar_cache.cache_dir() is None
    assert fresh_tables().plans == parser.compile_tables(parser.grammar_text()).plans
    assert not any(p.name.startswith("stamp") for p in tmp_path.rglob("*"))


def test_no_partial_files_are_left_behind(cache):
    for i in range(3):
        grammar_cache.cached("t", f"k{i}", lambda: "v" * 100_000, str.encode, bytes.decode)
    assert sorted(p.name.startswith(".") for p in cache.iterdir()) == [False] * 3


def test_lark_version_is_read_without_importing_lark():
    import lark
    assert grammar_cache.lark_version() == lark.__version__
