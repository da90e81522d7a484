"""Shared bits of the review tools: loading, rule names, source excerpts, location lists."""
from __future__ import annotations

import itertools
from pathlib import Path

from ..errors import AsmError, NO_SPAN
from ..semantics import ir
from ..semantics import types as T

LIBRARY_MODULES = {"StandardLibrary", "CTLLibrary", "LTLLibrary", "TimeLibrary"}

RULE_KINDS = {
    ir.Skip: "skip", ir.Update: "update", ir.UpdateVar: "update", ir.If: "if", ir.SwitchRule: "switch",
    ir.LetRule: "let", ir.Choose: "choose", ir.Forall: "forall", ir.Extend: "extend",
    ir.CallRule: "macro_call", ir.TurboReturn: "turbo_return", ir.TermCall: "rule_term_call",
    ir.Loop: "loop", ir.LocalRule: "local",
}


def load_spec(path: str):
    """The checked spec (errors as AsmError with file, line and column)."""
    from ..semantics.resolve import check_file
    spec = check_file(path)
    if spec is None:
        raise AsmError(None, f"{path}: the file is empty: nothing to review")
    if spec.main is None:
        raise AsmError(spec.root_module.syntax.span if spec.root_module.syntax else None,
                       f"{spec.name} has no main rule: nothing to review (is it a module?)")
    return spec


def rule_kind(r) -> str:
    if isinstance(r, ir.Block):
        return r.kind
    return RULE_KINDS.get(type(r), type(r).__name__.lower())


class Sources:
    """Source lines of the files spans point to (read once)."""

    def __init__(self):
        self._lines: dict = {}

    def lines(self, path: str) -> list[str]:
        got = self._lines.get(path)
        if got is None:
            try:
                got = Path(path).read_text(encoding="utf-8", errors="replace").split("\n")
            except OSError:
                got = []
            self._lines[path] = got
        return got

    def excerpt(self, span, limit: int = 80) -> str:
        """The source text of ``span``: its first line from its column (``...`` when it goes on)."""
        if span is None or span.line <= 0:
            return ""
        lines = self.lines(span.path)
        if span.line > len(lines):
            return ""
        line = lines[span.line - 1]
        if span.end_line == span.line and span.end_col > span.col:
            text = line[span.col - 1: span.end_col - 1]
        else:
            text = line[span.col - 1:].rstrip()
            if span.end_line > span.line:
                text += " ..."
        text = " ".join(text.split())
        if len(text) > limit:
            text = text[: limit - 4].rstrip() + " ..."
        return text


def rule_where(r, sources: Sources, **extra) -> dict:
    sp = r.span
    d = {"kind": "rule", "rule": rule_kind(r), "path": Path(sp.path).name, "line": sp.line, "column": sp.col,
         "text": sources.excerpt(sp)}
    if isinstance(r, (ir.Choose, ir.Forall)):
        d["var"] = ", ".join(v.name for v, _ in r.bindings)
    if isinstance(r, ir.CallRule):
        d["macro"] = r.rule.name
    if isinstance(r, ir.Update):
        d["location"] = r.func.name
    d.update(extra)
    return d


def user_functions(spec) -> list:
    return [f for f in spec.functions
            if f.module not in LIBRARY_MODULES and f is not spec.self_func and f is not spec.result_func]


def user_domains(spec) -> list:
    out = []
    for d in spec.domains:
        if not isinstance(d, T.Domain) or d is T.BOOLEAN:
            continue
        if getattr(d, "module", None) in LIBRARY_MODULES:
            continue
        root = T.root(d)
        if d.kind in ("enum", "abstract") or (d.kind == "subset" and (
                d.definition is not None or (isinstance(root, T.Domain) and root.kind == "abstract"))):
            out.append(d)
    return out


def all_locations(machine, f, limit: int = 20_000):
    """Every location of ``f`` (keys), or None when its domain cannot be enumerated or is too big."""
    if f.arity == 0:
        return [f.index]
    per = []
    n = 1
    for t in f.domain:
        try:
            vals = machine.domain_values(t, None, NO_SPAN)
        except AsmError:
            return None
        per.append(vals)
        n *= len(vals)
        if n > limit:
            return None
    return [(f.index, tuple(c)) for c in itertools.product(*per)]


def codomain_values(machine, f):
    try:
        return list(machine.domain_values(f.codomain, None, NO_SPAN))
    except AsmError:
        return None


def add_domain_options(p) -> None:
    p.add_argument("--monitored", action="append", default=[], metavar="NAME=LO..HI|v1,v2,..",
                   help="the values a monitored function with an infinite codomain takes (repeatable)")
    p.add_argument("--int-range", default=None, metavar="LO..HI", help="bound Integer and Natural to LO..HI")


def _values(text: str) -> list:
    if ".." in text:
        lo, hi = text.split("..", 1)
        try:
            return list(range(int(lo), int(hi) + 1))
        except ValueError:
            raise ValueError(f"bad range {text!r}: expected LO..HI with integers") from None
    out = []
    for part in text.split(","):
        p = part.strip()
        if p in ("true", "false"):
            out.append(p == "true")
            continue
        try:
            out.append(int(p))
        except ValueError:
            try:
                out.append(float(p))
            except ValueError:
                out.append(p.strip('"'))
    return out


def machine_options(args) -> dict:
    """The machine's options from --monitored and --int-range (ValueError on a bad value)."""
    opts: dict = {}
    if getattr(args, "int_range", None):
        r = _values(args.int_range)
        opts["int_range"] = (min(r), max(r))
    mons = {}
    for item in getattr(args, "monitored", None) or []:
        if "=" not in item:
            raise ValueError(f"--monitored expects NAME=LO..HI or NAME=v1,v2,..., not {item!r}")
        name, rng = item.split("=", 1)
        mons[name.strip()] = _values(rng)
    if mons:
        opts["monitored_ranges"] = mons
    return opts


def use_import_path(dirs) -> None:
    """The folders searched for imports not found beside the importing file (the ``-I`` option)."""
    import os
    from ..errors import UsageError
    from ..semantics.resolve import set_import_path
    dirs = [os.fspath(d) for d in dirs or ()]
    for d in dirs:
        if not os.path.isdir(d):
            raise UsageError(f"--import-path {d}: no such folder")
    set_import_path(os.path.abspath(d) for d in dirs)
