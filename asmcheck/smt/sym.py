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

    __slots__ = ("values", "index", "width", "name")

    def __init__(self, values: list, name: str = ""):
        self.values = list(values)
        self.index = {}
        for i, v in enumerate(self.values):
            self.index.setdefault(vk(v), i)
        n = max(len(self.values), 2)
        self.width = max(1, (n - 1).bit_length())
        self.name = name

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
        return U([(EQ(x, self.const(i)), v) for i, v in enumerate(self.values)], (self, x))


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
    """A union from (guard, value) pairs: equal values merged, false guards dropped."""
    order = []
    groups: dict = {}
    for g, v in pairs:
        if is_f(g):
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


def map1(u: U, fn) -> U:
    if u.is_concrete:
        return const(fn(u.alts[0][1]))
    return make([(g, fn(v)) for g, v in u.alts])


def mapn(us: list, fn) -> U:
    """``fn`` applied to every combination of alternatives (errors propagate: fn sees ERR)."""
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
            if same_value(v1, v2):
                gg = AND(g1, g2)
                if not is_f(gg):
                    gs.append(gg)
    return OR(gs)


def encode(u: U, table: Table):
    """(bit-vector code of the value in ``table``, guard of the values the table lacks)."""
    if u.code is not None and u.code[0] is table:
        return u.code[1], FALSE
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
