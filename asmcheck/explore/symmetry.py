"""Symmetry reduction: interchangeable domain elements, and one state per class.

Detection.  For an enum domain, a static abstract domain (its elements are the static constants
declared in it) or a finite subset of Integer given by its elements, the elements that no
literal (or, for an abstract domain, no use of the static constant) names (anywhere: rules, static and derived definitions, the initial
state, every property checked, the values given with ``--monitored``) are interchangeable
when the spec and its properties never tell them apart: a value of the domain may only be
compared by equality (with another value of the domain or with a literal), passed as an
argument where the domain is declared, stored in a location of the domain, bound by a
``let``, or chosen or quantified over the whole domain.  Any other use (arithmetic, an order
comparison, a library function, a collection, a comprehension over the domain, a value of
another type where the domain is expected, a variable of the domain bound around a temporal
operator, ...) leaves the domain without symmetry, with the first such use as the reason.  The
spec must not use ``extend``, and ``--fair`` (fairness of each choice on its own) turns the
reduction off.

Reduction.  Each interchangeable element gets a signature: the sorted list of the locations
where it occurs (function, position, the other arguments, the value).  The elements are
renamed so that their signatures come in the order of the elements; elements with equal
signatures play the same part (swapping them leaves the state as it is), so the result is
the same for every state of a class: a canonical representative.  A stored function with
several positions over symmetric domains (``link: Node -> Node``, ``edge: Prod(Node, Node) ->
Boolean``) needs more (:meth:`Symmetry.canon_multi`): colours refined over the locations, then
the least renamed state among the numberings that keep the colours' order; a domain of more than
six interchangeable elements in such a function is left without symmetry.

Counts of a reduced search are counts of classes (orbits); invariants, deadlock and LTL/CTL
properties keep their verdicts, since no property names an interchangeable element and each
is evaluated by the same equality-only operations; traces are made concrete again by a replay
through the step function from the real initial state, and the failing step of an error trace is
the concrete state's branch (:meth:`Symmetry.concrete_error`).

The native engine (native_sym.c) makes the same representative on its packed states, from the
tables :func:`native_tables` writes out of this module's own signature entries and location texts
(numbers only): the same classes, numbers, parents and traces as the Python engine's search.

Why one module of some 1,300 lines: the detection (:class:`_Uses`), the canonical form
(:class:`Symmetry`) and the native tables read the same signature entries; kept together, a
change to what a signature holds cannot reach one of the three and miss the others.
"""
from __future__ import annotations

import math
import os
from itertools import permutations

from ..semantics import ir
from ..semantics import types as T
from ..semantics.analysis import abstract_codomain, ir_nodes, is_subdomain
from ..semantics.values import EnumValue, abstract_value, show, vkey


class SymmetricDomain:
    """A domain with interchangeable elements: ``free`` (in the domain's order) and the
    elements literals name."""

    def __init__(self, domain, values: list, named: list):
        self.domain = domain
        self.name = domain.name
        self.values = values
        self.named = named
        nameset = set(map(_vid, named))
        self.free = [v for v in values if _vid(v) not in nameset]
        self.free_ids = {_vid(v): i for i, v in enumerate(self.free)}

    def describe(self) -> str:
        return f"{self.name}'s {len(self.free):,} unnamed elements"


_MISSING = object()

#: a domain with more elements is not considered
MAX_ELEMENTS = 100_000
#: a function with several positions over a domain whose interchangeable elements have more
#: renamings than this leaves that domain without symmetry (6! = 720)
MAX_RENAMINGS = 720


def _vid(v):
    """A key telling values apart (1 and True differ)."""
    return (type(v) is bool, v)


