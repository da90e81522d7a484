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

The canonicaliser runs on every successor, so it works incrementally: what a
location (key and value object) contributes is worked out once and cached, and
each state is compared with the state before (mostly the same objects) so that
only the locations that differ are looked at again.  Colours are compared as
the texts described at ``_Sorted``, exactly as if they were built from scratch.
"""
from __future__ import annotations

from itertools import compress, count, repeat
from operator import attrgetter, is_, is_not

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


# the public name of the walk (conform.py matches new elements with it)
walk_fresh = _walk_fresh


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

    def twin(self, key, value) -> "_Loc":
        """This location's analysis for an equal ``key`` and ``value``."""
        t = _Loc(key, value, self.elems, self.bound)
        t.segs = self.segs
        t.pos = self.pos
        t.const = self.const
        t.zero = self.zero
        if self.renamed is None:
            self.renamed = {}
        t.renamed = self.renamed
        return t


# the order of vkey among abstract elements
_ORDER = attrgetter("domain", "serial", "name")
_ABSTRACT_ONLY = {AbstractValue}

# types whose equal values are the same object
_IDENTICAL = frozenset((AbstractValue, EnumValue, type(None)))
# types whose equal values of the same type show the same text
_PLAIN_TEXT = frozenset((AbstractValue, EnumValue, type(None), bool, int, str))


def _same_key(k, v):
    """A key under which equal locations are the same to the canonicaliser (same text, same
    elements), or None when equality could hide a difference (1 and True, 0.0 and -0.0, a
    sequence and a tuple, ...)."""
    tv = type(v)
    if tv not in _PLAIN_TEXT:
        if (tv is not SeqV and tv is not tuple) or not all(map(_IDENTICAL.__contains__, map(type, v))):
            return None
    if type(k) is tuple:
        args = k[1]
        if type(args) is not tuple or not all(map(_IDENTICAL.__contains__, map(type, args))):
            return None
    return (k, tv, v)


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


_DOM_SLOT = object()


class _Scanned:
    """A state as the canonicaliser sees it, kept to look at the next state (which mostly has
    the same locations, most of them holding the same objects): per position its slot (see
    ``Canonicalizer._slot``), the positions of the domains, the locations renaming may change,
    and the texts of round 0 of each occurring element."""

    __slots__ = ("keys", "vals", "slots", "doms", "texts", "sigs")

    def __init__(self):
        self.keys: list = []
        self.vals: list = []
        self.slots: list = []
        self.doms: list = []        # positions of the domains
        self.texts: dict = {}       # id of an occurring element -> its texts of round 0
        self.sigs: dict = {}        # id -> sorted texts (dropped when the texts change)

    def add(self, loc) -> None:
        texts = self.texts
        sigs = self.sigs
        for i, t, c in loc.zero:
            p = texts.get(i)
            if p is None:
                texts[i] = [t] * c
            else:
                p.extend([t] * c)
            sigs.pop(i, None)

    def remove(self, loc) -> None:
        texts = self.texts
        sigs = self.sigs
        for i, t, c in loc.zero:
            p = texts[i]
            for _ in range(c):
                p.remove(t)
            if not p:
                del texts[i]
            sigs.pop(i, None)

    def sig0(self, i) -> tuple:
        s = self.sigs.get(i)
        if s is None:
            p = self.texts.get(i)
            s = self.sigs[i] = tuple(sorted(p)) if p else ()
        return s


# locations remembered across states (they mostly recur unchanged from state to state)
_CACHE_LIMIT = 1 << 17


