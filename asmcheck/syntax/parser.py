"""Parse AsmetaL text into the syntax tree of :mod:`asmcheck.syntax.ast`.

This is the only module that imports lark.  Parse errors become
:class:`~asmcheck.errors.AsmSyntaxError` with the file, line and column.

It is one module of about a thousand lines on purpose: the lark grammar's callbacks (the
tree builder, one method per grammar rule) and the error recovery that turns lark's
exceptions into located messages share the grammar's rule names, and splitting them would
spread one table over several files.
"""
from __future__ import annotations

import contextlib
import gc
import inspect
import os
import stat
import threading
from pathlib import Path

from lark import Lark, Token, Tree, v_args
from lark.visitors import Transformer_NonRecursive
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken, VisitError

from ..errors import AsmError, AsmSyntaxError, SOURCES, Span
from . import ast as A

_GRAMMAR_PATH = Path(__file__).with_name("asmetal.lark")
_lock = threading.Lock()
_parser: Lark | None = None

# Words the AsmetaL lexer always reserves: never a function, domain or enum name.
RESERVED = frozenset("""
asm module asyncr import export signature init default agent invariant CTLSPEC ctlspec LTLSPEC ltlspec
JUSTICE justice FAIRNESS fairness COMPASSION compassion INVAR invar over definitions function static
dynamic derived monitored controlled shared out domain anydomain basic abstract enum subsetof Prod Seq
Powerset Bag Map Rule true false undef i if then else endif switch endswitch case otherwise endcase let
endlet exists exist unique with forall skip rule macro turbo main par endpar choose do ifnone extend seq endseq
iterate enditerate local try catch while whilerec in
""".split())

_OPS = {
    "+": "plus", "-": "minus", "*": "mult", "/": "div", "^": "pwr", "mod": "mod",
    "=": "eq", "!=": "neq", "<": "lt", "<=": "le", ">": "gt", ">=": "ge",
    "and": "and", "or": "or", "xor": "xor", "implies": "implies", "iff": "iff", "not": "not",
}

# How terminals are named in "expected ..." messages.
_TERMINAL_NAMES = {
    "ENUM_ID": "an enum constant (two capitals first)",
    "DOMAIN_ID": "a domain name (one capital first)",
    "RULE_ID": "a rule name (r_...)",
    "INV_ID": "an invariant name (inv_...)",
    "CTL_ID": "a property name (ctlSpec_...)",
    "LTL_ID": "a property name (ltlSpec_...)",
    "FUNC_ID": "a function name (lower-case first)",
    "VAR_ID": "a variable ($...)",
    "ANY_NAME": "a name",
    "MODULE_PATH": "a module path",
    "INT_LIT": "a number",
    "NAT_LIT": "a natural number (e.g. 3n)",
    "REAL_LIT": "a real number",
    "CHAR_LIT": "a character literal",
    "STRING_LIT": "a string literal",
    "RELOP": "a comparison operator",
    "$END": "end of file",
}


def _cache_file():
    """Where lark keeps the parser tables between runs: a file in asmcheck's private cache
    folder (see :mod:`asmcheck.cache`), or False (no caching) when none can be trusted."""
    import hashlib
    from ..cache import private_cache_file
    digest = hashlib.sha256(_GRAMMAR_PATH.read_bytes()).hexdigest()[:16]
    path = private_cache_file(f"grammar-{digest}.lark.cache")
    return str(path) if path is not None else False


def _grammar() -> Lark:
    global _parser
    with _lock:
        if _parser is None:
            _parser = Lark(
                _GRAMMAR_PATH.read_text(encoding="utf-8"),
                parser="lalr",
                lexer="contextual",
                propagate_positions=True,
                maybe_placeholders=False,
                cache=_cache_file(),
            )
        return _parser


def decode_source(data: bytes) -> str:
    """Text of a spec file: UTF-8 when valid, otherwise Latin-1 (one character per byte)."""
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")


