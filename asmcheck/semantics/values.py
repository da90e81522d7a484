"""Run-time values of AsmetaL.

Representation (chosen for hashing speed, since states are stored by the million):

* undef: ``None``; Boolean: ``bool``; Integer and Natural: ``int``; Real: ``float``;
  String: ``str``; Char: :class:`CharV` (a one-character ``str`` subclass);
* enum constants: interned :class:`EnumValue`; elements of abstract domains:
  interned :class:`AbstractValue` (named static constants and ``extend``-made
  elements ``D!k``);
* tuples: ``tuple``; sequences: :class:`SeqV` (a ``tuple`` subclass); sets:
  :class:`SetV` (a ``frozenset`` subclass); bags: :class:`BagV` (sorted ``tuple``);
  maps: :class:`MapV` (``tuple`` of pairs sorted by key);
* rule values: :class:`RuleValue`.

Iteration order never depends on Python's hashing: every place that walks a
set sorts it with :func:`vkey`, so runs are deterministic byte for byte.
"""
from __future__ import annotations

import zlib


class CharV(str):
    __slots__ = ()

    def __repr__(self) -> str:
        return f"CharV({str.__repr__(self)})"


class EnumValue:
    __slots__ = ("domain", "name", "index", "_h")

    def __init__(self, domain: str, name: str, index: int):
        self.domain = domain
        self.name = name
        self.index = index
        self._h = zlib.crc32(f"E{domain}.{name}".encode())

    def __hash__(self) -> int:
        return self._h

    def __repr__(self) -> str:
        return self.name

    def __reduce__(self):
        return (_enum_unpickle, (self.domain, self.name, self.index))


# Interned: one object per (domain, symbol, position), so values compare by identity.  The
# position is part of the key because two specs read in one process may declare a domain of
# the same name with the same symbols in another order.
_ENUMS: dict[tuple[str, str, int], EnumValue] = {}


def enum_value(domain: str, name: str, index: int) -> EnumValue:
    key = (domain, name, index)
    v = _ENUMS.get(key)
    if v is None:
        v = EnumValue(domain, name, index)
        _ENUMS[key] = v
    return v


def _enum_unpickle(domain, name, index):
    return enum_value(domain, name, index)


class AbstractValue:
    """An element of an abstract domain.

    ``name`` is the static constant's name (``camera_task``) or, for an element
    made by ``extend``, ``D!k``; ``serial`` is ``k`` for those and 0 for named ones.
    """

    __slots__ = ("domain", "name", "serial", "_h")

    def __init__(self, domain: str, name: str, serial: int):
        self.domain = domain
        self.name = name
        self.serial = serial
        self._h = zlib.crc32(f"A{domain}.{name}".encode())

    def __hash__(self) -> int:
        return self._h

    def __repr__(self) -> str:
        return self.name

    def __reduce__(self):
        return (_abstract_unpickle, (self.domain, self.name, self.serial))


_ABSTRACT: dict[tuple[str, str], AbstractValue] = {}


def abstract_value(domain: str, name: str, serial: int = 0) -> AbstractValue:
    key = (domain, name)
    v = _ABSTRACT.get(key)
    if v is None:
        v = AbstractValue(domain, name, serial)
        _ABSTRACT[key] = v
    return v


def fresh_value(domain: str, k: int) -> AbstractValue:
    return abstract_value(domain, f"{domain}!{k}", k)


def _abstract_unpickle(domain, name, serial):
    return abstract_value(domain, name, serial)


class SeqV(tuple):
    __slots__ = ()

    def __repr__(self) -> str:
        return "SeqV" + tuple.__repr__(self)


class SetV(frozenset):
    __slots__ = ()

    def ordered(self) -> list:
        return sorted(self, key=vkey)

    def __repr__(self) -> str:
        return "SetV(" + repr(self.ordered()) + ")"


class BagV(tuple):
    """A bag: its elements with repetitions, sorted by :func:`vkey`."""

    __slots__ = ()

    @staticmethod
    def of(items) -> "BagV":
        return BagV(sorted(items, key=vkey))

    def __repr__(self) -> str:
        return "BagV" + tuple.__repr__(self)


class MapV(tuple):
    """A finite map: ``(key, value)`` pairs sorted by key."""

    __slots__ = ()

    @staticmethod
    def of(pairs) -> "MapV":
        d = {}
        for k, v in pairs:
            d[k] = v
        return MapV(sorted(d.items(), key=lambda kv: vkey(kv[0])))

    def get(self, key):
        for k, v in self:
            if k == key and type(k) is type(key):
                return v
        return None

    def __repr__(self) -> str:
        return "MapV" + tuple.__repr__(self)


