"""Canonical names for the elements ``extend`` makes, and collection of dropped ones.

Two states that differ only in the names of ``extend``-made elements (``D!k``)
are one state.  Elements are renamed ``D!1, D!2, ...`` in an order that does
not depend on their old names: every element gets a colour from the places
where it occurs (which function, which argument position, what value, the
colours of the other elements there), refined a few rounds, and elements are
numbered by colour.  Elements with equal final colours play symmetric roles;
their relative order falls back on the old names (so the result is still a
deterministic function of the state).

An element that no location refers to any more is dropped from its domain,
unless the spec ranges over that domain (``forall``/``choose``/quantifiers or
the domain used as a term), where dropping it would change the behaviour.
"""
from __future__ import annotations

from ..semantics.state import is_dom_key
from ..semantics.values import AbstractValue, BagV, MapV, SeqV, SetV, fresh_value, rename_state, vkey

ROUNDS = 3


def _walk_fresh(v, out: list) -> None:
    t = type(v)
    if t is AbstractValue:
        if v.serial > 0:
            out.append(v)
    elif t in (tuple, SeqV, BagV):
        for x in v:
            _walk_fresh(x, out)
    elif t is SetV:
        for x in v:
            _walk_fresh(x, out)
    elif t is MapV:
        for a, b in v:
            _walk_fresh(a, out)
            _walk_fresh(b, out)


def _render(v, color: dict, me) -> str:
    """A text of ``v`` where fresh elements show as their colour ('*' for the element ``me``)."""
    t = type(v)
    if t is AbstractValue and v.serial > 0:
        return "*" if v is me else f"#{color.get(v, '?')}"
    if t is tuple:
        return "(" + ",".join(_render(x, color, me) for x in v) + ")"
    if t is SeqV:
        return "[" + ",".join(_render(x, color, me) for x in v) + "]"
    if t is SetV or t is BagV:
        return "{" + ",".join(sorted(_render(x, color, me) for x in v)) + "}"
    if t is MapV:
        return "{" + ",".join(sorted(_render(a, color, me) + ">" + _render(b, color, me) for a, b in v)) + "}"
    return repr(v) if not isinstance(v, AbstractValue) else v.name


class Canonicalizer:
    def __init__(self, machine, gc_domains: set[str]):
        self.machine = machine
        self.gc = gc_domains
        self.last_mapping: dict = {}

    def __call__(self, state: dict) -> dict:
        """The canonical form of ``state``.  Afterwards ``self.last_mapping`` maps each element
        that was renamed to its new name (elements not in it keep theirs; dropped elements are
        not in the result)."""
        self.last_mapping = {}
        doms = {k[1]: v for k, v in state.items() if is_dom_key(k) and v}
        if not doms:
            return state
        # where each fresh element occurs
        occ: dict = {}
        entries = []
        for k, v in state.items():
            if is_dom_key(k):
                continue
            found: list = []
            if type(k) is tuple:
                _walk_fresh(k[1], found)
            _walk_fresh(v, found)
            if found:
                entries.append((k, v))
                for e in found:
                    occ.setdefault(e, []).append(len(entries) - 1)
        # drop unreferenced elements of domains nobody ranges over
        changed = False
        new_doms = {}
        for d, els in doms.items():
            if d in self.gc:
                kept = tuple(e for e in els if e.serial == 0 or e in occ)
                if len(kept) != len(els):
                    changed = True
                new_doms[d] = kept
            else:
                new_doms[d] = els
        elements = [e for d in sorted(new_doms) for e in new_doms[d] if e.serial > 0]
        if not elements:
            if not changed:
                return state
            out = {k: v for k, v in state.items() if not is_dom_key(k)}
            for d, els in new_doms.items():
                if els:
                    out[("#dom", d)] = els
            return out
        fname = self.machine.fname
        # colour refinement
        color = {e: 0 for e in elements}
        for _ in range(ROUNDS):
            sigs = {}
            for e in elements:
                parts = []
                for i in occ.get(e, ()):
                    k, v = entries[i]
                    if type(k) is tuple:
                        parts.append(f"{fname[k[0]]}{_render(k[1], color, e)}={_render(v, color, e)}")
                    else:
                        parts.append(f"{fname[k]}={_render(v, color, e)}")
                parts.sort()
                sigs[e] = (e.domain, color[e], tuple(parts))
            ranked = sorted(set(sigs.values()))
            rank = {s: i for i, s in enumerate(ranked)}
            new_color = {e: rank[sigs[e]] for e in elements}
            if len(set(new_color.values())) == len(set(color.values())) and _ == 0:
                color = new_color
                continue
            color = new_color
        # number per domain by colour, ties by old serial
        mapping = {}
        by_dom: dict = {}
        for e in elements:
            by_dom.setdefault(e.domain, []).append(e)
        for d, els in by_dom.items():
            els.sort(key=lambda e: (color[e], e.serial))
            for i, e in enumerate(els, 1):
                if e.serial != i:
                    mapping[e] = fresh_value(d, i)
        self.last_mapping = mapping
        if not mapping and not changed:
            return state
        base = {k: v for k, v in state.items() if not is_dom_key(k)}
        for d, els in new_doms.items():
            if els:
                base[("#dom", d)] = els
        return rename_state(base, mapping) if mapping else base


def ranged_domains(spec) -> set[str]:
    """Names of the domains the spec ranges over (directly or through a super-domain)."""
    from ..semantics import ir
    from ..semantics import types as T

    used: set = set()
    seen: set = set()

    def walk(x):
        if id(x) in seen:
            return
        seen.add(id(x))
        if isinstance(x, ir.DomainTerm):
            used.add(x.domain)
        if isinstance(x, (ir.Term, ir.Rule)):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
        elif isinstance(x, ir.Property):
            walk(x.body)
            walk(x.body2)

    for r in spec.rules:
        walk(r.body)
    for f in spec.functions:
        if f.body is not None:
            walk(f.body)
    for p in spec.properties:
        walk(p)
    names = set()
    for d in spec.domains:
        if not isinstance(d, T.Domain):
            continue
        x = d
        hops = 0
        while isinstance(x, T.Domain) and hops < 50:
            if x in used:
                names.add(d.name)
                break
            if x.kind != "subset" or x.base is None:
                break
            x = x.base
            hops += 1
    if T.AGENT in used:
        for d in spec.domains:
            if isinstance(d, T.Domain) and T.agent_like(d):
                names.add(d.name)
    return names
