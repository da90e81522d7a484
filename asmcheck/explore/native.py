"""The native explorer: C code generated from the IR, compiled once per model.

asmcheck writes a C translation of the step function, of the invariants, step properties and
INVAR constraints (from the IR only: no text of the spec is ever pasted into the C source;
strings and other composite constants go into a table of numbers), compiles it (see
:mod:`.native_build`, cached by the hash of the source) and runs the breadth-first search there.

A state is a few 64-bit words: a location over a small finite domain (Booleans, enums, finite
integer subdomains, the named elements of abstract domains) is a bit field; an Integer location
holds its value (64 bits, wrapping like Java's long); a sequence, tuple, set or string is the
number of its entry in a value table where equal values are interned once.  The rules translated:
par, seq, if, switch, let, forall, choose, while/iterate, macro calls (an argument the Python
engine passes by name is substituted into the body written in place), turbo calls and their
return values, rules called through rule values, agents' programs (``program($a)`` and ``self``).
A choose or forall over a set computed in the state meets its elements in the Python engine's
order (a generated comparison sorts them as ``vkey`` does).  Reads inside a seq block see the working state; update sets are
composed as the Python step function composes them (a clash is a run-time error).

The same enumeration of choices as the Python step function is used, so states are discovered in
the same order; a run-time error of a step becomes the pseudo property ``error`` with the Python
step function's message; every trace the native search reports is decoded and *replayed through
the Python step function* before it is shown.  The search runs in slices of a quarter second, so
progress is shown, Ctrl-C is answered and an Integer location that grows level after level is
named while it runs.

Anything outside that subset raises :class:`Unsupported` (with the reason) and the Python
explorer runs instead.

It is one module of some 1,300 lines because the generator (IR -> C), the codec between Python
values and the C encoding (which the generator fixes while it writes the code) and the explorer
that packs, decodes and replays states share one layout; split, each part would reach into the
others' tables.
"""
from __future__ import annotations

import copy
import ctypes
import math
import os
import re
import struct
import time
from array import array
from importlib import resources

from ..errors import AsmError, AsmRuntimeError, UsageError
from ..semantics import ir
from ..semantics import types as T
from ..semantics.machine import Machine, Undetermined
from ..semantics.state import is_dom_key, same_value
from ..semantics.values import AbstractValue, BagV, EnumValue, MapV, RuleValue, SeqV, SetV, fresh_value
from . import native_build
from .native_build import Unsupported

UNDEF_C = "UNDEF"
UNDEF_V = -(1 << 63)
MASK64 = (1 << 64) - 1
MAX_CANDIDATES = 1 << 16
LOCAL_SLOTS = 64        # a local function has slots when it has at most that many locations (else a map)
MAX_RECURSION = 1000      # nested calls of derived functions (each rule call too) in the C code, at most
MAX_SLOTS = 1 << 18       # locations laid out, at most (200,000 compile in about 6 s)
CN_K = 16              # element slots per domain extended at run time, at first (native_canon.c)
CN_K_MAX = 256         # ... and at most: a search that needs more slots starts again with twice as many
CN_FRESH = 2 << 40     # the code of element k of extended domain d: CN_FRESH + (d << 24) + k
RULE_BASE = 1 << 48       # the code of a rule value: RULE_BASE + its number (apart from elements, 2^40...)
K_BAG = 10               # value table kinds of bags and map values (native_rt.c)
K_MAPV = 11


def _ceil_log2(n: int) -> int:
    b = 0
    while (1 << b) < n:
        b += 1
    return max(b, 1)


K_ANY = 16                         # a value in a location of type Any: (kind, code), interned
R_NAN = 0x7FF8000000000000
R_NEGZ = 0x7FF8000000000001


def real_code(x: float) -> int:
    """The int64 code of a Real (a Java double): its bit pattern, one code for every NaN and
    one for -0.0 (whose pattern is the undef sentinel)."""
    if x != x:
        return R_NAN
    if x == 0 and math.copysign(1.0, x) < 0:
        return R_NEGZ
    b = struct.unpack("<q", struct.pack("<d", x))[0]
    return b


def real_value(b: int) -> float:
    if b == R_NEGZ:
        return -0.0
    return struct.unpack("<d", struct.pack("<q", b))[0]


def storable_real(x) -> bool:
    """A Real the native states may hold: the Python engine's states compare floats with ``==``
    (-0.0 equals 0.0, a NaN only itself), the native ones by code."""
    return type(x) is float and x == x and not (x == 0 and math.copysign(1.0, x) < 0)


class Codec:
    """Python values <-> the int64 values of the generated code."""

    def __init__(self, machine: Machine):
        self.m = machine
        self.abstract_ids: dict = {}
        for d in sorted(machine.static_elements, key=lambda d: d.name):
            for e in machine.static_elements[d]:
                if e not in self.abstract_ids:
                    self.abstract_ids[e] = len(self.abstract_ids)
        self.abstract_by_id = {i: e for e, i in self.abstract_ids.items()}
        self.enum_base: dict = {}
        self.comp: list = []             # composite values met while generating: (kind, element codes)
        self.comp_ids: dict = {}
        self.frozen = False
        self.dll = None
        self.dyn: dict = {}              # dynamic domain extended by the spec -> its number
        self.cn_k = CN_K                 # element slots per extended domain
        self.rule_ids: dict = {}         # rule declaration -> number (rule values <<r>>)
        self.rule_by_id: list = []
        self.any_tags: list = []         # the kinds of value held in locations of type Any: (key, decoding type)
        self.any_tag_ids: dict = {}

    def to_c(self, v) -> int | None:
        """The int64 for a value (None for undef)."""
        if v is None:
            return None
        t = type(v)
        if t is bool:
            return int(v)
        if t is int:
            if not (-(1 << 63) < v < (1 << 63)):
                raise Unsupported("an integer beyond 64 bits")
            return v
        if t is float:
            return real_code(v)
        if t is EnumValue:
            # distinct enum domains get distinct codes (a union or Any mixes them)
            base = self.enum_base.get(v.domain)
            if base is None:
                base = self.enum_base[v.domain] = len(self.enum_base) << 20
            return base + v.index
        if t is RuleValue:
            # a rule value with no agent bound to it: a number of its own (RULE_BASE + k)
            if v.agent is not None or v.args:
                raise Unsupported("a rule value bound to an agent")
            k = self.rule_ids.get(v.rule)
            if k is None:
                if self.frozen:
                    raise Unsupported("a rule value met after the code was generated")
                k = self.rule_ids[v.rule] = len(self.rule_by_id)
                self.rule_by_id.append(v.rule)
            return RULE_BASE + k
        if t is AbstractValue:
            if v.serial > 0 and v.domain in self.dyn:
                # an element made by extend: see native_canon.c
                if v.serial > self.cn_k:
                    raise Unsupported(f"more than {self.cn_k} elements of {v.domain} made by extend")
                return CN_FRESH + (self.dyn[v.domain] << 24) + v.serial
            if v not in self.abstract_ids:
                raise Unsupported(f"the element {v.name} is not a named element of its domain")
            return (1 << 40) + self.abstract_ids[v]
        if t is SeqV or t is tuple or t is str or t is SetV:
            kind = {SeqV: 1, tuple: 2, str: 3, SetV: 4}[t]
            if t is str:
                codes = tuple(ord(ch) for ch in v)
            else:
                if any(type(e) is float and not storable_real(e) for e in v):
                    raise Unsupported("-0.0 or NaN inside a composite value")
                codes = tuple(UNDEF_V if x is None else x for x in (self.to_c(e) for e in v))
                if t is SetV:
                    codes = tuple(sorted(set(codes)))
            key = (kind, codes)
            i = self.comp_ids.get(key)
            if i is None:
                if self.frozen:
                    return self.found(key)
                i = self.comp_ids[key] = len(self.comp)
                self.comp.append(key)
            return i
        if t is BagV or t is MapV:
            return self.bag_map_code(v)
        raise Unsupported(f"a value of kind {t.__name__}")

    def bag_map_code(self, v) -> int:
        """A bag (its element codes sorted, repetitions kept) or a map value (its (key, value)
        code pairs sorted by key code, an undef value kept) as an entry of the value table."""
        def code(e):
            x = self.to_c(e)
            return UNDEF_V if x is None else x
        if type(v) is BagV:
            key = (K_BAG, tuple(sorted(code(e) for e in v)))
        else:
            pairs = sorted((code(k), code(x)) for k, x in v)
            key = (K_MAPV, tuple(x for pr in pairs for x in pr))
        return self.intern(key)

    def from_c(self, x: int, typ):
        """The Python value of the int64 ``x`` of static type ``typ``."""
        if x == UNDEF_V:
            return None
        r = T.root(typ)
        if isinstance(r, T.Domain) and r.kind == "any":
            kind, (tag, code) = self.fetch(x)
            return self.from_c(code, self.any_tags[tag][1])
        if r is T.BOOLEAN:
            return bool(x)
        if r in (T.INTEGER, T.NATURAL):
            return x
        if r is T.REAL:
            return real_value(x)
        if r is T.STRING:
            return "".join(chr(e) for e in self.fetch(x)[1])
        if isinstance(r, T.Struct) and r.kind in ("Bag", "Map"):
            kind, elems = self.fetch(x)
            if r.kind == "Bag":
                return BagV.of(self.from_c(e, r.args[0]) for e in elems)
            return MapV.of((self.from_c(elems[i], r.args[0]), self.from_c(elems[i + 1], r.args[1]))
                           for i in range(0, len(elems), 2))
        if isinstance(r, T.Struct) and r.kind in ("Seq", "Prod", "Powerset"):
            key = self.fetch(x)
            kind, elems = key
            if r.kind == "Seq":
                return SeqV(self.from_c(e, r.args[0]) for e in elems)
            if r.kind == "Powerset":
                return SetV(self.from_c(e, r.args[0]) for e in elems)
            return tuple(self.from_c(e, a) for e, a in zip(elems, r.args))
        if CN_FRESH <= x < CN_FRESH + (len(self.dyn) << 24):
            name = sorted(self.dyn)[(x - CN_FRESH) >> 24]
            return fresh_value(name, (x - CN_FRESH) & 0xffffff)
        if isinstance(r, T.Struct) and r.kind == "Rule":
            if RULE_BASE <= x < RULE_BASE + len(self.rule_by_id):
                return RuleValue(self.rule_by_id[x - RULE_BASE])
            raise Unsupported(f"a value of type {typ} that the native search cannot decode")
        if x >= 1 << 40:
            return self.abstract_by_id[x - (1 << 40)]
        if isinstance(r, T.Domain) and r.kind == "enum":
            for e in r.elements:
                if self.to_c(e) == x:
                    return e
        raise Unsupported(f"a value of type {typ} that the native search cannot decode")

    # -------------------------------------------------------------- values of type Any
    def any_tag_key(self, typ):
        """The kind of value of static type ``typ`` in a location of type Any (None: not held)."""
        r = T.root(typ)
        if r is T.BOOLEAN:
            return ("bool",), T.BOOLEAN
        if r in (T.INTEGER, T.NATURAL):
            return ("int",), T.INTEGER
        if r is T.REAL:
            return ("real",), T.REAL
        if r is T.STRING:
            return ("str",), T.STRING
        if isinstance(r, T.Domain) and r.kind == "enum":
            return ("enum", r.name), r
        if isinstance(r, T.Domain) and r.kind == "abstract":
            return ("abs",), r
        return None

    def any_tag(self, key, typ) -> int:
        i = self.any_tag_ids.get(key)
        if i is None:
            if self.frozen:
                raise Unsupported("a kind of value in a location of type Any met after the code was generated")
            # True, 1 and 1.0 are one key of the Python engine's states: one numeric kind at most
            nums = {("bool",), ("int",), ("real",)}
            if key in nums and any(k in nums for k, _ in self.any_tags):
                raise Unsupported("Booleans, Integers or Reals mixed in locations of type Any")
            i = self.any_tag_ids[key] = len(self.any_tags)
            self.any_tags.append((key, typ))
        return i

    def any_code(self, v) -> int | None:
        """The code of a Python value in a location of type Any: an interned (kind, code) pair."""
        if v is None:
            return None
        t = type(v)
        if t is bool:
            key, typ = ("bool",), T.BOOLEAN
        elif t is int:
            key, typ = ("int",), T.INTEGER
        elif t is float:
            if not storable_real(v):
                raise Unsupported("-0.0 or NaN in a location of type Any")
            key, typ = ("real",), T.REAL
        elif t is str:
            key, typ = ("str",), T.STRING
        elif t is EnumValue:
            dom = next((d for d in self.m.spec.domains if isinstance(d, T.Domain) and d.kind == "enum"
                        and d.name == v.domain), None)
            if dom is None:
                raise Unsupported(f"the enum value {v.name} in a location of type Any")
            key, typ = ("enum", v.domain), dom
        elif t is AbstractValue:
            key, typ = ("abs",), T.AGENT
        else:
            raise Unsupported(f"a value of kind {t.__name__} in a location of type Any")
        tag = self.any_tag(key, typ)
        x = self.to_c(v)
        return self.intern((K_ANY, (tag, UNDEF_V if x is None else x)))

    def fetch(self, i: int):
        if i < len(self.comp):
            return self.comp[i]
        dll = self.dll
        n = dll.asm_value_len(i)
        buf = (ctypes.c_int64 * max(n, 1))()
        kind = dll.asm_value_elems(i, buf)
        return kind, tuple(buf[:n])

    def literal(self, v) -> str:
        x = self.to_c(v)
        return UNDEF_C if x is None else f"((V){x}LL)"

    def intern(self, key) -> int:
        """The number of the composite value ``key`` (kind, element codes): a new entry while the
        code is generated, afterwards one the search made (see ``found``)."""
        i = self.comp_ids.get(key)
        if i is None:
            if self.frozen:
                return self.found(key)
            i = self.comp_ids[key] = len(self.comp)
            self.comp.append(key)
        return i

    def found(self, key) -> int:
        """The number of a composite value the search made (a state asked for by value may hold
        one); a value in no entry occurs in no state."""
        if self.dll is not None:
            kind, codes = key
            buf = (ctypes.c_int64 * max(len(codes), 1))(*codes)
            i = self.dll.asm_value_find(kind, buf, len(codes))
            if i >= 0:
                self.comp_ids[key] = i
                return i
        raise Unsupported("a composite value met after the code was generated")


class ByName:
    """A macro parameter passed by name: the C code of its argument (evaluated where the body
    uses it) and, for a location argument, its function and the code of its arguments."""

    __slots__ = ("expr", "loc")

    def __init__(self, expr: str, loc):
        self.expr = expr
        self.loc = loc


