"""How to give the values of a monitored function the explorer cannot enumerate: the advice,
in a form ``--monitored`` reads for the function's codomain."""
from __future__ import annotations

from . import types as T


def monitored_hint(f) -> str:
    """How to give the values of the monitored function ``f`` whose codomain is not enumerable,
    in a form ``--monitored`` reads for that codomain."""
    cod = f.codomain
    root = cod.root() if hasattr(cod, "root") else cod
    if root in (T.INTEGER, T.NATURAL):
        return f"--monitored {f.name}=LO..HI (or --int-range LO..HI)"
    if root is T.REAL:
        return f"--monitored {f.name}=V1,V2,... (real numbers)"
    if root is T.STRING:
        return f'--monitored {f.name}="a","b",...'
    sample = example(root)
    if sample is None:
        return f"a finite domain for {f.name} in the model ({cod} cannot be given on the command line)"
    return f"--monitored '{f.name}={sample},...' (values of {cod}, written as asmcheck prints them)"


def example(t):
    """A value of type ``t`` as written on the command line, for a message; None when the
    command line cannot give one."""
    t = t.root() if hasattr(t, "root") else t
    if isinstance(t, T.Struct):
        if t.kind == "Prod":
            parts = [example(a) for a in t.args]
            return None if None in parts else "(" + ", ".join(parts) + ")"
        if t.kind in ("Powerset", "Seq"):
            e = example(t.args[0])
            return None if e is None else ("{" if t.kind == "Powerset" else "[") + e + ("}" if t.kind == "Powerset" else "]")
        return None
    if t in (T.INTEGER, T.NATURAL):
        return "0"
    if t is T.BOOLEAN:
        return "true"
    if t is T.STRING:
        return '"a"'
    if t is T.REAL:
        return "0.5"
    if isinstance(t, T.Domain) and t.kind == "enum" and t.elements:
        return t.elements[0].name
    return None


def too_big(f) -> str:
    """'infinite' for a codomain of numbers or strings, else 'infinite or too large to enumerate'."""
    root = f.codomain.root() if hasattr(f.codomain, "root") else f.codomain
    return "infinite" if root in (T.INTEGER, T.NATURAL, T.REAL, T.STRING) else "infinite or too large to enumerate"
