"""Parse an edited document again, one declaration at a time.

A keystroke changes one declaration (a rule, a function definition, a
signature line, a property).  After a full parse this parser remembers where
each top-level declaration of the text starts and ends; when the next text
differs from the previous one only inside one declaration, it parses that
declaration alone (with the grammar started at that declaration's rule, the
text padded so lines and columns come out as in the whole file), puts the new
node in place of the old one and moves the positions of what follows by the
number of lines added or removed.  Anything else -- an edit across two
declarations, a declaration that no longer parses alone, an edit in the
header -- is a full parse with the front end's own parser, so every error is
reported exactly as ``asmcheck parse`` reports it.
"""
from __future__ import annotations

import dataclasses
import hashlib
import re
import threading
from dataclasses import dataclass
from pathlib import Path

from lark import Lark, Tree
from lark.exceptions import UnexpectedInput, VisitError

from ..cache import private_cache_file
from ..errors import AsmError, SOURCES, Span
from ..syntax import ast as A
from ..syntax import parser as P

_DOMAIN_DECLS = {"subset_domain": "domain_decl", "any_domain": "domain_decl", "basic_domain": "domain_decl",
                 "abstract_domain": "domain_decl", "enum_domain": "domain_decl"}
_BODY = {"domain_def": ("domain_def", "domain_defs"), "function_def": ("function_def", "function_defs"),
         "macro_decl": ("rule_decl", "rules"), "turbo_decl": ("rule_decl", "rules"),
         "invar_constraint": ("invar_constraint", "properties"), "justice": ("fairness", "properties"),
         "compassion": ("fairness", "properties"), "invariant": ("property", "properties"),
         "ctlspec": ("property", "properties"), "ltlspec": ("property", "properties")}
_STARTS = ["start", "domain_decl", "function_decl", "domain_def", "function_def", "rule_decl", "main_decl",
           "invar_constraint", "fairness", "property", "domain_init", "function_init"]
_GAP = re.compile(r"(?:\s+|//[^\n]*|/\*.*?\*/)*\Z", re.S)

_lock = threading.Lock()
_parts: Lark | None = None


GRAMMAR = Path(P.__file__).with_name("asmetal.lark")


def _cache_file():
    """Where lark keeps this parser's tables between runs: a file of asmcheck's private cache
    (:mod:`asmcheck.cache`), or False when none can be trusted."""
    digest = hashlib.sha256(GRAMMAR.read_bytes() + repr(_STARTS).encode()).hexdigest()[:16]
    path = private_cache_file(f"grammar-{digest}-parts.lark.cache")
    return str(path) if path is not None else False


def _part_parser() -> Lark:
    """The front end's grammar (asmcheck/syntax/asmetal.lark), with each kind of declaration as a
    start symbol besides the whole file."""
    global _parts
    with _lock:
        if _parts is None:
            _parts = Lark(GRAMMAR.read_text(encoding="utf-8"), parser="lalr", lexer="contextual",
                          propagate_positions=True, maybe_placeholders=False, start=_STARTS, cache=_cache_file())
        return _parts


def warm_up() -> None:
    """Build (or read from the cache) the parser tables before the first edit needs them."""
    _part_parser()


def _build(tree, path: str):
    """The syntax tree node of a parse tree, as the front end builds it."""
    return P._Builder(path).transform(tree)


@dataclass
class Item:
    start: int          # character offsets in the text, end exclusive
    end: int
    line: int           # first and last line (1-based)
    end_line: int
    end_col: int        # just after its last character (1-based)
    symbol: str         # the start symbol that parses it alone
    where: tuple        # where its node is in the Spec: ("rules", 3), ("main",), ("inits", 0, "functions", 2)


class State:
    def __init__(self, text: str, spec: A.Spec | None, items: list[Item] | None):
        self.text = text
        self.spec = spec
        self.items = items          # None: no incremental parse from this text


