"""What the language server knows about one document: errors, names, scopes.

Everything here is plain Python over asmcheck's front end (no LSP types), so it
can be tested and measured on its own.  Positions are asmcheck's: lines and
columns 1-based, ends exclusive.

A document is analysed from its editor text (not from disk); the modules it
imports are read from disk through the parser's cache, so after the first
analysis only the edited text is parsed again.
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass, field, fields, is_dataclass
from pathlib import Path

from ..errors import AsmError, AsmSyntaxError, AsmTypeError, Span
from ..semantics import ir
from ..semantics import resolve as R
from ..semantics import stdlib
from ..semantics import types as T
from ..syntax import ast as A
from ..syntax.parser import decode_source, parse_text
from . import library as L


# ----------------------------------------------------------------- loading a document's text
class _TextLoader(R.Loader):
    """A Loader whose root comes from a string; it remembers which import of the root is being read."""

    def __init__(self, text: str, parser=None) -> None:
        super().__init__()
        self.text = text
        self.parser = parser
        self.root: R.Module | None = None
        self.current_import: A.Import | None = None
        self.declared = False

    def load_root(self, path: str) -> R.Module:
        p = os.path.abspath(path)
        stem = Path(p).stem
        if stem in R.REFUSED:
            raise AsmError(Span(path, 1, 1), f"{Path(path).name} names a library that asmcheck provides itself; "
                                             f"it is not read as a spec (import it instead)")
        syntax = self.parser.parse(self.text) if self.parser is not None else parse_text(self.text, path)
        if syntax is None:
            return None
        mod = R.Module(syntax.name, path, syntax)
        self.root = mod
        self.modules[p] = mod
        self._declare(mod, [p])
        self.declared = True
        return mod

    def _import(self, importer, imp, stack):
        if importer is self.root:
            self.current_import = imp
        return super()._import(importer, imp, stack)


@dataclass
class Problem:
    """A diagnostic: where, what, and (for an error inside an imported module) where it really is."""

    span: Span
    message: str
    severity: str = "error"           # error warning information
    related: list[tuple[Span, str]] = field(default_factory=list)


@dataclass
class Analysis:
    path: str
    text: str
    syntax: A.Spec | None = None
    loader: _TextLoader | None = None
    root: R.Module | None = None        # set once the root's declarations are complete
    spec: ir.Spec | None = None
    error: AsmError | None = None
    problems: list[Problem] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.error is None


def _load_spec(loader: _TextLoader, path: str) -> ir.Spec | None:
    """What :func:`asmcheck.semantics.resolve.check_file` does, with the root read from the loader's text."""
    root = loader.load_root(path)
    if root is None:
        return None
    syn = root.syntax
    if syn.name != Path(path).stem:
        raise AsmError(syn.name_span or syn.span,
                       f"the {'module' if syn.is_module else 'asm'} name {syn.name!r} differs from its file "
                       f"name {Path(path).name!r}")
    for mod in loader.order:
        if mod.library is None or mod.library == "TimeLibrary":
            R.resolve_module(loader, mod, mod is root)
    if loader.time is not None and not loader.time.resolved:
        R.resolve_module(loader, loader.time, False)
    if syn.main is not None:
        main = next(r for r in root.rules if r.name == syn.main.name and len(r.params) == len(syn.main.params))
        if main.params:
            raise AsmTypeError(syn.main.span, "the main rule takes no parameters")
    if not syn.is_module and syn.inits and not any(i.default for i in syn.inits):
        raise AsmTypeError(syn.span, "an asm with init blocks needs one 'default init'")
    return root


def analyse(path: str, text: str, parser=None) -> Analysis:
    """Parse and check ``text`` as the file ``path``; errors become problems.

    ``parser``: an :class:`asmcheck.lsp.incremental.IncrementalParser` for this path, which parses
    only the declaration an edit changed (the document's imports come from the parser's file cache).
    """
    an = Analysis(path, text)
    loader = _TextLoader(text, parser)
    an.loader = loader
    try:
        _load_spec(loader, path)
    except AsmError as err:
        an.error = err
        an.problems.append(_problem(an, loader, err))
    except RecursionError:
        an.error = AsmError(Span(path, 1, 1), "the spec nests too deeply (recursion limit reached)")
        an.problems.append(Problem(an.error.span, an.error.message))
    if loader.root is not None:
        an.syntax = loader.root.syntax
        if loader.declared:
            an.root = loader.root
    return an


