#!/usr/bin/env python3
"""Language-server benchmark: re-diagnosis of the largest corpus file after an edit.

    python benchmarks/bench_lsp.py [--shared ../shared] [--edits N] [--file SPEC.asm]

Starts ``python -m asmcheck lsp`` as an editor would (over stdio, with pygls' client),
opens the largest .asm file of the ASMETA corpus (by size; or --file), waits for its
first diagnostics, then makes N small edits (a space added at the end of a line in the
middle of the file, alternating with its removal) and measures, for each edit, the time
from sending textDocument/didChange to receiving textDocument/publishDiagnostics.
It does the same with ASMCHECK_LSP_INCREMENTAL=0 in the server's environment (every
edit parses the whole text again), to show what parsing one declaration saves.
Prints a Markdown table. A benchmark, not a test: nothing fails on a slow machine;
the target is a median at or under 150 ms after the first parse.
"""
from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def largest(shared: Path) -> Path | None:
    corpus = shared / "asmeta"
    files = [p for p in corpus.rglob("*.asm") if p.stem not in ("StandardLibrary", "CTLLibrary", "LTLLibrary")]
    if not files:
        return None
    return max(files, key=lambda p: (p.stat().st_size, str(p)))


def edits(text: str, n: int) -> list[tuple[int, int, str]]:
    """(line, character, inserted text or '' to delete one character) for n edits in the middle:
    in turn a space added at the end of a line and taken away, a line break added and taken away."""
    lines = text.split("\n")
    mid = len(lines) // 2
    out = []
    for i in range(n):
        ln = mid + (i // 4) % 10
        col = len(lines[ln].rstrip("\r"))
        out.append((ln, col, [" ", "", "\n", ""][i % 4]))
    return out


def decode(data: bytes) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")


async def over_stdio(path: Path, n: int, incremental: bool = True) -> tuple[float, list[float], int]:
    from lsprotocol import types as lsp
    from pygls.lsp.client import LanguageClient
    from pygls.uris import from_fs_path

    client = LanguageClient("bench", "1")
    got: asyncio.Queue = asyncio.Queue()

    @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diags(params: lsp.PublishDiagnosticsParams):
        got.put_nowait((time.perf_counter(), params))

    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "ASMCHECK_LSP_INCREMENTAL": "1" if incremental else "0"}
    await client.start_io(sys.executable, "-m", "asmcheck", "lsp", env=env)
    await client.initialize_async(lsp.InitializeParams(capabilities=lsp.ClientCapabilities()))
    client.initialized(lsp.InitializedParams())
    text = decode(path.read_bytes())
    uri = from_fs_path(str(path))
    t0 = time.perf_counter()
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(uri, "asmetal", 1, text)))
    t1, first = await got.get()
    problems = len(first.diagnostics)
    times = []
    for version, (ln, col, ins) in enumerate(edits(text, n), start=2):
        if ins:
            rng = lsp.Range(lsp.Position(ln, col), lsp.Position(ln, col))
        else:
            rng = lsp.Range(lsp.Position(ln, col), lsp.Position(ln, col + 1))
        change = lsp.TextDocumentContentChangePartial(range=rng, text=ins)
        s = time.perf_counter()
        client.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=uri, version=version), [change]))
        e, _ = await got.get()
        times.append(e - s)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return t1 - t0, times, problems


def ms(x: float) -> str:
    return f"{x * 1000:.1f}"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shared", default=os.environ.get("ASMCHECK_SHARED", str(ROOT.parent / "shared")))
    ap.add_argument("--edits", type=int, default=20)
    ap.add_argument("--file")
    a = ap.parse_args()
    path = Path(a.file) if a.file else largest(Path(a.shared))
    if path is None:
        print(f"no ASMETA corpus under {a.shared}; nothing to measure (set --shared or ASMCHECK_SHARED)")
        return 0
    try:
        import pygls  # noqa: F401
    except ImportError:
        print("the language server needs the 'lsp' extra (pip install '.[lsp]'); nothing to measure")
        return 0
    text = path.read_bytes()
    nlines = text.count(b"\n") + 1
    print(f"file: {path} ({len(text):,} bytes, {nlines:,} lines), {a.edits} edits\n")
    first, times, problems = asyncio.run(over_stdio(path, a.edits))
    full_first, full_times, _ = asyncio.run(over_stdio(path, a.edits, incremental=False))
    print("| measured | first parse (ms) | re-diagnosis median (ms) | min | max |")
    print("|---|---:|---:|---:|---:|")
    print(f"| the server: the edited declaration parsed again | {ms(first)} | {ms(statistics.median(times))} | "
          f"{ms(min(times))} | {ms(max(times))} |")
    print(f"| the server with ASMCHECK_LSP_INCREMENTAL=0: the whole text parsed again | {ms(full_first)} | "
          f"{ms(statistics.median(full_times))} | {ms(min(full_times))} | {ms(max(full_times))} |")
    print(f"\ndiagnostics on open: {problems}; target: median re-diagnosis <= 150 ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
