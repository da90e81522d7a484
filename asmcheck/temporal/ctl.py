"""CTL by fixpoint labelling on the Kripke structure, with fairness as NuSMV does it.

Every path quantifier ranges over *fair* paths: ``fair`` is the set of nodes where a fair
path starts (``EG true`` under the fairness constraints); ``EX f = pre(f & fair)``,
``E[f U g]`` is the least fixpoint from ``g & fair``, and ``EG f`` is computed from the
fair strongly connected components of the subgraph of ``f`` nodes (justice: the
component meets every justice set; compassion (p, q): it meets q or, if not, the
component without its p nodes is searched again).  A property holds when every fair
initial node satisfies it (NuSMV ignores initial states from which no fair path starts).

Witnesses and counterexamples are built by :meth:`CTL.explain` on the core formula.
"""
from __future__ import annotations

from collections import deque

from .graph import b_and, b_not, b_or, bfs_path, cover_cycle, fair_sccs, full, members


class CTL:
    def __init__(self, K):
        self.K = K
        self.n = K.n
        self.cache: dict = {}
        self.justice = [lab for _, lab in K.justice]
        self.compassion = [(p, q) for _, p, q in K.compassion]
        self._fair_sccs_cache: dict = {}
        from . import kernel
        if not self.justice and not self.compassion and kernel.all_succ(K):
            # no fairness constraint and a successor everywhere: a path goes on for ever from
            # every node (EG true is every node)
            self.fair = full(self.n)
        else:
            self.fair = self._eg(full(self.n))

    # -------------------------------------------------------------- labelling
    def sat(self, f) -> bytearray:
        r = self.cache.get(f)
        if r is not None:
            return r
        op = f[0]
        n = self.n
        if op == "true":
            r = full(n)
        elif op == "false":
            r = bytearray(n)
        elif op == "ap":
            r = self.K.label[f[1]]
        elif op == "not":
            r = b_not(self.sat(f[1]))
        elif op == "and":
            r = b_and(self.sat(f[1]), self.sat(f[2]))
        elif op == "or":
            r = b_or(self.sat(f[1]), self.sat(f[2]))
        elif op == "EX":
            r = self._ex(self.sat(f[1]))
        elif op == "EU":
            r = self._eu(self.sat(f[1]), b_and(self.sat(f[2]), self.fair))
        elif op == "EG":
            r = self._eg(self.sat(f[1]))
        else:
            raise ValueError(f"not a CTL formula: {op}")
        self.cache[f] = r
        return r

    def _ex(self, s: bytearray) -> bytearray:
        K = self.K
        g = b_and(s, self.fair)
        from . import kernel
        y = kernel.ex(K, g)
        if y is not None:
            return y
        cls_ok = bytearray(len(K.cls_succ))
        for c, lst in enumerate(K.cls_succ):
            for w in lst:
                if g[w]:
                    cls_ok[c] = 1
                    break
        return bytearray(cls_ok[c] for c in K.cls)

    def _eu(self, f: bytearray, start: bytearray) -> bytearray:
        """Nodes from which a path of f nodes reaches a ``start`` node."""
        K = self.K
        from . import kernel
        y = kernel.eu(K, f, start)
        if y is not None:
            return y
        y = bytearray(start)
        q = deque(members(start))
        done = bytearray(len(K.cls_succ))
        member_of, cls_nodes = K.member_of, K.cls_nodes
        while q:
            w = q.popleft()
            for c in member_of[w]:
                if done[c]:
                    continue
                done[c] = 1
                for v in cls_nodes[c]:
                    if f[v] and not y[v]:
                        y[v] = 1
                        q.append(v)
        return y

    def fair_sccs(self, s: bytearray) -> list[list[int]]:
        key = bytes(s)
        r = self._fair_sccs_cache.get(key)
        if r is None:
            from . import kernel
            r = kernel.fair_sccs(self.K, s, self.justice, self.compassion)
            if r is None:
                r = fair_sccs(self.n, self.K.succ, members(s), s, self.justice, self.compassion)
            self._fair_sccs_cache[key] = r
        return r

    def fair_mask(self, s: bytearray) -> bytearray:
        """The nodes of the fair components of the subgraph of ``s``."""
        key = bytes(s)
        r = self._fair_sccs_cache.get(key)
        if r is None:
            from . import kernel
            got = kernel.fair_comp(self.K, s, self.justice, self.compassion)
            if got is not None:
                # the components as lists only when a path through one is shown (fair_sccs)
                return kernel.in_comp(got[1], self.n)
            r = self.fair_sccs(s)
        start = bytearray(self.n)
        for comp in r:
            for v in comp:
                start[v] = 1
        return start

    def _eg(self, s: bytearray) -> bytearray:
        return self._eu(s, self.fair_mask(s))

    # -------------------------------------------------------------- verdict
    def check(self, f):
        """(holds, a fair initial node violating f or None)."""
        s = self.sat(f)
        for v in self.K.init:
            if self.fair[v] and not s[v]:
                return False, v
        return True, None

    def initial(self, f, want: bool) -> list[int]:
        """The fair initial nodes where f is ``want``, in the structure's order."""
        s = self.sat(f)
        return [v for v in self.K.init if self.fair[v] and bool(s[v]) == want]

    # -------------------------------------------------------------- explanations
    def explain(self, f, v, want: bool, budget: int = 12):
        """A path from node v showing that f is ``want`` at v: (nodes, loop index or None).  ``v``
        may be a list of such nodes (the initial nodes where f is ``want``): the path then starts
        at the one from which the path a breadth-first search finds is shortest, where f's shape
        lets one search start from all of them (a path to a node, under ``not``); elsewhere at
        the first."""
        K = self.K
        op = f[0]
        sources = v if isinstance(v, list) else [v]
        v = sources[0]
        if budget <= 0:
            return [v], None
        if op in ("true", "false", "ap"):
            return [v], None
        if op == "not":
            return self.explain(f[1], sources, not want, budget)
        if op in ("and", "or"):
            a, b = f[1], f[2]
            # the disjunct that makes "or" true / the conjunct that makes "and" false; else
            # the first temporal operand
            decisive = (op == "or") == want
            for x in (a, b):
                if decisive and self.sat(x)[v] == want:
                    return self.explain(x, v, want, budget - 1)
            for x in (a, b):
                if _temporal(x) and self.sat(x)[v] == want:
                    return self.explain(x, v, want, budget - 1)
            return [v], None
        if op == "EX":
            g = f[1]
            if want:
                gs = b_and(self.sat(g), self.fair)
                w = next((w for w in K.succ(v) if gs[w]), None)
                if w is None:
                    return [v], None
                return self._then([v], self.explain(g, w, True, budget - 1))
            # every (fair) successor falsifies g: show one
            fs = self.fair
            w = next((w for w in K.succ(v) if fs[w]), None)
            if w is None:
                return [v], None
            return self._then([v], self.explain(g, w, False, budget - 1))
        if op == "EU":
            a, b = f[1], f[2]
            if want:
                bs = b_and(self.sat(b), self.fair)
                sa = self.sat(a)
                eu = self.sat(f)
                path = self._path(sources, bs, b_and(sa, eu))
                if path is None:
                    return [v], None
                return self._then(path[:-1], self.explain(b, path[-1], True, budget - 1))
            # E[a U b] false: show the fair path that fails it: a & !b up to a !a & !b node,
            # or a fair cycle of a & !b nodes (EG(!b) holds then)
            na_nb = b_and(b_not(self.sat(a)), b_not(self.sat(b)))
            a_nb = b_and(self.sat(a), b_not(self.sat(b)))
            target = b_and(na_nb, self.fair)
            path = self._path(sources, target, a_nb)
            if path is not None:
                return path, None
            return self._lasso(v, b_not(self.sat(b)))
        if op == "EG":
            g = f[1]
            if want:
                return self._lasso(v, self.sat(g))
            # EG g false: every fair path meets !g: show the nearest !g node
            ng = b_and(b_not(self.sat(g)), self.fair)
            path = self._path(sources, ng, self.fair)
            if path is None:
                return [v], None
            return self._then(path[:-1], self.explain(g, path[-1], False, budget - 1))
        return [v], None

    def _bfs(self, sources, target, allowed, keep, skip):
        """bfs_path over node sets (the compiled search when there is one)."""
        from . import kernel
        got = kernel.bfs(self.K, sources, target, allowed, keep, skip)
        if got is not False:
            return got
        succ = self.K.succ
        if keep is not None:
            succ = lambda x: [w for w in self.K.succ(x) if keep[w]]   # noqa: E731
        return bfs_path(succ, sources, lambda x: target[x] == 1,
                        (lambda x: allowed[x] == 1) if allowed is not None else None, skip_sources=skip)

    def _path(self, sources, target, allowed):
        return self._bfs(sources, target, allowed, None, False)

    def _then(self, prefix: list, rest):
        nodes, loop = rest
        if loop is not None:
            loop += len(prefix)
        return prefix + nodes, loop

    def _lasso(self, v: int, s: bytearray):
        """A fair path of s nodes from v that loops: (nodes, loop index)."""
        K = self.K
        comps = self.fair_sccs(s)
        if not comps:
            return [v], None
        inside = bytearray(self.n)
        owner = {}
        for i, comp in enumerate(comps):
            for x in comp:
                inside[x] = 1
                owner[x] = i
        path = self._path([v], inside, s)
        if path is None:
            return [v], None
        entry = path[-1]
        comp = comps[owner[entry]]
        cmask = bytearray(self.n)
        for x in comp:
            cmask[x] = 1
        required = list(self.justice)
        for p, q in self.compassion:
            if any(p[x] for x in comp):
                required.append(q)
        cycle = cover_cycle(K.succ, entry, cmask, required, bfs=self._bfs)
        return path[:-1] + cycle, len(path) - 1


def _temporal(f) -> bool:
    if f[0] in ("EX", "EU", "EG"):
        return True
    return any(isinstance(x, tuple) and _temporal(x) for x in f[1:])
