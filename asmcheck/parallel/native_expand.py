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


_u8p = ctypes.POINTER(ctypes.c_uint8)
_u64p = ctypes.POINTER(ctypes.c_uint64)
_i64p = ctypes.POINTER(ctypes.c_int64)
_EXPAND_SIG = (ctypes.c_int64, [_u64p, _u8p, ctypes.c_int64, ctypes.c_int64, _u64p, _u64p, _u8p, _i64p])


def _portable(gen) -> str | None:
    """Why the packed states of ``gen`` (a native Generator) do not mean the same in every
    process, or None when they do."""
    from ..explore.native import T
    if gen.dyn:
        return "domains extended at run time (their elements are renamed per search)"
    for s, vals in enumerate(gen.slot_values):
        typ = gen.slot_types[s]
        if isinstance(typ, tuple):
            return f"the function {typ[1].name} over an infinite domain (a value of the per-process value table)"
        if vals is not None:
            continue
        r = T.root(typ)
        if r in (T.BOOLEAN, T.INTEGER, T.NATURAL, T.REAL):
            continue
        if isinstance(r, T.Domain) and r.kind in ("enum", "abstract"):
            continue
        if isinstance(r, T.Struct) and r.kind == "Rule":
            continue
        return (f"the location {gen.m.location_text(gen.slots[s])} holds values of the per-process value table "
                f"(type {typ})")
    return None


class NativeExpander:
    """Successors and property checks of packed states by the compiled step function."""

    CAP = 256

    def __init__(self, machine, state_props=(), step_props=(), deadlock=False):
        from ..explore.native import NativeExplorer, Unsupported
        self.m = machine
        self.state_props = list(state_props)
        self.step_props = list(step_props)
        self.deadlock = deadlock
        try:
            nx = NativeExplorer(machine, state_props=self.state_props, step_props=self.step_props, deadlock=deadlock)
        except Unsupported as e:
            raise Refused(str(e)) from None
        except RecursionError:
            raise Refused("the spec nests more deeply than the C generator follows") from None
        why = _portable(nx.gen)
        if why:
            raise Refused(f"the partitioned search cannot share its packed states: {why}")
        self.nx = nx
        self.gen = nx.gen
        self.dll = nx.dll
        self.compile_seconds = nx.compile_seconds
        fn = self.dll.asm_x_expand
        fn.restype, fn.argtypes = _EXPAND_SIG
        self._fn = fn
        self.nwords = self.gen.nwords
        self._fmt = struct.Struct(f"<{self.nwords}Q")
        # the value table's first entries (the values the generated code names)
        self.dll.asm_start((ctypes.c_uint64 * 1)(), 0, -1, -1, -1.0, 0, 0)
        self.ninv = len(self.state_props)
        self.nstep = len(self.step_props)
        self._skip_cache: dict = {}
        self._py = None
        self._grow(self.CAP)
        self._sfail = (ctypes.c_uint8 * max(self.ninv, 1))()
        self._info = (ctypes.c_int64 * 4)()

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
        from ..explore.native import Unsupported
        try:
            return self._fmt.pack(*self.gen.pack(st))
        except Unsupported as e:
            raise Refused(str(e)) from None

    def state_of(self, key: bytes) -> dict:
        return self.gen.unpack(list(self._fmt.unpack(key)))

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
        words = (ctypes.c_uint64 * self.nwords).from_buffer_copy(key)
        sk = self._skip(skip)
        while True:
            n = self._fn(words, sk, 1 if successors else 0, self.cap, self._succ, self._masks, self._sfail, self._info)
            if n != -3:
                break
            self._grow(self.cap * 4)
        if n == -2:
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
        raw = bytes(self._succ)[:n * size] if n else b""
        out = res.succ
        masks = self._masks
        targets = set()
        for j in range(n):
            k = raw[j * size:(j + 1) * size]
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


def picks_of(explorer, src_state: dict, position: int) -> tuple:
    """The choices of the successor at ``position`` among the admitted successors of
    ``src_state`` (the Python step function's enumeration, as the native one's)."""
    from ..explore.bfs import ReplayError
    succ = explorer.admitted_successors(src_state)
    if not 0 <= position < len(succ):
        raise ReplayError(f"no successor {position} of a state of the partitioned search")
    return succ[position][0]


