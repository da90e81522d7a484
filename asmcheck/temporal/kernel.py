"""The LTL product and its fair components computed over arrays by compiled code (kernel.c,
model-independent, compiled once and cached as the native engine's models are).

:func:`product_and_fair` gives what :func:`asmcheck.temporal.ltl.check_ltl` computes in Python
-- the product nodes numbered in the same breadth-first order, their successor lists, the
initial nodes and the fair components -- or None when the kernel cannot be used (no C
compiler, a past operator, more than 64 literals); the caller then runs the Python code.
"""
from __future__ import annotations

import ctypes
from array import array
from importlib import resources
from itertools import accumulate, chain

ENABLED = True                 # tests switch the kernel off to compare with the Python code

_i64, _p = ctypes.c_int64, ctypes.c_void_p
_SYMBOLS = {
    "kn_product": (_i64, [_i64, _p, _p, _p, _p, _i64, _p, _i64, _p, _p, _i64, _p, _p, _p]),
    "kn_sig": (None, [_i64, _i64, _p, _p, _p]),
    "kn_adj_len": (_i64, []),
    "kn_init_len": (_i64, []),
    "kn_nodes": (None, [_p, _p]),
    "kn_succ": (None, [_p, _p, _p]),
    "kn_map": (None, [_i64, _p, _p]),
    "kn_fair": (_i64, [_i64, _p, _i64, _p, _p, _p]),
    "kn_free": (None, []),
    "kn_fair_graph": (_i64, [_i64, _p, _p, _p, _i64, _p, _p, _i64, _p, _i64, _p, _p, _p]),
    "kn_eu": (_i64, [_i64, _i64, _p, _p, _p, _p, _p, _p]),
}
_dll = None
_failed = False


def library():
    """The loaded kernel, or None (no compiler, or it failed once in this process)."""
    global _dll, _failed
    if _dll is not None or _failed or not ENABLED:
        return _dll if ENABLED else None
    try:
        from ..explore import native_build
        src = resources.files("asmcheck.temporal").joinpath("kernel.c").read_text()
        _dll = native_build.build(src, _SYMBOLS)
    except Exception:           # no compiler, a failed build: the Python code runs
        _failed = True
        return None
    return _dll


def _addr(buf) -> int:
    return ctypes.addressof(ctypes.c_char.from_buffer(buf)) if len(buf) else 0


def _arr(typecode, items) -> array:
    a = array(typecode, items)
    if not len(a):
        a.append(0)
    return a


