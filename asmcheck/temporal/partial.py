"""LTL and CTL verdicts from a search that stopped before its end.

A search stopped by a limit (states, depth, time, memory) leaves a *partial* state graph: the
*expanded* states, whose successors are all known, and the *frontier*, states that were stored
(their labels are known) but whose successors were never computed.  A property is *decided* on
this part when it has the same value in every state graph that extends it, that is, for every
possible continuation of the frontier.  :func:`check_partial` finds the properties so decided,
each with the usual witness or counterexample; the others stay incomplete.

The check: two ordinary checks on completed structures
--------------------------------------------------------
The Kripke structure is built from the partial graph as for a complete one
(:func:`asmcheck.temporal.kripke.build_kripke`): a node is a state, or a step with the values of
the atoms that read monitored functions.  A *frontier node* is one whose successors are unknown:
a frontier state, or a step into a frontier state.  Then

1. every atom occurrence of the formula is replaced by a *literal* of its own: an occurrence
   under an even number of negations by the atom ``P_p`` (true where ``p`` is), one under an odd
   number by ``not N_p`` (``N_p`` true where ``p`` is false).  Every operator of the formulas
   (``and or EX EU EG``, ``X U R``, the past ``Y Z S T``) is monotone in each argument, so the
   formula is *monotone* in the literal labels: making a literal true in more nodes never makes
   it false.  On the known nodes ``P_p = p`` and ``N_p = not p``, so nothing changes there;
2. one *sink* node is added, with a self-loop, and made the only successor of every frontier
   node;
3. the formula is checked twice: with every literal false at the sink (``lo``) and with every
   literal true there (``hi``).  True in ``lo``: the property **holds**; false in ``hi``: it is
   **violated**; otherwise it stays incomplete.  (``lo`` true and ``hi`` false cannot both be.)

Why it is sound.  Let K' be any total structure that extends the known part (the expanded
nodes keep exactly their successors; a frontier node gets any non-empty set of successors, old
or new).  Relate each known node to itself and the sink to every node of K'.  This relation R
matches moves both ways: from a related pair of known expanded nodes the successors are the
same nodes; from a frontier node, the sink (its only successor in ``lo``/``hi``) is related to
every successor it has in K' (there is at least one, K' is total), and back; from (sink, x),
the sink's only successor is the sink, related to every successor of x.  So every path of one
structure from a node has a pointwise related path of the other from a related node.  The
literals are equal on related known nodes, and at the sink every literal is false (``lo``: at
most its value in K') or true (``hi``: at least its value in K').  By induction on the monotone
formula, over state subformulas and over paths (an existential quantifier takes a path of one
structure to a related path of the other; a universal one, every path of the other to a related
one), a formula true at a node of ``lo`` is true at every related node of K', and a formula
false at a node of ``hi`` is false at every related node of K'.  The initial nodes are known
and related to themselves, so the verdict (every initial node satisfies the formula) carries
over: holds in ``lo`` implies holds in every K'; violated in ``hi`` implies violated in every
K'.  The same argument covers LTL (a path formula, checked as ``A phi``): a counterexample of
``hi`` is a prefix that every continuation violates (a lasso that never reaches the sink is a
real lasso of the graph), and a property true in ``lo`` is true whatever the frontier does
(for instance ``p`` in the initial state); most LTL properties of infinite behaviour are never
decided true, as they should not be.

A witness or counterexample that reaches the sink is cut before it: it ends at the frontier
node where any continuation decides (a finite path, shown without a loop).

What is not decided, and why:

* **fairness** (JUSTICE, COMPASSION, ``--fair``): a path through the sink is fair or unfair
  depending on what the frontier would do, and NuSMV's reading counts only initial nodes with a
  fair path; no property is decided under fairness constraints;
* **INVAR** constraints: they can leave a node without successors, which the complete check
  reads as a node where no path starts; a frontier node of K' might be such a node.  A spec with
  INVAR constraints gets no decided verdict;
* in a structure whose nodes are steps, an initial state whose steps are unknown (it was not
  expanded): the initial nodes themselves are unknown.
"""
from __future__ import annotations