_FIELD_CACHE: dict[type, tuple[str, ...]] = {}


def _fields(tp) -> tuple[str, ...]:
    f = _FIELD_CACHE.get(tp)
    if f is None:
        f = _FIELD_CACHE[tp] = tuple(x.name for x in dataclasses.fields(tp))
    return f


def _items(tree: Tree, spec: A.Spec) -> list[Item] | None:
    """Each top-level declaration of the parse tree and where its node is in the Spec."""
    out: list[Item] = []
    header = body = main = None
    for c in tree.children:
        if isinstance(c, Tree):
            if c.data == "header":
                header = c
            elif c.data == "body":
                body = c
            elif c.data == "main_decl":
                main = c
    if header is None or body is None:
        return None
    sig = next((c for c in header.children if isinstance(c, Tree) and c.data == "signature"), None)
    counts = {"domains": 0, "functions": 0, "domain_defs": 0, "function_defs": 0, "rules": 0, "properties": 0}

    def add(t: Tree, symbol: str | None, field: str):
        idx = counts[field]
        counts[field] += 1
        if symbol is not None:
            m = t.meta
            out.append(Item(m.start_pos, m.end_pos, m.line, m.end_line, m.end_column, symbol, (field, idx)))

    for c in (sig.children if sig is not None else []):
        if not isinstance(c, Tree):
            continue
        if c.data == "function_decl":
            add(c, "function_decl", "functions")
        else:
            add(c, _DOMAIN_DECLS.get(c.data), "domains")
    for c in body.children:
        if isinstance(c, Tree) and c.data in _BODY:
            symbol, field = _BODY[c.data]
            add(c, symbol, field)
    n_rules = len(spec.rules) - (1 if spec.main is not None else 0)
    if (counts["domains"], counts["functions"], counts["domain_defs"], counts["function_defs"], counts["rules"],
            counts["properties"]) != (len(spec.domains), len(spec.functions), len(spec.domain_defs),
                                      len(spec.function_defs), n_rules, len(spec.properties)):
        return None
    if main is not None:
        m = main.meta
        out.append(Item(m.start_pos, m.end_pos, m.line, m.end_line, m.end_column, "main_decl", ("main",)))
    init = next((c for c in tree.children if isinstance(c, Tree) and c.data == "init_section"), None)
    if init is not None:
        blocks = [c for c in init.children if isinstance(c, Tree) and c.data == "init_block"]
        if len(blocks) != len(spec.inits):
            return None
        for b, (blk, ib) in enumerate(zip(blocks, spec.inits)):
            doms = [c for c in blk.children if isinstance(c, Tree) and c.data == "domain_init"]
            funcs = [c for c in blk.children if isinstance(c, Tree) and c.data == "function_init"]
            if len(doms) != len(ib.domains) or len(funcs) != len(ib.functions):
                return None
            for i, c in enumerate(doms):
                m = c.meta
                out.append(Item(m.start_pos, m.end_pos, m.line, m.end_line, m.end_column, "domain_init", ("inits", b, "domains", i)))
            for i, c in enumerate(funcs):
                m = c.meta
                out.append(Item(m.start_pos, m.end_pos, m.line, m.end_line, m.end_column, "function_init",
                                ("inits", b, "functions", i)))
    out.sort(key=lambda it: it.start)
    return out