class Symmetry:
    """What detection found: ``domains`` (SymmetricDomain, possibly none), ``lines`` (one
    explanation per candidate domain) and ``reason`` (why no reduction is possible, or '')."""

    def __init__(self, domains: list, lines: list, reason: str = "", positions: dict | None = None,
                 multi: dict | None = None):
        self.domains = domains
        # function index -> [(position, SymmetricDomain)]: stored functions with several positions
        # over symmetric domains (their canonical form is worked out by refinement and, for the
        # elements refinement does not tell apart, by trying their renamings: canon_multi)
        self.multi = multi or {}
        # function index -> the positions apply renames
        self._all_positions = {f: [p] for f, (p, _) in (positions or {}).items()}
        for f, ps in self.multi.items():
            self._all_positions[f] = [p for p, _ in ps]
        self.lines = lines
        self.reason = reason
        # function index -> (position, SymmetricDomain): the argument (or -1, the value) of a
        # stored function over a symmetric domain
        self.positions = positions or {}
        n = 0
        for d in domains:
            d.offset = n
            n += len(d.free)
        self._n = n
        self._keys: dict = {}           # location key -> _key_info
        self._base = None               # (state, its scan, sorted signatures): see canon_from

    @property
    def active(self) -> bool:
        return bool(self.domains)

    def describe(self) -> str:
        """'the symmetry of Numero's 21 unnamed elements' (and others)."""
        parts = [d.describe() for d in self.domains]
        return "the symmetry of " + _and(parts)

    # ---------------------------------------------------------------- the canonical form
    def _key_info(self, k):
        """What location key ``k`` is to :meth:`canon`: None (no interchangeable element can
        occur in it), else (position, SymmetricDomain, global index of the element at an
        argument position or -1, the location's signature entry prefix)."""
        if type(k) is tuple:
            if k[0] == "#dom":
                return None
            info = self.positions.get(k[0])
            if info is None:
                return None
            p, sd = info
            args = k[1]
            if p >= 0:
                ix = sd.free_ids.get(_vid(args[p]))
                if ix is None:
                    return None
                return (p, sd, sd.offset + ix, (k[0], p, tuple([vkey(a) for i, a in enumerate(args) if i != p])), {})
            return (p, sd, -1, (k[0], -1, tuple([vkey(a) for a in args])), None)
        info = self.positions.get(k)
        if info is None:
            return None
        return (-1, info[1], -1, (k, -1, ()), None)

    def _info(self, k):
        kc = self._keys
        info = kc.get(k, _MISSING)
        if info is _MISSING:
            if len(kc) > 1 << 18:
                kc.clear()
            info = kc[k] = self._key_info(k)
        return info

    def _entry(self, info, v):
        """(global index of the element location ``info`` holding ``v`` is about, its signature
        entry), or None when it is about no interchangeable element."""
        g = info[2]
        if g < 0:
            if v is None:
                return None
            ix = info[1].free_ids.get(_vid(v))
            if ix is None:
                return None
            return info[1].offset + ix, (info[3], 0, 0)
        ents = info[4]
        ent = ents.get(v)
        if ent is None or ent[0] is not v.__class__:
            if len(ents) > 64:
                ents.clear()
            ent = ents[v] = (v.__class__, (info[3], 1, v) if v.__class__ is bool else (info[3], 2, vkey(v)))
        return g, ent[1]

    def _scan(self, state: dict):
        """Per interchangeable element (global index): its signature entries, and the keys of
        its locations."""
        sigs = [[] for _ in range(self._n)]
        occ = [[] for _ in range(self._n)]
        info_of = self._info
        entry = self._entry
        for k, v in state.items():
            info = info_of(k)
            if info is None:
                continue
            e = entry(info, v)
            if e is None:
                continue
            sigs[e[0]].append(e[1])
            occ[e[0]].append(k)
        return sigs, occ

    def canon(self, state: dict) -> tuple[dict, dict]:
        """(the canonical representative of ``state``'s class, the renaming that makes it from
        ``state``: element -> element, for the elements that move)."""
        if self.multi:
            return self.canon_multi(state)
        sigs, occ = self._scan(state)
        return self._finish(state, [sorted(x) for x in sigs], occ)

    def canon_from(self, parent: dict, state: dict) -> tuple[dict, dict]:
        """:meth:`canon` of ``state``, a successor of ``parent`` (mostly the same value objects):
        the scan of ``parent`` is kept for its next successor, and only the locations whose value
        object differs are looked at again."""
        if self.multi:
            return self.canon_multi(state)
        base = self._base
        if base is None or base[0] is not parent:
            sigs, occ = self._scan(parent)
            base = self._base = (parent, sigs, occ, [sorted(x) for x in sigs])
        _, psigs, pocc, pkeys = base
        diff = [k for k, v in state.items() if parent.get(k, _MISSING) is not v]
        if len(state) - sum(1 for k in diff if k not in parent) != len(parent):
            diff.extend(k for k in parent if k not in state)
        sigs = psigs
        occ = pocc
        touched: set = set()
        info_of = self._info
        entry = self._entry
        for k in diff:
            info = info_of(k)
            if info is None:
                continue
            for v, add in ((parent.get(k, _MISSING), False), (state.get(k, _MISSING), True)):
                if v is _MISSING:
                    continue
                e = entry(info, v)
                if e is None:
                    continue
                g = e[0]
                if g not in touched:
                    if not touched:
                        sigs = list(psigs)
                        occ = list(pocc)
                    touched.add(g)
                    sigs[g] = list(sigs[g])
                    occ[g] = list(occ[g])
                if add:
                    sigs[g].append(e[1])
                    occ[g].append(k)
                else:
                    sigs[g].remove(e[1])
                    occ[g].remove(k)
        if touched:
            keys = list(pkeys)
            for g in touched:
                keys[g] = sorted(sigs[g])
        else:
            keys = pkeys
        return self._finish(state, keys, occ)

    def canon_multi(self, state: dict) -> tuple[dict, dict]:
        """The canonical form when some stored function has several positions over symmetric
        domains.  Each element is coloured by the locations it occurs in (the other elements there
        shown by their colours), refined until the colours no longer split; the elements are
        numbered by colour, and among the numberings that keep the colours' order (the elements of
        equal colour in every order), the one whose renamed state is least is taken."""
        parts_of = []               # per location: (key, value, [(position, global index or -1, const)])
        occurs: dict = {}           # global index -> [(location number, position)]
        for k, v in state.items():
            if type(k) is tuple:
                if k[0] == "#dom":
                    continue
                f, args = k
            else:
                f, args = k, ()
            ps = self.multi.get(f)
            if ps is None:
                one = self.positions.get(f)
                if one is None:
                    continue
                ps = [one]
            holes = []
            for p, sd in ps:
                e = args[p] if p >= 0 else v
                ix = sd.free_ids.get(_vid(e)) if (p >= 0 or v is not None) else None
                holes.append((p, -1 if ix is None else sd.offset + ix))
            if all(g < 0 for _, g in holes):
                continue
            n = len(parts_of)
            parts_of.append((k, v, holes))
            for p, g in holes:
                if g >= 0:
                    occurs.setdefault(g, []).append((n, p))
        const = {}                  # location number -> its text with the free elements left out
        for n, (k, v, holes) in enumerate(parts_of):
            f, args = (k if type(k) is tuple else (k, ()))
            free_pos = {p for p, g in holes if g >= 0}
            const[n] = (f, tuple(vkey(a) if i not in free_pos else (-1,) for i, a in enumerate(args)),
                        (-1,) if -1 in free_pos else vkey(v))
        colour = [0] * self._n
        for sd in self.domains:
            for i in range(len(sd.free)):
                colour[sd.offset + i] = 0
        classes = -1
        for _ in range(self._n + 1):
            sig = {}
            for g in range(self._n):
                entries = []
                for n, p in occurs.get(g, ()):
                    holes = parts_of[n][2]
                    entries.append((const[n], p, tuple((q, -1 if h < 0 else (-2 if h == g else colour[h]))
                                                       for q, h in holes)))
                entries.sort()
                sig[g] = (colour[g], tuple(entries))
            new = [0] * self._n
            count = 0
            for sd in self.domains:
                idx = range(sd.offset, sd.offset + len(sd.free))
                ranks = {x: r for r, x in enumerate(sorted({sig[g] for g in idx}))}
                for g in idx:
                    new[g] = ranks[sig[g]]
                count += len(ranks)
            colour = new
            if count == classes:
                break
            classes = count
        # the numberings that keep the colours' order
        choices = []
        for sd in self.domains:
            groups: dict = {}
            for i in range(len(sd.free)):
                groups.setdefault(colour[sd.offset + i], []).append(i)
            choices.append((sd, [groups[c] for c in sorted(groups)]))
        best = None
        for perm in _numberings(choices):
            out = self.apply(state, perm)
            key = sorted((vkey(k), vkey(x)) for k, x in out.items())
            if best is None or key < best[0]:
                best = (key, out, perm)
        return best[1], best[2]

    def _finish(self, state: dict, keys: list, occ: list) -> tuple[dict, dict]:
        """The canonical form from each element's sorted signature (``keys``) and locations."""
        kc = self._keys
        perm: dict = {}
        for sd in self.domains:
            free = sd.free
            off = sd.offset
            order = sorted(range(len(free)), key=lambda i: (keys[off + i], i))
            for j, i in enumerate(order):
                if i != j:
                    perm[free[i]] = free[j]
        if not perm:
            return state, {}
        # only the locations of the elements that move change
        out = dict(state)
        new = []
        for sd in self.domains:
            off = sd.offset
            for e in sd.free:
                n = perm.get(e)
                if n is None:
                    continue
                for k in occ[off + sd.free_ids[_vid(e)]]:
                    v = out.pop(k)
                    p = kc[k][0]
                    if p >= 0:
                        args = k[1]
                        new.append(((k[0], args[:p] + (n,) + args[p + 1:]), v))
                    else:
                        new.append((k, n))
        out.update(new)
        return out, perm

    def apply(self, state: dict, perm: dict) -> dict:
        """``state`` with the elements renamed by ``perm`` (element -> element) at the positions
        of the symmetric domains."""
        if not perm:
            return state
        pos_of = self._all_positions
        ren = {_vid(a): b for a, b in perm.items()}
        out = {}
        for k, v in state.items():
            if type(k) is tuple:
                ps = pos_of.get(k[0]) if k[0] != "#dom" else None
            else:
                ps = pos_of.get(k)
            if ps is not None:
                for p in ps:
                    if p >= 0:
                        args = k[1]
                        n = ren.get(_vid(args[p]))
                        if n is not None:
                            k = (k[0], args[:p] + (n,) + args[p + 1:])
                    elif v is not None:
                        v = ren.get(_vid(v), v)
            out[k] = v
        return out

    def concrete_error(self, machine, state: dict, err):
        """The failing branch of ``state``'s step (a concrete state of a trace) that is the image of
        ``err``, a failing branch of the step of its class's representative: the same choices with
        the elements renamed (the first such branch in the step function's order), or None."""
        from ..errors import AsmError
        perm = self.canon(state)[1]         # concrete element -> the representative's
        ren = {_vid(a): b for a, b in perm.items()}
        typed = self._choice_types(machine)
        want = _choice_keys(getattr(err, "choices", None) or (), {}, typed)
        errors: list = []
        try:
            for _ in machine.successors(state, errors=errors):
                pass
        except AsmError as e:
            errors = [e]
        for e in errors:
            if _choice_keys(getattr(e, "choices", None) or (), ren, typed) == want:
                return e
        return None

    def _choice_types(self, machine) -> "_ChoiceTypes":
        got = getattr(self, "_typed", None)
        if got is None or got.machine is not machine:
            got = self._typed = _ChoiceTypes(machine, [sd.domain for sd in self.domains])
        return got

    @staticmethod
    def inverse(perm: dict) -> dict:
        return {b: a for a, b in perm.items()}

    @staticmethod
    def compose(first: dict, then: dict) -> dict:
        """The renaming ``then`` after ``first``."""
        out = {}
        for a in list(first) + [k for k in then if k not in first]:
            b = first.get(a, a)
            c = then.get(b, b)
            if c != a:
                out[a] = c
        return out


