"""Values and states as text: asmcheck's own format and ASMETA's simulator format."""
from __future__ import annotations

import math
from decimal import Decimal

from .state import is_dom_key
from .values import AbstractValue, BagV, CharV, EnumValue, MapV, RuleValue, SeqV, SetV, show


def java_double(x: float) -> str:
    """Java's Double.toString, which ASMETA uses for reals (shortest digits that round-trip)."""
    if x != x:
        return "NaN"
    if x == math.inf:
        return "Infinity"
    if x == -math.inf:
        return "-Infinity"
    if x == 0:
        return "-0.0" if math.copysign(1, x) < 0 else "0.0"
    sign = "-" if x < 0 else ""
    d = Decimal(repr(abs(x)))
    _, digits, exp = d.as_tuple()
    digits = "".join(map(str, digits)).rstrip("0") or "0"
    e10 = len("".join(map(str, d.as_tuple()[1]))) - 1 + exp
    if 1e-3 <= abs(x) < 1e7:
        text = format(d, "f")
        if "." not in text:
            text += ".0"
        return sign + text
    return f"{sign}{digits[0]}.{digits[1:] or '0'}E{e10}"


def show_asmeta(v) -> str:
    """A value as ASMETA's simulator prints it (strings unquoted, sets sorted as text)."""
    if v is None:
        return "undef"
    t = type(v)
    if t is bool:
        return "true" if v else "false"
    if t is int:
        return str(v)
    if t is float:
        return java_double(v)
    if t is str or t is CharV:
        return str(v)
    if t is EnumValue or t is AbstractValue:
        return v.name
    if t is SeqV:
        return "[" + ",".join(show_asmeta(x) for x in v) + "]"
    if t is tuple:
        return "(" + ",".join(show_asmeta(x) for x in v) + ")"
    if t is SetV:
        return "{" + ",".join(sorted(show_asmeta(x) for x in v)) + "}"
    if t is BagV:
        return "<" + ",".join(sorted(show_asmeta(x) for x in v)) + ">"
    if t is MapV:
        return "{" + ",".join(f"{show_asmeta(k)}->{show_asmeta(x)}" for k, x in v) + "}"
    if t is RuleValue:
        return f"rule {v.rule.name}({','.join(str(p.type) for p in v.rule.params)})"
    return str(v)


def location_sort_key(machine, key):
    """Sort as ASMETA does: by function name, then arity, then the location's text."""
    if type(key) is int:
        return (machine.fname[key], 0, machine.fname[key])
    f, args = key
    return (machine.fname[f], len(args), location_text_asmeta(machine, key))


def location_text_asmeta(machine, key) -> str:
    if type(key) is int:
        return machine.fname[key]
    f, args = key
    return f"{machine.fname[f]}({','.join(show_asmeta(a) for a in args)})"


def location_text(machine, key) -> str:
    if type(key) is int:
        return machine.fname[key]
    f, args = key
    return f"{machine.fname[f]}({', '.join(show(a) for a in args)})"


def printable(machine, key) -> bool:
    if is_dom_key(key):
        return False
    fidx = key if type(key) is int else key[0]
    if fidx >= len(machine.functions):
        return False                   # a local function's location (within a step only)
    f = machine.functions[fidx]
    return f.kind in ("controlled", "out") and f is not machine.spec.self_func


def asmeta_state_lines(machine, state: dict, keys=None) -> list[str]:
    """``D={...}`` domain lines, then ``f(args)=value`` lines, as ASMETA prints a state."""
    lines = []
    doms = {}
    for d, els in machine.static_elements.items():
        if els:
            doms.setdefault(d.name, set()).update(e.name for e in els)
    for k, v in state.items():
        if is_dom_key(k) and v:
            doms.setdefault(k[1], set()).update(e.name for e in v)
    for name in sorted(doms):
        lines.append(f"{name}={{{','.join(sorted(doms[name]))}}}")
    locs = [k for k in (keys if keys is not None else state.keys()) if printable(machine, k)]
    for k in sorted(locs, key=lambda k: location_sort_key(machine, k)):
        lines.append(f"{location_text_asmeta(machine, k)}={show_asmeta(state.get(k))}")
    return lines


