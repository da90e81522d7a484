"""LTL by the automata-theoretic method: the negated property is turned into a generalised
Büchi automaton (the tableau construction of Gerth, Peled, Vardi and Wolper), multiplied
with the Kripke structure, and the product is searched for a reachable fair accepting
strongly connected component (every acceptance set and every justice constraint met,
compassion by refinement).  Such a component gives a lasso: a prefix and a cycle.

Past operators (``y z h o s t``) are handled by a deterministic monitor that runs along
the path and holds the current truth value of every past subformula (and of the
arguments of ``y`` / ``z``); in the product a node is (Kripke node, monitor state,
automaton state), and past subformulas are read from the monitor like atoms.  A future
operator inside a past one is not supported.
"""
from __future__ import annotations

from collections import deque

from .formula import FALSE, TRUE, FormulaError, temporal_free
from .graph import bfs_path, cover_cycle, fair_sccs

_PAST = ("Y", "Z", "S", "T")
_FUTURE = ("X", "U", "R")


# ----------------------------------------------------------------- past monitor
class Monitor:
    """Tracks the values of the past subformulas along a path."""

    def __init__(self):
        self.entries: list = []     # (kind, args): kind Y Z S T val
        self.index: dict = {}
        self.states: dict = {}      # tuple of bools -> id
        self.values: list = []      # id -> tuple
        self._step_cache: dict = {}

    def replace_past(self, f):
        """f with every past subformula replaced by ("pa", j)."""
        op = f[0]
        if op in _PAST:
            return ("pa", self._entry(f))
        if op in ("true", "false", "ap"):
            return f
        return (op,) + tuple(self.replace_past(x) for x in f[1:])

    def _past_arg(self, f):
        op = f[0]
        if op in _FUTURE:
            raise FormulaError(None, "a future operator (x, g, f, u, v) inside a past one (y, z, h, o, s, t) "
                                     "is not supported")
        if op in _PAST:
            return ("pa", self._entry(f))
        if op in ("true", "false", "ap"):
            return f
        return (op,) + tuple(self._past_arg(x) for x in f[1:])

    def _add(self, key):
        j = self.index.get(key)
        if j is None:
            j = self.index[key] = len(self.entries)
            self.entries.append(key)
        return j

    def _entry(self, f):
        op = f[0]
        if op in ("Y", "Z"):
            a = self._past_arg(f[1])
            e = self._add(("val", a))
            return self._add((op, e))
        a = self._past_arg(f[1])
        b = self._past_arg(f[2])
        return self._add((op, a, b))

    @property
    def empty(self) -> bool:
        return not self.entries

    def _eval(self, f, label, k, cur):
        op = f[0]
        if op == "true":
            return True
        if op == "false":
            return False
        if op == "ap":
            return label[f[1]][k] == 1
        if op == "pa":
            return cur[f[1]]
        if op == "not":
            return not self._eval(f[1], label, k, cur)
        if op == "and":
            return self._eval(f[1], label, k, cur) and self._eval(f[2], label, k, cur)
        if op == "or":
            return self._eval(f[1], label, k, cur) or self._eval(f[2], label, k, cur)
        raise FormulaError(None, f"unexpected operator {op} in a past formula")

    def step(self, prev: int | None, label, k: int) -> int:
        """The monitor state at node k, given the state at the previous position (None at
        the first position)."""
        prevv = self.values[prev] if prev is not None else None
        cur: list = []
        for kind, *args in self.entries:
            if kind == "val":
                v = self._eval(args[0], label, k, cur)
            elif kind == "Y":
                v = prevv[args[0]] if prevv is not None else False
            elif kind == "Z":
                v = prevv[args[0]] if prevv is not None else True
            elif kind == "S":
                a = self._eval(args[0], label, k, cur)
                b = self._eval(args[1], label, k, cur)
                j = len(cur)
                v = b or (a and prevv is not None and prevv[j])
            else:  # T
                a = self._eval(args[0], label, k, cur)
                b = self._eval(args[1], label, k, cur)
                j = len(cur)
                v = b and (a or prevv is None or prevv[j])
            cur.append(v)
        t = tuple(cur)
        i = self.states.get(t)
        if i is None:
            i = self.states[t] = len(self.values)
            self.values.append(t)
        return i