# -------------------------------------------------------------------- the native canonical form
#: False: native_sym.c's general signatures (rank lists) even where one 64-bit number holds each (tests)
NATIVE_FAST = True


class NativeRefused(Exception):
    """A symmetry the native engine does not reduce (the reason is the message)."""


def native_reason(sym: Symmetry) -> str:
    """Why the native engine cannot reduce ``sym`` before any code is generated ('' when it may)."""
    return ""


#: the most numberings the native canonical form of a function with several positions tries in
#: one state (more: the native search stops there, and the Python engine takes the run)
NATIVE_MAX_NUMBERINGS = 40_320


def native_multi_tables(sym: Symmetry, gen) -> str:
    """The C tables of native_sym.c's canonical form for functions with several positions over
    symmetric domains (:meth:`Symmetry.canon_multi`, the same representative): per location of a
    function over a symmetric domain (a narrow slot), its holes (position, element or the value),
    the rank of its text with the free elements left out (per code), its value's rank (per code)
    and its key's place in the order of the state's items; NativeRefused otherwise."""
    dom_no = {id(sd): i for i, sd in enumerate(sym.domains)}
    for key in gen.slots:
        if type(key) is tuple and key and key[0] == "map" and not gen.local_slot(key):
            # (its locations' keys would have to take their places among the items compared)
            raise NativeRefused(f"{gen.spec.functions[key[1]].name}'s locations are one map value in the native "
                                f"layout, beside a function with several positions over a symmetric domain")
    ms = []                  # (slot, f, [(p, domain number, element global or -1)], codes' values)
    for s, key in enumerate(gen.slots):
        if type(key) is tuple and key and key[0] == "map":
            continue
        if type(key) is tuple:
            if not key or key[0] == "#dom" or type(key[0]) is not int or len(key) != 2:
                continue
            fi, args = key
        elif type(key) is int:
            fi, args = key, ()
        else:
            continue
        ps = sym.multi.get(fi)
        if ps is None:
            one = sym.positions.get(fi)
            if one is None:
                continue
            ps = [one]
        f = gen.spec.functions[fi]
        codes = gen.slot_values[s]
        if codes is None or gen.bits[s] >= 32:
            raise NativeRefused(f"{f.name} over {_and(sorted({sd.name for _, sd in ps}))} holds values of "
                                f"{f.codomain}, which the native canonical form does not order")
        if fi in getattr(gen, "map_slot", {}):
            raise NativeRefused(f"{f.name}'s locations are one map value in the native layout")
        values = [codes[x] if x < len(codes) else None for x in range(1 << gen.bits[s])]
        holes = []
        for p, sd in ps:
            if p >= 0:
                ix = sd.free_ids.get(_vid(args[p]))
                holes.append((p, dom_no[id(sd)], -1 if ix is None else sd.offset + ix))
            else:
                holes.append((p, dom_no[id(sd)], -2))
        if all(g == -1 for _, _, g in holes):
            continue
        ms.append((s, fi, args, holes, values, ps))
    for fi in list(sym.multi) + list(sym.positions):
        if fi in getattr(gen, "map_slot", {}):
            raise NativeRefused(f"{gen.spec.functions[fi].name}'s locations are one map value in the native layout")
    # the texts of the locations (per code), the values' order, the keys' order
    consts, const_of = [], []
    vranks, undef_code = [], []
    for s, fi, args, holes, values, ps in ms:
        free_args = {p for p, _, g in holes if p >= 0 and g >= 0}
        row_c, row_v = [], []
        order = sorted(range(len(values)), key=lambda x: (values[x] is None, vkey(values[x])))
        vr = [0] * len(values)
        for r, x in enumerate(order):
            vr[x] = r
        und = next((x for x, v in enumerate(values) if v is None), -1)
        for x, v in enumerate(values):
            if v is None:
                row_c.append(None)
                continue
            vfree = any(p < 0 for p, _, _ in holes) and \
                sym.domains[next(d for p, d, _ in holes if p < 0)].free_ids.get(_vid(v)) is not None
            c = (fi, tuple(vkey(a) if i not in free_args else (-1,) for i, a in enumerate(args)),
                 (-1,) if vfree else vkey(v))
            row_c.append(c)
            consts.append(c)
        const_of.append(row_c)
        vranks.append(vr)
        undef_code.append(und)
        if und < 0:
            raise NativeRefused(f"a location of {gen.spec.functions[fi].name} has no undef code in the native layout")
    consts.sort()
    crank: dict = {}
    for c in consts:
        if c not in crank:
            crank[c] = len(crank)
    # keys in the order of Python's items (vkey of the key), over every slot
    keyorder = sorted(range(len(gen.slots)), key=lambda s: vkey(gen.slots[s]) if not (
        type(gen.slots[s]) is tuple and gen.slots[s] and gen.slots[s][0] == "map") else (99,))
    grank = [0] * len(gen.slots)
    for r, s in enumerate(keyorder):
        grank[s] = r
    m_of_slot = {s: m for m, (s, *_rest) in enumerate(ms)}
    # the renamed argument: slot + (index of the new element - index of the old) * stride
    fpidx, fp_off = [], {}
    h_p, h_dom, h_g, h_stride, h_fp, h_cur, m_hoff, m_h = [], [], [], [], [], [], [], []
    vmap, vinv, m_vmap, m_vinv = [], [], [], []
    for m, (s, fi, args, holes, values, ps) in enumerate(ms):
        m_hoff.append(len(h_p))
        m_h.append(len(holes))
        base_info = gen.fn_base.get(fi)
        vh = None
        for p, d, g in holes:
            sd = sym.domains[d]
            h_p.append(p)
            h_dom.append(d)
            h_g.append(g)
            if p >= 0:
                if base_info is None:
                    raise NativeRefused(f"{gen.spec.functions[fi].name} has no regular layout")
                arg_values = base_info[1]
                stride = 1
                for vals in arg_values[p + 1:]:
                    stride *= len(vals)
                key = (fi, p)
                if key not in fp_off:
                    fp_off[key] = len(fpidx)
                    for e in sd.free:
                        fpidx.append(next(i for i, a in enumerate(arg_values[p]) if _vid(a) == _vid(e)))
                cur = next(i for i, a in enumerate(arg_values[p]) if _vid(a) == _vid(args[p]))
                h_stride.append(stride)
                h_fp.append(fp_off[key])
                h_cur.append(cur)
                if g >= 0:
                    for j, e in enumerate(sd.free):
                        t = gen.slot_of.get((fi, args[:p] + (e,) + args[p + 1:]))
                        if t != s + (fpidx[fp_off[key] + j] - cur) * stride:
                            raise NativeRefused(f"{gen.spec.functions[fi].name}'s slots are not laid out by their "
                                                f"arguments")
            else:
                vh = sd
                h_stride.append(0)
                h_fp.append(0)
                h_cur.append(0)
        if vh is not None:
            per_code = [-1 if v is None else vh.free_ids.get(_vid(v), -1) for v in values]
            inv = [-1] * len(vh.free)
            for x, i in enumerate(per_code):
                if i >= 0 and inv[i] < 0:
                    inv[i] = x
            if any(x < 0 for x in inv):
                raise NativeRefused(f"a location of {gen.spec.functions[fi].name} cannot hold every element of "
                                    f"{vh.name} in the native layout")
            m_vmap.append(len(vmap))
            vmap.extend(-1 if i < 0 else vh.offset + i for i in per_code)
            m_vinv.append(len(vinv))
            vinv.extend(inv)
        else:
            m_vmap.append(-1)
            m_vinv.append(-1)
    # every renamed location is one of them (a location whose holes hold no free element keeps its place)
    for m, (s, fi, args, holes, values, ps) in enumerate(ms):
        for p, d, g in holes:
            if p >= 0 and g >= 0:
                for e in sym.domains[d].free:
                    t = gen.slot_of.get((fi, args[:p] + (e,) + args[p + 1:]))
                    if t not in m_of_slot:
                        raise NativeRefused(f"{gen.spec.functions[fi].name}'s renamed locations are not all slots")
    m_const, m_vrank, consts_flat, vr_flat = [], [], [], []
    for m in range(len(ms)):
        m_const.append(len(consts_flat))
        consts_flat.extend(-1 if c is None else crank[c] for c in const_of[m])
        m_vrank.append(len(vr_flat))
        vr_flat.extend(vranks[m])
    korder = sorted(range(len(ms)), key=lambda m: grank[ms[m][0]])
    others = [s for s in range(len(gen.slots)) if s not in m_of_slot and not gen.local_slot(gen.slots[s])]

    def arr(ctype, name, xs):
        return f"static const {ctype} {name}[] = {{{', '.join(str(int(x)) for x in xs) or '0'}}};"
    hmax = max(m_h, default=1)
    maxd = max((len(sd.free) for sd in sym.domains), default=1)
    out = [f"#define SYM_N {sym._n}", f"#define SYM_ND {len(sym.domains)}", f"#define SYM_MAXD {maxd}",
           f"#define SYM_NMS {len(ms)}", f"#define SYM_HMAX {hmax}", f"#define SYM_NH {len(h_p)}",
           f"#define SYM_MAXNUM {NATIVE_MAX_NUMBERINGS}", f"#define SYM_NOTHER {len(others)}",
           arr("int", "SYM_DOFF", [sd.offset for sd in sym.domains]),
           arr("int", "SYM_DLEN", [len(sd.free) for sd in sym.domains]),
           arr("int", "SYM_MS_SLOT", [x[0] for x in ms]), arr("int", "SYM_MS_HOFF", m_hoff), arr("int", "SYM_MS_H", m_h),
           arr("int", "SYM_MS_CONST", m_const), arr("int32_t", "SYM_CONST", consts_flat),
           arr("int", "SYM_MS_VRANK", m_vrank), arr("int32_t", "SYM_VRANKS", vr_flat),
           arr("int", "SYM_MS_UNDEF", undef_code), arr("int", "SYM_MS_VMAP", m_vmap), arr("int32_t", "SYM_VMAPS", vmap),
           arr("int", "SYM_MS_VINV", m_vinv), arr("int32_t", "SYM_VINVS", vinv),
           arr("int", "SYM_H_P", h_p), arr("int", "SYM_H_G", h_g), arr("int64_t", "SYM_H_STRIDE", h_stride),
           arr("int", "SYM_H_FP", h_fp), arr("int", "SYM_H_CUR", h_cur), arr("int", "SYM_FPIDX", fpidx),
           arr("int", "SYM_KORDER", korder), arr("int", "SYM_MS_GRANK", [grank[x[0]] for x in ms]),
           arr("int", "SYM_OTHER", others), arr("int", "SYM_OTHER_GRANK", [grank[s] for s in others]),
           f"#define SYM_NMSLOT {len(gen.slots) or 1}",
           arr("int", "SYM_M_OF_SLOT", [m_of_slot.get(s, -1) for s in range(len(gen.slots))])]
    return "\n".join(out) + "\n"



