"""Read-only text of the libraries asmcheck provides itself, served to editors.

StandardLibrary, CTLLibrary and LTLLibrary are built into asmcheck as signatures
(:mod:`asmcheck.semantics.stdlib`); an editor that jumps to ``plus`` or
``Integer`` gets an AsmetaL rendering of those signatures.  TimeLibrary is an
AsmetaL file of the package's ``stdlib`` folder and is served as it is.
Every library document has an ``asmcheck:`` URI, so the editor opens it read-only.
"""
from __future__ import annotations

from functools import lru_cache
from importlib import resources

from ..semantics import stdlib
from ..semantics import types as T

SCHEME = "asmcheck"
LIBRARY_URI = SCHEME + ":/library/{name}.asm"


def library_uri(name: str) -> str:
    return LIBRARY_URI.format(name=name)


def _type_text(t) -> str:
    return str(t)


def signature_text(sig: stdlib.Signature) -> str:
    """``static plus: Prod(Integer, Integer) -> Integer`` for one built-in signature."""
    if not sig.params:
        dom = ""
    elif len(sig.params) == 1:
        dom = _type_text(sig.params[0]) + " -> "
    else:
        dom = "Prod(" + ", ".join(_type_text(p) for p in sig.params) + ") -> "
    return f"static {sig.name}: {dom}{_type_text(sig.result)}"


class LibraryText:
    """The text of one library and the line of each declaration in it (1-based)."""

    def __init__(self, name: str, text: str, lines: dict):
        self.name = name
        self.text = text
        self.lines = lines          # id(object) or ("domain", name) or ("function", name) -> (line, col, end_col)

    def where(self, key):
        return self.lines.get(key)


def _generated(name: str, table: dict, with_domains: bool) -> LibraryText:
    out = [f"// {name} as asmcheck provides it (read-only: generated from asmcheck's built-in signatures).",
           f"module {name}", "export *", "signature:"]
    lines: dict = {}

    def add(text: str, key, word: str):
        out.append("\t" + text)
        col = text.index(word) + 2          # 1-based, after the tab
        lines[key] = (len(out), col, col + len(word))

    if with_domains:
        for d in T.BASICS.values():
            add(f"basic domain {d.name}", ("domain", d.name), d.name)
            lines[id(d)] = lines[("domain", d.name)]
        for d in (T.AGENT, T.RESERVE):
            add(f"abstract domain {d.name}", ("domain", d.name), d.name)
            lines[id(d)] = lines[("domain", d.name)]
        for d in T.GENERICS.values():
            add(f"anydomain {d.name}", ("domain", d.name), d.name)
            lines[id(d)] = lines[("domain", d.name)]
    for fname in table:
        for sig in table[fname]:
            text = signature_text(sig)
            add(text, id(sig), fname)
            lines.setdefault(("function", fname), lines[id(sig)])
    if with_domains:
        add("controlled self: Agent", ("function", "self"), "self")
        add("controlled result: Any", ("function", "result"), "result")
    out.append("definitions:")
    out.append("")
    return LibraryText(name, "\n".join(out), lines)


@lru_cache(maxsize=None)
def library(name: str) -> LibraryText | None:
    if name == "StandardLibrary":
        return _generated(name, stdlib.STANDARD, True)
    if name == "CTLLibrary":
        return _generated(name, stdlib.CTL, False)
    if name == "LTLLibrary":
        return _generated(name, stdlib.LTL, False)
    if name == "TimeLibrary":
        text = resources.files("asmcheck.stdlib").joinpath("TimeLibrary.asm").read_text(encoding="utf-8")
        return LibraryText(name, text, {})
    return None


def library_of_uri(uri: str) -> LibraryText | None:
    prefix = SCHEME + ":/library/"
    if not uri.startswith(prefix) or not uri.endswith(".asm"):
        return None
    return library(uri[len(prefix):-4])