# ----------------------------------------------------------------- LTL -> generalised Büchi automaton
def nnf(f, neg=False):
    op = f[0]
    if op == "true":
        return FALSE if neg else TRUE
    if op == "false":
        return TRUE if neg else FALSE
    if op in ("ap", "pa"):
        return ("lit", f, not neg)
    if op == "not":
        return nnf(f[1], not neg)
    if op in ("and", "or"):
        a, b = nnf(f[1], neg), nnf(f[2], neg)
        real = op if not neg else ("or" if op == "and" else "and")
        return _mk(real, a, b)
    if op == "X":
        return ("X", nnf(f[1], neg))
    if op in ("U", "R"):
        a, b = nnf(f[1], neg), nnf(f[2], neg)
        real = op if not neg else ("R" if op == "U" else "U")
        if real == "U" and b == TRUE:
            return TRUE
        if real == "R" and b == FALSE:
            return FALSE
        return (real, a, b)
    raise FormulaError(None, f"unexpected operator {op} in an LTL formula")


def _mk(op, a, b):
    if op == "and":
        if a == FALSE or b == FALSE:
            return FALSE
        if a == TRUE:
            return b
        if b == TRUE:
            return a
    else:
        if a == TRUE or b == TRUE:
            return TRUE
        if a == FALSE:
            return b
        if b == FALSE:
            return a
    return (op, a, b)


class GBA:
    def __init__(self):
        self.nodes: list = []        # (old frozenset, next frozenset)
        self.incoming: list = []     # set of node ids (-1 = initial)
        self.lits: list = []         # [(ref, positive)]
        self.succ: list = []
        self.init: list = []
        self.accept: list = []       # bytearray over nodes, one per until subformula


def _key(f):
    return repr(f)


def build_gba(phi) -> GBA:
    """GPVW tableau of the NNF formula ``phi``."""
    g = GBA()
    found: dict = {}                 # (old, next) -> id
    stack = [(frozenset([-1]), [phi] if phi != TRUE else [], frozenset(), frozenset())]
    if phi == FALSE:
        stack = []
    while stack:
        inc, new, old, nxt = stack.pop()
        if not new:
            key = (old, nxt)
            i = found.get(key)
            if i is not None:
                g.incoming[i] |= inc
                continue
            i = found[key] = len(g.nodes)
            g.nodes.append((old, nxt))
            g.incoming.append(set(inc))
            stack.append((frozenset([i]), sorted(nxt, key=_key), frozenset(), frozenset()))
            continue
        new = list(new)
        eta = new.pop()
        op = eta[0]
        if op in ("lit", "true", "false"):
            if op == "false":
                continue
            if op == "lit" and ("lit", eta[1], not eta[2]) in old:
                continue
            stack.append((inc, new, old | {eta} if op == "lit" else old, nxt))
            continue
        if op == "and":
            add = [x for x in (eta[1], eta[2]) if x not in old]
            stack.append((inc, new + add, old | {eta}, nxt))
            continue
        if op == "X":
            stack.append((inc, new, old | {eta}, nxt | {eta[1]}))
            continue
        a, b = eta[1], eta[2]
        if op == "or":
            n1, x1, n2 = [a], [], [b]
        elif op == "U":
            n1, x1, n2 = [a], [eta], [b]
        else:  # R
            n1, x1, n2 = [b], [eta], [a, b]
        o2 = old | {eta}
        stack.append((inc, new + [x for x in n2 if x not in old], o2, nxt))
        stack.append((inc, new + [x for x in n1 if x not in old], o2, nxt | frozenset(x1)))
    n = len(g.nodes)
    g.succ = [[] for _ in range(n)]
    for j in range(n):
        for i in sorted(g.incoming[j]):
            if i == -1:
                g.init.append(j)
            else:
                g.succ[i].append(j)
    for old, _ in g.nodes:
        g.lits.append(sorted(((x[1], x[2]) for x in old if x[0] == "lit"), key=_key))
    untils = set()
    for old, _ in g.nodes:
        untils.update(x for x in old if x[0] == "U")
    for u in sorted(untils, key=_key):
        acc = bytearray(n)
        for i, (old, _) in enumerate(g.nodes):
            if u not in old or u[2] == TRUE or u[2] in old:
                acc[i] = 1
        g.accept.append(acc)
    return g