def native_tables(sym: Symmetry, gen) -> str:
    """The C tables of native_sym.c for the native engine's layout (``gen``: its Generator, after
    the layout and the slots' bits are made), from the Python canonical form's own location keys
    and signature entries (so both give the same representative).  NativeRefused when a location
    of a symmetric domain is not a narrow slot of the layout."""
    why = native_reason(sym)
    if why:
        raise NativeRefused(why)
    if sym.multi:
        text = native_multi_tables(sym, gen)
        return "#define SYM_MULTI 1\n" + text + _key_words(gen, _slots_of(text, "SYM_MS_SLOT"))
    for fi in sym.positions:
        if fi in getattr(gen, "map_slot", {}):
            f = gen.spec.functions[fi]
            raise NativeRefused(f"{f.name}'s locations are one map value in the native layout")
    dom_no = {id(sd): i for i, sd in enumerate(sym.domains)}
    rows: dict = {}          # prefix -> [domain number, {free index: slot}, per code rank entries]
    vals: list = []          # (slot, domain number, prefix, per code: free index or -1)
    entries: list = []
    for s, key in enumerate(gen.slots):
        if type(key) is tuple and key and key[0] == "map":
            continue
        try:
            info = sym._info(key)
        except (TypeError, IndexError, KeyError):
            continue
        if info is None:
            continue
        p, sd = info[0], info[1]
        f = gen.spec.functions[key if type(key) is int else key[0]]
        codes = gen.slot_values[s]
        if codes is None and p >= 0 and gen.bits[s] == 64 and T.root(f.codomain) in (T.INTEGER, T.NATURAL) \
                and not gen.any_typed(f.codomain):
            # an Integer location (its word is the integer, or undef): its entries are ordered by
            # (the row's place, the integer), as Python orders (prefix, 2, (2, n))
            row = rows.get(info[3])
            if row is None:
                row = rows[info[3]] = [dom_no[id(sd)], {}, None, (info[3], 2, (2,))]
                entries.append(row[3])
            elif row[3] is None:
                raise NativeRefused(f"{f.name} over {sd.name} has narrow and wide locations")
            row[1][info[2] - sd.offset] = s
            continue
        if codes is None or gen.bits[s] >= 32:
            raise NativeRefused(f"{f.name} over {sd.name} holds values of {f.codomain}, which the native canonical "
                                f"form does not order")
        ncodes = 1 << gen.bits[s]
        values = [codes[x] if x < len(codes) else None for x in range(ncodes)]
        if p >= 0:
            row = rows.get(info[3])
            if row is None:
                row = rows[info[3]] = [dom_no[id(sd)], {}, None, None]
                row[2] = [None if v is None else sym._entry(info, v)[1] for v in values]
            elif row[3] is not None:
                raise NativeRefused(f"{f.name} over {sd.name} has narrow and wide locations")
            row[1][info[2] - sd.offset] = s
            for e in row[2]:
                if e is not None:
                    entries.append(e)
        else:
            ent = (info[3], 0, 0)
            entries.append(ent)
            vals.append((s, dom_no[id(sd)], ent, [-1 if v is None else sd.free_ids.get(_vid(v), -1)
                                                   for v in values]))
    entries.sort()
    rank: list = []
    for e in entries:
        if not rank or rank[-1][0] != e:
            rank.append((e, len(rank)))

    def rank_of(e) -> int:
        lo, hi = 0, len(rank)
        while lo < hi:
            mid = (lo + hi) // 2
            if rank[mid][0] < e:
                lo = mid + 1
            else:
                hi = mid
        return rank[lo][1]
    rslots, rranks, row_dom, row_slot, row_rank, row_wide = [], [], [], [], [], []
    for prefix in sorted(rows):
        d, by_el, ents, wide = rows[prefix]
        row_wide.append(-1 if wide is None else rank_of(wide))
        n = len(sym.domains[d].free)
        if len(by_el) != n:
            f = gen.spec.functions[prefix[0]]
            raise NativeRefused(f"not every location of {f.name} over {sym.domains[d].name} is a slot of the "
                                f"native layout")
        row_dom.append(d)
        row_slot.append(len(rslots))
        rslots.extend(by_el[i] for i in range(n))
        row_rank.append(len(rranks))
        if ents is not None:
            rranks.extend(-1 if e is None else rank_of(e) for e in ents)
    vmap, vinv, val_slot, val_dom, val_rank, val_map, val_inv = [], [], [], [], [], [], []
    seen: dict = {}
    for s, d, ent, per_code in vals:
        n = len(sym.domains[d].free)
        inv = [-1] * n
        for x, i in enumerate(per_code):
            if i >= 0 and inv[i] < 0:
                inv[i] = x
        if any(x < 0 for x in inv):
            f = gen.spec.functions[gen.slots[s] if type(gen.slots[s]) is int else gen.slots[s][0]]
            raise NativeRefused(f"a location of {f.name} cannot hold every element of {sym.domains[d].name} "
                                f"in the native layout")
        key = (tuple(per_code), tuple(inv))
        if key not in seen:
            seen[key] = (len(vmap), len(vinv))
            vmap.extend(per_code)
            vinv.extend(inv)
        val_slot.append(s)
        val_dom.append(d)
        val_rank.append(rank_of(ent))
        val_map.append(seen[key][0])
        val_inv.append(seen[key][1])

    # the rows and value slots in the order of their entries' prefixes: an element's entries come
    # out of them in ascending order; when an element has at most ke entries of kb bits each (its
    # rank + 1), its signature is one 64-bit number (entries from the top, 0 where none is left)
    srcs = sorted([(prefix, r) for r, prefix in enumerate(sorted(rows))] +
                  [(vals[v][2][0], len(row_dom) + v) for v in range(len(vals))])
    per_dom = [0] * len(sym.domains)
    for d in row_dom + val_dom:
        per_dom[d] += 1
    ke = max(per_dom, default=0)
    kb = max(len(rank), 1).bit_length()
    fast = 1 if NATIVE_FAST and 0 < ke and ke * kb <= 64 and all(x < 0 for x in row_wide) else 0

    def arr(ctype, name, xs):
        return f"static const {ctype} {name}[] = {{{', '.join(str(int(x)) for x in xs) or '0'}}};"
    nent = len(rslots) + len(val_slot)
    maxd = max((len(sd.free) for sd in sym.domains), default=1)
    out = [f"#define SYM_N {sym._n}", f"#define SYM_ND {len(sym.domains)}", f"#define SYM_NROW {len(row_dom)}",
           f"#define SYM_NVAL {len(val_slot)}", f"#define SYM_NENT {nent}", f"#define SYM_MAXD {maxd}",
           arr("int", "SYM_DOFF", [sd.offset for sd in sym.domains]),
           arr("int", "SYM_DLEN", [len(sd.free) for sd in sym.domains]),
           arr("int", "SYM_ROW_DOM", row_dom), arr("int", "SYM_ROW_SLOT", row_slot),
           arr("int", "SYM_ROW_RANK", row_rank), arr("int", "SYM_RSLOTS", rslots),
           arr("int32_t", "SYM_ROW_WIDE", row_wide),
           arr("int32_t", "SYM_RRANK", rranks),
           arr("int", "SYM_VAL_SLOT", val_slot), arr("int", "SYM_VAL_DOM", val_dom),
           arr("int32_t", "SYM_VAL_RANK", val_rank), arr("int", "SYM_VAL_MAP", val_map),
           arr("int", "SYM_VAL_INV", val_inv), arr("int32_t", "SYM_VMAP", vmap), arr("int32_t", "SYM_VINV", vinv),
           f"#define SYM_FAST {fast}", f"#define SYM_KE {ke}", f"#define SYM_KB {kb}", f"#define SYM_NSRC {len(srcs)}",
           arr("int", "SYM_SRC", [x for _, x in srcs])]
    return "\n".join(out) + "\n" + _key_words(gen, rslots + val_slot)


