"""AsmetaL terms and rules written inside scenarios: parsing and name resolution.

Terms go through asmcheck's own term parser (:func:`asmcheck.syntax.parser.parse_term`);
an ``exec`` rule is wrapped as the main rule of a tiny asm and parsed with the AsmetaL
grammar.  Either way, positions in the result (and in errors) are positions in the
scenario file.

Elements that ``extend`` made are named ``D!k`` in ASMETA's output; ASMETA's own scenario
lexer cannot read such names (ASMETA issue #156).  Here they are accepted anywhere in a
term: ``check f = D!2;`` is the k-th element added to the abstract domain ``D``.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, fields

from lark.exceptions import UnexpectedInput, VisitError

from ..errors import AsmError, AsmSyntaxError, AsmTypeError, Span
from ..semantics import ir
from ..semantics import types as T
from ..semantics.resolve import Env, Resolver
from ..semantics.values import fresh_value
from ..syntax import ast as A
from ..syntax import parser as P
from .syntax import KEYWORDS, Text


@dataclass(slots=True, eq=False)
class ElementLit(A.Term):
    """``D!k``: the k-th element that ``extend`` added to the abstract domain ``D``."""

    domain: str
    serial: int
    text: str


# "D!k" outside strings and comments (the '!' of '!=' is never followed by a digit)
_ELEMENT = re.compile(r'"[^"]*"|//[^\n]*|/\*[\s\S]*?\*/|(?<![\w$!])([A-Za-z_][A-Za-z0-9_]*)!([0-9]+)(?![\w!])')


def _mask_elements(text: str, origin: tuple[int, int]):
    """Replace each ``D!k`` with ``D_k`` (same length, so positions do not move); return the
    new text and {(line, col) in the file: (domain, k, written text)}."""
    found = {}
    out = []
    last = 0
    for m in _ELEMENT.finditer(text):
        if m.group(1) is None:
            continue
        start = m.start()
        before = text[:start]
        nl = before.count("\n")
        line = origin[0] + nl
        col = (origin[1] + start) if nl == 0 else start - before.rfind("\n")
        found[(line, col)] = (m.group(1), int(m.group(2)), m.group(0))
        out.append(text[last:m.start()])
        out.append(m.group(0).replace("!", "_"))
        last = m.end()
    if not found:
        return text, found
    out.append(text[last:])
    return "".join(out), found


def _replace_elements(node, found):
    """Put ElementLit nodes where the masked ``D_k`` names were parsed."""
    def sub(n):
        if isinstance(n, (A.DomainRef, A.EnumLit, A.Apply)) and n.span is not None:
            hit = found.get((n.span.line, n.span.col))
            if hit is not None:
                name = n.type.name if isinstance(n, A.DomainRef) else n.name
                if name == hit[2].replace("!", "_") and (not isinstance(n, A.Apply) or n.args is None):
                    return ElementLit(n.span, hit[0], hit[1], hit[2])
        if isinstance(n, A.Node):
            for f in fields(n):
                v = getattr(n, f.name)
                nv = sub(v)
                if nv is not v:
                    setattr(n, f.name, nv)
            return n
        if isinstance(n, list):
            for i, x in enumerate(n):
                nx = sub(x)
                if nx is not x:
                    n[i] = nx
            return n
        if isinstance(n, tuple):
            items = [sub(x) for x in n]
            if any(a is not b for a, b in zip(items, n)):
                return tuple(items)
            return n
        return n
    return sub(node)


def _hint(err: AsmError, text: Text, what: str = "term") -> AsmError:
    """Parse errors in the words of a scenario: the text ends at the ';' of the command, and
    an Avalla keyword inside it usually means a missing ';' before it."""
    if err.message.startswith("unexpected end of file"):
        return AsmSyntaxError(err.span, f"the {what} ends too early" + err.message[len("unexpected end of file"):])
    m = re.match(r"unexpected '([a-z]+)'", err.message)
    if m and m.group(1) in KEYWORDS and m.group(1) not in ("in",):
        return AsmSyntaxError(err.span, err.message.split(";")[0] + " (is a ';' missing at the end of the "
                                                                     "command before it?)")
    return err


def parse_scenario_term(text: Text) -> A.Term:
    """Parse the AsmetaL term of a command."""
    masked, found = _mask_elements(text.text, text.origin)
    try:
        term = P.parse_term(masked, text.span.path, text.origin)
    except AsmError as err:
        raise _hint(err, text) from None
    return _replace_elements(term, found) if found else term


_RULE_HEAD = "asm T\nsignature:\ndefinitions:\nmain rule r_avalla__exec =\n"
_RULE_HEAD_LINES = _RULE_HEAD.count("\n")


def parse_scenario_rule(text: Text) -> A.Rule:
    """Parse the AsmetaL rule of an ``exec`` command."""
    path = text.span.path
    oline, ocol = text.origin
    masked, found = _mask_elements(text.text, text.origin)
    wrapped = _RULE_HEAD + masked + "\n"

    def unwrap(line, col):
        if line <= _RULE_HEAD_LINES:
            return oline, ocol
        if line == _RULE_HEAD_LINES + 1:
            return oline, col + ocol - 1
        return oline + line - _RULE_HEAD_LINES - 1, col

    def fix(sp: Span) -> Span:
        if sp is None or sp.line == 0:
            return sp
        l1, c1 = unwrap(sp.line, sp.col)
        l2, c2 = unwrap(sp.end_line or sp.line, sp.end_col or sp.col)
        return Span(path, l1, c1, l2, c2)

    try:
        tree = P._grammar().parse(wrapped)
    except UnexpectedInput as exc:
        err = P._convert(exc, wrapped, path)
        raise _hint(AsmSyntaxError(fix(err.span), err.message), text, "rule") from None
    try:
        spec = P._Builder(path).transform(tree.children[0])
    except VisitError as exc:
        if isinstance(exc.orig_exc, AsmError):
            e = exc.orig_exc
            raise AsmSyntaxError(fix(e.span), e.message) from None
        raise
    if spec.main is None:
        raise AsmSyntaxError(text.span, "expected a rule")
    rule = spec.main.body
    _shift(rule, fix)
    return _replace_elements(rule, found) if found else rule


def _shift(node, fix) -> None:
    seen = set()

    def walk(n):
        if isinstance(n, A.Node):
            if id(n) in seen:
                return
            seen.add(id(n))
            for f in fields(n):
                v = getattr(n, f.name)
                if isinstance(v, Span):
                    setattr(n, f.name, fix(v))
                elif isinstance(v, list):
                    for i, x in enumerate(v):
                        if isinstance(x, tuple):
                            v[i] = tuple(fix(y) if isinstance(y, Span) else y for y in x)
                            for y in x:
                                walk(y)
                        else:
                            walk(x)
                elif isinstance(v, tuple):
                    setattr(n, f.name, tuple(fix(y) if isinstance(y, Span) else y for y in v))
                    for y in v:
                        walk(y)
                else:
                    walk(v)
        elif isinstance(n, (list, tuple)):
            for x in n:
                walk(x)
    walk(node)


# ----------------------------------------------------------------- resolution
class ScenarioResolver(Resolver):
    """Resolves scenario terms and rules in the scope of the loaded spec's root module."""

    def __init__(self, spec):
        super().__init__(spec.loader, spec.root_module)

    def t_ElementLit(self, t: ElementLit, env: Env) -> ir.Term:
        dom = self.domain(t.domain, t.span)
        root = T.root(dom) if isinstance(dom, T.Domain) else None
        if not (isinstance(dom, T.Domain) and (dom.kind == "abstract" or (
                isinstance(root, T.Domain) and root.kind == "abstract"))):
            raise AsmTypeError(t.span, f"{t.text} names an element of {t.domain}, which is not an abstract domain")
        if t.serial < 1:
            raise AsmTypeError(t.span, f"{t.text}: the elements that extend adds are numbered from 1")
        return ir.Const(dom, t.span, fresh_value(dom.name, t.serial))

    def check_term(self, text: Text) -> ir.Term:
        return self.bool_term(parse_scenario_term(text), Env())

    def value_term(self, text: Text) -> ir.Term:
        return self.term(parse_scenario_term(text), Env())

    def set_rule(self, span: Span, location: Text, value: Text) -> ir.Rule:
        loc = parse_scenario_term(location)
        if not isinstance(loc, A.Apply) or loc.op is not None:
            raise AsmTypeError(loc.span, "set needs a location: a function applied to its arguments, "
                                         "as in f or f(a, b)")
        val = parse_scenario_term(value)
        return self.rule(A.UpdateRule(span, loc, val), Env())

    def exec_rule(self, text: Text) -> ir.Rule:
        return self.rule(parse_scenario_rule(text), Env())
