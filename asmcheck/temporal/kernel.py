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

from .classes import Classes

ENABLED = True                 # tests switch the kernel off to compare with the Python code
# E[f U g] on a structure whose lists hold more entries than this runs first by passes over the
# forward lists (kn_eu_fwd), and makes the backward lists (2 or 4 bytes an entry) only when
# EU_FORWARD_PASSES passes did not reach the fixpoint; tests change both
EU_FORWARD_ENTRIES = 0
EU_FORWARD_PASSES = 8

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
    "kn_fair_graph": (_i64, [_i64, _i64, _p, _p, _p, _i64, _p, _p, _i64, _p, _i64, _p, _p, _p]),
    "kn_eu_fwd": (_i64, [_i64, _i64, _p, _p, _p, _p, _p, _p, _p, _i64]),
    "kn_class_nodes": (None, [_i64, _i64, _p, _p, _p]),
    "kn_layout": (None, [_i64, _p, _p, _i64]),
    "kn_csr": (_i64, [_i64, _i64, _p, _p, _p, _p, _p]),
    "kn_gather": (None, [_i64, _p, _p, _p]),
    "kn_bit": (None, [_i64, _p, _i64, _p]),
    "kn_bit8": (None, [_i64, _p, _i64, _p]),
    "kn_ex": (_i64, [_i64, _i64, _p, _p, _p, _p, _p]),
    "kn_group": (_i64, [_i64, _i64, _p, _p, _p]),
    "kn_in_comp": (None, [_i64, _p, _p]),
    "kn_quotient": (_i64, [_i64, _i64, _p, _p, _p, _p, _p, _p, _p, _p]),
    "kn_quotient_first": (None, [_p]),
    "kn_ascending": (_i64, [_i64, _p]),
    "kn_rev": (None, [_i64, _i64, _p, _p, _p, _p, _p, _p, _p]),
    "kn_eu_rev": (_i64, [_i64, _i64, _p, _p, _p, _p, _p, _p, _p]),
    "kn_rev_16": (None, [_i64, _i64, _p, _p, _p, _p, _p, _p, _p]),
    "kn_eu_rev_16": (_i64, [_i64, _i64, _p, _p, _p, _p, _p, _p, _p]),
    "kn_bfs": (_i64, [_i64, _i64, _p, _p, _p, _i64, _p, _p, _p, _p, _i64, _p]),
    "kn_mark": (None, [_i64, _p, _p]),
    "kn_all_succ": (_i64, [_i64, _p, _p]),
    "kn_qs_begin": (_i64, [_i64, _p]),
    "kn_qs_add": (_i64, [_i64, _i64, _p, ctypes.c_uint64, _p]),
    "kn_qs_end": (_i64, []),
    "kn_qs_len": (_i64, []),
    "kn_qs_take": (None, [_p, _p, _p, _p]),
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
    cls, coff, cadj = _csr(K)
    labels = bytearray()
    bits = array("Q")
    for b, lab in ap_bits:
        labels += lab
        bits.append(b)
    if not len(bits):
        bits.append(0)
    if not labels:
        labels = bytearray(1)
    sig = array("Q", [0]) * max(n, 1)
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
    comp = array("i", [0]) * max(N, 1)
    nfair = dll.kn_fair(len(justice), _addr(just), len(compassion), _addr(cp), _addr(cq), _addr(comp))
    if nfair < 0:
        dll.kn_free()
        return None

    def build():
        # the product's successors are made again from these arrays (kernel.c: prod_succ), read in
        # the Kripke structure's layout
        _csr(K)
        _ = (sig, goff, gadj, pm, nm)       # (held until then: the kernel reads them)
        kk = array("i", [0]) * max(N, 1)
        qq = array("i", [0]) * max(N, 1)
        dll.kn_nodes(_addr(kk), _addr(qq))
        na = dll.kn_adj_len()
        ni = dll.kn_init_len()
        off = array("i", [0]) * (N + 1)
        adj = array("i", [0]) * max(na, 1)
        init = array("i", [0]) * max(ni, 1)
        dll.kn_succ(_addr(off), _addr(adj), _addr(init))
        succ = Classes(off, adj[:max(na, 1)])      # a product node's successors, made when a path asks
        groups: dict = {}
        for v in range(N):
            c = comp[v]
            if c >= 0:
                groups.setdefault(c, []).append(v)
        comps = sorted(groups.values())
        dll.kn_free()
        del kk[N:], qq[N:]
        return kk, qq, succ, init[:ni].tolist(), comps, justice, compassion

    if nfair == 0:
        dll.kn_free()
        return N, 0, None
    return N, nfair, build