def _slots_of(text: str, name: str) -> list:
    """The numbers of the C table ``name`` in ``text``."""
    line = next(ln for ln in text.splitlines() if f" {name}[]" in ln)
    body = line.split("{", 1)[1].rsplit("}", 1)[0]
    return [int(x) for x in body.split(",") if x.strip()]


def _key_words(gen, slots) -> str:
    """SYM_NKW, SYM_KW, SYM_KMASK: the words (and their bits) that hold the locations the canonical
    form reads: a successor equal to its (canonical) state there is canonical already."""
    masks: dict = {}
    for sl in set(slots):
        b = gen.bits[sl]
        m = (1 << 64) - 1 if b == 64 else ((1 << b) - 1) << gen.shifts[sl]
        masks[gen.words[sl]] = masks.get(gen.words[sl], 0) | m
    kw = sorted(masks)
    return "\n".join([f"#define SYM_NKW {len(kw)}",
                      f"static const int SYM_KW[] = {{{', '.join(map(str, kw)) or '0'}}};",
                      f"static const uint64_t SYM_KMASK[] = {{{', '.join(f'{masks[x]}ULL' for x in kw) or '0'}}};"]) + "\n"


def _renamed(v, ren: dict):
    """``v`` (a choice's value: bindings, tuples, elements) with the elements renamed by ``ren``
    (value id -> element)."""
    if isinstance(v, dict):
        return tuple((k, _renamed(x, ren)) for k, x in v.items())
    if type(v) is tuple or type(v) is list:
        return tuple(_renamed(x, ren) for x in v)
    try:
        got = ren.get(_vid(v), v)
    except TypeError:
        return v
    return vkey(got) if got is not None else None


