"""The explorer object of a partitioned search, as reports and traces expect it.

It answers the questions of :class:`asmcheck.explore.bfs.Explorer` (``path_to``, ``replay``,
``state``, ``parent``, ``via``, ``frozen``, ``edges``).  With the graph kept (``--graph``, LTL,
CTL) every state is gathered here after the search.  Otherwise the states stay with their
owners: a trace is rebuilt by walking parent links from owner to owner, and the few states on
it are fetched (and then replayed through the step function, as always).
"""
from __future__ import annotations

from array import array

from ..explore.bfs import Explorer


class _Lazy:
    """One per-state column, fetched from the owners on demand."""

    def __init__(self, view, col):
        self.view = view
        self.col = col

    def __len__(self):
        return self.view.n_states

    def __getitem__(self, sid):
        if sid < 0:
            sid += self.view.n_states
        if not 0 <= sid < self.view.n_states:
            raise IndexError(sid)
        return self.view._record(sid)[self.col]


class PartitionedExplorer(Explorer):
    def __init__(self, machine, search, state_props=(), step_props=(), deadlock=False, keep_graph=False):
        super().__init__(machine, state_props=state_props, step_props=step_props, deadlock=deadlock,
                         keep_graph=keep_graph)
        self.search = search
        self._n = 0
        self._cache: dict = {}
        self.gathered = False

    @property
    def n_states(self) -> int:
        """The number of states the partitioned search found (all owners together)."""
        return self._n

    def finish(self, result) -> None:
        """After the search: gather the graph (when kept) or fetch the states the traces need."""
        s = self.search
        self._n = s.n_states
        if self.keep_graph:
            self._gather()
        else:
            self.frozen = _Lazy(self, 0)
            self.parent = _Lazy(self, 1)
            self.via = _Lazy(self, 2)
            self.depth_of = _Lazy(self, 3)
            for v in result.violations:
                for sid in (v.state, v.source):
                    while sid is not None and sid >= 0:
                        sid = self._record(sid)[1]

    def _gather(self) -> None:
        n = self.n_states
        frozen = [None] * n
        parent = array("l", [0]) * n
        depth = array("l", [0]) * n
        via = [None] * n
        b = self.search.b
        for w in range(b.n):
            for sid, key, par, picks, d in b.call(w, "gather"):
                if sid >= n:
                    continue
                frozen[sid] = self.layout.freeze(dict(key))
                parent[sid] = par
                via[sid] = picks
                depth[sid] = d
        self.frozen = frozen
        self.index = {fz: i for i, fz in enumerate(frozen)}
        self.parent = parent
        self.depth_of = depth
        self.via = via
        self.edges = self.search.edges
        self.gathered = True

    def _record(self, sid: int):
        r = self._cache.get(sid)
        if r is None:
            w = self.search.owner[sid]
            key, par, picks, d = self.search.b.call(w, "fetch", [sid])[0]
            r = self._cache[sid] = (self.layout.freeze(dict(key)), par, picks, d)
        return r
