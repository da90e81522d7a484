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

# the successors (of the last sources asked for) whose choices PartitionedExplorer.picks keeps
PICKS_HELD = 1 << 15


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
        if self.col == 2:
            return self.view._via(sid)
        return self.view._record(sid)[self.col]


class PartitionedExplorer(Explorer):
    def __init__(self, machine, search, state_props=(), step_props=(), deadlock=False, keep_graph=False):
        super().__init__(machine, state_props=state_props, step_props=step_props, deadlock=deadlock,
                         keep_graph=keep_graph)
        self.search = search
        self._n = 0
        self._cache: dict = {}
        self._picks_src: dict = {}      # source -> its successors [(choices, frozen state)], the last few
        self._picks_held = 0            # how many successors _picks_src holds
        self.gathered = False

    @property
    def n_states(self) -> int:
        """The number of states the partitioned search found (all owners together)."""
        return self._n

    def finish(self, result) -> None:
        """After the search: gather the graph (when kept) or fetch the states the traces need."""
        s = self.search
        self._n = s.n_states
        # the failing branches, in the sequential search's order (for asmcheck.temporal's halts)
        self.error_edges = list(s.error_edges)
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
        for v in result.violations:
            if isinstance(v.picks, int):
                v.picks = self.picks(v.source, v.picks, self.frozen[v.state])

    def _gather(self) -> None:
        n = self.n_states
        frozen = [None] * n
        parent = array("l", [0]) * n
        depth = array("l", [0]) * n
        via = [None] * n
        b = self.search.b
        state_of = self.search.x.state_of
        for w in range(b.n):
            for sid, key, par, picks, d in b.call(w, "gather"):
                if sid >= n:
                    continue
                frozen[sid] = self.layout.freeze(state_of(key))
                parent[sid] = par
                via[sid] = picks
                depth[sid] = d
        self.frozen = frozen
        self.index = {fz: i for i, fz in enumerate(frozen)}
        self.parent = parent
        self.depth_of = depth
        self.via = _Choices(self, via)
        self.edges = _Edges(self, self.search.edges)
        self.gathered = True

    def edge_arrays(self):
        """(sources, targets) of the gathered graph, without choices."""
        e = self.search.edges
        return array("q", [x[0] for x in e]), array("q", [x[1] for x in e])

    def _record(self, sid: int):
        r = self._cache.get(sid)
        if r is None:
            w = self.search.owner[sid]
            key, par, picks, d = self.search.b.call(w, "fetch", [sid])[0]
            fz = self.layout.freeze(self.search.x.state_of(key))
            r = self._cache[sid] = (fz, par, picks, d)
        return r

    def _via(self, sid: int):
        """The choices of the step to state ``sid`` (a position turned into choices here, once)."""
        fz, par, picks, d = self._record(sid)
        if isinstance(picks, int):
            picks = self.picks(par, picks, fz)
            self._cache[sid] = (fz, par, picks, d)
        return picks

    def picks(self, src: int, position: int, target) -> tuple:
        """The choices of the step from state ``src`` to its successor at ``position``, which is the
        state frozen as ``target`` (the native expander sends positions; the Python step function
        gives the choices, for the few states a trace or the graph shows; the successors of the
        last sources, up to PICKS_HELD of them, are kept: the states' choices, then the edges',
        ask for the same sources).  Where the Python step function's successor at that position
        is another state, the first of its successors that is ``target`` gives them, as the
        native engine's own replay finds them."""
        from ..explore.bfs import ReplayError
        cache = self._picks_src
        succ = cache.get(src)
        if succ is None:
            # (a state where some branch fails has its well-defined successors in the graph)
            succ = [(s[0], self.layout.freeze(s[3])) for s in self.admitted_successors(self.state(src), errors=[])]
            while cache and self._picks_held + len(succ) > PICKS_HELD:
                self._picks_held -= len(cache.pop(next(iter(cache))))
            cache[src] = succ
            self._picks_held += len(succ)
        if 0 <= position < len(succ) and succ[position][1] == target:
            return succ[position][0]
        for picks, fz in succ:
            if fz == target:
                return picks
        raise ReplayError(f"no step of the Python step function goes from state {src} to a state of the search")


class _Choices:
    """The choices of each state's step from its parent (positions resolved on demand)."""

    def __init__(self, view, via):
        self.view = view
        self.via = via

    def __len__(self):
        return len(self.via)

    def __getitem__(self, sid):
        p = self.via[sid]
        if isinstance(p, int):
            p = self.via[sid] = self.view.picks(self.view.parent[sid], p, self.view.frozen[sid])
        return p

    def __iter__(self):
        for sid in range(len(self.via)):
            yield self[sid]


class _Edges:
    """The transitions (source, target, choices) of the gathered graph (positions resolved on
    demand, source by source)."""

    def __init__(self, view, edges):
        self.view = view
        self.e = edges

    def __len__(self):
        return len(self.e)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self.e)))]
        a, b, p = self.e[i]
        if isinstance(p, int):
            p = self.view.picks(a, p, self.view.frozen[b])
            self.e[i] = (a, b, p)
        return a, b, p

    def __iter__(self):
        for i in range(len(self.e)):
            yield self[i]