class _ChoiceTypes:
    """Which parts of a step's choices hold elements of the symmetric ``domains``, from the types
    the spec declares: a choose rule's variables (by the rule's label, "choose at <place>"), a
    monitored function's codomain and argument positions (by the location's text).  An Integer
    that a monitored function or a variable over Integer takes is not an element of a subset of
    Integer, even when it is equal to one, and is not renamed."""

    def __init__(self, machine, domains: list):
        self.machine = machine
        self.domains = domains
        self.choose: dict = {}       # label -> {variable name: holds elements}
        self.functions = {f.name: f for f in machine.spec.functions}
        for x in ir_nodes(machine.spec.rules):
            if isinstance(x, ir.Choose):
                self.choose[f"choose at {x.span.short()}"] = {v.name: self.holds(v.type) for v, _ in x.bindings}

    def holds(self, t) -> bool:
        """Whether a value of type ``t`` may hold an element of the symmetric domains (unknown
        types: yes)."""
        if isinstance(t, T.Domain):
            return t.kind == "any" or any(is_subdomain(t, d) for d in self.domains)
        if isinstance(t, T.Struct):
            return any(self.holds(a) for a in t.args)
        return True

    def read(self, c) -> bool:
        """Whether the value a monitored choice ``c`` read may hold elements."""
        f = self.functions.get(c.label.split("(", 1)[0])
        return True if f is None else self.holds(f.codomain)

    def binding(self, c, name: str) -> bool:
        got = self.choose.get(c.label)
        return True if got is None else got.get(name, True)

    def label(self, c, ren: dict) -> str:
        """A monitored location's text with the elements among its arguments renamed."""
        if c.kind != "monitored" or "(" not in c.label or not ren:
            return c.label
        name, rest = c.label.split("(", 1)
        f = self.functions.get(name)
        if f is None or not rest.endswith(")"):
            return c.label
        args = _split_args(rest[:-1])
        if len(args) != len(f.domain):
            return c.label
        texts = {show(a): show(b) for (_, a), b in ren.items()}
        out = [texts.get(a, a) if self.holds(d) else a for a, d in zip(args, f.domain)]
        return f"{name}({','.join(out)})"


def _split_args(text: str) -> list:
    """The top-level comma-separated parts of ``text`` (brackets nest)."""
    out, depth, cur = [], 0, []
    for ch in text:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            out.append("".join(cur))
            cur = []
        else:
            cur.append(ch)
    out.append("".join(cur))
    return out


def _choice_keys(choices, ren: dict, typed: _ChoiceTypes) -> tuple:
    """The choices of a step, compared up to the renaming ``ren``: kind, place, value, nested.
    Only the values and arguments whose declared types (``typed``) may hold elements of the
    symmetric domains are renamed (an Integer equal to an element of a subset of Integer is not
    one)."""
    out = []
    for c in choices:
        if c.kind == "monitored":
            v = _renamed(c.value, ren if typed.read(c) else {})
        elif isinstance(c.value, dict):
            v = tuple((k, _renamed(x, ren if typed.binding(c, k) else {})) for k, x in c.value.items())
        else:
            v = _renamed(c.value, ren)
        out.append((c.kind, typed.label(c, ren), v, _choice_keys(c.nested or (), ren, typed)))
    return tuple(out)


def _numberings(choices):
    """Every renaming (element -> element, the moving ones) that numbers each domain's elements
    group by group, the groups in their order and the elements of a group in any order."""
    per_domain = []
    for sd, groups in choices:
        options = [[]]
        for grp in groups:
            options = [o + list(q) for o in options for q in permutations(grp)]
        per_domain.append((sd, options))
    out = [{}]
    for sd, options in per_domain:
        nxt = []
        for base in out:
            for order in options:
                perm = dict(base)
                for j, i in enumerate(order):
                    if i != j:
                        perm[sd.free[i]] = sd.free[j]
                nxt.append(perm)
        out = nxt
    return out


def _and(parts: list) -> str:
    if len(parts) <= 1:
        return "".join(parts)
    return ", ".join(parts[:-1]) + " and " + parts[-1]


# -------------------------------------------------------------------- detection
class _Refused(Exception):
    pass


def _contains(t, cands) -> list:
    """The candidate domains inside the structured type ``t``."""
    out = []
    stack = [t]
    while stack:
        x = stack.pop()
        if isinstance(x, T.Struct):
            stack.extend(x.args)
        elif x in cands and x not in out:
            out.append(x)
    return out