def _closure(mod: R.Module) -> set[str]:
    seen: set[str] = set()
    todo = [mod]
    while todo:
        m = todo.pop()
        if m.path in seen:
            continue
        seen.add(m.path)
        todo.extend(t for t, _, _ in m.imports)
    return seen


def _problem(an: Analysis, loader: _TextLoader, err: AsmError) -> Problem:
    here = os.path.abspath(an.path)
    sp = err.span
    if sp is None or sp.line == 0:
        return Problem(Span(an.path, 1, 1, 1, 1), err.message)
    if os.path.abspath(sp.path) == here or sp.path == an.path:
        return Problem(sp, err.message, related=[(s, n) for s, n in err.notes if s is not None and s.line])
    # an error inside an imported module: show it on the import line that leads there
    imp = None
    root = loader.root
    if root is not None:
        target = os.path.abspath(sp.path) if not sp.path.startswith("<") else sp.path
        for mod, _, ispan in root.imports:
            if target in _closure(mod):
                imp = next((i for i in root.syntax.imports if i.span == ispan), None)
                if imp is not None:
                    break
        if imp is None and loader.current_import is not None:
            imp = loader.current_import
    where = imp.span if imp is not None else Span(an.path, 1, 1, 1, 1)
    return Problem(where, f"{Path(sp.path).name}:{sp.line}:{sp.col}: {err.message}",
                   related=[(sp, err.message)])


# ----------------------------------------------------------------- tokens
TOKEN_RE = re.compile(r"""
    (?P<comment>//[^\n]*|/\*.*?\*/)
  | (?P<string>"(?:[^"\\\n]|\\.)*"|'(?:[^'\\\n]|\\.)*')
  | (?P<name>\$?[A-Za-z_][A-Za-z0-9_]*)
""", re.S | re.X)


@dataclass(frozen=True)
class Token:
    name: str
    line: int
    col: int

    @property
    def end_col(self) -> int:
        return self.col + len(self.name)


def tokens(text: str) -> list[Token]:
    """The names and $variables of a text with their positions (comments and literals skipped)."""
    out = []
    line_starts = [0]
    for m in re.finditer("\n", text):
        line_starts.append(m.end())
    import bisect
    for m in TOKEN_RE.finditer(text):
        if m.lastgroup != "name":
            continue
        pos = m.start()
        ln = bisect.bisect_right(line_starts, pos)
        out.append(Token(m.group(), ln, pos - line_starts[ln - 1] + 1))
    return out


def token_at(text: str, line: int, col: int) -> Token | None:
    """The name under (or just before) the cursor; ``col`` is 1-based."""
    lines = text.split("\n")
    if not (1 <= line <= len(lines)):
        return None
    s = lines[line - 1]
    for m in TOKEN_RE.finditer(s):
        if m.lastgroup == "name" and m.start() + 1 <= col <= m.end() + 1:
            return Token(m.group(), line, m.start() + 1)
    return None


# ----------------------------------------------------------------- variables and their scopes
@dataclass(frozen=True)
class Binder:
    name: str
    span: Span              # where the variable is introduced
    start: tuple[int, int]  # scope
    end: tuple[int, int]
    detail: str = ""        # e.g. "$x in Task"


def span_start(sp: Span) -> tuple[int, int]:
    return (sp.line, sp.col)


def span_end(sp: Span) -> tuple[int, int]:
    if sp.end_line:
        return (sp.end_line, sp.end_col)
    return (sp.line, sp.col + 1)


def node_end(node) -> tuple[int, int]:
    """The farthest end of a node and its children (rule declarations carry only their name's span)."""
    best = (0, 0)

    def walk(x):
        nonlocal best
        if isinstance(x, A.Node):
            sp = x.span
            if sp.line:
                best = max(best, span_end(sp))
            for f in fields(x):
                walk(getattr(x, f.name))
        elif isinstance(x, (list, tuple)):
            for y in x:
                walk(y)
        elif isinstance(x, Span) and x.line:
            best = max(best, span_end(x))
    walk(node)
    return best


def _range_text(term) -> str:
    if isinstance(term, A.DomainRef):
        return str(term.type)
    if isinstance(term, A.Apply) and not term.args:
        return term.name
    return ""


