"""Diagnostics latency of `stampc lsp`: the time from a didChange notification to the
publishDiagnostics that answers it, on the largest example (by size) or FILE.

A real LSP client (pygls) starts `python -m stampc lsp` over stdio, opens the file, then
sends --changes edits, alternating a clean text and one with an undefined predicate
(so every answer is checked to hold the expected diagnostics), and prints the median,
90th percentile and maximum.

    python bench/lsp.py
    python bench/lsp.py examples/keva/domain.stamp --changes 100

Target (issue 16): diagnostics < 200 ms after a change on the largest example.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def largest_example() -> Path:
    return max(REPO.glob("examples/*/*.stamp"), key=lambda p: p.stat().st_size)


async def measure(path: Path, changes: int) -> list[float]:
    from lsprotocol import types as lsp
    from pygls.lsp.client import LanguageClient

    client = LanguageClient("stampc-bench", "1")
    answers: asyncio.Queue = asyncio.Queue()

    @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def diagnostics(params: lsp.PublishDiagnosticsParams) -> None:
        answers.put_nowait((time.perf_counter(), params.diagnostics))

    env = {**os.environ, "PYTHONPATH": str(REPO)}
    await client.start_io(sys.executable, "-m", "stampc", "lsp", env=env)
    await client.initialize_async(lsp.InitializeParams(capabilities=lsp.ClientCapabilities()))
    client.initialized(lsp.InitializedParams())
    uri, text = path.resolve().as_uri(), path.read_text(encoding="utf-8")
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(text_document=lsp.TextDocumentItem(
        uri=uri, language_id="stamp", version=1, text=text)))
    _, first = await answers.get()
    broken = text + "\naction bench_probe()\n    pre  no_such_predicate\n    eff  not no_such_predicate\n"
    latencies = []
    for version in range(2, changes + 2):
        edited = broken if version % 2 else text
        sent = time.perf_counter()
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            text_document=lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[lsp.TextDocumentContentChangeWholeDocument(text=edited)]))
        received, diags = await answers.get()
        codes = {d.code for d in diags}
        assert ("E102" in codes) == (edited is broken), f"unexpected diagnostics {codes}"
        latencies.append(received - sent)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return latencies


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("file", nargs="?", type=Path, default=None)
    parser.add_argument("--changes", type=int, default=40)
    args = parser.parse_args()
    path = args.file or largest_example()
    latencies = sorted(asyncio.run(measure(path, args.changes)))
    ms = [t * 1000 for t in latencies]
    print(f"{path.relative_to(REPO) if path.is_relative_to(REPO) else path} "
          f"({path.stat().st_size} bytes, {len(path.read_text().splitlines())} lines): "
          f"{len(ms)} changes, diagnostics after median {statistics.median(ms):.1f} ms, "
          f"p90 {ms[int(0.9 * (len(ms) - 1))]:.1f} ms, max {ms[-1]:.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
