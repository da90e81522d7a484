"""Partitions in forked worker processes (``explore --workers N``).

Each worker is forked after the spec is loaded, so it inherits the machine and the properties
and builds its own expander (with its own canonicaliser).  The coordinator talks to each worker
over a pipe; the batches of successors pass through it as pickled bytes, never unpickled there.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import traceback

from .partition import Partition, rss_bytes
from .search import WorkerLost, level_by_calls


def _serve(conn, wid, n, make_expander, memory_share, keep_graph):
    # the worker's share is of the memory it adds: the pages it was forked with are the calling
    # process's (shared until written), however large that process has grown
    inherited = rss_bytes()
    try:
        share = memory_share + inherited if memory_share is not None else None
        part = Partition(wid, n, make_expander(), share, keep_graph)
    except BaseException as e:  # pragma: no cover - reported to the coordinator
        conn.send(("err", f"{type(e).__name__}: {e}"))
        return
    conn.send(("ok", os.getpid()))
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return
        if msg is None:
            return
        method, args = msg
        try:
            out = getattr(part, method)(*args)
            conn.send(("ok", out))
        except BaseException as e:
            if os.environ.get("ASMCHECK_DEBUG"):
                traceback.print_exc()
            try:
                conn.send(("err", e))
            except Exception:
                conn.send(("err", f"{type(e).__name__}: {e}"))


class ProcessBackend:
    name = "processes"

    def __init__(self, make_expander, n: int, memory_share=None, keep_graph=False):
        self.n = n
        ctx = multiprocessing.get_context("fork")
        self.conns = []
        self.procs = []
        try:
            for w in range(n):
                parent, child = ctx.Pipe()
                p = ctx.Process(target=_serve, args=(child, w, n, make_expander, memory_share, keep_graph),
                                name=f"asmcheck-worker-{w + 1}", daemon=True)
                p.start()
                child.close()
                self.conns.append(parent)
                self.procs.append(p)
            self.pids = [self._recv(w) for w in range(n)]
        except BaseException:
            self.close()
            raise

    def _lost(self, w: int) -> WorkerLost:
        p = self.procs[w]
        p.join(timeout=1.0)
        code = p.exitcode
        how = (f"killed by signal {-code} ({signal.Signals(-code).name})" if code is not None and code < 0
               else f"exit code {code}" if code is not None else "no answer")
        return WorkerLost(f"worker {w + 1} (process {p.pid}) died during the search ({how}); "
                          f"the search has no verdict")

    def _recv(self, w: int):
        try:
            status, out = self.conns[w].recv()
        except (EOFError, OSError, ConnectionError):
            raise self._lost(w) from None
        if status == "err":
            if isinstance(out, BaseException):
                raise out
            raise RuntimeError(f"worker {w + 1}: {out}")
        return out

    def _send(self, w: int, method: str, args):
        try:
            self.conns[w].send((method, args))
        except (OSError, ConnectionError, BrokenPipeError):
            raise self._lost(w) from None

    def call_all(self, method: str, args_list):
        for w, args in enumerate(args_list):
            self._send(w, method, args)
        return [self._recv(w) for w in range(self.n)]

    def call(self, w: int, method: str, *args):
        self._send(w, method, args)
        return self._recv(w)

    def route(self, batches_by_src):
        return self.call_all("receive", [([b[w] for b in batches_by_src],) for w in range(self.n)])

    def level(self, args_list, route: bool):
        return level_by_calls(self, args_list, route)

    def close(self, reuse=False):
        for c in self.conns:
            try:
                c.send(None)
            except Exception:
                pass
        for p in self.procs:
            p.join(timeout=2.0)
            if p.is_alive():
                p.kill()
                p.join(timeout=2.0)
        for c in self.conns:
            c.close()
        self.conns = []
        self.procs = []