import time
from array import array

from ..errors import AsmError
from .formula import FormulaError

__all__ = ["check_partial", "literal_formula", "with_sink"]

_NOT = bytes([1, 0]) + bytes(254)


class Undecidable(Exception):
    """The formula has an operator whose monotonicity this check does not know."""


# ----------------------------------------------------------------- the formula over literals
def literal_formula(f, key, positive: bool = True):
    """``f`` with each atom occurrence replaced by its literal: ``("ap", key(i, True))`` under an
    even number of negations, ``("not", ("ap", key(i, False)))`` under an odd number (the literal
    ``not p`` is atom ``key(i, False)``).  The result is monotone in the literals' labels."""
    op = f[0]
    if op in ("true", "false"):
        return f
    if op == "ap":
        return ("ap", key(f[1], True)) if positive else ("not", ("ap", key(f[1], False)))
    if op == "not":
        return ("not", literal_formula(f[1], key, not positive))
    if op in ("and", "or", "EX", "EU", "EG", "X", "U", "R", "Y", "Z", "S", "T"):
        return (op,) + tuple(literal_formula(x, key, positive) for x in f[1:])
    raise Undecidable(op)


# ----------------------------------------------------------------- the structure with a sink
def _np_of(a):
    import numpy as np
    return np.frombuffer(a, dtype=np.dtype(a.typecode)) if len(a) else np.zeros(0, dtype=np.int64)


def _to_array(x) -> array:
    out = array("i")
    out.frombytes(x.astype("int32").tobytes())
    return out


def _copy(a, typecode: str) -> array:
    """A new array of ``typecode`` with the items of ``a`` (a slice when it is one already)."""
    if isinstance(a, array) and a.typecode == typecode:
        return a[:]
    return array(typecode, a)


