"""The partitioned search's expander over the native engine's compiled step function.

:class:`NativeExpander` offers what :class:`asmcheck.parallel.expand.PythonExpander` offers (see
:mod:`asmcheck.parallel.expand`), computed by the C code the native engine generates for the spec
(:mod:`asmcheck.explore.native`, compiled once and cached by the hash of its source; every
process, every Ray actor, compiles or loads it itself):

* a key is the packed state, the bytes of its fixed-width words: equal states pack to equal
  bytes in every process, and :meth:`NativeExpander.owner_hash` hashes the bytes;
* the successors come in the order of the Python step function's enumeration, INVAR-filtered,
  with the same state and step property checks and the same deadlock check;
* a successor's choices travel as its position among its parent's successors (an ``int``);
  the coordinator turns a position into the choices of the Python step function only for the
  few states a trace (or ``--graph``) shows (:meth:`asmcheck.parallel.view.PartitionedExplorer.picks`).

Where the compiled code cannot answer as the Python step function would (a property that cannot
be evaluated, a step that fails), that state is expanded again by the Python step function, so
the messages and errors are the reference's.  A spec the native engine refuses, or a value it
cannot encode at run time, raises :class:`Refused` (the search then runs on the Python expander).
Packed states hold the codes of the value table (sequences, sets, maps, strings, values of type
Any) only by a number local to the process: such specs are refused too.
"""
from __future__ import annotations

import ctypes
import hashlib
import struct

from ..errors import AsmError
from .expand import Expansion, PythonExpander


class Refused(Exception):
    """The native expander cannot expand this spec (the one-line reason)."""


class MoreSlots(Refused):
    """A state holds more elements made by extend than the compiled code has slots for
    (``cn_k`` per domain): the search can start again on code with more."""

    def __init__(self, reason: str, cn_k: int):
        super().__init__(reason)
        self.cn_k = cn_k

    def __reduce__(self):
        return (MoreSlots, (str(self), self.cn_k))


_u8p = ctypes.POINTER(ctypes.c_uint8)
_u64p = ctypes.POINTER(ctypes.c_uint64)
_i64p = ctypes.POINTER(ctypes.c_int64)
_EXPAND_SIG = (ctypes.c_int64, [_u64p, _u8p, ctypes.c_int64, ctypes.c_int64, _u64p, _u64p, _u8p, _i64p])


def _table_slots(gen) -> list:
    """[(word, type, map function or None)] of the slots whose words hold numbers of the value
    table (sequences, sets, bags, maps, strings, tuples, values of type Any, the defined
    locations of a function over an infinite domain): those numbers are the process's own."""
    from ..explore.native import T
    out = []
    for s, vals in enumerate(gen.slot_values):
        typ = gen.slot_types[s]
        if isinstance(typ, tuple):
            out.append((gen.words[s], None, typ[1]))
            continue
        if vals is not None:
            continue
        r = T.root(typ)
        if (r is T.STRING or (isinstance(r, T.Domain) and r.kind == "any")
                or (isinstance(r, T.Struct) and r.kind in ("Seq", "Prod", "Powerset", "Bag", "Map"))):
            out.append((gen.words[s], typ, None))
    return out


_Q = struct.Struct("<q")
_SORTED = {4, 5, 10, 11}          # kinds whose elements the value table keeps sorted by code