def state_lines(machine, state: dict, keys=None) -> list[str]:
    """asmcheck's own listing: one ``location = value`` line per location, sorted."""
    out = []
    for k in sorted((k for k in (keys if keys is not None else state.keys()) if not is_dom_key(k)),
                    key=lambda k: location_sort_key(machine, k)):
        out.append(f"{location_text(machine, k)} = {show(state.get(k))}")
    for k in sorted((k for k in (keys if keys is not None else state.keys()) if is_dom_key(k)),
                    key=lambda k: k[1]):
        out.append(f"{k[1]} = {{{', '.join(e.name for e in state.get(k, ()))}}}")
    return out


def split_top(text: str, sep: str = ",") -> list[str]:
    """Split at separators outside brackets."""
    parts, depth, cur = [], 0, []
    i = 0
    while i < len(text):
        c = text[i]
        if c in "([{<":
            depth += 1
        elif c in ")]}>" and not (c == ">" and i > 0 and text[i - 1] == "-"):
            depth -= 1
        if depth == 0 and text.startswith(sep, i):
            parts.append("".join(cur))
            cur = []
            i += len(sep)
            continue
        cur.append(c)
        i += 1
    if cur or parts:
        parts.append("".join(cur))
    return parts


def parse_asmeta_value(text: str, typ, machine=None):
    """The value of ``typ`` that ASMETA prints as ``text`` (the inverse of show_asmeta).

    Raises ValueError when the text is not a value of the type."""
    from . import types as T
    from .values import CharV, abstract_value, enum_value, fresh_value

    text = text.strip()
    if text == "undef":
        return None
    if isinstance(typ, T.Domain):
        r = typ.root()
        if r is T.BOOLEAN:
            if text in ("true", "false"):
                return text == "true"
            raise ValueError(text)
        if r in (T.INTEGER, T.NATURAL):
            return int(text)
        if r is T.REAL:
            return float(text)
        if r is T.STRING:
            return text
        if r is T.CHAR:
            return CharV(text[:1])
        if typ.kind == "enum":
            for e in typ.elements:
                if e.name == text:
                    return e
            raise ValueError(text)
        if isinstance(r, T.Domain) and r.kind == "abstract":
            if "!" in text:
                dom, _, k = text.partition("!")
                return fresh_value(dom, int(k))
            if machine is not None:
                for d, els in machine.static_elements.items():
                    for e in els:
                        if e.name == text:
                            return e
            return abstract_value(typ.name, text)
        if isinstance(r, T.Struct):
            return parse_asmeta_value(text, r, machine)
        raise ValueError(text)
    if isinstance(typ, T.Struct):
        from .values import MapV, SeqV, SetV, BagV
        if typ.kind == "Prod":
            if not (text.startswith("(") and text.endswith(")")):
                raise ValueError(text)
            parts = split_top(text[1:-1])
            if len(parts) != len(typ.args):
                raise ValueError(text)
            return tuple(parse_asmeta_value(p, t, machine) for p, t in zip(parts, typ.args))
        if typ.kind in ("Seq", "Powerset", "Bag"):
            o, c = {"Seq": "[]", "Powerset": "{}", "Bag": "<>"}[typ.kind]
            if not (text.startswith(o) and text.endswith(c)):
                raise ValueError(text)
            inner = text[1:-1]
            items = [parse_asmeta_value(p, typ.args[0], machine) for p in split_top(inner)] if inner.strip() else []
            return SeqV(items) if typ.kind == "Seq" else SetV(items) if typ.kind == "Powerset" else BagV.of(items)
        if typ.kind == "Map":
            inner = text[1:-1]
            pairs = []
            for p in (split_top(inner) if inner.strip() else []):
                k, _, v = p.partition("->")
                pairs.append((parse_asmeta_value(k, typ.args[0], machine), parse_asmeta_value(v, typ.args[1], machine)))
            return MapV.of(pairs)
    raise ValueError(text)
