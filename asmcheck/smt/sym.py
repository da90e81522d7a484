"""Symbolic values for the Z3 encoding: finite guarded unions of concrete values.

A symbolic value is a :class:`U`: a list of ``(guard, value)`` alternatives whose guards
(Z3 Boolean terms) are pairwise exclusive and, under the constraints of the encoding,
exhaustive.  Every ``value`` is a concrete run-time value of :mod:`asmcheck.semantics.values`
(``None`` is undef) or :data:`ERR`, the value of a term whose evaluation raises a run-time
error.  Operations apply the explicit semantics alternative by alternative and merge equal
results, so the encoding computes exactly what the step function computes.

A union read from a location may also carry its *code*: ``(table, bit-vector term)``, the
location's variable (or an if-then-else of such) over the value table of its codomain.
Equality of two unions over the same table is then a bit-vector equality, and copying a
location into another of the same table needs no case split.
"""
from __future__ import annotations

import z3

from collections import Counter

from ..semantics.values import AbstractValue, BagV, CharV, EnumValue, MapV, RuleValue, SeqV, SetV

TRUE = z3.BoolVal(True)
FALSE = z3.BoolVal(False)


class _Err:
    __slots__ = ()

    def __repr__(self) -> str:
        return "ERR"


ERR = _Err()


def vk(v):
    """A hashable key telling apart every two values ``same_value`` tells apart.

    (Not :func:`vkey`: enum constants are interned by domain and name, so their index
    may come from another spec loaded in the same process.)"""
    if v is None:
        return (0,)
    t = type(v)
    if t is bool:
        return (1, v)
    if t is int or t is float:
        return (2, v)
    if t is str or t is CharV:
        return (3, str(v))
    if t is EnumValue:
        return (4, v.domain, v.name)
    if t is AbstractValue:
        return (5, v.domain, v.name)
    if t is tuple:
        return (6, tuple(vk(x) for x in v))
    if t is SeqV:
        return (7, tuple(vk(x) for x in v))
    if t is SetV:
        return (8, frozenset(vk(x) for x in v))
    if t is BagV:
        return (9, frozenset(Counter(vk(x) for x in v).items()))
    if t is MapV:
        return (10, frozenset((vk(k), vk(x)) for k, x in v))
    if t is RuleValue:
        return (11, v.rule.qualname, vk(v.agent))
    if v is ERR:
        return ("ERR",)
    return (12, t.__name__, repr(v))


# ----------------------------------------------------------------- guards
# The literals true and false are always these two objects (everything here builds
# guards through AND/OR/NOT/ITE), so they are recognised by identity; the connectives
# call Z3's C API directly, which is several times faster than the Python wrappers.
_CTX = z3.main_ctx()
_REF = _CTX.ref()


def _bool(ast):
    return z3.BoolRef(ast, _CTX)


def _array(gs):
    arr = (z3.Ast * len(gs))()
    for i, g in enumerate(gs):
        arr[i] = g.as_ast()
    return arr


def is_t(g) -> bool:
    return g is TRUE


def is_f(g) -> bool:
    return g is FALSE


def AND(*gs):
    out = []
    for g in gs:
        if g is FALSE:
            return FALSE
        if g is TRUE:
            continue
        out.append(g)
    if not out:
        return TRUE
    if len(out) == 1:
        return out[0]
    return _bool(z3.Z3_mk_and(_REF, len(out), _array(out)))


def OR(gs):
    out = []
    for g in gs:
        if g is TRUE:
            return TRUE
        if g is FALSE:
            continue
        out.append(g)
    if not out:
        return FALSE
    if len(out) == 1:
        return out[0]
    return _bool(z3.Z3_mk_or(_REF, len(out), _array(out)))


def NOT(g):
    if g is TRUE:
        return FALSE
    if g is FALSE:
        return TRUE
    return _bool(z3.Z3_mk_not(_REF, g.as_ast()))