class ValueCodec:
    """Values of the value table <-> bytes that mean the same in every process: the value's
    structure, with its elements' encodings; the elements of a set, bag or map in the order of
    their encodings (the table orders them by code, which is the process's own)."""

    def __init__(self, gen, dll):
        from ..explore.native import T
        self.T = T
        self.codec = gen.codec
        self.dll = dll
        self.out: dict = {}            # code -> bytes
        self.into: dict = {}           # bytes -> code
        fn = dll.asm_x_intern
        fn.restype, fn.argtypes = ctypes.c_int64, [ctypes.c_int64, _i64p, ctypes.c_int64]
        self._intern = fn

    def intern(self, kind: int, codes) -> int:
        n = len(codes)
        buf = (ctypes.c_int64 * max(n, 1))(*codes)
        i = self._intern(kind, buf, n)
        if i < 0:
            raise MemoryError("the native value table is out of memory")
        return i

    def _elem_types(self, kind, typ, fn, n):
        T = self.T
        if fn is not None:
            dt = fn.domain[0] if len(fn.domain) == 1 else T.Struct("Prod", tuple(fn.domain))
            return [dt, fn.codomain] * (n // 2)
        r = T.root(typ)
        if kind == 3:
            return [T.INTEGER] * n
        if kind == 16:
            return None
        if isinstance(r, T.Struct):
            if r.kind == "Prod":
                return list(r.args)
            if r.kind == "Map":
                return [r.args[0], r.args[1]] * (n // 2)
            return [r.args[0]] * n
        raise Refused(f"a value of type {typ} in the value table")

    def encode(self, x: int, typ, fn=None) -> bytes:
        """The bytes of the value whose code is ``x`` (of static type ``typ``; ``fn``: the map of
        a function over an infinite domain)."""
        if x >= 1 << 63:
            x -= 1 << 64
        b = self.out.get((x, id(typ), id(fn)))
        if b is not None:
            return b
        from ..explore.native import UNDEF_V
        T = self.T
        r = T.root(typ) if typ is not None else None
        table = fn is not None or r is T.STRING or (isinstance(r, T.Domain) and r.kind == "any") or (
            isinstance(r, T.Struct) and r.kind in ("Seq", "Prod", "Powerset", "Bag", "Map"))
        if x == UNDEF_V or not table:
            b = b"i" + _Q.pack(x)
        else:
            kind, elems = self.codec.fetch(x)
            if kind == 16:
                tag, code = elems
                parts = [_Q.pack(tag) + self.encode(code, self.codec.any_tags[tag][1])]
            else:
                tys = self._elem_types(kind, typ, fn, len(elems))
                parts = [self.encode(e, t) for e, t in zip(elems, tys)]
                if kind in (5, 11):
                    pairs = sorted(zip(parts[0::2], parts[1::2]))
                    parts = [_Q.pack(len(a)) + a + _Q.pack(len(v)) + v for a, v in pairs]
                elif kind in _SORTED:
                    parts = sorted(parts)
                    parts = [_Q.pack(len(p)) + p for p in parts]
                else:
                    parts = [_Q.pack(len(p)) + p for p in parts]
            b = b"t" + _Q.pack(kind) + _Q.pack(len(elems)) + b"".join(parts)
        self.out[(x, id(typ), id(fn))] = b
        return b

    def decode(self, b: bytes, typ, fn=None) -> int:
        """This process's code of the value encoded as ``b``."""
        x = self.into.get(b)
        if x is None:
            x = self.into[b] = self._decode(b, 0, typ, fn)[0]
        return x

    def _decode(self, b: bytes, i: int, typ, fn):
        if b[i:i + 1] == b"i":
            return _Q.unpack_from(b, i + 1)[0], i + 9
        kind = _Q.unpack_from(b, i + 1)[0]
        n = _Q.unpack_from(b, i + 9)[0]
        i += 17
        if kind == 16:
            tag = _Q.unpack_from(b, i)[0]
            code, i = self._decode(b, i + 8, self.codec.any_tags[tag][1], None)
            return self.intern(kind, (tag, code)), i
        tys = self._elem_types(kind, typ, fn, n)
        codes = []
        for t in tys:
            ln = _Q.unpack_from(b, i)[0]
            i += 8
            code, _ = self._decode(b, i, t, None)
            codes.append(code)
            i += ln
        if kind in (5, 11):
            pairs = sorted(zip(codes[0::2], codes[1::2]))
            codes = [c for pr in pairs for c in pr]
        elif kind in _SORTED:
            codes.sort()
        return self.intern(kind, codes), i


class NativeExpander:
    """Successors and property checks of packed states by the compiled step function."""

    CAP = 256

    def __init__(self, machine, state_props=(), step_props=(), deadlock=False, cn_k=None):
        from ..explore.native import NativeExplorer, Unsupported
        self.m = machine
        self.state_props = list(state_props)
        self.step_props = list(step_props)
        self.deadlock = deadlock
        try:
            nx = NativeExplorer(machine, state_props=self.state_props, step_props=self.step_props, deadlock=deadlock)
            if cn_k is not None and nx.gen.dyn and cn_k != nx.gen.cn_k:
                self._more_slots(nx, cn_k)
        except Unsupported as e:
            raise Refused(str(e)) from None
        except RecursionError:
            raise Refused("the spec nests more deeply than the C generator follows") from None
        self.nx = nx
        self.gen = nx.gen
        self.dll = nx.dll
        self.compile_seconds = nx.compile_seconds
        fn = self.dll.asm_x_expand
        fn.restype, fn.argtypes = _EXPAND_SIG
        self._fn = fn
        self.nwords = self.gen.nwords
        self._fmt = struct.Struct(f"<{self.nwords}Q")
        self.tslots = _table_slots(self.gen)
        self.vc = ValueCodec(self.gen, self.dll)
        if self.tslots:
            self._key_plan()
        # a composite value asked for by value (an initial state, a state the Python step
        # function made) enters this process's value table
        codec = self.gen.codec

        def found(key, codec=codec, vc=self.vc):
            i = codec.comp_ids[key] = vc.intern(key[0], key[1])
            return i
        codec.found = found
        # the value table's first entries (the values the generated code names)
        if self.gen.dyn:
            self.dll.asm_canon_reset()
        self.dll.asm_start((ctypes.c_uint64 * 1)(), 0, -1, -1, -1.0, 0, 0)
        self.ninv = len(self.state_props)
        self.nstep = len(self.step_props)
        self._skip_cache: dict = {}
        self._py = None
        self._grow(self.CAP)
        self._sfail = (ctypes.c_uint8 * max(self.ninv, 1))()
        self._info = (ctypes.c_int64 * 4)()

    @staticmethod
    def _more_slots(nx, cn_k: int) -> None:
        """The code again with ``cn_k`` element slots per extended domain (as the native search
        does when it meets a state with more elements)."""
        from ..explore import native_build
        from ..explore.native import Generator, build_library
        old = nx.gen
        gen = Generator(nx.m, nx.state_props)
        gen.step_props = old.step_props
        gen.invars = old.invars
        gen.invar_pre = getattr(old, "invar_pre", False)
        gen.label_atoms = getattr(old, "label_atoms", None)
        gen.cn_k = cn_k
        src = gen.generate()
        dll = build_library(src)
        gen.codec.dll = dll
        nx.gen, nx.dll = gen, dll
        nx.compile_seconds += native_build.last_compile_seconds

    def _grow(self, cap: int) -> None:
        self.cap = cap
        self._succ = (ctypes.c_uint64 * (cap * self.nwords))()
        self._masks = (ctypes.c_uint64 * (2 * cap))()

    @property
    def py(self) -> PythonExpander:
        """The Python step function (for the states the compiled code leaves to it)."""
        if self._py is None:
            self._py = PythonExpander(self.m, self.state_props, self.step_props, self.deadlock)
        return self._py

    # ------------------------------------------------------------------ keys
    def owner_hash(self, key: bytes) -> int:
        return int.from_bytes(hashlib.blake2b(key, digest_size=8).digest(), "little")

    @staticmethod
    def freeze(key):
        return key

    @staticmethod
    def thaw(frozen):
        return frozen

    def key_of(self, st: dict) -> bytes:
        from ..explore.native import MASK64, Unsupported
        try:
            return self.key_of_words(self._fmt.pack(*[w & MASK64 for w in self.gen.pack(st)]))
        except Unsupported as e:
            raise Refused(str(e)) from None

    def _key_plan(self) -> None:
        """Where the words of the value table lie in a packed state: the byte ranges of the other
        words (kept in the key, in order) and the offsets of the table's words."""
        table = sorted({wi for wi, _, _ in self.tslots})
        self._toffs = [8 * wi for wi, _, _ in self.tslots]
        segs = []
        for wi in range(self.nwords):
            if wi in table:
                continue
            if segs and segs[-1][1] == 8 * wi:
                segs[-1][1] = 8 * wi + 8
            else:
                segs.append([8 * wi, 8 * wi + 8])
        self._segs = [tuple(x) for x in segs]
        self._rest = struct.Struct(f"<{self.nwords - len(table)}Q")
        self._rest_index = [wi for wi in range(self.nwords) if wi not in table]
        self._suffix: dict = {}        # the table's words (this process's codes) -> their encodings
        self._codes: dict = {}         # encodings -> this process's codes

    def key_of_words(self, raw: bytes) -> bytes:
        """The key of the packed state ``raw`` (this process's words): the words but those holding
        numbers of the value table, then those values' encodings."""
        if not self.tslots:
            return raw
        tail = b"".join([raw[o:o + 8] for o in self._toffs])
        suf = self._suffix.get(tail)
        if suf is None:
            parts = []
            enc = self.vc.encode
            for (wi, typ, fn), o in zip(self.tslots, self._toffs):
                b = enc(_Q.unpack_from(raw, o)[0], typ, fn)
                parts.append(_Q.pack(len(b)))
                parts.append(b)
            suf = b"".join(parts)
            if len(self._suffix) > 1 << 20:
                self._suffix.clear()
            self._suffix[tail] = suf
        return b"".join([raw[a:b] for a, b in self._segs]) + suf

    def words_of(self, key: bytes) -> list:
        """This process's words of the packed state ``key``."""
        if not self.tslots:
            return list(self._fmt.unpack(key))
        n = self._rest.size
        w = [0] * self.nwords
        for wi, x in zip(self._rest_index, self._rest.unpack_from(key, 0)):
            w[wi] = x
        suf = key[n:]
        codes = self._codes.get(suf)
        if codes is None:
            codes = []
            i = 0
            dec = self.vc.decode
            for wi, typ, fn in self.tslots:
                ln = _Q.unpack_from(suf, i)[0]
                i += 8
                codes.append(dec(suf[i:i + ln], typ, fn) & 0xFFFFFFFFFFFFFFFF)
                i += ln
            if len(self._codes) > 1 << 20:
                self._codes.clear()
            codes = self._codes[suf] = tuple(codes)
        for (wi, _, _), x in zip(self.tslots, codes):
            w[wi] = x
        return w

    def state_of(self, key: bytes) -> dict:
        return self.gen.unpack(self.words_of(key))

    # ------------------------------------------------------------------ steps
    def initial(self) -> list:
        """The initial states [(key, picks)], as the Python expander gives them (duplicates kept)."""
        return [(self.key_of(dict(k)), picks) for k, picks in self.py.initial()]

    def _skip(self, skip) -> ctypes.Array:
        arr = self._skip_cache.get(skip)
        if arr is None:
            names = set(skip)
            arr = (ctypes.c_uint8 * max(self.ninv + self.nstep, 1))(
                *[1 if p.name in names else 0 for p in self.state_props + self.step_props])
            self._skip_cache[skip] = arr
        return arr

    def expand(self, key: bytes, skip=frozenset(), successors=True) -> Expansion:
        skip = frozenset(skip)
        if self.tslots:
            words = (ctypes.c_uint64 * self.nwords)(*self.words_of(key))
        else:
            words = (ctypes.c_uint64 * self.nwords).from_buffer_copy(key)
        sk = self._skip(skip)
        while True:
            n = self._fn(words, sk, 1 if successors else 0, self.cap, self._succ, self._masks, self._sfail, self._info)
            if n != -3:
                break
            self._grow(self.cap * 4)
        if n == -2:
            from ..explore.native import Unsupported
            try:
                more = self.gen.dyn and self.nx._canon_refusal()
            except Unsupported as e:
                raise Refused(str(e)) from None
            if more:
                raise MoreSlots(f"more than {self.gen.cn_k} elements of a domain made by extend in one state",
                                self.gen.cn_k)
            raise Refused(self._hard_error())
        res = Expansion()
        sfail = self._sfail
        st = None
        for i in range(self.ninv):
            f = sfail[i]
            if not f:
                continue
            if f == 2:
                if st is None:
                    st = self.state_of(key)
                try:
                    ok = self.state_props[i].check_state(self.m, st)
                except AsmError as e:
                    res.state_failures.append((i, f"cannot be evaluated: {e.message}", e))
                    continue
                if not ok:
                    res.state_failures.append((i, "", None))
            else:
                res.state_failures.append((i, "", None))
        if not successors:
            return res
        if n == -1:
            # a step fails: the Python step function says how (and which successors it has)
            return self._python(key, skip, res.state_failures)
        size = 8 * self.nwords
        raw = ctypes.string_at(self._succ, n * size) if n else b""
        out = res.succ
        masks = self._masks
        targets = set()
        conv = self.key_of_words if self.tslots else None
        for j in range(n):
            k = raw[j * size:(j + 1) * size]
            if conv is not None:
                k = conv(k)
            out.append((k, j))
            targets.add(k)
            bad = masks[2 * j]
            if bad:
                if masks[2 * j + 1] & bad:
                    return self._python(key, skip, res.state_failures)
                for i in range(self.nstep):
                    if bad >> i & 1:
                        res.step_failures.append((j, i, "", None))
        res.distinct = len(targets)
        if self.deadlock and all(t == key for t in targets):
            res.deadlock = "no successor" if not targets else "the only successor is the state itself"
        return res

    def _python(self, key: bytes, skip, state_failures) -> Expansion:
        """The expansion of ``key`` by the Python step function, its successors as packed states
        and positions."""
        e = self.py.expand(tuple(self.state_of(key).items()), skip, True)
        e.state_failures = state_failures
        e.succ = [(self.key_of(dict(k)), j) for j, (k, _picks) in enumerate(e.succ)]
        return e

    def _hard_error(self) -> str:
        code, site = self._info[0], self._info[1] - 1000
        reasons = self.gen.site_reasons
        if code == 4 and 0 <= site < len(reasons):
            return f"{reasons[site]}, reached at run time"
        return ("a value outside the native encoding at run time" if code == 4 else
                "more choices in one step than the native search follows" if code == 6 else
                f"a run-time condition the native search does not handle (code {code})")

    def close(self) -> None:
        self.nx = None
