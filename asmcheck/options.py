"""The options of a run as the API and the command line take them, checked against the spec:
integer ranges (``LO..HI``, 64-bit, not reversed, never materialised as lists), the values
of monitored functions (each in its function's codomain) and the default memory bound."""
from __future__ import annotations

import os
import re

from .errors import AsmError, UsageError
from .semantics.advice import monitored_hint, too_big
from .explore.store import default_max_memory  # noqa: F401  (part of the options' API)

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


# the most values one range may have: the explorer enumerates every one of them (a monitored
# value is a successor of every state), so a larger range is an input error, not a long wait
MAX_RANGE = 1_000_000


def parse_int_range(value, what: str = "--int-range") -> tuple[int, int]:
    """``"LO..HI"`` or ``(lo, hi)`` as a pair of 64-bit integers with LO <= HI and at most
    :data:`MAX_RANGE` values."""
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
    if hi - lo + 1 > MAX_RANGE:
        raise UsageError(f"{what} {lo}..{hi}: {hi - lo + 1:,} values; asmcheck enumerates every value of a range, "
                         f"so it takes at most {MAX_RANGE:,}")
    return lo, hi


def parse_range(text: str, what: str = "--monitored"):
    """The command line's value list: ``LO..HI`` (a ``range``, never a list) or ``v1,v2,...``
    (the words as written; :func:`load` reads them against the function's codomain)."""
    if ".." in text and not text.strip().startswith('"'):
        lo, hi = parse_int_range(text, what)
        return range(lo, hi + 1)
    parts = [p.strip() for p in split_values(text)]
    if any(p == "" for p in parts):
        raise UsageError(f"{what}: {text!r} has an empty value")
    return [Word(p) for p in parts]


class Word(str):
    """A value as written on the command line, to be read against a codomain."""


def split_values(text: str) -> list:
    """``v1,v2,...`` cut at the commas outside brackets and quotes (a set ``{1, 2}``, a tuple
    ``(0, 1)`` or a sequence ``[a, b]`` is one value)."""
    out, depth, quote, cur = [], 0, False, []
    for ch in text:
        if ch == '"':
            quote = not quote
        elif not quote and ch in "({[":
            depth += 1
        elif not quote and ch in ")}]":
            depth -= 1
        elif ch == "," and depth == 0 and not quote:
            out.append("".join(cur))
            cur = []
            continue
        cur.append(ch)
    out.append("".join(cur))
    return out


def _squeeze(text: str) -> str:
    """``text`` without the blanks outside quotes (``{1,2}`` and ``{1, 2}`` are one value)."""
    return "".join(p if i % 2 else re.sub(r"\s+", "", p) for i, p in enumerate(text.split('"')))


def _parse_value(word: str, typ, machine, what: str, f):
    """A composite value written on the command line (tuples ``(a, b)``, sets ``{a, b}``,
    sequences ``[a, b]`` of numbers, booleans, strings and enum constants), read against ``typ``."""
    from .semantics import types as T
    from .semantics.values import SeqV, SetV, show
    root = typ.root() if hasattr(typ, "root") else typ
    word = word.strip()

    def bad():
        return UsageError(f"{what}: {word!r} is not a value of {typ} ({f.name} ranges over {f.codomain})")
    if isinstance(root, T.Struct) and root.kind in ("Prod", "Powerset", "Seq"):
        opener, closer = {"Prod": "()", "Powerset": "{}", "Seq": "[]"}[root.kind]
        if not (word.startswith(opener) and word.endswith(closer)):
            raise bad()
        inner = word[1:-1].strip()
        parts = [p for p in split_values(inner)] if inner else []
        if root.kind == "Prod":
            if len(parts) != len(root.args):
                raise bad()
            v = tuple(_parse_value(p, a, machine, what, f) for p, a in zip(parts, root.args))
        else:
            items = [_parse_value(p, root.args[0], machine, what, f) for p in parts]
            v = SetV(items) if root.kind == "Powerset" else SeqV(items)
    elif root is T.BOOLEAN:
        if word not in ("true", "false"):
            raise bad()
        v = word == "true"
    elif root in (T.INTEGER, T.NATURAL):
        v = _int(word, what)
        if root is T.NATURAL and v < 0:
            raise bad()
    elif root is T.REAL:
        try:
            v = float(word)
        except ValueError:
            raise bad() from None
    elif root is T.STRING:
        v = word[1:-1] if len(word) >= 2 and word[0] == word[-1] == '"' else word
    elif isinstance(root, T.Domain) and root.kind == "enum":
        v = next((e for e in root.elements if show(e) == word), None)
        if v is None:
            raise bad()
    else:
        raise UsageError(f"{what}: asmcheck cannot read values of {typ} ({f.name}) from the command line")
    # a subset domain's elements: the value must be one of them
    if (machine is not None and typ is not root and isinstance(typ, T.Domain) and typ.kind == "subset"
            and typ.definition is not None):
        if v not in set(machine.domain_values(typ, None, f.span)):
            raise UsageError(f"{what}: {show(v)} is not in {typ} ({f.name} ranges over {f.codomain})")
    return v