class Generator:
    def __init__(self, machine: Machine, props):
        self.m = machine
        self.spec = machine.spec
        self.codec = Codec(machine)
        self.props = props
        self.out: list[str] = []
        self.funcs: list[str] = []
        self.slots: list = []            # slot -> location key
        self.slot_of: dict = {}
        self.slot_values: list = []      # slot -> list of Python values (codes), undef last
        self.slot_types: list = []       # slot -> codomain type (("map", f) for a map slot)
        self.map_slot: dict = {}         # function index -> the slot holding its locations as a map
        self.fn_base: dict = {}          # function index -> (base slot, arg domains, codomain values)
        self.mon_base: dict = {}
        self.nmon = 0
        self.dom_tables: dict = {}       # tuple of values -> C table name
        self.enc_tables: dict = {}       # codomain id -> encoder name
        self.defined_done: set = set()
        self.step_mode = False
        self.param_uids: set = set()
        self._plan = None
        self.step_props: list = []
        self.invars: list = []
        self.rules_done: dict = {}
        self.cn_k = CN_K                 # element slots per extended domain (native_canon.c)
        self.invar_pre = False           # an INVAR reads monitored functions: checked before the step too
        self.unlaid: dict = {}           # function index -> why it has no slots (it is never used)
        self.site_reasons: list = []     # reasons of the run-time refusals (site 1000 + i)
        self._recursion_site = None
        self._used = None
        self._loose = None
        self._any_read = False           # the term being translated may be a location of type Any
        self.uid = 0
        self.sym = None                  # symmetry reduction (explore.symmetry.Symmetry, active): native_sym.c

    # -------------------------------------------------------------- helpers
    def fresh(self, prefix="t") -> str:
        self.uid += 1
        return f"{prefix}{self.uid}"

    def values_of(self, dom: T.Type) -> list:
        if isinstance(T.root(dom), T.Struct):
            # the values of a Powerset/Seq/... domain are not enumerated (2^n of them for a set)
            raise Unsupported(f"ranging over the values of {dom}")
        fresh = self.dyn_values(dom)
        if fresh:
            return fresh
        try:
            vals = self.m.domain_values(dom, None, None)
        except Undetermined:
            raise Unsupported(f"the infinite domain {dom}")
        for v in vals:
            self.codec.to_c(v)
        return list(vals)

    def codomain_values(self, f):
        """The values a controlled function's locations hold, or None for an integer codomain
        (a wide slot: the value itself, 64 bits, is stored)."""
        if self.composite(f.codomain) or T.root(f.codomain) is T.REAL:
            return None      # a Real location holds its code (an initial value may lie outside a subset)
        if self.any_typed(f.codomain):
            try:
                return self.values_of(f.codomain)   # a subset of Any given by its elements
            except Unsupported:
                return None      # a tagged value (see any_term)
        try:
            return self.values_of(f.codomain)
        except Unsupported:
            r = T.root(f.codomain)
            if r in (T.INTEGER, T.NATURAL, T.REAL) or self.composite(f.codomain):
                return None
            if isinstance(r, T.Struct) and r.kind == "Rule":
                return self.rule_slot_values()
            raise

    def rule_slot_values(self):
        """The values a location of a rule codomain can hold: the rules written as values in the
        spec (a rule value is made only by ``<<r>>``; another one, an agent's program, is refused
        by the codec), so that the slot is narrow; None (a wide slot holding the code) when the spec
        writes none."""
        rules = self.referenced_rules()
        if not rules:
            return None
        vals = [RuleValue(rd) for rd in rules]
        for v in vals:
            self.codec.to_c(v)
        return vals

    def composite(self, typ) -> bool:
        """A sequence or tuple type over types the native search encodes."""
        r = T.root(typ)
        if r is T.STRING:
            return True
        if not isinstance(r, T.Struct) or r.kind not in ("Seq", "Prod", "Powerset", "Bag", "Map"):
            return False
        for a in r.args:
            ra = T.root(a)
            if isinstance(ra, T.Struct) or ra is T.STRING:
                if not self.composite(a):
                    return False
            elif ra is T.REAL and r.kind == "Prod":
                continue     # a Real in a tuple (stored only when neither -0.0 nor NaN)
            elif ra in (T.REAL, T.CHAR, T.COMPLEX) or (isinstance(ra, T.Domain) and ra.kind == "any"):
                return False
        return True

    @property
    def composite_slots(self) -> bool:
        """Whether a location holds a sequence, set, bag, map or string (whose size may grow)."""
        return any(not isinstance(t, tuple) and self.composite(t) for t in self.slot_types)

    def map_function(self, f) -> bool:
        """A function whose arguments range over an infinite domain, held as one map value: its
        arguments and values must be scalars (integers, enums, named elements, Booleans)."""
        def scalar(t):
            r = T.root(t)
            return r in (T.INTEGER, T.NATURAL, T.BOOLEAN) or (isinstance(r, T.Domain) and r.kind in ("enum", "abstract")) \
                or self.composite(t)     # a set, sequence, ... is the number of its entry in the value table
        cd = f.codomain
        if isinstance(cd, T.Domain) and cd.kind == "subset" and cd.definition is not None:
            return False
        rule_cd = isinstance(T.root(cd), T.Struct) and T.root(cd).kind == "Rule"    # a rule value is a code too
        return bool(f.domain) and all(scalar(d) for d in f.domain) and (scalar(cd) or rule_cd)

    def map_key(self, f, args: list) -> str:
        if len(args) == 1:
            return args[0]
        arr = self.fresh("k")
        return f"({{ V {arr}[{len(args)}] = {{{', '.join(args)}}}; v_intern(c, K_TUPLE, {arr}, {len(args)}); }})"

    def table(self, values: list) -> str:
        key = tuple(self.codec.to_c(v) for v in values)
        name = self.dom_tables.get(key)
        if name is None:
            name = f"DT{len(self.dom_tables)}"
            self.dom_tables[key] = name
        return name

    # -------------------------------------------------------------- layout
    def layout(self) -> None:
        self.dyn_setup()
        init_states = self.m.initial_states()
        self.init_states = [st for _, st in init_states]
        for st in self.init_states:
            for k in st:
                if is_dom_key(k):
                    raise Unsupported("domains extended at run time")
        for f in self.spec.functions:
            if f.kind not in ("controlled", "out", "shared"):
                continue
            if f is self.spec.self_func or f is self.spec.result_func:
                continue
            if f.index in self.m.lazy:
                self.layout_lazy(f)
                continue
            if T.root(f.codomain) is T.UNDEF and self.unused(f):
                self.unlaid[f.index] = f"the function {f.name} of codomain Undef"
                continue
            try:
                if f.index in self.agent_loose_functions() and self.map_function(f):
                    raise Unsupported(f"{f.name} updated at agents outside its domain")
                arg_values = [self.values_of(d) for d in f.domain]
                if f.index in getattr(self, "undef_args", ()):
                    arg_values = [vals + [None] for vals in arg_values]     # see NativeExplorer._undef_arg_slots
            except Unsupported as e:
                if not self.map_function(f):
                    if self.unused(f):
                        # never read nor updated: its locations stay undef, no slot is needed
                        self.unlaid[f.index] = e.args[0] if e.args else str(e)
                        continue
                    raise
                # a function over an infinite domain: its defined locations are one map value
                s_ = len(self.slots)
                self.slot_of[("map", f.index)] = s_
                self.slots.append(("map", f.index))
                self.slot_values.append(None)
                self.slot_types.append(("map", f))
                self.map_slot[f.index] = s_
                continue
            n = 1
            for vals in arg_values:
                n *= len(vals)
            if len(self.slots) + n > MAX_SLOTS:
                raise Unsupported(f"more than {MAX_SLOTS:,} locations (the C compiler fails on a million)")
            cod = self.codomain_values(f)
            combos = [()]
            for vals in arg_values:
                combos = [c + (v,) for c in combos for v in vals]
            base = len(self.slots)
            for combo in combos:
                key = f.index if not combo else (f.index, combo)
                self.slot_of[key] = len(self.slots)
                self.slots.append(key)
                self.slot_values.append(cod)
                self.slot_types.append(f.codomain)
            self.fn_base[f.index] = (base, arg_values, cod)
            if len(self.slots) > MAX_SLOTS:
                raise Unsupported(f"more than {MAX_SLOTS:,} locations (the C compiler fails on a million)")
        self.dyn_slots()
        self.layout_result()
        self.layout_local()
        self.constant_slots()
        self.initial_values_outside()
        for st in self.init_states:
            for k in st:
                if k not in self.slot_of and not (type(k) is tuple and k[0] in self.map_slot):
                    raise Unsupported("a location outside the finite layout")
        for f in self.spec.functions:
            if f.kind == "monitored":
                try:
                    arg_values = [self.values_of(d) for d in f.domain]
                    cod = self.m.monitored_options(f, None, f.span)
                except (Undetermined, Unsupported):
                    continue     # only an error if the model reads it (then translation fails)
                for v in cod:
                    self.codec.to_c(v)
                n = 1
                for vals in arg_values:
                    n *= len(vals)
                self.mon_base[f.index] = (self.nmon, arg_values, cod)
                self.nmon += n

    def layout_lazy(self, f) -> None:
        """A function initialised over an infinite domain: its updated locations are one map
        value (as for any function over an infinite domain); a location not in the map has the
        value of the init term, which must read no location (then its first read in a step and
        every later one agree)."""
        params, body = self.m.lazy[f.index]
        lazy_ok = self.map_function(f) or (bool(f.domain) and all(
            T.root(d) in (T.INTEGER, T.NATURAL, T.BOOLEAN) for d in f.domain)
            and isinstance(T.root(f.codomain), T.Struct) and T.root(f.codomain).kind == "Rule")
        if not lazy_ok or not self.reads_no_location(body) or self.has_choose():
            # a location first read keeps its initial value in the next state; the Python engine
            # reads it also in the alternatives of a choose that it merges, and in none when it
            # reuses a choose's outcomes: only specs without choose rules are translated
            raise Unsupported(f"the lazily initialised function {f.name}")
        s_ = len(self.slots)
        self.slot_of[("map", f.index)] = s_
        self.slots.append(("map", f.index))
        self.slot_values.append(None)
        self.slot_types.append(("map", f))
        self.map_slot[f.index] = s_
        self.__dict__.setdefault("lazy_init", {})[f.index] = (params, body)

    def has_choose(self) -> bool:
        return _contains([rd.body for rd in self.spec.rules], ir.Choose)

    def reads_no_location(self, t) -> bool:
        todo = [t]
        while todo:
            x = todo.pop()
            if isinstance(x, ir.Loc) and (x.func.kind != "static" or x.func.body is not None and not
                                          self.reads_no_location(x.func.body)):
                return False
            if isinstance(x, (ir.StepOp,)):
                return False
            if isinstance(x, ir.Term):
                todo.extend(v for v in vars(x).values() if isinstance(v, (ir.Term, list, tuple)))
            elif isinstance(x, (list, tuple)):
                todo.extend(y for y in x if isinstance(y, (ir.Term, list, tuple)))
        return True

    def lazy_read(self, f, args: list) -> str:
        """A read of a lazily initialised location: its value in the map, else the init term's."""
        name = self.init_term(f, self.lazy_init[f.index], "lz")
        ks = [self.fresh("lk") for _ in args]
        m = self.fresh("lm")
        decl = " ".join(f"V {k} = {a};" for k, a in zip(ks, args))
        if "lz_note" not in self.defined_done:
            self.defined_done.add("lz_note")
            self.funcs.append(
                "/* lazily initialised locations read in this run: the next state keeps their value */\n"
                "static _Thread_local uint32_t lz_gen = 0; static _Thread_local int lz_n = 0;\n"
                "static _Thread_local int lz_slot[MAXV]; static _Thread_local V lz_key[MAXV], lz_val[MAXV];\n"
                "static V lz_note(Ctx *c, int s, V k, V v) {\n"
                "    if (c->in_prop || c->rd != c->cur) return v;\n"
                "    if (lz_gen != c->gen) { lz_gen = c->gen; lz_n = 0; }\n"
                "    if (lz_n >= MAXV) { fail(c, E_UNSUPPORTED, 0); return v; }\n"
                "    lz_slot[lz_n] = s; lz_key[lz_n] = k; lz_val[lz_n] = v; lz_n++;\n"
                "    return v;\n"
                "}\n"
                "static void lz_flush(Ctx *c) {\n"
                "    if (c->err || lz_gen != c->gen) return;\n"
                "    for (int i = 0; i < lz_n; i++) {\n"
                "        if (lz_val[i] == UNDEF) { fail(c, E_UNSUPPORTED, 0); return; }\n"
                "        int vs = vslot(c, lz_slot[i], lz_key[i]);\n"
                "        if (vs >= 0 && c->wgen[vs] != c->gen) upd(c, vs, lz_val[i], 0);\n"
                "    }\n"
                "    lz_n = 0;\n"
                "}")
        sl = self.map_slot[f.index]
        key = self.fresh("lq")
        return (f"({{ {decl} V {key} = {self.map_key(f, ks)}; V {m} = map_get(c->rd[{sl}], {key}); "
                f"{m} == UNDEF ? lz_note(c, {sl}, {key}, {name}(c{''.join(', ' + k for k in ks)})) : {m}; }})")

    def layout_result(self) -> None:
        """The location ``result`` of turbo rules (type Any): a slot of the one type every
        update of it in the spec gives it, or none when nothing updates it."""
        rf = self.spec.result_func
        if rf is None:
            return
        types = []
        todo: list = [rd.body for rd in self.spec.rules]
        while todo:
            x = todo.pop()
            if isinstance(x, ir.Update) and x.func is rf:
                types.append(x.value.type)
            if isinstance(x, (ir.Rule, ir.Term)):
                todo.extend(v for v in vars(x).values() if isinstance(v, (ir.Rule, ir.Term, list, tuple)))
            elif isinstance(x, (list, tuple)):
                todo.extend(y for y in x if isinstance(y, (ir.Rule, ir.Term, list, tuple)))
        if not types:
            return
        roots = {T.INTEGER if T.root(t) is T.NATURAL else T.root(t) for t in types}
        if len(roots) != 1:
            raise Unsupported("values of several types in the location result")
        (typ,) = roots
        if typ in (T.INTEGER, T.NATURAL) or self.composite(typ) or (
                isinstance(typ, T.Domain) and typ.kind == "abstract"):
            cod = None       # the code itself (an element of an abstract domain decodes by its number)
        elif typ is T.BOOLEAN or (isinstance(typ, T.Domain) and typ.kind == "enum"):
            cod = self.values_of(typ)
        else:
            raise Unsupported(f"the location result of type {typ}")
        base = len(self.slots)
        self.slot_of[rf.index] = base
        self.slots.append(rf.index)
        self.slot_values.append(cod)
        self.slot_types.append(typ)
        self.fn_base[rf.index] = (base, [], cod)
    def runtime_site(self, why: str) -> int:
        self.site_reasons.append(why)
        return 1000 + len(self.site_reasons) - 1

    def agent_loose_functions(self) -> set:
        """Functions updated at ``self`` by the program of agents outside the function's domain
        (a rule shared by several kinds of agent): the Python engine keeps such a location even
        outside the declared domain, so these functions are held as maps, which take any argument."""
        if self._loose is not None:
            return self._loose
        loose: set = set()
        selff = self.spec.self_func

        def within(t, d) -> bool:
            k = 0
            while isinstance(t, T.Domain) and k < 50:
                if t is d:
                    return True
                t = t.base if t.kind == "subset" else None
                k += 1
            return t is d

        for dom, ag in self.m.agent_programs.items():
            rules, todo = [], [ag.rule]
            while todo:
                rd = todo.pop()
                if any(rd is x for x in rules):
                    continue
                rules.append(rd)
                todo.extend(ir.called_rules(rd.body))
            seen: set = set()

            def walk(x):
                if id(x) in seen:
                    return
                seen.add(id(x))
                if isinstance(x, ir.Update) and x.func.domain:
                    for a, d in zip(x.args, x.func.domain):
                        if isinstance(a, ir.Loc) and a.func is selff and not within(dom, d):
                            loose.add(x.func.index)
                if isinstance(x, (ir.Term, ir.Rule)):
                    for v in vars(x).values():
                        walk(v)
                elif isinstance(x, (list, tuple)):
                    for v in x:
                        walk(v)
            for rd in rules:
                walk(rd.body)
        self._loose = loose
        return loose

    @staticmethod
    def any_typed(typ) -> bool:
        r = T.root(typ) if typ is not None else None
        return isinstance(r, T.Domain) and r.kind == "any"

    def any_slot(self, f) -> bool:
        """Are the locations of ``f`` of type Any holding tagged values (not a finite subset)?  Not
        ``result``: its slot holds the plain values of the one type every update gives it
        (layout_result), so it is read and compared as a location of that type."""
        if f is self.spec.result_func:
            return False
        return self.any_typed(f.codomain) and f.index in self.fn_base and self.fn_base[f.index][2] is None

    def any_term(self, t, env) -> str:
        """A term's value as held in a location of type Any (a tagged, interned pair)."""
        if isinstance(t, ir.Const) and t.value is None:
            return UNDEF_C
        if self.any_typed(t.type):
            if not (isinstance(t, ir.Loc) and self.any_slot(t.func)):
                raise Unsupported(f"a term of type {t.type}")
            self._any_read = True
            return self.term(t, env)
        tk = self.codec.any_tag_key(t.type)
        if tk is None:
            raise Unsupported(f"a value of type {t.type} in a location of type Any")
        tag = self.codec.any_tag(*tk)
        x = self.fresh("a")
        val = self.term(t, env)
        if tk[0] == ("real",):
            val = f"r_chk(c, {val})"
        return (f"({{ V {x}[2] = {{{tag}, {val}}}; {x}[1] == UNDEF ? UNDEF : v_intern(c, {K_ANY}, {x}, 2); }})")

    def unused(self, f) -> bool:
        """Is ``f`` never mentioned and never given an initial value (all its locations undef)?"""
        if f.index in self.used_functions():
            return False
        return not any(k == f.index or (type(k) is tuple and k[0] == f.index) for st in self.init_states for k in st)

    def used_functions(self) -> set:
        """The indexes of the functions the rules, the derived functions, the properties and the
        INVAR constraints mention (read or update)."""
        if self._used is not None:
            return self._used
        used: set = set()
        seen: set = set()

        def walk(x):
            if id(x) in seen:
                return
            seen.add(id(x))
            if isinstance(x, ir.Function):
                if x.index not in used:
                    used.add(x.index)
                    if x.body is not None:
                        walk(x.body)
                return
            if isinstance(x, (ir.Term, ir.Rule)):
                for v in vars(x).values():
                    walk(v)
            elif isinstance(x, (list, tuple)):
                for v in x:
                    walk(v)
        for r in self.spec.rules:
            walk(r.body)
        for p in self.spec.properties:
            walk(p.body)
        for p in list(self.props) + list(self.step_props):
            walk(p.prop.body)
        for f in self.spec.functions:
            if f.kind in ("static", "derived") and f.body is not None:
                walk(f.body)
        if self.spec.default_init is not None:
            for _func, _params, body, _span in self.spec.default_init.functions:
                walk(body)
        del walk        # (the closure refers to itself: freed now, with the ids seen, not by the collector)
        self._used = used
        return used

    def initial_values_outside(self) -> None:
        """An initial value outside its location's codomain (the Python engine does not check
        initial values): the slot's codes go on after the undef code (the codomain's values,
        undef, then such values), so the encoder of updates still sees only the codomain."""
        self.slot_undef = [None] * len(self.slots)
        for s, key in enumerate(self.slots):
            vals = self.slot_values[s]
            if vals is None or isinstance(self.slot_types[s], tuple):
                continue
            extra: list = []
            for st in self.init_states:
                v = st.get(key)
                if v is not None and not any(same_value(x, v) and type(x) is type(v) for x in vals + extra):
                    self.codec.to_c(v)
                    extra.append(v)
            if extra:
                self.slot_undef[s] = len(vals)
                self.slot_values[s] = list(vals) + [None] + extra

    def constant_slots(self) -> None:
        """Locations of monitored functions given a value by the initial state: the Python engine
        keeps that value in every state (a step reads monitored values from its inputs, never from
        the state), so each is a slot no update touches, with the values the initial states give."""
        for st in self.init_states:
            for k in st:
                if k in self.slot_of or (type(k) is tuple and k[0] in self.map_slot):
                    continue
                f = self.spec.functions[k if type(k) is int else k[0]]
                if f.kind != "monitored":
                    continue
                vals: list = []
                for st2 in self.init_states:
                    v = st2.get(k)
                    if v is not None and not any(same_value(v, x) and type(v) is type(x) for x in vals):
                        self.codec.to_c(v)
                        vals.append(v)
                cod = None
                if type(k) is int and not T.root(f.codomain) is T.REAL:
                    # a 0-ary one may be updated (a turbo rule's result): its codomain's codes,
                    # the initial values outside it after undef (initial_values_outside)
                    try:
                        cod = self.values_of(f.codomain)
                    except Unsupported:
                        cod = None
                if cod is not None:
                    self.fn_base[f.index] = (len(self.slots), [], cod)
                    vals = list(cod)
                self.slot_of[k] = len(self.slots)
                self.slots.append(k)
                self.slot_values.append(vals)
                self.slot_types.append(f.codomain)

    # -------------------------------------------------------------- terms
    def term(self, t: ir.Term, env: dict) -> str:
        meth = getattr(self, "t_" + type(t).__name__, None)
        if meth is None:
            raise Unsupported(f"the term {type(t).__name__} at {t.span.short() if t.span else '?'}")
        return meth(t, env)

    def t_Const(self, t, env):
        return self.codec.literal(t.value)

    def t_RuleRef(self, t, env):
        return self.codec.literal(RuleValue(t.rule))

    def t_VarRef(self, t, env):
        name = env.get(t.var.uid)
        if name is None:
            # AsmetaL keeps a variable known for the rest of its declaration once bound anywhere in
            # it; where no enclosing binder binds it, reading it is the Python engine's run-time
            # error ("variable ... is not bound here": a called rule or derived function sees only
            # its parameters, as here)
            return "({ fail(c, E_MODEL, 0); (V)UNDEF; })"
        if isinstance(name, ByName):
            return name.expr
        return name

    def may_choose(self, t) -> bool:
        """Whether evaluating ``t`` may make a choice (read a monitored function, directly or
        through a derived or static function's body): the Python engine makes its choices in the
        order it reads, left to right."""
        memo = self.__dict__.setdefault("_may_choose", {})
        todo = [t]
        while todo:
            x = todo.pop()
            if isinstance(x, ir.Loc):
                f = x.func
                if f.kind == "monitored":
                    return True
                if f.kind in ("static", "derived") and f.body is not None:
                    if f.index not in memo:
                        memo[f.index] = False        # a recursive function: its other reads decide
                        memo[f.index] = self.may_choose(f.body)
                    if memo[f.index]:
                        return True
            if isinstance(x, ir.Term):
                todo.extend(v for v in vars(x).values() if isinstance(v, (ir.Term, list, tuple)))
            elif isinstance(x, (list, tuple)):
                todo.extend(y for y in x if isinstance(y, (ir.Term, list, tuple)))
        return False

    def in_order(self, t, env, meth):
        """``meth(t, env)`` with the arguments of ``t`` that may make a choice evaluated first, left
        to right, when two or more may (C leaves the order of a call's arguments open, and the
        order of the choices is the order of the successors).  Each is bound to a C variable and
        read through a variable reference of its type; the arguments of other kinds are left."""
        pick = [i for i, a in enumerate(t.args) if self.may_choose(a)]
        if len(pick) < 2 or getattr(t, "_in_order", False):
            return meth(t, env)
        env2 = dict(env)
        args = list(t.args)
        pre = []
        any_read, self._any_read = self._any_read, False     # (it is the call's, not an argument's)
        for i in pick:
            a = t.args[i]
            r = T.root(a.type)
            if not (r in (T.INTEGER, T.NATURAL, T.BOOLEAN) or isinstance(r, T.Domain) and r.kind in ("enum", "abstract")):
                continue
            if isinstance(a, ir.Loc) and self.any_slot(a.func):
                continue
            name = self.fresh("ord")
            pre.append(f"V {name} = {self.term(a, env)};")
            var = ir.Var(name, a.type, a.span, uid=("ord", name))
            env2[var.uid] = name
            args[i] = ir.VarRef(a.type, a.span, var)
        self._any_read = any_read
        if len(pre) < 2:
            return meth(t, env)
        t2 = copy.copy(t)
        t2.args = args
        t2._in_order = True
        return "({ " + " ".join(pre) + f" {meth(t2, env2)}; }})"

    def ordered_terms(self, ts, env) -> tuple[str, list[str]]:
        """The C code of the terms ``ts`` (a location's arguments in an update) and the C
        statements to run before, which evaluate left to right those that may make a choice
        when two or more may (see in_order)."""
        args = [self.term(a, env) for a in ts]
        if sum(1 for a in ts if self.may_choose(a)) < 2:
            return "", args
        pre = []
        for i, a in enumerate(ts):
            if self.may_choose(a):
                name = self.fresh("ord")
                pre.append(f"V {name} = {args[i]};")
                args[i] = name
        return " ".join(pre), args

    def t_Loc(self, t, env):
        if len(t.args) > 1:
            return self.in_order(t, env, self.t_Loc_)
        return self.t_Loc_(t, env)

    def t_Loc_(self, t, env):
        f = t.func
        if f is self.spec.self_func:
            return "c->self"
        if f.kind == "static" and f.arity == 0 and isinstance(f.codomain, T.Domain) and \
                isinstance(T.root(f.codomain), T.Domain) and T.root(f.codomain).kind == "abstract":
            from ..semantics.values import abstract_value
            return self.codec.literal(abstract_value(f.codomain.name, f.name))
        if self.any_slot(f) and not self._any_read:
            raise Unsupported(f"the value of {f.name} (of type {f.codomain}) outside an update or a comparison")
        self._any_read = False
        args = [self.term(a, env) for a in t.args]
        if f.kind in ("static", "derived") and f.body is not None:
            name = self.defined(f)
            return f"{name}(c{''.join(', ' + a for a in args)})"
        if f.kind == "static":
            return UNDEF_C
        if f.kind == "monitored":
            if f.index not in self.mon_base:
                raise Unsupported(f"the monitored function {f.name} over an infinite domain")
            base, arg_values, cod = self.mon_base[f.index]
            return f"({self.mon_reader(f)}(c{''.join(', ' + a for a in args)}))"
        if f.index in getattr(self, "lazy_init", ()):
            return self.lazy_read(f, args)
        if f.index in self.map_slot:
            return f"map_get(c->rd[{self.map_slot[f.index]}], {self.map_key(f, args)})"
        if f.index not in self.fn_base:
            if f.kind == "derived" and f.body is None:
                # declared without a definition: no location of it holds a value (the Python
                # step function reads it from the state, where nothing puts it)
                return UNDEF_C
            raise Unsupported(f"the function {f.name}")
        return f"({self.reader(f)}(c{''.join(', ' + a for a in args)}))"

    def offset_code(self, arg_values, params: list[str]) -> list[str]:
        """C statements computing `off` (the argument tuple's position) or returning -1."""
        lines = ["int64_t off = 0;"]
        for vals, p in zip(arg_values, params):
            tab = self.table(vals)
            codes = [self.codec.to_c(v) for v in vals]
            if codes and len(set(codes)) == len(codes) and codes == list(range(codes[0], codes[0] + len(codes))):
                # consecutive codes (an enum or abstract domain, an integer range): the position
                # is the difference (unsigned: undef and the codes below wrap to big numbers)
                lines.append(f"{{ uint64_t j = (uint64_t){p} - (uint64_t){codes[0]}LL; if (j >= {len(vals)}u) return -1;"
                             f" off = off * {len(vals)} + (int64_t)j; }}")
                continue
            lines.append(f"{{ int j = -1; for (int q = 0; q < {len(vals)}; q++) if ({tab}[q] == {p}) {{ j = q; break; }}"
                         f" if (j < 0) return -1; off = off * {len(vals)} + j; }}")
        return lines

    def reader(self, f) -> str:
        name = f"rd{f.index}"
        if name in self.defined_done:
            return name
        self.defined_done.add(name)
        base, arg_values, cod = self.fn_base[f.index]
        params = [f"a{i}" for i in range(len(arg_values))]
        sig = "".join(f", V {p}" for p in params)
        body = [f"static int sl{f.index}(Ctx *c{sig}) {{"]
        body += ["    " + x for x in self.offset_code(arg_values, params)]
        body.append(f"    return {base} + (int)off;")
        body.append("}")
        body.append(f"static V {name}(Ctx *c{sig}) {{")
        body.append(f"    int s = sl{f.index}(c{''.join(', ' + p for p in params)});")
        init = getattr(self.m, "init_terms", {}).get(f.index)
        if init is not None and params:
            self.funcs.append(f"static V {name}(Ctx *c{sig});")      # (the init term may read f)
            # read at an undef argument (no location of the layout, or an undef-argument slot not
            # yet updated), the init term gives the value in the state of the read, as the Python
            # step function computes it (its read_with_init)
            body.append(f"    if ((s < 0 || c->rd[s] == UNDEF) && ({' || '.join(p + ' == UNDEF' for p in params)})) "
                        f"return {self.init_term(f, init)}(c{''.join(', ' + p for p in params)});")
        body.append("    return s < 0 ? UNDEF : c->rd[s];")
        body.append("}")
        self.funcs.append("\n".join(body))
        return name

    def init_term(self, f, init, prefix: str = "it") -> str:
        """The C function of the init term of ``f`` (``init``: its parameters and body), called
        with the arguments of a location (``prefix``: "lz" for a lazily initialised function)."""
        params, body = init
        name = f"{prefix}{f.index}"
        if name not in self.defined_done:
            self.defined_done.add(name)
            env = {p.uid: f"q{p.uid}" for p in params}
            sig = "".join(f", V q{p.uid}" for p in params)
            self.funcs.append(f"static V {name}(Ctx *c{sig});")
            self.funcs.append(f"static V {name}(Ctx *c{sig}) {{ return {self.term(body, env)}; }}")
        return name

    def mon_reader(self, f) -> str:
        name = f"mn{f.index}"
        if name in self.defined_done:
            return name
        self.defined_done.add(name)
        base, arg_values, cod = self.mon_base[f.index]
        params = [f"a{i}" for i in range(len(arg_values))]
        sig = "".join(f", V {p}" for p in params)
        tab = self.table(cod)
        body = [f"static int mi{f.index}(Ctx *c{sig}) {{"]
        body += ["    " + x for x in self.offset_code(arg_values, params)]
        body.append(f"    return {base} + (int)off;")
        body.append("}")
        body.append(f"static V {name}(Ctx *c{sig}) {{")
        body.append(f"    int s = mi{f.index}(c{''.join(', ' + p for p in params)});")
        body.append("    if (s < 0) return UNDEF;")
        body.append("    if ((!c->in_prop || c->mfix) && c->mgen[s] == c->gen) return c->mon[s];")
        # in a property, a value the step did not fix is one of the property's own choices
        body.append(f"    if (c->in_prop) {{ if (c->pgen[s] != c->pgen_cur) {{ c->pgen[s] = c->pgen_cur; "
                    f"c->pmon[s] = {tab}[{len(cod)} > 1 ? pchoice(c, {len(cod)}) : 0]; }} return c->pmon[s]; }}")
        body.append(f"    int i = {len(cod)} > 1 ? choice(c, {len(cod)}) : 0;")
        body.append(f"    c->mgen[s] = c->gen; c->mon[s] = {tab}[i];")
        body.append("    return c->mon[s];")
        body.append("}")
        self.funcs.append("\n".join(body))
        return name

    def encoder(self, f) -> str:
        """C function: value -> code for the locations of f (fails outside the codomain)."""
        base, arg_values, cod = self.fn_base[f.index]
        if T.root(f.codomain) is T.REAL:
            return self.real_encoder(f, cod)
        if cod is None:
            if "encW" not in self.defined_done:
                self.defined_done.add("encW")
                self.funcs.append("static inline V encW(Ctx *c, V v, int site) { return v; }")
            return "encW"
        key = ("enc", tuple(self.codec.to_c(v) for v in cod))
        name = self.enc_tables.get(key)
        if name is not None:
            return name
        name = f"enc{len(self.enc_tables)}"
        self.enc_tables[key] = name
        tab = self.table(cod)
        ints = [self.codec.to_c(v) for v in cod]
        lines = [f"static int32_t {name}(Ctx *c, V v, int site) {{", f"    if (v == UNDEF) return {len(cod)};"]
        if ints and ints == list(range(ints[0], ints[0] + len(ints))):
            lines.append(f"    if (v >= {ints[0]}LL && v <= {ints[-1]}LL) return (int32_t)(v - {ints[0]}LL);")
        else:
            lines.append(f"    for (int q = 0; q < {len(cod)}; q++) if ({tab}[q] == v) return q;")
        cd = f.codomain
        really = isinstance(cd, T.Domain) and cd.kind == "subset" and cd.definition is not None
        lines.append(f"    fail(c, {'E_DOMAIN' if really else 'E_UNSUPPORTED'}, site); return 0;")
        lines.append("}")
        self.funcs.append("\n".join(lines))
        return name

    def real_encoder(self, f, cod) -> str:
        """The encoder of a Real location (which holds the code itself): -0.0 and NaN are refused
        (see ``storable_real``), and a value outside a subset codomain is an error."""
        cd = f.codomain
        if not (isinstance(cd, T.Domain) and cd.kind == "subset"):
            return "encR"
        try:
            vals = self.values_of(cd)
        except Unsupported:
            return "encR"
        codes = tuple(self.codec.to_c(v) for v in vals)
        key = ("encR", codes)
        name = self.enc_tables.get(key)
        if name is not None:
            return name
        name = f"enc{len(self.enc_tables)}"
        self.enc_tables[key] = name
        tab = self.table(vals)
        really = cd.definition is not None
        self.funcs.append("\n".join([
            f"static V {name}(Ctx *c, V v, int site) {{",
            "    if (v == UNDEF) return v;",
            "    if (v == R_NEGZ || v == R_NAN) { fail(c, E_UNSUPPORTED, site); return v; }",
            f"    for (int q = 0; q < {len(vals)}; q++) if ({tab}[q] == v) return v;",
            f"    fail(c, {'E_DOMAIN' if really else 'E_UNSUPPORTED'}, site); return v;",
            "}"]))
        return name

    def defined(self, f) -> str:
        name = f"df{f.index}"
        if name in self.defined_done:
            return name
        self.defined_done.add(name)
        env = {}
        params = []
        for p in f.params:
            v = f"p{p.uid}"
            env[p.uid] = v
            params.append(v)
        sig = "".join(f", V {p}" for p in params)
        # declared first: a derived function may call itself.  A recursion deeper than
        # MAX_RECURSION calls goes to the Python engine (which reports one that does not end)
        # before it overflows the C stack
        self.funcs.append(f"static V {name}(Ctx *c{sig});")
        body = self.term(f.body, env)
        site = self.recursion_site()
        self.funcs.append(f"static V {name}(Ctx *c{sig}) {{ if (c->err) return UNDEF; "
                          f"if (++c->rdepth > {MAX_RECURSION}) {{ c->rdepth--; fail(c, E_UNSUPPORTED, {site}); "
                          f"return UNDEF; }} V r = {body}; c->rdepth--; return r; }}")
        return name

    def recursion_site(self) -> int:
        if self._recursion_site is None:
            self._recursion_site = self.runtime_site(f"a derived function or rule called more than "
                                                     f"{MAX_RECURSION:,} times within itself")
        return self._recursion_site

    BIN = {"eq": "v_eq", "neq": "v_neq", "lt": "v_lt", "le": "v_le", "gt": "v_gt", "ge": "v_ge",
           "plus": "v_add", "minus": "v_sub", "mult": "v_mul", "min": "v_min", "max": "v_max"}

    SEQ1 = {"length": "seq_len", "isEmpty": "seq_empty", "notEmpty": "seq_nonempty", "first": "seq_first",
            "last": "seq_last"}
    SEQ2 = {"at": "seq_at", "contains": "seq_contains", "indexOf": "seq_index_of", "count": "seq_count"}

    def t_Call(self, t, env):
        if len(t.args) > 1 and t.name not in ("and", "or", "implies"):
            return self.in_order(t, env, self.t_Call_)
        return self.t_Call_(t, env)

    def t_Call_(self, t, env):
        name = t.name
        if name in ("eq", "neq", "isDef", "isUndef") and any(
                isinstance(a, ir.Loc) and self.any_slot(a.func) for a in t.args):
            args = [self.any_term(a, env) for a in t.args]
            if name in ("isDef", "isUndef"):
                return f"(V)({args[0]} {'!=' if name == 'isDef' else '=='} UNDEF)"
            return f"{'v_eq' if name == 'eq' else 'v_neq'}({args[0]}, {args[1]})"
        if t.args and self.composite(t.args[0].type):
            return self.composite_call(t, env)
        if name == "print":      # the number of its arguments, whatever their kinds
            return self.scalar_library_call(t, [self.term(a, env) for a in t.args])
        if name == "prepend" and len(t.args) == 2 and self.composite(t.args[1].type):
            return f"seq_prepend(c, {self.term(t.args[0], env)}, {self.term(t.args[1], env)})"
        if name in ("eq", "neq", "isDef", "isUndef") and all(
                isinstance(T.root(a.type), T.Struct) and T.root(a.type).kind == "Rule" for a in t.args):
            # rule values: equal when they are the same rule (one code per rule)
            ra = [self.term(a, env) for a in t.args]
            return {"eq": "v_eq({0}, {1})", "neq": "v_neq({0}, {1})", "isDef": "(V)({0} != UNDEF)",
                    "isUndef": "(V)({0} == UNDEF)"}[name].format(*ra)
        if any(T.root(a.type) is T.REAL for a in t.args) or name in ("div", "itor", "ntor"):
            return self.real_call(t, env)
        for a in t.args:
            r = T.root(a.type)
            if r in (T.REAL, T.STRING, T.CHAR, T.COMPLEX) or isinstance(r, T.Struct):
                raise Unsupported(f"{name} on {a.type}")
        args = [self.term(a, env) for a in t.args]
        if name in self.BIN and len(args) == 2:
            return f"{self.BIN[name]}({args[0]}, {args[1]})"
        if name == "minus" and len(args) == 1:
            return f"v_neg({args[0]})"
        if name == "plus" and len(args) == 1:
            return args[0]
        if name == "abs":
            return f"v_abs({args[0]})"
        if name == "mod":
            return f"v_mod(c, {args[0]}, {args[1]}, 0)"
        if name == "idiv":
            return f"v_idiv(c, {args[0]}, {args[1]}, 0)"
        if name == "not":
            return f"v_not({args[0]})"
        if name == "and":
            a, b = args
            x = self.fresh()
            return f"({{ V {x} = {a}; {x} == 0 ? (V)0 : v_and({x}, {b}); }})"
        if name == "or":
            a, b = args
            x = self.fresh()
            return f"({{ V {x} = {a}; {x} == 1 ? (V)1 : v_or({x}, {b}); }})"
        if name == "implies":
            a, b = args
            x = self.fresh()
            return f"({{ V {x} = {a}; {x} == 0 ? (V)1 : v_or(v_not({x}), {b}); }})"
        if name in ("iff", "xor"):
            a, b = args
            x, y = self.fresh(), self.fresh()
            op = "==" if name == "iff" else "!="
            return f"({{ V {x} = {a}; V {y} = {b}; ({x} == UNDEF || {y} == UNDEF) ? UNDEF : (V)({x} {op} {y}); }})"
        if name == "isDef":
            return f"(V)({args[0]} != UNDEF)"
        if name == "isUndef":
            return f"(V)({args[0]} == UNDEF)"
        if name in ("iton", "ntoi"):
            return args[0]
        lib = self.scalar_library_call(t, args)
        if lib is not None:
            return lib
        raise Unsupported(f"the library function {name}")

    def scalar_library_call(self, t, args):
        """print, toString of an integer and the clock functions (which have no value: the Python
        engine's run-time error) on arguments that are not composite (None: none of them)."""
        name = t.name
        if name == "print":
            x = self.fresh("pr")
            return "({ " + " ".join(f"V {x}_{i} = {a}; (void){x}_{i};" for i, a in enumerate(args)) + f" (V){len(args)}; }})"
        if name == "toString" and len(args) == 1 and T.root(t.args[0].type) in (T.INTEGER, T.NATURAL):
            return f"int_to_string(c, {args[0]})"
        if name in ("currTimeNanosecs", "currTimeMillisecs", "currTimeSecs") and not args:
            return "({ fail(c, E_MODEL, 0); (V)UNDEF; })"
        return None

    def composite_call(self, t, env):
        import re
        name = t.name
        r0 = T.root(t.args[0].type)
        kind = "String" if r0 is T.STRING else r0.kind
        args = [self.term(a, env) for a in t.args]
        if name in ("eq", "neq") and len(args) == 2 and self.composite(t.args[1].type):
            x, y = self.fresh(), self.fresh()
            # undef = undef is true, undef = a value false (as for every other value)
            return f"{'v_eq' if name == 'eq' else 'v_neq'}({args[0]}, {args[1]})"
        if name in ("isDef", "isUndef"):
            return f"(V)({args[0]} {'!=' if name == 'isDef' else '=='} UNDEF)"
        lib = self.library_call(t, args, kind)
        if lib is not None:
            return lib
        if kind == "String":
            raise Unsupported(f"{name} on String")
        if kind == "Powerset":
            if name in ("size",) and len(args) == 1:
                return f"seq_len({args[0]})"
            if name in ("isEmpty", "notEmpty") and len(args) == 1:
                return f"{self.SEQ1[name]}({args[0]})"
            if name == "contains" and len(args) == 2:
                return f"set_contains({args[0]}, {args[1]})"
            if name == "notin" and len(args) == 2:
                return f"v_not(set_contains({args[0]}, {args[1]}))"
            if name == "including" and len(args) == 2:
                return f"set_including(c, {args[0]}, {args[1]})"
            if name == "excluding" and len(args) == 2:
                return f"set_excluding(c, {args[0]}, {args[1]})"
            ops = {"union": 0, "intersection": 1, "difference": 2}
            if name in ops and len(args) == 2 and T.root(t.args[1].type) == r0:
                return f"set_op(c, {args[0]}, {args[1]}, {ops[name]})"
            raise Unsupported(f"{name} on {t.args[0].type}")
        if name == "union" and len(args) == 2 and kind == "Seq":
            return f"seq_concat(c, {args[0]}, {args[1]})"
        if kind == "Prod":
            m = re.fullmatch(r"#(\d+)", name)
            k = int(m.group(1)) - 1 if m else {"first": 0, "second": 1, "third": 2, "fourth": 3, "fifth": 4,
                                                "sixth": 5, "seventh": 6, "eighth": 7, "ninth": 8}.get(name)
            if k is not None and len(args) == 1:
                return f"tuple_nth({args[0]}, {k})"
            raise Unsupported(f"{name} on {t.args[0].type}")
        if name in self.SEQ1 and len(args) == 1:
            return f"{self.SEQ1[name]}({args[0]})"
        if name in self.SEQ2 and len(args) == 2:
            return f"{self.SEQ2[name]}({args[0]}, {args[1]})"
        if name == "append" and len(args) == 2:
            return f"seq_append(c, {args[0]}, {args[1]})"
        if name == "tail" and len(args) == 1:
            return f"seq_tail(c, {args[0]})"
        if name == "excluding" and len(args) == 2:
            return f"seq_excluding(c, {args[0]}, {args[1]})"
        if name == "subSequence" and len(args) == 3:
            return f"seq_sub(c, {args[0]}, {args[1]}, {args[2]})"
        raise Unsupported(f"{name} on {t.args[0].type}")

    def orderable(self, typ) -> bool:
        """Elements whose codes are in the order of the Python engine's values (:func:`vkey`):
        integers, Booleans, the constants of one enum domain, and the named elements of abstract
        domains when no domain grows and their numbers follow their names."""
        r = T.root(typ)
        if isinstance(r, T.Domain) and r.kind == "abstract":
            return self.abstract_codes_sorted(r)
        return r in (T.INTEGER, T.NATURAL, T.BOOLEAN) or (isinstance(r, T.Domain) and r.kind == "enum")

    def in_value_order(self, x: str, typ) -> str | None:
        """C code: the elements of the set or bag ``x`` (of element type ``typ``) as a sequence in
        the Python engine's order (None: not for such elements)."""
        if self.orderable(typ):
            return f"v_rekind(c, {x}, K_SEQ)"
        if T.root(typ) is T.STRING:
            return f"str_sorted(c, {x})"
        return None

    @staticmethod
    def regex_literal(p: str):
        """The text a regular expression matches when it is a plain literal (``\\|`` is ``|``),
        else None."""
        out = []
        i = 0
        while i < len(p):
            ch = p[i]
            if ch == "\\":
                if i + 1 >= len(p) or p[i + 1].isascii() and p[i + 1].isalnum():
                    return None
                out.append(p[i + 1])
                i += 2
                continue
            if ch in ".^$*+?{}[]|()":
                return None
            out.append(ch)
            i += 1
        return "".join(out)

    def split_regex(self, t, args) -> str:
        """``split(s, re)`` by a constant regular expression: its program (``regex_program``) in a
        table, run by str_split_re (native_rt.c)."""
        sep = t.args[1]
        if not (isinstance(sep, ir.Const) and type(sep.value) is str):
            raise Unsupported("split on String by a regular expression computed in the state")
        prog = regex_program(sep.value)
        if prog is None:
            raise Unsupported("split on String by a regular expression outside the translated subset (a capturing "
                              "group, a look-around, a back-reference, flags, a repeat of what may match the empty text, ...)")
        return f"str_split_re(c, {args[0]}, {self.table(prog)})"

    def library_call(self, t, args, kind):
        """The StandardLibrary functions on strings, bags, map values and the conversions between
        collections (None: not one of them)."""
        name = t.name
        n = len(args)
        a0 = t.args[0].type
        if name == "print":
            x = self.fresh("pr")
            return "({ " + " ".join(f"V {x}_{i} = {a}; (void){x}_{i};" for i, a in enumerate(args)) + f" (V){n}; }})"
        if kind == "String":
            def string(i):
                return T.root(t.args[i].type) is T.STRING
            if name in ("size", "length") and n == 1:
                return f"seq_len({args[0]})"
            if name in ("toUpper", "toLower") and n == 1:
                return f"str_case(c, {args[0]}, {int(name == 'toUpper')})"
            if name == "contains" and n == 2 and string(1):
                return f"str_contains({args[0]}, {args[1]})"
            if name in ("concat", "plus") and n == 2 and string(1):
                return f"str_concat(c, {args[0]}, {args[1]})"
            if name == "subString" and n == 3:
                return f"str_sub(c, {args[0]}, {args[1]}, {args[2]})"
            if name == "toString" and n == 1:
                return args[0]
            if name == "split" and n == 2 and string(1):
                sep = t.args[1]
                lit = self.regex_literal(sep.value) if isinstance(sep, ir.Const) and type(sep.value) is str else None
                if not lit:
                    return self.split_regex(t, args)
                return f"str_split(c, {args[0]}, {self.codec.literal(lit)})"
            return None
        if name == "chooseone" and n == 1 and kind in ("Seq", "Powerset", "Bag") and (
                kind == "Seq" or self.in_value_order(args[0], T.root(a0).args[0])):
            # outside the initialisation: the first element (of a set, the least)
            if kind == "Seq" or self.orderable(T.root(a0).args[0]):
                return f"seq_first({args[0]})"
            return f"seq_first({self.in_value_order(args[0], T.root(a0).args[0])})"
        if name == "sum" and n == 1 and kind in ("Seq", "Powerset", "Bag") and \
                T.root(T.root(a0).args[0]) in (T.INTEGER, T.NATURAL):
            return f"v_sum(c, {args[0]})"
        if kind == "Map":
            if name == "at" and n == 2:
                return f"mapv_at({args[0]}, {args[1]})"
            if name == "merge" and n == 2:
                return f"mapv_merge(c, {args[0]}, {args[1]})"
            if name == "assign" and n == 3:
                return f"mapv_assign(c, {args[0]}, {args[1]}, {args[2]})"
            raise Unsupported(f"{name} on {a0}")
        if kind == "Bag":
            if name in ("contains", "count") and n == 2:
                return f"{self.SEQ2[name]}({args[0]}, {args[1]})"
            if name == "notin" and n == 2:
                return f"v_not(seq_contains({args[0]}, {args[1]}))"
            if name == "including" and n == 2:
                return f"bag_including(c, {args[0]}, {args[1]})"
            if name == "excluding" and n == 2:
                return f"bag_excluding(c, {args[0]}, {args[1]})"
            if name == "union" and n == 2 and T.root(t.args[1].type) == T.root(a0):
                return f"bag_union(c, {args[0]}, {args[1]})"
            if name == "asSet" and n == 1:
                return f"v_rekind(c, {args[0]}, K_SET)"
            if name == "asSequence" and n == 1 and self.in_value_order(args[0], T.root(a0).args[0]):
                return self.in_value_order(args[0], T.root(a0).args[0])
            raise Unsupported(f"{name} on {a0}")
        if kind == "Seq":
            if name == "insertAt" and n == 3:
                return f"seq_insert_at(c, {args[0]}, {args[1]}, {args[2]})"
            if name == "replaceAt" and n == 3:
                return f"seq_replace_at(c, {args[0]}, {args[1]}, {args[2]})"
            if name == "asSequence" and n == 1:
                return args[0]
            if name == "asSet" and n == 1:
                return f"v_rekind(c, {args[0]}, K_SET)"
            if name == "asBag" and n == 1:
                return f"v_rekind(c, {args[0]}, K_BAG)"
            return None
        if kind == "Powerset":
            elem = T.root(a0).args[0]
            if n == 2 and name in ("allin", "notallin", "symmetricDifference") and T.root(t.args[1].type) == T.root(a0):
                return {"allin": f"set_allin({args[0]}, {args[1]})",
                        "notallin": f"v_not(set_allin({args[0]}, {args[1]}))",
                        "symmetricDifference": f"set_symdiff(c, {args[0]}, {args[1]})"}[name]
            if name == "asSequence" and n == 1 and self.in_value_order(args[0], elem):
                return self.in_value_order(args[0], elem)
            if name == "asBag" and n == 1:
                return f"v_rekind(c, {args[0]}, K_BAG)"
            if name == "asSet" and n == 1:
                return args[0]
            return None
        return None

    def t_Range(self, t, env):
        """An interval ``{a : b}``, ``[a : b, step]``, ``<a : b>`` of integers."""
        from ..semantics.analysis import is_constant
        parts = [t.start, t.end] + ([t.step] if t.step is not None else [])
        if not self.composite(t.type) or any(T.root(x.type) not in (T.INTEGER, T.NATURAL) for x in parts):
            raise Unsupported(f"an interval of type {t.type}")
        if is_constant(t):
            from ..semantics.machine import Ctx, Chooser
            try:
                v = self.m.term(t)(Ctx(self.m, {}, Chooser()))
            except AsmError:
                raise Unsupported("an interval the Python engine cannot build") from None
            return self.codec.literal(v)
        kind = {"set": "K_SET", "seq": "K_SEQ", "bag": "K_BAG"}[t.kind]
        step = self.term(t.step, env) if t.step is not None else "(V)1"
        return f"range_make(c, {kind}, {self.term(t.start, env)}, {self.term(t.end, env)}, {step})"

    def t_MapLit(self, t, env):
        if not self.composite(t.type):
            raise Unsupported(f"a map of type {t.type}")
        if self.literal_term(t):
            from ..semantics.machine import Ctx, Chooser
            return self.codec.literal(self.m.term(t)(Ctx(self.m, {}, Chooser())))
        arr = self.fresh("e")
        vals = [self.term(x, env) for pr in t.pairs for x in pr]
        return f"({{ V {arr}[{max(len(vals), 1)}] = {{{', '.join(vals) or '0'}}}; mapv_make(c, {arr}, {len(t.pairs)}); }})"

    def literal_term(self, t) -> bool:
        """A term made of constants and the named elements of abstract domains only (its value is
        computed once, while the code is generated)."""
        if isinstance(t, ir.Const):
            return True
        if isinstance(t, ir.Loc):
            f = t.func
            return (f.kind == "static" and f.arity == 0 and f.body is None and isinstance(f.codomain, T.Domain)
                    and isinstance(T.root(f.codomain), T.Domain) and T.root(f.codomain).kind == "abstract")
        if isinstance(t, (ir.Collection, ir.TupleLit)):
            return all(self.literal_term(x) for x in t.items)
        if isinstance(t, ir.MapLit):
            return all(self.literal_term(x) for pr in t.pairs for x in pr)
        return False

    def t_Collection(self, t, env):
        if t.kind == "bag" and self.composite(t.type):
            arr = self.fresh("e")
            vals = [self.term(x, env) for x in t.items]
            return f"({{ V {arr}[{max(len(vals), 1)}] = {{{', '.join(vals) or '0'}}}; bag_make(c, {arr}, {len(vals)}); }})"
        if t.kind not in ("seq", "set") or not self.composite(t.type):
            raise Unsupported(f"a {t.kind} literal")
        if t.kind == "set":
            arr = self.fresh("e")
            vals = [self.term(x, env) for x in t.items]
            return f"({{ V {arr}[{max(len(vals), 1)}] = {{{', '.join(vals) or '0'}}}; set_make(c, {arr}, {len(vals)}); }})"
        return self.build(1, t.items, env)

    def t_TupleLit(self, t, env):
        if not self.composite(t.type):
            raise Unsupported(f"a tuple of type {t.type}")
        return self.build(2, t.items, env)

    def build(self, kind, items, env):
        arr = self.fresh("e")
        vals = [self.term(x, env) for x in items]
        vals = [f"r_chk(c, {v})" if x.type is not None and T.root(x.type) is T.REAL else v for v, x in zip(vals, items)]
        return (f"({{ V {arr}[{max(len(vals), 1)}] = {{{', '.join(vals) or '0'}}}; "
                f"v_intern(c, {kind}, {arr}, {len(vals)}); }})")

    def t_Cond(self, t, env):
        c = self.term(t.cond, env)
        a = self.term(t.then, env)
        b = self.term(t.other, env) if t.other is not None else UNDEF_C
        g = self.fresh("g")
        return f"({{ V {g} = {c}; guard(c, {g}, 0) ? ({a}) : ({b}); }})"

    def t_Switch(self, t, env):
        s = self.fresh("s")
        r = self.fresh("r")
        parts = [f"V {s} = {self.term(t.subject, env)}; V {r};"]
        first = True
        for cs, res in t.cases:
            kw = "if" if first else "else if"
            parts.append(f"{kw} ({s} == {self.term(cs, env)}) {r} = {self.term(res, env)};")
            first = False
        other = self.term(t.other, env) if t.other is not None else UNDEF_C
        parts.append(f"else {r} = {other};" if not first else f"{r} = {other};")
        parts.append(f"{r};")
        return "({ " + " ".join(parts) + " })"

    def t_Let(self, t, env):
        env = dict(env)
        decls = []
        for v, x in t.bindings:
            name = self.fresh("l")
            decls.append(f"V {name} = {self.term(x, env)};")
            env[v.uid] = name
        return "({ " + " ".join(decls) + f" {self.term(t.body, env)}; }})"

    REAL2 = {"plus": "r_add", "minus": "r_sub", "mult": "r_mul", "div": "r_div", "lt": "r_lt", "le": "r_le",
             "gt": "r_gt", "ge": "r_ge", "min": "r_min", "max": "r_max", "pwr": "r_pow"}
    REAL1 = {"minus": "r_neg", "abs": "r_abs", "sqrt": "r_sqrt", "floor": "r_floor"}

    def real_call(self, t, env):
        """A StandardLibrary function over Reals (Java doubles, as :mod:`..semantics.reals`)."""
        name = t.name
        roots = [T.root(a.type) for a in t.args]
        ints = (T.INTEGER, T.NATURAL)
        desc = ", ".join(str(a.type) for a in t.args)
        args = [self.term(a, env) for a in t.args]
        if name in ("eq", "neq") and len(args) == 2:
            if all(r in (T.REAL, T.UNDEF) for r in roots):
                e = f"v_eq({args[0]}, {args[1]})"
            elif roots[0] is T.REAL and roots[1] in ints:
                e = f"r_eq_ri({args[0]}, {args[1]})"
            elif roots[1] is T.REAL and roots[0] in ints:
                e = f"r_eq_ir({args[0]}, {args[1]})"
            else:
                raise Unsupported(f"{name} on {desc}")
            return e if name == "eq" else f"(V)!{e}"
        if name in ("isDef", "isUndef") and len(args) == 1:
            return f"(V)({args[0]} {'!=' if name == 'isDef' else '=='} UNDEF)"
        if name in ("itor", "ntor") and len(args) == 1 and roots[0] in ints:
            return f"r_itor({args[0]})"
        if name == "div" and len(args) == 2 and all(r in ints for r in roots):
            return f"r_div(r_itor({args[0]}), r_itor({args[1]}))"
        if not all(r is T.REAL for r in roots):
            raise Unsupported(f"{name} on {desc}")
        if len(args) == 2 and name in self.REAL2:
            return f"{self.REAL2[name]}({args[0]}, {args[1]})"
        if len(args) == 1 and name in self.REAL1:
            return f"{self.REAL1[name]}({args[0]})"
        if len(args) == 1 and name == "plus":
            return args[0]
        if len(args) == 1 and name in ("rtoi", "rton"):
            return f"r_rtoi(c, {args[0]})"
        if len(args) == 1 and name == "round":
            return f"r_round(c, {args[0]})"
        raise Unsupported(f"{name} on {desc}")

    def t_StepOp(self, t, env):
        if not self.step_mode:
            raise Unsupported(f"{t.op}(...) outside a step property")
        if t.op == "next":
            sv, r = self.fresh("sv"), self.fresh("r")
            return (f"({{ V *{sv} = c->rd; c->rd = c->post; V {r} = {self.term(t.args[0], env)}; "
                    f"c->rd = {sv}; {r}; }})")
        loc = t.args[-1]
        f = loc.func
        if f.index in self.map_slot and t.op in ("updated", "updatedBy", "changed"):
            return self.map_step_op(t, env)
        if f.index not in self.fn_base or f.index in self.map_slot:
            raise Unsupported(f"{t.op} of {f.name}")
        self.reader(f)
        args = [self.term(a, env) for a in loc.args]
        sl = self.fresh("s")
        head = f"int {sl} = sl{f.index}(c{''.join(', ' + a for a in args)});"
        if t.op == "updated":
            return f"({{ {head} (V)({sl} >= 0 && c->wgen[{sl}] == c->gen); }})"
        if t.op == "updatedBy":
            ag = self.term(t.args[0], env)
            return (f"({{ {head} V a_{sl} = {ag}; (V)({sl} >= 0 && c->wgen[{sl}] == c->gen && "
                    f"c->uagent[c->wpos[{sl}]] == a_{sl}); }})")
        if t.op == "changed":
            return f"({{ {head} (V)({sl} >= 0 && c->cur[{sl}] != c->post[{sl}]); }})"
        raise Unsupported(f"the step operator {t.op}")

    def map_step_op(self, t, env) -> str:
        """updated / updatedBy / changed of a location of a function held as a map: the step's
        update of it is the one of its virtual slot, if the step made one."""
        loc = t.args[-1]
        f = loc.func
        m = self.map_slot[f.index]
        key = self.map_key(f, [self.term(a, env) for a in loc.args])
        k, vs = self.fresh("k"), self.fresh("vs")
        if t.op == "changed":
            return f"({{ V {k} = {key}; (V)(map_get(c->cur[{m}], {k}) != map_get(c->post[{m}], {k})); }})"
        head = f"V {k} = {key}; int {vs} = vslot_find(c, {m}, {k});"
        if t.op == "updated":
            return f"({{ {head} (V)({vs} >= 0 && c->wgen[{vs}] == c->gen); }})"
        ag = self.term(t.args[0], env)
        return (f"({{ {head} V a_{vs} = {ag}; (V)({vs} >= 0 && c->wgen[{vs}] == c->gen && "
                f"c->uagent[c->wpos[{vs}]] == a_{vs}); }})")

    def range_values(self, r: ir.Term) -> list:
        if isinstance(r, ir.DomainTerm):
            d = r.domain
            if self.dyn_values(d):
                return self.dyn_values(d)
            if isinstance(d, T.Domain) and d.dynamic and self.grows(d) and (d.kind == "abstract" or (
                    d.kind == "subset" and isinstance(T.root(d), T.Domain) and T.root(d).kind == "abstract")):
                raise Unsupported(f"ranging over the dynamic domain {d}")
            return self.values_of(d)
        from ..semantics.machine import Ctx, Chooser
        from ..semantics.analysis import is_constant, ordered
        if is_constant(r):
            v = self.m.term(r)(Ctx(self.m, {}, Chooser()))
            vals = ordered(v, r.span)
            for x in vals:
                self.codec.to_c(x)
            return vals
        raise Unsupported("ranging over a term that changes with the state")

    def loop_head(self, rg, env, name, q, any_order: bool) -> str:
        """The C loop header binding ``name`` to each value of the range ``rg``: a constant range
        is a table in the Python engine's order; with ``any_order`` a set or sequence computed in
        the state is walked in the order of its codes (the result must not depend on the order)."""
        try:
            vals = self.range_values(rg)
        except Unsupported as e:
            why = e.args[0] if e.args else ""
            if why.startswith("the infinite domain") and isinstance(rg, ir.DomainTerm):
                # the Python engine cannot range over it either: the search hands the spec over
                # if it is reached (an unreachable one, as in a comprehension over [], is no reason)
                site = self.runtime_site(why)
                return f"fail(c, E_UNSUPPORTED, {site}); for (int {q} = 0; {q} < 0; {q}++) {{ V {name} = UNDEF;"
            r = T.root(rg.type) if rg.type is not None else None
            sorter = None
            if not self.runtime_order_ok(rg.type) and isinstance(r, T.Struct) and \
                    r.kind == "Powerset" and self.composite(rg.type):
                # a set of composite values: walked sorted as the Python engine sorts it (vkey),
                # also where any order would do (a quantifier stops where the Python engine stops)
                sorter = self.vkey_sorter(r.args[0])
                if sorter is None and not any_order:
                    raise
            elif not ((any_order or self.runtime_order_ok(rg.type)) and isinstance(r, T.Struct)
                      and r.kind in ("Powerset", "Seq") and self.composite(rg.type)):
                raise
            rv = self.fresh("rv")
            value = self.term(rg, env) if sorter is None else f"{sorter}(c, {self.term(rg, env)})"
            return (f"V {rv} = {value}; if ({rv} == UNDEF) fail(c, E_MODEL, 0); "
                    f"for (int {q} = 0; {rv} != UNDEF && {q} < v_len({rv}); {q}++) {{ V {name} = v_elems({rv})[{q}];")
        return self.range_head(rg, vals, q, name)

    def vkey_cmp(self, typ):
        """The name of a C function comparing two codes of type ``typ`` as ``vkey`` compares
        the values (-1, 0, 1), or None where that is not written."""
        r = T.root(typ)
        key = ("vcmp", str(typ))
        names = self.__dict__.setdefault("_vcmp", {})
        if key in names:
            return names[key]
        head = "if (a == b) return 0; if (a == UNDEF) return -1; if (b == UNDEF) return 1;"
        if self.codes_sorted_like_vkey(typ):
            body = head + " return a < b ? -1 : 1;"
        elif r is T.STRING:
            body = (head + " int n = v_len(a), m = v_len(b); for (int i = 0; i < n && i < m; i++) { "
                    "V x = v_elems(a)[i], y = v_elems(b)[i]; if (x != y) return x < y ? -1 : 1; } "
                    "return n < m ? -1 : n > m ? 1 : 0;")
        elif isinstance(r, T.Struct) and r.kind in ("Seq", "Prod", "Powerset") and self.composite(typ):
            if r.kind == "Powerset" and not self.codes_sorted_like_vkey(r.args[0]):
                names[key] = None
                return None
            subs = [self.vkey_cmp(a) for a in r.args]
            if any(x is None for x in subs):
                names[key] = None
                return None
            if r.kind == "Prod":
                parts = " ".join(f"{{ int k = {subs[i]}(v_elems(a)[{i}], v_elems(b)[{i}]); if (k) return k; }}"
                                 for i in range(len(subs)))
                body = head + " " + parts + " return 0;"
            else:
                pre = "int n = v_len(a), m = v_len(b); "
                if r.kind == "Powerset":      # (8, len, elements sorted)
                    pre += "if (n != m) return n < m ? -1 : 1; "
                body = (head + " " + pre + "for (int i = 0; i < n && i < m; i++) { "
                        f"int k = {subs[0]}(v_elems(a)[i], v_elems(b)[i]); if (k) return k; }} "
                        "return n < m ? -1 : n > m ? 1 : 0;")
        else:
            names[key] = None
            return None
        name = f"vc{len(names)}"
        names[key] = name
        self.funcs.append(f"static int {name}(V a, V b) {{ {body} }}")
        return name

    def vkey_sorter(self, elem):
        """The name of a C function: a set of ``elem`` values -> the sequence of its elements
        sorted by ``vkey`` (interned), or None."""
        cmp = self.vkey_cmp(elem)
        if cmp is None:
            return None
        name = f"{cmp}_sorted"
        if name not in self.defined_done:
            self.defined_done.add(name)
            self.funcs.append(
                f"static int {cmp}_q(const void *x, const void *y) {{ return {cmp}(*(const V *)x, *(const V *)y); }}\n"
                f"static V {name}(Ctx *c, V s) {{\n"
                f"    if (s == UNDEF) return UNDEF;\n"
                f"    int n = v_len(s);\n"
                f"    if (n > (1 << 16)) {{ fail(c, E_UNSUPPORTED, 0); return UNDEF; }}\n"
                f"    memcpy(vscratch, v_elems(s), n * sizeof(V));\n"
                f"    qsort(vscratch, n, sizeof(V), {cmp}_q);\n"
                f"    return v_intern(c, K_SEQ, vscratch, n);\n"
                f"}}")
        return name

    def runtime_order_ok(self, typ) -> bool:
        """Does a sequence or set of type ``typ`` computed in the state list its elements, in the
        order of their codes, as the Python engine does (a sequence in its order, a set sorted by
        ``vkey``)?  Then a loop over it meets the elements (and makes its choices) in the Python
        engine's order."""
        r = T.root(typ) if typ is not None else None
        if not isinstance(r, T.Struct) or r.kind not in ("Seq", "Powerset") or not self.composite(typ):
            return False
        if r.kind == "Seq":
            return True
        return self.codes_sorted_like_vkey(r.args[0])

    def codes_sorted_like_vkey(self, typ) -> bool:
        """Do the codes of the values of ``typ`` sort as ``vkey`` sorts the values?"""
        from ..semantics.values import vkey
        r = T.root(typ)
        if r in (T.INTEGER, T.NATURAL, T.BOOLEAN):
            return True
        if isinstance(r, T.Domain) and r.kind == "enum":
            return True
        if isinstance(r, T.Domain) and r.kind == "abstract":
            return self.abstract_codes_sorted(r)
        return False

    def abstract_codes_sorted(self, r) -> bool:
        """Do the codes of the elements of the abstract domain ``r`` and of the domains inside it
        sort as ``vkey`` sorts them?  ``vkey`` orders by the domain's name, then the serial (0 for a
        named element, k for the k-th element made by extend), then the name; the codes put every
        named element (numbered by domain name, then in declaration order) before every element
        made by extend (numbered by domain name, then serial).  Both agree when the named elements'
        numbers follow ``vkey`` and no domain extended at run time sorts before the domain of a
        named element (an element of a domain not declared in the spec counts as inside ``r``)."""
        from ..semantics.analysis import is_subdomain
        from ..semantics.values import vkey
        root = T.root(r)
        names = {d.name for d in self.spec.domains if isinstance(d, T.Domain)}
        inside = {d.name for d in self.spec.domains if isinstance(d, T.Domain) and is_subdomain(d, root)}
        inside.add(root.name)
        named = [e for e in self.codec.abstract_ids if e.domain in inside or e.domain not in names]
        if sorted(named, key=vkey) != sorted(named, key=lambda e: self.codec.abstract_ids[e]):
            return False
        grown = [d for d in self.dyn if d in inside]
        return not any(a < e.domain for a in grown for e in named)

    def t_DomainTerm(self, t, env):
        d = t.domain
        if self.dyn_values(d):
            vals = self.dyn_values(d)
            arr, m, q, x = self.fresh("e"), self.fresh("m"), self.fresh("q"), self.fresh("x")
            return (f"({{ V {arr}[{len(vals)}]; int {m} = 0; {self.range_head(t, vals, q, x)} {arr}[{m}++] = {x}; }} "
                    f"set_make(c, {arr}, {m}); }})")
        if isinstance(d, T.Domain) and d.dynamic and self.grows(d):
            raise Unsupported(f"the dynamic domain {d} as a value")
        vals = self.values_of(d)
        if not self.composite(T.Struct("Powerset", (d,))):
            raise Unsupported(f"the domain {d} as a value")
        return self.codec.literal(SetV(vals))

    def t_Compr(self, t, env):
        if t.kind not in ("set", "seq", "bag", "map") or (t.body2 is not None) != (t.kind == "map") \
                or not self.composite(t.type):
            raise Unsupported(f"a {t.kind} comprehension")
        env = dict(env)
        heads = []
        for v, rg in t.bindings:
            q, name = self.fresh("q"), self.fresh("x")
            # a map's later pair of a key wins: its pairs are made in the Python engine's order
            heads.append(self.loop_head(rg, env, name, q, t.kind in ("set", "bag")))
            env[v.uid] = name
        guard = self.term(t.guard, env) if t.guard is not None else "(V)1"
        body = self.term(t.body, env)
        buf, n, g = self.fresh("cb"), self.fresh("cn"), self.fresh("g")
        if t.kind == "map":
            body2 = self.term(t.body2, env)
            add = (f"if ({n} >= (1 << 13)) fail(c, E_UNSUPPORTED, 0); "
                   f"else {{ {buf}[2 * {n}] = {body}; {buf}[2 * {n} + 1] = {body2}; {n}++; }}")
        else:
            add = f"if ({n} >= (1 << 14)) fail(c, E_UNSUPPORTED, 0); else {buf}[{n}++] = {body};"
        make = {"set": f"set_make(c, {buf}, {n})", "seq": f"v_intern(c, K_SEQ, {buf}, {n})",
                "bag": f"bag_make(c, {buf}, {n})", "map": f"mapv_make(c, {buf}, {n})"}[t.kind]
        # the buffer is static: a body that reaches the same comprehension again (a recursive
        # derived function) would overwrite it, so that is left to the Python engine
        return ("({ " + f"static _Thread_local V {buf}[1 << 14]; static _Thread_local int busy_{buf} = 0; int {n} = 0; "
                f"if (busy_{buf}) fail(c, E_UNSUPPORTED, 0); busy_{buf} = 1; " + " ".join(heads) +
                f" V {g} = {guard}; if ({g} == UNDEF) fail(c, E_MODEL, 0); "
                f"else if ({g}) {{ {add} }} "
                + "}" * len(heads) + f" busy_{buf} = 0; {make}; }})")

    def t_Quant(self, t, env):
        env = dict(env)
        heads = []
        for v, r in t.bindings:
            q = self.fresh("q")
            name = self.fresh("x")
            heads.append(self.loop_head(r, env, name, q, True))
            env[v.uid] = name
        guard = self.term(t.guard, env) if t.guard is not None else "(V)1"
        res = self.fresh("res")
        g = self.fresh("g")
        code = [f"V {res} = {1 if t.kind == 'forall' else 0}; int n_{res} = 0;"]
        for h in heads:
            code.append(h)
        code.append(f"V {g} = {guard}; if ({g} == UNDEF) {{ fail(c, E_UNDEF_GUARD, 0); }}")
        if t.kind == "forall":
            code.append(f"if ({g} == 0) {{ {res} = 0; goto end_{res}; }}")
        elif t.kind == "exists":
            code.append(f"if ({g} == 1) {{ {res} = 1; goto end_{res}; }}")
        else:
            code.append(f"if ({g} == 1) {{ n_{res}++; if (n_{res} > 1) goto end_{res}; }}")
        code.append("}" * len(heads))
        code.append(f"end_{res}: ;")
        if t.kind == "exists_unique":
            code.append(f"{res} = (n_{res} == 1);")
        code.append(f"{res};")
        return "({ " + " ".join(code) + " })"

    # -------------------------------------------------------------- rules
    def rule(self, r: ir.Rule, env: dict) -> str:
        meth = getattr(self, "r_" + type(r).__name__, None)
        if meth is None:
            raise Unsupported(f"the rule {type(r).__name__} at {r.span.short() if r.span else '?'}")
        return meth(r, env)

    def r_Skip(self, r, env):
        return ";"

    def layout_local(self) -> None:
        """Slots for each local function (``local x : D [init] body`` in a rule; see r_LocalRule)
        over finite argument domains: its updates never leave the rule, so the stored states hold
        it undef, and the working state holds the values of the call running."""
        for f in getattr(self.spec, "local_functions", ()) or ():
            if self.any_typed(f.codomain):
                continue
            try:
                cod = self.codomain_values(f)
                arg_values = [self.values_of(d) for d in f.domain]
                if math.prod(len(vals) for vals in arg_values) > LOCAL_SLOTS:
                    raise Unsupported("more locations than the slots of a local function")
            except Unsupported:
                if f.arity and self.map_function(f):
                    # over an infinite domain: its locations are one map value (see r_LocalRule)
                    s_ = len(self.slots)
                    self.slot_of[("map", f.index)] = s_
                    self.slots.append(("map", f.index))
                    self.slot_values.append(None)
                    self.slot_types.append(("map", f))
                    self.map_slot[f.index] = s_
                continue
            combos = [()]
            for vals in arg_values:
                combos = [c + (v,) for c in combos for v in vals]
            base = len(self.slots)
            for combo in combos:
                key = f.index if not combo else (f.index, combo)
                self.slot_of[key] = len(self.slots)
                self.slots.append(key)
                self.slot_values.append(cod)
                self.slot_types.append(f.codomain)
            self.fn_base[f.index] = (base, arg_values, cod)

    def local_slot(self, key) -> bool:
        """Is ``key`` (a slot's location key) one of a local function's slots?"""
        fi = key if type(key) is int else key[1] if key[0] == "map" else key[0]
        return type(fi) is int and fi >= len(self.spec.functions)

    def local_drop(self) -> str:
        """C: take the updates of the slots ``lo`` .. ``hi - 1`` made at or after ``mark`` out of the
        update buffer (a local function's updates stay in its rule), the others moved up in order."""
        if "local_drop" not in self.defined_done:
            self.defined_done.add("local_drop")
            self.funcs.append(
                "static void local_drop(Ctx *c, int32_t mark, int lo, int hi, int vm) {\n"
                "    static _Thread_local int32_t moved[MAXUPD];\n"
                "    int32_t w = mark;\n"
                "    for (int32_t i = mark; i < c->nupd; i++) {\n"
                "        int s = c->upd_slot[i];\n"
                "        if ((s >= lo && s < hi) || (s >= NSLOTS && c->vs_slot[s - NSLOTS] == vm)) { moved[i - mark] = -1; continue; }\n"
                "        int32_t q = c->uprev[i];\n"
                "        if (q >= mark) q = moved[q - mark];\n"
                "        moved[i - mark] = w;\n"
                "        c->upd_slot[w] = s; c->upd_code[w] = c->upd_code[i]; c->ustamp[w] = c->ustamp[i];\n"
                "        c->uprev[w] = q; c->uagent[w] = c->uagent[i];\n"
                "        c->wpos[s] = w; w++;\n"
                "    }\n"
                "    c->nupd = w;\n"
                "}\n"
                "/* a local function's initial rule: its updates (of any location) are written to the working\n"
                " * state, logged so that the end of the local rule restores what they overwrote, and taken\n"
                " * out of the update buffer */\n"
                "static void local_init_apply(Ctx *c, int32_t mark) {\n"
                "    for (int32_t i = mark; i < c->nupd; i++) {\n"
                "        int s = c->upd_slot[i];\n"
                "        if (c->nlog >= MAXUPD) { fail(c, E_UNSUPPORTED, 0); return; }\n"
                "        if (s >= NSLOTS) {\n"
                "            int m = c->vs_slot[s - NSLOTS];\n"
                "            c->rlog_slot[c->nlog] = m; c->rlog_val[c->nlog] = c->cur[m]; c->nlog++;\n"
                "            c->cur[m] = map_put(c, c->cur[m], c->vs_key[s - NSLOTS], c->upd_code[i]);\n"
                "            continue;\n"
                "        }\n"
                "        c->rlog_slot[c->nlog] = s; c->rlog_val[c->nlog] = c->cur[s]; c->nlog++;\n"
                "        c->cur[s] = slot_decode(s, c->upd_code[i]);\n"
                "    }\n"
                "    seq_step_drop(c, mark);\n"
                "}")
        return "local_drop"

    def r_LocalRule(self, r, env):
        """``local x : D [init] body``, as the Python engine runs it: ``init`` runs on the working
        state as an update set of its own, and its updates (of x or of any other location) are
        written to a copy of the working state the body runs on, not made; the body's updates of
        x are dropped when it ends, the others are made in parallel with the rule's siblings; the
        working state is then the caller's again (a recursive rule has one x per call).  x's
        slots are hidden from the caller's updates of them while the rule runs."""
        f = r.func
        if (f.index not in self.fn_base and f.index not in self.map_slot) or _has_extend(r.init):
            raise Unsupported(f"the local function {f.name} at {r.span.short() if r.span else '?'} (a location of "
                              f"one call of its rule, which the native state has no slot for: a codomain Any, a codomain Real "
                              f"over an infinite domain or more than {LOCAL_SLOTS} locations, or extend in its initial rule)")
        if f.index in self.map_slot:
            return self.local_map_rule(r, env)
        base, arg_values, _ = self.fn_base[f.index]
        n = 1
        for vals in arg_values:
            n *= len(vals)
        v = self.fresh("lr")
        drop = self.local_drop()
        gen = f"lr_gen{f.index}"
        if gen not in self.defined_done:
            self.defined_done.add(gen)
            self.funcs.append(f"static _Thread_local uint32_t {gen} = 0;   /* the run of the step that last entered it */")
        init = self.rule(r.init, env)
        # the first call of a run finds x undef, as every stored state holds it (a run that failed
        # inside the rule left its values in the working state)
        return (f"{{ if ({gen} != c->gen) {{ {gen} = c->gen; for (int i = 0; i < {n}; i++) c->cur[{base} + i] = UNDEF; }} "
                f"V cv_{v}[{n}]; uint32_t wg_{v}[{n}]; int32_t wp_{v}[{n}]; "
                f"for (int i = 0; i < {n}; i++) {{ cv_{v}[i] = c->cur[{base} + i]; wg_{v}[i] = c->wgen[{base} + i]; "
                f"wp_{v}[i] = c->wpos[{base} + i]; c->wgen[{base} + i] = c->gen - 1; }} "
                f"int32_t mk_{v} = c->nupd, lm_{v} = c->nlog, ss_{v} = c->seqstart, st_{v} = c->curstep; "
                f"c->seqstart = c->nupd; c->curstep = ++c->stepctr; "
                f"{{ {init} }} "
                f"c->seqstart = ss_{v}; c->curstep = st_{v}; if (c->err) return; "
                f"local_init_apply(c, mk_{v}); if (c->err) return; "
                f"{{ {self.rule(r.body, env)} }} "
                f"while (c->nlog > lm_{v}) {{ c->nlog--; c->cur[c->rlog_slot[c->nlog]] = c->rlog_val[c->nlog]; }} "
                f"{drop}(c, mk_{v}, {base}, {base + n}, -1); "
                f"for (int i = 0; i < {n}; i++) {{ c->cur[{base} + i] = cv_{v}[i]; c->wgen[{base} + i] = wg_{v}[i]; "
                f"c->wpos[{base} + i] = wp_{v}[i]; }} "
                f"if (c->err) return; }}")

    def local_map_rule(self, r, env) -> str:
        """r_LocalRule for a local function over an infinite domain, held as a map value in slot m
        (its locations updated in a step are virtual slots of m): the caller's virtual slots of m
        are hidden while the rule runs (their slot number is made negative, one number per depth
        of calls), and those the call made are retired when it ends."""
        f = r.func
        m = self.map_slot[f.index]
        v = self.fresh("lr")
        drop = self.local_drop()
        gen, dep = f"lr_gen{f.index}", f"lr_dep{f.index}"
        if gen not in self.defined_done:
            self.defined_done.add(gen)
            self.funcs.append(f"static _Thread_local uint32_t {gen} = 0;   /* the run of the step that last entered it */\n"
                              f"static _Thread_local int {dep} = 0;        /* calls of its rule running */")
        init = self.rule(r.init, env)
        hide = f"(-2 - ({m} * 64 + {dep}))"
        return (f"{{ if ({gen} != c->gen) {{ {gen} = c->gen; {dep} = 0; }} "
                f"if ({dep} >= 63) {{ fail(c, E_UNSUPPORTED, 0); return; }} "
                f"V cv_{v} = c->cur[{m}]; int32_t nv_{v} = c->nvs; "
                f"for (int i = 0; i < nv_{v}; i++) if (c->vs_slot[i] == {m}) c->vs_slot[i] = {hide}; "
                f"{dep}++; "
                f"int32_t mk_{v} = c->nupd, lm_{v} = c->nlog, ss_{v} = c->seqstart, st_{v} = c->curstep; "
                f"c->seqstart = c->nupd; c->curstep = ++c->stepctr; "
                f"{{ {init} }} "
                f"c->seqstart = ss_{v}; c->curstep = st_{v}; if (c->err) return; "
                f"local_init_apply(c, mk_{v}); if (c->err) return; "
                f"{{ {self.rule(r.body, env)} }} "
                f"while (c->nlog > lm_{v}) {{ c->nlog--; c->cur[c->rlog_slot[c->nlog]] = c->rlog_val[c->nlog]; }} "
                f"{drop}(c, mk_{v}, 0, 0, {m}); "
                f"{dep}--; "
                f"for (int i = nv_{v}; i < c->nvs; i++) if (c->vs_slot[i] == {m}) c->vs_slot[i] = -1; "
                f"for (int i = 0; i < nv_{v}; i++) if (c->vs_slot[i] == {hide}) c->vs_slot[i] = {m}; "
                f"c->cur[{m}] = cv_{v}; "
                f"if (c->err) return; }}")

    def r_Update(self, r, env):
        f = r.func
        if f.index in getattr(self, "lazy_init", ()):
            return self.update_location(f, [self.term(a, env) for a in r.args], self.term(r.value, env))
        if f is self.spec.result_func and f.index in self.fn_base:
            # a turbo return reads the value of result its call gave (see r_TurboReturn)
            args = [self.term(a, env) for a in r.args]
            if "res_written" not in self.defined_done:
                self.defined_done.add("res_written")
                self.funcs.append("static _Thread_local int res_written = 0;   /* the call running updated result */")
            return "{ " + self.update_location(f, args, self.term(r.value, env)) + " res_written = 1; }"
        if self.any_slot(f):
            args = [self.term(a, env) for a in r.args]
            v = self.fresh("v")
            s = self.fresh("lsl")
            self.reader(f)
            return (f"{{ V {v} = {self.any_term(r.value, env)}; int {s} = sl{f.index}(c{''.join(', ' + a for a in args)}); "
                    f"if ({s} < 0) fail(c, E_UNSUPPORTED, 0); else upd(c, {s}, {v}, 0); }}")
        if f.index in self.map_slot:
            pre, args = self.ordered_terms(r.args, env)
            v = self.fresh("v")
            return (f"{{ V {v} = {self.term(r.value, env)}; {pre} int lsl_{v} = vslot(c, {self.map_slot[f.index]}, "
                    f"{self.map_key(f, args)}); if (lsl_{v} >= 0) upd(c, lsl_{v}, {v}, 0); if (c->err) return; }}")
        if f.index not in self.fn_base:
            raise Unsupported(f"an update of {f.name}")
        pre, args = self.ordered_terms(r.args, env)
        v = self.fresh("v")
        s = self.fresh("lsl")
        self.reader(f)
        enc = self.encoder(f)
        # a location outside the layout (an argument outside its domain, undef) made undef leaves the
        # state as it is in the Python engine too (unless a step property may ask whether it was updated)
        keep = f"{v} != UNDEF" if not self.step_props else "1"
        return (f"{{ V {v} = {self.term(r.value, env)}; {pre} int {s} = sl{f.index}(c{''.join(', ' + a for a in args)}); "
                f"if ({s} < 0) {{ if ({keep}) fail(c, E_UNSUPPORTED, {self.outside_site(f)}); }} else upd(c, {s}, {enc}(c, {v}, 0), 0); }}")

    def outside_site(self, f) -> int:
        """The run-time refusal of an update of ``f`` at arguments outside the layout: the Python
        engine keeps such a location (an argument undef or outside its domain) in the state."""
        if f.kind == "local":
            # (its locations are the call's own: no layout with more slots would hold them)
            local_sites = self.__dict__.setdefault("_local_outside_sites", {})
            if f.index not in local_sites:
                local_sites[f.index] = self.runtime_site(
                    f"an update of the local function {f.name} at an argument undef or outside its domain")
            return local_sites[f.index]
        sites = self.__dict__.setdefault("_outside_sites", {})
        if f.index not in sites:
            sites[f.index] = self.runtime_site(
                f"an update of {f.name} at an argument undef or outside its domain (the Python engine keeps "
                f"such a location in the state; the native layout has slots for the domains' elements only)")
        return sites[f.index]

    def update_location(self, f, args: list, value: str) -> str:
        """The update of the location ``f(args)`` (the arguments' and the value's C code)."""
        if f.index in self.map_slot:
            v = self.fresh("v")
            if f.index in getattr(self, "lazy_init", ()):
                # undef in a lazily initialised location is kept apart from "never updated" by
                # the Python engine; the map cannot hold it
                value = f"({{ V lz_{v} = {value}; if (lz_{v} == UNDEF) fail(c, E_UNSUPPORTED, 0); lz_{v}; }})"
            return (f"{{ V {v} = {value}; int lsl_{v} = vslot(c, {self.map_slot[f.index]}, "
                    f"{self.map_key(f, args)}); if (lsl_{v} >= 0) upd(c, lsl_{v}, {v}, 0); if (c->err) return; }}")
        if f.index not in self.fn_base:
            raise Unsupported(f"an update of {f.name}")
        v = self.fresh("v")
        s = self.fresh("lsl")
        self.reader(f)
        enc = self.encoder(f)
        return (f"{{ V {v} = {value}; int {s} = sl{f.index}(c{''.join(', ' + a for a in args)}); "
                f"if ({s} < 0) fail(c, E_UNSUPPORTED, 0); else upd(c, {s}, {enc}(c, {v}, 0), 0); }}")

    def r_UpdateVar(self, r, env):
        uid = r.var.uid
        name = env.get(uid)
        if isinstance(name, ByName):
            if name.loc is None:
                # the Python engine rebinds the parameter to the value: not followed here
                raise Unsupported(f"an update of the rule parameter {r.var.name} passed by name")
            # a macro parameter bound to a location: the update is one of that location, whose
            # arguments are evaluated in the caller's scope (as the Python engine does)
            f, args = name.loc
            return self.update_location(f, args, self.term(r.value, env))
        # a parameter of a translated rule was passed by value (a location argument whose rule
        # updates the parameter is substituted in place, see r_CallRule): a local rebinding
        if name is None:
            raise Unsupported("a variable bound outside the translated code")
        v = self.fresh("uv")
        return f"{{ V {v} = {self.term(r.value, env)}; if (c->err) return; {name} = {v}; }}"

    def r_Block(self, r, env):
        if r.kind == "par":
            return "{ " + " ".join(self.rule(x, env) for x in r.rules) + " }"
        f = self.fresh("sf")
        # (the last step's updates are not written into the working state: the end of the block
        # restores what the steps wrote there at once, and nothing reads it in between)
        steps = " ".join(f"seq_step_begin(c); {{ {self.rule(x, env)} }} if (c->err) {{ seq_end(c, &{f}); return; }} "
                         f"seq_step_end(c, &{f});" for x in r.rules[:-1])
        last = f"seq_step_begin(c); {{ {self.rule(r.rules[-1], env)} }}" if r.rules else ""
        return f"{{ SeqFrame {f}; seq_begin(c, &{f}); {steps} {last} seq_end(c, &{f}); if (c->err) return; }}"

    def r_Loop(self, r, env):
        f = self.fresh("sf")
        n = self.fresh("n")
        mark = self.fresh("mk")
        body = self.rule(r.body, env)
        if r.cond is not None:
            g = self.fresh("g")
            test = (f"V {g} = {self.term(r.cond, env)}; if (c->err) break; "
                    f"if ({g} == UNDEF) {{ fail(c, E_MODEL, 0); break; }} if (!{g}) break;")
            idle = ""
        else:
            test = ""
            idle = f"if (seq_step_idle(c, &{f}, {mark})) {{ seq_step_drop(c, {mark}); break; }}"
        return (f"{{ SeqFrame {f}; seq_begin(c, &{f}); int {n} = 0; "
                f"for (;; {n}++) {{ if ({n} >= {int(self.m.max_loop)}) {{ fail(c, E_MODEL, 0); break; }} {test} "
                f"seq_step_begin(c); int32_t {mark} = c->nupd; {{ {body} }} if (c->err) break; {idle} "
                f"seq_step_end(c, &{f}); if (c->err) break; }} "
                f"seq_end(c, &{f}); if (c->err) return; }}")

    def r_TermCall(self, r, env):
        t = r.term
        if isinstance(t, ir.RuleRef):
            rd = t.rule
            if len(r.args) != len(rd.params):
                raise Unsupported("a rule value called with the wrong number of arguments")
            self.check_by_name(rd, r.args)
            name = self.rule_fn(rd)
            args = [self.term(a, env) for a in r.args]
            return f"{name}(c{''.join(', ' + a for a in args)}); if (c->err) return;"
        if isinstance(t, ir.Call) and t.name == "program" and not r.args:
            x = self.fresh("ag")
            sv = self.fresh("sv")
            parts = [f"{{ V {x} = {self.term(t.args[0], env)}; if (c->err) return; V {sv} = c->self; "
                     f"if ({x} == UNDEF) {{ fail(c, E_MODEL, 0); return; }}"]
            first = True
            for dom, ag in self.m.agent_programs.items():
                if ag.rule.params:
                    raise Unsupported("an agent program with parameters")
                vals = self.values_of(dom)
                tab = self.table(vals)
                q = self.fresh("q")
                fn = self.rule_fn(ag.rule)
                kw = "if" if first else "else if"
                parts.append(f"{kw} (({{ int {q} = 0; while ({q} < {len(vals)} && {tab}[{q}] != {x}) {q}++; "
                             f"{q} < {len(vals)}; }})) {{ c->self = {x}; {fn}(c); c->self = {sv}; }}")
                first = False
            parts.append(("else " if not first else "") + "fail(c, E_MODEL, 0);")
            parts.append("if (c->err) return; }")
            return " ".join(parts)
        return self.call_rule_value(r, env)

    def referenced_rules(self) -> list:
        """Every rule written as a value (``<<r>>``) in the spec, in a fixed order."""
        if getattr(self, "_referenced", None) is not None:
            return self._referenced
        out: list = []
        seen: set = set()
        todo: list = [rd.body for rd in self.spec.rules]
        todo += [f.body for f in self.spec.functions if f.body is not None]
        for init in self.spec.inits:
            todo += [term for _, _, term, _ in init.functions]
        while todo:
            x = todo.pop()
            if isinstance(x, ir.RuleRef):
                if id(x.rule) not in seen:
                    seen.add(id(x.rule))
                    out.append(x.rule)
            if isinstance(x, (ir.Term, ir.Rule)):
                todo.extend(vars(x).values())
            elif isinstance(x, (list, tuple)):
                todo.extend(x)
        out.sort(key=lambda rd: (rd.qualname, rd.span.short() if rd.span else ""))
        self._referenced = out
        return out

    def call_rule_value(self, r, env):
        """``t[args]`` for a term ``t`` whose value is a rule: one branch per rule written as a
        value in the spec that takes as many arguments (anything else is the Python engine's
        run-time error); the arguments are passed by value, as the Python engine passes them."""
        rt = T.root(r.term.type) if r.term.type is not None else None
        if not (isinstance(rt, T.Struct) and rt.kind == "Rule"):
            raise Unsupported("a rule called through a term other than program(agent) or a rule name")
        x = self.fresh("rv")
        args = [self.term(a, env) for a in r.args]
        avs = [self.fresh("ra") for _ in args]
        parts = [f"{{ V {x} = {self.term(r.term, env)}; if (c->err) return;"]
        parts += [f"V {n} = {a}; if (c->err) return;" for n, a in zip(avs, args)]
        first = True
        for rd in self.referenced_rules():
            if len(rd.params) != len(args):
                continue
            code = self.codec.to_c(RuleValue(rd))
            fn = self.rule_fn(rd)
            kw = "if" if first else "else if"
            parts.append(f"{kw} ({x} == {code}LL) {{ {fn}(c{''.join(', ' + a for a in avs)}); }}")
            first = False
        parts.append(("else " if not first else "") + "fail(c, E_MODEL, 0);")
        parts.append("if (c->err) return; }")
        return " ".join(parts)

    def check_by_name(self, rd, args):
        from ..semantics.analysis import has_sequencing as _has_sequencing, is_simple as _is_simple
        if any(not _is_simple(a) for a in args) and _has_sequencing(rd):
            raise Unsupported(f"an argument passed by name to {rd.name}, which has sequencing")

    def r_If(self, r, env):
        g = self.fresh("g")
        then = self.rule(r.then, env)
        other = self.rule(r.other, env) if r.other is not None else ";"
        return f"{{ V {g} = {self.term(r.cond, env)}; if (c->err) return; if (guard(c, {g}, 0)) {{ {then} }} else {{ {other} }} }}"

    def r_SwitchRule(self, r, env):
        s = self.fresh("s")
        parts = [f"{{ V {s} = {self.term(r.subject, env)};"]
        first = True
        for cs, body in r.cases:
            kw = "if" if first else "else if"
            parts.append(f"{kw} ({s} == {self.term(cs, env)}) {{ {self.rule(body, env)} }}")
            first = False
        if r.other is not None:
            parts.append(f"{'else ' if not first else ''}{{ {self.rule(r.other, env)} }}")
        parts.append("}")
        return " ".join(parts)

    def r_LetRule(self, r, env):
        env = dict(env)
        decls = []
        for v, x in r.bindings:
            name = self.fresh("l")
            decls.append(f"V {name} = {self.term(x, env)};")
            env[v.uid] = name
        return "{ " + " ".join(decls) + " " + self.rule(r.body, env) + " }"

    def makes_choices(self, x, seen=None) -> bool:
        """Could running the rule ``x`` make a choice (a choose, a monitored read, a rule value)?"""
        seen = set() if seen is None else seen
        todo = [x]
        while todo:
            y = todo.pop()
            if isinstance(y, (ir.Choose, ir.TermCall)):
                return True
            if isinstance(y, ir.Loc) and (y.func.kind == "monitored" or (
                    y.func.body is not None and y.func not in seen and (seen.add(y.func) or True)
                    and self.makes_choices(y.func.body, seen))):
                return True
            if isinstance(y, (ir.CallRule, ir.TurboReturn)):
                rd = y.rule if isinstance(y, ir.CallRule) else y.call.rule
                if rd not in seen:
                    seen.add(rd)
                    todo.append(rd.body)
            if isinstance(y, (ir.Rule, ir.Term)):
                todo.extend(v for v in vars(y).values() if isinstance(v, (ir.Rule, ir.Term, list, tuple)))
            elif isinstance(y, (list, tuple)):
                todo.extend(z for z in y if isinstance(z, (ir.Rule, ir.Term, list, tuple)))
        return False

    def r_Forall(self, r, env):
        env = dict(env)
        heads = []
        # the body's choices follow the order of the elements: then it must be the Python engine's
        any_order = not self.makes_choices(r.body)
        for v, rg in r.bindings:
            q = self.fresh("q")
            name = self.fresh("x")
            heads.append(self.loop_head(rg, env, name, q, any_order))
            env[v.uid] = name
        g = self.fresh("g")
        guard = self.term(r.guard, env) if r.guard is not None else "(V)1"
        body = self.rule(r.body, env)
        return ("{ " + " ".join(heads) +
                f" V {g} = {guard}; if (guard(c, {g}, 0)) {{ {body} }} if (c->err) return; " + "}" * len(heads) + " }")

    def r_Choose(self, r, env):
        if self.mergeable(r, env):
            return self.choose_merged(r, env)
        try:
            for _, rg in r.bindings:
                self.range_values(rg)
        except Unsupported:
            return self.choose_at_run_time(r, env)
        env2 = dict(env)
        heads = []
        sizes = 1
        names = []
        for v, rg in r.bindings:
            vals = self.range_values(rg)
            tab = self.table(vals)
            q = self.fresh("q")
            name = self.fresh("x")
            env2[v.uid] = name
            names.append(name)
            sizes *= max(len(vals), 1)
            heads.append(self.range_head(rg, vals, q, name))
        if sizes > MAX_CANDIDATES:
            raise Unsupported("a choose over too many candidates")
        k = len(names)
        cand = self.fresh("cand")
        n = self.fresh("n")
        g = self.fresh("g")
        guard = self.term(r.guard, env2) if r.guard is not None else "(V)1"
        i = self.fresh("i")
        body, ifnone, pick, store = self.choose_parts(r, env, names, cand, n, i)
        # (the thread's own list and cache marks are one thread-local record, reached through a
        # pointer taken once: each use of a thread-local variable of a shared library is a call)
        tl = self.fresh("tl")
        fields, pre, post = self.candidate_cache(tl, n)
        decl = (f"static _Thread_local struct {{ V cand[{sizes * k}]; {fields} }} {tl} = {{ .ep = -1 }}; "
                f"__typeof__({tl}) *p_{tl} = &{tl}; TLS_KEEP(p_{tl}); V *{cand} = p_{tl}->cand; ")
        return ("{ " + decl + f"int {n} = 0; " + pre + " ".join(heads) +
                f" V {g} = {guard}; if (guard(c, {g}, 0)) {{ {store} {n}++; }} if (c->err) return; " + "}" * len(heads)
                + post +
                f" if ({n} == 0) {{ {ifnone} }} else {{ int {i} = {n} > 1 ? choice(c, {n}) : 0; {pick} {body} }} }}")

    CACHE_PREFIX = 8      # the longest sequence of earlier choices a choose's candidate cache keeps

    def candidate_cache(self, tl: str, n: str) -> tuple[str, str, str]:
        """(fields, pre, post): C that keeps a choose's candidates (count ``n``, in the record
        ``tl``) for the later runs of the step from the same state.  One run of the step is
        a function of the state and of the choices it has made so far, so the candidates a
        choose collects at its first visit in a run are those of any other run from the same
        state (``c->epoch``) that reached its first visit after the same choices (the first
        ``pos0`` of ``c->idx``): the list is reused when both are the same as when it was made,
        the choices being kept when there are at most :data:`CACHE_PREFIX` of them.  A later
        visit in one run (a rule called twice in a seq block, a loop, a forall) may meet other
        variables or another working state: it makes the list again and the cache forgets it.
        A list whose making took a choice (a monitored value read first there) is not kept."""
        ep, cn, lg, pn, px = (f"p_{tl}->{x}" for x in ("ep", "cn", "lg", "pn", "px"))
        first = self.fresh("first")
        P = self.CACHE_PREFIX
        fields = f"int64_t ep; int cn; uint32_t lg; int pn; int32_t px[{P}];"
        pre = (f"int pos0 = c->pos; "
               f"int {first} = {lg} != c->gen; {lg} = c->gen; if (!{first}) {ep} = -1; "
               f"if ({first} && {ep} == c->epoch && {pn} == pos0 && cache_prefix_is(c, {px}, pos0)) "
               f"{{ {n} = {cn}; }} else {{ ")
        post = (f" if (c->pos == pos0 && pos0 <= {P} && {first}) {{ {ep} = c->epoch; {cn} = {n}; {pn} = pos0; "
                f"for (int q = 0; q < pos0; q++) {px}[q] = c->idx[q]; }} }}")
        return fields, pre, post

    def choose_parts(self, r, env, names, cand, n, i):
        """What both translations of a choose share: its body (the bound variables read from the
        candidate picked), its ifnone rule, the C that copies candidate ``i`` out of ``cand`` and
        the C that stores the current binding ``names`` as candidate ``n``."""
        k = len(names)
        body_env = dict(env)
        bound = []
        for v, _ in r.bindings:
            nm = self.fresh("b")
            body_env[v.uid] = nm
            bound.append(nm)
        body = self.rule(r.body, body_env)
        ifnone = self.rule(r.ifnone, env) if r.ifnone is not None else ";"
        pick = " ".join(f"V {bound[j]} = {cand}[{i} * {k} + {j}];" for j in range(k))
        store = " ".join(f"{cand}[{n} * {k} + {j}] = {names[j]};" for j in range(k))
        return body, ifnone, pick, store

    # -------------------------------------------------------------- choose, merged by effect
    MERGE_RULES = (ir.Skip, ir.Update, ir.Block, ir.If, ir.SwitchRule, ir.LetRule, ir.Forall, ir.CallRule)

    def mergeable(self, r, env) -> bool:
        """Can the choose ``r`` be translated as the Python engine enumerates it: one alternative
        per distinct effect of its body (``choose_merged``)?  Its body must make no choice (no
        choose, monitored read or rule value: its effect is then its update set alone), update only
        locations whose codes are equal exactly when the values are (no Real, no value of type
        Any, no map of locations) and change nothing but the update set (no extend, no update of a
        variable, no turbo return, no loop); no variable in scope may be passed by name."""
        if not getattr(self.m, "dedupe", True):
            return False
        if self.step_chooses() < 2:
            # one choose a run: its candidates are the sequences of choices, with no product to
            # keep small, and the search's table merges the successors with the same effect
            return False
        if any(isinstance(v, ByName) or not isinstance(v, str) for v in env.values()):
            return False
        if self.makes_choices(r.body):
            return False
        seen = set()
        todo = [r.body]
        while todo:
            x = todo.pop()
            if not isinstance(x, self.MERGE_RULES):
                return False
            if isinstance(x, ir.Update):
                f = x.func
                if (f.index not in self.fn_base or f.index in self.map_slot or self.any_slot(f)
                        or f is self.spec.result_func or _holds_real(f.codomain)):
                    return False
            elif isinstance(x, ir.CallRule):
                if x.rule not in seen:
                    seen.add(x.rule)
                    todo.append(x.rule.body)
            elif isinstance(x, ir.Block):
                todo.extend(x.rules)
            elif isinstance(x, ir.If):
                todo.extend(y for y in (x.then, x.other) if y is not None)
            elif isinstance(x, ir.SwitchRule):
                todo.extend(b for _, b in x.cases)
                if x.other is not None:
                    todo.append(x.other)
            elif isinstance(x, (ir.LetRule, ir.Forall)):
                todo.append(x.body)
        return True

    def step_chooses(self) -> int:
        """How many chooses one run of the step can pass: 0, 1, or 2 for two or more (a choose
        in a loop, a forall or another choose's body, in two branches of a block, or behind a
        rule value)."""
        got = getattr(self, "_step_chooses", None)
        if got is not None:
            return got
        active: set = set()

        def runs(x) -> int:
            if x is None or isinstance(x, (ir.Skip, ir.Update, ir.UpdateVar)):
                return 0
            if isinstance(x, ir.Choose):
                return min(2, 1 + runs(x.body) + runs(x.ifnone))
            if isinstance(x, (ir.Forall, ir.Loop)):
                return 2 if runs(x.body) else 0
            if isinstance(x, ir.Block):
                return min(2, sum(runs(y) for y in x.rules))
            if isinstance(x, ir.If):
                return max(runs(x.then), runs(x.other))
            if isinstance(x, ir.SwitchRule):
                return max([runs(b) for _, b in x.cases] + [runs(x.other)])
            if isinstance(x, (ir.LetRule, ir.Extend)):
                return runs(x.body)
            if isinstance(x, ir.LocalRule):
                return min(2, runs(x.init) + runs(x.body))
            if isinstance(x, ir.TurboReturn):
                return runs(x.call)
            if isinstance(x, ir.CallRule):
                if x.rule in active:
                    return 2          # a recursive call: as many runs of its body as it likes
                active.add(x.rule)
                try:
                    return runs(x.rule.body)
                finally:
                    active.discard(x.rule)
            return 2                  # a rule value (an agent's program), or a form not listed
        main = self.spec.main
        self._step_chooses = runs(main.body) if main is not None else 0
        return self._step_chooses

    def choose_merged(self, r, env):
        """A choose whose alternatives are its body's distinct effects, in the order first met,
        as the Python engine enumerates them: the body runs once per candidate with its updates
        kept apart (MChoose in _MERGE_C), and the step chooses among the distinct update sets.
        Outside seq blocks the outcomes depend only on the state, the variables in scope and self
        (when the guard and the ranges read no monitored function): they are computed once per
        expanded state and key, and reused by every later run of the step from that state."""
        if "mchoose" not in self.defined_done:
            self.defined_done.add("mchoose")
            self.funcs.append(_MERGE_C)
        env2, heads, names = self.run_time_heads(r, env)
        k = len(names)
        mc, cand, cap, n, g, i, e = (self.fresh(x) for x in ("mc", "cand", "cap", "n", "g", "i", "e"))
        # (the thread's own record, list and its size reached through pointers taken once: see TLS_KEEP)
        tl = mc
        cand, cap = f"p_{tl}->cand", f"p_{tl}->cap"
        guard = self.term(r.guard, env2) if r.guard is not None else "(V)1"
        body, ifnone, pick, store = self.choose_parts(r, env, names, cand, n, i)
        cacheable = not (r.guard is not None and self.makes_choices(r.guard)) and \
            not any(self.makes_choices(rg) for _, rg in r.bindings)
        key = list(dict.fromkeys(env.values())) + ["c->self"]
        grow = _grow_candidates(n, cand, cap, k, tl)
        collect = (f"int {n} = 0; " + " ".join(heads) +
                   f" V {g} = {guard}; if (c->err) return; if (guard(c, {g}, 0)) {{ {grow} {store} {n}++; }} "
                   f"if (c->err) return; " + "}" * len(heads) + " if (c->err) return;")
        # the body in a function of its own, so that a candidate whose body fails returns to the
        # loop: its error is an outcome (choosing it makes the step fail), as in the Python engine
        outer = list(dict.fromkeys(env.values()))
        bound = re.findall(r"V (\w+) = ", pick)
        params = list(dict.fromkeys(bound + outer))
        if all(re.fullmatch(r"[A-Za-z_]\w*", x) for x in params):
            fn = self.fresh("mcb")
            sig = "".join(f", V {x}" for x in params)
            self.funcs.append(f"static void {fn}(Ctx *c{sig}) {{ {body} }}")
            run = f"{fn}(c{''.join(', ' + x for x in params)});"
            fails = (f"if (c->err) {{ if (!mc_step_error(c->err)) {{ m_{e}->epoch = -1; return; }} "
                     f"if (!mc_outcome_err(c, m_{e}, {e}, mk_{e})) return; continue; }} ")
        else:
            run = body
            fails = f"if (c->err) {{ m_{e}->epoch = -1; return; }} "     # (no half-made entry is kept)
        outcomes = (f"int32_t mk_{e} = c->nupd, st_{e} = c->curstep, ss_{e} = c->seqstart; "
                    f"for (int {i} = 0; {i} < {n}; {i}++) {{ c->curstep = MC_STAMP; c->seqstart = -1; "
                    f"{{ {pick} {run} }} c->curstep = st_{e}; c->seqstart = ss_{e}; {fails}"
                    f"if (!mc_outcome(c, m_{e}, {e}, mk_{e})) return; }}")
        return ("{ " + f"static _Thread_local struct {{ MChoose m; V *cand; int cap; }} {tl}; __typeof__({tl}) *p_{tl} = &{tl}; "
                f"TLS_KEEP(p_{tl}); MChoose *m_{e} = &p_{tl}->m; V key_{e}[{len(key)}] = {{{', '.join(key)}}}; "
                f"int ca_{e} = {1 if cacheable else 0} && c->seqstart < 0; "
                f"int32_t {e} = ca_{e} ? mc_find(c, m_{e}, key_{e}, {len(key)}) : -1; "
                f"if ({e} < 0) {{ {collect} {e} = mc_begin(c, m_{e}, key_{e}, {len(key)}, {n}, ca_{e}); "
                f"if ({e} < 0) return; if ({n} > 0) {{ {outcomes} }} mc_commit(c, m_{e}, {e}, {len(key)}, ca_{e}); if (c->err) return; }} "
                f"{{ int32_t no_{e} = m_{e}->onum[{e}]; if (no_{e} == 0) {{ {ifnone} }} else {{ int32_t o_{e} = m_{e}->ofirst[{e}] + "
                f"(no_{e} > 1 ? choice(c, no_{e}) : 0); int32_t at_{e} = c->nupd; if (c->pos - 1 < mc_skip_from || no_{e} < 2) mc_apply(c, m_{e}, o_{e}); if (c->err) return; "
                f"if (no_{e} > 1 && c->seqstart < 0 && c->pos <= MAXCH && !m_{e}->kfail[{e}]) mc_note(c, m_{e}, {e}, o_{e}, at_{e}); }} }} }}")

    def run_time_heads(self, r, env):
        """The loop heads that walk a choose's ranges as computed at run time (in the Python
        engine's order), with the environment that binds its variables and their C names."""
        env2 = dict(env)
        heads = []
        names = []
        for v, rg in r.bindings:
            q, name = self.fresh("q"), self.fresh("x")
            heads.append(self.loop_head(rg, env2, name, q, False))
            env2[v.uid] = name
            names.append(name)
        return env2, heads, names

    def choose_at_run_time(self, r, env):
        """A choose whose ranges are computed in the state (or from variables bound before): the
        candidates are collected, in the Python engine's order, into a buffer that grows."""
        env2, heads, names = self.run_time_heads(r, env)
        k = len(names)
        cand, cap, n, g, i = self.fresh("cand"), self.fresh("cap"), self.fresh("n"), self.fresh("g"), self.fresh("i")
        tl = cand      # (the thread's buffer and its size reached through a pointer taken once: see TLS_KEEP)
        cand, cap = f"p_{tl}->cand", f"p_{tl}->cap"
        guard = self.term(r.guard, env2) if r.guard is not None else "(V)1"
        body, ifnone, pick, store = self.choose_parts(r, env, names, cand, n, i)
        grow = _grow_candidates(n, cand, cap, k, tl)
        # the buffer is static: the guard and the ranges are terms (no rule runs while it fills)
        # and the candidate is copied out before the body runs
        fields, pre, post = self.candidate_cache(tl, n)
        return ("{ " + f"static _Thread_local struct {{ V *cand; int cap; {fields} }} {tl} = {{ .ep = -1 }}; "
                f"__typeof__({tl}) *p_{tl} = &{tl}; TLS_KEEP(p_{tl}); int {n} = 0; " + pre + " ".join(heads) +
                f" V {g} = {guard}; if (c->err) return; if (guard(c, {g}, 0)) {{ {grow} {store} {n}++; }} "
                f"if (c->err) return; " + "}" * len(heads) + " if (c->err) return;" + post +
                f" if ({n} == 0) {{ {ifnone} }} else {{ int {i} = {n} > 1 ? choice(c, {n}) : 0; {pick} {body} }} }}")

    def r_CallRule(self, r, env):
        rd = r.rule
        if not r.turbo:
            from ..semantics.analysis import mentions_monitored
            modes = self.arg_modes(r, env)
            # a monitored argument is read where the body uses it (if it does), so its choice
            # comes where the Python engine makes it
            monitored = any(m == 1 and mentions_monitored(a) for a, m in zip(r.args, modes))
            if monitored and self.recursive(rd):
                raise Unsupported(f"a monitored argument passed by name to the recursive rule {rd.name}")
            if any(m == 3 and self.updates_param(rd, i) for i, m in enumerate(modes)) or (
                    any(m in (1, 3) for m in modes) and self.seq_rule(rd)) or monitored:
                return self.call_by_name(r, env, modes)
            self.check_by_name(rd, [a for a, m in zip(r.args, modes) if m != 3])
        # a turbo call passes its arguments by value
        name = self.rule_fn(rd)
        pre, args = self.ordered_terms(r.args, env)
        if pre:
            return f"{{ {pre} {name}(c{''.join(', ' + a for a in args)}); }} if (c->err) return;"
        return f"{name}(c{''.join(', ' + a for a in args)}); if (c->err) return;"

    def r_TurboReturn(self, r, env):
        """``target <- r_t(args)``: the call's updates join the step's, and the target takes the
        value the call gave ``result`` (undef when it gave none), as in the Python engine."""
        rf = self.spec.result_func
        call = self.rule(r.call, env)
        w = self.fresh("rw")
        if "res_written" not in self.defined_done:
            self.defined_done.add("res_written")
            self.funcs.append("static _Thread_local int res_written = 0;   /* the call running updated result */")
        if rf.index in self.fn_base:
            s = self.slot_of[rf.index]
            value = (f"(res_written && c->wgen[{s}] == c->gen ? slot_decode({s}, c->upd_code[c->wpos[{s}]]) : UNDEF)")
        else:
            value = "UNDEF"
        head = (f"{{ int {w} = res_written; res_written = 0; {{ {call} }} V v_{w} = {value}; "
                f"res_written = {w} | res_written; if (c->err) return;")
        tgt = r.target
        if isinstance(tgt, ir.Update):
            args = [self.term(a, env) for a in tgt.args]
            return head + " " + self.update_location(tgt.func, args, f"v_{w}") + " }"
        name = env.get(tgt.var.uid)
        if name is None or isinstance(name, ByName):
            raise Unsupported(f"a turbo return into {tgt.var.name}")
        return head + f" {name} = v_{w}; }}"

    def arg_modes(self, r, env) -> list:
        """How the Python engine passes each argument of a macro call: 0 by value, 1 by name,
        3 a location by name (an update of the parameter updates it); a variable bound to an
        argument passed by name passes it on as it is."""
        from ..semantics.analysis import is_simple, mentions_monitored
        by_name = self.seq_rule(r.rule)
        modes = []
        for a in r.args:
            if isinstance(a, ir.VarRef):
                b = env.get(a.var.uid)
                modes.append((3 if b.loc is not None else 1) if isinstance(b, ByName) else 0)
            elif isinstance(a, ir.Loc) and a.func.is_location and a.func.kind not in ("monitored", "static"):
                modes.append(3)
            elif (by_name and not is_simple(a)) or mentions_monitored(a):
                modes.append(1)
            else:
                modes.append(0)
        return modes

    def recursive(self, rd) -> bool:
        """Does ``rd`` call itself (through any chain of rule calls)?"""
        seen = set()
        todo = list(ir.called_rules(rd.body))
        while todo:
            x = todo.pop()
            if x is rd:
                return True
            if id(x) not in seen:
                seen.add(id(x))
                todo.extend(ir.called_rules(x.body))
        return False

    def seq_rule(self, rd) -> bool:
        from ..semantics.analysis import has_sequencing
        return has_sequencing(rd)

    def updates_param(self, rd, i: int, seen=None) -> bool:
        """Does the body of ``rd`` update its i-th parameter, itself or through a macro call
        that receives it?"""
        seen = set() if seen is None else seen
        if (rd, i) in seen:
            return False
        seen.add((rd, i))
        uid = rd.params[i].uid
        todo = [rd.body]
        while todo:
            x = todo.pop()
            if isinstance(x, ir.UpdateVar) and x.var.uid == uid:
                return True
            if isinstance(x, ir.CallRule) and not x.turbo:
                for j, a in enumerate(x.args):
                    if isinstance(a, ir.VarRef) and a.var.uid == uid and self.updates_param(x.rule, j, seen):
                        return True
            if isinstance(x, ir.TurboReturn):
                todo.append(x.target)
                todo.append(x.call)
            elif isinstance(x, ir.Rule):
                todo.extend(v for v in vars(x).values() if isinstance(v, (ir.Rule, list, tuple)))
            elif isinstance(x, (list, tuple)):
                todo.extend(y for y in x if isinstance(y, (ir.Rule, list, tuple)))
        return False

    def call_by_name(self, r, env, modes):
        """A macro call whose arguments the Python engine passes by name where the body sees the
        state change (seq blocks, loops) or updates a location argument through its parameter:
        the body is written in place with each such parameter standing for its argument's code
        (evaluated where the body uses it, in the caller's scope)."""
        rd = r.rule
        stack = self.__dict__.setdefault("_inlining", [])
        if rd in stack:
            raise Unsupported(f"a recursive rule {rd.name} with arguments passed by name")
        body_env = {}
        decls = []
        for p, a, m in zip(rd.params, r.args, modes):
            if m == 0:
                x = self.fresh("pv")
                decls.append(f"V {x} = {self.term(a, env)}; if (c->err) return;")
                body_env[p.uid] = x
            elif isinstance(a, ir.VarRef) and isinstance(env.get(a.var.uid), ByName):
                body_env[p.uid] = env[a.var.uid]
            elif m == 3:
                body_env[p.uid] = ByName(f"({self.term(a, env)})", (a.func, [self.term(x, env) for x in a.args]))
            else:
                body_env[p.uid] = ByName(f"({self.term(a, env)})", None)
        stack.append(rd)
        try:
            body = self.rule(rd.body, body_env)
        finally:
            stack.pop()
        return "{ " + " ".join(decls) + " { " + body + " } if (c->err) return; }"

    def rule_fn(self, rd) -> str:
        name = self.rules_done.get(rd)
        if name is not None:
            return name
        name = f"ru{len(self.rules_done)}"
        self.rules_done[rd] = name
        env = {}
        params = []
        for p in rd.params:
            self.param_uids.add(p.uid)
            v = f"p{p.uid}"
            env[p.uid] = v
            params.append(v)
        sig = "".join(f", V {p}" for p in params)
        self.funcs.append(f"static void {name}(Ctx *c{sig});")
        body = self.rule(rd.body, env)
        # the body may return early; the call that counts its depth (MAX_RECURSION) wraps it
        self.funcs.append(f"static inline void {name}_body(Ctx *c{sig}) {{ {body} }}")
        site = self.recursion_site()
        args = "".join(f", {p}" for p in params)
        self.funcs.append(f"static void {name}(Ctx *c{sig}) {{ if (++c->rdepth > {MAX_RECURSION}) {{ c->rdepth--; "
                          f"fail(c, E_UNSUPPORTED, {site}); return; }} {name}_body(c{args}); c->rdepth--; }}")
        return name

    # -------------------------------------------------------------- the whole model
    def generate(self) -> str:
        self.layout()
        main = self.rule_fn(self.spec.main)
        invs = []
        for p in self.props:
            invs.append(self.term(p.prop.body, {}))
        steps = []
        self.step_mode = True
        for p in self.step_props:
            e = self.term(p.prop.body, {})
            if type(p).__name__ == "MonitoredInvariant":
                # monitored values that break an INVAR are not inputs the spec considers
                for t in reversed(self.invars):
                    e = f"(({self.term(t, {})}) != 1 ? (V)1 : ({e}))"
            steps.append(e)
        self.step_mode = False
        invar_terms = [self.term(t, {}) for t in self.invars]
        label_exprs = self.label_code()
        for st in self.init_states:
            self.pack_values(st)
        self.codec.frozen = True
        nslots = len(self.slots)
        bits = [64 if vals is None else _ceil_log2(len(vals) + 1) for vals in self.slot_values]
        words, shifts = [], []
        # the narrow slots packed first, then one word per wide slot
        w, sh = 0, 0
        for s, b in enumerate(bits):
            if b == 64:
                continue
            if sh + b > 64:
                w += 1
                sh = 0
            words.append(w)
            shifts.append(sh)
            sh += b
        words_full = [0] * nslots
        shifts_full = [0] * nslots
        k = 0
        for s, b in enumerate(bits):
            if b != 64:
                words_full[s], shifts_full[s] = words[k], shifts[k]
                k += 1
        nxt = w + 1 if sh > 0 else w
        for s, b in enumerate(bits):
            if b == 64:
                words_full[s] = nxt
                nxt += 1
        words, shifts = words_full, shifts_full
        nwords = max(nxt, 1)
        self.words, self.shifts, self.bits = words, shifts, bits
        self.nwords = nwords
        seed = []
        for kind, elems in self.codec.comp:
            seed += [kind, len(elems), *elems]
        head = [f"#define NSEED {len(self.codec.comp)}",
                f"#define NSLOTS {nslots}", f"#define NWORDS {nwords}", f"#define NMON {self.nmon}",
                f"#define NINV {len(invs)}", f"#define NSTEP {len(steps)}", f"#define NINVAR {len(invar_terms)}"]
        rt = resources.files("asmcheck.explore").joinpath("native_rt.c").read_text()
        bfs = resources.files("asmcheck.explore").joinpath("native_bfs.c").read_text()
        tables = [f"static const int64_t SEED[] = {{{', '.join(('INT64_MIN' if x == UNDEF_V else f'{x}LL') for x in seed) or '0'}}};"]
        for key, name in self.dom_tables.items():
            vals = ", ".join("UNDEF" if x is None else f"{x}LL" for x in key) or "0"
            tables.append(f"static const V {name}[] = {{{vals}}};")
        dec_names = {}
        decs = []
        for vals in self.slot_values:
            if vals is None:
                continue
            key = tuple(self.codec.to_c(v) for v in vals)
            if key not in dec_names:
                dec_names[key] = f"DEC{len(dec_names)}"
                decs.append(f"static const V {dec_names[key]}[] = {{{', '.join('UNDEF' if x is None else f'{x}LL' for x in key)}"
                            f"{', ' if key else ''}UNDEF}};")
        layout = [
            f"static const int SLOT_WORD[{max(nslots, 1)}] = {{{', '.join(map(str, words)) or '0'}}};",
            f"static const int SLOT_SHIFT[{max(nslots, 1)}] = {{{', '.join(map(str, shifts)) or '0'}}};",
            f"static const int SLOT_BITS[{max(nslots, 1)}] = {{{', '.join(map(str, bits)) or '1'}}};",
            f"static const V *SLOT_DECODE[{max(nslots, 1)}] = {{"
            + ", ".join("0" if vals is None else dec_names[tuple(self.codec.to_c(v) for v in vals)]
                        for vals in self.slot_values) + "};",
        ]
        inv_code = ["static V check_invariant(Ctx *c, int k) {", "    switch (k) {"]
        for i, e in enumerate(invs):
            inv_code.append(f"    case {i}: return {e};")
        inv_code += ["    }", "    return 1;", "}"]
        inv_code += self.invariant_slots_table()
        inv_code += self.step_skip_table()
        inv_code += ["static V check_step_prop1(Ctx *c, int k) {", "    V r = 1;", "    c->in_prop = 1;", "    switch (k) {"]
        for i, e in enumerate(steps):
            inv_code.append(f"    case {i}: r = {e}; break;")
        inv_code += ["    }", "    c->in_prop = 0;", "    return r;", "}"]
        inv_code += ["static V check_invar1(Ctx *c, int k) {", "    V r = 1;", "    c->in_prop = 1;", "    switch (k) {"]
        for i, e in enumerate(invar_terms):
            inv_code.append(f"    case {i}: r = {e}; break;")
        inv_code += ["    }", "    c->in_prop = 0;", "    return r;", "}"]
        # every choice of the unread monitored values for a step property; one for an INVAR, both
        # before the step (with its monitored values) and after it (with none fixed)
        inv_code += ["static V check_step_prop(Ctx *c, int k) { c->mfix = 1; V r = prop_all(c, check_step_prop1, k, 0); "
                     "c->in_prop = 0; return r; }"]
        if self.invar_pre:
            inv_code += ["static V check_invar(Ctx *c, int k) {",
                         "    V *sv = c->rd; c->rd = c->cur; c->mfix = 1;",
                         "    V r = prop_all(c, check_invar1, k, 1); c->in_prop = 0; c->rd = sv;",
                         "    if (c->err || r != 1) return r;",
                         "    c->mfix = 0; r = prop_all(c, check_invar1, k, 1); c->in_prop = 0; return r;", "}"]
        else:
            inv_code += ["static V check_invar(Ctx *c, int k) { c->mfix = 0; V r = prop_all(c, check_invar1, k, 1); "
                         "c->in_prop = 0; return r; }"]
        step = [f"static void step_main(Ctx *c) {{ {main}(c); }}"]
        head.append(f"#define CN_NDYN {len(self.dyn)}")
        head.append(f"#define SYM_ON {1 if self.sym is not None else 0}")
        if "lz_note" in self.defined_done:
            step = [f"static void step_main(Ctx *c) {{ {main}(c); lz_flush(c); }}"]
        src = "\n".join(head) + "\n" + rt + "\n" + "\n".join(tables + decs + layout) + "\n" + \
            self.canon_code() + "\n" + self.sym_code() + "\n" + "\n\n".join(self.funcs) + "\n" + "\n".join(inv_code + step) + "\n" + bfs
        src += "\n" + self.label_entry(label_exprs)
        return src

    def invariant_read_slots(self, term) -> set | None:
        """The slots an invariant reads (through the derived functions it calls), or None when its
        value may depend on more than them: a monitored function, self, a lazily laid out
        function, a domain extended at run time."""
        slots_of: dict = {}
        for s, key in enumerate(self.slots):
            fi = key if type(key) is int else key[1] if type(key) is tuple and key[0] == "map" else \
                key[0] if type(key) is tuple and type(key[0]) is int else None
            if fi is not None:
                slots_of.setdefault(fi, set()).add(s)
        lazy = getattr(self.m, "lazy", ()) or ()
        dyn_names = set(self.dyn)
        out: set = set()
        seen: set = set()
        todo = [term]
        while todo:
            x = todo.pop()
            if id(x) in seen:
                continue
            seen.add(id(x))
            if isinstance(x, ir.Function):
                if x is self.spec.self_func or x.index in lazy or x.kind in ("monitored", "local"):
                    return None
                if x.kind in ("controlled", "shared", "out"):
                    out |= slots_of.get(x.index, set())
                if x.body is not None:
                    todo.append(x.body)
                continue
            if isinstance(x, ir.DomainTerm):
                d = x.domain
                for _ in range(50):
                    if getattr(d, "name", None) in dyn_names:
                        return None
                    d = getattr(d, "base", None) if getattr(d, "kind", None) == "subset" else None
                    if d is None:
                        break
            if isinstance(x, ir.Term):
                todo.extend(vars(x).values())
            elif isinstance(x, (list, tuple)):
                todo.extend(x)
        return out

    def invariant_slots_table(self) -> list:
        """The bits of the state each invariant reads: for invariant k, the pairs (INV_W[i],
        INV_M[i]) for INV_OFF[k] <= i < INV_OFF[k + 1], a word and the bits of its slots that k
        reads; INV_ALL[k] when it may read more than locations.  native_bfs.c checks an
        invariant in a state only when one of those bits differs from the parent's, where it
        held."""
        offs, ws, ms, alls = [0], [], [], []
        for p in self.props:
            sl = self.invariant_read_slots(p.prop.body)
            alls.append(1 if sl is None else 0)
            masks: dict = {}
            for s in sl or ():
                b = self.bits[s]
                masks[self.words[s]] = masks.get(self.words[s], 0) | (
                    (1 << 64) - 1 if b == 64 else ((1 << b) - 1) << self.shifts[s])
            for w in sorted(masks):
                ws.append(w)
                ms.append(masks[w])
            offs.append(len(ws))

        def arr(ctype, name, xs, suffix=""):
            return f"static const {ctype} {name}[] = {{{', '.join(f'{x}{suffix}' for x in xs) or '0'}}};"
        return [arr("int", "INV_OFF", offs), arr("int", "INV_W", ws), arr("uint64_t", "INV_M", ms, "ULL"),
                arr("int", "INV_ALL", alls)]

    def function_slots(self, f) -> set | None:
        """The slots of the locations of controlled function ``f``, or None when they are not all
        slots of their own (a function held as a map, lazily laid out, local)."""
        if f.kind not in ("controlled", "shared", "out") or f.index in self.map_slot or \
                f.index not in self.fn_base or f.index in (getattr(self.m, "lazy", ()) or ()):
            return None
        out = set()
        for s, key in enumerate(self.slots):
            fi = key if type(key) is int else key[0] if type(key) is tuple and type(key[0]) is int else None
            if fi == f.index:
                out.add(s)
        return out or None

    def quiet_term(self, t) -> bool:
        """Whether evaluating ``t`` in a step property never fails (no error, no monitored choice):
        a constant, a bound variable, a 0-ary controlled location, updated / changed of a location
        of a controlled function at such arguments, and not / and / or / implies of such terms."""
        if isinstance(t, (ir.Const, ir.VarRef)):
            return True
        if isinstance(t, ir.Loc):
            return not t.args and self.function_slots(t.func) is not None
        if isinstance(t, ir.StepOp):
            return t.op in ("updated", "changed") and isinstance(t.args[-1], ir.Loc) and \
                self.function_slots(t.args[-1].func) is not None and \
                all(isinstance(a, (ir.Const, ir.VarRef)) for a in t.args[-1].args)
        if isinstance(t, ir.Call) and t.name in ("not", "and", "or", "implies"):
            return all(self.quiet_term(a) for a in t.args)
        return False

    def false_sets(self, t) -> list | None:
        """Sets of slots such that ``t`` is false, and evaluating it fails in no way, in a step
        that updates no slot of one of them (None: none known)."""
        if isinstance(t, ir.StepOp):
            if not self.quiet_term(t):
                return None
            return [frozenset(self.function_slots(t.args[-1].func))]
        if isinstance(t, ir.Call) and t.name == "or" and len(t.args) == 2:
            a, b = (self.false_sets(x) for x in t.args)
            if a is None or b is None or len(a) != 1 or len(b) != 1:
                return None
            return [a[0] | b[0]]
        if isinstance(t, ir.Call) and t.name == "and" and len(t.args) == 2:
            # (the first conjunct false: the second is not evaluated; the second false: the first
            # was evaluated, so it must not fail)
            a = self.false_sets(t.args[0]) or []
            b = (self.false_sets(t.args[1]) or []) if self.quiet_term(t.args[0]) else []
            return (a + b) or None
        return None

    def true_sets(self, t) -> list | None:
        """Sets of slots such that step property ``t`` is true (1, without error) in a step that
        updates no slot of one of them: ``A implies forall ... with G implies B`` (A quiet, the
        quantifier over constant domains) where G is false by false_sets."""
        if isinstance(t, ir.Call) and t.name == "implies" and len(t.args) == 2:
            a, b = t.args
            return self.true_sets(b) if self.quiet_term(a) else None
        if isinstance(t, ir.Quant) and t.kind == "forall" and isinstance(t.guard, ir.Call) and \
                t.guard.name == "implies" and len(t.guard.args) == 2:
            for _, rg in t.bindings:
                if not isinstance(rg, ir.DomainTerm):
                    return None
                try:
                    if self.dyn_values(rg.domain) or not self.range_values(rg):
                        return None
                except Unsupported:
                    return None
            return self.false_sets(t.guard.args[0])
        return None

    def step_skip_table(self) -> list:
        """The steps in which a step property need not be evaluated (it is true): for step property
        k, the sets SKIP_SET_OFF[k] <= j < SKIP_SET_OFF[k + 1], each a bitmap of slots SKIP_BITS[j *
        SKIP_NW ..] (true_sets): when the step updated no slot of one of them, its value is 1."""
        nw = max((len(self.slots) + 63) // 64, 1)
        offs, bits = [0], []
        for p in self.step_props:
            sets = None if type(p).__name__ == "MonitoredInvariant" else self.true_sets(p.prop.body)
            for st in sets or ():
                b = [0] * nw
                for x in st:
                    b[x >> 6] |= 1 << (x & 63)
                bits += b
            offs.append(offs[-1] + len(sets or ()))
        return [f"#define SKIP_NW {nw}",
                f"static const int SKIP_SET_OFF[] = {{{', '.join(map(str, offs))}}};",
                f"static const uint64_t SKIP_BITS[] = {{{', '.join(f'{x}ULL' for x in bits) or '0'}}};"]

    # -------------------------------------------------------------- state atoms of temporal properties
    def label_code(self) -> list:
        """The C expressions of the atoms of the temporal properties (``self.label_atoms``: the
        first initial state -> (term, env) pairs), None for an atom that cannot be translated (the
        temporal layer evaluates it in Python)."""
        self.labels = []
        self.label_exprs = []
        atoms_of = getattr(self, "label_atoms", None)
        if atoms_of is None or not self.init_states:
            return []
        try:
            self.labels = list(atoms_of(self.init_states[0]))
        except AsmError:
            return []
        out = []
        for term, env in self.labels:
            mark = (len(self.funcs), set(self.defined_done), dict(self.rules_done), dict(self.enc_tables))
            try:
                cenv = {uid: self.codec.literal(v) for uid, v in env.items()}
                out.append(self.term(term, cenv))
            except Unsupported:
                del self.funcs[mark[0]:]
                self.defined_done, self.rules_done, self.enc_tables = mark[1], mark[2], mark[3]
                out.append(None)
        self.label_exprs = out
        return out

    def label_entry(self, exprs: list) -> str:
        """``asm_labels(k, out)``: atom k in every stored state (out[sid] = 1 where it is true);
        returns 0, or -1 when it cannot be evaluated in some state (Python then says why)."""
        lines = ["static V check_label(Ctx *c, int k) {", "    switch (k) {"]
        for i, e in enumerate(exprs):
            if e is not None:
                lines.append(f"    case {i}: return {e};")
        lines += ["    }", "    c->err = E_UNSUPPORTED;", "    return UNDEF;", "}",
                  "int64_t asm_labels(int64_t k, uint8_t *out) {",
                  "    Ctx *c = &ctx_static;",
                  "    for (int64_t sid = 0; sid < nstates; sid++) {",
                  "        load_state(c, state_words(sid));",
                  "        c->rd = c->cur; c->self = UNDEF; c->epoch = ++global_epoch; c->err = 0; c->in_prop = 1;",
                  "        V v = check_label(c, (int)k);",
                  "        c->in_prop = 0;",
                  "        if (c->err) { c->err = 0; return -1; }",
                  "        out[sid] = v == 1;",
                  "    }",
                  "    return 0;",
                  "}"]
        return "\n".join(lines) + "\n" + _STEP_ATOMS_C

    # -------------------------------------------------------------- packing
    def map_value(self, st: dict, f) -> int:
        """The number of the map holding the defined locations of ``f`` in ``st``."""
        pairs = []
        for k, v in st.items():
            if type(k) is tuple and k[0] == f.index and v is not None:
                args = k[1]
                kc = self.codec.to_c(args[0] if len(args) == 1 else tuple(args))
                pairs.append((kc, self.codec.to_c(v)))
        pairs.sort()
        return self.codec.intern((5, tuple(x for pr in pairs for x in pr)))

    def pack_values(self, st: dict) -> None:
        """Give every composite value of ``st`` its number (before the code is generated)."""
        for fi in self.map_slot:
            self.map_value(st, self.slot_types[self.map_slot[fi]][1])
        for s, key in enumerate(self.slots):
            if isinstance(self.slot_types[s], tuple):
                continue
            v = st.get(key)
            if v is not None and self.slot_values[s] is None:
                if self.any_typed(self.slot_types[s]):
                    self.codec.any_code(v)
                    continue
                self.codec.to_c(v)

    def pack(self, st: dict) -> list[int]:
        st = self.dyn_counts(st)
        words = [0] * self.nwords
        for s, key in enumerate(self.slots):
            vals = self.slot_values[s]
            if isinstance(self.slot_types[s], tuple):
                words[self.words[s]] = self.map_value(st, self.slot_types[s][1]) & MASK64
                continue
            v = st.get(key)
            if vals is None and self.any_typed(self.slot_types[s]):
                x = self.codec.any_code(v)
                words[self.words[s]] = (UNDEF_V if x is None else x) & MASK64
                continue
            if vals is None:
                if (type(v) is float or T.root(self.slot_types[s]) is T.REAL) and v is not None and \
                        not storable_real(v):
                    raise Unsupported("a Real location holding -0.0, NaN or a value of another type")
                x = self.codec.to_c(v)
                words[self.words[s]] = (UNDEF_V if x is None else x) & MASK64
                continue
            if v is None:
                code = len(vals) if self.slot_undef[s] is None else self.slot_undef[s]
            else:
                code = next((i for i, x in enumerate(vals) if same_value(x, v)), -1)
                if code < 0:
                    raise Unsupported(f"an initial value outside its domain")
            words[self.words[s]] |= code << self.shifts[s]
        return words

    def unpack(self, words) -> dict:
        plan = self._plan
        if plan is None:
            # per slot: (key, word, shift, mask, values) for a narrow slot, (key, word, type) for a wide one
            plan = self._plan = [
                (key, self.words[s], self.slot_types[s], True) if isinstance(self.slot_types[s], tuple) else
                (key, self.words[s], self.slot_types[s]) if self.slot_values[s] is None else
                (key, self.words[s], self.shifts[s], (1 << self.bits[s]) - 1, self.slot_values[s])
                for s, key in enumerate(self.slots)]
        st = {}
        from_c = self.codec.from_c
        for p in plan:
            if len(p) == 4:
                f = p[2][1]
                kind, elems = self.codec.fetch(words[p[1]])
                dt = f.domain[0] if len(f.domain) == 1 else T.Struct("Prod", tuple(f.domain))
                for i in range(0, len(elems), 2):
                    k = from_c(elems[i], dt)
                    st[(f.index, (k,) if len(f.domain) == 1 else tuple(k))] = from_c(elems[i + 1], f.codomain)
                continue
            if len(p) == 3:
                x = words[p[1]]
                if x >= 1 << 63:
                    x -= 1 << 64
                if x != UNDEF_V:
                    st[p[0]] = from_c(x, p[2])
                continue
            key, w, sh, mask, vals = p
            code = (words[w] >> sh) & mask
            if code < len(vals) and vals[code] is not None:
                st[key] = vals[code]
        if self.dyn:
            self.dyn_elements(st)
        return st

    # -------------------------------------------------------------- fresh elements (extend)
    def dyn_setup(self) -> None:
        """The domains the spec extends, numbered in the order of their names (native_canon.c)."""
        from ..semantics.analysis import is_subdomain
        from .canonical import ROUNDS, ranged_domains
        found: dict = {}
        seen: set = set()

        def walk(x):
            if id(x) in seen:
                return
            seen.add(id(x))
            if isinstance(x, ir.Extend):
                found[x.domain.name] = x.domain
            if isinstance(x, ir.Loop) and x.cond is None and _has_extend(x.body):
                raise Unsupported(f"extend inside iterate at {x.span.short() if x.span else '?'}")
            if isinstance(x, (ir.Term, ir.Rule)):
                for v in vars(x).values():
                    walk(v)
            elif isinstance(x, (list, tuple)):
                for v in x:
                    walk(v)
        for r in self.spec.rules:
            walk(r.body)
        del walk        # (the closure refers to itself: freed now, with the ids seen, not by the collector)
        self.dyn_doms = [found[n] for n in sorted(found)]
        self.dyn = {d.name: i for i, d in enumerate(self.dyn_doms)}
        self.codec.dyn = self.dyn
        self.codec.cn_k = self.cn_k
        self.cn_rounds = ROUNDS
        if not self.dyn:
            return
        for d in self.dyn_doms:
            if not isinstance(d, T.Domain) or not d.dynamic:
                raise Unsupported(f"extend of the domain {d}")
        gc = {d.name for d in self.spec.domains if getattr(d, "dynamic", False)} - ranged_domains(self.spec)
        self.dyn_gc = [d.name in gc for d in self.dyn_doms]
        self._dyn_sub = is_subdomain
        for f in self.spec.functions:
            if f.kind == "monitored" and (self.cn_may_hold(f.codomain) or any(self.cn_may_hold(d) for d in f.domain)):
                raise Unsupported(f"the monitored function {f.name} over a domain extended at run time")

    def dyn_values(self, dom) -> list | None:
        """The values of a domain that holds elements made by extend: its named elements, then
        element slots 1..cn_k of each extended domain inside it (``dyn_segments``); None for
        other domains (a domain that holds extended ones the Python engine does not list is refused)."""
        if not self.dyn or not isinstance(dom, T.Domain):
            return None
        segs = self.dyn_segments(dom)
        if segs:
            try:
                named = list(self.m.domain_values(dom, None, None))
            except Undetermined:
                raise Unsupported(f"the infinite domain {dom}")
            for v in named:
                self.codec.to_c(v)
            return named + [fresh_value(self.dyn_doms[d].name, k) for d in segs for k in range(1, self.cn_k + 1)]
        for d in self.dyn_doms:
            if self._dyn_sub(d, dom):
                raise Unsupported(f"the domain {dom}, which holds the elements extend adds to {d}")
        return None

    def grows(self, dom) -> bool:
        """Can the domain ``dom`` gain elements in a run (an extend of it or of a domain inside
        it)?  A dynamic domain nothing extends keeps its named elements (extend is the only rule
        that adds elements to a domain)."""
        from ..semantics.analysis import is_subdomain
        doms = getattr(self, "dyn_doms", None)
        return doms is None or any(is_subdomain(d, dom) for d in doms)

    def dyn_segments(self, dom) -> list:
        """The numbers of the extended domains whose elements the Python engine lists among the
        values of ``dom`` (after the named ones), in its order: the order of the spec's domains
        (``Machine._abstract_values``).  Empty where it lists none."""
        if not self.dyn or not isinstance(dom, T.Domain):
            return []
        root = dom.root()
        if not (dom.kind == "abstract" or (dom.kind == "subset" and dom.definition is None and
                                           isinstance(root, T.Domain) and root.kind == "abstract")):
            return []
        segs = [self.dyn[d.name] for d in self.spec.domains
                if isinstance(d, T.Domain) and d.dynamic and d.name in self.dyn
                and self.dyn_doms[self.dyn[d.name]] is d and self._dyn_sub(d, dom)]
        if len(segs) != sum(1 for d in self.dyn_doms if self._dyn_sub(d, dom)):
            raise Unsupported(f"the domain {dom}, which holds the elements extend adds to a domain not declared")
        return segs

    def range_len(self, rg, vals) -> str:
        """The C expression for how many of ``vals`` (the range ``rg``'s values) to walk: for an
        extended domain its named elements and the elements it has now."""
        if isinstance(rg, ir.DomainTerm) and self.dyn_values(rg.domain):
            (d,) = self.dyn_segments(rg.domain)
            return f"({len(vals) - self.cn_k} + cn_count(c, {d}))"
        return str(len(vals))

    def range_head(self, rg, vals, q: str, name: str) -> str:
        """The C loop header binding ``name`` to each of ``vals`` (the constant range ``rg``'s
        values, in the Python engine's order): for a domain holding the elements of several
        extended domains, the slots of elements not made yet are skipped."""
        tab = self.table(vals)
        segs = self.dyn_segments(rg.domain) if isinstance(rg, ir.DomainTerm) and self.dyn_values(rg.domain) else []
        if not segs:
            return f"for (int {q} = 0; {q} < {self.range_len(rg, vals)}; {q}++) {{ V {name} = {tab}[{q}];"
        named = len(vals) - len(segs) * self.cn_k
        # inside a seq block the elements finished steps made are seen, which need not be the
        # next numbers (an element made by a parallel branch is not): each slot is asked
        if len(segs) == 1:
            return (f"for (int {q} = 0; {q} < {self.range_len(rg, vals)}; {q}++) {{ if ({q} >= {named} && "
                    f"!cn_vis(c, {segs[0]}, {q} - {named} + 1)) continue; V {name} = {tab}[{q}];")
        doms = ", ".join(map(str, segs))
        return (f"for (int {q} = 0; {q} < {len(vals)}; {q}++) {{ if ({q} >= {named} && !cn_vis(c, "
                f"((const int[]){{{doms}}})[({q} - {named}) / {self.cn_k}], ({q} - {named}) % {self.cn_k} + 1)) continue; "
                f"V {name} = {tab}[{q}];")

    def dyn_slots(self) -> None:
        """One slot per extended domain: its number of elements (0..cn_k)."""
        self.dyn_count_slot = []
        for d in self.dyn_doms:
            key = ("#dom", d.name)
            self.dyn_count_slot.append(len(self.slots))
            self.slot_of[key] = len(self.slots)
            self.slots.append(key)
            self.slot_values.append(list(range(self.cn_k + 1)))
            self.slot_types.append(T.INTEGER)

    def dyn_counts(self, st: dict) -> dict:
        """``st`` with each extended domain's elements as their number (canonical: 1..n)."""
        if not self.dyn:
            return st
        st = dict(st)
        for d in self.dyn_doms:
            key = ("#dom", d.name)
            els = st.get(key, ())
            if tuple(e.serial for e in els) != tuple(range(1, len(els) + 1)) or len(els) > self.cn_k:
                raise Unsupported(f"the elements of {d.name} are not numbered 1..n (or more than {self.cn_k})")
            st[key] = len(els)
        return st

    def dyn_elements(self, st: dict) -> None:
        """The decoded numbers of elements back as the domains' elements."""
        for d in self.dyn_doms:
            key = ("#dom", d.name)
            n = st.pop(key, 0)
            if n:
                st[key] = tuple(fresh_value(d.name, k) for k in range(1, n + 1))

    def cn_may_hold(self, typ) -> bool:
        """Can a value of ``typ`` hold an element made by extend?"""
        if not self.dyn:
            return False
        if isinstance(typ, T.Domain):
            if typ.name in self.dyn:
                return True
            if typ.kind == "any":
                return True
            return any(self._dyn_sub(d, typ) for d in self.dyn_doms)
        if isinstance(typ, T.Struct):
            return any(self.cn_may_hold(a) for a in typ.args)
        return False

    def cn_type(self, typ, tys: list, memo: dict) -> int:
        """The offset of ``typ``'s descriptor in CN_TY (see native_canon.c)."""
        key = str(typ)
        if key in memo:
            return memo[key]
        r = T.root(typ)
        if r in (T.INTEGER, T.NATURAL):
            node = [0]
        elif r is T.BOOLEAN:
            node = [1]
        elif isinstance(r, T.Domain) and r.kind in ("enum", "abstract"):
            node = [2]
        elif isinstance(r, T.Struct) and r.kind == "Rule":
            node = [2]                          # rule values: texts from the atom table
        elif r is T.STRING:
            node = [3]
        elif r is T.REAL:
            node = [8]                          # Python's repr of the double (cn_real)
        elif isinstance(r, T.Struct) and r.kind in ("Seq", "Powerset") and self.composite(typ):
            node = [4 if r.kind == "Seq" else 6, self.cn_type(r.args[0], tys, memo)]
        elif isinstance(r, T.Struct) and r.kind == "Prod" and self.composite(typ):
            node = [5, len(r.args)] + [self.cn_type(a, tys, memo) for a in r.args]
        else:
            raise Unsupported(f"a value of type {typ} beside elements made by extend")
        memo[key] = len(tys)
        tys.extend(node)
        return memo[key]

    def canon_map_slot(self, f, tys, memo, fn_ids, slot_fn, slot_vty, slot_nargs, slot_arg, slot_base) -> None:
        """The tables of native_canon.c for the slot holding the locations of ``f`` as a map whose
        keys or values may hold elements made by extend: each entry is a location f(args)=value,
        renamed by rebuilding the map (type node T_LMAP: arity, key type, value type)."""
        if f.index in getattr(self, "lazy_init", ()):
            raise Unsupported(f"the lazily initialised function {f.name} over extended domains")
        key_t = f.domain[0] if len(f.domain) == 1 else T.Struct("Prod", tuple(f.domain))
        kt = self.cn_type(key_t, tys, memo)
        vt = self.cn_type(f.codomain, tys, memo)
        node = len(tys)
        tys.extend([7, len(f.domain), kt, vt])
        if f.index not in fn_ids:
            fn_ids[f.index] = len(fn_ids)
        slot_fn.append(fn_ids[f.index]); slot_vty.append(node); slot_nargs.append(0); slot_arg.append(0)
        slot_base.append(-1)

    def canon_code(self) -> str:
        """The tables of native_canon.c and the file itself (nothing without extend)."""
        if not self.dyn:
            return ""
        chars: list = []
        text_off: dict = {}

        def text(t: str) -> int:
            if t not in text_off:
                text_off[t] = len(chars)
                chars.append(len(t))
                chars.extend(ord(ch) for ch in t)
            return text_off[t]
        tys: list = []
        memo: dict = {}
        fn_ids: dict = {}
        slot_fn, slot_vty, slot_nargs, slot_arg, slot_base = [], [], [], [], []
        args: list = []
        idxs: list = []
        for s, key in enumerate(self.slots):
            typ = self.slot_types[s]
            if self.local_slot(key):            # a local function's: undef (an empty map) in every stored state
                slot_fn.append(-1); slot_vty.append(0); slot_nargs.append(0); slot_arg.append(0); slot_base.append(-1)
                continue
            if isinstance(typ, tuple):          # a map slot
                f = typ[1]
                if self.cn_may_hold(f.codomain) or any(self.cn_may_hold(d) for d in f.domain):
                    self.canon_map_slot(f, tys, memo, fn_ids, slot_fn, slot_vty, slot_nargs, slot_arg, slot_base)
                    continue
                key = None
            if key is None or (type(key) is tuple and key[0] == "#dom"):
                slot_fn.append(-1); slot_vty.append(0); slot_nargs.append(0); slot_arg.append(0); slot_base.append(-1)
                continue
            fi = key if type(key) is int else key[0]
            f = self.spec.functions[fi]
            vt = self.slot_types[s]            # the codomain, or the one type of the location result
            over = any(self.cn_may_hold(d) for d in f.domain)
            if not over and not self.cn_may_hold(vt):
                slot_fn.append(-1); slot_vty.append(0); slot_nargs.append(0); slot_arg.append(0); slot_base.append(-1)
                continue
            if fi not in fn_ids:
                fn_ids[fi] = len(fn_ids)
            slot_fn.append(fn_ids[fi])
            slot_vty.append(self.cn_type(vt, tys, memo))
            combo = () if type(key) is int else key[1]
            slot_nargs.append(len(combo))
            slot_arg.append(len(args))
            base, arg_values, _ = self.fn_base[fi]
            slot_base.append(base if over else -1)
            for i, v in enumerate(combo):
                stride = 1
                for vals in arg_values[i + 1:]:
                    stride *= len(vals)
                args += [self.codec.to_c(v), self.cn_type(f.domain[i], tys, memo), stride]
                idxs.append(next(j for j, x in enumerate(arg_values[i]) if same_value(x, v)))
        fn_off = [0] * len(fn_ids)
        for fi, i in fn_ids.items():
            fn_off[i] = text(self.m.fname[fi])
        atoms: dict = {}
        for d in self.spec.domains:
            if isinstance(d, T.Domain) and d.kind == "enum":
                for e in d.elements:
                    atoms[self.codec.to_c(e)] = text(repr(e))
        for e, i in self.codec.abstract_ids.items():
            atoms[(1 << 40) + i] = text(e.name)
        # other atoms a narrow location holds (rule values): their texts as canonical.py shows them
        from ..semantics.values import RuleValue
        known = [RuleValue(rd) for rd in getattr(self.codec, "rule_by_id", ())]
        for vals in self.slot_values + [known]:
            for v in vals or ():
                if type(v) is RuleValue:
                    if v.agent is not None:
                        raise Unsupported("a rule value bound to an agent beside elements made by extend")
                    x = self.codec.to_c(v)
                    if atoms.get(x, text(repr(v))) != text(repr(v)):
                        raise Unsupported("two values with one code beside elements made by extend")
                    atoms[x] = text(repr(v))
        codes = sorted(atoms)

        def arr(ctype, name, xs):
            return f"static const {ctype} {name}[] = {{{', '.join(f'{x}' for x in xs) or '0'}}};"
        out = [
            f"#define CN_K {self.cn_k}", f"#define CN_ROUNDS {self.cn_rounds}", f"#define CN_NATOM {len(codes)}",
            arr("int", "CN_COUNT_SLOT", self.dyn_count_slot),
            arr("int", "CN_GC", [int(g) for g in self.dyn_gc]),
            arr("int", "CN_SLOT_FN", slot_fn), arr("int", "CN_SLOT_VTY", slot_vty),
            arr("int", "CN_SLOT_NARGS", slot_nargs), arr("int", "CN_SLOT_ARG", slot_arg),
            arr("int", "CN_SLOT_BASE", slot_base),
            f"#define CN_NREL {sum(1 for x in slot_fn if x >= 0)}",
            arr("int", "CN_REL", [i for i, x in enumerate(slot_fn) if x >= 0]),
            arr("int64_t", "CN_ARGS", [f"{x}LL" if x != UNDEF_V else "INT64_MIN" for x in args]),
            arr("int64_t", "CN_SLOT_IDX", idxs),
            arr("int", "CN_TY", tys),
            arr("int64_t", "CN_ATOM_CODE", [f"{x}LL" for x in codes]),
            arr("int", "CN_ATOM_OFF", [atoms[x] for x in codes]),
            arr("int", "CN_FN_OFF", fn_off),
            arr("int", "CN_CHARS", chars),
        ]
        # the bits of the words that hold those locations and the counts (the key of a kept form)
        masks: dict = {}
        for sl in [i for i, x in enumerate(slot_fn) if x >= 0] + list(self.dyn_count_slot):
            b = self.bits[sl]
            m = MASK64 if b == 64 else ((1 << b) - 1) << self.shifts[sl]
            masks[self.words[sl]] = masks.get(self.words[sl], 0) | m
        kw = sorted(masks)
        out += [f"#define CN_NKW {len(kw)}", arr("int", "CN_KW", kw),
                arr("uint64_t", "CN_KMASK", [f"{masks[x]}ULL" for x in kw])]
        canon = resources.files("asmcheck.explore").joinpath("native_canon.c").read_text()
        return "\n".join(out) + "\n" + canon

    def sym_code(self) -> str:
        """The tables of native_sym.c and the file itself (nothing without symmetry reduction)."""
        if self.sym is None:
            return ""
        from .symmetry import NativeRefused, native_tables
        if len(self.step_props) > 63:
            raise Unsupported("more than 63 step properties with --symmetry")
        try:
            tables = native_tables(self.sym, self)
        except NativeRefused as e:
            raise Unsupported(f"--symmetry: {e}") from None
        return tables + resources.files("asmcheck.explore").joinpath("native_sym.c").read_text()

    def r_Extend(self, r, env):
        d = r.domain
        di = self.dyn.get(getattr(d, "name", None))
        if di is None:
            raise Unsupported(f"extend of the domain {d}")
        env = dict(env)
        parts = []
        for v in r.vars:
            x = self.fresh("fx")
            parts.append(f"V {x} = fresh_elem(c, {di}); if (c->err) return;")
            env[v.uid] = x
        return "{ " + " ".join(parts) + " " + self.rule(r.body, env) + " }"


def _has_extend(rule) -> bool:
    """Does ``rule`` (or a rule inside it, or one it calls) extend a domain?"""
    return _contains([rule], ir.Extend)


def _contains(roots: list, kind) -> bool:
    """Is there a ``kind`` node in the rules and terms ``roots``, or in a rule they call?"""
    stack, seen = list(roots), set()
    while stack:
        x = stack.pop()
        if id(x) in seen:
            continue
        seen.add(id(x))
        if isinstance(x, kind):
            return True
        if isinstance(x, ir.CallRule):
            stack.append(x.rule.body)
        if isinstance(x, ir.RuleRef):
            stack.append(x.rule.body)
        if isinstance(x, (ir.Term, ir.Rule)):
            stack.extend(vars(x).values())
        elif isinstance(x, (list, tuple)):
            stack.extend(x)
    return False


# ----------------------------------------------------------------- split by a regular expression
RX_CHAR, RX_CLASS, RX_SPLIT, RX_JMP, RX_BOL, RX_EOL, RX_MATCH = 1, 2, 3, 4, 5, 6, 7
RX_MAX_INSTR = 4096
_RX_CLASS_ESC = "dDwWsS"
_RX_CHAR_ESC = {"n": "\n", "t": "\t", "r": "\r", "f": "\f", "v": "\v"}


class _RxRefused(Exception):
    pass


def regex_program(p: str):
    """The regular expression ``p`` (Python's ``re``, as the Python engine's split uses it) as a
    program of the backtracking matcher of native_rt.c (``str_split_re``): a list of int64, the
    number of instructions first, then (op, a, b) per instruction, then the character classes
    (bits of the characters 0..127 in two words, then 0 / 1: no / every other character matches,
    2: another character is refused at run time).  None outside the subset translated: literal
    characters and escapes, ``.``, classes ``[...]`` and ``\\d \\w \\s`` (their members computed by
    ``re`` itself), ``^ $``, alternatives, non-capturing groups, and the greedy and lazy quantifiers
    ``* + ? {m} {m,} {,n} {m,n}`` on parts that cannot match the empty text (a capturing group
    would put its text among the parts; an empty loop follows ``re``'s own rule)."""
    import warnings
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            if re.compile(p).groups:
                return None
        ast, pos = _rx_alt(p, 0)
        if pos != len(p):
            return None
        code: list = []
        data: list = []
        _rx_emit(ast, code, data)
        code.append([RX_MATCH, 0, 0])
    except (_RxRefused, re.error, Warning, RecursionError):
        return None
    if len(code) > RX_MAX_INSTR:
        return None
    base = 1 + 3 * len(code)
    out = [len(code)]
    for op, a, b in code:
        out += [op, base + a if op == RX_CLASS else a, b]
    return out + data


def _rx_alt(p, i):
    seqs = []
    seq, i = _rx_seq(p, i)
    seqs.append(seq)
    while i < len(p) and p[i] == "|":
        seq, i = _rx_seq(p, i + 1)
        seqs.append(seq)
    return (("alt", seqs) if len(seqs) > 1 else seqs[0]), i


def _rx_seq(p, i):
    items = []
    while i < len(p) and p[i] not in "|)":
        atom, i = _rx_atom(p, i)
        atom, i = _rx_quant(p, i, atom)
        items.append(atom)
    return ("seq", items), i


def _rx_class_node(text: str, hi: int):
    bits = [0, 0]
    for ch in range(128):
        if re.fullmatch(text, chr(ch)):
            bits[ch >> 6] |= 1 << (ch & 63)
    return ("class", tuple(b - (1 << 64) if b >= 1 << 63 else b for b in bits) + (hi,))


def _rx_atom(p, i):
    ch = p[i]
    if ch == "(":
        if not p.startswith("(?:", i):
            raise _RxRefused
        node, j = _rx_alt(p, i + 3)
        if j >= len(p) or p[j] != ")":
            raise _RxRefused
        return node, j + 1
    if ch == "[":
        j = i + 1
        if j < len(p) and p[j] == "^":
            j += 1
        if j < len(p) and p[j] == "]":
            j += 1
        while j < len(p) and p[j] != "]":
            if p[j] == "[":
                raise _RxRefused
            j += 2 if p[j] == "\\" else 1
        if j >= len(p):
            raise _RxRefused
        text = p[i:j + 1]
        inner = text[1:-1]
        simple = all(ord(x) < 128 for x in inner) and not re.search(r"\\[A-Za-z0-9]", inner.replace("\\\\", ""))
        hi = (1 if inner.startswith("^") else 0) if simple else 2
        return _rx_class_node(text, hi), j + 1
    if ch == ".":
        return _rx_class_node(".", 1), i + 1
    if ch == "^":
        return ("bol",), i + 1
    if ch == "$":
        return ("eol",), i + 1
    if ch == "\\":
        if i + 1 >= len(p):
            raise _RxRefused
        x = p[i + 1]
        if x in _RX_CLASS_ESC:
            return _rx_class_node(p[i:i + 2], 2), i + 2
        if x in _RX_CHAR_ESC:
            return ("char", ord(_RX_CHAR_ESC[x])), i + 2
        if x.isascii() and x.isalnum():
            raise _RxRefused
        return ("char", ord(x)), i + 2
    if ch in "*+?{}]":
        raise _RxRefused
    return ("char", ord(ch)), i + 1


def _rx_quant(p, i, atom):
    if i >= len(p) or p[i] not in "*+?{":
        return atom, i
    if p[i] == "{":
        m = re.compile(r"\{(\d*)(,?)(\d*)\}").match(p, i)
        if m is None or (not m.group(1) and not m.group(3) and m.group(2)) or (not m.group(2) and not m.group(1)):
            raise _RxRefused
        lo = int(m.group(1)) if m.group(1) else 0
        hi = int(m.group(3)) if m.group(3) else (None if m.group(2) else lo)
        if lo > RX_MAX_INSTR or (hi is not None and (hi > RX_MAX_INSTR or hi < lo)):
            raise _RxRefused
        i = m.end()
    else:
        lo, hi = {"*": (0, None), "+": (1, None), "?": (0, 1)}[p[i]]
        i += 1
    lazy = i < len(p) and p[i] == "?"
    if lazy:
        i += 1
    if i < len(p) and p[i] in "*+?{":
        raise _RxRefused         # a possessive quantifier, or a repeat of a repeat
    if atom[0] in ("bol", "eol") or _rx_nullable(atom):
        raise _RxRefused
    return ("rep", atom, lo, hi, lazy), i


def _rx_nullable(node) -> bool:
    kind = node[0]
    if kind in ("char", "class"):
        return False
    if kind in ("bol", "eol"):
        return True
    if kind == "seq":
        return all(_rx_nullable(x) for x in node[1])
    if kind == "alt":
        return any(_rx_nullable(x) for x in node[1])
    return node[2] == 0 or _rx_nullable(node[1])


def _rx_emit(node, code: list, data: list) -> None:
    if len(code) > RX_MAX_INSTR:
        raise _RxRefused
    kind = node[0]
    if kind == "char":
        code.append([RX_CHAR, node[1], 0])
    elif kind == "class":
        code.append([RX_CLASS, len(data), 0])
        data.extend(node[1])
    elif kind == "bol":
        code.append([RX_BOL, 0, 0])
    elif kind == "eol":
        code.append([RX_EOL, 0, 0])
    elif kind == "seq":
        for x in node[1]:
            _rx_emit(x, code, data)
    elif kind == "alt":
        jumps = []
        alts = node[1]
        for k, x in enumerate(alts):
            if k < len(alts) - 1:
                split = [RX_SPLIT, len(code) + 1, 0]
                code.append(split)
                _rx_emit(x, code, data)
                jumps.append([RX_JMP, 0, 0])
                code.append(jumps[-1])
                split[2] = len(code)
            else:
                _rx_emit(x, code, data)
        for j in jumps:
            j[1] = len(code)
    else:
        _, body, lo, hi, lazy = node
        for _ in range(lo):
            _rx_emit(body, code, data)
        if hi is None:
            top = len(code)
            split = [RX_SPLIT, 0, 0]
            code.append(split)
            _rx_emit(body, code, data)
            code.append([RX_JMP, top, 0])
            body_at, end = top + 1, len(code)
            split[1], split[2] = (end, body_at) if lazy else (body_at, end)
        else:
            splits = []
            for _ in range(hi - lo):
                split = [RX_SPLIT, 0, 0]
                code.append(split)
                splits.append((split, len(code)))
                _rx_emit(body, code, data)
            end = len(code)
            for split, body_at in splits:
                split[1], split[2] = (end, body_at) if lazy else (body_at, end)


def _holds_real(typ) -> bool:
    """Is a value of ``typ`` a Real or made of Reals somewhere (or of a type not known here)?"""
    if typ is None:
        return True
    r = T.root(typ) if isinstance(typ, T.Domain) else typ
    if isinstance(r, T.Struct):
        return any(_holds_real(a) for a in r.args)
    return r is T.REAL or r is T.COMPLEX or (isinstance(r, T.Domain) and r.kind == "any")


# The run-time part of the merged choose (Generator.choose_merged), emitted once in a model that
# has one.  Per choose site, for each key (the values of the variables in scope and self) met in
# the state being expanded (epoch): the distinct update sets of the body over the candidates, in
# the order first met, each a run of (slot, code) pairs sorted by slot in one pool.
_MERGE_C = r"""/* a choose whose alternatives with the same effect are one (see Generator.choose_merged) */
typedef struct {
    int64_t epoch;                   /* the state the keys belong to */
    int32_t nkeys, cap_keys;
    V *keys;                         /* klen values per key */
    int32_t *ofirst, *onum;          /* key -> its first outcome, their number (0: no candidate) */
    int32_t *kfail;                  /* key -> has an outcome that fails (then no tail of mc_tail) */
    int32_t *kh, khcap;              /* keys by hash: index + 1 (0: empty) */
    int32_t nout, cap_out;
    int32_t *ustart, *ulen;          /* outcome -> its updates in the pool */
    uint64_t *uhash;
    int32_t nu, cap_u;
    int32_t *uslot;
    V *ucode;
    int32_t *oh, ohcap;              /* the outcomes of the key being computed, by hash: index + 1 */
    int32_t last;                    /* the entry found last */
    uint32_t resets;                 /* how many times the entries were forgotten */
} MChoose;

/* the seq step a body runs in while its outcomes are computed: no other update has it (the
   others have 0 or a seq step's number), and its updates are taken back before the next run */
#define MC_STAMP (-2)
static inline uint64_t mc_mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
static uint64_t mc_hash(const V *k, int n) {
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int i = 0; i < n; i++) h = mc_mix(h ^ (uint64_t)k[i]);
    return h;
}
static int mc_more(void **p, int64_t n, size_t sz) {
    void *q = realloc(*p, (size_t)(n > 0 ? n : 1) * sz);
    if (!q) return 0;
    *p = q;
    return 1;
}
static inline int mc_same(const V *a, const V *b, int n) {
    for (int i = 0; i < n; i++) if (a[i] != b[i]) return 0;
    return 1;
}
/* the key's entry computed in this state, or -1 (a new state forgets the entries) */
static int32_t mc_find(Ctx *c, MChoose *m, const V *key, int klen) {
    if (m->epoch != c->epoch) {
        m->epoch = c->epoch;
        m->nkeys = 0; m->nout = 0; m->nu = 0; m->resets++;
        if (m->khcap) memset(m->kh, 0, (size_t)m->khcap * sizeof(int32_t));
        return -1;
    }
    if (!m->khcap) return -1;
    /* the runs of a step from one state mostly meet the keys in the same order: the one after
       the key found last, or the first, is tried before the hash */
    int32_t g = m->last + 1 < m->nkeys ? m->last + 1 : 0;
    if (g < m->nkeys && mc_same(m->keys + (int64_t)g * klen, key, klen)) { m->last = g; return g; }
    uint64_t msk = (uint64_t)m->khcap - 1;
    uint64_t h = mc_hash(key, klen) & msk;
    while (m->kh[h]) {
        int32_t e = m->kh[h] - 1;
        if (mc_same(m->keys + (int64_t)e * klen, key, klen)) { m->last = e; return e; }
        h = (h + 1) & msk;
    }
    return -1;
}
/* a new entry for the key, before its outcomes (ncand candidates); -1 when out of memory */
static int32_t mc_begin(Ctx *c, MChoose *m, const V *key, int klen, int ncand, int cached) {
    if (!cached) { m->epoch = -1; m->nkeys = 0; m->nout = 0; m->nu = 0; m->resets++; }
    if (m->nkeys >= m->cap_keys) {
        int32_t nc = m->cap_keys ? 2 * m->cap_keys : 16;
        if (!mc_more((void **)&m->keys, (int64_t)nc * klen, sizeof(V)) || !mc_more((void **)&m->ofirst, nc, sizeof(int32_t))
            || !mc_more((void **)&m->onum, nc, sizeof(int32_t)) || !mc_more((void **)&m->kfail, nc, sizeof(int32_t))) {
            fail(c, E_MEMORY, 0); return -1;
        }
        m->cap_keys = nc;
    }
    int32_t need = 16;
    while (need < 2 * ncand) need *= 2;
    if (need > m->ohcap) {
        if (!mc_more((void **)&m->oh, need, sizeof(int32_t))) { fail(c, E_MEMORY, 0); return -1; }
        m->ohcap = need;
    }
    memset(m->oh, 0, (size_t)m->ohcap * sizeof(int32_t));
    int32_t e = m->nkeys++;
    memcpy(m->keys + (int64_t)e * klen, key, (size_t)klen * sizeof(V));
    m->ofirst[e] = m->nout;
    m->onum[e] = 0;
    m->kfail[e] = 0;
    m->last = e;
    return e;
}
/* the updates the body made since mark: an outcome of entry e unless one has the same, then
   taken back (the body ran with its own seq step, so each of its updates has its entry) */
static int mc_outcome(Ctx *c, MChoose *m, int32_t e, int32_t mark) {
    int32_t nu = c->nupd - mark;
    if (m->nu + nu > m->cap_u) {
        int32_t nc = m->cap_u ? m->cap_u : 64;
        while (nc < m->nu + nu) nc *= 2;
        if (!mc_more((void **)&m->uslot, nc, sizeof(int32_t)) || !mc_more((void **)&m->ucode, nc, sizeof(V))) {
            fail(c, E_MEMORY, 0); return 0;
        }
        m->cap_u = nc;
    }
    int32_t at = m->nu;
    int32_t *us = m->uslot + at;
    V *uc = m->ucode + at;
    for (int32_t i = 0; i < nu; i++) {            /* sorted by slot (a slot has one update) */
        int32_t s = c->upd_slot[mark + i];
        V v = c->upd_code[mark + i];
        int32_t j = i;
        while (j > 0 && us[j - 1] > s) { us[j] = us[j - 1]; uc[j] = uc[j - 1]; j--; }
        us[j] = s; uc[j] = v;
    }
    for (int32_t i = c->nupd - 1; i >= mark; i--) {
        int32_t s = c->upd_slot[i];
        if (c->uprev[i] >= 0) c->wpos[s] = c->uprev[i]; else c->wgen[s] = c->gen - 1;
    }
    c->nupd = mark;
    uint64_t h = 0x51afd7ed558ccd6dULL ^ (uint64_t)nu;
    for (int32_t i = 0; i < nu; i++) h = mc_mix(h ^ mc_mix((uint64_t)us[i] ^ ((uint64_t)uc[i] << 21) ^ (uint64_t)uc[i]));
    uint64_t msk = (uint64_t)m->ohcap - 1, p = h & msk;
    while (m->oh[p]) {
        int32_t o = m->oh[p] - 1;
        if (m->uhash[o] == h && m->ulen[o] == nu && memcmp(m->uslot + m->ustart[o], us, (size_t)nu * sizeof(int32_t)) == 0
            && memcmp(m->ucode + m->ustart[o], uc, (size_t)nu * sizeof(V)) == 0) return 1;
        p = (p + 1) & msk;
    }
    if (m->nout >= m->cap_out) {
        int32_t nc = m->cap_out ? 2 * m->cap_out : 64;
        if (!mc_more((void **)&m->ustart, nc, sizeof(int32_t)) || !mc_more((void **)&m->ulen, nc, sizeof(int32_t))
            || !mc_more((void **)&m->uhash, nc, sizeof(uint64_t))) { fail(c, E_MEMORY, 0); return 0; }
        m->cap_out = nc;
    }
    int32_t o = m->nout++;
    m->ustart[o] = at; m->ulen[o] = nu; m->uhash[o] = h;
    m->nu += nu;
    m->onum[e]++;
    m->oh[p] = o + 1;
    return 1;
}
/* the errors a body may make in the Python engine (the others end the native search) */
static inline int mc_step_error(int e) { return e == E_UNDEF_GUARD || e == E_CLASH || e == E_DOMAIN || e == E_MODEL; }
/* the body failed: an outcome of entry e that makes the step fail with that error (ulen -1, the
   error in ustart and uhash), its updates taken back; one per error, site and clashing slot */
static int mc_outcome_err(Ctx *c, MChoose *m, int32_t e, int32_t mark) {
    int code = c->err;
    uint64_t at = ((uint64_t)(uint32_t)c->err_site << 32) | (uint32_t)(code == E_CLASH ? c->clash_slot : -1);
    c->err = 0;
    for (int32_t i = c->nupd - 1; i >= mark; i--) {
        int32_t s = c->upd_slot[i];
        if (c->uprev[i] >= 0) c->wpos[s] = c->uprev[i]; else c->wgen[s] = c->gen - 1;
    }
    c->nupd = mark;
    for (int32_t o = m->ofirst[e]; o < m->nout; o++)
        if (m->ulen[o] < 0 && m->ustart[o] == code && m->uhash[o] == at) return 1;
    if (m->nout >= m->cap_out) {
        int32_t nc = m->cap_out ? 2 * m->cap_out : 64;
        if (!mc_more((void **)&m->ustart, nc, sizeof(int32_t)) || !mc_more((void **)&m->ulen, nc, sizeof(int32_t))
            || !mc_more((void **)&m->uhash, nc, sizeof(uint64_t))) { fail(c, E_MEMORY, 0); return 0; }
        m->cap_out = nc;
    }
    int32_t o = m->nout++;
    m->ustart[o] = code; m->ulen[o] = -1; m->uhash[o] = at;
    m->onum[e]++;
    m->kfail[e] = 1;
    return 1;
}
/* the entry's outcomes are complete: findable from now on (when cached) */
static void mc_insert(MChoose *m, int32_t e, int klen) {
    uint64_t msk = (uint64_t)m->khcap - 1;
    uint64_t h = mc_hash(m->keys + (int64_t)e * klen, klen) & msk;
    while (m->kh[h]) h = (h + 1) & msk;
    m->kh[h] = e + 1;
}
static void mc_commit(Ctx *c, MChoose *m, int32_t e, int klen, int cached) {
    if (!cached) return;
    if (2 * m->nkeys > m->khcap) {
        int32_t nc = m->khcap ? 2 * m->khcap : 32;
        while (nc < 2 * m->nkeys) nc *= 2;
        if (!mc_more((void **)&m->kh, nc, sizeof(int32_t))) { fail(c, E_MEMORY, 0); return; }
        m->khcap = nc;
        memset(m->kh, 0, (size_t)nc * sizeof(int32_t));
        for (int32_t x = 0; x < m->nkeys; x++) mc_insert(m, x, klen);
        return;
    }
    mc_insert(m, e, klen);
}
/* The choice points of this run of the step that are merged chooses, with the alternative taken
   and where its updates begin in the update buffer (see mc_tail in native_bfs.c). */
#define MC_TAIL 1
typedef struct { uint32_t gen; uint32_t resets; int64_t epoch; MChoose *m; int32_t e, o, at; } MPoint;
static _Thread_local MPoint mc_pt[MAXCH];
static _Thread_local int32_t mc_skip_from = MAXCH;   /* choice points from here on apply nothing */
static inline void mc_note(Ctx *c, MChoose *m, int32_t e, int32_t o, int32_t at) {
    MPoint *p = &mc_pt[c->pos - 1];
    p->gen = c->gen; p->epoch = c->epoch; p->resets = m->resets; p->m = m; p->e = e; p->o = o; p->at = at;
}
/* the updates of outcome o join the step's */
static void mc_apply(Ctx *c, MChoose *m, int32_t o) {
    int32_t a = m->ustart[o], n = m->ulen[o];
    if (n < 0) {                         /* an outcome that fails */
        if (!c->err) { int32_t cs = (int32_t)(uint32_t)m->uhash[o]; fail(c, a, (int)(m->uhash[o] >> 32)); if (cs >= 0) c->clash_slot = cs; }
        return;
    }
    for (int32_t i = 0; i < n && !c->err; i++) upd(c, m->uslot[a + i], m->ucode[a + i], 0);
}
"""


# ----------------------------------------------------------------- compile and load
_i64, _f64 = ctypes.c_int64, ctypes.c_double
_u64p, _i64p, _u32p = ctypes.POINTER(ctypes.c_uint64), ctypes.POINTER(ctypes.c_int64), ctypes.POINTER(ctypes.c_uint32)
_SYMBOLS = {
    "asm_start": (_i64, [_u64p, _i64, _i64, _i64, _f64, _i64, _i64]),
    "asm_run": (_i64, [_f64, _i64p]),
    "asm_parent": (_i64, [_i64]),
    "asm_state": (None, [_i64, _u64p]),
    "asm_find": (_i64, [_u64p]),
    "asm_parents": (None, [_i64p]),
    "asm_edges": (None, [_u32p, _u32p]),
    "asm_edges_drop": (None, []),
    "asm_edges_take": (None, [_i64, _u32p]),
    "asm_range": (None, [_i64, _i64p]),
    "asm_inv_error": (_i64, [_i64]),
    "asm_err_code": (_i64, []),
    "asm_value_len": (_i64, [_i64]),
    "asm_value_elems": (_i64, [_i64, _i64p]),
    "asm_values": (_i64, []),
    "asm_value_find": (_i64, [_i64, _i64p, _i64]),
    "asm_free": (None, []),
    "asm_run_par": (_i64, [_f64, _i64p, _i64]),
    "asm_limit_memory": (None, [_i64]),
    "asm_memory_bytes": (_i64, []),
    "asm_canon_bytes": (_i64, []),
    "asm_par_stats": (None, [ctypes.POINTER(ctypes.c_double)]),
    "asm_par_min_chunk": (None, [_i64]),
    "asm_par_max_chunk": (None, [_i64]),
    "asm_par_adapt": (None, [_i64]),
    "asm_pack": (None, [_i64]),
    "asm_packed_words": (_i64, []),
    "asm_grow_test": (None, [_f64, _i64]),
    "asm_grow_abandoned": (_i64, []),
    "asm_labels": (_i64, [_i64, ctypes.c_char_p]),
    "asm_step_atoms": (_i64, [_i64, _i64p, _i64, _i64p, _i64]),
    "asm_err_states": (_i64, [_i64p]),
    "asm_err_succ": (_i64, [_i64, _i64p, _i64]),
    "asm_qf": (None, [_i64, _i64p, _i64]),
    "asm_qf_cond": (None, [_i64, _i64p, ctypes.c_char_p, ctypes.c_char_p]),
    "asm_qf_status": (None, [_i64p]),
    "asm_qf_has_out": (_i64, [ctypes.c_void_p]),
    "asm_qf_quotient": (_i64, [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint64]),
    "asm_qf_chunk": (None, [_i64, _i64, ctypes.c_void_p]),
    "asm_qf_table_limit": (None, [_i64]),
    "asm_qf_steps": (_i64, [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]),
    "asm_qf_give": (None, [_i64, ctypes.c_void_p]),
    "asm_qf_layout": (None, [_i64p]),
    "asm_qf_keys": (None, [ctypes.c_void_p, ctypes.c_void_p]),
    "asm_qf_direct_bits": (None, [_i64]),
    "asm_first_choices": (_i64, [_i64, _i64, ctypes.POINTER(ctypes.c_int32), _i64]),
}


_MMAP_FIXED = False


def _fixed_mmap_threshold() -> None:
    """Blocks of 128 KB and more mapped apart and given back to the system when freed, in every
    phase of the process from the first native explorer on (glibc's mallopt; nothing elsewhere).
    glibc raises its threshold to the size of each mapped block freed (up to 32 MB): after the
    generated source or a table that grew is freed, the blocks of that size come from the heap,
    where what is freed stays resident -- the old copies of the search's growing tables, the
    temporal quotient's buffers.  Set once per process."""
    global _MMAP_FIXED
    if _MMAP_FIXED:
        return
    _MMAP_FIXED = True
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return
    mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    mallopt.restype = ctypes.c_int
    mallopt(-3, 128 * 1024)          # M_MMAP_THRESHOLD (glibc's default, made fixed)


def build_library(src: str):
    """The compiled library of the generated source ``src`` (from the cache when it is there),
    with the argument and result types of the engine's entry points."""
    return native_build.build(src, _SYMBOLS)


def _grow_candidates(n: str, cand: str, cap: str, k: int, tl: str) -> str:
    """C that makes room for candidate ``n`` (of ``k`` values) in the thread's buffer ``cand`` of
    ``cap`` candidates (doubling it, from 64, up to MAX_CANDIDATES; ``tl`` names its locals)."""
    return (f"if ({n} >= {cap}) {{ if ({cap} >= {MAX_CANDIDATES}) {{ fail(c, E_UNSUPPORTED, 0); return; }} "
            f"int nc_{tl} = {cap} ? 2 * {cap} : 64; V *t_{tl} = (V *)realloc({cand}, (size_t)nc_{tl} * {k} * sizeof(V)); "
            f"if (!t_{tl}) {{ fail(c, E_MEMORY, 0); return; }} {cand} = t_{tl}; {cap} = nc_{tl}; }}")


# The C's variables that live as long as the library (``static``, not ``const``) and that the
# threaded search (native_bfs.c, asm_run_par) shares knowingly: the search's tables, written by one
# thread between the parallel phases or with atomic operations, and the value table, only read
# while the threads expand.  Any other such variable in the generated C would be shared by the
# threads unknowingly (a scratch buffer, a cache): it must be ``_Thread_local``, else the search
# runs on one thread (``thread_unsafe``).  native_canon.c: the reason a search stopped on fresh
# elements and the search counter (atomic), the table of search contexts (compare-and-swap).
_SHARED_STATICS = frozenset("""
    vpool npool cap_pool vtab nvals cap_vals vhash vmask vt_oom vt_frozen
    states nstates cap_states parents table tmask tcount ctx0 sb0 global_epoch
    pk_allow pk_on PW pk_bits pk_raw pk_at pk_sh pk_vals pk_n pk_cap pk_tab pk_mask pk_count pk_par_w pk_par_c
    pk_par_ok pk_first pk_act pk_wf_off pk_wf ld_w ld_ok ld_bad ws_off pre_h pre_cap inv_need inv_cap wide_slots nwide
    interrupted stop_all W C nworkers bar_n ptime chunk_new chunk_trans newtab newmask max_chunk
    cn_reason cn_reason_dom cn_search cn_ws
    succs
    grow_deadline grow_mask grow_abandoned
    wide_of_word self_first sb_self sb_self_cap
    sym_refused
    pk_par_t pk_dirty pk_dirty_ok pre_dm inv_wm inv_wm_ok cm_on sb_cm sb_cm_cap cn_wm cn_wm_ok
    skip_of skip_sets
""".split())
_STATIC_VAR = re.compile(r"\bstatic\s+(?!const\b|_Thread_local\b|inline\b)((?:volatile\s+)?[A-Za-z_]\w*\s*\**)\s*"
                         r"([A-Za-z_]\w*)\s*(?=[\[=;,])")


def thread_unsafe(src: str) -> list:
    """The names of the variables of the C source ``src`` that threads would share unknowingly."""
    return sorted({m.group(2) for m in _STATIC_VAR.finditer(src)} - _SHARED_STATICS)


# asm_step_atoms(src, ks, nk, out, cap): for every step from the stored state src (every sequence of
# choices, INVAR-filtered as the search does) that leads to a stored state dst, the distinct vectors
# of the atoms ks (bit k: atom ks[k] is true) evaluated in src with the monitored values the step
# read, the monitored locations it did not read taking every value (a nested enumeration after
# the step's own choices); pairs (dst, vector) in the order met, each once.  Returns their number,
# -1 when an atom or the step cannot be evaluated, -2 when more than cap pairs.
_STEP_ATOMS_C = """
int64_t asm_step_atoms(int64_t src, const int64_t *ks, int64_t nk, int64_t *out, int64_t cap) {
    Ctx *c = &ctx_static;
    uint64_t nw[NWORDS > 0 ? NWORDS : 1];
    static _Thread_local V smon[NMON > 0 ? NMON : 1];
    static _Thread_local uint32_t smgen[NMON > 0 ? NMON : 1];
    int64_t nrec = 0;
    const uint64_t *sw = state_words(src);     /* decoded from the packed store */
    load_state(c, sw);
    c->rd = c->cur;
    c->epoch = ++global_epoch;
    c->plen = 0;
    c->in_prop = 0;
    for (;;) {
        begin_run(c);
        step_main(c);
        if (c->err) return -1;
        int ok = 1;
#if NSTEP > 0 || NINVAR > 0
        if (c->nupd > 0 || NINVAR > 0 || NSTEP > 0) make_post(c);
#endif
#if NINVAR > 0
        c->rd = c->post;
        for (int k = 0; k < NINVAR && ok; k++) { V v = check_invar(c, k); if (c->err || v != 1) ok = 0; }
        c->rd = c->cur;
        if (c->err == E_UNSUPPORTED) return -1;
        c->err = 0;
        c->in_prop = 0;
#endif
        if (ok) {
            store_state(c, sw, nw);
#if SYM_ON
            if (sym_canon(nw) < 0) return -1;     /* (symmetry: the class's representative) */
#endif
            int64_t dst = asm_find(nw);
            if (dst >= 0) {
                int32_t P = c->pos;
                memcpy(smon, c->mon, sizeof(smon));
                memcpy(smgen, c->mgen, sizeof(smgen));
                c->plen = P;
                for (;;) {
                    c->pos = P;
                    memcpy(c->mon, smon, sizeof(smon));
                    memcpy(c->mgen, smgen, sizeof(smgen));
                    c->err = 0;
                    int64_t vec = 0;
                    for (int64_t k = 0; k < nk; k++) {
                        V v = check_label(c, (int)ks[k]);
                        if (c->err) return -1;
                        if (v == 1) vec |= (int64_t)1 << k;
                    }
                    int dup = 0;
                    for (int64_t r = 0; r < nrec; r++) if (out[2 * r] == dst && out[2 * r + 1] == vec) { dup = 1; break; }
                    if (!dup) {
                        if (nrec >= cap) return -2;
                        out[2 * nrec] = dst; out[2 * nrec + 1] = vec; nrec++;
                    }
                    if (!next_choices(c, P)) break;
                }
                c->pos = P;
                memcpy(c->mon, smon, sizeof(smon));
                memcpy(c->mgen, smgen, sizeof(smgen));
            }
        }
        if (!next_choices(c, 0)) break;
    }
    return nrec;
}
"""


class NativeExplorer:
    """The explorer's interface (run, path_to, replay) over the native search."""

    engine = "native"
    SLICE = 0.25          # seconds of search between two returns to Python (progress, Ctrl-C)

    def __init__(self, machine: Machine, *, max_states=None, max_depth=None, max_seconds=None, deadlock=False,
                 state_props=None, step_props=None, keep_graph=False, progress=None, warn=None, workers=1,
                 max_memory=None, table_memory=None, label_atoms=None, step_quotient=None, symmetry=None,
                 **_ignored):
        from ..semantics.analysis import mentions_monitored
        _fixed_mmap_threshold()
        self.m = machine
        self.state_props = list(state_props or [])
        self.step_props = list(step_props or [])
        for p in self.state_props:
            if type(p).__name__ != "StateProperty":
                raise Unsupported(f"the property {p.name} (of kind {type(p).__name__})")
        for p in self.step_props:
            if type(p).__name__ not in ("StepProperty", "MonitoredInvariant"):
                raise Unsupported(f"the property {p.name} (of kind {type(p).__name__})")
        if len(self.step_props) > 64:
            raise Unsupported("more than 64 step properties")
        self.invars = [p.body for p in machine.spec.properties if p.kind == "invar"]
        self.gen = Generator(machine, self.state_props)
        self.gen.step_props = self.step_props
        self.gen.invars = self.invars
        self.gen.label_atoms = label_atoms
        self.gen.invar_pre = any(mentions_monitored(t) for t in self.invars)
        # symmetry reduction (explore.symmetry.Symmetry, active): the search stores the Python
        # canonical form's representatives (native_sym.c)
        self.sym = symmetry if symmetry is not None and symmetry.active else None
        self.gen.sym = self.sym
        # the element slots an earlier search of the same spec and properties needed: the C is
        # generated once, with them (not first with too few, then again)
        self._slots_key = self._element_slots_key(label_atoms)
        hinted = self._believed_slots(native_build.recall(self._slots_key)) if self._slots_key else 0
        if hinted:
            self.gen.cn_k = hinted
        try:
            src = self.gen.generate()
        except AsmRuntimeError as e:
            # a step of the Python engine fails there too: it reports the failure (with its trace)
            raise Unsupported(f"{e.message} (while the C code was generated)") from None
        # (the key of the note of element slots when the spec's files give none: see
        # _more_element_slots; a source is some 10 to 400 KB, not kept when not needed)
        self._first_src = src if self._slots_key is None and self.gen.dyn else None
        k = 0 if hinted else self._slots_needed(src)
        if k and self._slots_key:
            native_build.remember(self._slots_key, str(k))     # (a note kept by the source only)
        if k:
            self.gen = self._regenerate(cn_k=k)
            src = self.gen.generate()
        self.dll = build_library(src)
        # thread_unsafe(src): worked out now for threads, else only when they are asked for later
        # (then from the source generated again: it is not kept, 10 to 400 KB)
        self._thread_unsafe = thread_unsafe(src) if max(int(workers or 1), 1) > 1 else None
        del src
        self.gen.codec.dll = self.dll
        # the code generation's garbage (its texts, the source: some 0.3 to 1 MB for a big spec) is
        # free in the C heap but still resident: given back before the search's tables are made
        native_build.trim_heap()
        self.compile_seconds = native_build.last_compile_seconds
        self.max_states = max_states
        self.max_depth = max_depth
        self.max_seconds = max_seconds
        self.deadlock = deadlock
        self.keep_graph = keep_graph
        self.progress = progress
        self.warn = warn
        self.edge_src = None
        self.edge_dst = None
        self.warnings: list = []
        self._states: dict = {}
        self._parent = None
        self._picks_cache = None
        self._canon = None
        self.nstates = 0
        # threads that expand each level together (asm_run_par: the same result as one); the
        # bound on the process's memory in bytes (None: none), of which the search's tables get
        # what the process does not hold when the search begins, or exactly table_memory bytes
        self.workers = max(int(workers or 1), 1)
        self.threaded = False        # True: the threaded search even with one worker (benchmarks)
        self.adapt = True            # False: every slice on all the threads, even when one is faster
        self.packed = True           # False: the plain store even on one thread (tests, benchmarks)
        self.max_memory = max_memory
        self.table_memory = table_memory
        # the temporal checks need only the quotient of the steps (temporal.quotient_plan: the first
        # initial state -> the atoms that read monitored functions): the search records the steps'
        # (target, atom values) pairs, state by state, instead of the edges (asm_qf in native_bfs.c)
        self.step_quotient_plan = step_quotient
        self.qf = False
        self._qf_edges_too = False

    @property
    def thread_unsafe(self) -> list:
        """The static variables of the generated C the threads would share unknowingly."""
        if self._thread_unsafe is None:
            self._thread_unsafe = thread_unsafe(self._regenerate(cn_k=self.gen.cn_k).generate())
        return self._thread_unsafe

    @thread_unsafe.setter
    def thread_unsafe(self, names: list) -> None:
        self._thread_unsafe = list(names)

    def thread_stats(self) -> dict:
        """What the threaded search did since the last call (benchmarks, tests): chunks of a level
        done on the threads, chunks sent back to one thread (a value not yet in the value table, a
        run-time condition), chunks walked by thread 0 (something to record, a limit), growths of
        the table inside a chunk; seconds in the threaded chunks, CPU seconds of thread 0 alone
        (walks, counters), of the chunks done on one thread (small or sent back), and of threads 0
        and 1 (spinning at barriers not counted); the barriers thread 0 met, the futex sleeps of
        all threads, the seconds threads 0 and 1 waited at barriers; the slices (calls) run on one
        thread because that was faster (a busy machine)."""
        o = (ctypes.c_double * 14)()
        self.dll.asm_par_stats(o)
        return {"parallel_chunks": int(o[2]), "serial_chunks": int(o[1]), "walked_chunks": int(o[8]),
                "table_growths": int(o[9]), "parallel_seconds": o[0], "one_thread_slices": int(o[4]),
                "merge_cpu": o[5], "one_thread_cpu": o[3], "thread_cpu": (o[6], o[7]),
                "barriers": int(o[10]), "sleeps": int(o[11]), "barrier_wait": (o[12], o[13])}

    def _table_bound(self) -> int:
        """Bytes the search's tables may take (-1: no bound)."""
        if self.table_memory is not None:
            return max(int(self.table_memory), 0)
        if not self.max_memory:
            return -1
        from .store import memory_in_use
        return max(int(self.max_memory) - memory_in_use(), 0)

    def _growing(self, depth: int) -> list:
        """Integer locations that took a new least or greatest value at the last level, or whose
        values moved past those of the last call (see :func:`asmcheck.explore.bfs.drifted`)."""
        from .bfs import drifted
        g = self.gen
        out = []
        buf = (ctypes.c_int64 * 5)()
        windows = self._windows
        for s, vals in enumerate(g.slot_values):
            typ = g.slot_types[s]
            if vals is not None or isinstance(typ, tuple) or T.root(typ) not in (T.INTEGER, T.NATURAL):
                continue
            self.dll.asm_range(s, buf)
            lo, hi, grew = buf[0], buf[1], buf[2]
            window = (buf[3], buf[4]) if buf[3] <= buf[4] else None
            prev, windows[s] = windows.get(s), window
            if grew >= 0 and (grew >= depth - 1 or drifted(prev, window)):
                out.append((self.m.location_text(g.slots[s]), lo, hi))
        return out

    def _seconds_left(self) -> float:
        """The time the search may take (-1: no bound): ``max_seconds``, or what is left of it
        when the run has a deadline (``check_deadline``, time.monotonic(): the whole call's), so
        that a search run again (an ``ag`` broken, the lists or edges recorded afresh) does not
        start the clock again."""
        if self.max_seconds is None:
            return -1.0
        deadline = getattr(self, "check_deadline", None)
        if deadline is None:
            return float(self.max_seconds)
        return max(min(float(self.max_seconds), deadline - time.monotonic()), 0.0)

    def run(self):
        from .bfs import DEADLOCK, PseudoProperty, Result, Violation
        g = self.gen
        inits = []
        invar_fns = [self.m.term(t) for t in self.invars]
        for st in g.init_states:
            if invar_fns:
                from ..props import evaluate_all
                if not all(any(v is True for v in evaluate_all(self.m, fn, st, None)) for fn in invar_fns):
                    continue
            w = g.pack(st if self.sym is None else self.sym.canon(st)[0])
            if w not in inits:
                inits.append(w)
        flat = (ctypes.c_uint64 * max(len(inits) * g.nwords, 1))(*[x for w in inits for x in w])
        nprops = len(self.state_props)
        out = (ctypes.c_int64 * (12 + 3 * (nprops + 2 + len(self.step_props))))()
        self._run_out = out         # (the counts so far, for a search a Ctrl-C ends: counts_so_far)
        t0 = time.perf_counter()
        if g.dyn:
            self.dll.asm_canon_reset()
        # one thread keeps the states in the packed store (native_bfs.c: a dictionary code a word,
        # in bit fields); the threads share the plain one
        self.dll.asm_pack(1 if self.packed and not self.threaded and (self.workers <= 1 or self.thread_unsafe) else 0)
        self.dll.asm_start(flat, len(inits), -1 if self.max_states is None else self.max_states,
                           -1 if self.max_depth is None else self.max_depth, self._seconds_left(),
                           1 if self.deadlock else 0, 1 if self.keep_graph else 0)
        self.dll.asm_limit_memory(self._table_bound())
        self.qf = self._qf_start()
        # chunks of fewer states a thread run on one thread (ASMCHECK_THREAD_MIN_CHUNK: tests)
        self.dll.asm_par_min_chunk(_env_count("ASMCHECK_THREAD_MIN_CHUNK", 8))
        # and of more states split (ASMCHECK_THREAD_MAX_CHUNK: tests; at most 65,536)
        self.dll.asm_par_max_chunk(_env_count("ASMCHECK_THREAD_MAX_CHUNK", 65536))
        self.dll.asm_par_adapt(1 if self.adapt else 0)
        if self.workers > 1 and self.thread_unsafe:
            msg = (f"the native search runs on one thread, not {self.workers}: its C code keeps state in "
                   f"variables the threads would share ({', '.join(self.thread_unsafe)})")
            self.workers = 1
            self.warnings.append(msg)
            if self.warn is not None:
                self.warn(msg)
        # the search runs in slices: between two, Python shows progress, notices Ctrl-C and
        # watches for integer locations that grow level after level
        growth_depth = -1
        streak: dict = {}
        self._windows = {}
        from .bfs import SizeWatch
        sizes = SizeWatch(self.m)
        while True:
            status = (self.dll.asm_run_par(self.SLICE, out, -self.workers if self.threaded else self.workers)
                      if self.workers > 1 or self.threaded else self.dll.asm_run(self.SLICE, out))
            if status != 6:
                break
            now = time.perf_counter() - t0
            if self.progress is not None:
                self.progress(out[0], out[8], out[1], now)
            depth = out[8]
            if depth != growth_depth:
                growth_depth = depth
                if self.gen.composite_slots:
                    # the last state found: a sequence, set, map or string that keeps growing
                    buf = (ctypes.c_uint64 * self.gen.nwords)()
                    self.dll.asm_state(out[0] - 1, buf)
                    for msg in sizes.watch(self.gen.unpack(buf[:]), depth):
                        self.warnings.append(msg)
                        if self.warn is not None:
                            self.warn(msg)
                for name, lo, hi in self._growing(depth):
                    streak[name] = streak.get(name, 0) + 1
                    if streak[name] == 3:
                        msg = (f"{name} keeps taking new values level after level (range {lo}..{hi} at depth "
                               f"{depth}): the search may not end; bound it in the model (a subset domain "
                               f"or a guard), or stop the search with --max-depth or --max-states")
                        self.warnings.append(msg)
                        if self.warn is not None:
                            self.warn(msg)
        if status == 7:
            raise KeyboardInterrupt
        if status == 11:
            return self._watched_broken(out[5])
        secs = time.perf_counter() - t0
        nstates, transitions, depth = out[0], out[1], out[2]
        self.nstates = nstates
        self._err_code = self.dll.asm_err_code()
        if status == 4 and g.dyn and self._canon_refusal():
            return self._more_element_slots()
        if status == 4 and self.sym is not None and _sym_refused(self.dll):
            from .symmetry import NATIVE_MAX_NUMBERINGS
            raise Unsupported(f"--symmetry: a state whose canonical form tries more than {NATIVE_MAX_NUMBERINGS:,} "
                              f"numberings of the interchangeable elements")
        if status == 4:
            code = out[4]
            self.failed_state = out[5]     # the state whose step or property was refused
            site = out[6] - 1000
            if code == 4 and 0 <= site < len(g.site_reasons):
                fi = next((i for i, x in getattr(g, "_outside_sites", {}).items() if x == site + 1000), None)
                # (not where the canonical form renames the arguments: elements made by extend)
                if fi is not None and fi not in getattr(g, "undef_args", ()) and not (
                        g.dyn and any(g.cn_may_hold(d) for d in self.m.spec.functions[fi].domain)):
                    return self._undef_arg_slots(fi)
                raise Unsupported(f"{g.site_reasons[site]}, reached at run time")
            raise Unsupported("a value outside the native encoding at run time" if code == 4 else
                              "more choices in one step than the native search follows" if code == 6 else
                              f"a run-time condition the native search does not handle (code {code})")
        if status == 5:
            raise AsmError(None, "out of memory in the native search")
        if out[11]:
            # a state with more sequences of choices than the search follows (the Python explorer
            # stops there, incomplete, and counts after merging a choose's alternatives)
            self._step_error(-1, 9, PseudoProperty, Violation)
        if self.keep_graph and (not self.qf or self._qf_edges_too):
            self._take_edges(out[9])
        # (what the search counted: the result of a run whose time limit ends the check below)
        self.counts = (nstates, transitions, depth)
        # the errors of the failing steps: of the states where the error property is violated, or
        # of every such state when the graph is kept (the failing steps are edges to halt nodes)
        err_sids = {out[13 + 3 * i] for i in range(out[7]) if out[12 + 3 * i] == nprops + 1}
        failed = self._failed_steps(None if self.keep_graph else err_sids)
        violations = []
        for i in range(out[7]):
            k, sid, src = out[12 + 3 * i], out[13 + 3 * i], out[14 + 3 * i]
            if k == nprops + 1 and sid in failed:
                e = failed[sid][0]
                violations.append(Violation(PseudoProperty("error", "error", e.span), sid, message=e.message, error=e))
            elif k == nprops + 1:
                violations.append(self._step_error(sid, self._err_code, PseudoProperty, Violation))
            elif k == nprops:
                none = not any(True for _ in self.m.successors(self.state(sid)))
                violations.append(Violation(DEADLOCK, sid, message="no successor" if none else
                                            "the only successor is the state itself"))
            elif k > nprops + 1:
                violations.append(self._step_violation(self.step_props[k - nprops - 2], src, sid,
                                                       self.dll.asm_inv_error(k), Violation))
            else:
                prop = self.state_props[k]
                v = Violation(prop, sid)
                if self.dll.asm_inv_error(k):
                    try:
                        prop.check_state(self.m, self.state(sid))
                    except AsmError as e:
                        v = Violation(prop, sid, message=f"cannot be evaluated: {e.message}", error=e)
                violations.append(v)
        # the order of the Python explorer: by when they were found
        from .bfs import memory_text
        stopped = out[11] != 0
        incomplete = status in (1, 2, 3, 8) or stopped
        reason = {1: f"state limit {self.max_states} reached", 2: f"depth limit {self.max_depth} reached",
                  3: f"time limit {self.max_seconds} s reached",
                  8: (f"memory limit {memory_text(self.max_memory or 0)} reached" if self.table_memory is None
                      else f"memory limit {self.table_memory / 2**20:,.1f} MB of tables reached")}.get(status, "")
        if stopped and not reason:
            reason = "a step could not be computed"
        from .bfs import Stop
        stop = {1: Stop.STATES, 2: Stop.DEPTH, 3: Stop.TIME, 8: Stop.MEMORY}.get(status, Stop.STEP_FAILED if stopped else "")
        time_limit = None
        if status == 3:
            from .bfs import TimeLimit
            time_limit = TimeLimit(self.max_seconds, self._stopped_inside(out[5], out[4])
                                   + ("; " + self.warnings[-1] if self.warnings else ""))
            reason = time_limit.text()
        verdict = "violated" if violations else ("incomplete" if incomplete else "holds")
        res = Result(verdict, nstates, transitions, depth, secs, violations, reason if incomplete else "",
                     list(self.state_props) + list(self.step_props))
        res.deadlock_checked = self.deadlock
        res.engine = "native"
        res.workers = self.workers
        res.compile_seconds = self.compile_seconds
        res.time_limit = time_limit
        res.stop = stop if incomplete else ""
        return res

    def counts_so_far(self) -> tuple:
        """(states, transitions, depth) the search had reached at its last return to Python: what
        a search that a Ctrl-C ended reports."""
        out = getattr(self, "_run_out", None)
        return (int(out[0]), int(out[1]), int(out[2])) if out is not None else (0, 0, 0)

    def _take_edges(self, n: int) -> None:
        """The edge arrays (4 bytes an end) copied out of the search, whose own copy is freed (each
        array as soon as it is copied: three arrays at most at a time, not four)."""
        take = getattr(self.dll, "asm_edges_take", None)
        if take is not None:
            ends = []
            for which in (0, 1):
                a = array("I", [0]) * max(n, 1)     # (no bytes object of the same size beside it)
                take(which, (ctypes.c_uint32 * len(a)).from_buffer(a))
                del a[n:]
                ends.append(a)
            self.edge_src, self.edge_dst = ends
            self.dll.asm_edges_drop()
            return
        src = array("I", [0]) * max(n, 1)
        dst = array("I", [0]) * max(n, 1)
        self.dll.asm_edges((ctypes.c_uint32 * len(src)).from_buffer(src), (ctypes.c_uint32 * len(dst)).from_buffer(dst))
        del src[n:], dst[n:]
        self.edge_src, self.edge_dst = src, dst
        drop = getattr(self.dll, "asm_edges_drop", None)
        if drop is not None:
            drop()

    def _qf_atoms(self):
        """The numbers (in the generated code's atoms) of the atoms the temporal quotient reads in
        the steps, in its order, and their keys; None when the search cannot record its steps (no
        plan, threads, an atom not translated, more than 63 atoms)."""
        plan = self.step_quotient_plan
        if plan is None or not self.keep_graph or self.workers > 1 or self.threaded or not self.gen.init_states:
            return None
        try:
            atoms = plan(self.gen.init_states[0])
        except AsmError:
            return None
        if atoms is None or len(atoms) > 63:
            return None
        index = {}
        for k, (term, env) in enumerate(getattr(self.gen, "labels", ())):
            index.setdefault((id(term), _env_key(env)), k)
        keys = [(id(term), _env_key(env)) for term, env in atoms]
        ks = [index.get(key) for key in keys]
        if any(k is None or self.gen.label_exprs[k] is None for k in ks):
            return None
        return ks, keys

    def _qf_start(self) -> bool:
        """Set the search up to record the steps of the temporal quotient (when it can)."""
        self.lists_kept = "all"
        self.dll.asm_qf_cond(-1, None, None, None)
        got = self._qf_atoms()
        if got is None:
            return False
        ks, self._qf_keys = got
        # (the edges too when something else reads them: --graph, the structure of --fair)
        self._qf_edges_too = bool(getattr(self.step_quotient_plan, "edges_too", False))
        self.dll.asm_qf(len(ks), (ctypes.c_int64 * max(len(ks), 1))(*ks), 1 if self._qf_edges_too else 0)
        if self.QF_TABLE is not None:
            self.dll.asm_qf_table_limit(self.QF_TABLE)
        if self.QF_DIRECT_BITS is not None:
            self.dll.asm_qf_direct_bits(self.QF_DIRECT_BITS)
        self._qc_start(ks)
        return True

    def _qc_start(self, ks) -> None:
        """Have the search record only the successor lists the CTL check reads, the first entry of the
        others (temporal/need.py:
        the plan's ``need``), where it can: one thread, no atom that reads a monitored function,
        no state or depth bound (the check of a partial state space reads every list), no element
        made by extend, no symmetry reduction, every atom of the condition translated.  ``self.lists_kept``: "none", "some" or "all"."""
        self.lists_kept = "all"
        self.edge_need = "all"
        self.dll.asm_qf_cond(-1, None, None, None)
        if ks or os.environ.get("ASMCHECK_EDGE_NEED", "") == "all":
            return
        if self.max_states is not None or self.max_depth is not None or self.gen.dyn or self.sym is not None:
            return
        got = getattr(self, "_need_again", None)
        if got is None:
            fn = getattr(self.step_quotient_plan, "need", None)
            if fn is None:
                return
            try:
                got = fn(list(self.gen.init_states))
            except AsmError:
                return
        need, atoms = got
        if not hasattr(need, "watched"):        # "all" (temporal.need.ALL)
            return
        # the ag(p) with p free of temporal operators: watched by the search, which stops at the
        # first state that breaks one (then searched again, with the lists it reads)
        watch = need.watched()
        ids = sorted(set(need.atoms()) | set(need.atoms_of(watch)))
        if len(ids) > 16:
            watch = []
            ids = need.atoms()
        if len(ids) > 16:
            return
        index = {}
        for k, (term, env) in enumerate(getattr(self.gen, "labels", ())):
            index.setdefault((id(term), _env_key(env)), k)
        lab = [index.get((id(atoms.items[i].term), _env_key(atoms.items[i].env))) for i in ids]
        if any(k is None or self.gen.label_exprs[k] is None for k in lab):
            return
        table = bytes(need.table(ids))
        if all(table):
            return              # (every list)
        later = bytes(need.table_of_all(watch, ids)) if watch else None
        self._qc_watch = (need, atoms, watch)
        self.dll.asm_qf_cond(len(lab), (ctypes.c_int64 * max(len(lab), 1))(*lab), table, later)
        self.edge_need = need
        self.lists_kept = "none" if not any(table) else "some"

    def _watched_broken(self, sid: int):
        """The search stopped at state ``sid``, which breaks an ag(p) it watched (asm_qf_cond): the
        search again, recording the lists the properties broken there read (later_cond) and watching
        the others."""
        need, atoms, watch = self._qc_watch
        self._need_again = (need.after_broken(watch, atoms, self.m, self.state(sid)), atoms)
        return self.run()

    def lists_again(self, need, atoms) -> None:
        """The search again, recording the lists of ``need`` (temporal/need.py: an ``ag``/``ef``
        property the set of states did not decide reads more): the same states in the same
        order."""
        from .bfs import TimeUp
        self._need_again = (need, atoms)
        keep = (self.progress, self.warn, list(self.warnings), self.counts)
        self.progress = self.warn = None
        try:
            res = self.run()
        finally:
            self.progress, self.warn, self.warnings = keep[:3]
        if res.stopped_early or self.counts != keep[3]:
            raise TimeUp()

    def _qf_recorded(self) -> bool:
        """Whether the search recorded the steps of the temporal quotient, not yet handed over."""
        if not self.qf:
            return False
        st = (ctypes.c_int64 * 3)()
        self.dll.asm_qf_status(st)
        return bool(st[0])

    def _edges_again(self) -> None:
        """The search again, recording the edges (the steps of the temporal quotient could not be
        recorded, or something else needs the edges): the same states in the same order."""
        self.step_quotient_plan = None
        keep = (self.progress, self.warn, list(self.warnings))
        self.progress = self.warn = None
        try:
            self.run()
        finally:
            self.progress, self.warn, self.warnings = keep

    def has_successor(self) -> bytearray | None:
        """The states with a step to a stored state (1), when the search recorded the steps of the
        temporal quotient; None otherwise (the edge arrays tell)."""
        if not self._qf_recorded():
            return None
        n = self.nstates
        out = bytearray(max(n, 1))
        if self.dll.asm_qf_has_out((ctypes.c_char * len(out)).from_buffer(out)) != 0:
            return None
        del out[n:]
        return out

    def step_quotient(self, items, sig, ok_state, need: int):
        """The quotient of the temporal structure whose nodes are steps (kripke._quotient_by_source's
        result: the source, target and atom bits of each node's first step, and for each state the
        nodes leaving it as (off, adj)), merged from the pairs the search recorded: ``items`` must be
        the atoms the search evaluated (in the same order), ``sig`` each state's signature, steps from
        states with ``ok_state`` unset or whose bits miss one of ``need`` dropped.  None when the
        search did not record them for these atoms (then the edges are recorded by a search again).
        The bits come as array('B') with at most 8 atoms (empty without atoms), else array('q').
        The lists come as 16-bit entries when they fit (array('H')): the nodes when there are at
        most 65,536, else -- without atoms, at most 65,536 states -- the targets, and ``adj`` is
        then ``(targets, key, tab, n)``: the node of target t in state s's list is
        ``tab[key[s] * n + t]`` (:class:`asmcheck.temporal.classes.Classes`)."""
        if not self._qf_recorded():
            return None
        if [(id(a.term), _env_key(a.env)) for a in items] != self._qf_keys:
            return None
        n = self.nstates
        sg = sig if isinstance(sig, array) and sig.typecode == "Q" else array("Q", sig)
        if not len(sg):
            sg = array("Q", [0])
        okb = bytearray(ok_state) if len(ok_state) else bytearray(1)
        ptr = ctypes.c_void_p
        addr = lambda a: ctypes.addressof(ctypes.c_char.from_buffer(a))  # noqa: E731
        nq = self.dll.asm_qf_quotient(addr(sg), addr(okb), need)
        if nq < 0:
            return None
        st = (ctypes.c_int64 * 3)()
        self.dll.asm_qf_status(st)
        na = st[1]
        lay = (ctypes.c_int64 * 3)()
        self.dll.asm_qf_layout(lay)
        self.qf_direct = bool(lay[2])      # (the tests read it)
        code = "i" if lay[0] == 0 else "H"
        # each node's first step and the offsets, before the lists: each array copied out and its C
        # original freed before the next is made (the bits first: 8 bytes a node there, 1 here with at
        # most 8 atoms; none without atoms)
        nk = len(items)
        give = self.dll.asm_qf_give
        if nk:
            fvec = array("B" if nk <= 8 else "q", [0]) * max(nq, 1)
            give(3, ptr(addr(fvec)))
            del fvec[nq:]
        else:
            fvec = array("B")
        fsrc = array("I", [0]) * max(nq, 1)
        give(1, ptr(addr(fsrc)))
        fdst = array("i", [0]) * max(nq, 1)
        give(2, ptr(addr(fdst)))
        off = array("i", [0]) * (n + 1)
        give(0, ptr(addr(off)))
        del fsrc[nq:], fdst[nq:]
        # the lists a part at a time (a long one is not held twice), then the rest
        adj = array(code)
        part = array(code, [0]) * min(max(na, 1), 1 << 16)
        view = memoryview(part).cast("B")
        for start in range(0, na, len(part)):
            k = min(len(part), na - start)
            self.dll.asm_qf_chunk(start, k, ptr(addr(part)))
            adj.frombytes(view[:part.itemsize * k])
        del view, part
        if lay[0] == 2:
            key = array("i", [0]) * max(n, 1)
            tab = array("i", [0]) * max(lay[1] * n, 1)
            self.dll.asm_qf_keys(ptr(addr(key)), ptr(addr(tab)))
            del key[n:], tab[lay[1] * n:]
            adj = (adj, key, tab, n)
        give(4, None)
        self.qf = False
        return fsrc, fdst, fvec, off, adj

    def _canon_refusal(self) -> None:
        """Raise the reason the search stopped on elements made by extend, if it did."""
        fn = self.dll.asm_canon_reason
        fn.restype = ctypes.c_int64
        fn.argtypes = [_i64p]
        buf = (ctypes.c_int64 * 1)()
        why = fn(buf)
        if why == 1 and self.gen.cn_k < CN_K_MAX:
            return True
        if why == 1:
            raise Unsupported(f"more than {self.gen.cn_k} elements of {self.gen.dyn_doms[buf[0]].name} made by extend "
                              f"in one state")
        if why == 3:
            raise Unsupported(f"{self.gen.dyn_doms[buf[0]].name} ranged over inside a seq block after an extend of it")
        if why == 4:
            raise Unsupported(f"more than 64 elements of {self.gen.dyn_doms[buf[0]].name} made by extend in one step "
                              f"of a seq block")
        if why:
            raise Unsupported("a state with elements made by extend that the native canonical form does not handle")

    def _regenerate(self, cn_k: int) -> "Generator":
        """A generator for the same spec, properties and layout, with ``cn_k`` element slots per
        extended domain."""
        gen = Generator(self.m, self.state_props)
        gen.step_props = self.gen.step_props
        gen.invars = self.gen.invars
        gen.label_atoms = getattr(self.gen, "label_atoms", None)
        gen.invar_pre = getattr(self.gen, "invar_pre", False)
        gen.sym = getattr(self.gen, "sym", None)
        gen.cn_k = cn_k
        if getattr(self.gen, "undef_args", None):
            gen.undef_args = set(self.gen.undef_args)
        return gen

    def _element_slots_key(self, label_atoms) -> str | None:
        """What identifies the engine's source before it is generated, for the note of the element
        slots a search needed (:meth:`_more_element_slots`): the spec's files (path and content),
        the machine's options, the properties, INVAR and atoms; None when a file cannot be read
        (then the note is keyed by the generated source itself).  Only a hint: a note that does
        not fit (another spec's) at most costs slots or a second generation, never a result."""
        import hashlib
        spec = self.m.spec
        files = [spec.path, *getattr(spec, "modules", [])]
        parts = ["element slots", str(CN_K)]
        for f in files:
            try:
                with open(f, "rb") as fh:
                    parts += [os.path.abspath(f), hashlib.sha256(fh.read()).hexdigest()]
            except (OSError, TypeError, ValueError):
                return None
        opts = getattr(self.m, "options", {}) or {}
        parts.append(repr(sorted((k, repr(v)) for k, v in opts.items() if k != "deadline" and not callable(v))))
        parts += [f"{type(p).__name__} {p.name}" for p in self.state_props + self.step_props]
        parts.append(f"{len(self.invars)} {label_atoms!r} {self.gen.invar_pre}")
        return "\0".join(parts)

    def _believed_slots(self, k: str | None) -> int:
        """The number of element slots a note gives, when the retry of :meth:`_more_element_slots`
        could have reached it from the first number (doubled, up to CN_K_MAX); else 0."""
        if k is None or not k.isdigit():
            return 0
        k = int(k)
        return k if k <= CN_K_MAX and k in (self.gen.cn_k << i for i in range(1, 8)) else 0

    def _slots_needed(self, src: str) -> int:
        """The element slots per extended domain an earlier search of the same engine source
        (with the first number of slots) needed, when it needed more (kept in the private cache
        folder by :meth:`_more_element_slots`); else 0.  The search then starts with them, and
        does not run first with too few, then again."""
        if not self.gen.dyn:
            return 0
        return self._believed_slots(native_build.recall(src))

    def _more_element_slots(self):
        """The search again, on an engine with twice the element slots per extended domain.
        The first search's memory is freed, and the number of slots is kept for the next run of
        the same spec (:meth:`_slots_needed`)."""
        gen = self._regenerate(cn_k=self.gen.cn_k * 2)
        src = gen.generate()
        native_build.remember(self._slots_key or self._first_src, str(gen.cn_k))
        self.dll.asm_canon_reset()       # the first search's canonical forms kept go, and its tables
        self.close()
        native_build.forget(self.dll)
        dll = build_library(src)
        gen.codec.dll = dll
        self.gen, self.dll = gen, dll
        self._thread_unsafe = None
        self.compile_seconds += native_build.last_compile_seconds
        self._states = {}
        self._parent = None
        self._picks_cache = None
        return self.run()

    def _undef_arg_slots(self, fi: int):
        """The search again, on an engine whose layout also has the locations of the function
        numbered ``fi`` at undef arguments (the Python engine keeps such a location in the state,
        with its key's argument None: an update at an argument that is undef).  An argument
        outside its domain still ends the search (the reason is the same)."""
        gen = Generator(self.m, self.state_props)
        gen.step_props = self.gen.step_props
        gen.invars = self.gen.invars
        gen.label_atoms = getattr(self.gen, "label_atoms", None)
        gen.invar_pre = getattr(self.gen, "invar_pre", False)
        gen.cn_k = self.gen.cn_k
        gen.sym = getattr(self.gen, "sym", None)
        gen.undef_args = set(getattr(self.gen, "undef_args", ())) | {fi}
        src = gen.generate()
        dll = build_library(src)
        gen.codec.dll = dll
        self.close()
        self.thread_unsafe = thread_unsafe(src)
        self.gen, self.dll = gen, dll
        self.compile_seconds += native_build.last_compile_seconds
        self._states = {}
        self._parent = None
        self._picks_cache = None
        return self.run()

    def _norm(self, st: dict) -> tuple:
        """The canonical form of a successor the Python step function made, and the renaming."""
        if self.sym is not None:
            return self.sym.canon(st)[0], {}
        if not self.gen.dyn:
            return st, {}
        if self._canon is None:
            from .canonical import Canonicalizer, ranged_domains
            spec = self.m.spec
            gc = {d.name for d in spec.domains if getattr(d, "dynamic", False)} - ranged_domains(spec)
            self._canon = Canonicalizer(self.m, gc)
        out = self._canon(st)
        return out, dict(self._canon.last_mapping)

    def _step_violation(self, prop, src, dst, failed, Violation):
        """The violation of a step property by a step from ``src`` to ``dst``: the first such step
        of the Python step function gives the choices (and the message, when it cannot be evaluated)."""
        st = self.state(src)
        want = self.state(dst)

        def violation(log, ups, nxt, mon):
            picks = tuple(c.pick for c in log)
            try:
                ok = prop.check_step(self.m, st, ups, nxt, mon)
            except AsmError as e:
                return Violation(prop, dst, src, picks, message=f"cannot be evaluated: {e.message}", error=e)
            return None if ok else Violation(prop, dst, src, picks)
        # the first step to dst, run once along the native engine's choices: when it violates the
        # property it is the first such step; else the steps are enumerated
        got = self.guided_step(src, dst, st, want)
        found = violation(got[1], got[2], got[4], got[3]) if got is not None else None
        if found is not None:
            return found
        for log, ups, nxt, mon in self.m.successors(st, errors=[]):
            if self._norm(nxt)[0] != want:
                continue
            found = violation(log, ups, nxt, mon)
            if found is not None:
                return found
        raise Unsupported(f"a violation of {prop.name} found by the native search that the Python step "
                          f"function does not make")

    def _failed_steps(self, only: set | None = None) -> dict:
        """The states where a branch of the step fails, as the native search recorded them (it went
        on with their well-defined successors): for each, the errors of its failing branches as the
        Python step function makes them (state id -> [AsmError], the first one its violation);
        ``only``: just those of these states (the rest are not looked at: a spec where most states
        have a failing branch would otherwise run the Python step function from each).  The
        Python step function runs from each such state, and must make the successors the native
        search made (the same, first made in the same order), else Unsupported.  With
        keep_graph the failing branches are also ``error_edges`` (state, choices, error), as the
        Python explorer records them for asmcheck.temporal."""
        from .bfs import Explorer, error_edge
        self.error_edges = []
        n = self.dll.asm_err_states(None)
        if n <= 0:
            return {}
        sids = (ctypes.c_int64 * n)()
        self.dll.asm_err_states(sids)
        py = Explorer(self.m, symmetry=self.sym)    # its admitted_successors: the INVAR constraints, canonical names
        out: dict = {}
        todo = [(i, sid) for i, sid in enumerate(sids) if only is None or sid in only]
        for done, (i, sid) in enumerate(todo):
            self.failed_checked = (done, len(todo))   # (how far the check got, where a time limit ends it)
            m = self.dll.asm_err_succ(i, None, 0)
            buf = (ctypes.c_int64 * max(m, 1))()
            self.dll.asm_err_succ(i, buf, m)
            errors: list = []
            # the check has the time the search had (``check_deadline``, time.monotonic(); the
            # caller turns DeadlineReached into an incomplete result)
            old_deadline = self.m.deadline
            if getattr(self, "check_deadline", None) is not None:
                self.m.deadline = self.check_deadline
            try:
                succ = py.admitted_successors(self.state(sid), errors)
            except AsmError as exc:
                raise Unsupported(f"the steps from a state where a step fails cannot be enumerated "
                                  f"({exc.message})") from None
            finally:
                self.m.deadline = old_deadline
            if not errors:
                raise Unsupported("a run-time error of the native search that the Python step function does not make")
            # each successor once, in the order first made (a choose whose alternatives have the same
            # effect is one alternative in the Python step function, not always in the native one),
            # compared as the Python explorer tells states apart
            got = list(dict.fromkeys(py.layout.freeze(nxt) for _picks, _ups, _raw, nxt, _mon in succ))
            want = list(dict.fromkeys(buf[:m]))
            if len(got) != len(want) or any(py.layout.freeze(self.state(t)) != g for t, g in zip(want, got)):
                raise Unsupported("the well-defined successors of a state where a step fails differ "
                                  "between the engines")
            out[sid] = errors
            if self.keep_graph:
                self.error_edges.extend(error_edge(sid, e) for e in errors)
        return out

    def _stopped_inside(self, sid: int, runs: int) -> str:
        """What the search was doing when the time limit stopped it inside the enumeration of
        state ``sid``'s successors (``runs`` of them so far), as the Python explorer says it:
        the choice points of the state's first sequence of choices ('' for a short enumeration)."""
        from .bfs import SLOW_ENUMERATION, stopped_inside
        from ..semantics.choice import Enumerator
        if runs < SLOW_ENUMERATION or not 0 <= sid < self.nstates:
            return ""          # (no Python step for a short enumeration)
        ch = Enumerator([])
        try:
            self.m.step(self.state(sid), ch)
        except AsmError:
            pass
        return stopped_inside(runs, ch.log, sid)

    def _step_error(self, sid, code, PseudoProperty, Violation):
        """The run-time error of a step from ``sid``, as the Python step function reports it."""
        if code == 9:
            # the Python step function merges the alternatives of a choose that have the same
            # effect before it counts successors: its count is not the native enumeration's
            raise Unsupported("more than 1,000,000 sequences of choices from one state (the Python engine "
                              "merges a choose's alternatives with the same effect before counting)")
        st = self.state(sid)
        try:
            self.m.successors(st)
        except AsmError as e:
            return Violation(PseudoProperty("error", "error", e.span), sid, message=e.message, error=e)
        raise Unsupported("a run-time error of the native search that the Python step function does not make")

    # -------------------------------------------------------------- the explorer's interface
    STATE_CACHE = 65536
    QF_TABLE = None       # the most entries of the table that merges the quotient's nodes (tests: 0)
    QF_DIRECT_BITS = None  # the bits of a recorded pair's direct code (tests: few, so that it overflows)

    @property
    def n_states(self) -> int:
        return self.nstates

    def state(self, sid: int) -> dict:
        st = self._states.get(sid)
        if st is None:
            buf = (ctypes.c_uint64 * self.gen.nwords)()
            self.dll.asm_state(sid, buf)
            st = self.gen.unpack(buf[:])
            if len(self._states) >= self.STATE_CACHE:
                self._states.clear()
            self._states[sid] = st
        return st

    @property
    def parent(self):
        if self._parent is None:
            # written by the engine into the array itself (not through a list of n Python ints:
            # some 40 bytes a state for a moment)
            n = self.nstates
            par = array("q", [0]) * max(n, 1)
            self.dll.asm_parents((ctypes.c_int64 * len(par)).from_buffer(par))
            del par[n:]
            self._parent = par
        return self._parent

    def edge_arrays(self):
        """(sources, targets) of the transitions, sources ascending (recorded with keep_graph)."""
        if self.edge_src is None and self.keep_graph and self.step_quotient_plan is not None:
            self._edges_again()
        if self.edge_src is None:
            raise Unsupported("the state graph was not recorded (keep_graph)")
        return self.edge_src, self.edge_dst

    @property
    def edges(self):
        return _NativeEdges(self)

    # -------------------------------------------------------------- the graph a person reads (--graph)
    @property
    def depth_of(self) -> array:
        """The depth of every explored state (a parent is numbered before its children)."""
        got = getattr(self, "_depth_of", None)
        if got is None or len(got) != self.nstates:
            parent = self.parent
            got = array("l", [0]) * self.nstates
            for s in range(self.nstates):
                p = parent[s]
                got[s] = 0 if p < 0 else got[p] + 1
            self._depth_of = got
        return got

    def graph_edges(self) -> list:
        """Every step between explored states as the Python explorer records it for --graph:
        (source, target, choices) for every sequence of choices the step function enumerates from
        each state (several per pair of states when different choices lead to the same state),
        sources ascending, in the step function's order (:meth:`graph_made` gives each the step as
        the enumeration made it, for its label in the graph).  The step function
        enumerates the steps once per state; the native edge arrays say where each must lead
        (Unsupported when they disagree: then the Python engine writes the graph).  A branch whose
        step fails is no edge, as in the Python explorer."""
        got = getattr(self, "_graph_edges", None)
        if got is not None:
            return got
        from .bfs import Explorer
        py = Explorer(self.m)       # the INVAR constraints, canonical names
        m = self.m
        src_a, dst_a = self.edge_arrays()
        out: list = []
        made: dict = {}
        steps: list = []
        e = 0
        ne = len(src_a)
        try:
            for src in range(self.nstates):
                want = set()
                while e < ne and src_a[e] == src:
                    want.add(dst_a[e])
                    e += 1
                st = self.state(src)
                try:
                    succ = m.successors(st, limit=py.MAX_SUCCESSORS, errors=[])
                except AsmError as exc:
                    raise Unsupported(f"--graph: the steps from state {src} cannot be enumerated "
                                      f"({exc.message})") from None
                got_dst = set()
                for log, _ups, raw, mon in succ:
                    # as Explorer.admitted_successors: the steps the INVAR constraints admit
                    if py.invars and not (py._invar_ok(st, mon) and py._invar_ok(raw)):
                        continue
                    dst = self.find(py._norm(raw))
                    if dst is None:
                        raise Unsupported(f"--graph: a successor of state {src} that the native search did not store")
                    got_dst.add(dst)
                    out.append((src, dst, tuple(c.pick for c in log)))
                    steps.append(_made_step(made, m, log, mon))
                if got_dst != want:
                    raise Unsupported(f"--graph: the successors of state {src} differ between the engines")
        except KeyboardInterrupt:
            # Ctrl-C: the run is incomplete, and the steps found so far are its graph (writing the
            # graph then does not enumerate every step again)
            n = min(len(out), len(steps))
            self._graph_edges, self._graph_made = out[:n], steps[:n]
            raise
        if e != ne:
            raise Unsupported("--graph: the native edges are not ordered by source")
        self._graph_edges, self._graph_made = out, steps
        return out

    def graph_made(self) -> list:
        """For each step of :meth:`graph_edges`: (choices log, monitored values) as the enumeration
        made it, one object for the steps whose choices and values print the same, so that the
        graph labels the step without running it again."""
        self.graph_edges()
        return self._graph_made

    def state_labels(self, items):
        """The truth of each atom (``.term``, ``.env``) in every explored state, evaluated by the
        compiled code: a list of bytearrays (1 where the atom is true, undef counts as false), or
        None when one of them was not translated or fails somewhere (then Python evaluates them)."""
        index = getattr(self, "_label_index", None)
        if index is None:
            index = self._label_index = {}
            for k, (term, env) in enumerate(self.gen.labels):
                index.setdefault((id(term), _env_key(env)), k)
        ks = []
        for a in items:
            k = index.get((id(a.term), _env_key(a.env)))
            if k is None:
                return None
            ks.append(k)
        out = []
        n = self.nstates
        for k in ks:
            buf = ctypes.create_string_buffer(max(n, 1))
            if self.dll.asm_labels(k, buf) != 0:
                return None
            out.append(bytearray(buf.raw[:n]))
        return out

    def step_atoms(self, items, ok_state):
        """For the CTL structure whose nodes are steps: three arrays (src, dst, bits of the atoms
        ``items``: bit k is atom k) for every step between stored states, each triple once, in the
        order of the Python step function's enumeration -- the atoms (which read monitored functions) evaluated in src with
        the values the step read, the others taking every value.  None when the compiled code
        cannot (an atom not translated, more than 64 atoms, an evaluation error)."""
        got = self._recorded_steps(items, ok_state)
        if got is not None:
            return got
        each = self.step_atoms_each(items, ok_state)
        if each is None:
            return None
        rs, rd, rv = array("I"), array("i"), array("B" if len(items) <= 8 else "q")
        for src, n, buf in each:
            rd.extend(buf[0:2 * n:2].tolist())
            rv.extend(buf[1:2 * n:2] if rv.typecode == "q" else buf[1:2 * n:2].tolist())
            rs.extend(array("I", [src]) * n)
        if each.failed:
            return None
        return rs, rd, rv

    def _recorded_steps(self, items, ok_state):
        """:meth:`step_atoms` from the pairs the search recorded (for these atoms), or None."""
        if not items or not self._qf_recorded() or [(id(a.term), _env_key(a.env)) for a in items] != self._qf_keys:
            return None
        okb = bytearray(ok_state) if len(ok_state) else bytearray(1)
        addr = lambda a: ctypes.c_void_p(ctypes.addressof(ctypes.c_char.from_buffer(a)))  # noqa: E731
        m = self.dll.asm_qf_steps(addr(okb), None, None, None)
        if m < 0:
            return None
        rs, rd, rv = array("I", [0]) * max(m, 1), array("i", [0]) * max(m, 1), array("q", [0]) * max(m, 1)
        self.dll.asm_qf_steps(addr(okb), addr(rs), addr(rd), addr(rv))
        del rs[m:], rd[m:], rv[m:]
        return rs, rd, (rv if len(items) > 8 else array("B", rv))

    def step_atoms_each(self, items, ok_state):
        """:meth:`step_atoms` source by source, without keeping the steps: an iterator of
        ``(src, n, buf)`` for every stored state with ``ok_state`` set, ascending -- the first 2n
        entries of ``buf`` (an array('q'), reused from one source to the next) are the (dst, bits)
        pairs of src's steps; after the iteration ``.failed`` tells whether the compiled code
        failed on a state (then the steps given are not all of them).  None when the compiled code
        cannot (an atom not translated, more than 64 atoms)."""
        index = getattr(self, "_label_index", None)
        if index is None:
            self.state_labels([])
            index = self._label_index
        ks = []
        for a in items:
            k = index.get((id(a.term), _env_key(a.env)))
            if k is None or self.gen.label_exprs[k] is None:
                return None
            ks.append(k)
        if not ks or len(ks) > 64:
            return None
        return _StepAtoms(self, (ctypes.c_int64 * len(ks))(*ks), len(ks), ok_state)

    def find(self, st: dict):
        """The number of the explored state equal to ``st``, or None."""
        try:
            w = self.gen.pack(st)
        except Unsupported:
            return None
        sid = self.dll.asm_find((ctypes.c_uint64 * self.gen.nwords)(*w))
        return None if sid < 0 else sid

    def picks_between(self, src: int, dst: int) -> tuple:
        """The choices of the first step of the Python step function from ``src`` to ``dst``: the
        native engine's choices of that step followed once (:meth:`guided_step`), else the
        successors of ``src`` enumerated.  The successors of the last source enumerated are kept:
        edges are read source by source, so the third step asked from one source (in a row)
        enumerates it rather than asking the native engine again."""
        from .bfs import ReplayError
        cache = self._picks_cache
        if cache is None or cache[0] != src:
            asked = getattr(self, "_picks_asked", None)
            if asked is None or asked[0] != src:
                asked = self._picks_asked = [src, 0]
            asked[1] += 1
            if asked[1] <= 2:
                got = self.guided_step(src, dst)
                if got is not None:
                    return tuple(c.pick for c in got[1])
            by_dst: dict = {}
            for log, ups, nxt, mon in self.m.successors(self.state(src), errors=[]):
                sid = self.find(self._norm(nxt)[0])
                if sid is not None and sid not in by_dst:
                    by_dst[sid] = tuple(c.pick for c in log)
            cache = self._picks_cache = (src, by_dst)
        picks = cache[1].get(dst)
        if picks is None:
            raise ReplayError(f"no step of the Python step function goes from state {src} to state {dst}")
        return picks

    # -------------------------------------------------------------- the native engine's choices of a step
    # How the native run's choice vector (c->idx / c->cnt, native_rt.c choice()) gives the Python
    # step function's choices, so that a trace's step runs the Python step once instead of once
    # per successor.  The two engines enumerate the runs of a step in the same order (an odometer
    # over the choice points, the last fastest), but their choice points differ in three ways:
    #   - a monitored location with one possible value is a choice point (n = 1) of the Python
    #     step only; one with n > 1 values is a point of both, its values in the same order;
    #   - a choose rule of the Python step is one point over the *distinct effects* of its body
    #     (over every candidate and every choice the body makes), and no point when there is one
    #     effect.  The native choose whose body makes no choice is either merged
    #     (Generator.choose_merged: one point over the distinct effects, as the Python one) or plain
    #     (one point over the candidates when there are two or more); a plain choose's body makes
    #     its own points after the candidate's;
    #   - the monitored values a property reads are not the step's (native pchoice, Python:
    #     evaluated apart).
    # The guide (_Guide) runs the Python step and reads the native vector as it goes: a monitored
    # point with n > 1 values, and a choose with n > 1 effects, take the next native point, which
    # must have n alternatives (a merged choose, or a plain one whose candidates all have effects of
    # their own: the same numbering).  A choose whose body makes choices (an agent's program that
    # reads an input) is plain natively: its candidate's point, then the points of the body's run,
    # name one run of the body among those the Python step worked the effects out from (_GuideSub,
    # one per candidate and sequence of the body's choices).  When every run has an effect of its
    # own, effect r is run r.  When runs share effects (a plain choose, with or without choices in
    # its body), the native number is a run's: the effect is the one whose first run it is, and as
    # the effects' first runs ascend with their numbers, the guide tries a number and checks it
    # after the choose (the rule gives the choice the effect's first run's log, ``nested``), the
    # step running again with the number bounded by half each time (_GuideRetry, GUIDED_RUNS).  A
    # choose with one effect from two or more candidates may be a plain native point (then at 0
    # among as many alternatives as candidates) or none: the guide follows both readings until one
    # fails (they never give different choices: where they would, it gives up).  It gives up (the
    # caller enumerates, as without the native engine) at a choose whose body runs a choose (a
    # nested choose), a native point whose number of alternatives is not the Python point's, or a
    # vector not read to its end.  Why the choices it gives are the FIRST the Python enumeration
    # meets to the target: two runs with the same effect at a choose continue alike (the choose's
    # bindings are local to its body), so the native engine's first run to the target takes at each
    # plain choose the first run of its effect (0 at one whose candidates have one effect); over
    # such runs the reading above is a one-to-one map onto the Python runs that keeps their order,
    # hence the first native run to the target is the first Python one.  The caller checks anyway
    # that the step gives the stored target: a reading gone wrong costs the enumeration, never
    # another trace.
    from ..semantics.choice import Choice as _Choice, Chooser as _Chooser, Enumerator as _Enumerator

    class _GuideLost(Exception):
        """The guide cannot read the native choices as the Python step's (the caller enumerates)."""

    class _GuideSub(_Enumerator):
        """A sub-chooser a choose's outcomes are worked out with (one run of its body: a candidate
        and a sequence of the body's own choices); ``deep`` once the body ran a choose."""

        def __init__(self, prefix, cand: int):
            super().__init__(prefix)
            self.cand = cand
            self.deep = False

        def sub(self, prefix):
            self.deep = True
            return super().sub(prefix)

        def points(self, ncand: int):
            """The native points of this run of the body: (numbers, sizes)."""
            own = [x for x in self.log if x.n > 1]
            lead = ncand > 1
            return ([self.cand] if lead else []) + [x.index for x in own], \
                ([ncand] if lead else []) + [x.n for x in own]

    class _GuideRetry(Exception):
        """The effect the guide took at a plain choose whose candidates share effects is not the
        native run's: the step runs again with the number of the effect bounded (``k``: which such
        choose in the step, ``bounds``: lowest and highest number left)."""

        def __init__(self, k, bounds):
            super().__init__(k, bounds)
            self.k, self.bounds = k, bounds

    class _Guide(_Chooser):
        """The Python step's chooser that follows the native engine's choice vector ``idx`` /
        ``cnt`` (see above); records the choices as :class:`Enumerator` does.  ``bounds``: the
        numbers of the effects left to try at the plain chooses whose candidates share effects
        (the k-th such choose of the step: (lowest, highest)), from the runs before."""

        enumerates = True

        def __init__(self, idx, cnt, bounds=None):
            super().__init__()
            self.idx, self.cnt = idx, cnt
            self.at = {0}           # where the next native point may be (both readings of a choose)
            self.group = None       # the choose whose outcomes are being worked out: its body's runs
            self.ncand = 0
            self.nlog = 0
            self.bounds = bounds if bounds is not None else {}
            self.nshared = 0        # the plain chooses whose candidates share effects met so far
            self.pending = None     # the last one's choice, to check: (log position, runs, run, k, lo, hi, j)

        @property
        def memo(self):
            # a choose rule reads its chooser's memo first (rules.py): a new choose starts
            self._check()
            self._settle()
            self.group = []
            self.ncand = 0
            return None

        def sub(self, prefix):
            g = self.group
            if g is None:
                raise NativeExplorer._GuideLost()
            if not prefix:
                self.ncand += 1     # (each candidate's body runs first with no choice given)
            e = NativeExplorer._GuideSub(prefix, self.ncand - 1)
            g.append(e)
            return e

        def _check(self):
            """The effect taken at the last choose whose candidates share effects: the choose rule
            set the choice's nested log to that of the effect's first run of the body (rules.py),
            which must be the run the native engine took; else the step runs again with the
            effect's number bounded (the effects' first runs ascend with their numbers)."""
            got, self.pending = self.pending, None
            if got is None:
                return
            pos, g, r, k, lo, hi, j = got
            nested = self.log[pos].nested if pos < len(self.log) else None
            if nested is g[r].log:
                return
            first = next((x for x, e in enumerate(g) if e.log is nested), None)
            if first is None or first == r:
                raise NativeExplorer._GuideLost()
            raise NativeExplorer._GuideRetry(k, (j + 1, hi) if first < r else (lo, j - 1))

        def _flat(self, g) -> bool:
            """Whether no run of the body made a choice point the native engine makes."""
            for e in g:
                if e.deep:
                    raise NativeExplorer._GuideLost()
                if any(x.n > 1 for x in e.log):
                    return False
            return True

        def _settle(self):
            """The choose before, if it made no choice point of the Python step (one effect)."""
            g, self.group = self.group, None
            if not g:
                return
            if not self._flat(g):
                raise NativeExplorer._GuideLost()
            k = self.ncand
            if k > 1:
                idx, cnt = self.idx, self.cnt
                self.at = self.at | {q + 1 for q in self.at if q < len(idx) and cnt[q] == k and idx[q] == 0}

        def choose(self, kind, label, options, values_repr=None) -> int:
            self._check()
            if len(self.log) != self.nlog:
                raise NativeExplorer._GuideLost()          # (the step started again: a deep rule)
            n = len(options)
            idx, cnt, L = self.idx, self.cnt, len(self.idx)
            picks, at = set(), set()
            shared = set()          # (run of the body, where the next point is): a choose whose candidates share effects
            g = None
            if kind == "choose" and self.group is not None:
                g, self.group = self.group, None
                flat = self._flat(g)
                if not flat or len(g) == n:
                    # a plain choose: the candidate's point and those of the body's run; when every
                    # run has an effect of its own, outcome r is run r
                    for q in self.at:
                        for r, e in enumerate(g):
                            num, size = e.points(self.ncand)
                            if list(idx[q:q + len(num)]) == num and list(cnt[q:q + len(num)]) == size:
                                if len(g) == n:
                                    picks.add(r)
                                    at.add(q + len(num))
                                else:
                                    shared.add((r, q + len(num)))
                if flat:
                    # a merged choose: one point over the effects
                    for q in self.at:
                        if q < L and cnt[q] == n:
                            picks.add(idx[q])
                            at.add(q + 1)
                        elif q < L and cnt[q] == self.ncand != n:
                            shared.add((idx[q], q + 1))
            elif kind in ("choose", "monitored"):
                if self.group:      # (an open choose without candidates yet: its guard or range reads it)
                    self._settle()
                if n == 1 and kind == "monitored":
                    picks.add(0)
                    at = self.at
                else:
                    for q in self.at:
                        if q < L and cnt[q] == n:
                            picks.add(idx[q])
                            at.add(q + 1)
            if shared:
                # the native number is a run's (a candidate's), not an effect's: the effect whose
                # first run it is has a number between these bounds, tried and checked (_check)
                runs = {r for r, _ in shared}
                if picks or len(runs) != 1:
                    raise NativeExplorer._GuideLost()
                r = runs.pop()
                k = self.nshared
                self.nshared += 1
                lo, hi = self.bounds.get(k, (max(0, n - (len(g) - r)), min(r, n - 1)))
                if lo > hi:
                    raise NativeExplorer._GuideLost()
                i = (lo + hi) // 2
                self.pending = (len(self.log), g, r, k, lo, hi, i)
                at = {q for _, q in shared}
            else:
                if len(picks) != 1:
                    raise NativeExplorer._GuideLost()
                i = picks.pop()
            self.at = at
            self.log.append(NativeExplorer._Choice(kind, label, n, i, options[i], i))
            self.nlog = len(self.log)
            return i

        def finish(self):
            """After the step: every native point read."""
            self._check()
            self._settle()
            if len(self.idx) not in self.at or len(self.log) != self.nlog:
                raise NativeExplorer._GuideLost()

    def native_choices(self, src: int, dst: int):
        """The native engine's choice vector (idx, cnt) of the first run of the step from the
        stored state ``src`` whose successor is the stored state ``dst`` (native_bfs.c,
        asm_first_choices), or None when it cannot say."""
        fn = getattr(self.dll, "asm_first_choices", None)
        if fn is None:
            return None
        buf = getattr(self, "_choices_buf", None)
        if buf is None:
            buf = self._choices_buf = (ctypes.c_int32 * 8192)()
        n = fn(src, dst, buf, len(buf))
        if n < 0:
            return None
        got = buf[:2 * n]
        return got[:n], got[n:]

    #: the runs of the Python step a guided step may take (the plain chooses whose candidates share
    #: effects: each run narrows the number of one's effect by half)
    GUIDED_RUNS = 16

    def guided_step(self, src: int, dst: int, st: dict | None = None, want: dict | None = None):
        """The first step of the Python step function from the stored state ``src`` (its state
        ``st``) to the stored state ``dst`` (``want``), run once along the native engine's choices:
        (next state, choices log, update set, monitored values, raw next state, renaming) as
        :meth:`replay_steps` records a step, or None when the native engine cannot say or its
        choices do not read as the Python step's (see the comment above _GuideLost) or do not lead
        to ``dst``."""
        hint = self.native_choices(src, dst)
        if hint is None:
            return None
        if st is None:
            st = self.state(src)
        bounds: dict = {}
        for _ in range(self.GUIDED_RUNS):
            guide = NativeExplorer._Guide(*hint, bounds)
            try:
                ups, raw, ctx = self.m.step(st, guide)
                guide.finish()
                break
            except NativeExplorer._GuideRetry as again:
                bounds[again.k] = again.bounds
            except (AsmError, NativeExplorer._GuideLost):
                return None
        else:
            return None
        nxt, mapping = self._norm(raw)
        if (nxt != want) if want is not None else (self.find(nxt) != dst):
            return None
        return nxt, guide.log, ups, ctx.mon, raw, mapping

    def path_to(self, sid: int) -> list[int]:
        path = []
        while sid != -1:
            path.append(sid)
            sid = self.dll.asm_parent(sid)
        return path[::-1]

    def replay(self, path, last_picks=None, last_target=None):
        """Rebuild each step of ``path`` with the Python step function (the first successor that
        equals the next stored state gives the choices); entries as the Python explorer's."""
        steps = [(None, sid) for sid in path[1:]]
        if last_picks is not None:
            steps.append((last_picks, last_target))
        return self.replay_steps(path[0], steps)

    def replay_steps(self, first: int, steps: list) -> list:
        from ..semantics.machine import ScriptChooser
        from .bfs import ReplayError
        if self.sym is not None:
            return self._replay_concrete(first, steps)
        m = self.m
        st0 = self.state(first)
        init_log = None
        for log, st in m.initial_states():
            if st == st0:
                init_log = log
                break
        if init_log is None:
            raise ReplayError("the initial state does not replay")
        out = [(st0, init_log, None, getattr(m, "init_mon", {}), None, None)]
        cur, src = st0, first
        for picks, dst in steps:
            want = self.state(dst)
            found = None
            if picks is not None:
                ch = ScriptChooser(picks)
                ups, raw, ctx = m.step(cur, ch)
                nxt, mapping = self._norm(raw)
                if nxt == want:
                    found = (nxt, ch.log, ups, ctx.mon, raw, mapping)
            else:
                found = self.guided_step(src, dst, cur, want)
            if found is None and picks is None:
                for log, ups, raw, mon in m.successors(cur, errors=[]):
                    nxt, mapping = self._norm(raw)
                    if nxt == want:
                        found = (nxt, log, ups, mon, raw, mapping)
                        break
            if found is None:
                raise ReplayError(f"step to state {dst} does not replay")
            out.append(found)
            cur, src = want, dst
        return out

    def _replay_concrete(self, first: int, steps: list) -> list:
        """:meth:`replay_steps` under symmetry reduction, as the Python explorer's: the stored states are
        class representatives, the trace concrete (see bfs.Explorer._replay_concrete).  The choices of
        a step not given are those of the representative's first step into the stored target."""
        from ..semantics.machine import ScriptChooser
        from .bfs import Explorer
        picked = []
        for picks, dst in steps:
            if picks is None:
                src = first if not picked else picked[-1][1]
                picks = self.picks_between(src, dst)
            picked.append((picks, dst))
        py = Explorer(self.m, symmetry=self.sym)
        want0 = self.state(first)
        init_log = None
        for log, st in self.m.initial_states():
            if self.sym.canon(st)[0] == want0:
                init_log = log
                break
        py.via = {first: tuple(c.pick for c in init_log or ())}
        py.frozen = _StoredFrozen(self, py)
        return py._replay_concrete(first, picked)

    def close(self):
        try:
            self.dll.asm_free()
        except Exception:
            pass


def _env_count(name: str, default: int) -> int:
    """A positive count from the environment variable ``name`` (a tuning knob of the tests):
    ``default`` when it is unset or empty; a usage error naming it otherwise."""
    text = os.environ.get(name, "").strip()
    if not text:
        return default
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise UsageError(f"{name}={text!r}: give a whole number of states, 1 or more")
    return n


def _sym_refused(dll) -> bool:
    """Whether a symmetric search stopped on a state with too many numberings (native_sym.c)."""
    fn = dll.asm_sym_refused
    fn.restype, fn.argtypes = ctypes.c_int64, []
    return bool(fn())


class _StoredFrozen:
    """The native explorer's stored states as an Explorer's ``frozen`` list (its layout's frozen
    forms), for the replay of a symmetric trace."""

    def __init__(self, ex, py):
        self.ex, self.py = ex, py

    def __getitem__(self, sid: int):
        return self.py.layout.freeze(self.ex.state(sid))


def _made_step(made: dict, machine, log, mon: dict) -> tuple:
    """(log, mon) of a step for its label in the graph (:meth:`NativeExplorer.graph_edges`), the
    object kept in ``made`` for an earlier step whose choices and monitored values print the same
    (the label is made of those texts only)."""
    from ..semantics.values import show

    def flat(choices):
        for c in choices or ():
            yield c
            yield from flat(getattr(c, "nested", None))
    key = (tuple((c.kind, c.label, tuple((k, show(v)) for k, v in c.value.items()) if isinstance(c.value, dict)
                  else show(c.value)) for c in flat(log)),
           tuple(sorted((machine.location_text(k), show(v)) for k, v in mon.items())))
    got = made.get(key)
    if got is None:
        got = made[key] = (log, dict(mon))
    return got


def _env_key(env) -> tuple:
    items = tuple(sorted((env or {}).items(), key=lambda kv: kv[0]))
    try:
        hash(items)
        return items
    except TypeError:
        return repr(items)


class _StepAtoms:
    """The iterator of :meth:`NativeExplorer.step_atoms_each`."""

    def __init__(self, ex, karr, nk: int, ok_state):
        self.ex, self.karr, self.nk, self.ok = ex, karr, nk, ok_state
        self.failed = False

    def __iter__(self):
        dll = self.ex.dll
        cap = 1024
        buf = array("q", [0]) * (2 * cap)
        for src in range(self.ex.nstates):
            if not self.ok[src]:
                continue
            while True:
                n = dll.asm_step_atoms(src, self.karr, self.nk, (ctypes.c_int64 * len(buf)).from_buffer(buf), cap)
                if n != -2:
                    break
                cap *= 4
                buf = array("q", [0]) * (2 * cap)
            if n < 0:
                self.failed = True
                return
            yield src, n, buf


class _NativeEdges:
    """The transitions as (source, target, choices), the choices found on demand by the Python
    step function (only traces and the step mode of the temporal checks ask for them)."""

    def __init__(self, ex: NativeExplorer):
        self.ex = ex
        self.src, self.dst = ex.edge_arrays()

    def __len__(self):
        return len(self.src)

    def __getitem__(self, i):
        a, b = self.src[i], self.dst[i]
        return a, b, self.ex.picks_between(a, b)

    def __iter__(self):
        for i in range(len(self.src)):
            yield self[i]