def with_sink(K, frontier, unknown_steps: bool = False, init_states=()):
    """A copy of the Kripke structure K with one more node, the sink, that loops on itself and is
    the only successor of every node whose successor class is in ``frontier`` (classes are
    explored states: the nodes leaving a state).  With ``unknown_steps`` (a structure whose nodes
    are steps) each frontier state t gets instead a node u_t of its own (numbered ``K.n`` on, in
    the order of ``frontier``), the only node leaving t, whose only successor is the sink; an
    initial t makes u_t initial.  Labels are left to the caller.  Returns (the new structure,
    the sink)."""
    import numpy as np
    from .classes import Classes
    from .kripke import Kripke
    cs = K.cls_succ
    if isinstance(cs, Classes):
        off0, adj0 = _np_of(cs.off).astype(np.int64), _np_of(cs.adj).astype(np.int32)
        if cs.tab is not None:
            # 16-bit target states read through the table of nodes: the nodes themselves
            lens = np.diff(off0)
            keys = np.repeat(_np_of(cs.key).astype(np.int64)[:len(lens)], lens)
            adj0 = _np_of(cs.tab).astype(np.int32)[keys * cs.nstates + adj0]
        over, extra = dict(cs.over), list(cs.extra)
    else:
        lists = list(cs)
        off0 = np.zeros(len(lists) + 1, dtype=np.int64)
        off0[1:] = np.cumsum([len(x) for x in lists])
        adj0 = np.array([w for x in lists for w in x], dtype=np.int32)
        over, extra = {}, []
    nb = len(off0) - 1
    fr = np.asarray(frontier, dtype=np.int64)          # ascending, each class once
    fr = fr[fr < nb]
    nu = len(fr) if unknown_steps else 0
    sink = K.n + nu
    fr_set = None
    ov = sorted(c for c in over if c < nb)
    if ov:
        fr_set = set(fr.tolist())
        ov = [c for c in ov if c not in fr_set]
    # 1. the base lists of the replaced classes are dropped (few: halts, a state expanded in part)
    lens0 = np.diff(off0)
    drop = sorted(set(fr[lens0[fr] > 0].tolist()) | {c for c in ov if lens0[c] > 0})
    if drop:
        keep = np.ones(len(adj0), dtype=bool)
        for c in drop:
            keep[off0[c]:off0[c + 1]] = False
        adj0 = adj0[keep]
        lens0 = lens0.copy()
        lens0[drop] = 0
        off0 = np.zeros(nb + 1, dtype=np.int64)
        off0[1:] = np.cumsum(lens0)
    # 2. the new lists inserted where their (now empty) classes start, in class order
    ov_arr = np.array(ov, dtype=np.int64)
    ov_cnt = np.array([len(over[c]) for c in ov], dtype=np.int64)
    all_cls = np.concatenate([fr, ov_arr])
    all_cnt = np.concatenate([np.ones(len(fr), dtype=np.int64), ov_cnt])
    order = np.argsort(all_cls, kind="stable")
    all_cls, all_cnt = all_cls[order], all_cnt[order]
    ins = np.zeros(nb, dtype=np.int64)
    ins[all_cls] = all_cnt
    vals = np.full(int(all_cnt.sum()), sink, dtype=np.int32)
    start = np.concatenate([[0], np.cumsum(all_cnt)[:-1]]).astype(np.int64)
    if nu:
        is_fr = order < len(fr)
        vals[start[is_fr]] = (K.n + order[is_fr]).astype(np.int32)
    if ov:
        at = np.searchsorted(all_cls, ov_arr)
        for c, k in zip(ov, at.tolist()):
            vals[start[k]:start[k] + len(over[c])] = over[c]
    adj = np.insert(adj0, np.repeat(off0[all_cls], all_cnt), vals) if len(vals) else adj0
    off = off0.copy()
    off[1:] += np.cumsum(ins)
    # 3. the appended classes (halt nodes), then the sink's
    tail = [list(over.get(nb + j, lst)) for j, lst in enumerate(extra)] + [[sink]]
    more = np.array([w for lst in tail for w in lst], dtype=np.int32)
    off = np.concatenate([off, off[-1] + np.cumsum([len(x) for x in tail])])
    adj = np.concatenate([adj, more])
    K2 = Kripke()
    for name, value in vars(K).items():
        if not name.startswith("_"):
            setattr(K2, name, value)
    K2.n = K.n + nu + 1
    cls = _copy(K.cls, "i")
    cls.extend(array("i", [len(off) - 2]) * (nu + 1))
    K2.cls = cls
    if nu:
        sid = _copy(K.sid, K.sid.typecode if isinstance(K.sid, array) else "q")
        sid.frombytes(np.append(fr, 0).astype(np.dtype(sid.typecode)).tobytes())
        tgt = _copy(K.tgt, K.tgt.typecode if isinstance(K.tgt, array) else "q")
        tgt.frombytes(bytes(tgt.itemsize * (nu + 1)))
        K2.sid, K2.tgt = sid, tgt
        ini = np.asarray(sorted(init_states), dtype=np.int64)
        at = np.searchsorted(fr, ini)
        hit = at < len(fr)
        hit[hit] = fr[at[hit]] == ini[hit]
        K2.init = list(K.init) + (K.n + at[hit]).tolist()
        K2.unknown = (K.n, fr)
    K2.cls_succ = Classes(_to_array(off), _to_array(adj))
    K2.label = {}
    K2.justice, K2.compassion = [], []
    return K2, sink


def _cut(nodes, loop, sink, K=None):
    """A path of the structure with the sink, without the sink: a path that reaches it ends at the
    frontier node before it (a finite path).  A node u_t (a frontier state whose steps are unknown)
    that ends it is dropped when the path shows the inputs of its last step (the step into t then
    shows t)."""
    if sink in nodes:
        nodes, loop = list(nodes[:nodes.index(sink)]), None
    nodes = list(nodes)
    u = getattr(K, "unknown", None)
    if u is not None and nodes and nodes[-1] >= u[0] and K.mon_atoms:
        nodes = nodes[:-1]
    return nodes, loop


