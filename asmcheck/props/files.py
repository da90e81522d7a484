"""Property files: properties written apart from the specs they apply to.

A property file (``*.prop``, in a ``properties/`` folder beside the specs or
given with ``--properties``) reads::

    // comments as in AsmetaL
    applies to sb_async_master, sb_sync_master      (asm names; '*' for every spec)
    invariant inv_name: <term>                      a state property
    step stp_name: <term>                           a transition property (see below)
    LTLSPEC ltlSpec_name: <term>                    LTLLibrary operators
    CTLSPEC ctlSpec_name: <term>                    CTLLibrary operators
    JUSTICE <term>                                  fairness for the LTL/CTL properties
    COMPASSION(<term>, <term>)

A declaration starts at a line that begins with one of these words and runs to
the next one.  Terms are AsmetaL terms over the spec's functions.  In a ``step``
property plain terms read the state before the step, and

* ``next(t)``           is ``t`` in the state after the step;
* ``updated(f(a))``     is true when the step's update set holds the location f(a);
* ``changed(f(a))``     is true when f(a) has another value after the step;
* ``updatedBy(x, f(a))`` is true when agent x (the ``self`` of the rule that made it)
  updated f(a) in the step.

A spec declares the properties it is built to break with a comment line
``// asmcheck: expect violated NAME[, NAME]`` (the seeded-bug specs do).
"""
from __future__ import annotations

import re
from pathlib import Path

from ..errors import AsmError, AsmRuntimeError, AsmSyntaxError, AsmTypeError, SOURCES, Span
from ..semantics import ir
from ..semantics.machine import Chooser, Ctx
from ..syntax.parser import decode_source, parse_term
from ..semantics.choice import next_prefix

KEYWORDS = ("invariant", "step", "LTLSPEC", "ltlspec", "CTLSPEC", "ctlspec", "JUSTICE", "justice",
            "COMPASSION", "compassion", "applies")
_DECL = re.compile(r"^(\s*)(invariant|step|LTLSPEC|ltlspec|CTLSPEC|ctlspec|JUSTICE|justice|COMPASSION|compassion|"
                   r"applies\s+to)\b")
_EXPECT = re.compile(r"//[ \t]*asmcheck:[ \t]*expect[ \t]+violated[ \t]+([A-Za-z0-9_, \t]+)")


class PropDecl:
    def __init__(self, kind, name, text, line, col, path, name_span):
        self.kind = kind
        self.name = name
        self.text = text
        self.line = line
        self.col = col
        self.path = path
        self.name_span = name_span


class PropFile:
    def __init__(self, path: str, applies: list[str] | None, decls: list[PropDecl], applies_span: Span | None):
        self.path = path
        self.applies = applies
        self.decls = decls
        self.applies_span = applies_span

    def applies_to(self, spec_name: str) -> bool:
        return self.applies is not None and ("*" in self.applies or spec_name in self.applies)