class IncrementalParser:
    """Parses the successive texts of one document; ``parse(text)`` returns the Spec (or raises)."""

    def __init__(self, path: str):
        self.path = path
        self.state: State | None = None
        self.last_was_partial = False

    def parse(self, text: str) -> A.Spec | None:
        st = self.state
        self.last_was_partial = False
        if st is not None and st.items is not None and st.spec is not None:
            if text == st.text:
                SOURCES.add(self.path, text)
                return st.spec
            try:
                spec = self._partial(st, text)
            except Exception:                 # never worse than parsing the whole text
                spec = None
            if spec is not None:
                self.last_was_partial = True
                return spec
        return self._full(text)

    # -- a whole text
    def _full(self, text: str) -> A.Spec | None:
        self.state = None
        try:
            with P.gc_paused():
                tree = _part_parser().parse(text, start="start")
                spec = _build(tree.children[0], self.path) if tree.children else None
        except (UnexpectedInput, VisitError, RecursionError):
            # the front end's parser says what is wrong, exactly as `asmcheck parse` does
            spec = P.parse_text(text, self.path)
            self.state = State(text, spec, None)
            return spec
        SOURCES.add(self.path, text)
        self.state = State(text, spec, _items(tree.children[0], spec) if spec is not None else None)
        return spec

    # -- one declaration
    def _partial(self, st: State, text: str) -> A.Spec | None:
        old = st.text
        a = _common_prefix(old, text)
        limit = min(len(old), len(text)) - a
        s = _common_suffix(old, text, limit)
        b_old = len(old) - s                 # the change is old[a:b_old] -> text[a:len(text)-s]
        delta = len(text) - len(old)
        items = st.items
        k = next((i for i, it in enumerate(items) if it.start <= a and b_old <= it.end), None)
        if k is None:
            return self._gap(st, text, a, b_old, delta)
        it = items[k]
        if k + 1 < len(items) and items[k + 1].line <= it.end_line:
            return None                       # the next declaration starts on this one's last line
        new_end = it.end + delta
        piece = text[it.start:new_end]
        line_start = text.rfind("\n", 0, it.start) + 1
        col = it.start - line_start
        pad = "\n" * (it.line - 1) + " " * col
        try:
            tree = _part_parser().parse(pad + piece, start=it.symbol)
            node = _build(tree, self.path)
        except (UnexpectedInput, VisitError, AsmError, RecursionError):
            return None
        spec = st.spec
        old_node = _get(spec, it.where)
        if type(node) is not type(old_node):
            return None
        if isinstance(node, A.DomainDecl) and node.kind != old_node.kind:
            return None
        lines_delta = text.count("\n", it.start, new_end) - old.count("\n", it.start, it.end)
        new_spec = _replace(spec, it.where, node)
        m = tree.meta
        ends_file = (spec.span.end_line, spec.span.end_col) == (it.end_line, it.end_col)
        new_items = [dataclasses.replace(x) for x in items]
        new_items[k].end = new_end
        new_items[k].end_line = m.end_line
        new_items[k].end_col = m.end_column
        for x in new_items[k + 1:]:
            x.start += delta
            x.end += delta
            x.line += lines_delta
            x.end_line += lines_delta
        if lines_delta:
            after = it.end_line           # every span that starts on a later line moves
            _shift_spec(new_spec, items[k + 1:], after, lines_delta)
        if ends_file:                         # the declaration ends the file: so does the new one
            new_spec.span = Span(spec.span.path, spec.span.line, spec.span.col, m.end_line, m.end_column)
        SOURCES.add(self.path, text)
        self.state = State(text, new_spec, new_items)
        return new_spec


    # -- white space and comments between two declarations
    def _gap(self, st: State, text: str, a: int, b_old: int, delta: int) -> A.Spec | None:
        items = st.items
        j = next((i for i, it in enumerate(items) if it.start >= b_old), len(items))   # the item after the gap
        if j == 0 or items[j - 1].end > a:
            return None                       # in the header, or across a declaration
        lo = items[j - 1].end
        hi = items[j].start if j < len(items) else len(st.text)
        old_gap, new_gap = st.text[lo:hi], text[lo:hi + delta]
        if not (_GAP.match(old_gap) and _GAP.match(new_gap)) or '"' in new_gap or "'" in new_gap:
            return None
        if new_gap[:1].isspace() is False or (j < len(items) and not new_gap[-1:].isspace()):
            return None                       # the neighbours' tokens must stay apart
        lines_delta = new_gap.count("\n") - old_gap.count("\n")
        new_items = [dataclasses.replace(x) for x in items]
        for x in new_items[j:]:
            x.start += delta
            x.end += delta
            x.line += lines_delta
            x.end_line += lines_delta
        spec = st.spec
        if lines_delta:
            spec = dataclasses.replace(spec)
            _shift_spec(spec, items[j:], items[j - 1].end_line, lines_delta)
        SOURCES.add(self.path, text)
        self.state = State(text, spec, new_items)
        return spec


