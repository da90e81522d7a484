"""Read Avalla scenario files (``*.avalla``) into a small syntax tree.

The grammar (``avalla.lark``) follows ASMETA's ``Avalla.xtext``.  Terms and rules inside
commands stay raw text here, with the position where they start; :mod:`asmcheck.avalla.terms`
parses them with asmcheck's AsmetaL parser.  Syntax errors are
:class:`~asmcheck.errors.AsmSyntaxError` with the file, line and column.
"""
from __future__ import annotations

import re
import threading
from dataclasses import dataclass, field
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from ..errors import AsmError, AsmSyntaxError, SOURCES, Span
from ..syntax.parser import decode_source

_GRAMMAR_PATH = Path(__file__).with_name("avalla.lark")
_lock = threading.Lock()
_parser: Lark | None = None

KEYWORDS = ("scenario", "load", "invariant", "check", "set", "step", "until", "exec", "pick", "in",
            "execblock", "begin", "end")


def _grammar() -> Lark:
    global _parser
    with _lock:
        if _parser is None:
            _parser = Lark(_GRAMMAR_PATH.read_text(encoding="utf-8"), parser="lalr", lexer="contextual",
                           propagate_positions=True, maybe_placeholders=False, cache=False)
        return _parser


# ----------------------------------------------------------------- the tree
@dataclass
class Text:
    """AsmetaL text written in a scenario, and where it starts."""

    text: str
    span: Span

    @property
    def origin(self) -> tuple[int, int]:
        return (self.span.line, self.span.col)

    def display(self) -> str:
        """The text on one line (blanks collapsed), for reports."""
        return " ".join(_strip_comments(self.text).split())


@dataclass
class Command:
    span: Span          # the whole command, from its keyword

    kind = "command"


@dataclass
class Check(Command):
    term: Text
    kind = "check"


@dataclass
class Set(Command):
    location: Text
    value: Text
    kind = "set"


@dataclass
class Step(Command):
    kind = "step"


@dataclass
class StepUntil(Command):
    cond: Text
    kind = "step until"


@dataclass
class Exec(Command):
    rule: Text
    kind = "exec"


@dataclass
class Pick(Command):
    var: str
    var_span: Span
    rule: str | None
    rule_span: Span | None
    value: Text
    kind = "pick"


@dataclass
class ExecBlock(Command):
    scenario: str | None
    block: str
    block_span: Span
    kind = "execblock"


@dataclass
class Block(Command):
    name: str
    name_span: Span
    elements: list = field(default_factory=list)
    kind = "block"


@dataclass
class Invariant:
    span: Span
    name: str
    name_span: Span
    term: Text


@dataclass
class Scenario:
    path: str
    name: str
    name_span: Span
    load: str
    load_span: Span
    invariants: list[Invariant]
    elements: list

    def blocks(self):
        """Every block (nested ones too), in the order they are written."""
        out = []

        def walk(els):
            for e in els:
                if isinstance(e, Block):
                    out.append(e)
                    walk(e.elements)
        walk(self.elements)
        return out


# ----------------------------------------------------------------- reading
def read_scenario(path: str) -> Scenario:
    """Read and parse a scenario file."""
    from ..syntax.parser import read_source_bytes
    data = read_source_bytes(path)      # regular files only (a FIFO would block): a located error
    return parse_scenario(decode_source(data), path)


def parse_scenario(text: str, path: str) -> Scenario:
    SOURCES.add(path, text)
    try:
        tree = _grammar().parse(text)
    except UnexpectedInput as exc:
        raise _convert(exc, text, path) from None
    return _build(tree.children[0], path)


def _tspan(path: str, tok: Token) -> Span:
    return Span(path, tok.line, tok.column, tok.end_line or tok.line, tok.end_column or tok.column + len(tok))


def _span(path: str, tree: Tree) -> Span:
    m = tree.meta
    return Span(path, m.line, m.column, m.end_line, m.end_column)


def _text(path: str, tok: Token) -> Text:
    raw = str(tok).rstrip(" \t\r\n\f")
    lines = raw.split("\n")
    end_line = tok.line + len(lines) - 1
    end_col = (tok.column + len(raw)) if len(lines) == 1 else len(lines[-1]) + 1
    return Text(raw, Span(path, tok.line, tok.column, end_line, end_col))


def _build(tree: Tree, path: str) -> Scenario:
    ch = tree.children
    name_tok = ch[1]
    load_tree = ch[2]
    load_tok = load_tree.children[1]
    load = str(load_tok)
    if load.startswith('"') and load.endswith('"') and len(load) >= 2:
        load = load[1:-1]
    invariants = []
    elements = []
    for c in ch[3:]:
        if c.data == "invariant":
            _, name, term = c.children[0], c.children[1], c.children[2]
            invariants.append(Invariant(_span(path, c), str(name), _tspan(path, name), _text(path, term)))
        else:
            elements.append(_element(c, path))
    return Scenario(path, str(name_tok), _tspan(path, name_tok), load, _tspan(path, load_tok), invariants, elements)