def binders(syntax: A.Spec | None) -> list[Binder]:
    """Every $variable the spec introduces, with the region where it is in scope."""
    out: list[Binder] = []
    if syntax is None:
        return out

    def add(name, span, start, end, detail=""):
        out.append(Binder(name, span, start, end, detail))

    def walk(x):
        if isinstance(x, A.Node):
            sp = x.span
            if isinstance(x, (A.ChooseRule, A.ForallRule, A.QuantTerm, A.ComprTerm)):
                for b in x.bindings:
                    rt = _range_text(b.range)
                    add(b.var, b.span, span_start(sp), span_end(sp), f"{b.var} in {rt}" if rt else b.var)
            elif isinstance(x, (A.LetRule, A.LetTerm)):
                for name, bspan, _ in x.bindings:
                    add(name, bspan, span_start(sp), span_end(sp), f"let {name}")
            elif isinstance(x, A.ExtendRule):
                for name, bspan in x.vars:
                    add(name, bspan, span_start(sp), span_end(sp), f"{name} in {x.domain}")
            for f in fields(x):
                walk(getattr(x, f.name))
        elif isinstance(x, (list, tuple)):
            for y in x:
                walk(y)

    for r in syntax.rules:
        end = node_end(r)
        for p in r.params:
            add(p.name, p.span, span_start(r.span), end, f"{p.name} in {p.type}")
        walk(r.body)
    for fd in list(syntax.function_defs) + [f for ib in syntax.inits for f in ib.functions]:
        end = node_end(fd)
        for p in fd.params:
            add(p.name, p.span, span_start(fd.span), end, f"{p.name} in {p.type}")
        walk(fd.body)
    for dd in syntax.domain_defs + [d for ib in syntax.inits for d in ib.domains]:
        walk(dd.body)
    for p in syntax.properties:
        walk(p.body)
        if p.body2 is not None:
            walk(p.body2)
    return out


def vars_in_scope(bs: list[Binder], line: int, col: int) -> dict[str, Binder]:
    """The variables visible at a position: the innermost binder of each name."""
    found: dict[str, Binder] = {}
    for b in bs:
        if b.start <= (line, col) <= b.end:
            cur = found.get(b.name)
            if cur is None or b.start >= cur.start:
                found[b.name] = b
    return found


# ----------------------------------------------------------------- declarations
KINDS = ("functions", "rules", "domains", "enums")


def lookup(scope: R.Table, name: str) -> list:
    """Every declaration a name can stand for in a module's scope."""
    out = []
    for kind in KINDS:
        out.extend(getattr(scope, kind).get(name, []))
    return out


@dataclass(frozen=True)
class Place:
    """Where a declaration is written: a file path or an ``asmcheck:`` library URI, and a span."""

    where: str              # a file path, or an asmcheck: URI
    line: int
    col: int
    end_line: int
    end_col: int

    @property
    def is_uri(self) -> bool:
        return self.where.startswith(L.SCHEME + ":")


def _span_place(sp: Span) -> Place | None:
    if sp is None or sp.line == 0:
        return None
    if sp.path.startswith("<") and sp.path.endswith(">"):
        where = L.library_uri(sp.path[1:-1])
    else:
        where = os.path.abspath(sp.path)
    end_line, end_col = span_end(sp)
    return Place(where, sp.line, sp.col, end_line, end_col)


def _library_place(lib: str, key) -> Place | None:
    text = L.library(lib)
    if text is None:
        return None
    hit = text.where(key)
    if hit is None:
        return None
    line, col, end = hit
    return Place(L.library_uri(lib), line, col, line, end)


class Index:
    """Where each declaration of an analysed document's world is written."""

    def __init__(self, an: Analysis):
        self.an = an
        self.enum_spans: dict[tuple[int, str], Span] = {}
        loader = an.loader
        mods = list(loader.modules.values()) if loader else []
        if loader is not None and loader.time is not None:
            mods.append(loader.time)
        for m in mods:
            if m.syntax is None:
                continue
            for d in m.syntax.domains:
                if d.kind != "enum":
                    continue
                for dom in m.own.domains.get(d.name, []):
                    for el, el_span in d.elements:
                        self.enum_spans[(id(dom), el)] = el_span

    def place(self, obj) -> Place | None:
        if isinstance(obj, stdlib.Signature):
            return _library_place(obj.library, id(obj))
        if isinstance(obj, tuple) and len(obj) == 2 and isinstance(obj[1], T.Domain):
            v, dom = obj
            sp = self.enum_spans.get((id(dom), v.name))
            return _span_place(sp) if sp is not None else None
        if isinstance(obj, T.Domain) and obj.module == "StandardLibrary":
            return _library_place("StandardLibrary", id(obj)) or _library_place("StandardLibrary",
                                                                               ("domain", obj.name))
        if isinstance(obj, ir.Function) and obj.module == "StandardLibrary" and not obj.span.line:
            return _library_place("StandardLibrary", ("function", obj.name))
        sp = getattr(obj, "span", None)
        return _span_place(sp) if isinstance(sp, Span) else None