def _csr(K):
    """(cls, off, adj) of the Kripke structure's successor classes, made once per structure
    (the structure's own arrays when it keeps them so); the kernel is told their layout
    (:class:`~asmcheck.temporal.classes.Classes`: 32-bit or 16-bit entries, or 16-bit states
    with a node table), so call it right before the kernel reads them."""
    got = getattr(K, "_kernel_csr", None)
    if got is None:
        cls = K.cls if isinstance(K.cls, array) and K.cls.typecode == "i" and len(K.cls) else _arr("i", K.cls)
        lay = None
        layout = getattr(K.cls_succ, "layout", None)
        arrays = getattr(K.cls_succ, "arrays", None)
        if layout is not None:
            lay = layout()
        if lay is not None:
            off, adj = lay[0], lay[1]
        elif arrays is not None:
            off, adj = arrays()
        else:
            off = array("i", [0])
            off.extend(accumulate(len(x) for x in K.cls_succ))
            adj = _arr("i", chain.from_iterable(K.cls_succ))
        if not len(adj):
            adj = _arr(adj.typecode, ())
        mode, key, tab, ns = (lay[2], lay[3], lay[4], lay[5]) if lay is not None else (0, None, None, 0)
        got = K._kernel_csr = (cls, off, adj, (mode, key, tab, ns))
    dll = library()
    mode, key, tab, ns = got[3]
    if dll is not None:
        dll.kn_layout(mode, _addr(key) if key is not None and len(key) else 0,
                      _addr(tab) if tab is not None and len(tab) else 0, ns)
    return got[:3]


def _identity(K, cls) -> bool:
    """Whether node v's class is v (a state graph's), found once per structure."""
    got = getattr(K, "_kernel_ident", None)
    if got is None:
        got = K._kernel_ident = cls == array("i", range(len(cls)))
    return got


def _u32(a) -> array:
    return a if isinstance(a, array) and a.typecode == "I" else array("I", a)


def csr(n: int, src, dst, ok: bytearray):
    """(off, adj): the successor lists of the n nodes of the graph whose edges are ``src[e] ->
    dst[e]`` (two sequences), the edges between nodes with ``ok`` set only, each list ascending
    and without repeats; ``off`` has n + 1 entries (array('i'))."""
    dll = library()
    ne = len(src)
    if dll is not None:
        s, d = _u32(src), _u32(dst)
        off = array("i", [0]) * (n + 1)
        adj = array("i", [0]) * max(ne, 1)
        okb = bytearray(ok) if len(ok) else bytearray(1)
        k = dll.kn_csr(n, ne, _addr(s) if ne else 0, _addr(d) if ne else 0, _addr(okb), _addr(off), _addr(adj))
        if k >= 0:
            del adj[k:]
            return off, adj
    succ: list = [[] for _ in range(n)]
    for a, b in zip(src, dst):
        if ok[a] and ok[b]:
            succ[a].append(b)
    off = array("i", [0])
    adj = array("i")
    for lst in succ:
        adj.extend(sorted(set(lst)))
        off.append(len(adj))
    return off, adj


def group(n: int, owner) -> tuple[array, array]:
    """(off, adj): for each of the n owners, the positions i with ``owner[i]`` equal to it,
    ascending."""
    m = len(owner)
    off = array("i", [0]) * (n + 1)
    adj = array("i", [0]) * max(m, 1)
    dll = library()
    if dll is not None and m:
        ow = _u32(owner)
        if dll.kn_group(n, m, _addr(ow), _addr(off), _addr(adj)) == 0:
            del adj[m:]
            return off, adj
    del adj[m:]
    for o in owner:
        off[o + 1] += 1
    for v in range(n):
        off[v + 1] += off[v]
    pos = array("i", off)
    for i, o in enumerate(owner):
        adj[pos[o]] = i
        pos[o] += 1
    return off, adj


