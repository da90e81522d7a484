"""Compact, hashable states for the explorer.

A state (a ``dict`` location -> value) is frozen into a tuple with one slot per
location: slot numbers are given to locations in the order they are first met,
so the same dict always freezes to the same tuple (trailing empty slots are
dropped).  An absent location is ``None`` in its slot; a location that holds
undef explicitly (only functions with a lazily evaluated init do) holds
:data:`UNDEF_MARK`.
"""
from __future__ import annotations

import os


def memory_in_use() -> int:
    """The resident memory of this process in bytes (0 when unknown)."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        try:
            import resource
            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
        except Exception:       # pragma: no cover - no way to know
            return 0


class _UndefMark:
    __slots__ = ()

    def __repr__(self):
        return "UNDEF"

    def __reduce__(self):
        return (_undef_mark, ())


UNDEF_MARK = _UndefMark()


def _undef_mark():
    return UNDEF_MARK


class Layout:
    """The slot of every location met so far."""

    def __init__(self):
        self.slot: dict = {}
        self.keys: list = []

    def freeze(self, state: dict) -> tuple:
        slot = self.slot
        n = len(self.keys)
        vals = [None] * n
        for k, v in state.items():
            i = slot.get(k)
            if i is None:
                i = slot[k] = len(self.keys)
                self.keys.append(k)
                vals.append(None)
            vals[i] = UNDEF_MARK if v is None else v
        while vals and vals[-1] is None:
            vals.pop()
        return tuple(vals)

    def thaw(self, frozen: tuple) -> dict:
        keys = self.keys
        out = {}
        for i, v in enumerate(frozen):
            if v is not None:
                out[keys[i]] = None if v is UNDEF_MARK else v
        return out


def default_max_memory() -> int | None:
    """The memory bound a run has when none is given: three quarters of the physical memory,
    or of the address-space limit when one is set and lower (None when neither is known)."""
    limits = []
    try:
        limits.append(int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") * 0.75))
    except (ValueError, OSError, AttributeError):
        pass
    try:
        import resource
        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft != resource.RLIM_INFINITY and soft > 0:
            limits.append(int(soft * 0.75))
    except (ImportError, ValueError, OSError):
        pass
    return min(limits) if limits else None