class Canonicalizer:
    def __init__(self, machine, gc_domains: set[str]):
        self.machine = machine
        self.gc = gc_domains
        self.last_mapping: dict = {}
        self._locs: dict = {}       # (id(key), id(value)) -> _Loc, checked by identity
        self._kinds: dict = {}      # id(key) -> (key, _key_kind(key)) for keys with arguments
        self._equal: dict = {}      # _same_key(key, value) -> _Loc
        self._last = None           # the _Scanned state of the previous call

    def __call__(self, state: dict) -> dict:
        """The canonical form of ``state``.  Afterwards ``self.last_mapping`` maps each element
        that was renamed to its new name (elements not in it keep theirs; dropped elements are
        not in the result)."""
        self.last_mapping = {}
        keys = list(state)
        vals = list(state.values())
        sc = self._last
        self._last = None
        if sc is None:
            sc = _Scanned()
        self._follow(sc, keys, vals)
        self._last = sc
        doms = {keys[p][1]: vals[p] for p in sc.doms if vals[p]}
        if not doms:
            return state
        # drop unreferenced elements of domains nobody ranges over
        occurring = sc.texts
        changed = False
        new_doms = {}
        gc = self.gc
        for d, els in doms.items():
            if d in gc:
                kept = tuple(e for e in els if e.serial == 0 or id(e) in occurring)
                if len(kept) != len(els):
                    changed = True
                new_doms[d] = kept
            else:
                new_doms[d] = els
        elements = [e for d in sorted(new_doms) for e in new_doms[d] if e.serial > 0]
        if not elements:
            if not changed:
                return state
            return self._rebuild(state, keys, vals, sc, new_doms, {})
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
        zero = None
        for d, els in by_dom.items():
            if len(els) == 1:
                e = els[0]
                if e.serial != 1:
                    mapping[e] = fresh_value(d, 1)
                continue
            if zero is None:
                # the texts of round 0 hold only elements with a colour (none shows as '#?')
                zero = sc.texts.keys() <= {id(e) for e in elements}
            if zero and color is None:
                # a domain whose elements round 0 tells apart keeps that order in later rounds
                sig0 = sc.sig0
                sigs = [sig0(id(e)) for e in els]
                if len(set(sigs)) == len(els):
                    for i, (_, e) in enumerate(sorted(zip(sigs, els)), 1):
                        if e.serial != i:
                            mapping[e] = fresh_value(d, i)
                    continue
            if color is None:
                color = self._colours(elements, sc)
            els.sort(key=lambda e: (color[id(e)], e.serial))
            for i, e in enumerate(els, 1):
                if e.serial != i:
                    mapping[e] = fresh_value(d, i)
        self.last_mapping = mapping
        if not mapping and not changed:
            return state
        return self._rebuild(state, keys, vals, sc, new_doms, mapping)

    def _slot(self, k, v):
        """What the location ``k`` holding ``v`` is to the canonicaliser: _DOM_SLOT for a
        domain, its _Loc when elements occur or renaming may change it, else None."""
        if type(k) is tuple:
            kinds = self._kinds
            kind = kinds.get(id(k))
            if kind is None or kind[0] is not k:
                if len(kinds) >= _CACHE_LIMIT:
                    kinds.clear()
                kind = kinds[id(k)] = (k, _key_kind(k))
            kind = kind[1]
            if kind == _DOM:
                return _DOM_SLOT
            if kind == _PLAIN and type(v) in _ATOMS:
                return None
        elif type(v) in _ATOMS:
            return None
        cache = self._locs
        loc = cache.get((id(k), id(v)))
        if loc is None or loc.key is not k or loc.value is not v:
            if len(cache) >= _CACHE_LIMIT:
                cache.clear()
            # an equal location met before, when equality leaves nothing to tell apart
            eq = _same_key(k, v)
            if eq is not None:
                twin = self._equal.get(eq)
                if twin is not None:
                    loc = twin.twin(k, v)
                else:
                    loc = _scan(k, v, self.machine.fname)
                    if len(self._equal) >= _CACHE_LIMIT:
                        self._equal.clear()
                    self._equal[eq] = loc
            else:
                loc = _scan(k, v, self.machine.fname)
            cache[(id(k), id(v))] = loc
        return loc if loc.elems or loc.bound else None

    def _follow(self, sc: "_Scanned", keys: list, vals: list) -> None:
        """Make ``sc``, the scan of the state before, the scan of the state of locations
        ``keys`` holding ``vals``.  Consecutive states mostly list the same key objects in
        the same order with a few keys changed in between: the common beginning and end are
        compared value by value (by identity), the keys in between are taken out and added."""
        okeys = sc.keys
        ovals = sc.vals
        oslots = sc.slots
        n = len(keys)
        m = len(okeys)
        head = next(compress(count(), map(is_not, keys, okeys)), min(n, m))
        if head == n == m:
            for pos in compress(count(), map(is_not, vals, ovals)):
                self._move(sc, pos, keys[pos], vals[pos])
            sc.vals = vals
            return
        tail = min(next(compress(count(), map(is_not, reversed(keys), reversed(okeys))), m), n - head, m - head)
        # the middle of the state before goes
        for s in oslots[head:m - tail]:
            if s is not None and s is not _DOM_SLOT:
                sc.remove(s)
        slots = oslots[:head]
        slots.extend(repeat(None, n - tail - head))
        slots.extend(oslots[m - tail:])
        sc.slots = slots
        for pos in compress(count(), map(is_not, vals[:head], ovals[:head])):
            self._move(sc, pos, keys[pos], vals[pos])
        for q in compress(count(), map(is_not, vals[n - tail:], ovals[m - tail:])):
            self._move(sc, n - tail + q, keys[n - tail + q], vals[n - tail + q])
        # the middle of this state comes
        slot = self._slot
        for pos in range(head, n - tail):
            s = slots[pos] = slot(keys[pos], vals[pos])
            if s is not None and s is not _DOM_SLOT:
                sc.add(s)
        sc.keys = keys
        sc.vals = vals
        sc.doms = list(compress(count(), map(is_, slots, repeat(_DOM_SLOT))))

    def _move(self, sc: "_Scanned", pos: int, k, v) -> None:
        """Location ``k`` at position ``pos`` now holds ``v``."""
        old = sc.slots[pos]
        new = self._slot(k, v)
        if new is old:
            return
        sc.slots[pos] = new
        if old is not None:
            sc.remove(old)
        if new is not None:
            sc.add(new)

    def _colours(self, elements: list, sc: "_Scanned") -> dict:
        """Colours (id -> int) whose order within each domain numbers the elements.

        Round ``r`` ranks the signatures ``(domain, colour, sorted texts of the element's
        locations)`` of all elements; the rank is the next colour.  Signatures are compared
        group by group (same domain and colour): an element alone in its group needs no
        texts, and once every element is alone the order within a domain no longer changes.
        ``sc`` is the scanned state, with the texts of round 0 (every element colour 0)."""
        uniq: dict = {}
        for e in elements:
            uniq[id(e)] = e
        color = dict.fromkeys(uniq, 0)
        texts = sc.texts
        entries = None
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
                entries = [loc for loc in sc.slots if loc is not None and loc is not _DOM_SLOT and loc.elems]
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
                        sigs[ie] = sc.sig0(ie)
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
    def _rebuild(state: dict, keys: list, vals: list, sc: "_Scanned", new_doms: dict, mapping: dict) -> dict:
        """``state`` (locations ``keys`` holding ``vals``, scanned as ``sc``) with the domains
        ``new_doms`` and the elements renamed by ``mapping``."""
        changes = []                # (position, renamed key, renamed value)
        moved = False               # some key is renamed
        if mapping:
            ids = {id(e): id(n) for e, n in mapping.items()}
            slots = sc.slots
            for pos in compress(count(), slots):
                loc = slots[pos]
                if loc is _DOM_SLOT:
                    continue
                k = loc.key
                if loc.bound:
                    # a rule value's agent may be renamed: no shortcut
                    nk = (k[0], rename(k[1], mapping)) if type(k) is tuple else k
                    changes.append((pos, nk, rename(loc.value, mapping)))
                    if nk is not k and nk != k:
                        moved = True
                    continue
                # the new names of the location's elements decide the renamed location
                elems = loc.elems
                if len(elems) == 1:
                    sig = ids.get(elems[0][0])
                    if sig is None:
                        continue
                else:
                    sig = tuple([ids.get(i, i) for i, _, _ in elems])
                    if sig == tuple([i for i, _, _ in elems]):
                        continue
                memo = loc.renamed
                if memo is None:
                    memo = loc.renamed = {}
                kv = memo.get(sig)
                if kv is None:
                    if type(k) is tuple:
                        nk = (k[0], rename(k[1], mapping))
                        kv = memo[sig] = (nk, rename(loc.value, mapping), nk != k)
                    else:
                        kv = memo[sig] = (k, rename(loc.value, mapping), False)
                changes.append((pos, kv[0], kv[1]))
                if kv[2]:
                    moved = True
        if moved:
            # renamed keys take the places of the old ones
            keys = keys.copy()
            vals = vals.copy()
            for pos, k, v in changes:
                keys[pos] = k
                vals[pos] = v
            for p in reversed(sc.doms):
                del keys[p]
                del vals[p]
            out = dict(zip(keys, vals))
        else:
            out = state.copy()
            for pos, k, v in changes:
                out[keys[pos]] = v
            for p in sc.doms:
                del out[keys[p]]
        idmap = {id(e): n for e, n in mapping.items()}
        for d, els in new_doms.items():
            if els:
                if mapping:
                    els = list(map(idmap.get, map(id, els), els))
                    els.sort(key=_ORDER if set(map(type, els)) == _ABSTRACT_ONLY else vkey)
                    els = tuple(els)
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