def ITE(c, a, b):
    """If c then a else b, for bit-vector (or Boolean) terms."""
    if c is TRUE:
        return a
    if c is FALSE:
        return b
    if a.eq(b):
        return a
    return z3.z3._to_expr_ref(z3.Z3_mk_ite(_REF, c.as_ast(), a.as_ast(), b.as_ast()), _CTX)


def EQ(a, b):
    return _bool(z3.Z3_mk_eq(_REF, a.as_ast(), b.as_ast()))


# ----------------------------------------------------------------- unions
class Table:
    """The values a location (or a choice) can hold, each with a code (its index)."""

    __slots__ = ("values", "index", "width", "name", "irange", "base")

    def __init__(self, values: list, name: str = ""):
        self.values = list(values)
        self.index = {}
        for i, v in enumerate(self.values):
            self.index.setdefault(vk(v), i)
        n = max(len(self.values), 2)
        self.width = max(1, (n - 1).bit_length())
        self.name = name
        # a contiguous range of integers (after undef): codes are offsets, arithmetic is native
        self.base = 1 if self.values and self.values[0] is None else 0
        ints = self.values[self.base:]
        self.irange = None
        if ints and all(type(v) is int for v in ints) and ints == list(range(ints[0], ints[0] + len(ints))):
            self.irange = (ints[0], ints[-1])

    def __len__(self) -> int:
        return len(self.values)

    def code_of(self, v) -> int | None:
        return self.index.get(vk(v))

    def const(self, i: int):
        return z3.BitVecVal(i, self.width)

    def in_range(self, x):
        n = len(self.values)
        if n == 1 << self.width:
            return TRUE
        return z3.ULT(x, z3.BitVecVal(n, self.width))

    def union(self, x) -> "U":
        """The union of the values of a variable (or term) ``x`` over this table."""
        if z3.is_bv_value(x):
            return U([(TRUE, self.values[x.as_long()])], (self, x))
        if self.irange is not None and self.irange[1] - self.irange[0] + 1 > SYM_MIN:
            lo, hi = self.irange
            w = max(sbits(lo, hi), self.width + 1)
            e = z3.ZeroExt(w - self.width, x) + z3.BitVecVal(lo - self.base, w)
            alts = [(EQ(x, self.const(0)), None)] if self.base else []
            alts.append((NOT(alts[0][0]) if alts else TRUE, SymInt(e, lo, hi)))
            return U(alts, (self, x))
        return U([(EQ(x, self.const(i)), v) for i, v in enumerate(self.values)], (self, x))

    def sym_code(self, s: "SymInt"):
        """(code of a symbolic integer in this integer-range table, guard of it being outside)."""
        lo, hi = self.irange
        w = max(s.width, sbits(lo, hi), self.width + 1) + 1
        e = sx(s.e, w)
        outside = OR([(e < z3.BitVecVal(lo, w)) if s.lo < lo else FALSE,
                      (e > z3.BitVecVal(hi, w)) if s.hi > hi else FALSE])
        code = z3.Extract(self.width - 1, 0, e - z3.BitVecVal(lo - self.base, w))
        return code, outside


SYM_MIN = 8          # integer ranges wider than this are read as symbolic integers
MAX_EXPAND = 4096    # values of a symbolic integer expanded where a concrete value is needed


class TooWide(Exception):
    """A symbolic integer with too many values to expand."""


def sbits(lo: int, hi: int) -> int:
    """Bits of a signed bit-vector holding every integer in [lo, hi]."""
    def b(v):
        return (v.bit_length() if v >= 0 else (-v - 1).bit_length()) + 1
    return max(2, b(lo), b(hi))


def sx(e, w):
    return e if e.size() == w else z3.SignExt(w - e.size(), e)


class SymInt:
    """An integer known as a signed bit-vector term ``e`` whose value lies in [lo, hi]."""

    __slots__ = ("e", "lo", "hi")

    def __init__(self, e, lo: int, hi: int):
        self.e = e
        self.lo = lo
        self.hi = hi

    @property
    def width(self) -> int:
        return self.e.size()

    def __repr__(self) -> str:
        return f"SymInt({self.e} in {self.lo}..{self.hi})"

    @staticmethod
    def of(v: int) -> "SymInt":
        return SymInt(z3.BitVecVal(v, sbits(v, v)), v, v)