def product_and_fair(K, g, ap_bits, posm, negm, justice_k, justice_q, compassion_k):
    """``ap_bits``: (bit, Kripke label) per atom literal; ``posm``/``negm``: literal masks per
    automaton node; ``justice_q``: acceptance sets over automaton nodes; ``justice_k`` and
    ``compassion_k``: sets over Kripke nodes.  Returns ``(N, fair, build)``: the number of
    product nodes, the number of fair components and a function giving, on demand, ``(kk, qq,
    succ, init, comps, justice, compassion)`` as the Python code has them (for a lasso)."""
    dll = library()
    if dll is None:
        return None
    n = K.n
    Q = max(len(g.nodes), 1)
    cls = _arr("i", K.cls)
    lens = [len(x) for x in K.cls_succ]
    coff = array("i", [0])
    coff.extend(accumulate(lens))
    cadj = _arr("i", chain.from_iterable(K.cls_succ))
    labels = bytearray()
    bits = array("Q")
    for b, lab in ap_bits:
        labels += lab
        bits.append(b)
    if not len(bits):
        bits.append(0)
    if not labels:
        labels = bytearray(1)
    sig = array("Q", bytes(8 * max(n, 1)))
    dll.kn_sig(n, len(ap_bits), _addr(labels), _addr(bits), _addr(sig))
    kinit = _arr("i", K.init)
    goff = array("i", [0])
    goff.extend(accumulate(len(x) for x in g.succ))
    if len(goff) < Q + 1:
        goff.extend([goff[-1]] * (Q + 1 - len(goff)))
    gadj = _arr("i", chain.from_iterable(g.succ))
    ginit = _arr("i", g.init)
    pm = _arr("Q", posm)
    nm = _arr("Q", negm)
    N = dll.kn_product(n, _addr(cls), _addr(coff), _addr(cadj), _addr(sig), len(K.init), _addr(kinit), Q,
                       _addr(goff), _addr(gadj), len(g.init), _addr(ginit), _addr(pm), _addr(nm))
    if N < 0:
        dll.kn_free()
        return None

    def mapped(by_q, src):
        out = bytearray(max(N, 1))
        s = bytearray(src) if len(src) else bytearray(1)
        dll.kn_map(by_q, _addr(s), _addr(out))
        return out[:N]

    justice = [mapped(1, acc) for acc in justice_q] + [mapped(0, lab) for lab in justice_k]
    compassion = [(mapped(0, p), mapped(0, q)) for p, q in compassion_k]
    # justice sets met everywhere constrain nothing
    justice = [j for j in justice if j.count(0)]
    just = bytearray().join(justice) or bytearray(1)
    cp = bytearray().join(p for p, _ in compassion) or bytearray(1)
    cq = bytearray().join(q for _, q in compassion) or bytearray(1)
    comp = array("i", bytes(4 * max(N, 1)))
    nfair = dll.kn_fair(len(justice), _addr(just), len(compassion), _addr(cp), _addr(cq), _addr(comp))
    if nfair < 0:
        dll.kn_free()
        return None

    def build():
        kk = array("i", bytes(4 * max(N, 1)))
        qq = array("i", bytes(4 * max(N, 1)))
        dll.kn_nodes(_addr(kk), _addr(qq))
        na = dll.kn_adj_len()
        ni = dll.kn_init_len()
        off = array("i", bytes(4 * (N + 1)))
        adj = array("i", bytes(4 * max(na, 1)))
        init = array("i", bytes(4 * max(ni, 1)))
        dll.kn_succ(_addr(off), _addr(adj), _addr(init))
        succ = [adj[off[i]:off[i + 1]].tolist() for i in range(N)]
        groups: dict = {}
        for v in range(N):
            c = comp[v]
            if c >= 0:
                groups.setdefault(c, []).append(v)
        comps = sorted(groups.values())
        dll.kn_free()
        return kk[:N].tolist(), qq[:N].tolist(), succ, init[:ni].tolist(), comps, justice, compassion

    if nfair == 0:
        dll.kn_free()
        return N, 0, None
    return N, nfair, build


def _csr(K):
    """(cls, off, adj) of the Kripke structure's successor classes, made once per structure."""
    got = getattr(K, "_kernel_csr", None)
    if got is None:
        cls = _arr("i", K.cls)
        off = array("i", [0])
        off.extend(accumulate(len(x) for x in K.cls_succ))
        adj = _arr("i", chain.from_iterable(K.cls_succ))
        got = K._kernel_csr = (cls, off, adj)
    return got


def fair_sccs(K, s: bytearray, justice, compassion):
    """:func:`asmcheck.temporal.graph.fair_sccs` on the Kripke structure restricted to the nodes
    of ``s`` (roots: those nodes), by compiled code; None when it is not available."""
    dll = library()
    if dll is None:
        return None
    n = K.n
    cls, off, adj = _csr(K)
    roots = _arr("i", (i for i in range(n) if s[i]))
    nroots = s.count(1)
    mask = bytearray(s) if len(s) else bytearray(1)
    just = bytearray().join(justice) or bytearray(1)
    cp = bytearray().join(p for p, _ in compassion) or bytearray(1)
    cq = bytearray().join(q for _, q in compassion) or bytearray(1)
    comp = array("i", bytes(4 * max(n, 1)))
    nfair = dll.kn_fair_graph(n, _addr(cls), _addr(off), _addr(adj), nroots, _addr(roots), _addr(mask),
                              len(justice), _addr(just), len(compassion), _addr(cp), _addr(cq), _addr(comp))
    if nfair < 0:
        return None
    if nfair == 0:
        return []
    groups: dict = {}
    for v in range(n):
        c = comp[v]
        if c >= 0:
            groups.setdefault(c, []).append(v)
    return sorted(groups.values())


def eu(K, f: bytearray, start: bytearray):
    """The nodes from which a path of ``f`` nodes reaches a ``start`` node (E[f U start]), by
    compiled code over the successor classes; None when it is not available."""
    dll = library()
    if dll is None:
        return None
    n = K.n
    if n == 0:
        return bytearray()
    cls, off, adj = _csr(K)
    fb, sb = bytearray(f), bytearray(start)
    y = bytearray(n)
    if dll.kn_eu(n, len(off) - 1, _addr(cls), _addr(off), _addr(adj), _addr(fb), _addr(sb), _addr(y)) != 0:
        return None
    return y
