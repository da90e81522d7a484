"""Successor lists kept as flat arrays (the Kripke structure's and the LTL product's)."""
from __future__ import annotations

from array import array


class Classes:
    """The successor classes as two arrays: class c's list is ``adj[off[c]:off[c + 1]]``; lists
    replaced or appended later (halt nodes) are kept apart.  Reads as a list of lists."""

    def __init__(self, off: array, adj: array):
        self.off, self.adj = off, adj
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
        return self.adj[self.off[c]:self.off[c + 1]].tolist()

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

    def arrays(self) -> tuple[array, array]:
        """(off, adj) with the replaced and appended lists."""
        if not self.over and not self.extra:
            return self.off, self.adj
        off, adj = array("i", [0]), array("i")
        for lst in self:
            adj.extend(lst)
            off.append(len(adj))
        return off, adj