class RuleValue:
    """A rule used as a value: ``<<r_elab(Scheduler)>>``, or an agent's program."""

    __slots__ = ("rule", "agent", "args", "_h")

    def __init__(self, rule, agent=None, args=()):
        self.rule = rule
        self.agent = agent
        self.args = tuple(args)
        self._h = zlib.crc32(("R" + rule.qualname + (agent.name if agent is not None else "")).encode())

    @staticmethod
    def bound(rule, agent, args=()):
        return RuleValue(rule, agent, ())

    def __eq__(self, other):
        return isinstance(other, RuleValue) and other.rule is self.rule and other.agent == self.agent

    def __hash__(self):
        return self._h

    def __repr__(self):
        return f"<<{self.rule.name}>>"


def vkey(v):
    """A total order on values: used to iterate sets and to sort output."""
    if v is None:
        return (0,)
    t = type(v)
    if t is bool:
        return (1, v)
    if t is int or t is float:
        return (2, v)
    if t is str or t is CharV:
        return (3, v)
    if t is EnumValue:
        return (4, v.domain, v.index)
    if t is AbstractValue:
        return (5, v.domain, v.serial, v.name)
    if t is SeqV:
        return (7, tuple(vkey(x) for x in v))
    if t is tuple:
        return (6, tuple(vkey(x) for x in v))
    if t is SetV:
        return (8, len(v), tuple(sorted(vkey(x) for x in v)))
    if t is BagV:
        return (9, tuple(vkey(x) for x in v))
    if t is MapV:
        return (10, tuple((vkey(k), vkey(x)) for k, x in v))
    if t is RuleValue:
        return (11, v.rule.qualname)
    return (12, repr(v))


def _fmt_real(x: float) -> str:
    if x != x:
        return "NaN"
    if x in (float("inf"), float("-inf")):
        return "Infinity" if x > 0 else "-Infinity"
    r = repr(float(x))
    return r


def show(v) -> str:
    """A value as ASMETA's simulator prints it."""
    if v is None:
        return "undef"
    t = type(v)
    if t is bool:
        return "true" if v else "false"
    if t is int:
        return str(v)
    if t is float:
        return _fmt_real(v)
    if t is str:
        return '"' + v + '"'
    if t is CharV:
        return "'" + str(v) + "'"
    if t is EnumValue or t is AbstractValue:
        return v.name
    if t is SeqV:
        return "[" + ", ".join(show(x) for x in v) + "]"
    if t is tuple:
        return "(" + ", ".join(show(x) for x in v) + ")"
    if t is SetV:
        return "{" + ", ".join(show(x) for x in v.ordered()) + "}"
    if t is BagV:
        return "<" + ", ".join(show(x) for x in v) + ">"
    if t is MapV:
        return "{" + ", ".join(f"{show(k)}->{show(x)}" for k, x in v) + "}"
    if t is RuleValue:
        return repr(v)
    return str(v)


def is_undef(v) -> bool:
    return v is None


def rename(v, mapping: dict):
    """``v`` with the abstract elements in ``mapping`` replaced (deeply, through collections)."""
    if not mapping:
        return v
    t = type(v)
    if t is AbstractValue:
        return mapping.get(v, v)
    if t is tuple:
        return tuple(rename(x, mapping) for x in v)
    if t is SeqV:
        return SeqV(rename(x, mapping) for x in v)
    if t is SetV:
        return SetV(rename(x, mapping) for x in v)
    if t is BagV:
        return BagV.of(rename(x, mapping) for x in v)
    if t is MapV:
        return MapV.of((rename(k, mapping), rename(x, mapping)) for k, x in v)
    if t is RuleValue and v.agent is not None and v.agent in mapping:
        return RuleValue(v.rule, mapping[v.agent], v.args)
    return v


def rename_state(state: dict, mapping: dict) -> dict:
    """A state with abstract elements renamed, in location arguments and in values."""
    out = {}
    for k, v in state.items():
        if type(k) is tuple and k and k[0] == "#dom":
            out[k] = tuple(sorted((mapping.get(e, e) for e in v), key=vkey))
        elif type(k) is tuple:
            out[(k[0], rename(k[1], mapping))] = rename(v, mapping)
        else:
            out[k] = rename(v, mapping)
    return out