def gather(idx, lab) -> bytearray:
    """bytearray(lab[i] for i in idx), by compiled code when it is there."""
    n = len(idx)
    dll = library()
    if dll is not None and n and len(lab):
        ix = _u32(idx)
        src = bytearray(lab)
        out = bytearray(n)
        dll.kn_gather(n, _addr(ix), _addr(src), _addr(out))
        return out
    return bytearray(lab[i] for i in idx)


def bit(vec, k: int) -> bytearray:
    """bytearray(bit k of each vec[i]) for an array('q') of bit vectors."""
    n = len(vec)
    dll = library()
    if dll is not None and n and isinstance(vec, array) and vec.typecode in ("q", "B"):
        out = bytearray(n)
        (dll.kn_bit if vec.typecode == "q" else dll.kn_bit8)(n, _addr(vec), k, _addr(out))
        return out
    return bytearray((x >> k) & 1 for x in vec)


def ex(K, g: bytearray):
    """The nodes with a successor in ``g`` (over the successor classes), or None."""
    dll = library()
    if dll is None:
        return None
    n = K.n
    if n == 0:
        return bytearray()
    cls, off, adj = _csr(K)
    gb = bytearray(g)
    y = bytearray(n)
    if dll.kn_ex(n, len(off) - 1, _addr(cls), _addr(off), _addr(adj), _addr(gb), _addr(y)) != 0:
        return None
    return y


def fair_comp(K, s: bytearray, justice, compassion):
    """The fair components of the Kripke structure restricted to the nodes of ``s`` (roots:
    those nodes), by compiled code: (number of components, array('i') giving each node's
    component, -1 outside every one), or None when the code is not available."""
    dll = library()
    if dll is None:
        return None
    n = K.n
    cls, off, adj = _csr(K)
    mask = bytearray(s) if len(s) else bytearray(1)
    just = bytearray().join(justice) or bytearray(1)
    cp = bytearray().join(p for p, _ in compassion) or bytearray(1)
    cq = bytearray().join(q for _, q in compassion) or bytearray(1)
    comp = array("i", [0]) * max(n, 1)
    # the roots: every node of s, ascending (passed as none); a state graph's classes are its
    # nodes (no relay vertices)
    relay = not _identity(K, cls)
    nfair = dll.kn_fair_graph(n, len(off) - 1 if relay else 0, _addr(cls) if relay else 0, _addr(off), _addr(adj),
                              n, 0, _addr(mask),
                              len(justice), _addr(just), len(compassion), _addr(cp), _addr(cq), _addr(comp))
    if nfair < 0:
        return None
    return nfair, comp


def in_comp(comp: array, n: int) -> bytearray:
    """The nodes that lie in a component (``comp[v] >= 0``)."""
    out = bytearray(max(n, 1))
    dll = library()
    if dll is not None and n:
        dll.kn_in_comp(n, _addr(comp), _addr(out))
        return out[:n]
    return bytearray(1 if comp[v] >= 0 else 0 for v in range(n))


def comp_lists(nfair: int, comp: array, n: int) -> list:
    """The components as sorted lists of nodes, in the order of their first nodes."""
    if nfair == 0:
        return []
    groups: dict = {}
    for v in range(n):
        c = comp[v]
        if c >= 0:
            groups.setdefault(c, []).append(v)
    return sorted(groups.values())


