"""Successor lists kept as flat arrays (the Kripke structure's and the LTL product's)."""
from __future__ import annotations

from array import array


class Classes:
    """The successor classes as two arrays: class c's list is ``adj[off[c]:off[c + 1]]``; lists
    replaced or appended later (halt nodes) are kept apart.  Reads as a list of lists.

    ``adj`` holds 32-bit (array('i')) or 16-bit (array('H')) entries.  With ``tab`` (array('i'))
    and ``key`` (array('i'), one a class) its 16-bit entries are states: the node of entry t of
    class c's list is ``tab[key[c] * nstates + t]`` -- a structure whose nodes are (key, target)
    pairs, every entry of a list with its class's key (the temporal quotient of a spec whose atoms
    read no monitored function: a list is its state's targets), so that a list takes 2 bytes an
    entry even with more than 65,536 nodes."""

    def __init__(self, off: array, adj: array, key: array | None = None, tab: array | None = None,
                 nstates: int = 0):
        self.off, self.adj = off, adj
        self.key, self.tab, self.nstates = key, tab, nstates
        self.base = len(off) - 1
        self.over: dict = {}
        self.extra: list = []

    def __len__(self):
        return self.base + len(self.extra)

    def __getitem__(self, c):
        if c >= self.base:
            return self.extra[c - self.base]
        got = self.over.get(c)
        if got is not None:
            return got
        part = self.adj[self.off[c]:self.off[c + 1]]
        if self.tab is not None:
            tab, row = self.tab, self.key[c] * self.nstates
            return [tab[row + t] for t in part]
        return part.tolist()

    def __setitem__(self, c, lst):
        if c >= self.base:
            self.extra[c - self.base] = list(lst)
        else:
            self.over[c] = list(lst)

    def append(self, lst):
        self.extra.append(list(lst))

    def __iter__(self):
        for c in range(len(self)):
            yield self[c]

    def layout(self):
        """(off, adj, mode, key, tab, nstates) as the compiled kernel reads them (mode 0: 32-bit
        entries, 1: 16-bit, 2: 16-bit states through ``tab``), or None when lists were replaced or
        appended (then :meth:`arrays`)."""
        if self.over or self.extra:
            return None
        if self.tab is not None:
            return self.off, self.adj, 2, self.key, self.tab, self.nstates
        return self.off, self.adj, (1 if self.adj.typecode == "H" else 0), None, None, 0

    def arrays(self) -> tuple[array, array]:
        """(off, adj) with the replaced and appended lists, 32-bit entries."""
        if not self.over and not self.extra and self.tab is None and self.adj.typecode == "i":
            return self.off, self.adj
        off, adj = array("i", [0]), array("i")
        for lst in self:
            adj.extend(lst)
            off.append(len(adj))
        return off, adj
