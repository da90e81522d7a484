"""The options of a run as the API and the command line take them, checked against the spec:
integer ranges (``LO..HI``, 64-bit, not reversed, never materialised as lists), the values
of monitored functions (each in its function's codomain) and the default memory bound."""
from __future__ import annotations

import os
import re

from .errors import AsmError, UsageError

# 64-bit integers, as the step function computes them
LONG_MIN, LONG_MAX = -(1 << 63), (1 << 63) - 1


def _int(text: str, what: str) -> int:
    t = text.strip()
    if not re.fullmatch(r"[+-]?[0-9]+", t):
        raise UsageError(f"{what}: {text.strip()!r} is not an integer")
    v = int(t)
    if not LONG_MIN <= v <= LONG_MAX:
        raise UsageError(f"{what}: {t} is outside the 64-bit integers asmcheck computes with")
    return v


def parse_int_range(value, what: str = "--int-range") -> tuple[int, int]:
    """``"LO..HI"`` or ``(lo, hi)`` as a pair of 64-bit integers with LO <= HI."""
    if isinstance(value, str):
        if ".." not in value:
            raise UsageError(f"{what} {value!r}: expected LO..HI (two integers)")
        lo_t, hi_t = value.split("..", 1)
        lo, hi = _int(lo_t, what), _int(hi_t, what)
    else:
        try:
            lo, hi = value
        except (TypeError, ValueError):
            raise UsageError(f"{what}: expected (lo, hi), not {value!r}") from None
        if not (isinstance(lo, int) and isinstance(hi, int)) or isinstance(lo, bool) or isinstance(hi, bool):
            raise UsageError(f"{what}: expected two integers, not {value!r}")
        for v in (lo, hi):
            if not LONG_MIN <= v <= LONG_MAX:
                raise UsageError(f"{what}: {v} is outside the 64-bit integers asmcheck computes with")
    if lo > hi:
        raise UsageError(f"{what} {lo}..{hi}: the range is empty (the lower bound is above the upper one)")
    return lo, hi


def parse_range(text: str, what: str = "--monitored"):
    """The command line's value list: ``LO..HI`` (a ``range``, never a list) or ``v1,v2,...``
    (the words as written; :func:`load` reads them against the function's codomain)."""
    if ".." in text and not text.strip().startswith('"'):
        lo, hi = parse_int_range(text, what)
        return range(lo, hi + 1)
    parts = [p.strip() for p in text.split(",")]
    if any(p == "" for p in parts):
        raise UsageError(f"{what}: {text!r} has an empty value")
    return [Word(p) for p in parts]


class Word(str):
    """A value as written on the command line, to be read against a codomain."""


def _codomain_values(machine, f):
    """The values of a monitored function's codomain when it is finite, else None."""
    from .semantics.machine import Undetermined
    try:
        return machine.domain_values(f.codomain, None, f.span)
    except (Undetermined, AsmError):
        return None


def _read_value(word: str, f, codomain, what: str):
    """A word of the command line as a value of ``f``'s codomain."""
    from .semantics import types as T
    from .semantics.values import show
    if codomain is not None:
        for v in codomain:
            if show(v) == word or (isinstance(v, str) and v == word.strip('"')):
                return v
        shown = ", ".join(show(v) for v in list(codomain)[:12]) + (", ..." if len(codomain) > 12 else "")
        raise UsageError(f"{what}: {word!r} is not a value of {f.name}'s codomain {f.codomain} ({shown})")
    root = f.codomain.root() if hasattr(f.codomain, "root") else f.codomain
    if root in (T.INTEGER, T.NATURAL):
        v = _int(word, what)
        if root is T.NATURAL and v < 0:
            raise UsageError(f"{what}: {v} is not a Natural ({f.name} ranges over {f.codomain})")
        return v
    if root is T.REAL:
        try:
            return float(word)
        except ValueError:
            raise UsageError(f"{what}: {word!r} is not a Real ({f.name} ranges over {f.codomain})") from None
    if root is T.STRING:
        return word[1:-1] if len(word) >= 2 and word[0] == word[-1] == '"' else word
    raise UsageError(f"{what}: asmcheck cannot read values of {f.codomain} ({f.name}) from the command line")