class _Uses:
    """Walks the spec and its properties: the literals, and the first use of each candidate
    domain's values that could tell its elements apart."""

    def __init__(self, cands: dict, path: str = ""):
        self.cands = cands              # Domain -> set of value ids
        self.path = path                # the spec's file (places in others are named with their file)
        self.why: dict = {}             # Domain -> reason
        self.named: dict = {d: [] for d in cands}
        self.seen: set = set()

    # -- helpers
    def refuse(self, d, reason: str, span=None) -> None:
        if d in self.why:
            return
        where = ""
        if span is not None and getattr(span, "line", 0):
            other = getattr(span, "path", "") or ""
            if other and self.path and os.path.abspath(other) != os.path.abspath(self.path):
                where = f" ({os.path.basename(other)}, line {span.line}, column {span.col})"
            else:
                where = f" (line {span.line}, column {span.col})"
        self.why[d] = reason + where

    def cand(self, t):
        return t if t in self.cands else None

    def literal(self, v) -> None:
        if type(v) is bool or v is None:
            return
        for d, ids in self.cands.items():
            if _vid(v) in ids and not any(_vid(x) == _vid(v) for x in self.named[d]):
                self.named[d].append(v)

    # -- terms
    def term(self, t, ctx, what: str) -> None:
        """``t`` appears where a value of ``ctx`` (a candidate domain, or None: any other type)
        is expected; ``what`` says where, for the reasons."""
        if t is None:
            return
        typ = getattr(t, "type", None)
        d = self.cand(typ)
        if isinstance(t, ir.Const):
            self.literal(t.value)
            if d is not None and ctx is not d:
                self.refuse(d, f"a value of {d.name} is {what}", t.span)
            return
        if d is not None and ctx is not d:
            self.refuse(d, f"a value of {d.name} is {what}", t.span)
        if ctx is not None and d is None:
            self.refuse(ctx, f"a value of {typ} is used where {ctx.name} is expected ({what})", t.span)
        if isinstance(typ, T.Struct):
            for c in _contains(typ, self.cands):
                self.refuse(c, f"a value of {typ} holds elements of {c.name} ({what})", t.span)
        if isinstance(t, ir.Loc):
            f = t.func
            if f.kind == "static" and not t.args and abstract_codomain(f):
                # a static constant of an abstract domain names its element
                self.literal(abstract_value(f.codomain.name, f.name))
            for i, a in enumerate(t.args):
                dt = f.domain[i] if i < len(f.domain) else None
                self.term(a, self.cand(dt), f"an argument of {f.name}")
        elif isinstance(t, ir.Call):
            self.call(t)
        elif isinstance(t, (ir.Temporal, ir.StepOp)):
            for a in t.args:
                self.term(a, None, f"an argument of {t.op}")
        elif isinstance(t, ir.DomainTerm):
            c = self.cand(t.domain)
            if c is not None:
                self.refuse(c, f"the domain {c.name} is used as a value", t.span)
        elif isinstance(t, ir.Cond):
            self.term(t.cond, None, "a condition")
            self.term(t.then, self.cand(typ), "a branch of a conditional term")
            self.term(t.other, self.cand(typ), "a branch of a conditional term")
        elif isinstance(t, ir.Switch):
            ds = self.cand(t.subject.type)
            self.term(t.subject, ds, "the subject of a switch")
            for c, r in t.cases:
                self.term(c, ds, "a case of a switch")
                self.term(r, self.cand(typ), "a result of a switch")
            self.term(t.other, self.cand(typ), "a result of a switch")
        elif isinstance(t, ir.Let):
            self.around_temporal(t.bindings, (t.body,), t.span)
            for v, x in t.bindings:
                self.term(x, self.cand(v.type), f"bound to {v.name}")
            self.term(t.body, self.cand(typ), "the result of a let")
        elif isinstance(t, ir.Quant):
            self.bindings(t.bindings)
            self.around_temporal(t.bindings, (t.guard,), t.span)
            self.term(t.guard, None, "a guard")
        elif isinstance(t, ir.Compr):
            for v, rng in t.bindings:
                for c in self._ranges(v, rng):
                    self.refuse(c, f"a comprehension ranges over {c.name}", t.span)
            self.bindings(t.bindings)
            self.term(t.guard, None, "a guard")
            self.term(t.body, self.cand(t.body.type), "the body of a comprehension")
        elif isinstance(t, ir.Collection):
            for x in t.items:
                self.term(x, self.cand(x.type), "an item of a collection")
        elif isinstance(t, ir.Range):
            for x in (t.start, t.end, t.step):
                self.term(x, None, "a bound of a range")
        elif isinstance(t, ir.MapLit):
            for a, b in t.pairs:
                self.term(a, self.cand(a.type), "a key of a map")
                self.term(b, self.cand(b.type), "a value of a map")
        elif isinstance(t, ir.TupleLit):
            for x in t.items:
                self.term(x, self.cand(x.type), "an item of a tuple")
        elif isinstance(t, ir.RuleRef):
            self.rule_decl(t.rule)
        elif isinstance(t, (ir.VarRef,)):
            pass
        elif isinstance(t, ir.Term):
            # a term this walk does not know: every candidate it may touch is refused
            for c in list(self.cands):
                self.refuse(c, f"a {type(t).__name__} term is not analysed", t.span)

    def _ranges(self, v, rng) -> list:
        out = []
        if isinstance(rng, ir.DomainTerm) and self.cand(rng.domain) is not None:
            out.append(rng.domain)
        if self.cand(v.type) is not None and v.type not in out:
            out.append(v.type)
        return out

    def around_temporal(self, bindings, parts, span) -> None:
        """A variable of a candidate domain bound around a temporal operator: the property is
        checked once per element, each time with atoms that name that element."""
        doms = [c for v, rng in bindings for c in self._ranges(v, rng)]
        if doms and any(_has_temporal(x) for x in parts):
            for c in doms:
                self.refuse(c, f"a property binds a variable of {c.name} around a temporal operator", span)

    def bindings(self, bindings) -> None:
        for v, rng in bindings:
            dv = self.cand(v.type)
            if isinstance(rng, ir.DomainTerm):
                dr = self.cand(rng.domain)
                if dr is not None or dv is not None:
                    if dr is not dv:
                        c = dr or dv
                        self.refuse(c, f"{v.name} of {v.type} ranges over {rng.domain}", rng.span)
                continue
            if dv is not None:
                self.refuse(dv, f"{v.name} ranges over a part of {dv.name}", rng.span)
            self.term(rng, None, f"the range of {v.name}")

    def call(self, t) -> None:
        name = t.name
        if name in ("eq", "neq") and len(t.args) == 2:
            ds = [self.cand(a.type) for a in t.args]
            d = ds[0] or ds[1]
            if d is not None:
                for a, da in zip(t.args, ds):
                    if da is d:
                        self.term(a, d, "compared")
                    elif isinstance(a, ir.Const):
                        self.literal(a.value)
                    else:
                        self.refuse(d, f"a value of {d.name} is compared with a value of {a.type}", t.span)
                        self.term(a, None, "compared")
                return
        if name in ("isDef", "isUndef") and len(t.args) == 1:
            a = t.args[0]
            self.term(a, self.cand(a.type), "tested for undef")
            return
        what = f"an argument of {t.op or name}"
        for a in t.args:
            self.term(a, None, what)

    # -- rules
    def rule_decl(self, r) -> None:
        if id(r) in self.seen:
            return
        self.seen.add(id(r))
        self.rule(r.body)

    def rule(self, r) -> None:
        if r is None:
            return
        if isinstance(r, ir.Skip):
            return
        if isinstance(r, ir.Update):
            f = r.func
            for i, a in enumerate(r.args):
                dt = f.domain[i] if i < len(f.domain) else None
                self.term(a, self.cand(dt), f"an argument of {f.name}")
            self.term(r.value, self.cand(f.codomain), f"stored in {f.name}")
        elif isinstance(r, ir.UpdateVar):
            self.term(r.value, self.cand(r.var.type), f"stored in {r.var.name}")
        elif isinstance(r, ir.Block):
            for x in r.rules:
                self.rule(x)
        elif isinstance(r, ir.If):
            self.term(r.cond, None, "a condition")
            self.rule(r.then)
            self.rule(r.other)
        elif isinstance(r, ir.SwitchRule):
            ds = self.cand(r.subject.type)
            self.term(r.subject, ds, "the subject of a switch")
            for c, x in r.cases:
                self.term(c, ds, "a case of a switch")
                self.rule(x)
            self.rule(r.other)
        elif isinstance(r, ir.LetRule):
            for v, x in r.bindings:
                self.term(x, self.cand(v.type), f"bound to {v.name}")
            self.rule(r.body)
        elif isinstance(r, ir.Choose):
            self.bindings(r.bindings)
            self.term(r.guard, None, "a guard")
            self.rule(r.body)
            self.rule(r.ifnone)
        elif isinstance(r, ir.Forall):
            self.bindings(r.bindings)
            self.term(r.guard, None, "a guard")
            self.rule(r.body)
        elif isinstance(r, ir.Extend):
            for c in list(self.cands):
                self.refuse(c, "the spec uses extend", r.span)
            self.rule(r.body)
        elif isinstance(r, ir.CallRule):
            params = r.rule.params
            for i, a in enumerate(r.args):
                pt = params[i].type if i < len(params) else None
                self.term(a, self.cand(pt), f"an argument of {r.rule.name}")
            self.rule_decl(r.rule)
        elif isinstance(r, ir.TurboReturn):
            self.rule(r.target)
            self.rule(r.call)
        elif isinstance(r, ir.TermCall):
            self.term(r.term, None, "a called rule value")
            for a in r.args:
                self.term(a, None, "an argument of a called rule value")
        elif isinstance(r, ir.Loop):
            self.term(r.cond, None, "a condition")
            self.rule(r.body)
        elif isinstance(r, ir.LocalRule):
            self.function(r.func)
            self.rule(r.init)
            self.rule(r.body)
        else:
            for c in list(self.cands):
                self.refuse(c, f"a {type(r).__name__} rule is not analysed", getattr(r, "span", None))

    def function(self, f) -> None:
        for dt in list(f.domain) + [f.codomain]:
            if isinstance(dt, T.Struct):
                for c in _contains(dt, self.cands):
                    self.refuse(c, f"{f.name} is declared over {dt}", f.span)
        if f.body is not None:
            for p in f.params or ():
                if isinstance(p.type, T.Struct):
                    for c in _contains(p.type, self.cands):
                        self.refuse(c, f"a parameter of {f.name} ranges over {p.type}", f.span)
            self.term(f.body, self.cand(f.codomain), f"the value of {f.name}")


