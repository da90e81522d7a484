"""States, locations and update sets.

A state is a plain ``dict``: location key -> value, holding only defined
locations (a missing key reads as undef).  A location key is the function's
index for a 0-ary function and ``(index, args)`` otherwise.  The elements that
``extend`` added to a dynamic abstract domain are kept under the key
``("#dom", domain name)`` as a sorted tuple.
"""
from __future__ import annotations

import math

from ..errors import InconsistentUpdate, Span
from .values import show, vkey


def dom_key(name: str) -> tuple:
    return ("#dom", name)


def is_dom_key(k) -> bool:
    return type(k) is tuple and len(k) == 2 and k[0] == "#dom"


def same_value(a, b) -> bool:
    """Equality of two values as ASMETA compares update values (booleans are not numbers)."""
    if a is b:
        return True
    if type(a) is bool or type(b) is bool:
        return type(a) is type(b) and a == b
    if a is None or b is None:
        return False
    if a == b:
        # reals compare as Java's Double.equals: 0.0 and -0.0 differ
        return type(a) is not float or a != 0 or math.copysign(1.0, a) == math.copysign(1.0, b)
    return a != a and b != b    # NaN equals NaN (Double.equals)


class Update:
    """One update: the value, where it was written and by whom."""

    __slots__ = ("value", "span", "agent", "rule")

    def __init__(self, value, span: Span, agent=None, rule=None):
        self.value = value
        self.span = span
        self.agent = agent
        self.rule = rule


class UpdateSet:
    """Updates of one step (or of a sub-rule): location key -> Update, plus new domain elements."""

    __slots__ = ("locs", "fresh")

    def __init__(self):
        self.locs: dict = {}
        self.fresh: list = []          # (domain name, element) made by extend, in order

    def add(self, key, value, span, agent, rule, machine) -> None:
        old = self.locs.get(key)
        if old is not None:
            if not same_value(old.value, value):
                loc = machine.location_text(key)
                raise InconsistentUpdate(
                    span, f"inconsistent update of {loc}: {show(old.value)} and {show(value)}",
                    [(old.span, f"{loc} := {show(old.value)} is here")])
            return
        self.locs[key] = Update(value, span, agent, rule)

    def merge_par(self, other: "UpdateSet", machine) -> None:
        for k, u in other.locs.items():
            self.add(k, u.value, u.span, u.agent, u.rule, machine)
        self.fresh.extend(other.fresh)

    def merge_seq(self, other: "UpdateSet") -> None:
        self.locs.update(other.locs)
        self.fresh.extend(other.fresh)

    def __len__(self) -> int:
        return len(self.locs) + len(self.fresh)


def apply_updates(state: dict, ups: UpdateSet, keep_undef=frozenset()) -> dict:
    """The state after firing ``ups`` (a new dict; ``state`` is left as it was)."""
    new = dict(state)
    apply_in_place(new, ups, keep_undef)
    return new


def apply_in_place(state: dict, ups: UpdateSet, keep_undef=frozenset()) -> None:
    """Fire ``ups`` on ``state``.  Undef values remove the location, except for functions in
    ``keep_undef`` (those with a lazily evaluated initial value, where a missing location
    reads that value)."""
    for dom, el in ups.fresh:
        k = dom_key(dom)
        cur = state.get(k, ())
        if el not in cur:
            state[k] = tuple(sorted(cur + (el,), key=vkey))
    for k, u in ups.locs.items():
        if u.value is None:
            if keep_undef and (k if type(k) is int else k[0]) in keep_undef:
                state[k] = None
            else:
                state.pop(k, None)
        else:
            state[k] = u.value