def _element(t: Tree, path: str):
    sp = _span(path, t)
    toks = [c for c in t.children if isinstance(c, Token)]
    kind = t.data
    if kind == "check":
        return Check(sp, _text(path, toks[1]))
    if kind == "set":
        return Set(sp, _text(path, toks[1]), _text(path, toks[3]))
    if kind == "step":
        return Step(sp)
    if kind == "step_until":
        return StepUntil(sp, _text(path, toks[2]))
    if kind == "exec":
        return Exec(sp, _text(path, toks[1]))
    if kind == "pick":
        var = toks[1]
        rule = next((x for x in toks if x.type == "RULE_NAME"), None)
        value = next(x for x in toks if x.type == "TEXT")
        return Pick(sp, str(var), _tspan(path, var), str(rule) if rule is not None else None,
                    _tspan(path, rule) if rule is not None else None, _text(path, value))
    if kind == "execblock":
        names = [x for x in toks if x.type == "NAME"]
        if len(names) == 2:
            return ExecBlock(sp, str(names[0]), str(names[1]), _tspan(path, names[1]))
        return ExecBlock(sp, None, str(names[0]), _tspan(path, names[0]))
    if kind == "block":
        name = toks[1]
        els = [_element(c, path) for c in t.children if isinstance(c, Tree)]
        return Block(sp, str(name), _tspan(path, name), els)
    raise AssertionError(kind)


# ----------------------------------------------------------------- errors
_TERMINAL_NAMES = {
    "NAME": "a name",
    "PATH": "the path of the spec to load",
    "VARIABLE": "a variable ($x)",
    "RULE_NAME": "a rule name (r_...)",
    "TEXT": "an AsmetaL term or rule",
    "LOCATION": "a location",
    "ASSIGN": "':='",
    "SEMICOLON": "';'",
    "COLON": "':'",
    "$END": "end of file",
}


def _expected(names) -> str:
    shown = sorted({_TERMINAL_NAMES.get(n, repr(n.lower())) for n in names
                    if n not in ("WS", "COMMENT", "BLOCK_COMMENT")})
    return ", ".join(shown)


_WORD = re.compile(r"[^\s;:]+|.")


def _convert(exc: UnexpectedInput, text: str, path: str) -> AsmSyntaxError:
    line = getattr(exc, "line", None) or 1
    col = getattr(exc, "column", None) or 1
    if isinstance(exc, UnexpectedCharacters):
        m = _WORD.match(text, exc.pos_in_stream)
        word = m.group(0) if m else text[exc.pos_in_stream:exc.pos_in_stream + 1]
        if len(word) > 30:
            word = word[:27] + "..."
        msg = f"unexpected {word!r}"
        if exc.allowed:
            msg += f"; expected {_expected(exc.allowed)}"
        if exc.allowed and exc.allowed <= {"TEXT", "LOCATION"} and word == ";":
            msg = "the command has no " + ("location" if "LOCATION" in exc.allowed else "term")
        return AsmSyntaxError(Span(path, line, col, line, col + len(word)), msg)
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        if tok.type == "$END":
            line, col = _end_of_text(text)
            return AsmSyntaxError(Span(path, line, col), f"unexpected end of file; expected {_expected(exc.expected)}")
        # the contextual lexer may have read a longer token (a term's text) than the word there
        m = _WORD.match(text, tok.start_pos) if tok.start_pos is not None else None
        val = m.group(0) if m else str(tok)
        if len(val) > 30:
            val = val[:27] + "..."
        sp = Span(path, tok.line, tok.column, tok.line, tok.column + len(val))
        if val == "invariant":
            return AsmSyntaxError(sp, "scenario invariants come right after 'load', before every command")
        msg = f"unexpected {val!r}; expected {_expected(exc.expected)}"
        return AsmSyntaxError(sp, msg)
    if isinstance(exc, UnexpectedEOF):
        line, col = _end_of_text(text)
        return AsmSyntaxError(Span(path, line, col), "unexpected end of file")
    return AsmSyntaxError(Span(path, line, col), str(exc).split("\n")[0])


def _end_of_text(text: str) -> tuple[int, int]:
    lines = text.rstrip().split("\n")
    return len(lines), len(lines[-1].rstrip("\r")) + 1


_COMMENTS = re.compile(r'"[^"]*"|//[^\n]*|/\*[\s\S]*?\*/')


def _strip_comments(text: str) -> str:
    return _COMMENTS.sub(lambda m: m.group(0) if m.group(0).startswith('"') else " ", text)