@contextlib.contextmanager
def gc_paused():
    """Pause Python's cyclic garbage collector while large acyclic structures are built.

    Parsing and resolving allocate hundreds of thousands of objects that stay alive; the
    collector would traverse them again and again (about 45 % of the time on large specs)."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def parse_text(text: str, path: str) -> A.Spec | None:
    """Parse one AsmetaL file; raise AsmSyntaxError on bad input."""
    SOURCES.add(path, text)
    parser = _grammar()
    with gc_paused():
        try:
            tree = parser.parse(text)
        except UnexpectedInput as exc:
            raise _convert(exc, text, path) from None
        if not tree.children:
            return None     # an empty file (or one with only comments) is accepted, as AsmetaL does
        try:
            return _Builder(path).transform(tree.children[0])
        except VisitError as exc:
            if isinstance(exc.orig_exc, AsmError):
                raise exc.orig_exc from None
            raise


_CACHE: dict[tuple, A.Spec | None] = {}

MAX_SOURCE_BYTES = 64 * 1024 * 1024
# Pseudo-file systems: their files can look regular (/proc/self/environ) but are not specs.
_SPECIAL_ROOTS = ("/proc/", "/sys/", "/dev/")


def _file_kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def read_source_bytes(path: str | Path, origin: Span | None = None) -> bytes:
    """The bytes of a regular file; anything else is an error located at ``origin``.

    ``origin`` is where the file is named (an import clause); by default the file itself
    (line 1, column 1).  FIFOs, devices, folders and the files of /proc, /sys and /dev (also
    through a symbolic link) are refused before anything is read from them; at most the
    size the file system reports is read, and never more than MAX_SOURCE_BYTES."""
    p = str(path)
    where = origin or Span(p, 1, 1)
    try:
        st = os.stat(p)
    except OSError as exc:
        raise AsmError(where, f"cannot read {p}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise AsmError(where, f"cannot read {p}: it is {_file_kind(st.st_mode)}; asmcheck reads regular files only")
    real = os.path.realpath(p)
    if real.startswith(_SPECIAL_ROOTS) or real in ("/proc", "/sys", "/dev"):
        shown = f" (it leads to {real})" if real != os.path.abspath(p) else ""
        raise AsmError(where, f"cannot read {p}: a special file of the system{shown}; asmcheck reads regular "
                              f"files only")
    if st.st_size > MAX_SOURCE_BYTES:
        raise AsmError(where, f"cannot read {p}: {st.st_size} bytes, more than the {MAX_SOURCE_BYTES} a spec "
                              f"file may have")
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(p, flags)
    except OSError as exc:
        raise AsmError(where, f"cannot read {p}: {exc.strerror or exc}") from None
    try:
        st2 = os.fstat(fd)
        if not stat.S_ISREG(st2.st_mode) or (st2.st_dev, st2.st_ino) != (st.st_dev, st.st_ino):
            raise AsmError(where, f"cannot read {p}: the file changed while it was opened")
        size = min(st2.st_size, MAX_SOURCE_BYTES)
        chunks, got = [], 0
        while got < size:
            chunk = os.read(fd, min(size - got, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            got += len(chunk)
        return b"".join(chunks)
    except OSError as exc:
        raise AsmError(where, f"cannot read {p}: {exc.strerror or exc}") from None
    finally:
        os.close(fd)


def read_source_file(path: str | Path, origin: Span | None = None) -> str:
    """The text of a regular file (see :func:`read_source_bytes` and :func:`decode_source`)."""
    return decode_source(read_source_bytes(path, origin))


def parse_file(path: str | Path, origin: Span | None = None) -> A.Spec | None:
    """Parse a file (cached by path, size and modification time: imports are read once).

    Only regular files are read; ``origin`` locates the error for any other (an import)."""
    p = str(path)
    try:
        st = os.stat(p)
    except OSError as exc:
        raise AsmError(origin or Span(p, 1, 1), f"cannot read {p}: {exc.strerror or exc}") from None
    key = (p, st.st_mtime_ns, st.st_size, st.st_ino)
    if key in _CACHE:
        return _CACHE[key]
    data = read_source_bytes(p, origin)
    spec = parse_text(decode_source(data), p)
    if len(_CACHE) > 2000:
        _CACHE.clear()
    _CACHE[key] = spec
    return spec


def _describe(tok: Token) -> str:
    if tok.type == "$END":
        return "end of file"
    val = str(tok)
    if len(val) > 30:
        val = val[:27] + "..."
    return repr(val)


def _expected(names) -> str:
    shown = []
    for n in sorted(set(names)):
        if n in _TERMINAL_NAMES:
            shown.append(_TERMINAL_NAMES[n])
        else:
            shown.append(repr(_terminal_text(n)))
    shown = sorted(set(shown))
    if len(shown) > 8:
        shown = shown[:8] + ["..."]
    return ", ".join(shown)


_TERMINAL_TEXT: dict[str, str] = {}


def _terminal_text(name: str) -> str:
    if not _TERMINAL_TEXT:
        for t in _grammar().terminals:
            pat = t.pattern
            if pat.type == "str":
                _TERMINAL_TEXT[t.name] = pat.value
            else:
                _TERMINAL_TEXT[t.name] = t.name.strip("_").lower()
    return _TERMINAL_TEXT.get(name, name.strip("_").lower())


def _convert(exc: UnexpectedInput, text: str, path: str) -> AsmSyntaxError:
    line = getattr(exc, "line", None) or 1
    col = getattr(exc, "column", None) or 1
    if isinstance(exc, UnexpectedCharacters):
        ch = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else ""
        if ch in "\"'":
            msg = "unterminated or malformed " + ("string" if ch == '"' else "character") + " literal"
        else:
            msg = f"unexpected character {ch!r}"
            if exc.allowed:
                msg += f"; expected {_expected(exc.allowed)}"
        return AsmSyntaxError(Span(path, line, col, line, col + 1), msg)
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        if tok.type == "$END":
            line, col = _end_of_text(text)
            return AsmSyntaxError(Span(path, line, col), f"unexpected end of file; expected {_expected(exc.expected)}")
        msg = f"unexpected {_describe(tok)}; expected {_expected(exc.expected)}"
        hint = _hint(tok, exc.expected)
        if hint:
            msg += f" ({hint})"
        end = (tok.end_line or line, tok.end_column or col + 1)
        return AsmSyntaxError(Span(path, tok.line or line, tok.column or col, end[0], end[1]), msg)
    if isinstance(exc, UnexpectedEOF):
        line, col = _end_of_text(text)
        return AsmSyntaxError(Span(path, line, col), "unexpected end of file")
    return AsmSyntaxError(Span(path, line, col), str(exc).split("\n")[0])


def _end_of_text(text: str) -> tuple[int, int]:
    """Line and column just after the last character that is not white space."""
    lines = text.rstrip().split("\n")
    return len(lines), len(lines[-1].rstrip("\r")) + 1


# the parts of a body (after ``definitions:``), in the order they must come
_BODY_PARTS = (
    ("domain definitions", {"_DOMAIN"}),
    ("function definitions", {"_FUNCTION"}),
    ("rule declarations", {"_RULE", "MACRO", "TURBO"}),
    ("INVAR constraints", {"_INVAR", "_INVAR_L"}),
    ("JUSTICE and COMPASSION constraints", {"_JUSTICE", "_JUSTICE_L", "_COMPASSION", "_COMPASSION_L"}),
    ("the properties (invariant, CTLSPEC, LTLSPEC)", {"_INVARIANT", "_CTLSPEC", "_CTLSPEC_L", "_LTLSPEC", "_LTLSPEC_L"}),
    ("the main rule", {"_MAIN"}),
    ("the initial states", {"_INIT", "DEFAULT"}),
)


_KEYWORD_KINDS = {"domain": "_DOMAIN", "function": "_FUNCTION", "rule": "_RULE", "macro": "MACRO", "turbo": "TURBO",
                  "INVAR": "_INVAR", "invar": "_INVAR_L", "JUSTICE": "_JUSTICE", "justice": "_JUSTICE_L",
                  "COMPASSION": "_COMPASSION", "compassion": "_COMPASSION_L", "invariant": "_INVARIANT",
                  "CTLSPEC": "_CTLSPEC", "ctlspec": "_CTLSPEC_L", "LTLSPEC": "_LTLSPEC", "ltlspec": "_LTLSPEC_L",
                  "main": "_MAIN"}


def _order_hint(tok: Token, exp: set) -> str | None:
    """A part of a body met after a later part (a JUSTICE after a CTLSPEC): the order to keep."""
    # where the keyword is not expected, the lexer may take it for a name ('function' as FUNC_ID)
    kind = _KEYWORD_KINDS.get(str(tok), tok.type)
    mine = next((i for i, (_, kinds) in enumerate(_BODY_PARTS) if kind in kinds), None)
    if mine is None or _BODY_PARTS[mine][1] & exp:
        return None
    later = [i for i, (_, kinds) in enumerate(_BODY_PARTS) if kinds & exp and i > mine]
    if not later:
        return None
    first = min(later)
    if first == len(_BODY_PARTS) - 1 and mine < first - 1:
        first -= 1                    # past the main rule, which comes before the initial states
    return f"{_BODY_PARTS[mine][0]} come before {_BODY_PARTS[first][0]}"


def _hint(tok: Token, expected) -> str | None:
    val = str(tok)
    exp = set(expected)
    order = _order_hint(tok, exp)
    if order:
        return order
    if tok.type == "DOMAIN_ID" and "ENUM_ID" in exp and "_" in val[:2]:
        return f"{val!r} lexes as a domain name: an enum constant needs two capitals first"
    if tok.type == "DOMAIN_ID" and "ENUM_ID" in exp:
        return f"{val!r} is a domain name: an enum constant has two capitals first and no lower-case letters"
    if tok.type in ("FUNC_ID", "DOMAIN_ID") and "RULE_ID" in exp and "FUNC_ID" not in exp:
        return "rule names start with 'r_'"
    if tok.type == "FUNC_ID" and "VAR_ID" in exp and "FUNC_ID" not in exp:
        return "variables start with '$'"
    return None


def _span(path: str, meta) -> Span:
    if getattr(meta, "empty", False) or not hasattr(meta, "line"):
        return Span(path, 0, 0)
    return Span(path, meta.line, meta.column, meta.end_line, meta.end_column)


def _tspan(path: str, tok: Token) -> Span:
    return Span(path, tok.line, tok.column, tok.end_line or tok.line, tok.end_column or tok.column + len(tok))


def _unescape(body: str) -> str:
    out = []
    i = 0
    simple = {"n": "\n", "t": "\t", "b": "\b", "r": "\r", "f": "\f", "\\": "\\", "'": "'", '"': '"'}
    while i < len(body):
        c = body[i]
        if c == "\\" and i + 1 < len(body):
            n = body[i + 1]
            if n in simple:
                out.append(simple[n])
                i += 2
                continue
            j = i + 1
            while j < len(body) and j < i + 4 and body[j] in "01234567":
                j += 1
            if j > i + 1:
                out.append(chr(int(body[i + 1:j], 8)))
                i = j
                continue
        out.append(c)
        i += 1
    return "".join(out)


def _noeq(ch):
    return [c for c in ch if not (isinstance(c, Token) and c.type == "EQ")]


_KIND_TOKENS = {"STATIC": "static", "DERIVED": "derived", "CONTROLLED": "controlled", "MONITORED": "monitored",
                "SHARED": "shared", "OUT": "out", "LOCAL": "local"}


@v_args(meta=True)
class _Builder(Transformer_NonRecursive):
    """lark parse tree -> :mod:`asmcheck.syntax.ast` (iterative: deep nesting does not exhaust the stack)."""

    def __init__(self, path: str):
        super().__init__(visit_tokens=False)
        self.path = path

    _methods: dict | None = None

    @classmethod
    def _method_table(cls) -> dict:
        """Rule name -> the plain function (meta, children) of this class (built once).

        Calls it directly instead of through lark's per-call v_args wrappers."""
        if cls._methods is None:
            table = {}
            for name in dir(cls):
                if name.startswith("_"):
                    continue
                attr = inspect.getattr_static(cls, name)
                base = getattr(attr, "base_func", None)
                if base is not None and callable(base):
                    table[name] = base
            cls._methods = table
        return cls._methods

    def _call_userfunc(self, tree, new_children=None):
        children = new_children if new_children is not None else tree.children
        f = self._method_table().get(tree.data)
        if f is None:
            return super()._call_userfunc(tree, new_children)
        try:
            return f(self, tree.meta, children)
        except Exception as exc:
            raise VisitError(tree.data, tree, exc) from exc

    # -- helpers
    def sp(self, meta) -> Span:
        return _span(self.path, meta)

    def tsp(self, tok: Token) -> Span:
        return _tspan(self.path, tok)

    def name(self, tok: Token) -> str:
        val = str(tok)
        if tok.type in ("FUNC_ID", "DOMAIN_ID", "ENUM_ID", "ANY_NAME") and val in RESERVED:
            raise AsmSyntaxError(self.tsp(tok), f"{val!r} is a reserved word and cannot be used as a name")
        return val

    @staticmethod
    def toks(children, *types):
        return [c for c in children if isinstance(c, Token) and c.type in types]

    # -- spec
    def start(self, meta, ch):
        return ch[0] if ch else None

    def spec(self, meta, ch):
        asyncr = False
        i = 0
        if isinstance(ch[i], Token) and ch[i].type == "ASYNCR":
            asyncr = True
            i += 1
        is_module = ch[i].type == "MODULE"
        i += 1
        name, name_span = ch[i]
        i += 1
        header = ch[i]
        body = ch[i + 1]
        main = None
        inits: list[A.InitBlock] = []
        for extra in ch[i + 2:]:
            if isinstance(extra, A.RuleDecl):
                main = extra
            else:
                inits = extra
        imports, export, export_all, domains, functions = header
        domain_defs, function_defs, rules, props = body
        if main is not None:
            rules = rules + [main]
        return A.Spec(self.sp(meta), name, is_module, asyncr, imports, export, export_all, domains, functions,
                      domain_defs, function_defs, rules, props, main, inits, name_span)

    def spec_name(self, meta, ch):
        return (str(ch[0]), self.tsp(ch[0]))

    def header(self, meta, ch):
        imports = [c for c in ch if isinstance(c, A.Import)]
        export, export_all = None, False
        domains: list = []
        functions: list = []
        for c in ch:
            if isinstance(c, tuple) and c and c[0] == "export":
                export, export_all = c[1], c[2]
            elif isinstance(c, tuple) and c and c[0] == "signature":
                domains, functions = c[1], c[2]
        return imports, export, export_all, domains, functions

    def import_clause(self, meta, ch):
        path = str(ch[0])
        if path.startswith('"') and path.endswith('"'):
            path = path[1:-1]
        names = ch[1] if len(ch) > 1 else None
        return A.Import(self.sp(meta), path, names)

    def import_list(self, meta, ch):
        return [(str(t), self.tsp(t)) for t in ch]

    def export_clause(self, meta, ch):
        if ch and isinstance(ch[0], Token) and ch[0].type == "STAR":
            return ("export", None, True)
        return ("export", [(str(t), self.tsp(t)) for t in ch], False)

    def signature(self, meta, ch):
        domains = [c for c in ch if isinstance(c, A.DomainDecl)]
        functions = [c for c in ch if isinstance(c, A.FunctionDecl)]
        return ("signature", domains, functions)

    # -- domains
    def subset_domain(self, meta, ch):
        dyn = bool(self.toks(ch, "DYNAMIC"))
        name_tok = self.toks(ch, "DOMAIN_ID")[0]
        return A.DomainDecl(self.tsp(name_tok), self.name(name_tok), "subset", dyn, base=ch[-1])

    def any_domain(self, meta, ch):
        return A.DomainDecl(self.tsp(ch[0]), self.name(ch[0]), "any")

    def basic_domain(self, meta, ch):
        return A.DomainDecl(self.tsp(ch[0]), str(ch[0]), "basic")

    def abstract_domain(self, meta, ch):
        dyn = bool(self.toks(ch, "DYNAMIC"))
        tok = self.toks(ch, "DOMAIN_ID")[0]
        return A.DomainDecl(self.tsp(tok), self.name(tok), "abstract", dyn)

    def enum_domain(self, meta, ch):
        ch = _noeq(ch)
        tok = ch[0]
        elements = list(ch[1:])
        return A.DomainDecl(self.tsp(tok), self.name(tok), "enum", elements=elements)

    def enum_element(self, meta, ch):
        return (self.name(ch[0]), self.tsp(ch[0]))

    def struct_domain_decl(self, meta, ch):
        t = ch[0]
        return A.DomainDecl(self.sp(meta), str(t), "structured", base=t)

    # -- functions
    def func_kind(self, meta, ch):
        dyn = any(t.type == "DYNAMIC" for t in ch)
        kind = next(_KIND_TOKENS[t.type] for t in ch if t.type in _KIND_TOKENS)
        return (kind, dyn)

    def function_decl(self, meta, ch):
        kind, dyn = ch[0]
        name_tok = ch[1]
        types = ch[2:]
        domain = types[0] if len(types) == 2 else None
        return A.FunctionDecl(self.tsp(name_tok), self.name(name_tok), kind, dyn, domain, types[-1])

    # -- types
    def named_type(self, meta, ch):
        tok = ch[0]
        return A.TypeExpr(self.tsp(tok), self.name(tok))

    def struct_type(self, meta, ch):
        kw = ch[0]
        name = {"PROD": "Prod", "SEQ_T": "Seq", "POWERSET": "Powerset", "BAG_T": "Bag", "MAP_T": "Map",
                "RULE_T": "Rule"}[kw.type]
        return A.TypeExpr(self.sp(meta), name, list(ch[1:]), structured=True)

    # -- body
    def body(self, meta, ch):
        domain_defs = [c for c in ch if isinstance(c, A.DomainDef)]
        function_defs = [c for c in ch if isinstance(c, A.FunctionDef)]
        rules = [c for c in ch if isinstance(c, A.RuleDecl)]
        props = [c for c in ch if isinstance(c, A.Property)]
        return domain_defs, function_defs, rules, props

    def domain_def(self, meta, ch):
        ch = _noeq(ch)
        return A.DomainDef(self.tsp(ch[0]), self.name(ch[0]), ch[1])

    def function_def(self, meta, ch):
        ch = _noeq(ch)
        name_tok = ch[0]
        params = ch[1] if len(ch) == 3 else []
        return A.FunctionDef(self.sp(meta), self.name(name_tok), params, ch[-1], self.tsp(name_tok))

    def formal_params(self, meta, ch):
        return list(ch)

    def formal(self, meta, ch):
        return A.Formal(self.tsp(ch[0]), str(ch[0]), ch[1])

    def _rule_decl(self, meta, ch, kind):
        ch = _noeq(ch)
        toks = [c for c in ch if isinstance(c, Token)]
        name_tok = next(t for t in toks if t.type == "RULE_ID")
        params: list = []
        returns = None
        rest = [c for c in ch if not isinstance(c, Token)]
        if rest and isinstance(rest[0], list):
            params = rest.pop(0)
        if len(rest) == 2:
            returns = rest.pop(0)
        return A.RuleDecl(self.tsp(name_tok), str(name_tok), params, rest[0], kind, returns)

    def macro_decl(self, meta, ch):
        return self._rule_decl(meta, ch, "macro")

    def turbo_decl(self, meta, ch):
        return self._rule_decl(meta, ch, "turbo")

    def main_decl(self, meta, ch):
        return self._rule_decl(meta, ch, "macro")

    def invar_constraint(self, meta, ch):
        return A.Property(self.sp(meta), "invar", None, ch[0])

    def justice(self, meta, ch):
        return A.Property(self.sp(meta), "justice", None, ch[0])

    def compassion(self, meta, ch):
        return A.Property(self.sp(meta), "compassion", None, ch[0], ch[1])

    def invariant(self, meta, ch):
        name = None
        if isinstance(ch[0], Token) and ch[0].type == "INV_ID":
            name = str(ch[0])
            ch = ch[1:]
        over = [c for c in ch[:-1]]
        return A.Property(self.sp(meta), "invariant", name, ch[-1], over=over)

    def over_item(self, meta, ch):
        tok = ch[0]
        t = ch[1] if len(ch) > 1 else None
        # "f()" leaves no child for the parentheses; look at the text span
        has_parens = t is not None or (meta.end_column - meta.column) > len(tok)
        return A.OverItem(self.tsp(tok), str(tok), t, has_parens)

    def ctlspec(self, meta, ch):
        name = str(ch[0]) if len(ch) == 2 else None
        return A.Property(self.sp(meta), "ctl", name, ch[-1])

    def ltlspec(self, meta, ch):
        name = str(ch[0]) if len(ch) == 2 else None
        return A.Property(self.sp(meta), "ltl", name, ch[-1])

    # -- init
    def init_section(self, meta, ch):
        blocks = []
        default_next = False
        for c in ch:
            if isinstance(c, Token) and c.type == "DEFAULT":
                default_next = True
                continue
            if default_next:
                c.default = True
                default_next = False
            blocks.append(c)
        return blocks

    def init_block(self, meta, ch):
        ch = _noeq(ch)
        name = str(ch[0])
        doms = [c for c in ch if isinstance(c, A.DomainDef)]
        funcs = [c for c in ch if isinstance(c, A.FunctionDef)]
        agents = [c for c in ch if isinstance(c, A.AgentInit)]
        return A.InitBlock(self.tsp(ch[0]), name, False, doms, funcs, agents)

    def domain_init(self, meta, ch):
        return self.domain_def(meta, ch)

    def function_init(self, meta, ch):
        return self.function_def(meta, ch)

    def agent_init(self, meta, ch):
        ch = _noeq(ch)
        return A.AgentInit(self.sp(meta), self.name(ch[0]), ch[1])

    # -- rules
    def skip_rule(self, meta, ch):
        return A.SkipRule(self.sp(meta))

    def update_rule(self, meta, ch):
        return A.UpdateRule(self.sp(meta), ch[0], ch[1])

    def var_location(self, meta, ch):
        return A.VarRef(self.tsp(ch[0]), str(ch[0]))

    def par_rule(self, meta, ch):
        return A.BlockRule(self.sp(meta), "par", list(ch))

    def seq_rule(self, meta, ch):
        return A.BlockRule(self.sp(meta), "seq", list(ch))

    def if_rule(self, meta, ch):
        return A.IfRule(self.sp(meta), ch[0], ch[1], ch[2] if len(ch) > 2 else None)

    def switch_rule(self, meta, ch):
        cases = [c for c in ch[1:] if isinstance(c, tuple)]
        other = ch[-1] if not isinstance(ch[-1], tuple) and len(ch) > 1 else None
        return A.SwitchRule(self.sp(meta), ch[0], cases, other)

    def rule_case(self, meta, ch):
        return (ch[0], ch[1])

    def term_case(self, meta, ch):
        return (ch[0], ch[1])

    def let_binding(self, meta, ch):
        ch = _noeq(ch)
        return (str(ch[0]), self.tsp(ch[0]), ch[1])

    def binding(self, meta, ch):
        return A.Binding(self.tsp(ch[0]), str(ch[0]), ch[1])

    def let_rule(self, meta, ch):
        return A.LetRule(self.sp(meta), list(ch[:-1]), ch[-1])

    def _guarded(self, ch):
        bindings = [c for c in ch if isinstance(c, A.Binding)]
        rest = [c for c in ch if not isinstance(c, A.Binding)]
        return bindings, rest

    def choose_rule(self, meta, ch):
        bindings, rest = self._guarded(ch)
        # rest: [guard?] body [ifnone?]; the guard is a term, the others rules
        guard = rest.pop(0) if rest and isinstance(rest[0], A.Term) else None
        body = rest[0]
        ifnone = rest[1] if len(rest) > 1 else None
        return A.ChooseRule(self.sp(meta), bindings, guard, body, ifnone)

    def forall_rule(self, meta, ch):
        bindings, rest = self._guarded(ch)
        guard = rest.pop(0) if len(rest) == 2 else None
        return A.ForallRule(self.sp(meta), bindings, guard, rest[0])

    def extend_rule(self, meta, ch):
        dom = ch[0]
        vars_ = [(str(t), self.tsp(t)) for t in ch[1:-1]]
        return A.ExtendRule(self.sp(meta), self.name(dom), self.tsp(dom), vars_, ch[-1])

    def macro_call(self, meta, ch):
        return A.CallRule(self.sp(meta), str(ch[0]), list(ch[1:]), turbo=False)

    def turbo_call(self, meta, ch):
        return A.CallRule(self.sp(meta), str(ch[0]), list(ch[1:]), turbo=True)

    def turbo_return_rule(self, meta, ch):
        return A.TurboReturnRule(self.sp(meta), ch[0], ch[1])

    def term_call_rule(self, meta, ch):
        head = ch[0]
        if isinstance(head, Token):
            head = A.VarRef(self.tsp(head), str(head))
        return A.TermCallRule(self.sp(meta), head, list(ch[1:]))

    def iterate_rule(self, meta, ch):
        return A.LoopRule(self.sp(meta), "iterate", None, ch[0])

    def while_rule(self, meta, ch):
        return A.LoopRule(self.sp(meta), "while", ch[0], ch[1])

    def whilerec_rule(self, meta, ch):
        return A.LoopRule(self.sp(meta), "whilerec", ch[0], ch[1])

    def local_decl(self, meta, ch):
        toks = [c for c in ch if isinstance(c, Token)]
        dyn = any(t.type == "DYNAMIC" for t in toks)
        name_tok = [t for t in toks if t.type not in ("DYNAMIC", "LOCAL")][0]
        rest = [c for c in ch if not isinstance(c, Token)]
        types = [c for c in rest if isinstance(c, A.TypeExpr)]
        init = rest[-1]
        decl = A.FunctionDecl(self.tsp(name_tok), self.name(name_tok), "local", dyn,
                              types[0] if len(types) == 2 else None, types[-1])
        return (decl, init)

    def local_rule(self, meta, ch):
        (decl, init), body = ch
        return A.LocalRule(self.sp(meta), decl, init, body)

    # -- terms
    def binop(self, meta, ch):
        left, op, right = ch
        return A.Apply(self.sp(meta), _OPS[str(op)], [left, right], op=str(op), name_span=self.tsp(op))

    def unop(self, meta, ch):
        op, arg = ch
        return A.Apply(self.sp(meta), _OPS[str(op)], [arg], op=str(op), name_span=self.tsp(op))

    def var_term(self, meta, ch):
        return A.VarRef(self.sp(meta), str(ch[0]))

    def func_term(self, meta, ch):
        agent = None
        toks = [c for c in ch if isinstance(c, Token)]
        if len(toks) == 2:
            agent = str(toks[0])
        name_tok = toks[-1]
        args = ch[-1] if not isinstance(ch[-1], Token) else None
        return A.Apply(self.sp(meta), self.name(name_tok), args, agent=agent, name_span=self.tsp(name_tok))

    def op_func_term(self, meta, ch):
        return A.Apply(self.sp(meta), str(ch[0]), ch[1], name_span=self.tsp(ch[0]))

    def args(self, meta, ch):
        return list(ch)

    def domain_term(self, meta, ch):
        t = ch[0]
        if isinstance(t, Token):
            t = A.TypeExpr(self.tsp(t), self.name(t))
        return A.DomainRef(self.sp(meta), t)

    def paren_term(self, meta, ch):
        if len(ch) == 1:
            return ch[0]
        return A.TupleTerm(self.sp(meta), list(ch))

    def _quant(self, meta, ch, kind):
        bindings, rest = self._guarded(ch)
        return A.QuantTerm(self.sp(meta), kind, bindings, rest[0] if rest else None)

    def forall_term(self, meta, ch):
        return self._quant(meta, ch, "forall")

    def exists_term(self, meta, ch):
        return self._quant(meta, ch, "exists")

    def exists_unique_term(self, meta, ch):
        return self._quant(meta, [c for c in ch if not isinstance(c, Token)], "exists_unique")

    def if_term(self, meta, ch):
        return A.CondTerm(self.sp(meta), ch[0], ch[1], ch[2] if len(ch) > 2 else None)

    def switch_term(self, meta, ch):
        cases = [c for c in ch[1:] if isinstance(c, tuple)]
        other = ch[-1] if not isinstance(ch[-1], tuple) and len(ch) > 1 else None
        return A.SwitchTerm(self.sp(meta), ch[0], cases, other)

    def let_term(self, meta, ch):
        return A.LetTerm(self.sp(meta), list(ch[:-1]), ch[-1])

    def empty_seq(self, meta, ch):
        return A.CollectionTerm(self.sp(meta), "seq", [])

    def seq_term(self, meta, ch):
        return A.CollectionTerm(self.sp(meta), "seq", list(ch))

    def seq_range(self, meta, ch):
        return A.RangeTerm(self.sp(meta), "seq", ch[0], ch[1], ch[2] if len(ch) > 2 else None)

    def _compr(self, meta, ch, kind):
        bindings, rest = self._guarded(ch)
        if kind == "map":
            guard = rest[0] if len(rest) == 3 else None
            return A.ComprTerm(self.sp(meta), kind, bindings, guard, rest[-2], rest[-1])
        guard = rest[0] if len(rest) == 2 else None
        return A.ComprTerm(self.sp(meta), kind, bindings, guard, rest[-1])

    def seq_compr(self, meta, ch):
        return self._compr(meta, ch, "seq")

    def empty_set(self, meta, ch):
        return A.CollectionTerm(self.sp(meta), "set", [])

    def set_term(self, meta, ch):
        return A.CollectionTerm(self.sp(meta), "set", list(ch))

    def set_range(self, meta, ch):
        return A.RangeTerm(self.sp(meta), "set", ch[0], ch[1], ch[2] if len(ch) > 2 else None)

    def set_compr(self, meta, ch):
        return self._compr(meta, ch, "set")

    def map_compr(self, meta, ch):
        return self._compr(meta, ch, "map")

    def empty_map(self, meta, ch):
        return A.MapTerm(self.sp(meta), [])

    def map_term(self, meta, ch):
        return A.MapTerm(self.sp(meta), list(ch))

    def map_pair(self, meta, ch):
        return (ch[0], ch[1])

    def empty_bag(self, meta, ch):
        ch = [c for c in ch if not (isinstance(c, Token) and c.type in ('LT', 'GT'))]
        return A.CollectionTerm(self.sp(meta), "bag", [])

    def bag_term(self, meta, ch):
        ch = [c for c in ch if not (isinstance(c, Token) and c.type in ('LT', 'GT'))]
        return A.CollectionTerm(self.sp(meta), "bag", list(ch))

    def bag_range(self, meta, ch):
        ch = [c for c in ch if not (isinstance(c, Token) and c.type in ('LT', 'GT'))]
        return A.RangeTerm(self.sp(meta), "bag", ch[0], ch[1], ch[2] if len(ch) > 2 else None)

    def bag_compr(self, meta, ch):
        ch = [c for c in ch if not (isinstance(c, Token) and c.type in ('LT', 'GT'))]
        return self._compr(meta, ch, "bag")

    def rule_as_term(self, meta, ch):
        return A.RuleAsTerm(self.sp(meta), str(ch[0]), list(ch[1:]))

    # constants
    def int_lit(self, meta, ch):
        return A.Const(self.sp(meta), "int", int(ch[0]), str(ch[0]))

    def nat_lit(self, meta, ch):
        return A.Const(self.sp(meta), "nat", int(str(ch[0])[:-1]), str(ch[0]))

    def real_lit(self, meta, ch):
        return A.Const(self.sp(meta), "real", float(ch[0]), str(ch[0]))

    def char_lit(self, meta, ch):
        body = _unescape(str(ch[0])[1:-1])
        if len(body) != 1:
            raise AsmSyntaxError(self.sp(meta), f"a character literal holds exactly one character, not {str(ch[0])}")
        return A.Const(self.sp(meta), "char", body, str(ch[0]))

    def string_lit(self, meta, ch):
        # AsmetaL keeps the text between the quotes as written (no escape processing)
        return A.Const(self.sp(meta), "string", str(ch[0])[1:-1], str(ch[0]))

    def true_lit(self, meta, ch):
        return A.Const(self.sp(meta), "bool", True, "true")

    def false_lit(self, meta, ch):
        return A.Const(self.sp(meta), "bool", False, "false")

    def undef_lit(self, meta, ch):
        return A.Const(self.sp(meta), "undef", None, "undef")

    def enum_lit(self, meta, ch):
        return A.EnumLit(self.sp(meta), self.name(ch[0]))


