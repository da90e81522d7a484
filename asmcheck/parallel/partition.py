"""One partition of the search: the states one worker owns, and the expansion of its frontier.

A :class:`Partition` holds the states whose :meth:`owner_hash` falls to it: their keys (in the
expander's compact local form), the global state number of each, its parent, the choices of the
step from the parent and its depth.  The coordinator (:mod:`.search`) drives it level by level:

1. :meth:`expand_level` expands the partition's frontier (in state-number order) and sorts the
   successors into one batch per owner (it first numbers the previous level's new states, step 3,
   when they come with it: one call where a call costs a round trip);
2. :meth:`receive` takes the batches addressed to it from every worker and finds the new states;
   a new state's *discovery key* is (number of its first parent, position among that parent's
   successors), which is exactly the order the sequential search discovers states in;
3. :meth:`number` takes the global numbers the coordinator gave to its new states (the rank of
   each discovery key among all workers' new states), which makes the numbering, parents and
   traces equal to the sequential search's.

The methods take and return plain picklable data, so a partition lives in the coordinator's
process (simulated workers), in a forked process, or in a Ray actor alike.
"""
from __future__ import annotations

import os
import pickle
import time
from array import array

from .expand import K_DEADLOCK, K_ERROR, K_STATE, K_STEP
from ..explore.bfs import error_edge
from ..semantics.choice import DeadlineReached
from .native_expand import Refused

SHIFT = 32                       # discovery key = parent number << SHIFT | successor position


class OverMemory(Exception):
    pass


