"""The partitioned breadth-first search, written once over any backend and any expander.

The coordinator keeps no states: each state lives in the partition its hash names.  Per level:

* every worker expands its share of the frontier and sends each successor to its owner;
* each owner finds its new states and their discovery keys (first parent's number, position
  among that parent's successors);
* the coordinator merges the owners' sorted key lists: the rank of a key is the number the
  sequential search gives that state, so numbers, parents, shortest traces and ``--graph``
  are the sequential search's, whatever the number of workers.

The numbers travel with the next level's expansion (a partition numbers its new states, then
expands them), and a backend may hand the batches to their owners without waiting for the
coordinator (:meth:`RayBackend.level <asmcheck.parallel.cluster.RayBackend.level>`): a level
costs one round trip between the coordinator and the workers.

Where the sequential search stops inside a level (a state limit, every property violated), the coordinator finds the same stopping point from per-state summaries and drops
what the sequential search would not have reached.  A time limit stops at a level boundary.

A backend runs the partitions: :class:`InlineBackend` (in this process; N simulated workers),
:class:`asmcheck.parallel.procs.ProcessBackend` (forked processes) or
:class:`asmcheck.parallel.cluster.RayBackend` (Ray actors).
"""
from __future__ import annotations

import time
from array import array

from ..explore.bfs import DEADLOCK, PseudoProperty, Result, Stop, TimeLimit, Violation
from .expand import K_DEADLOCK, K_ERROR, K_STATE, K_STEP
from .native_expand import MoreSlots, Refused
from .partition import SHIFT, Partition


class WorkerLost(Exception):
    """A worker died (or could not be reached) during the search: the run has no verdict."""


class InlineBackend:
    """N partitions in this process, run one after the other: N simulated workers (the
    partitioning and the merge are exercised exactly as with processes)."""

    name = "inline"

    def __init__(self, make_expander, n: int, memory_share=None, keep_graph=False):
        self.n = n
        self.parts = [Partition(w, n, make_expander(), memory_share, keep_graph) for w in range(n)]

    def call_all(self, method: str, args_list):
        return [getattr(p, method)(*a) for p, a in zip(self.parts, args_list)]

    def call(self, w: int, method: str, *args):
        return getattr(self.parts[w], method)(*args)

    def route(self, batches_by_src):
        """Hand each owner its batches (one from every worker); returns receive()'s results."""
        return self.call_all("receive", [([b[w] for b in batches_by_src],) for w in range(self.n)])

    def level(self, args_list, route: bool):
        return level_by_calls(self, args_list, route)

    def close(self, reuse=False):
        self.parts = []


def level_by_calls(backend, args_list, route: bool):
    """One level on ``backend``: every partition's expand_level (with ``args_list``), then, when
    ``route`` and no worker stopped, the batches to their owners.  Returns (reports, the
    owners' receive() results or None)."""
    res = backend.call_all("expand_level", args_list)
    reports = [r for r, _ in res]
    if not route or any(r["stopped"] for r in reports):
        return reports, None
    return reports, backend.route([bs for _, bs in res])


