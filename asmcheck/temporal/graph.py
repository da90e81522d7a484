"""Graph algorithms shared by the CTL and LTL checkers: node sets as 0/1 bytearrays,
strongly connected components (iterative Tarjan), fair SCCs (justice and compassion, by
SCC refinement as in Emerson--Lei), shortest paths and covering cycles."""
from __future__ import annotations

from collections import deque


# ----------------------------------------------------------------- node sets (bytearray of 0/1)
def full(n: int) -> bytearray:
    return bytearray(b"\x01") * n


def empty(n: int) -> bytearray:
    return bytearray(n)


def b_and(a: bytearray, b: bytearray) -> bytearray:
    n = len(a)
    return bytearray((int.from_bytes(a, "little") & int.from_bytes(b, "little")).to_bytes(n, "little"))


def b_or(a: bytearray, b: bytearray) -> bytearray:
    n = len(a)
    return bytearray((int.from_bytes(a, "little") | int.from_bytes(b, "little")).to_bytes(n, "little"))


def b_not(a: bytearray) -> bytearray:
    n = len(a)
    return bytearray((int.from_bytes(a, "little") ^ int.from_bytes(full(n), "little")).to_bytes(n, "little"))


def members(a: bytearray) -> list[int]:
    out = []
    i = a.find(1)
    while i >= 0:
        out.append(i)
        i = a.find(1, i + 1)
    return out


def any_in(a: bytearray, nodes) -> bool:
    return any(a[v] for v in nodes)


# ----------------------------------------------------------------- SCCs
def tarjan(n: int, succ, roots, mask=None) -> list[list[int]]:
    """The strongly connected components reachable from ``roots`` inside ``mask`` (every
    node when None), in reverse topological order; ``succ(v)`` lists v's successors."""
    index = [-1] * n
    low = [0] * n
    onstack = bytearray(n)
    stack: list[int] = []
    out: list[list[int]] = []
    counter = 0
    for r in roots:
        if index[r] != -1 or (mask is not None and not mask[r]):
            continue
        index[r] = low[r] = counter
        counter += 1
        stack.append(r)
        onstack[r] = 1
        work = [(r, iter(succ(r)))]
        while work:
            v, it = work[-1]
            pushed = False
            for w in it:
                if mask is not None and not mask[w]:
                    continue
                if index[w] == -1:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    onstack[w] = 1
                    work.append((w, iter(succ(w))))
                    pushed = True
                    break
                if onstack[w] and index[w] < low[v]:
                    low[v] = index[w]
            if pushed:
                continue
            work.pop()
            if work:
                u = work[-1][0]
                if low[v] < low[u]:
                    low[u] = low[v]
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    onstack[w] = 0
                    comp.append(w)
                    if w == v:
                        break
                out.append(comp)
    return out


def nontrivial(comp: list[int], succ) -> bool:
    if len(comp) > 1:
        return True
    v = comp[0]
    return v in succ(v)


def fair_sccs(n: int, succ, roots, mask, justice, compassion) -> list[list[int]]:
    """The components in which a path can stay for ever and meet every fairness condition:
    each justice set (bytearray) infinitely often, and for each compassion pair (p, q):
    q infinitely often if p is.  Components that see p but no q are refined by removing
    the p nodes (the Emerson--Lei treatment of strong fairness)."""
    out = []
    todo = [(list(roots), mask)]
    while todo:
        rts, msk = todo.pop()
        for comp in tarjan(n, succ, rts, msk):
            if not nontrivial(comp, succ):
                continue
            if any(not any_in(j, comp) for j in justice):
                continue
            bad = [p for p, q in compassion if any_in(p, comp) and not any_in(q, comp)]
            if bad:
                sub = bytearray(n)
                keep = [v for v in comp if not any(p[v] for p in bad)]
                for v in keep:
                    sub[v] = 1
                if keep:
                    todo.append((sorted(keep), sub))
                continue
            out.append(sorted(comp))
    out.sort()
    return out


# ----------------------------------------------------------------- paths
def bfs_path(succ, sources, target, allowed=None, skip_sources=False):
    """A shortest path [s, ..., t] from one of ``sources`` to a node with ``target(t)``,
    moving only out of nodes with ``allowed(v)`` (every node when None).  With
    ``skip_sources`` the path has at least one step (a source may be its own target).
    None when there is none."""
    parent: dict = {}
    q = deque()
    if skip_sources:
        for s in sources:
            if allowed is not None and not allowed(s):
                continue
            for w in succ(s):
                if w not in parent:
                    parent[w] = (s,)
                    if target(w):
                        return [s, w]
                    q.append(w)
    else:
        for s in sources:
            if s not in parent:
                parent[s] = None
                if target(s):
                    return [s]
                q.append(s)
    while q:
        v = q.popleft()
        if allowed is not None and not allowed(v):
            continue
        for w in succ(v):
            if w in parent:
                continue
            parent[w] = v
            if target(w):
                path = [w]
                x = v
                while True:
                    path.append(x)
                    p = parent[x]
                    if p is None:
                        break
                    if type(p) is tuple:
                        path.append(p[0])
                        break
                    x = p
                return path[::-1]
            q.append(w)
    return None


def cover_cycle(succ, start: int, comp_mask: bytearray, required: list, bfs=None) -> list[int]:
    """A cycle [start, ..., x] (x -> start is an edge) inside the component ``comp_mask`` that
    meets every set in ``required`` (bytearrays; each must meet the component).  ``bfs(sources,
    target, allowed, keep, skip)``: a search over node sets that gives bfs_path's paths (None:
    bfs_path itself)."""
    inside = lambda v: comp_mask[v] == 1   # noqa: E731
    isucc = lambda v: [w for w in succ(v) if comp_mask[w]]   # noqa: E731
    path = [start]
    cur = start
    for req in required:
        if any(req[v] for v in path):
            continue
        if bfs is not None:
            seg = bfs([cur], req, comp_mask, comp_mask, False)
        else:
            seg = bfs_path(isucc, [cur], lambda v, r=req: r[v] == 1, inside)
        if seg is None:
            raise AssertionError("a fairness set cannot be reached inside its component")
        path.extend(seg[1:])
        cur = path[-1]
    if bfs is not None:
        back = bytearray(len(comp_mask))
        back[start] = 1
        seg = bfs([cur], back, comp_mask, comp_mask, True)
    else:
        seg = bfs_path(isucc, [cur], lambda v: v == start, inside, skip_sources=True)
    if seg is None:
        raise AssertionError("no cycle back inside a component")
    path.extend(seg[1:-1])
    return path
