"""Bitstate search (``explore --bitstate BITS``): states too many to store, remembered as bits.

The search is the sequential breadth-first search, except that a visited state leaves only
``K`` bits set in a table of ``2**BITS`` bits (positions from its 64-bit stable hash, by double
hashing).  A new state whose ``K`` bits are all set already is taken for visited: it is *missed*,
and so is what only it leads to.  The search keeps per state only its parent, the choices of the
step from it and its hash; the states of the current and next level are kept whole.

The chance of a miss is known while the search runs: when the i-th distinct state is met with a
fraction f_i of the table's bits set, it is taken for visited with probability f_i**K.  The report
gives the expected number of missed states (the sum of f_i**K, plus the chance that two of the
states share a 64-bit hash) and the probability that some state was missed (at most that sum).
A violation found is real (its trace is replayed); "holds" is "holds for every state visited".
"""
from __future__ import annotations

import math
from array import array

from ..explore.bfs import Explorer
from .stable import MASK, StateHasher, mix

K = 3


class BitstateExplorer(Explorer):
    def __init__(self, machine, bits: int, **kw):
        if not 10 <= bits <= 40:
            raise ValueError("--bitstate expects 10 to 40 (a table of 2**BITS bits)")
        kw.pop("keep_graph", None)
        super().__init__(machine, keep_graph=False, **kw)
        self.bits = bits
        self.m_bits = 1 << bits
        self.table = bytearray(self.m_bits >> 3)
        self.set_bits = 0
        self.hasher = StateHasher()
        self.hashes = array("Q")
        self.live: dict = {}            # number -> frozen state, for states not yet expanded
        self.recent: dict = {}          # hash -> number, for the states of the last levels
        self._n = 0
        self.frozen = _Count(self)
        self.expected_missed = 0.0
        self._level_mark = 0

    @property
    def n_states(self) -> int:
        """The number of states counted so far (the table keeps no states)."""
        return self._n

    @n_states.setter
    def n_states(self, n: int) -> None:
        self._n = n

    def _positions(self, h: int):
        a = h & 0xFFFFFFFF
        b = (mix(h ^ 0x2545F4914F6CDD1D) | 1) & MASK
        m = self.m_bits
        return [(a + i * b) % m for i in range(K)]

    def _add(self, st: dict, parent: int, picks, depth: int):
        h = self.hasher(st.items())
        known = self.recent.get(h)
        if known is not None:
            return known, False
        pos = self._positions(h)
        table = self.table
        if all(table[p >> 3] >> (p & 7) & 1 for p in pos):
            # visited (or a miss: the estimate below accounts for it)
            return -2 - (h & 0x3FFFFFFFFFFFFFFF), False
        self.expected_missed += (self.set_bits / self.m_bits) ** K
        for p in pos:
            byte = table[p >> 3]
            bit = 1 << (p & 7)
            if not byte & bit:
                table[p >> 3] = byte | bit
                self.set_bits += 1
        sid = self.n_states
        self.n_states += 1
        self.hashes.append(h)
        self.parent.append(parent)
        self.depth_of.append(depth)
        self.via.append(picks)
        self.live[sid] = self.layout.freeze(st)
        self.recent[h] = sid
        return sid, True

    def state(self, sid: int) -> dict:
        fz = self.live.pop(sid, None)
        if fz is not None:
            d = self.depth_of[sid]
            if d != self._level_mark:
                # a new level: keep the hashes of the states from the one before it on, so that
                # self-loops and steps within these levels name their target exactly
                self._level_mark = d
                self.recent = {hh: s for hh, s in self.recent.items() if self.depth_of[s] >= d - 1}
            return self.layout.thaw(fz)
        return self.replay(self.path_to(sid))[-1][0]

    def is_stored(self, st: dict, sid: int) -> bool:
        """The table keeps only hashes: a replayed state is checked against the stored hash (a
        target numbered below 0 is not checked)."""
        return sid < 0 or self.hasher(st.items()) == self.hashes[sid]

    def report(self) -> dict:
        """The table, its fill and the chance of a missed state."""
        n = self.n_states
        collide = n * (n - 1) / 2 / 2.0 ** 64
        expected = self.expected_missed + collide
        return {"bits": self.bits, "hashes": K, "table_bytes": len(self.table),
                "fill": self.set_bits / self.m_bits, "expected_missed": expected,
                "p_missed": min(1.0, expected), "p_none_missed": max(0.0, math.exp(-expected))}

    def note(self) -> str:
        r = self.report()
        return (f"bitstate search: 2^{r['bits']} bits ({_size(r['table_bytes'])}), {K} hashes, {r['fill']:.2%} set; "
                f"probability that a reachable state was missed <= {_p(r['p_missed'])} "
                f"(expected states missed directly {_p(r['expected_missed'])})")


class _Count:
    """``len(explorer.frozen)`` for the sequential search's limits and progress."""

    def __init__(self, ex):
        self.ex = ex

    def __len__(self):
        return self.ex.n_states


def _p(x: float) -> str:
    if x == 0:
        return "0"
    if x >= 0.01:
        return f"{x:.3f}"
    return f"{x:.1e}"


def _size(b: float) -> str:
    for unit in ("bytes", "KB", "MB"):
        if b < 1024:
            return f"{b:.0f} {unit}"
        b /= 1024
    return f"{b:.0f} GB"
