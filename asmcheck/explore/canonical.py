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

from ..semantics.values import AbstractValue, BagV, EnumValue, MapV, RuleValue, SeqV, SetV, fresh_value, rename, vkey

ROUNDS = 3

# values that hold no element: no need to look inside
_ATOMS = frozenset((int, bool, float, str, type(None), EnumValue))


def _walk_fresh(v, out: list) -> bool:
    """Append the fresh elements in ``v`` to ``out`` (once per occurrence); True when ``v``
    holds a rule value bound to an agent (which renaming may change although it is no
    occurrence)."""
    t = type(v)
    if t is AbstractValue:
        if v.serial > 0:
            out.append(v)
        return False
    if t is tuple or t is SeqV or t is BagV or t is SetV:
        bound = False
        for x in v:
            if type(x) in _ATOMS:
                continue
            if _walk_fresh(x, out):
                bound = True
        return bound
    if t is MapV:
        bound = False
        for a, b in v:
            if _walk_fresh(a, out):
                bound = True
            if _walk_fresh(b, out):
                bound = True
        return bound
    return t is RuleValue and v.agent is not None


# The signature of an element is made of texts of the locations where it occurs, with
# fresh elements shown as their colour ('#3', '#?' without one) and the element itself
# as '*'; sets, bags and maps list their members' texts sorted.  The order of the
# colours follows the order of these texts, so they are built exactly, but from
# templates made once per state: constant text, holes for the fresh elements, and
# `_Sorted` nodes for the collections whose member texts depend on colours.

class _Sorted:
    __slots__ = ("items",)

    def __init__(self, items):
        self.items = items          # one segment list per member

    def text(self, cs: dict, me) -> str:
        return "{" + ",".join(sorted(_text(x, cs, me) for x in self.items)) + "}"


def _text(segs: list, cs: dict, me) -> str:
    out = []
    for s in segs:
        t = type(s)
        if t is str:
            out.append(s)
        elif t is AbstractValue:
            out.append("*" if s is me else cs.get(id(s), "#?"))
        else:
            out.append(s.text(cs, me))
    return "".join(out)


def _join(items: list, sep: str, open_: str = "", close: str = ""):
    """Concatenation of compiled items (texts or segment lists), adjacent texts merged."""
    segs = []
    buf = open_
    first = True
    for it in items:
        if first:
            first = False
        else:
            buf += sep
        if type(it) is str:
            buf += it
            continue
        for s in it:
            if type(s) is str:
                buf += s
            else:
                if buf:
                    segs.append(buf)
                    buf = ""
                segs.append(s)
    buf += close
    if buf:
        segs.append(buf)
    return segs


def _compile(v):
    """The text of ``v`` when it holds no fresh element, else its segment list."""
    t = type(v)
    if t is AbstractValue:
        return [v] if v.serial > 0 else v.name
    if t is tuple or t is SeqV:
        items = [_compile(x) for x in v]
        o, c = ("(", ")") if t is tuple else ("[", "]")
        for x in items:
            if type(x) is not str:
                return _join(items, ",", o, c)
        return o + ",".join(items) + c
    if t is SetV or t is BagV or t is MapV:
        if t is MapV:
            items = []
            for a, b in v:
                ca, cb = _compile(a), _compile(b)
                if type(ca) is str and type(cb) is str:
                    items.append(ca + ">" + cb)
                else:
                    items.append(_join([ca, cb], ">"))
        else:
            items = [_compile(x) for x in v]
        for x in items:
            if type(x) is not str:
                return [_Sorted([x if type(x) is list else [x] for x in items])]
        return "{" + ",".join(sorted(items)) + "}"
    return repr(v)


