"""Domains (types) of AsmetaL and the compatibility rules used by the checker.

A named domain is a :class:`Domain` object (one per declaration); a structured
domain is a :class:`Struct` (``Seq(D)``, ``Powerset(D)``, ``Prod(A, B)``, ...).
Both are hashable and print as AsmetaL writes them.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import NO_SPAN, Span


class Type:
    __slots__ = ()

    def is_generic(self) -> bool:
        return False


@dataclass(eq=False)
class Domain(Type):
    """A declared domain: basic, enum, abstract, subset (concrete) or any (generic)."""

    name: str
    kind: str                     # basic enum abstract subset any
    dynamic: bool = False
    base: "Type | None" = None    # for subset domains
    elements: list = field(default_factory=list)   # enum constants (EnumValue), in order
    module: str = ""
    span: Span = NO_SPAN
    definition: object = None     # IR term giving the elements of a subset/abstract domain

    __hash__ = object.__hash__

    def __str__(self) -> str:
        return self.name

    def __repr__(self) -> str:
        return f"<Domain {self.name}>"

    def is_generic(self) -> bool:
        return self.kind == "any"

    def root(self) -> "Type":
        """The basic/abstract domain a chain of subset domains ends in."""
        t: Type = self
        seen = 0
        while isinstance(t, Domain) and t.kind == "subset" and t.base is not None and seen < 50:
            t = t.base
            seen += 1
        return t


@dataclass(frozen=True)
class Struct(Type):
    kind: str                     # Prod Seq Powerset Bag Map Rule
    args: tuple = ()

    def __str__(self) -> str:
        if self.kind == "Rule" and not self.args:
            return "Rule"
        return f"{self.kind}({','.join(str(a) for a in self.args)})"

    def is_generic(self) -> bool:
        return any(a.is_generic() for a in self.args)


def basic(name: str) -> Domain:
    return Domain(name, "basic", module="StandardLibrary")


INTEGER = basic("Integer")
NATURAL = basic("Natural")
REAL = basic("Real")
COMPLEX = basic("Complex")
CHAR = basic("Char")
STRING = basic("String")
BOOLEAN = basic("Boolean")
UNDEF = basic("Undef")
AGENT = Domain("Agent", "abstract", dynamic=True, module="StandardLibrary")
RESERVE = Domain("Reserve", "abstract", dynamic=True, module="StandardLibrary")
BASICS = {d.name: d for d in (INTEGER, NATURAL, REAL, COMPLEX, CHAR, STRING, BOOLEAN, UNDEF)}

GENERIC_NAMES = ("Any", "D", "D1", "D2", "D3", "D4", "D5", "D6", "D7", "D8", "D9")
GENERICS = {n: Domain(n, "any", module="StandardLibrary") for n in GENERIC_NAMES}


def seq(t: Type) -> Struct:
    return Struct("Seq", (t,))


def powerset(t: Type) -> Struct:
    return Struct("Powerset", (t,))


def bag(t: Type) -> Struct:
    return Struct("Bag", (t,))


def prod(*ts: Type) -> Struct:
    return Struct("Prod", tuple(ts))


def mapping(k: Type, v: Type) -> Struct:
    return Struct("Map", (k, v))


def rule_type(*ts: Type) -> Struct:
    return Struct("Rule", tuple(ts))


def is_numeric_root(t: Type) -> bool:
    r = t.root() if isinstance(t, Domain) else t
    return r in (INTEGER, NATURAL, REAL)


def element_type(t: Type) -> Type | None:
    """The type of ``$x`` in ``$x in t`` (sets, sequences, bags, domains)."""
    if isinstance(t, Domain) and t.kind == "subset" and t.base is not None:
        return element_type(t.base)
    if isinstance(t, Struct) and t.kind in ("Powerset", "Seq", "Bag") and t.args:
        return t.args[0]
    return None


def root(t: Type) -> Type:
    return t.root() if isinstance(t, Domain) else t


def agent_like(t: Type) -> bool:
    """A domain whose elements are agents (Agent itself, or a subset of it)."""
    seen = 0
    while isinstance(t, Domain) and seen < 50:
        if t is AGENT:
            return True
        if t.kind != "subset" or t.base is None:
            return False
        t = t.base
        seen += 1
    return False


class Bindings(dict):
    """Type-variable bindings made while matching a generic signature."""


def _abstract_root(t: Type) -> bool:
    r = root(t)
    return isinstance(r, Domain) and r.kind == "abstract"


def compatible(actual: Type, expected: Type, binds: Bindings | None = None, strict: bool = False) -> bool:
    """May a term of type ``actual`` stand where ``expected`` is required?

    The rules follow the checks AsmetaL's own parser makes: a subset domain is
    interchangeable with its base domain, ``undef`` fits anywhere, structured
    domains compare argument by argument, Natural and Integer are distinct.
    """
    if actual is expected:
        return True
    if isinstance(expected, Domain) and expected.kind == "any":
        if binds is None:
            return True
        bound = binds.get(expected)
        if bound is None:
            binds[expected] = actual
            return True
        if compatible(actual, bound) :
            return True
        if compatible(bound, actual):
            binds[expected] = actual
            return True
        return False
    if actual is UNDEF:
        return True
    if isinstance(actual, Domain) and actual.kind == "any":
        return True
    if isinstance(actual, Domain) and actual.kind == "subset" and actual.base is not None:
        if compatible(actual.base, expected, binds, strict):
            return True
    if isinstance(expected, Domain) and expected.kind == "subset" and expected.base is not None:
        # A value of the base domain fits a subset of a basic domain (checked at run time);
        # for subsets of abstract domains (Cani subsetof Mammiferi) AsmetaL requires the subset.
        if (not (strict and _abstract_root(expected)) or actual is AGENT) and compatible(
                actual, expected.base, binds, strict):
            return True
    if isinstance(actual, Struct) and isinstance(expected, Struct):
        if actual.kind != expected.kind:
            return False
        if expected.kind == "Rule" and (not expected.args or not actual.args):
            return True
        if len(actual.args) != len(expected.args):
            return False
        return all(compatible(a, e, binds, strict) for a, e in zip(actual.args, expected.args))
    return False


def substitute(t: Type, binds: Bindings) -> Type:
    if isinstance(t, Domain) and t.kind == "any":
        return binds.get(t, t)
    if isinstance(t, Struct) and t.args:
        return Struct(t.kind, tuple(substitute(a, binds) for a in t.args))
    return t


def unify(a: Type, b: Type) -> Type:
    """A common type for two branches (if/switch results, collection items)."""
    if a is UNDEF:
        return b
    if b is UNDEF:
        return a
    if compatible(a, b):
        return b if isinstance(a, Domain) and a.kind == "subset" else a
    if compatible(b, a):
        return a
    return a