def rss_bytes() -> int:
    """The resident memory of this process."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):  # pragma: no cover - not Linux
        import resource
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


class Partition:
    def __init__(self, wid: int, n: int, expander, memory_share: int | None = None, keep_graph=False):
        self.wid = wid
        self.n = n
        self.x = expander
        self.memory_share = memory_share       # bytes of resident memory this worker may use
        self.keep_graph = keep_graph
        self.index: dict = {}                  # frozen key -> global number
        self.frozen: dict = {}                 # global number -> frozen key
        self.parent: dict = {}
        self.via: dict = {}
        self.depth: dict = {}
        self.frontier: list = []               # global numbers, ascending
        self.pending: dict = {}                # frozen key -> [discovery key, picks] of this level's new states
        self.pending_order: list = []          # the pending frozen keys in discovery-key order
        self.candidates: list = []             # (discovery key, frozen key, picks) of every received successor
        self.sources: list = []                # (state number, distinct successors) in order, this level
        self.local: list = []                  # this level's successors that this partition owns
        self.level_depth = 0
        self.cpu0 = 0.0                        # this process's CPU seconds when the partition began

    # -------------------------------------------------------------- memory
    def _check_memory(self):
        if self.memory_share is not None and rss_bytes() > self.memory_share:
            raise OverMemory()

    def memory(self) -> int:
        return rss_bytes()

    # -------------------------------------------------------------- seeding
    def adopt(self, records) -> None:
        """Take initial states [(number, key, picks)]."""
        for sid, key, picks in records:
            fz = self.x.freeze(key)
            self.index[fz] = sid
            self.frozen[sid] = fz
            self.parent[sid] = -1
            self.via[sid] = picks
            self.depth[sid] = 0
            self.frontier.append(sid)
        self.frontier.sort()

    # -------------------------------------------------------------- phase 1
    def expand_level(self, depth: int, successors: bool, skip=(), deadline=None, numbered=None):
        """Expand the frontier.  Returns (report, batches): ``batches[w]`` is the pickled list of
        successors owned by worker w; ``report`` has the transition count, the property failures
        (each with its sort key (state, kind, successor, property)) and 'timeout'/'memory' flags.
        ``numbered``: the arguments of :meth:`number` for the previous level's new states, which
        are numbered first (they are this level's frontier); its edges are ``report['edges']``."""
        edges = self.number(*numbered) if numbered is not None else None
        x = self.x
        n = self.n
        skip = frozenset(skip)
        out = [[] for _ in range(n)]
        failures = []
        transitions = 0
        self.sources = []
        broken = []                 # states none of whose successors can be computed
        branches = []               # (state, choices, error) of each failing branch (graph kept)
        report = {"transitions": 0, "failures": failures, "stopped": None, "expanded": 0,
                  "broken": broken, "error_edges": branches, "edges": edges}
        # the step function stops a step that runs past the deadline (DeadlineReached), as the
        # sequential search's does: a level whose one step runs for minutes ends at the time limit
        machine = getattr(x, "m", None)
        timed = deadline is not None and hasattr(machine, "deadline")
        if timed:
            old_deadline = machine.deadline
            machine.deadline = time.monotonic() + (deadline - time.time())
        try:
            self._check_memory()
            for count, sid in enumerate(self.frontier):
                if deadline is not None and time.time() > deadline:
                    report["stopped"] = "time"
                    break
                if (count & 63) == 0:
                    self._check_memory()
                key = x.thaw(self.frozen[sid])
                e = x.expand(key, skip, successors)
                for i, msg, err in e.state_failures:
                    failures.append(((sid, K_STATE, 0, i), i, sid, None, (), msg, err))
                if not successors:
                    continue
                if e.too_many is not None:
                    # the sequential search stops at this state: so does this partition (the
                    # coordinator cuts the level there)
                    report["too_many"] = (sid, e.too_many)
                    break
                if e.error is not None:
                    failures.append(((sid, K_ERROR, 0, 0), -1, sid, None, (), e.error[0], e.error[1]))
                    broken.append(sid)
                    self.sources.append((sid, 0))
                    continue
                if e.failed:
                    # the state's well-defined successors are kept; its first failing branch is
                    # its candidate for the 'error' violation
                    err = e.failed[0]
                    failures.append(((sid, K_ERROR, 0, 0), -1, sid, None, (), err.message, err))
                    if self.keep_graph:
                        branches.extend(error_edge(sid, err) for err in e.failed)
                base = sid << SHIFT
                succ = e.succ
                for j, (k, picks) in enumerate(succ):
                    out[x.owner_hash(k) % n].append((k, base | j, picks))
                for j, i, msg, err in e.step_failures:
                    k, picks = succ[j]
                    failures.append(((sid, K_STEP, j, i), i, sid, k, picks, msg, err))
                if e.deadlock is not None:
                    failures.append(((sid, K_DEADLOCK, 0, 0), -1, sid, None, (), e.deadlock, None))
                transitions += e.distinct
                self.sources.append((sid, e.distinct))
            report["expanded"] = len(self.sources)
        except (OverMemory, MemoryError):
            out = [[] for _ in range(n)]
            report["stopped"] = "memory"
        except Refused as e:
            # the native expander met what it cannot compute: the search runs again on the Python one
            out = [[] for _ in range(n)]
            report["stopped"] = "refused"
            report["refused"] = str(e)
            report["slots"] = getattr(e, "cn_k", None)
        except DeadlineReached:
            out = [[] for _ in range(n)]
            report["stopped"] = "time"
        finally:
            if timed:
                machine.deadline = old_deadline
        report["transitions"] = transitions
        report["rss"] = rss_bytes()
        # this partition's own successors stay here, unpickled; its slot travels empty
        self.local = out[self.wid]
        return report, [b"" if w == self.wid else pickle.dumps(b, protocol=pickle.HIGHEST_PROTOCOL)
                        for w, b in enumerate(out)]

    def source_counts(self) -> list:
        """(state number, distinct successors) of the states expanded at this level."""
        return self.sources

    # -------------------------------------------------------------- phase 2
    def receive(self, batches):
        """Take the successors addressed to this partition (one pickled batch per worker).
        Returns the sorted discovery keys of the new states (an array of 64-bit integers), or
        the string 'memory' when this worker went over its memory share."""
        x = self.x
        index = self.index
        pending = {}
        cands = [] if self.keep_graph else None
        local, self.local = self.local, []
        try:
            for count, b in enumerate(batches):
                for k, dkey, picks in (local if count == self.wid else pickle.loads(b)):
                    fz = x.freeze(k)
                    if cands is not None:
                        cands.append((dkey, fz, picks))
                    if fz in index:
                        continue
                    p = pending.get(fz)
                    if p is None:
                        pending[fz] = [dkey, picks]
                    elif dkey < p[0]:
                        p[0] = dkey
                        p[1] = picks
                self._check_memory()
        except (OverMemory, MemoryError):
            self.pending = {}
            self.candidates = []
            return "memory"
        order = sorted(pending, key=lambda fz: pending[fz][0])
        self.pending = pending
        self.pending_order = order
        self.candidates = cands or []
        return array("q", (pending[fz][0] for fz in order))

    # -------------------------------------------------------------- phase 3
    def number(self, sids, depth: int):
        """Give the new states their global numbers (aligned with the keys :meth:`receive`
        returned; -1: beyond the point where the search stopped, dropped).  With the graph kept,
        returns this partition's edges [(discovery key, target number, picks)]."""
        pending = self.pending
        frontier = []
        for fz, sid in zip(self.pending_order, sids):
            if sid < 0:
                continue
            dkey, picks = pending[fz]
            self.index[fz] = sid
            self.frozen[sid] = fz
            self.parent[sid] = dkey >> SHIFT
            self.via[sid] = picks
            self.depth[sid] = depth
            frontier.append(sid)
        self.frontier = frontier
        self.pending = {}
        self.pending_order = []
        edges = None
        if self.keep_graph:
            index = self.index
            edges = [(dkey, index.get(fz, -1), picks) for dkey, fz, picks in self.candidates]
        self.candidates = []
        return edges

    # -------------------------------------------------------------- queries
    def lookup(self, keys) -> list:
        """The global numbers of states given by key (-1 for a state this partition does not hold)."""
        return [self.index.get(self.x.freeze(k), -1) for k in keys]

    def fetch(self, sids) -> list:
        """[(key, parent, picks, depth)] of states this partition holds."""
        return [(self.x.thaw(self.frozen[s]), self.parent[s], self.via[s], self.depth[s]) for s in sids]

    def gather(self) -> list:
        """Every state of this partition: [(number, key, parent, picks, depth)]."""
        return [(s, self.x.thaw(fz), self.parent[s], self.via[s], self.depth[s]) for s, fz in self.frozen.items()]

    def size(self) -> int:
        return len(self.frozen)

    def ping(self) -> int:
        return os.getpid()

    def cpu(self) -> float:
        """CPU seconds this worker's process has used since the partition began (for benchmarks)."""
        return time.process_time() - self.cpu0