# ----------------------------------------------------------------- the entry point
class _Literals(dict):
    """The labels of the literals (atom keys ``base + 4 i + k``: k = 0 p and 1 not p with every
    literal false at the sink, 2 p and 3 not p with every literal true there), made when a check
    first reads one; an atom's own key gives its label where it is known (false elsewhere).  ``slab``: the state atoms' labels of the explored states, for the nodes of
    the frontier states whose steps are unknown (``nu`` of them, in the order of ``frontier``);
    a monitored atom is unknown there: false or true as at the sink."""

    def __init__(self, K, slab, frontier, nu, base, used):
        super().__init__()
        # (the atoms' labels only: the structure's own successor arrays are not kept alive)
        self.labels, self.mon = K.label, set(K.mon_atoms)
        self.slab, self.frontier, self.nu, self.base, self.used = slab, frontier, nu, base, set(used)

    def __missing__(self, key):
        import numpy as np
        if isinstance(key, int) and 0 <= key < self.base and key in self.used:
            # an atom itself (what a trace shows): as known, false where it is not known
            i, k = key, 0
        else:
            i, k = divmod(key - self.base, 4)
            if key < self.base or i not in self.used:
                raise KeyError(key)
        hi = k >= 2
        known = bytes(self.labels[i])
        if self.nu and i not in self.mon:
            known += np.frombuffer(bytes(self.slab[i]), dtype=np.uint8)[self.frontier].tobytes()
        if k % 2:
            known = known.translate(_NOT)
        if self.nu and i in self.mon:
            known += (b"\x01" if hi else b"\x00") * self.nu
        lab = self[key] = bytearray(known + (b"\x01" if hi else b"\x00"))
        return lab


def frontier_states(explorer, has_out, stopped_inside: bool):
    """The states whose successors are unknown (a sorted numpy array): those without any recorded
    step (well-defined or failing), and, when the search may have stopped inside a state's steps
    (``stopped_inside``: the Python explorer, whose steps are recorded as they come), the last
    state it expanded."""
    import numpy as np
    out = np.flatnonzero(np.frombuffer(bytes(has_out), dtype=np.uint8) == 0)
    if stopped_inside:
        last = -1
        src, _ = explorer.edge_arrays()
        if len(src):
            last = int(src[-1])
        errs = list(getattr(explorer, "error_edges", None) or ())
        if errs:
            last = max(last, int(errs[-1][0]))
        if last >= 0 and has_out[last]:
            out = np.union1d(out, [last])
    return out