class PartitionedSearch:
    """The coordinator.  ``backend`` runs the partitions; ``expander`` is a local expander (for
    the initial states and the owner of a key); ``state_props``/``step_props`` are the property
    objects, in the same order as the workers' (violations name them by index)."""

    def __init__(self, backend, expander, *, state_props=(), step_props=(), deadlock=False,
                 max_states=None, max_depth=None, max_seconds=None,
                 keep_graph=False, progress=None, on_level=None):
        self.b = backend
        self.x = expander
        self.n = backend.n
        self.state_props = list(state_props)
        self.step_props = list(step_props)
        self.deadlock = deadlock
        self.max_states = max_states
        self.max_depth = max_depth
        self.max_seconds = max_seconds
        self.keep_graph = keep_graph
        self.progress = progress
        self.on_level = on_level        # called as on_level(search, depth) after each level
        self.owner = bytearray()        # owner of each state number
        self.edges: list = []
        self.levels: list = []          # per level: (depth, frontier size, new states, seconds)
        self.peak_rss: list = [0] * self.n
        self.error_edges: list = []     # (state, choices, error) of each failing branch (graph kept)

    def owner_of_key(self, key) -> int:
        return self.x.owner_hash(key) % self.n

    # -------------------------------------------------------------- the search
    def run(self) -> Result:
        t0 = time.perf_counter()
        deadline = None if self.max_seconds is None else time.time() + self.max_seconds  # wall clock: comparable across machines
        n = self.n
        all_props = self.state_props + self.step_props
        total_props = len(all_props) + (1 if self.deadlock else 0)
        chosen: dict = {}               # property name -> (sort key, violation record)
        names_order: list = []
        incomplete = False
        reason = ""
        why_stop = ""
        transitions = 0
        n_states = 0
        depth_seen = 0
        time_limit = None

        # level 0: the initial states, numbered in enumeration order
        seen = {}
        per_owner = [[] for _ in range(n)]
        for key, picks in self.x.initial():
            fz = self.x.freeze(key)
            if fz in seen:
                continue
            seen[fz] = n_states
            w = self.owner_of_key(key)
            per_owner[w].append((n_states, key, picks))
            self.owner.append(w)
            n_states += 1
        self.b.call_all("adopt", [(r,) for r in per_owner])
        frontier_size = n_states
        depth = 0
        stop = False
        numbered = None                 # the last level's numbers, not yet given to the partitions
        limit = None
        while frontier_size and not stop:
            lt = time.perf_counter()
            expand = self.max_depth is None or depth < self.max_depth
            skip = tuple(chosen)
            # (each partition first numbers the last level's new states: its frontier)
            reports, received = self.b.level(
                [(depth, expand, skip, deadline, None if numbered is None else numbered[w]) for w in range(n)],
                expand)
            if numbered is not None:
                self._edges([r["edges"] for r in reports], limit)
                numbered = None
            for w, r in enumerate(reports):
                self.peak_rss[w] = max(self.peak_rss[w], r.get("rss", 0))
            stopped = [r["stopped"] for r in reports if r["stopped"]]
            if "refused" in stopped:
                r = next(r for r in reports if r["stopped"] == "refused")
                raise Refused(r["refused"]) if r.get("slots") is None else MoreSlots(r["refused"], r["slots"])
            if "memory" in stopped:
                w = next(w for w, r in enumerate(reports) if r["stopped"] == "memory")
                return self._partial(t0, n_states, transitions, depth_seen, chosen,
                                     f"worker {w + 1} went over its memory share at depth {depth}", Stop.SHARE)
            if stopped:
                res = self._partial(t0, n_states, transitions, depth_seen, chosen, TimeLimit(self.max_seconds).text(),
                                    Stop.TIME)
                res.time_limit = TimeLimit(self.max_seconds)
                return res
            level_fail = {}
            for r in reports:
                for rec in r["failures"]:
                    name = self._name(rec)
                    old = level_fail.get(name)
                    if old is None or rec[0] < old[0]:
                        level_fail[name] = rec
            if not expand:
                # depth limit: the frontier's states are checked, not expanded
                incomplete = True
                reason, why_stop = f"depth limit {self.max_depth} reached", Stop.DEPTH
                for name, rec in sorted(level_fail.items(), key=lambda kv: kv[1][0]):
                    if name not in chosen:
                        chosen[name] = (rec[0], rec)
                        names_order.append(name)
                break
            if any(isinstance(r, str) for r in received):
                w = next(w for w, r in enumerate(received) if isinstance(r, str))
                return self._partial(t0, n_states, transitions, depth_seen, chosen,
                                     f"worker {w + 1} went over its memory share at depth {depth + 1}", Stop.SHARE)
            # merge: every new state's discovery key, tagged with its owner
            tagged = array("q")
            for w, keys in enumerate(received):
                tagged.extend(keys)
            new_total = len(tagged)
            level_transitions = sum(r["transitions"] for r in reports)
            # the states none of whose successors can be computed (a state with a failing branch
            # keeps its well-defined successors, as in the sequential search)
            errors = {s for r in reports for s in r["broken"]}
            branches = [b for r in reports for b in r["error_edges"]]
            too_many = min((r["too_many"] for r in reports if r.get("too_many")), default=None)
            lo = n_states - frontier_size
            cut = self._cut(level_fail, errors, chosen, n_states, lo, n_states, new_total, received, too_many)
            if cut is not None:
                cut_sid, why = cut
                stop = True
                limit = (cut_sid + 1) << SHIFT
                counts = {s: c for w in range(n) for s, c in self.b.call(w, "source_counts")}
                level_transitions = sum(c for s, c in counts.items() if s <= cut_sid)
                # (the state where the enumeration stopped had its state properties checked)
                level_fail = {k: v for k, v in level_fail.items() if v[0][0] <= cut_sid
                              or (why == "too many" and v[0][0] == cut_sid + 1 and v[0][1] == K_STATE)}
                branches = [b for b in branches if b[0] <= cut_sid]
                # errors before the cut leave the run incomplete
                if any(s <= cut_sid for s in errors):
                    incomplete = True
                    reason, why_stop = reason or "a step could not be computed", why_stop or Stop.STEP_FAILED
                if why == "state limit":
                    incomplete = True
                    reason, why_stop = f"state limit {self.max_states} reached", Stop.STATES
                elif why == "too many":
                    incomplete = True
                    reason, why_stop = too_many[1], Stop.TOO_MANY
            else:
                limit = None
                if errors:
                    incomplete = True
                    reason, why_stop = reason or "a step could not be computed", why_stop or Stop.STEP_FAILED
            if branches:
                branches.sort(key=lambda b: b[0])       # (stable: a state's branches in their order)
                self.error_edges.extend(branches)
            for name, rec in sorted(level_fail.items(), key=lambda kv: kv[1][0]):
                if name not in chosen:
                    chosen[name] = (rec[0], rec)
                    names_order.append(name)
            transitions += level_transitions
            # number the new states: rank of the discovery key among all owners' keys
            order = sorted(range(new_total), key=tagged.__getitem__) if n > 1 else range(new_total)
            offsets = []
            o = 0
            for keys in received:
                offsets.append(o)
                o += len(keys)
            sids_flat = array("q", [-1]) * new_total
            nxt = n_states
            for pos in order:
                if limit is not None and tagged[pos] >= limit:
                    break
                sids_flat[pos] = nxt
                nxt += 1
            owner_of_pos = bytearray(new_total)
            for w, keys in enumerate(received):
                owner_of_pos[offsets[w]:offsets[w] + len(keys)] = bytes([w]) * len(keys)
            self.owner.extend(b"\0" * (nxt - n_states))
            for pos in range(new_total):
                s = sids_flat[pos]
                if s >= 0:
                    self.owner[s] = owner_of_pos[pos]
            numbered = [(sids_flat[offsets[w]:offsets[w] + len(received[w])], depth + 1) for w in range(n)]
            new_states = nxt - n_states
            self.levels.append((depth, frontier_size, new_states, time.perf_counter() - lt))
            n_states = nxt
            frontier_size = new_states
            if new_states:
                depth += 1
                depth_seen = depth
            if self.progress is not None:
                self.progress(n_states, depth, transitions, time.perf_counter() - t0)
            if self.on_level is not None:
                self.on_level(self, depth)
            if not stop and self.max_seconds is not None and time.time() > deadline and frontier_size:
                incomplete = True
                time_limit = TimeLimit(self.max_seconds)
                reason, why_stop = time_limit.text(), Stop.TIME
                break
        if numbered is not None:
            self._edges(self.b.call_all("number", numbered), limit)
        self.n_states = n_states
        violations = [self._violation(chosen[name][1]) for name in
                      sorted(chosen, key=lambda nm: chosen[nm][0])]
        verdict = "violated" if violations else "incomplete" if incomplete else "holds"
        res = Result(verdict, n_states, transitions, depth_seen, time.perf_counter() - t0, violations,
                     reason if incomplete else "", all_props)
        res.deadlock_checked = self.deadlock
        res.time_limit = time_limit if incomplete else None
        res.stop = why_stop if incomplete else ""
        return res

    # -------------------------------------------------------------- helpers
    def _edges(self, edges, limit) -> None:
        """The edges the partitions gave when they numbered a level's new states (graph kept)."""
        if self.keep_graph:
            allE = [e for es in edges for e in es if limit is None or e[0] < limit]
            allE.sort(key=lambda e: e[0])
            self.edges.extend((e[0] >> SHIFT, e[1], e[2]) for e in allE)

    def _name(self, rec) -> str:
        kind, i = rec[0][1], rec[1]
        if kind == K_STATE:
            return self.state_props[i].name
        if kind == K_STEP:
            return self.step_props[i].name
        return "error" if kind == K_ERROR else "deadlock"

    def _cut(self, level_fail, errors, chosen, n_states, lo, hi, new_total, received, too_many=None):
        """Where inside this level (states lo..hi-1) the sequential search stops, or None: the
        state after whose successors it stops, and why.  The sequential search checks its limits
        after each state whose successors it computed (not after a state none of whose steps
        could be computed).  ``too_many``: (the first state whose successors could not all be
        enumerated, why), where the sequential search stops before that state's successors."""
        def first_full(s):
            while s < hi and s in errors:
                s += 1
            return s if s < hi else None

        cands = []
        if too_many is not None:
            cands.append((too_many[0] - 1, "too many"))
        total = len(self.state_props) + len(self.step_props) + (1 if self.deadlock else 0)
        if total and not self.keep_graph:
            # (as in the sequential search, an error is not one of the properties)
            names = set(chosen) - {"error"}
            trigger = lo if len(names) >= total else None
            if trigger is None and len(names | (set(level_fail) - {"error"})) >= total:
                for name, rec in sorted(level_fail.items(), key=lambda kv: kv[1][0]):
                    if name == "error":
                        continue
                    names.add(name)
                    if len(names) >= total:
                        trigger = rec[0][0]
                        break
            if trigger is not None:
                s = first_full(trigger)
                if s is not None:
                    cands.append((s, "all"))
        if self.max_states is not None and n_states + new_total >= self.max_states:
            if n_states >= self.max_states:
                s = first_full(lo)
                if s is not None:
                    cands.append((s, "state limit"))
            else:
                per_parent = {}
                for keys in received:
                    for k in keys:
                        p = k >> SHIFT
                        per_parent[p] = per_parent.get(p, 0) + 1
                c = n_states
                for p in sorted(per_parent):
                    c += per_parent[p]
                    if c >= self.max_states:
                        cands.append((p, "state limit"))
                        break
        if not cands:
            return None
        # at the same state the sequential search checks the state limit first; it stops at a
        # limit after a state's successors before it meets the next state's enumeration
        return min(cands, key=lambda c: (c[0], c[1] == "too many", c[1] != "state limit"))

    def _partial(self, t0, n_states, transitions, depth_seen, chosen, reason, stop) -> Result:
        """The report of a search that a worker's limit ended: what the completed levels found."""
        self.n_states = n_states
        violations = [self._violation(chosen[name][1]) for name in sorted(chosen, key=lambda nm: chosen[nm][0])]
        res = Result("violated" if violations else "incomplete", n_states, transitions, depth_seen,
                     time.perf_counter() - t0, violations, reason,
                     self.state_props + self.step_props)
        res.reason = reason
        res.stop = stop
        res.deadlock_checked = self.deadlock
        return res

    def _violation(self, rec) -> Violation:
        (sid, kind, j, i), pidx, src, key, picks, msg, err = rec
        if kind == K_STATE:
            return Violation(self.state_props[pidx], sid, message=msg, error=err)
        if kind == K_ERROR:
            return Violation(PseudoProperty("error", "error", err.span if err is not None else None), sid,
                             message=msg, error=err)
        if kind == K_DEADLOCK:
            return Violation(DEADLOCK, sid, message=msg)
        tid = self.b.call(self.owner_of_key(key), "lookup", [key])[0]
        return Violation(self.step_props[pidx], tid, src, picks, message=msg, error=err)