def parse_term(text: str, path: str = "<term>", origin: tuple[int, int] = (1, 1)) -> A.Term:
    """Parse a lone AsmetaL term (property files, scenarios).

    ``origin`` is the line and column where ``text`` starts in ``path``; positions in the
    result (and in errors) refer to that file."""
    head = "asm T\nsignature:\ndefinitions:\nfunction xx = "
    wrapped = head + text + "\n"
    oline, ocol = origin
    try:
        tree = _grammar().parse(wrapped)
    except UnexpectedInput as exc:
        err = _convert(exc, wrapped, path)
        sp = err.span
        line, col = _unwrap(sp.line, sp.col, oline, ocol)
        raise AsmSyntaxError(Span(path, line, col), err.message) from None
    try:
        spec = _Builder(path).transform(tree.children[0])
    except VisitError as exc:
        if isinstance(exc.orig_exc, AsmError):
            e = exc.orig_exc
            line, col = _unwrap(e.span.line, e.span.col, oline, ocol)
            raise AsmSyntaxError(Span(path, line, col), e.message) from None
        raise
    if not spec.function_defs:
        raise AsmSyntaxError(Span(path, oline, ocol), "expected a term")
    term = spec.function_defs[0].body
    return _shift(term, path, oline, ocol)


_HEAD_LINES = 3
_HEAD_COL = len("function xx = ")