def _codomain_values(machine, f):
    """The values of a monitored function's codomain when it is finite, else None."""
    from .semantics.machine import Undetermined
    try:
        return machine.domain_values(f.codomain, None, f.span)
    except (Undetermined, AsmError):
        return None


def _read_value(word: str, f, codomain, what: str, machine=None):
    """A word of the command line as a value of ``f``'s codomain."""
    from .semantics import types as T
    from .semantics.values import show
    if codomain is not None:
        squeezed = _squeeze(word)
        for v in codomain:
            if show(v) == word or (isinstance(v, str) and v == word.strip('"')) or _squeeze(show(v)) == squeezed:
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
    return _parse_value(word, f.codomain, machine, what, f)


def _check_value(v, f, codomain, what: str, machine=None):
    """A Python value given for ``f`` through the API: it must belong to the codomain."""
    from .semantics import types as T
    from .semantics.values import show
    if isinstance(v, Word):
        return _read_value(str(v), f, codomain, what, machine)
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
        # (a name declared in several modules: the monitored declaration is the one given values)
        if f.name not in by_name or (f.kind == "monitored" and by_name[f.name].kind != "monitored"):
            by_name[f.name] = f
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
            if len(values) > MAX_RANGE:
                raise UsageError(f"{what}: {len(values):,} values; asmcheck enumerates every value of a range, so "
                                 f"it takes at most {MAX_RANGE:,}")
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
            cv = _check_value(v, f, codomain, what, machine)
            if not any(cv is s or (type(cv) is type(s) and cv == s) for s in seen):
                seen.append(cv)
        out[name] = seen
    return out


def read_monitored(spec) -> list:
    """The monitored functions the spec reads (in its rules, definitions and properties), in
    declaration order."""
    from dataclasses import fields, is_dataclass
    from .semantics import ir
    found: dict = {}
    seen: set = set()
    stack = [r.body for r in spec.rules] + [f.body for f in spec.functions if f.body is not None] + \
        [p.body for p in spec.properties] + [getattr(p, "body2", None) for p in spec.properties]
    while stack:
        x = stack.pop()
        if x is None or id(x) in seen:
            continue
        if isinstance(x, (list, tuple)):
            stack.extend(x)
            continue
        if not is_dataclass(x) or isinstance(x, (type, ir.Function)):
            continue
        seen.add(id(x))
        if isinstance(x, ir.Loc) and x.func.kind == "monitored":
            found[x.func.index] = x.func
        for f in fields(x):
            if f.name not in ("type", "span", "func"):
                stack.append(getattr(x, f.name, None))
    return [found[i] for i in sorted(found)]


def unbounded_monitored(machine) -> None:
    """Raise one located error naming every monitored function the spec reads whose values
    are not finite (and not given with ``monitored`` or ``int_range``)."""
    bad = [f for f in read_monitored(machine.spec)
           if f.name not in machine.monitored_ranges and _codomain_values(machine, f) is None]
    if not bad:
        return
    f = bad[0]
    if len(bad) == 1:
        raise AsmError(f.span, f"monitored function {f.name} ranges over {f.codomain}, which is "
                               f"{too_big(f)}: give its values with {monitored_hint(f)}")
    # (functions of the same name in several modules: --monitored NAME gives the values of all)
    first = list({g.name: g for g in reversed(bad)}.values())[::-1]
    names = ", ".join(g.name for g in first)
    ints = [g for g in first if monitored_hint(g).endswith("(or --int-range LO..HI)")]
    opts = "; ".join([" ".join(f"--monitored {g.name}=LO..HI" for g in ints) + " (or --int-range LO..HI)"] * bool(ints)
                     + [monitored_hint(g) for g in first if g not in ints])
    big = "infinite domains" if all(too_big(g) == "infinite" for g in first) else "infinite or too large domains"
    raise AsmError(f.span, f"{len(first)} monitored functions range over {big} ({names}): give their values with {opts}",
                   notes=[(g.span, f"monitored function {g.name} ranges over {g.codomain}") for g in bad[1:]])