def fair_sccs(K, s: bytearray, justice, compassion):
    """:func:`asmcheck.temporal.graph.fair_sccs` on the Kripke structure restricted to the nodes
    of ``s`` (roots: those nodes), by compiled code; None when it is not available."""
    got = fair_comp(K, s, justice, compassion)
    if got is None:
        return None
    return comp_lists(got[0], got[1], K.n)


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
    ncls = len(off) - 1
    fb, sb = bytearray(f), bytearray(start)
    y = bytearray(n)
    rev = getattr(K, "_kernel_rev", None)
    if rev is None and off[ncls] > EU_FORWARD_ENTRIES:
        # passes over the forward lists: no backward lists (they would take 2 or 4 bytes an entry),
        # unless the passes do not reach the fixpoint soon; then a backward search from the part
        # found finishes it (the same set)
        nodes = getattr(K, "_kernel_nodes", None)
        if nodes is None:
            noff = array("i", [0]) * (ncls + 1)
            nadj = array("i", [0]) * max(n, 1)
            dll.kn_class_nodes(n, ncls, _addr(cls), _addr(noff), _addr(nadj))
            nodes = K._kernel_nodes = (noff, nadj)
        noff, nadj = nodes
        cls, off, adj = _csr(K)
        got = dll.kn_eu_fwd(n, ncls, _addr(off), _addr(adj), _addr(noff), _addr(nadj), _addr(fb), _addr(sb),
                            _addr(y), EU_FORWARD_PASSES)
        if got == -1:
            return None
        if got >= 0:
            return y
        sb = bytearray(y)
        cls, off, adj = _csr(K)
    if rev is None:
        # the backward lists, made once for the structure's searches (the classes in 16 bits
        # when there are fewer than 65,536 of them)
        short = ncls < 65536
        moff = array("i", [0]) * (n + 1)
        madj = array("H" if short else "i", [0]) * max(off[ncls], 1)
        noff = array("i", [0]) * (ncls + 1)
        nadj = array("i", [0]) * max(n, 1)
        (dll.kn_rev_16 if short else dll.kn_rev)(n, ncls, _addr(cls), _addr(off), _addr(adj), _addr(moff),
                                                  _addr(madj), _addr(noff), _addr(nadj))
        rev = K._kernel_rev = (moff, madj, noff, nadj)
    moff, madj, noff, nadj = rev
    search = dll.kn_eu_rev_16 if madj.typecode == "H" else dll.kn_eu_rev
    if search(n, ncls, _addr(moff), _addr(madj), _addr(noff), _addr(nadj), _addr(fb), _addr(sb), _addr(y)) != 0:
        return None
    return y


def quotient(n: int, src, dst, vec, sig, ok: bytearray):
    """The bisimulation quotient of a structure whose nodes are steps: node i is ``(src[i],
    dst[i], vec[i])`` (``vec`` None: no atom reads a monitored function; else an array('B') or
    array('q') of atom bits), nodes leaving one state have the same successors, and ``sig[s]``
    (array('Q')) is what a node's label and initial flag read of its source s.  Nodes with the same
    ``(sig[src], vec, dst)`` are one node; nodes whose source has ``ok`` unset are dropped.
    Returns ``(first, off, adj)``: the first node of each quotient node (ascending), and for each
    of the n states the quotient nodes of the nodes leaving it, in their order
    (``adj[off[s]:off[s + 1]]``).  Compiled code when there is a compiler, else Python."""
    m = len(src)
    dll = library()
    if dll is not None and m and n:
        s, d = _u32(src), _u32(dst)
        sg = sig if isinstance(sig, array) and sig.typecode == "Q" else array("Q", sig)
        okb = bytearray(ok)
        v64 = vec if isinstance(vec, array) and vec.typecode == "q" else None
        v8 = vec if isinstance(vec, array) and vec.typecode == "B" else None
        if vec is not None and v64 is None and v8 is None:
            v64 = array("q", vec)
        off = array("i", [0]) * (n + 1)
        adj = array("i", [0]) * m
        nq = dll.kn_quotient(n, m, _addr(s), _addr(d), _addr(v64) if v64 is not None else 0,
                             _addr(v8) if v8 is not None else 0, _addr(sg), _addr(okb), _addr(off), _addr(adj))
        if nq >= 0:
            first = array("i", [0]) * max(nq, 1)
            dll.kn_quotient_first(_addr(first))
            del first[nq:]
            del adj[off[n]:]
            return first, off, adj
    ids: dict = {}
    first = array("i")
    lists: list = [[] for _ in range(n)]
    for i in range(m):
        a = src[i]
        if not ok[a]:
            continue
        key = (sig[a], vec[i] if vec is not None else 0, dst[i])
        q = ids.get(key)
        if q is None:
            q = ids[key] = len(first)
            first.append(i)
        lists[a].append(q)
    off = array("i", [0])
    adj = array("i")
    for lst in lists:
        adj.extend(dict.fromkeys(lst))       # a step recorded twice is one entry
        off.append(len(adj))
    return first, off, adj


