"""Hashes of values and states that are the same in every process.

Python's own ``hash`` of a string changes from one interpreter to the next, so it cannot say
which worker owns a state when the workers are separate processes or machines.  These hashes
depend on the value only.  Values that Python compares equal (``1 == True``, a tuple and a
sequence with the same items) hash alike, so a cache keyed by Python equality stays exact.
"""
from __future__ import annotations

import zlib

from ..semantics.values import AbstractValue, EnumValue, RuleValue

MASK = (1 << 64) - 1
_NONE = 0x9E3779B97F4A7C15


def mix(h: int) -> int:
    """The splitmix64 finaliser: a 64-bit integer spread over all 64 bits."""
    h &= MASK
    h = ((h ^ (h >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    h = ((h ^ (h >> 27)) * 0x94D049BB133111EB) & MASK
    return h ^ (h >> 31)


def vhash(v) -> int:
    """A 64-bit hash of a value, the same in every process."""
    if v is None:
        return _NONE
    t = type(v)
    if t is int or t is bool:
        return mix(int(v) * 0x100000001B3 + 0x51)
    if isinstance(v, str):
        b = v.encode("utf-8", "surrogatepass")
        return mix(zlib.crc32(b) | (len(b) << 32) | (0xA5 << 56))
    if t is EnumValue or t is AbstractValue or t is RuleValue:
        return mix(v._h ^ 0x7F4A7C15_00000000)
    if isinstance(v, float):
        if v == v and v.is_integer():
            return vhash(int(v))
        return mix(zlib.crc32(repr(v).encode()) ^ 0xF10A7_00000000)
    if isinstance(v, frozenset):
        h = 0x5E7
        for x in v:
            h += vhash(x)
        return mix(h ^ (len(v) << 40))
    if isinstance(v, tuple):
        h = 0x7A8 + len(v)
        for x in v:
            h = mix(h * 31 + vhash(x))
        return h
    return mix(zlib.crc32(repr(v).encode()))


class StateHasher:
    """The hash of a state (a dict, or its items): the sum of its locations' hashes, so the
    order of the items does not matter.  Location/value pairs are cached."""

    def __init__(self):
        self.cache: dict = {}

    def __call__(self, items) -> int:
        cache = self.cache
        h = 0
        for kv in items:
            x = cache.get(kv)
            if x is None:
                if len(cache) > 2_000_000:
                    cache.clear()
                x = cache[kv] = mix(vhash(kv[0]) * 0x9E3779B1 + vhash(kv[1]))
            h += x
        return mix(h)