def _has_temporal(t) -> bool:
    seen = set()
    stack = [t]
    while stack:
        x = stack.pop()
        if x is None or id(x) in seen:
            continue
        seen.add(id(x))
        if isinstance(x, (ir.Temporal, ir.StepOp)):
            return True
        if isinstance(x, ir.Term):
            stack.extend(vars(x).values())
        elif isinstance(x, (list, tuple)):
            stack.extend(x)
    return False


def _candidates(machine) -> tuple[dict, list]:
    """Candidate domains (Domain -> their values) and the lines for the domains left out."""
    spec = machine.spec
    out = {}
    lines = []
    doms = [d for d in spec.domains if isinstance(d, T.Domain)]
    for d in doms:
        if d.kind == "enum":
            vals = list(d.elements)
        elif d.kind == "subset" and T.root(d) in (T.INTEGER, T.NATURAL) and d.definition is not None \
                and not d.dynamic:
            try:
                vals = list(machine.domain_values(d, None, d.span))
            except Exception as exc:        # noqa: BLE001 - its elements cannot be listed: no symmetry
                lines.append(f"{d.name}: no symmetry: its elements cannot be listed ({exc})")
                continue
            if len(vals) > MAX_ELEMENTS:
                lines.append(f"{d.name}: no symmetry: {len(vals):,} elements (more than {MAX_ELEMENTS:,})")
                continue
        elif d.kind == "abstract" and not d.dynamic and not T.agent_like(d) and d is not T.AGENT:
            vals = list(spec.static_elements.get(d, []))
        else:
            continue
        subs = [e.name for e in doms if e.kind == "subset" and e.base is d]
        if subs:
            lines.append(f"{d.name}: no symmetry: {', '.join(subs)} is declared a subset of it")
            continue
        out[d] = vals
    return out, lines


def detect(machine, properties=()) -> Symmetry:
    """The interchangeable elements of ``machine``'s spec, given the ``properties`` checked
    (objects with a ``prop`` or ``body``: ir.Property or the checker's property objects) on
    top of the spec's own."""
    spec = machine.spec
    cands, lines = _candidates(machine)
    if not cands:
        return Symmetry([], lines or ["no enum, static abstract or finite Integer subset domain"],
                        "no enum, static abstract or finite Integer subset domain")
    uses = _Uses({d: {_vid(v) for v in vals} for d, vals in cands.items()}, getattr(spec, "path", "") or "")
    for f in list(spec.functions) + list(getattr(spec, "local_functions", []) or []):
        uses.function(f)
    for r in spec.rules:
        uses.rule_decl(r)
    if spec.main is not None:
        uses.rule_decl(spec.main)
    for init in spec.inits:
        for _dom, x in init.domains:
            uses.term(x, None, "the initial elements of a domain")
        for f, params, body, _span in init.functions:
            uses.term(body, uses.cand(f.codomain), f"the initial value of {f.name}")
        for a in init.agents:
            params = a.rule.params
            for i, x in enumerate(a.args):
                pt = params[i].type if i < len(params) else None
                uses.term(x, uses.cand(pt), f"an argument of {a.rule.name}")
            uses.rule_decl(a.rule)
    props = list(spec.properties)
    for p in properties:
        ip = getattr(p, "prop", None)
        if ip is None and getattr(p, "body", None) is not None:
            ip = p
        if ip is not None and ip not in props:
            props.append(ip)
    for p in props:
        what = f"in property {p.name}"
        uses.term(p.body, None, what)
        uses.term(getattr(p, "body2", None), None, what)
    # values given to monitored functions of a candidate domain are named
    ranges = getattr(machine, "monitored_ranges", {}) or {}
    for f in spec.functions:
        if f.kind == "monitored" and f.name in ranges and f.codomain in cands:
            for v in ranges[f.name]:
                uses.literal(v)
    # the domains left with interchangeable elements
    doms = {}
    for d, vals in cands.items():
        if d in uses.why:
            continue
        sd = SymmetricDomain(d, vals, sorted(uses.named[d], key=vkey))
        if len(sd.free) >= 2:
            doms[d] = sd
    # every stored function has at most one position over them (a domain whose elements share
    # a location with others is dropped, until none does)
    stored = [f for f in spec.functions if not (f.kind == "derived" or (f.kind == "static" and f.body is not None)
                                                or (f.kind == "static" and f.arity == 0 and abstract_codomain(f)))]
    while True:
        positions = {}
        multi = {}
        bad = None
        for f in stored:
            ps = [(i, dt) for i, dt in enumerate(f.domain) if dt in doms] + \
                 ([(-1, f.codomain)] if f.codomain in doms else [])
            if len(ps) == 1:
                positions[f.index] = (ps[0][0], doms[ps[0][1]])
            elif len(ps) > 1:
                multi[f.index] = [(i, doms[dt]) for i, dt in ps]
                big = list(dict.fromkeys(dt for _, dt in ps if math.factorial(len(doms[dt].free)) > MAX_RENAMINGS))
                if big:
                    bad = (f, ps, big)
                    break
        if bad is None:
            break
        f, ps, big = bad
        names = _and(sorted({dt.name for _, dt in ps}))
        for dt in big:
            n = len(doms[dt].free)
            uses.refuse(dt, f"{f.name} has several positions over {names}, and {dt.name} has {n} interchangeable "
                            f"elements (the exact canonical form of such a function tries up to {n}! renamings; "
                            f"at most {MAX_RENAMINGS:,} are tried)", f.span)
            doms.pop(dt, None)
    lines_out = list(lines)
    for d, vals in cands.items():
        if d in doms:
            sd = doms[d]
            named = sd.named
            shown = ", ".join(_show(v) for v in named[:12]) + (", ..." if len(named) > 12 else "")
            lines_out.append(f"{d.name}: {len(sd.free):,} of its {len(vals):,} elements are interchangeable"
                             + (f" (named: {shown})" if named else ""))
        elif d in uses.why:
            lines_out.append(f"{d.name}: no symmetry: {uses.why[d]}")
        else:
            free = len(vals) - len(uses.named[d])
            lines_out.append(f"{d.name}: no symmetry: " + (
                f"every one of its {len(vals):,} elements is named by a literal" if free <= 0 else
                f"only one of its {len(vals):,} elements is named by no literal"))
    found = list(doms.values())
    reason = "" if found else "no domain has interchangeable elements"
    return Symmetry(found, lines_out, reason, positions, multi)


def _show(v) -> str:
    return v.name if isinstance(v, EnumValue) else repr(v)