def _common_prefix(x: str, y: str) -> int:
    lo, hi = 0, min(len(x), len(y))
    while lo < hi:                            # the longest k with x[:k] == y[:k]
        mid = (lo + hi + 1) // 2
        if x[:mid] == y[:mid]:
            lo = mid
        else:
            hi = mid - 1
    return lo


def _common_suffix(x: str, y: str, limit: int) -> int:
    lo, hi = 0, max(limit, 0)
    lx, ly = len(x), len(y)
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if x[lx - mid:] == y[ly - mid:]:
            lo = mid
        else:
            hi = mid - 1
    return lo


def _moved(sp: Span, after: int, d: int) -> Span:
    if sp.line > after:
        return Span(sp.path, sp.line + d, sp.col, sp.end_line + d if sp.end_line else 0, sp.end_col)
    if sp.end_line > after:
        return Span(sp.path, sp.line, sp.col, sp.end_line + d, sp.end_col)
    return sp


def _shift(x, after: int, d: int, seen: set):
    """Move every Span below ``x`` that lies after line ``after`` by ``d`` lines (in place)."""
    if isinstance(x, A.Node):
        if id(x) in seen:
            return x
        seen.add(id(x))
        for name in _fields(type(x)):
            v = getattr(x, name)
            if isinstance(v, Span):
                nv = _moved(v, after, d)
                if nv is not v:
                    setattr(x, name, nv)
            elif isinstance(v, (A.Node, list, tuple)):
                nv = _shift(v, after, d, seen)
                if nv is not v:
                    setattr(x, name, nv)
        return x
    if isinstance(x, list):
        for i, v in enumerate(x):
            nv = _shift(v, after, d, seen)
            if nv is not v:
                x[i] = nv
        return x
    if isinstance(x, tuple):
        out = tuple(_moved(v, after, d) if isinstance(v, Span) else _shift(v, after, d, seen) for v in x)
        return out if any(a is not b for a, b in zip(out, x)) else x
    return x


def _shift_spec(spec: A.Spec, later: list[Item], after: int, d: int) -> None:
    """Move the declarations that follow the re-parsed one (and the init blocks) by ``d`` lines."""
    seen: set = set()
    for x in later:
        _shift(_get(spec, x.where), after, d, seen)
    for ib in spec.inits:
        ib.span = _moved(ib.span, after, d)
        _shift(ib.agents, after, d, seen)
    spec.span = _moved(spec.span, after, d)


def _get(spec: A.Spec, where: tuple):
    if where[0] == "main":
        return spec.main
    if where[0] == "inits":
        return getattr(spec.inits[where[1]], where[2])[where[3]]
    return getattr(spec, where[0])[where[1]]


def _replace(spec: A.Spec, where: tuple, node) -> A.Spec:
    """A copy of the Spec (sharing what did not change) with ``node`` at ``where``."""
    if where[0] == "main":
        rules = list(spec.rules)
        rules[-1] = node
        return dataclasses.replace(spec, main=node, rules=rules)
    if where[0] == "inits":
        inits = list(spec.inits)
        blk = inits[where[1]]
        lst = list(getattr(blk, where[2]))
        lst[where[3]] = node
        inits[where[1]] = dataclasses.replace(blk, **{where[2]: lst})
        return dataclasses.replace(spec, inits=inits)
    lst = list(getattr(spec, where[0]))
    lst[where[1]] = node
    return dataclasses.replace(spec, **{where[0]: lst})