class _Loc:
    """What a location (key, value) holds: its fresh elements ``(id, element, occurrences)``,
    whether renaming may change it (``bound``: a rule value bound to an agent), and, when
    elements occur, its signature text as a template."""

    __slots__ = ("key", "value", "elems", "bound", "segs", "pos", "const", "zero", "renamed")

    def __init__(self, key, value, elems: tuple, bound: bool):
        self.key = key
        self.value = value
        self.elems = elems
        self.bound = bound
        self.segs = None            # the template
        self.pos = None             # id -> hole positions (flat templates of several elements)
        self.const = None           # the text when one element occurs (it needs no colours)
        self.zero = ()              # (id, text while every element has colour 0, occurrences)
        self.renamed = None         # new element ids -> (key, value) renamed


def _scan(k, v, fname) -> _Loc:
    found: list = []
    bound = False
    if type(k) is tuple:
        bound = _walk_fresh(k[1], found)
    if type(v) not in _ATOMS and _walk_fresh(v, found):
        bound = True
    if not found:
        return _Loc(k, v, (), bound)
    if len(found) == 1:
        e = found[0]
        loc = _Loc(k, v, ((id(e), e, 1),), bound)
    else:
        counts: dict = {}
        for e in found:
            c = counts.get(id(e))
            counts[id(e)] = [e, 1] if c is None else [e, c[1] + 1]
        loc = _Loc(k, v, tuple((i, e, c) for i, (e, c) in counts.items()), bound)
    if type(k) is tuple:
        segs = _join([fname[k[0]], _compile(k[1]), "=", _compile(v)], "")
    else:
        segs = _join([fname[k], "=", _compile(v)], "")
    loc.segs = segs
    if len(loc.elems) == 1:
        i, e, c = loc.elems[0]
        loc.const = _text(segs, {}, e)
        loc.zero = ((i, loc.const, c),)
        return loc
    if not any(type(s) is _Sorted for s in segs):
        pos: dict = {}
        for j, s in enumerate(segs):
            if type(s) is AbstractValue:
                p = pos.get(id(s))
                if p is None:
                    pos[id(s)] = [j]
                else:
                    p.append(j)
        loc.pos = pos
    zero = dict.fromkeys([i for i, _, _ in loc.elems], "#0")
    loc.zero = tuple((i, _text(segs, zero, e), c) for i, e, c in loc.elems)
    return loc


_PLAIN, _ARGS, _DOM = 0, 1, 2


def _key_kind(k: tuple) -> int:
    """_DOM for a domain's key, _ARGS when the arguments hold a fresh element or a rule
    value bound to an agent, else _PLAIN."""
    if k[0] == "#dom" and len(k) == 2:
        return _DOM
    found: list = []
    bound = _walk_fresh(k[1], found)
    return _ARGS if found or bound else _PLAIN


# locations remembered across states (they mostly recur unchanged from state to state)
_CACHE_LIMIT = 1 << 17