def is_int(v) -> bool:
    return type(v) is int


def has_sym(u) -> bool:
    return any(type(v) is SymInt for _, v in u.alts)


class U:
    __slots__ = ("alts", "code")

    def __init__(self, alts, code=None):
        self.alts = alts
        self.code = code

    def __repr__(self) -> str:
        return "U(" + ", ".join(f"{g}: {v!r}" for g, v in self.alts) + ")"

    def concrete(self):
        """The value, when the union has a single alternative (else a sentinel)."""
        if len(self.alts) == 1 and is_t(self.alts[0][0]):
            return self.alts[0][1]
        return _NOT_CONCRETE

    @property
    def is_concrete(self) -> bool:
        return len(self.alts) == 1 and is_t(self.alts[0][0])


_NOT_CONCRETE = object()
NOT_CONCRETE = _NOT_CONCRETE


def const(v) -> U:
    return U([(TRUE, v)])


UNDEF = const(None)
ERRU = const(ERR)


def make(pairs, code=None) -> U:
    """A union from (guard, value) pairs: equal values merged, false guards dropped.
    Symbolic integers (and the concrete integers beside them) merge into one."""
    pairs = [(g, v) for g, v in pairs if not is_f(g)]
    if any(type(v) is SymInt for _, v in pairs):
        ints = [(g, v if type(v) is SymInt else SymInt.of(v)) for g, v in pairs if type(v) in (SymInt, int)]
        rest = [(g, v) for g, v in pairs if type(v) not in (SymInt, int)]
        w = max(s.width for _, s in ints)
        e = sx(ints[-1][1].e, w)
        for g, s in reversed(ints[:-1]):
            e = ITE(g, sx(s.e, w), e)
        merged = SymInt(e, min(s.lo for _, s in ints), max(s.hi for _, s in ints))
        pairs = rest + [(OR([g for g, _ in ints]), merged)]
    order = []
    groups: dict = {}
    for g, v in pairs:
        if type(v) is SymInt:
            k = ("S", id(v))
            groups[k] = [v, [g]]
            order.append(k)
            continue
        k = vk(v)
        ent = groups.get(k)
        if ent is None:
            groups[k] = [v, [g]]
            order.append(k)
        else:
            ent[1].append(g)
    alts = [(OR(groups[k][1]), groups[k][0]) for k in order]
    if not alts:
        # no alternative is possible: an unreachable case (every guard false)
        alts = [(TRUE, ERR)]
    if len(alts) == 1 and not is_t(alts[0][0]):
        alts = [(TRUE, alts[0][1])]
    return U(alts, code)


def guard_of(u: U, pred) -> object:
    """The guard under which the value satisfies ``pred``."""
    return OR([g for g, v in u.alts if pred(v)])


def is_true(u: U):
    return OR([g for g, v in u.alts if v is True])


def is_false(u: U):
    return OR([g for g, v in u.alts if v is False])


def not_bool(u: U):
    """The guard of every value that is neither True nor False (undef, errors, non-Booleans)."""
    return OR([g for g, v in u.alts if v is not True and v is not False])


def is_err(u: U):
    return OR([g for g, v in u.alts if v is ERR])


def select(c, a: U, b: U) -> U:
    """``a`` where ``c`` holds, else ``b``."""
    if is_t(c):
        return a
    if is_f(c):
        return b
    code = None
    if a.code is not None and b.code is not None and a.code[0] is b.code[0]:
        code = (a.code[0], ITE(c, a.code[1], b.code[1]))
    return make([(AND(c, g), v) for g, v in a.alts] + [(AND(NOT(c), g), v) for g, v in b.alts], code)


def select_many(cases, default: U) -> U:
    """The value of the first case whose guard holds: cases = [(guard, U)]."""
    out = default
    for c, u in reversed(cases):
        out = select(c, u, out)
    return out