def _check_value(v, f, codomain, what: str):
    """A Python value given for ``f`` through the API: it must belong to the codomain."""
    from .semantics import types as T
    from .semantics.values import show
    if isinstance(v, Word):
        return _read_value(str(v), f, codomain, what)
    if codomain is not None:
        for c in codomain:
            if c is v or (type(c) is type(v) and c == v):
                return c
            if isinstance(v, str) and not isinstance(c, str) and show(c) == v:
                return c
        raise UsageError(f"{what}: {v!r} is not a value of {f.name}'s codomain {f.codomain}")
    root = f.codomain.root() if hasattr(f.codomain, "root") else f.codomain
    if root in (T.INTEGER, T.NATURAL):
        if not isinstance(v, int) or isinstance(v, bool):
            raise UsageError(f"{what}: {v!r} is not an integer ({f.name} ranges over {f.codomain})")
        if not LONG_MIN <= v <= LONG_MAX or (root is T.NATURAL and v < 0):
            raise UsageError(f"{what}: {v} is not a value of {f.codomain} ({f.name})")
        return v
    if root is T.REAL and isinstance(v, (int, float)) and not isinstance(v, bool):
        return float(v)
    if root is T.STRING and isinstance(v, str):
        return v
    raise UsageError(f"{what}: {v!r} is not a value of {f.name}'s codomain {f.codomain}")


def monitored_ranges(machine, monitored: dict) -> dict:
    """Check ``monitored`` (name -> values) against the spec: each name a monitored
    function, each value in its codomain.  Integer ranges stay ``range`` objects."""
    from .semantics import types as T
    by_name = {}
    for f in machine.spec.functions:
        by_name.setdefault(f.name, f)
    mons = sorted(f.name for f in machine.spec.functions if f.kind == "monitored")
    out = {}
    for name, values in monitored.items():
        what = f"--monitored {name}"
        f = by_name.get(name)
        if f is None or f.kind != "monitored":
            known = ", ".join(mons) if mons else "none"
            is_what = f"a {f.kind} function" if f is not None else "not a function of the spec"
            raise UsageError(f"{what}: {name} is {is_what}; the monitored functions are: {known}")
        if isinstance(values, str):
            values = parse_range(values, what)
        codomain = _codomain_values(machine, f)
        if isinstance(values, range):
            root = f.codomain.root() if hasattr(f.codomain, "root") else f.codomain
            if len(values) == 0:
                raise UsageError(f"{what}: the range is empty")
            if codomain is not None:
                bad = [v for v in (values[0], values[-1]) if v not in codomain or isinstance(codomain[0], bool)]
                if bad or any(not isinstance(c, int) or isinstance(c, bool) for c in codomain[:1]):
                    raise UsageError(f"{what}: {values[0]}..{values[-1]} is not within {f.name}'s codomain "
                                     f"{f.codomain}")
                if len(values) <= 1_000_000:
                    cset = set(codomain)
                    missing = next((v for v in values if v not in cset), None)
                    if missing is not None:
                        raise UsageError(f"{what}: {missing} is not a value of {f.name}'s codomain {f.codomain}")
            elif root not in (T.INTEGER, T.NATURAL, T.REAL):
                raise UsageError(f"{what}: {f.name} ranges over {f.codomain}, not over integers")
            elif root is T.NATURAL and values[0] < 0:
                raise UsageError(f"{what}: {values[0]} is not a Natural ({f.name} ranges over {f.codomain})")
            out[name] = values
            continue
        try:
            items = list(values)
        except TypeError:
            raise UsageError(f"{what}: expected a list of values, not {values!r}") from None
        if not items:
            raise UsageError(f"{what}: no values given")
        seen = []
        for v in items:
            cv = _check_value(v, f, codomain, what)
            if not any(cv is s or (type(cv) is type(s) and cv == s) for s in seen):
                seen.append(cv)
        out[name] = seen
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