def signatures(n: int, labs: list) -> array:
    """array('Q'): bit j of entry s is ``labs[j][s]`` (at most 64 state sets)."""
    sig = array("Q", [0]) * max(n, 1)
    dll = library()
    if dll is not None and n and labs:
        labels = bytearray().join(bytes(lab) for lab in labs)
        bits = array("Q", [1 << j for j in range(len(labs))])
        dll.kn_sig(n, len(labs), _addr(labels), _addr(bits), _addr(sig))
    else:
        for j, lab in enumerate(labs):
            b = 1 << j
            for s in range(n):
                if lab[s]:
                    sig[s] |= b
    del sig[n:]
    return sig


def take(a, idx, typecode: str) -> array:
    """array(typecode, (a[i] for i in idx))."""
    return array(typecode, (a[i] for i in idx))


def ascending(a) -> bool:
    """a[0] <= a[1] <= ... (an array of sources)."""
    dll = library()
    if dll is not None and len(a) > 1:
        a32 = _u32(a)
        return bool(dll.kn_ascending(len(a32), _addr(a32)))
    return all(a[i] <= a[i + 1] for i in range(len(a) - 1))


def bfs(K, sources, target: bytearray, allowed=None, keep=None, skip: bool = False):
    """:func:`asmcheck.temporal.graph.bfs_path` over the structure's successor classes with node
    sets for ``target`` and ``allowed`` (and ``keep``: the nodes a step may enter, None: all) by
    compiled code: the path, None when there is none, or False when the code is not available."""
    dll = library()
    if dll is None or K.n == 0:
        return False
    n = K.n
    cls, off, adj = _csr(K)
    srcs = _arr("i", sources)
    tb = bytearray(target)
    ab = bytearray(allowed) if allowed is not None else None
    kb = bytearray(keep) if keep is not None else None
    path = array("i", [0]) * (n + 2)
    k = dll.kn_bfs(n, len(off) - 1, _addr(cls), _addr(off), _addr(adj), len(sources), _addr(srcs), _addr(tb),
                   _addr(ab) if ab is not None else 0, _addr(kb) if kb is not None else 0, 1 if skip else 0,
                   _addr(path))
    if k < 0:
        return False
    return path[:k].tolist() if k else None


def mark(n: int, src) -> bytearray:
    """bytearray(n) with 1 at each entry of ``src``."""
    out = bytearray(max(n, 1))
    dll = library()
    if dll is not None and len(src):
        s32 = _u32(src)
        dll.kn_mark(len(s32), _addr(s32), _addr(out))
    else:
        for s in src:
            out[s] = 1
    return out[:n] if n else bytearray()


def all_succ(K) -> bool:
    """Whether every node of the structure has a successor."""
    dll = library()
    if dll is not None and K.n:
        cls, off, _adj = _csr(K)
        return bool(dll.kn_all_succ(K.n, _addr(cls), _addr(off)))
    return all(K.succ(v) for v in range(K.n))


def quotient_by_source(n: int, sig, sources, need: int = 0):
    """:func:`quotient` for steps given source by source: ``sources`` yields ``(src, k, recs)`` (the
    sources ascending, each once; recs an array('q') whose first 2k entries are (target, atom
    bits) pairs), none of them kept; steps whose bits miss one of ``need`` are left out.  Returns
    ``(fsrc, fdst, fvec, off, adj)`` -- the source, target and bits of each quotient node's first
    step, and the lists -- or None when there is no compiled code (or memory)."""
    dll = library()
    if dll is None:
        return None
    sg = sig if isinstance(sig, array) and sig.typecode == "Q" else array("Q", sig)
    if not len(sg):
        sg = array("Q", [0])
    if dll.kn_qs_begin(n, _addr(sg)) < 0:
        return None
    adj = array("i")
    out = array("i", [0])
    for src, k, recs in sources:
        if len(out) < k:
            out = array("i", [0]) * k
        got = dll.kn_qs_add(src, k, _addr(recs), need, _addr(out))
        if got < 0:
            dll.kn_qs_end()
            return None
        adj.extend(out[:got])
    nq = dll.kn_qs_end()
    if nq < 0:
        return None
    off = array("i", [0]) * (n + 1)
    fsrc = array("I", [0]) * max(nq, 1)
    fdst = array("i", [0]) * max(nq, 1)
    fvec = array("q", [0]) * max(nq, 1)
    dll.kn_qs_take(_addr(off), _addr(fsrc), _addr(fdst), _addr(fvec))
    del fsrc[nq:], fdst[nq:], fvec[nq:]
    return fsrc, fdst, fvec, off, adj