def _unwrap(line: int, col: int, oline: int, ocol: int) -> tuple[int, int]:
    if line <= _HEAD_LINES:
        return oline, ocol
    if line == _HEAD_LINES + 1:
        return oline, max(col - _HEAD_COL, 1) + ocol - 1
    return oline + line - _HEAD_LINES - 1, col


def _shift(node, path, oline=1, ocol=1):
    """Move the spans of a wrapped term back to where the term is written."""

    def fix(sp: Span) -> Span:
        if sp is None or sp.line == 0:
            return sp
        l1, c1 = _unwrap(sp.line, sp.col, oline, ocol)
        l2, c2 = _unwrap(sp.end_line or sp.line, sp.end_col or sp.col, oline, ocol)
        return Span(path, l1, c1, l2, c2)

    seen = set()
    todo = [node]            # iterative: a deeply nested term does not exhaust the stack
    while todo:
        n = todo.pop()
        if id(n) in seen:
            continue
        seen.add(id(n))
        if isinstance(n, A.Node):
            for f in n.__dataclass_fields__:
                v = getattr(n, f)
                if isinstance(v, Span):
                    setattr(n, f, fix(v))
                elif isinstance(v, list):
                    for i, x in enumerate(v):
                        if isinstance(x, tuple) and len(x) == 3 and isinstance(x[1], Span):
                            v[i] = (x[0], fix(x[1]), x[2])
                            todo.append(x[2])
                        else:
                            todo.append(x)
                else:
                    todo.append(v)
        elif isinstance(n, (list, tuple)):
            for x in n:
                if isinstance(x, (A.Node, list, tuple)):
                    todo.append(x)
    return node


__all__ = ["parse_file", "parse_text", "parse_term", "decode_source", "read_source_bytes", "read_source_file",
           "RESERVED", "Tree"]