class Canonicalizer:
    def __init__(self, machine, gc_domains: set[str]):
        self.machine = machine
        self.gc = gc_domains
        self.last_mapping: dict = {}
        self._locs: dict = {}       # (id(key), id(value)) -> _Loc, checked by identity
        self._kinds: dict = {}      # id(key) -> (key, _key_kind(key)) for keys with arguments

    def __call__(self, state: dict) -> dict:
        """The canonical form of ``state``.  Afterwards ``self.last_mapping`` maps each element
        that was renamed to its new name (elements not in it keep theirs; dropped elements are
        not in the result)."""
        self.last_mapping = {}
        atoms = _ATOMS
        cache = self._locs
        fname = self.machine.fname
        doms = {}
        texts: dict = {}            # id of a fresh element -> its texts while all colours are 0
        entries: list = []          # the _Loc of each location where fresh elements occur
        touched: dict = {}          # position -> _Loc of the locations renaming may change
        kinds = self._kinds
        for pos, (k, v) in enumerate(state.items()):
            if type(k) is tuple:
                kind = kinds.get(id(k))
                if kind is None or kind[0] is not k:
                    if len(kinds) >= _CACHE_LIMIT:
                        kinds.clear()
                    kind = kinds[id(k)] = (k, _key_kind(k))
                kind = kind[1]
                if kind == _DOM:
                    if v:
                        doms[k[1]] = v
                    continue
                if kind == _PLAIN and type(v) in atoms:
                    continue
            elif type(v) in atoms:
                continue
            loc = cache.get((id(k), id(v)))
            if loc is None or loc.key is not k or loc.value is not v:
                if len(cache) >= _CACHE_LIMIT:
                    cache.clear()
                loc = cache[(id(k), id(v))] = _scan(k, v, fname)
            if loc.elems:
                entries.append(loc)
                touched[pos] = loc
                for i, t, c in loc.zero:
                    p = texts.get(i)
                    if p is None:
                        texts[i] = [t] if c == 1 else [t] * c
                    elif c == 1:
                        p.append(t)
                    else:
                        p.extend([t] * c)
            elif loc.bound:
                touched[pos] = loc
        if not doms:
            return state
        # drop unreferenced elements of domains nobody ranges over
        changed = False
        new_doms = {}
        gc = self.gc
        for d, els in doms.items():
            if d in gc:
                kept = tuple(e for e in els if e.serial == 0 or id(e) in texts)
                if len(kept) != len(els):
                    changed = True
                new_doms[d] = kept
            else:
                new_doms[d] = els
        elements = [e for d in sorted(new_doms) for e in new_doms[d] if e.serial > 0]
        if not elements:
            if not changed:
                return state
            return self._rebuild(state, new_doms, {}, {})
        # number per domain by colour, ties by old serial
        by_dom: dict = {}
        for e in elements:
            g = by_dom.get(e.domain)
            if g is None:
                by_dom[e.domain] = [e]
            else:
                g.append(e)
        mapping = {}
        color = None
        for d, els in by_dom.items():
            if len(els) == 1:
                e = els[0]
                if e.serial != 1:
                    mapping[e] = fresh_value(d, 1)
                continue
            if color is None:
                color = self._colours(elements, entries, texts)
            els.sort(key=lambda e: (color[id(e)], e.serial))
            for i, e in enumerate(els, 1):
                if e.serial != i:
                    mapping[e] = fresh_value(d, i)
        self.last_mapping = mapping
        if not mapping and not changed:
            return state
        return self._rebuild(state, new_doms, mapping, touched)

    def _colours(self, elements: list, entries: list, texts: dict) -> dict:
        """Colours (id -> int) whose order within each domain numbers the elements.

        Round ``r`` ranks the signatures ``(domain, colour, sorted texts of the element's
        locations)`` of all elements; the rank is the next colour.  Signatures are compared
        group by group (same domain and colour): an element alone in its group needs no
        texts, and once every element is alone the order within a domain no longer changes.
        ``texts`` are the texts of round 0, where every element has colour 0."""
        uniq: dict = {}
        for e in elements:
            uniq[id(e)] = e
        color = dict.fromkeys(uniq, 0)
        occ = None
        fixed: dict = {}            # id -> _split of the element
        for r in range(ROUNDS):
            groups: dict = {}
            for i, e in uniq.items():
                key = (e.domain, color[i])
                g = groups.get(key)
                if g is None:
                    groups[key] = [e]
                else:
                    g.append(e)
            if len(groups) == len(uniq):
                break
            # round 0 from the texts made while scanning, unless an element without a colour
            # ('#?') occurs
            zero = r == 0 and texts.keys() <= color.keys()
            if not zero and occ is None:
                occ = {}
                for n, loc in enumerate(entries):
                    for i, _, c in loc.elems:
                        o = occ.get(i)
                        if o is None:
                            occ[i] = [(n, c)]
                        else:
                            o.append((n, c))
            cs = None               # id -> '#colour'
            bases: dict = {}        # entry -> its segments under this round's colours
            new: dict = {}
            rank = 0
            for key in sorted(groups):
                g = groups[key]
                if len(g) == 1:
                    new[id(g[0])] = rank
                    rank += 1
                    continue
                sigs = {}
                for e in g:
                    ie = id(e)
                    if zero:
                        parts = texts.get(ie)
                        if parts is None:
                            sigs[ie] = ()
                            continue
                        parts = parts.copy()
                        parts.sort()
                        sigs[ie] = tuple(parts)
                        continue
                    split = fixed.get(ie)
                    if split is None:
                        split = fixed[ie] = _split(occ.get(ie, ()), entries)
                    parts = split[0].copy()
                    if split[1] and cs is None:
                        cs = {i: "#%d" % c for i, c in color.items()}
                    for n, cnt in split[1]:
                        loc = entries[n]
                        if loc.pos is not None:
                            base = bases.get(n)
                            if base is None:
                                base = bases[n] = [s if type(s) is str else cs.get(id(s), "#?") for s in loc.segs]
                            pieces = base.copy()
                            for j in loc.pos[ie]:
                                pieces[j] = "*"
                            p = "".join(pieces)
                        else:
                            p = _text(loc.segs, cs, e)
                        if cnt == 1:
                            parts.append(p)
                        else:
                            parts.extend([p] * cnt)
                    parts.sort()
                    sigs[ie] = tuple(parts)
                order = {s: j for j, s in enumerate(sorted(set(sigs.values())), rank)}
                rank += len(order)
                for ie, s in sigs.items():
                    new[ie] = order[s]
            color = new
        return color

    @staticmethod
    def _rebuild(state: dict, new_doms: dict, mapping: dict, touched: dict) -> dict:
        """``state`` with the domains ``new_doms`` and the elements renamed by ``mapping``
        (only the locations ``touched``, position -> _Loc, can change)."""
        if mapping:
            ids = {id(e): id(n) for e, n in mapping.items()}
            out = {}
            for pos, (k, v) in enumerate(state.items()):
                if type(k) is tuple and k[0] == "#dom" and len(k) == 2:
                    continue
                loc = touched.get(pos)
                if loc is None:
                    out[k] = v
                    continue
                if loc.bound:
                    # a rule value's agent may be renamed: no shortcut
                    if type(k) is tuple:
                        out[(k[0], rename(k[1], mapping))] = rename(v, mapping)
                    else:
                        out[k] = rename(v, mapping)
                    continue
                # the new names of the location's elements decide the renamed location
                sig = tuple([ids.get(i, i) for i, _, _ in loc.elems])
                memo = loc.renamed
                if memo is None:
                    memo = loc.renamed = {}
                kv = memo.get(sig)
                if kv is None:
                    if all(i == j for (i, _, _), j in zip(loc.elems, sig)):
                        # none of its elements is renamed
                        out[k] = v
                        continue
                    if type(k) is tuple:
                        kv = memo[sig] = ((k[0], rename(k[1], mapping)), rename(v, mapping))
                    else:
                        kv = memo[sig] = (k, rename(v, mapping))
                out[kv[0]] = kv[1]
            for d, els in new_doms.items():
                if els:
                    out[("#dom", d)] = tuple(sorted((mapping.get(e, e) for e in els), key=vkey))
            return out
        out = {k: v for k, v in state.items() if not (type(k) is tuple and k[0] == "#dom" and len(k) == 2)}
        for d, els in new_doms.items():
            if els:
                out[("#dom", d)] = els
        return out


def _split(occs, entries) -> tuple:
    """An element's texts that do not depend on the colours, and the (entry, occurrences)
    whose texts do."""
    fixed = []
    var = []
    for n, cnt in occs:
        p = entries[n].const
        if p is None:
            var.append((n, cnt))
        elif cnt == 1:
            fixed.append(p)
        else:
            fixed.extend([p] * cnt)
    return fixed, var


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