def kind_of(obj) -> str:
    if isinstance(obj, (ir.Function, stdlib.Signature)):
        return "function"
    if isinstance(obj, ir.RuleDecl):
        return "rule"
    if isinstance(obj, T.Domain):
        return "domain"
    if isinstance(obj, tuple):
        return "enum"
    return "?"


def describe(obj) -> str:
    """A one-line declaration: ``controlled f: D -> C``, ``rule r_x($a in D)``, ``enum domain C``."""
    if isinstance(obj, stdlib.Signature):
        return L.signature_text(obj) + f"   ({obj.library})"
    if isinstance(obj, ir.Function):
        if not obj.domain:
            dom = ""
        elif len(obj.domain) == 1:
            dom = f"{obj.domain[0]} -> "
        else:
            dom = "Prod(" + ", ".join(map(str, obj.domain)) + ") -> "
        return f"{obj.kind} {obj.name}: {dom}{obj.codomain}"
    if isinstance(obj, ir.RuleDecl):
        params = ", ".join(f"{p.name} in {p.type}" for p in obj.params)
        head = "turbo rule" if obj.kind == "turbo" else "rule"
        ret = f" -> {obj.returns}" if obj.returns is not None else ""
        return f"{head} {obj.name}" + (f"({params})" if obj.params else "") + ret
    if isinstance(obj, T.Domain):
        if obj.kind == "enum":
            return f"enum domain {obj.name} = {{{' | '.join(v.name for v in obj.elements)}}}"
        if obj.kind == "subset":
            return f"{'dynamic ' if obj.dynamic else ''}domain {obj.name} subsetof {obj.base}"
        if obj.kind == "any":
            return f"anydomain {obj.name}"
        if obj.kind == "basic":
            return f"basic domain {obj.name}"
        return f"{'dynamic ' if obj.dynamic else ''}abstract domain {obj.name}"
    if isinstance(obj, tuple):
        v, dom = obj
        return f"{v.name}: {dom.name}"
    return str(obj)


def module_of(obj) -> str:
    if isinstance(obj, stdlib.Signature):
        return obj.library
    if isinstance(obj, tuple):
        return getattr(obj[1], "module", "")
    return getattr(obj, "module", "")


def doc_comment(text: str, line: int) -> str:
    """The comment written just above a declaration's line (or after it on the same line)."""
    lines = text.split("\n")
    if not (1 <= line <= len(lines)):
        return ""
    out: list[str] = []
    i = line - 2
    if i >= 0 and lines[i].strip().endswith("*/"):
        block = []
        while i >= 0:
            block.insert(0, lines[i])
            if "/*" in lines[i]:
                break
            i -= 1
        body = "\n".join(block)
        body = body[body.find("/*") + 2: body.rfind("*/")]
        out = [ln.strip().lstrip("*").strip() for ln in body.split("\n")]
    else:
        while i >= 0 and lines[i].strip().startswith("//"):
            out.insert(0, lines[i].strip()[2:].strip())
            i -= 1
    same = lines[line - 1]
    m = re.search(r"//(.*)$", same)
    if m and not same.strip().startswith("//"):
        out.append(m.group(1).strip())
    return "\n".join(x for x in out if x).strip()


# ----------------------------------------------------------------- texts of the modules in view
class Texts:
    """The text of each file, read once per modification (editor text for open documents)."""

    def __init__(self) -> None:
        self.open: dict[str, str] = {}                    # absolute path -> editor text
        self._disk: dict[str, tuple[int, str]] = {}

    def get(self, where: str) -> str | None:
        if where.startswith(L.SCHEME + ":"):
            lib = L.library_of_uri(where)
            return lib.text if lib else None
        p = os.path.abspath(where)
        if p in self.open:
            return self.open[p]
        try:
            st = os.stat(p)
        except OSError:
            return None
        hit = self._disk.get(p)
        if hit is not None and hit[0] == st.st_mtime_ns:
            return hit[1]
        try:
            text = decode_source(Path(p).read_bytes())
        except OSError:
            return None
        self._disk[p] = (st.st_mtime_ns, text)
        return text