# ----------------------------------------------------------------- the product and the search
class LTLResult:
    def __init__(self, holds, nodes=None, loop=None, product_states=0, automaton_states=0):
        self.holds = holds
        self.nodes = nodes or []
        self.loop = loop
        self.product_states = product_states
        self.automaton_states = automaton_states


def _gf(f):
    """p when f is g(f(p)) with p a state formula, else None."""
    if f[0] == "R" and f[1] == FALSE and f[2][0] == "U" and f[2][1] == TRUE and temporal_free(f[2][2]):
        return f[2][2]
    return None


def _conjuncts(f, out):
    if f[0] == "and":
        _conjuncts(f[1], out)
        _conjuncts(f[2], out)
    else:
        out.append(f)
    return out


def split_assumptions(phi):
    """``A -> psi`` where A's conjuncts are fairness assumptions -- ``g(f(p))`` (justice) and
    ``g(f(p)) implies g(f(q))`` (compassion) -- gives (psi', justice, compassion): a path
    satisfies A exactly when it is fair for these constraints, so phi holds on every path
    iff psi' holds on every such fair path.  Anything else stays in psi'."""
    justice, compassion = [], []
    rest = phi
    while rest[0] == "or":
        a, b = rest[1], rest[2]
        if a[0] == "not":
            prem, concl = a[1], b
        elif b[0] == "not":
            prem, concl = b[1], a
        else:
            break
        keep = []
        found = False
        for c in _conjuncts(prem, []):
            p = _gf(c)
            if p is not None:
                justice.append(p)
                found = True
                continue
            if c[0] == "or" and c[1][0] == "not" and _gf(c[1][1]) is not None and _gf(c[2]) is not None:
                compassion.append((_gf(c[1][1]), _gf(c[2])))
                found = True
                continue
            keep.append(c)
        if not found:
            break
        if keep:
            k = keep[0]
            for c in keep[1:]:
                k = ("and", k, c)
            concl = ("or", ("not", k), concl)
        rest = concl
    return rest, justice, compassion


def _eval_state(f, K) -> bytearray:
    from .graph import b_and, b_not, b_or, full
    op = f[0]
    if op == "true":
        return full(K.n)
    if op == "false":
        return bytearray(K.n)
    if op == "ap":
        return K.label[f[1]]
    if op == "not":
        return b_not(_eval_state(f[1], K))
    if op == "and":
        return b_and(_eval_state(f[1], K), _eval_state(f[2], K))
    return b_or(_eval_state(f[1], K), _eval_state(f[2], K))