def check_partial(explorer, props, fair=(), on_error: str = "halt", stopped_inside: bool = False,
                  notes: list | None = None):
    """The LTL/CTL properties of ``props`` that the partial state graph of ``explorer`` decides:
    a list of :class:`asmcheck.temporal.TemporalResult` (``decided_on``: the states explored),
    in the order of ``props``; the properties missing from it stay incomplete.  ``notes`` gets
    the reasons why none could be decided (fairness, INVAR)."""
    from . import TemporalResult, formulas, has_existential_top, kernel, step_halts
    from .kripke import AtomError, build_kripke, state_labels
    t_start = time.perf_counter()
    notes = notes if notes is not None else []
    machine = explorer.m
    S = explorer.n_states
    if not S:
        return []
    atoms, checks, justice, compassion, fairness_text, errors, invars, used = formulas(
        machine, props, list(fair or []), explorer.state(0))
    if errors:
        return []
    if justice or compassion or fair:
        notes.append("under fairness constraints a partial state space decides no LTL/CTL property")
        return []
    if invars:
        notes.append("with INVAR constraints a partial state space decides no LTL/CTL property")
        return []
    if getattr(explorer, "engine", "") == "native" and any(kind == "ltl" and f is not None
                                                            for _, kind, f, _ in checks):
        # LTL on the state graph reads the edge arrays: a native search that recorded the
        # quotient's steps instead runs again to record them, before the frontier is found
        try:
            explorer.edge_arrays()
        except Exception:       # (the structures say it again, or need no edges)
            pass
        S = explorer.n_states
    has_out, halts, relative_to = step_halts(explorer, S, on_error)
    frontier = frontier_states(explorer, has_out, stopped_inside)
    base = len(atoms.items)
    import numpy as np
    par = explorer.parent
    init_sids = np.flatnonzero(np.frombuffer(par, dtype=np.dtype(par.typecode)) == -1).tolist() \
        if isinstance(par, array) and len(par) else [s for s in range(S) if par[s] == -1]

    def key_lo(i, pos):
        return base + 4 * i + (0 if pos else 1)

    def key_hi(i, pos):
        return base + 4 * i + (2 if pos else 3)

    cache: dict = {}
    structures: dict = {}
    timing: dict = {}

    def kripke(step: bool):
        if step not in structures:
            t_build = time.perf_counter()
            K = build_kripke(explorer, atoms, used, invars, [], [], [], step=step, cache=cache, halts=halts,
                             quotient=True)
            unknown = K.mode == "step"
            t_sink = time.perf_counter()
            K2, sink = with_sink(K, frontier, unknown, init_sids)
            timing["structure_seconds"] = timing.get("structure_seconds", 0.0) + t_sink - t_build
            timing["sink_seconds"] = timing.get("sink_seconds", 0.0) + time.perf_counter() - t_sink
            st_atoms = [i for i in sorted(used) if i not in K.mon_atoms]
            slab = cache.get(("slab", tuple(st_atoms)))
            if unknown and slab is None:
                slab = state_labels(explorer, atoms, st_atoms)
            nu = K2.n - K.n - 1
            K2.label = _Literals(K, slab if unknown else None, frontier, nu, base, sorted(used))
            if not kernel.all_succ(K2):
                structures[step] = None          # a node without successors: the argument needs a total structure
                return None
            structures[step] = (K2, sink)
        return structures[step]

    results = []
    ctl = None
    for p, kind, f, err in checks:
        if f is None or kind not in ("ltl", "ctl"):
            continue
        t0 = time.perf_counter()
        try:
            f_lo = literal_formula(f, key_lo)
            f_hi = literal_formula(f, key_hi)
        except Undecidable:
            continue
        try:
            got = kripke(kind != "ltl")
        except (AtomError, AsmError):
            return []
        if got is None:
            continue
        K, sink = got
        if kind == "ltl":
            from .ltl import check_ltl
            try:
                r = check_ltl(K, f_lo)
                if r.holds:
                    nodes, loop, holds = [], None, True
                else:
                    r = check_ltl(K, f_hi)
                    if r.holds:
                        continue
                    nodes, loop = _cut(r.nodes, r.loop, sink, K)
                    holds = False
            except FormulaError:
                continue
            t = TemporalResult(p, kind, holds, nodes=nodes, loop=loop, fairness=fairness_text, explorer=explorer,
                               K=K, seconds=time.perf_counter() - t0,
                               stats={"product_states": r.product_states, "automaton_states": r.automaton_states,
                                      "kripke_nodes": K.n - 1})
        else:
            if ctl is None:
                from .ctl import CTL
                ctl = CTL(K)
            holds, bad = ctl.check(f_lo)
            nodes, loop, witness = [], None, False
            if holds:
                if has_existential_top(f_lo):
                    v0 = ctl.initial(f_lo, True)
                    if v0:
                        nodes, loop = _cut(*ctl.explain(f_lo, v0, True), sink, K)
                        witness = True
            else:
                hi_holds, bad = ctl.check(f_hi)
                if hi_holds:
                    continue
                nodes, loop = _cut(*ctl.explain(f_hi, ctl.initial(f_hi, False), False), sink, K)
            t = TemporalResult(p, kind, holds, nodes=nodes, loop=loop, fairness=fairness_text, explorer=explorer,
                               K=K, seconds=time.perf_counter() - t0, stats={"kripke_nodes": K.n - 1},
                               witness=witness)
        t.decided_on = S
        results.append(t)
    for r in results:
        r.stats["total_seconds"] = time.perf_counter() - t_start
        r.stats.update(timing)
        r.relative_to = relative_to
    return results