def read_prop_file(path: str) -> PropFile:
    from ..syntax.parser import read_source_bytes
    text = decode_source(read_source_bytes(path))      # regular files only (located error otherwise)
    SOURCES.add(path, text)
    lines = text.split("\n")
    # blank out comments (keeping columns) to find where declarations start
    clean = strip_comments(text).split("\n")
    starts = []
    for i, ln in enumerate(clean):
        m = _DECL.match(ln)
        if m:
            starts.append((i, len(m.group(1)), m.group(2)))
    if not starts and text.strip():
        first = next((i for i, ln in enumerate(clean) if ln.strip()), 0)
        raise AsmSyntaxError(Span(path, first + 1, 1), "expected 'applies to', 'invariant', 'step', 'LTLSPEC', "
                                                       "'CTLSPEC', 'JUSTICE' or 'COMPASSION'")
    for i, ln in enumerate(clean):
        if ln.strip() and (not starts or i < starts[0][0]):
            col = len(ln) - len(ln.lstrip()) + 1
            raise AsmSyntaxError(Span(path, i + 1, col), "unexpected text before the first declaration")
    applies = None
    applies_span = None
    decls = []
    for n, (line, col, kw) in enumerate(starts):
        end = starts[n + 1][0] if n + 1 < len(starts) else len(lines)
        body_lines = lines[line:end]
        body = "\n".join(body_lines)
        rest = body[col + len(kw):]
        rest_col = col + len(kw) + 1
        if kw.startswith("applies"):
            items = _applies_names(path, strip_comments(rest), line, rest_col)
            if not items:
                raise AsmSyntaxError(Span(path, line + 1, col + 1), "'applies to' needs spec names or '*'")
            applies = items
            applies_span = Span(path, line + 1, col + 1)
            continue
        kind = {"invariant": "invariant", "step": "step", "LTLSPEC": "ltl", "ltlspec": "ltl", "CTLSPEC": "ctl",
                "ctlspec": "ctl", "JUSTICE": "justice", "justice": "justice", "COMPASSION": "compassion",
                "compassion": "compassion"}[kw]
        name = None
        name_span = None
        offset = 0
        if kind in ("invariant", "step", "ltl", "ctl"):
            m = re.match(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*:", rest)
            if not m:
                # unnamed: the term starts right away
                if kind in ("invariant", "step"):
                    raise AsmSyntaxError(Span(path, line + 1, rest_col), f"expected '{kw} NAME: term'")
            else:
                name = m.group(1)
                name_span = Span(path, line + 1, rest_col + m.start(1))
                offset = m.end()
        term_text = rest[offset:]
        # the term's start position in the file
        pre = rest[:offset]
        tline = line + 1 + pre.count("\n")
        tcol = (rest_col + offset) if "\n" not in pre else len(pre.split("\n")[-1]) + 1
        decls.append(PropDecl(kind, name, term_text, tline, tcol, path, name_span or Span(path, line + 1, col + 1)))
    return PropFile(path, applies, decls, applies_span)


_APPLIES_TOKEN = re.compile(r",|[^\s,]+")


def _applies_names(path: str, rest: str, line: int, rest_col: int) -> list[str]:
    """The names of an 'applies to' line (``rest``: what follows the keyword, comments blanked,
    starting at 0-based ``line`` and 1-based column ``rest_col``): names separated by commas;
    anything else is an error at its own line and column."""
    def where(offset: int) -> Span:
        before = rest[:offset]
        if "\n" not in before:
            return Span(path, line + 1, rest_col + offset)
        return Span(path, line + 1 + before.count("\n"), offset - before.rindex("\n"))

    names: list[str] = []
    want_name = True
    for m in _APPLIES_TOKEN.finditer(rest):
        tok = m.group(0)
        if tok == ",":
            if want_name:
                raise AsmSyntaxError(where(m.start()), "expected a spec name or '*' before ',' in 'applies to'")
            want_name = True
        elif not re.fullmatch(r"\*|[A-Za-z_][A-Za-z0-9_]*", tok):
            raise AsmSyntaxError(where(m.start()), f"bad spec name {tok!r} in 'applies to'")
        elif not want_name:
            raise AsmSyntaxError(where(m.start()), f"unexpected {tok!r} after the spec names of 'applies to' "
                                                   f"(names are separated by commas; a declaration starts with "
                                                   f"'invariant', 'step', 'LTLSPEC', 'CTLSPEC', 'JUSTICE' or "
                                                   f"'COMPASSION')")
        else:
            names.append(tok)
            want_name = False
    if names and want_name:
        raise AsmSyntaxError(where(len(rest.rstrip())), "expected a spec name or '*' after ',' in 'applies to'")
    return names


def strip_comments(text: str) -> str:
    out = []
    i = 0
    n = len(text)
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("".join(c if c == "\n" else " " for c in text[i:j]))
            i = j
        elif text[i] == '"':
            j = text.find('"', i + 1)
            j = n if j < 0 else j + 1
            out.append(text[i:j])
            i = j
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


def expected_violations(spec_path: str) -> set[str]:
    """Property names a spec declares it breaks (``// asmcheck: expect violated NAME``)."""
    from ..syntax.parser import read_source_bytes
    try:
        text = decode_source(read_source_bytes(spec_path))
    except AsmError:
        return set()
    out = set()
    for m in _EXPECT.finditer(text):
        out.update(x.strip() for x in m.group(1).split(",") if x.strip())
    return out


def default_property_files(spec_path: str) -> list[str]:
    """The ``properties/`` folder beside the spec, or beside one of its parent folders."""
    p = Path(spec_path).resolve().parent
    for _ in range(4):
        cand = p / "properties"
        if cand.is_dir():
            return sorted(str(x) for x in cand.glob("*.prop"))
        if p.parent == p:
            break
        p = p.parent
    return []


# ----------------------------------------------------------------- resolution
def resolve_decl(spec, decl: PropDecl) -> ir.Property:
    from ..semantics.resolve import Env, Resolver

    term = parse_term(decl.text, decl.path, (decl.line, decl.col))
    mod = spec.root_module
    res = Resolver(spec.loader, mod)
    res.temporal_ok = decl.kind in ("ltl", "ctl")
    res.step_ok = decl.kind == "step"
    body2 = None
    if decl.kind == "compassion":
        from ..syntax import ast as A
        if not (isinstance(term, A.TupleTerm) and len(term.items) == 2):
            raise AsmTypeError(term.span, "COMPASSION needs two formulas: COMPASSION(p, q)")
        p, q = term.items
        body = res.bool_term(p, Env())
        body2 = res.bool_term(q, Env())
    else:
        body = res.bool_term(term, Env())
    name = decl.name or f"{decl.kind}@{Path(decl.path).name}:{decl.line}"
    prop = ir.Property(decl.kind, name, body, decl.name_span, body2, [], source=decl.path)
    return prop


class StepProperty:
    kind = "step"

    def __init__(self, prop, machine):
        self.prop = prop
        self.name = prop.name
        self.span = prop.span
        self.source = prop.source
        self.expect = getattr(prop, "expect", None)
        self.fn = machine.term(prop.body)

    def check_step(self, machine, state, ups, nxt, mon) -> bool:
        from . import evaluate_all
        for v in evaluate_all_step(machine, self.fn, state, ups, nxt, mon):
            if v is None:
                raise AsmRuntimeError(self.span, f"step property {self.name} is undef")
            if v is not True:
                return False
        return True


def evaluate_all_step(machine, fn, state, ups, nxt, mon):
    from ..semantics.machine import Enumerator
    prefix: list = []
    while True:
        ch = Enumerator(prefix)
        ctx = Ctx(machine, state, ch)
        ctx.post = nxt
        ctx.ups = ups
        if mon:
            ctx.mon = dict(mon)
        yield fn(ctx)
        prefix = next_prefix(ch.log)
        if prefix is None:
            return


def properties_for(spec, machine, spec_path, files=None, use_default=True, must_apply=False):
    """(state properties, step properties, temporal properties and fairness) that apply to
    the spec: the given files, plus by default the property files beside the specs.  With
    ``must_apply``, a given file whose ``applies to`` line does not name the spec is an error."""
    from . import MonitoredInvariant, StateProperty
    from ..semantics.analysis import mentions_monitored

    paths = list(files or [])
    if use_default:
        for p in default_property_files(spec_path):
            if p not in paths:
                paths.append(p)
    expected = expected_violations(spec_path)
    state, step, temporal = [], [], []
    names = {p.name for p in spec.properties}
    for path in paths:
        pf = read_prop_file(path)
        explicit = files is not None and path in files
        if pf.applies is None and not explicit:
            continue
        if not pf.applies_to(spec.name) and not (explicit and pf.applies is None):
            if explicit and must_apply:
                raise AsmTypeError(pf.applies_span, f"the property file {path} applies to "
                                                    f"{', '.join(pf.applies)}, not to {spec.name}; fix its "
                                                    f"'applies to' line, or leave the file out")
            continue
        for decl in pf.decls:
            prop = resolve_decl(spec, decl)
            if prop.name in names:
                raise AsmTypeError(decl.name_span, f"property {prop.name} is already declared (in the spec or "
                                                   f"another property file)")
            names.add(prop.name)
            if prop.kind == "invariant":
                if mentions_monitored(prop.body):
                    step.append(MonitoredInvariant(prop, machine))
                else:
                    state.append(StateProperty(prop, machine))
            elif prop.kind == "step":
                step.append(StepProperty(prop, machine))
            else:
                temporal.append(prop)
    for p in spec.properties:
        if p.kind in ("ltl", "ctl", "justice", "compassion"):
            temporal.append(p)
    for group in (state, step):
        for p in group:
            if p.name in expected:
                p.expect = "violated"
    for p in temporal:
        if p.name in expected:
            p.expect = "violated"
    return state, step, temporal