def check_ltl(K, phi) -> LTLResult:
    phi, extra_j, extra_c = split_assumptions(phi)
    mon = Monitor()
    body = mon.replace_past(phi)
    neg = nnf(body, neg=True)
    g = build_gba(neg)
    label = K.label
    # literals as bit masks: bit i = the i-th atom the automaton reads, then the monitor's
    refs = sorted({ref for lits in g.lits for ref, _ in lits}, key=_key)
    bit = {ref: 1 << i for i, ref in enumerate(refs)}
    ap_bits = [(bit[r], label[r[1]]) for r in refs if r[0] == "ap"]
    pa_bits = [(bit[r], r[1]) for r in refs if r[0] == "pa"]
    posm = [sum(bit[r] for r, pos in lits if pos) for lits in g.lits]
    negm = [sum(bit[r] for r, pos in lits if not pos) for lits in g.lits]
    if mon.empty and len(refs) <= 64:
        # the product and its fair components over arrays, by compiled code (None: not available)
        from . import kernel
        got = kernel.product_and_fair(
            K, g, ap_bits, posm, negm,
            [lab for _, lab in K.justice] + [_eval_state(f, K) for f in extra_j], g.accept,
            [(p, q) for _, p, q in K.compassion] + [(_eval_state(pf, K), _eval_state(qf, K)) for pf, qf in extra_c])
        if got is not None:
            N, nfair, build = got
            if not nfair:
                return LTLResult(True, product_states=N, automaton_states=len(g.nodes))
            kk, _, succ, init, comps, justice, compassion = build()
            return _lasso(N, succ.__getitem__, init, comps, justice, compassion, kk, g)
    ksig = [0] * K.n
    for b, lab in ap_bits:
        for k in range(K.n):
            if lab[k]:
                ksig[k] |= b
    msig: dict = {}

    def monsig(m):
        s_ = msig.get(m)
        if s_ is None:
            vals = mon.values[m]
            s_ = msig[m] = sum(b for b, j in pa_bits if vals[j])
        return s_

    def compatible(qs, sig):
        return [q for q in qs if (sig & posm[q]) == posm[q] and not (sig & negm[q])]

    ids: dict = {}
    kk: list = []
    mm: list = []
    qq: list = []
    succ: list = []
    init: list = []
    queue = deque()
    Q = max(len(g.nodes), 1)
    empty_mon = mon.empty
    if empty_mon:
        mon.step(None, label, 0)

    def node(k, m, q):
        key = k * Q + q if empty_mon else (k, m, q)
        i = ids.get(key)
        if i is None:
            i = ids[key] = len(kk)
            kk.append(k)
            mm.append(m)
            qq.append(q)
            succ.append(None)
            queue.append(i)
        return i

    for k in K.init:
        m = 0 if empty_mon else mon.step(None, label, k)
        for q in compatible(g.init, ksig[k] | monsig(m)):
            i = node(k, m, q)
            if i not in init:
                init.append(i)
    mstep_cache: dict = {}
    qcache: dict = {}
    # the successors of (k, m, q) depend on k only through its successor class: nodes of
    # one class share their successor list
    scache: dict = {}
    cls = K.cls
    while queue:
        i = queue.popleft()
        k, m, q = kk[i], mm[i], qq[i]
        skey = (cls[k], m, q)
        out = scache.get(skey)
        if out is not None:
            succ[i] = out
            continue
        out = scache[skey] = []
        qs = g.succ[q]
        for k2 in K.succ(k):
            if empty_mon:
                m2 = 0
                sig = ksig[k2]
            else:
                key = (m, k2)
                m2 = mstep_cache.get(key)
                if m2 is None:
                    m2 = mstep_cache[key] = mon.step(m, label, k2)
                sig = ksig[k2] | monsig(m2)
            ck = (q, sig)
            q2s = qcache.get(ck)
            if q2s is None:
                q2s = qcache[ck] = compatible(qs, sig)
            for q2 in q2s:
                out.append(node(k2, m2, q2))
        succ[i] = out
    N = len(kk)
    sfn = succ.__getitem__
    justice = []
    for acc in g.accept:
        justice.append(bytearray(acc[q] for q in qq))
    for _, lab in K.justice:
        justice.append(bytearray(lab[k] for k in kk))
    for f in extra_j:
        lab = _eval_state(f, K)
        justice.append(bytearray(lab[k] for k in kk))
    compassion = []
    for _, p, qs_ in K.compassion:
        compassion.append((bytearray(p[k] for k in kk), bytearray(qs_[k] for k in kk)))
    for pf, qf in extra_c:
        p, qs_ = _eval_state(pf, K), _eval_state(qf, K)
        compassion.append((bytearray(p[k] for k in kk), bytearray(qs_[k] for k in kk)))
    # justice sets met everywhere constrain nothing
    justice = [j for j in justice if j.count(0)]
    comps = fair_sccs(N, sfn, init, None, justice, compassion)
    if not comps:
        return LTLResult(True, product_states=N, automaton_states=len(g.nodes))
    return _lasso(N, sfn, init, comps, justice, compassion, kk, g)


def _lasso(N, sfn, init, comps, justice, compassion, kk, g) -> LTLResult:
    """The counterexample through the first fair component reached: a shortest path to it,
    then a cycle inside it that meets every justice set (and q of every compassion pair whose
    p it meets)."""
    inside = bytearray(N)
    owner = {}
    for ci, comp in enumerate(comps):
        for x in comp:
            inside[x] = 1
            owner[x] = ci
    path = bfs_path(sfn, init, lambda x: inside[x] == 1)
    entry = path[-1]
    comp = comps[owner[entry]]
    cmask = bytearray(N)
    for x in comp:
        cmask[x] = 1
    required = list(justice)
    for p, q in compassion:
        if any(p[x] for x in comp):
            required.append(q)
    cycle = cover_cycle(sfn, entry, cmask, required)
    prod = path[:-1] + cycle
    return LTLResult(False, [kk[x] for x in prod], len(path) - 1, N, len(g.nodes))