def expand(u: U) -> U:
    """The union with every symbolic integer split into its concrete values."""
    if not has_sym(u):
        return u
    pairs = []
    for g, v in u.alts:
        if type(v) is not SymInt:
            pairs.append((g, v))
            continue
        if v.hi - v.lo + 1 > MAX_EXPAND:
            raise TooWide(f"an integer term ranging over {v.lo}..{v.hi}")
        w = v.width
        for c in range(v.lo, v.hi + 1):
            pairs.append((AND(g, EQ(v.e, z3.BitVecVal(c, w))), c))
    out = U([(g, v) for g, v in pairs if not is_f(g)] or [(TRUE, ERR)])
    return out


def map1(u: U, fn) -> U:
    u = expand(u)
    if u.is_concrete:
        return const(fn(u.alts[0][1]))
    return make([(g, fn(v)) for g, v in u.alts])


def mapn(us: list, fn) -> U:
    """``fn`` applied to every combination of alternatives (errors propagate: fn sees ERR)."""
    us = [expand(u) for u in us]
    if all(u.is_concrete for u in us):
        return const(fn(*[u.alts[0][1] for u in us]))
    combos = [(TRUE, [])]
    for u in us:
        nxt = []
        for g, vals in combos:
            for g2, v in u.alts:
                gg = AND(g, g2)
                if not is_f(gg):
                    nxt.append((gg, vals + [v]))
        combos = nxt
    return make([(g, fn(*vals)) for g, vals in combos])


def same(a: U, b: U):
    """The guard under which the two values are the same (undef = undef, errors never)."""
    if a.code is not None and b.code is not None and a.code[0] is b.code[0]:
        table = a.code[0]
        ok = OR([g for g, v in a.alts if v is not ERR])
        return AND(ok, EQ(a.code[1], b.code[1]))
    from ..semantics.state import same_value
    gs = []
    for g1, v1 in a.alts:
        if v1 is ERR:
            continue
        for g2, v2 in b.alts:
            if v2 is ERR:
                continue
            if type(v1) is SymInt or type(v2) is SymInt:
                eq = sym_eq(v1, v2)
                if not is_f(eq):
                    gs.append(AND(g1, g2, eq))
                continue
            if same_value(v1, v2):
                gg = AND(g1, g2)
                if not is_f(gg):
                    gs.append(gg)
    return OR(gs)


def sym_eq(a, b):
    """The guard of a symbolic integer being equal to a value (symbolic or not)."""
    if type(a) is not SymInt:
        a, b = b, a
    if type(b) is float and b.is_integer():
        b = int(b)
    if type(b) is SymInt:
        if b.hi < a.lo or a.hi < b.lo:
            return FALSE
        w = max(a.width, b.width)
        return EQ(sx(a.e, w), sx(b.e, w))
    if type(b) is not int or not (a.lo <= b <= a.hi):
        return FALSE
    return EQ(a.e, z3.BitVecVal(b, a.width))


def encode(u: U, table: Table):
    """(bit-vector code of the value in ``table``, guard of the values the table lacks)."""
    if u.code is not None and u.code[0] is table:
        return u.code[1], FALSE
    if has_sym(u):
        if table.irange is None:
            u = expand(u)
        else:
            missing = []
            expr = None
            for g, v in reversed(u.alts):
                if type(v) is SymInt:
                    k, out = table.sym_code(v)
                    missing.append(AND(g, out))
                else:
                    c = table.code_of(v) if v is not ERR else None
                    if c is None:
                        missing.append(g)
                        continue
                    k = table.const(c)
                expr = k if expr is None else ITE(g, k, expr)
            return (expr if expr is not None else table.const(0)), OR(missing)
    missing = []
    expr = None
    for g, v in reversed(u.alts):
        c = table.code_of(v) if v is not ERR else None
        if c is None:
            missing.append(g)
            continue
        k = table.const(c)
        expr = k if expr is None else ITE(g, k, expr)
    if expr is None:
        expr = table.const(0)
    return expr, OR(missing)
