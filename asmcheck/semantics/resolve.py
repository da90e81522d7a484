"""From syntax trees to the typed IR: imports, name resolution and type checks.

``load_spec(path)`` reads a spec and everything it imports, resolves every
name (respecting export and import lists), checks arities and domains the way
AsmetaL's own parser does, and returns an :class:`asmcheck.semantics.ir.Spec`.
Every error is an :class:`~asmcheck.errors.AsmError` with a source position.

It is one module of about 1,050 lines: loading (:class:`Loader`), declaring
(:class:`Declarer`) and resolving (:class:`Resolver`) share the module tables and the
scopes of one spec and its imports, and the resolver's one method per syntax form is a
single recursive walk.
"""
from __future__ import annotations

import os
import sys
import threading
from collections import ChainMap
from importlib import resources
from pathlib import Path

from ..errors import AsmError, AsmSyntaxError, AsmTypeError, NO_SPAN, Span
from ..syntax import ast as A
from ..syntax.parser import gc_paused, parse_file, parse_text
from . import ir
from . import stdlib
from . import types as T
from .values import RuleValue, abstract_value, enum_value, CharV

LIBRARIES = ("StandardLibrary", "CTLLibrary", "LTLLibrary", "TimeLibrary")
# Library files that are never read as specs (TimeLibrary is an ordinary module when checked alone).
REFUSED = ("StandardLibrary", "CTLLibrary", "LTLLibrary")

# Folders searched, in order, for an import that is not found relative to the importing file
# (``asmcheck -I DIR`` and the ASMCHECK_PATH environment variable set it; see import_path()).
_SEARCH_PATH: list[str] = []


def set_import_path(dirs) -> None:
    """Set the folders searched for imports not found beside the importing file."""
    _SEARCH_PATH[:] = [str(d) for d in dirs]


def _asm_file(p: Path) -> Path:
    """An import's path as a file name: with ``.asm`` added unless it is there."""
    return p if str(p).endswith(".asm") else Path(str(p) + ".asm")


def import_path() -> list[str]:
    """The folders searched for imports: those set by set_import_path, then ASMCHECK_PATH's."""
    env = [d for d in os.environ.get("ASMCHECK_PATH", "").split(os.pathsep) if d]
    return list(_SEARCH_PATH) + env


class Table:
    """Names a module declares or sees: domains, functions, rules, enum constants."""

    def __init__(self) -> None:
        self.domains: dict[str, list] = {}
        self.functions: dict[str, list] = {}
        self.rules: dict[str, list] = {}
        self.enums: dict[str, list] = {}

    def add(self, kind: str, name: str, obj) -> None:
        lst = getattr(self, kind).setdefault(name, [])
        if not any(o is obj for o in lst):
            lst.append(obj)

    def merge(self, other: "Table", names: set[str] | None = None) -> None:
        if names is not None:
            names = set(names)
            for n in list(names):
                for d in other.domains.get(n, []):
                    if isinstance(d, T.Domain) and d.kind == "enum":
                        names.update(v.name for v in d.elements)
        for kind in ("domains", "functions", "rules", "enums"):
            for name, objs in getattr(other, kind).items():
                if names is not None and name not in names:
                    continue
                for o in objs:
                    self.add(kind, name, o)

    def has(self, name: str) -> bool:
        return any(name in getattr(self, k) for k in ("domains", "functions", "rules", "enums"))


class Module:
    def __init__(self, name: str, path: str, syntax: A.Spec | None, library: str | None = None):
        self.name = name
        self.path = path
        self.syntax = syntax
        self.library = library
        self.own = Table()
        self.scope = Table()
        self.exports = Table()
        self.imports: list[tuple["Module", list | None, Span]] = []
        self.functions: list[ir.Function] = []
        self.domains: list[T.Type] = []
        self.rules: list[ir.RuleDecl] = []
        self.local_functions: list[ir.Function] = []   # declared by `local` rules, numbered after the table
        self.resolved = False


# ----------------------------------------------------------------- built-in libraries
def _standard_library() -> Module:
    m = Module("StandardLibrary", "<StandardLibrary>", None, library="StandardLibrary")
    for d in list(T.BASICS.values()) + [T.AGENT, T.RESERVE] + list(T.GENERICS.values()):
        m.own.add("domains", d.name, d)
    for name, sigs in stdlib.STANDARD.items():
        for s in sigs:
            m.own.add("functions", name, s)
    self_f = ir.Function("self", "controlled", [], T.AGENT, "StandardLibrary")
    result_f = ir.Function("result", "controlled", [], T.GENERICS["Any"], "StandardLibrary")
    m.own.add("functions", "self", self_f)
    m.own.add("functions", "result", result_f)
    m.functions = [self_f, result_f]
    m.exports = m.own
    m.scope = m.own
    m.resolved = True
    return m


def _temporal_library(name: str, table: dict) -> Module:
    m = Module(name, f"<{name}>", None, library=name)
    for fname, sigs in table.items():
        for s in sigs:
            m.own.add("functions", fname, s)
    m.exports = m.own
    m.scope = m.own
    m.resolved = True
    return m


def _library_hint(name: str) -> str:
    """The library a name applied to arguments but unknown to a spec comes from, when it is one
    of them (the spec may just lack the import; a bare name such as ``y`` is rather a function
    the spec forgot, not LTL's operator)."""
    libs = [lib for lib, table in (("StandardLibrary", stdlib.STANDARD), ("CTLLibrary", stdlib.CTL),
                                   ("LTLLibrary", stdlib.LTL)) if name in table]
    if not libs:
        return ""
    return f" ({name} is defined in {' and '.join(libs)}: import {libs[0]})"


class Loader:
    """Reads a spec and its imports, once each, detecting cycles."""

    def __init__(self) -> None:
        self.modules: dict[str, Module] = {}
        self.order: list[Module] = []
        self.std = _standard_library()
        self.ctl = _temporal_library("CTLLibrary", stdlib.CTL)
        self.ltl = _temporal_library("LTLLibrary", stdlib.LTL)
        self.time: Module | None = None
        self._uid = 0

    def uid(self) -> int:
        self._uid += 1
        return self._uid

    def library(self, name: str) -> Module:
        if name == "StandardLibrary":
            return self.std
        if name == "CTLLibrary":
            return self.ctl
        if name == "LTLLibrary":
            return self.ltl
        if self.time is None:
            text = resources.files("asmcheck.stdlib").joinpath("TimeLibrary.asm").read_text(encoding="utf-8")
            syntax = parse_text(text, "<TimeLibrary>")
            self.time = Module("TimeLibrary", "<TimeLibrary>", syntax, library="TimeLibrary")
            self._declare(self.time, [])
        return self.time

    def load_root(self, path: str) -> Module:
        p = os.path.abspath(path)
        stem = Path(p).stem
        if stem in REFUSED:
            raise AsmError(Span(path, 1, 1), f"{Path(path).name} names a library that asmcheck provides itself; "
                                             f"it is not read as a spec (import it instead)")
        try:
            syntax = parse_file(path)
        except AsmError:
            raise
        if syntax is None:
            raise AsmSyntaxError(Span(path, 1, 1), "empty file: expected 'asm NAME' or 'module NAME'")
        mod = Module(syntax.name, path, syntax)
        self.modules[p] = mod
        self._declare(mod, [p])
        return mod

    def _import(self, importer: Module, imp: A.Import, stack: list[str]) -> Module:
        raw = imp.path.replace("\\", "/")
        base = Path(importer.path).parent if importer.library is None else Path(".")
        stem = Path(raw).name
        if stem.endswith(".asm"):
            stem = stem[:-4]
        target = _asm_file(base / raw)
        if stem in LIBRARIES:
            # Provided by asmcheck; a path that leads nowhere is still an error
            # (as for AsmetaL's own tools) unless the library is named bare.
            if "/" in raw and not target.exists():
                raise AsmError(imp.span, f"import not found: {target} (asmcheck provides {stem} itself: "
                                         f"write 'import {stem}' to use it without a file)")
            return self.library(stem)
        if not target.exists() and not os.path.isabs(raw):
            for d in import_path():
                cand = _asm_file(Path(d) / raw)
                if cand.exists():
                    target = cand
                    break
        p = os.path.abspath(str(target))
        if p in stack:
            cycle = " -> ".join(Path(s).name for s in stack[stack.index(p):] + [p])
            raise AsmError(imp.span, f"circular import: {cycle}")
        if p in self.modules:
            return self.modules[p]
        if not os.path.exists(p):
            where = import_path()
            hint = f" (also looked in: {', '.join(where)})" if where and not os.path.isabs(raw) else ""
            raise AsmError(imp.span, f"import not found: {target}{hint}")
        syntax = parse_file(p, imp.span)
        if syntax is None:
            raise AsmError(imp.span, f"imported file {target} is empty")
        if syntax.name != Path(p).stem:
            raise AsmError(syntax.name_span or syntax.span,
                           f"the module name {syntax.name!r} differs from its file name {Path(p).name!r}")
        mod = Module(syntax.name, p, syntax)
        self.modules[p] = mod
        self._declare(mod, stack + [p])
        return mod

    # -- declarations of one module (signature level)
    def _declare(self, mod: Module, stack: list[str]) -> None:
        syn = mod.syntax
        for imp in syn.imports:
            target = self._import(mod, imp, stack)
            mod.imports.append((target, imp.names, imp.span))
        # what this module sees from its imports
        for target, names, span in mod.imports:
            if names is None:
                mod.scope.merge(target.exports)
            else:
                wanted = set()
                for n, nspan in names:
                    if not target.exports.has(n):
                        raise AsmTypeError(nspan, f"{target.name} does not export {n!r}")
                    wanted.add(n)
                mod.scope.merge(target.exports, wanted)
        Declarer(self, mod).run()
        mod.scope.merge(mod.own)
        if syn.export_all:
            mod.exports = mod.scope
        elif syn.export is not None:
            ex = Table()
            for n, nspan in syn.export:
                if not mod.scope.has(n):
                    raise AsmTypeError(nspan, f"cannot export {n!r}: no such domain, function or rule")
                ex.merge(mod.scope, {n})
            mod.exports = ex
        self.order.append(mod)


# ----------------------------------------------------------------- declarations
class Declarer:
    """Creates the Domain, Function and RuleDecl objects of one module."""

    def __init__(self, loader: Loader, mod: Module):
        self.loader = loader
        self.mod = mod

    def run(self) -> None:
        syn = self.mod.syntax
        mod = self.mod
        # domains: first create them all (a subset domain may name a later one)
        pending = []
        for d in syn.domains:
            if d.kind == "structured":
                continue
            if d.kind == "basic":
                if d.name not in T.BASICS:
                    raise AsmTypeError(d.span, f"unknown basic domain {d.name!r}")
                continue
            if d.kind == "any":
                dom = T.GENERICS.get(d.name) or T.Domain(d.name, "any", module=mod.name, span=d.span)
            else:
                dom = T.Domain(d.name, d.kind, d.dynamic, module=mod.name, span=d.span)
            if self._clash(d.name, "domains"):
                raise AsmTypeError(d.span, f"domain {d.name!r} is declared twice")
            mod.own.add("domains", d.name, dom)
            mod.domains.append(dom)
            pending.append((d, dom))
        scope = _Overlay(mod.scope, mod.own)
        for d, dom in pending:
            if d.kind == "subset":
                dom.base = resolve_type(d.base, scope)
            elif d.kind == "enum":
                seen = set()
                for i, (el, el_span) in enumerate(d.elements):
                    if el in seen:
                        raise AsmTypeError(el_span, f"the enum symbol {el} is duplicate")
                    seen.add(el)
                    v = enum_value(dom.name, el, i)
                    dom.elements.append(v)
                    for other_v, other_d in mod.own.enums.get(el, []):
                        if other_d is not dom:
                            raise AsmTypeError(el_span, f"the enum symbol {el} is also declared in domain {other_d.name}")
                    mod.own.add("enums", el, (v, dom))
        # functions
        for f in syn.functions:
            if f.kind == "local":
                raise AsmTypeError(f.span, f"a local function cannot be declared in the signature: {f.name}")
            domain: list[T.Type] = []
            if f.domain is not None:
                dt = resolve_type(f.domain, scope)
                if isinstance(dt, T.Struct) and dt.kind == "Prod":
                    domain = list(dt.args)
                else:
                    domain = [dt]
            cod = resolve_type(f.codomain, scope)
            func = ir.Function(f.name, f.kind, domain, cod, mod.name, f.span)
            for other in mod.own.functions.get(f.name, []):
                if isinstance(other, ir.Function) and len(other.domain) == len(domain) and all(
                        a is b or a == b for a, b in zip(other.domain, domain)):
                    raise AsmTypeError(f.span, f"function {f.name!r} is declared twice with the same domain")
            mod.own.add("functions", f.name, func)
            mod.functions.append(func)
        # rules (bodies later)
        for r in syn.rules:
            params = [ir.Var(p.name, resolve_type(p.type, scope), p.span, self.loader.uid()) for p in r.params]
            rd = ir.RuleDecl(r.name, params, mod.name, r.span, r.kind,
                             resolve_type(r.returns, scope) if r.returns is not None else None)
            for other in mod.own.rules.get(r.name, []):
                if len(other.params) == len(params) and all(
                        a.type is b.type or a.type == b.type for a, b in zip(other.params, params)):
                    raise AsmTypeError(r.span, f"rule {r.name!r} is declared twice")
            mod.own.add("rules", r.name, rd)
            mod.rules.append(rd)

    def _clash(self, name: str, kind: str) -> bool:
        return name in getattr(self.mod.own, kind)


class _Overlay:
    """A scope made of two tables, the second one taking precedence."""

    def __init__(self, base: Table, top: Table):
        self.base = base
        self.top = top

    def get(self, kind: str, name: str) -> list:
        top = getattr(self.top, kind).get(name, [])
        if top:
            return top
        return getattr(self.base, kind).get(name, [])


class _LocalScope:
    """A scope plus one local function (a layer over the scope, not a copy of it)."""

    def __init__(self, base, name: str, func) -> None:
        self.domains = base.domains
        self.rules = base.rules
        self.enums = base.enums
        self.functions = ChainMap({name: list(base.functions.get(name, [])) + [func]}, base.functions)

    def has(self, name: str) -> bool:
        return any(name in getattr(self, k) for k in ("domains", "functions", "rules", "enums"))


def _lookup(scope, kind: str, name: str) -> list:
    if isinstance(scope, _Overlay):
        return scope.get(kind, name)
    return getattr(scope, kind).get(name, [])


def resolve_type(t: A.TypeExpr, scope) -> T.Type:
    if t.structured:
        args = tuple(resolve_type(a, scope) for a in t.args)
        if t.name == "Prod" and len(args) < 2:
            raise AsmTypeError(t.span, "a product domain has two components or more")
        return T.Struct(t.name, args)
    found = _lookup(scope, "domains", t.name)
    if len(found) > 1:
        # a generic name of the StandardLibrary (D, D1, ...) never hides a declared domain
        found = [d for d in found if not (isinstance(d, T.Domain) and d.kind == "any")] or found
    if not found:
        if t.name in T.BASICS:
            return T.BASICS[t.name]
        if t.name == "Agent":
            return T.AGENT
        raise AsmTypeError(t.span, f"unknown domain {t.name!r}")
    if len(found) > 1:
        mods = ", ".join(sorted({getattr(d, "module", "?") for d in found}))
        raise AsmTypeError(t.span, f"domain {t.name!r} is ambiguous: declared in {mods}")
    return found[0]


# ----------------------------------------------------------------- deep input
# Terms and rules nest at most this deep (an if inside an if ..., a sum of this many terms);
# deeper input is a located error.  Resolution runs on a thread with a large stack and a raised
# recursion limit (deep_call), so every depth up to this one resolves.
MAX_NESTING = 3000
_DEEP_RECURSION = 40_000
_DEEP_STACK = 256 * 1024 * 1024
_MIN_DEEP_STACK = 16 * 1024 * 1024
_deep_state = threading.local()
_deep_lock = threading.Lock()


def _deep_stack_size() -> int:
    """The stack for a deep call: :data:`_DEEP_STACK`, or under an address-space limit
    (``ulimit -v``, a CI memory cap) a quarter of the room left below it, so the stack never
    takes the memory the search needs; 0 when not even :data:`_MIN_DEEP_STACK` fits."""
    try:
        import resource
        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    except (ImportError, OSError, ValueError):
        return _DEEP_STACK
    if soft == resource.RLIM_INFINITY:
        return _DEEP_STACK
    try:
        with open("/proc/self/statm") as f:
            used = int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        used = 0
    size = min(_DEEP_STACK, max(soft - used, 0) // 4) & ~(1024 * 1024 - 1)
    return size if size >= _MIN_DEEP_STACK else 0


def _too_deep(span: Span, what: str, stack: bool = False) -> AsmError:
    how = "deeper than the stack allows" if stack else f"more than {MAX_NESTING} terms and rules deep"
    return AsmTypeError(span, f"the spec nests too deeply: this {what} is {how} (group a long sum or conjunction "
                              f"with parentheses, or split the rule)")


def deep_active() -> bool:
    """Whether this thread already runs inside :func:`deep_call`."""
    return bool(getattr(_deep_state, "active", False))


def deep_call(fn, *args, **kwargs):
    """``fn(*args, **kwargs)`` on a thread with a large stack and a high recursion limit.

    Deeply nested specs (hundreds of nested ifs, long sums) then resolve and run instead of
    stopping at Python's default recursion limit.  Called inside a deep call, it just calls."""
    if getattr(_deep_state, "active", False):
        return fn(*args, **kwargs)
    box: dict = {}

    def run():
        _deep_state.active = True
        try:
            box["value"] = fn(*args, **kwargs)
        except BaseException as exc:        # handed to the caller's thread as is
            box["error"] = exc

    worker = None
    with _deep_lock:
        size = _deep_stack_size()
        try:
            old_stack = threading.stack_size(size) if size else None
        except (ValueError, RuntimeError):
            old_stack = None
        if old_stack is not None:
            old_limit = sys.getrecursionlimit()
            # the frames a stack of this size holds, at the rate measured for the full stack
            sys.setrecursionlimit(max(old_limit, _DEEP_RECURSION * size // _DEEP_STACK))
            try:
                try:
                    worker = threading.Thread(target=run, name="asmcheck-deep", daemon=True)
                    worker.start()
                except RuntimeError:        # no room for the stack (a memory limit)
                    worker = None
                finally:
                    threading.stack_size(old_stack)
                if worker is not None:
                    worker.join()
            finally:
                sys.setrecursionlimit(old_limit)
    if worker is None:
        # no deep stack could be had: run here (and do not try again for nested calls)
        _deep_state.active = True
        try:
            return fn(*args, **kwargs)
        finally:
            _deep_state.active = False
    if "error" in box:
        raise box["error"]
    return box.get("value")


# ----------------------------------------------------------------- bodies
_DYNAMIC_KINDS = ("controlled", "monitored", "shared", "out", "local", "derived")


class Env:
    """Variables in scope while resolving a term or a rule."""

    __slots__ = ("vars", "seen")

    def __init__(self, vars_: dict | None = None, seen: dict | None = None):
        self.vars = vars_ or {}
        self.seen = seen if seen is not None else {}

    def bind(self, *vs: ir.Var) -> "Env":
        d = dict(self.vars)
        for v in vs:
            d[v.name] = v
            self.seen[v.name] = v
        return Env(d, self.seen)


class Resolver:
    """Resolves the definitions, rules, properties and inits of one module."""

    def __init__(self, loader: Loader, mod: Module):
        self.loader = loader
        self.mod = mod
        self.scope = mod.scope
        self.temporal_ok = False
        self.step_ok = False        # next/updated/changed/updatedBy allowed (step properties)
        self.used: set[ir.Function] | None = None   # functions referenced (for static/derived checks)
        self.in_rule: ir.RuleDecl | None = None
        self.depth = 0                  # terms and rules being resolved, one inside the other

    def uid(self) -> int:
        return self.loader.uid()

    # -- lookups
    def functions(self, name: str) -> list:
        return self.scope.functions.get(name, [])

    def domain(self, name: str, span: Span) -> T.Type:
        return resolve_type(A.TypeExpr(span, name), _Overlay(self.scope, self.mod.own))

    def type_of(self, t: A.TypeExpr) -> T.Type:
        return resolve_type(t, _Overlay(self.scope, self.mod.own))

    # -- terms
    def term(self, t: A.Term, env: Env) -> ir.Term:
        if self.depth == 0 and not getattr(_deep_state, "active", False):
            return deep_call(self.term, t, env)     # a term of a property file or a scenario
        meth = getattr(self, "t_" + type(t).__name__)
        self.depth += 1
        try:
            if self.depth > MAX_NESTING:
                raise _too_deep(t.span, "term")
            return meth(t, env)
        except RecursionError:          # no deep stack could be had: the error is still located
            raise _too_deep(t.span, "term", stack=True) from None
        finally:
            self.depth -= 1

    def t_Const(self, t: A.Const, env: Env) -> ir.Term:
        kind = t.kind
        if kind == "int":
            return ir.Const(T.INTEGER, t.span, t.value)
        if kind == "nat":
            return ir.Const(T.NATURAL, t.span, t.value)
        if kind == "real":
            return ir.Const(T.REAL, t.span, t.value)
        if kind == "char":
            return ir.Const(T.CHAR, t.span, CharV(t.value))
        if kind == "string":
            return ir.Const(T.STRING, t.span, t.value)
        if kind == "bool":
            return ir.Const(T.BOOLEAN, t.span, t.value)
        return ir.Const(T.UNDEF, t.span, None)

    def t_EnumLit(self, t: A.EnumLit, env: Env) -> ir.Term:
        found = self.scope.enums.get(t.name, [])
        if not found:
            raise AsmTypeError(t.span, f"unknown enum constant {t.name!r}")
        if len({id(d) for _, d in found}) > 1:
            doms = ", ".join(sorted(d.name for _, d in found))
            raise AsmTypeError(t.span, f"enum constant {t.name!r} is ambiguous: it belongs to {doms}")
        v, dom = found[0]
        return ir.Const(dom, t.span, v)

    def t_VarRef(self, t: A.VarRef, env: Env) -> ir.Term:
        v = env.vars.get(t.name)
        if v is None:
            # AsmetaL keeps a variable known for the rest of the declaration once it has been
            # bound anywhere in it; such a use is accepted here and is an error only if it is
            # evaluated where nothing binds it.
            v = env.seen.get(t.name)
        if v is None:
            raise AsmTypeError(t.span, f"undeclared variable {t.name}")
        return ir.VarRef(v.type, t.span, v)

    def t_DomainRef(self, t: A.DomainRef, env: Env) -> ir.Term:
        dom = self.type_of(t.type)
        return ir.DomainTerm(T.powerset(dom), t.span, dom)

    def t_TupleTerm(self, t: A.TupleTerm, env: Env) -> ir.Term:
        items = [self.term(x, env) for x in t.items]
        return ir.TupleLit(T.prod(*[i.type for i in items]), t.span, items)

    def t_CondTerm(self, t: A.CondTerm, env: Env) -> ir.Term:
        c = self.bool_term(t.cond, env)
        a = self.term(t.then, env)
        b = self.term(t.other, env) if t.other is not None else None
        ty = T.unify(a.type, b.type) if b is not None else a.type
        return ir.Cond(ty, t.span, c, a, b)

    def t_SwitchTerm(self, t: A.SwitchTerm, env: Env) -> ir.Term:
        subj = self.term(t.subject, env)
        cases = [(self.term(c, env), self.term(r, env)) for c, r in t.cases]
        other = self.term(t.otherwise, env) if t.otherwise is not None else None
        ty = cases[0][1].type if cases else T.UNDEF
        for _, r in cases[1:]:
            ty = T.unify(ty, r.type)
        if other is not None:
            ty = T.unify(ty, other.type)
        return ir.Switch(ty, t.span, subj, cases, other)

    def t_LetTerm(self, t: A.LetTerm, env: Env) -> ir.Term:
        bindings = []
        inner = env
        for name, span, val in t.bindings:
            v_ir = self.term(val, inner)
            var = ir.Var(name, v_ir.type, span, self.uid())
            bindings.append((var, v_ir))
            inner = inner.bind(var)
        body = self.term(t.body, inner)
        return ir.Let(body.type, t.span, bindings, body)

    def bindings(self, bs: list[A.Binding], env: Env):
        out = []
        inner = env
        for b in bs:
            rng = self.term(b.range, inner)
            et = T.element_type(rng.type)
            if et is None:
                raise AsmTypeError(b.range.span, f"{b.var} ranges over a term of domain {rng.type}, "
                                                 f"which is not a set, sequence, bag or domain")
            var = ir.Var(b.var, et, b.span, self.uid())
            out.append((var, rng))
            inner = inner.bind(var)
        return out, inner

    def t_QuantTerm(self, t: A.QuantTerm, env: Env) -> ir.Term:
        bs, inner = self.bindings(t.bindings, env)
        guard = self.bool_term(t.guard, inner) if t.guard is not None else None
        return ir.Quant(T.BOOLEAN, t.span, t.kind, bs, guard)

    def t_ComprTerm(self, t: A.ComprTerm, env: Env) -> ir.Term:
        bs, inner = self.bindings(t.bindings, env)
        guard = self.bool_term(t.guard, inner) if t.guard is not None else None
        body = self.term(t.body, inner)
        body2 = self.term(t.body2, inner) if t.body2 is not None else None
        if t.kind == "map":
            ty = T.mapping(body.type, body2.type)
        else:
            ty = T.Struct({"set": "Powerset", "seq": "Seq", "bag": "Bag"}[t.kind], (body.type,))
        return ir.Compr(ty, t.span, t.kind, bs, guard, body, body2)

    def t_CollectionTerm(self, t: A.CollectionTerm, env: Env) -> ir.Term:
        items = [self.term(x, env) for x in t.items]
        et: T.Type = T.UNDEF
        for i in items:
            if et is not T.UNDEF and i.type is not T.UNDEF and not (T.compatible(i.type, et) or T.compatible(et, i.type)):
                raise AsmTypeError(i.span, f"element of domain {i.type} in a collection of {et}")
            et = T.unify(et, i.type)
        kind = {"set": "Powerset", "seq": "Seq", "bag": "Bag"}[t.kind]
        return ir.Collection(T.Struct(kind, (et,)), t.span, t.kind, items)

    def t_RangeTerm(self, t: A.RangeTerm, env: Env) -> ir.Term:
        a = self.term(t.start, env)
        b = self.term(t.end, env)
        step = self.term(t.step, env) if t.step is not None else None
        for x in (a, b) + ((step,) if step else ()):
            if not T.is_numeric_root(x.type) and x.type is not T.UNDEF:
                raise AsmTypeError(x.span, f"an interval bound must be a number, not a term of domain {x.type}")
        kind = {"set": "Powerset", "seq": "Seq", "bag": "Bag"}[t.kind]
        et = T.root(a.type)
        return ir.Range(T.Struct(kind, (et,)), t.span, t.kind, a, b, step)

    def t_MapTerm(self, t: A.MapTerm, env: Env) -> ir.Term:
        pairs = [(self.term(k, env), self.term(v, env)) for k, v in t.pairs]
        kt: T.Type = T.UNDEF
        vt: T.Type = T.UNDEF
        for k, v in pairs:
            kt = T.unify(kt, k.type)
            vt = T.unify(vt, v.type)
        return ir.MapLit(T.mapping(kt, vt), t.span, pairs)

    def t_RuleAsTerm(self, t: A.RuleAsTerm, env: Env) -> ir.Term:
        types = [self.type_of(x) for x in t.types]
        cands = self.scope.rules.get(t.name, [])
        if not cands:
            raise AsmTypeError(t.span, f"unknown rule {t.name}")
        match = [r for r in cands if len(r.params) == len(types) and all(
            a is p.type or a == p.type for a, p in zip(types, r.params))]
        if not match:
            match = [r for r in cands if len(r.params) == len(types) and all(
                T.compatible(a, p.type) for a, p in zip(types, r.params))]
        if not match:
            match = [r for r in cands if len(r.params) == len(types)]
        if not match:
            raise AsmTypeError(t.span, f"no rule {t.name} with {len(types)} parameter(s)")
        r = match[0]
        return ir.RuleRef(T.rule_type(*(types or [p.type for p in r.params])), t.span, r)

    def bool_term(self, t: A.Term, env: Env) -> ir.Term:
        x = self.term(t, env)
        if x.type is not T.BOOLEAN and x.type is not T.UNDEF and not (
                isinstance(x.type, T.Domain) and x.type.kind == "any") and T.root(x.type) is not T.BOOLEAN:
            raise AsmTypeError(t.span, f"expected a Boolean term, found a term of domain {x.type}")
        return x

    def t_Apply(self, t: A.Apply, env: Env) -> ir.Term:
        name = t.name
        if self.step_ok and name in STEP_OPS and t.args is not None:
            return self.step_op(t, env)
        args = [self.term(a, env) for a in (t.args or [])]
        cands = self.functions(name)
        if not cands:
            where = t.name_span or t.span
            if t.op is not None:
                raise AsmTypeError(where, f"operator {t.op!r} needs the StandardLibrary ({name} is not visible: "
                                          f"import StandardLibrary)")
            raise AsmTypeError(where, f"unknown function {name!r}"
                                        + (_library_hint(name) if t.args is not None else ""))
        n = len(args)
        by_arity = [c for c in cands if _arity(c) == n]
        if not by_arity and n == 1 and isinstance(args[0].type, T.Struct) and args[0].type.kind == "Prod":
            # f(t) with t a tuple stands for f(t1, ..., tk) when f is declared on Prod(...)
            k = len(args[0].type.args)
            if any(_arity(c) == k for c in cands):
                tup = args[0]
                args = [ir.Call(tup.type.args[i], tup.span, "#" + str(i + 1), [tup], stdlib.nth(i))
                        for i in range(k)]
                n = k
                by_arity = [c for c in cands if _arity(c) == n]
        if not by_arity:
            arities = sorted({_arity(c) for c in cands})
            raise AsmTypeError(t.name_span or t.span,
                               f"{name} takes {' or '.join(map(str, arities))} argument(s), not {n}")
        matches = []
        for c in by_arity:
            binds = T.Bindings()
            params = c.params if isinstance(c, stdlib.Signature) else c.domain
            if all(T.compatible(a.type, p, binds, strict=True) for a, p in zip(args, params)):
                matches.append((c, binds))
        if not matches:
            got = ", ".join(str(a.type) for a in args)
            options = "; ".join(_sig_text(c) for c in by_arity[:4])
            raise AsmTypeError(t.name_span or t.span,
                               f"no {name} applies to ({got}); declared: {options}")
        c, binds = self._best(matches, args, by_arity)
        if isinstance(c, stdlib.Signature):
            result = T.substitute(c.result, binds)
            if c.library in ("CTLLibrary", "LTLLibrary"):
                if not self.temporal_ok:
                    raise AsmTypeError(t.name_span or t.span,
                                       f"temporal operator {name} may only appear in a CTLSPEC or LTLSPEC property")
                return ir.Temporal(T.BOOLEAN, t.span, name, args)
            if name == "program" and n == 1:
                return ir.Call(T.rule_type(), t.span, name, args, None)
            impl = stdlib.IMPLEMENTATIONS.get(name)
            if impl is None:
                raise AsmTypeError(t.name_span or t.span, f"{name} is not supported by asmcheck")
            if name in ("at", "first") and args and isinstance(args[0].type, T.Struct) and args[0].type.kind == "Prod":
                if name == "at" and isinstance(args[1], ir.Const) and isinstance(args[1].value, int):
                    k = args[1].value
                    if 0 <= k < len(args[0].type.args):
                        result = args[0].type.args[k]
            return ir.Call(result, t.span, name, args, impl, t.op)
        if self.used is not None:
            self.used.add(c)
        return ir.Loc(c.codomain, t.span, c, args)

    @staticmethod
    def _best(matches, args, cands=()):
        if len(matches) == 1:
            return matches[0]
        # Overloaded user functions (one name declared on different domains, possibly in
        # different modules): ASMETA takes the latest declared function whose domain fits
        # the arguments' domains (AsmetaParserUtility.getFunction over compareFixingAnyDomain).
        users = [m for m in matches if isinstance(m[0], ir.Function)]
        if len(users) > 1:
            order = {id(c): i for i, c in enumerate(cands)}
            for m in sorted(users, key=lambda m: -order.get(id(m[0]), -1)):
                if all(_asmeta_fits(p, a.type) for p, a in zip(m[0].domain, args)):
                    return m

        def score(m):
            c, _ = m
            params = c.params if isinstance(c, stdlib.Signature) else c.domain
            exact = sum(1 for a, p in zip(args, params) if a.type is p or T.root(a.type) is p)
            generic = 1 if (isinstance(c, stdlib.Signature) and c.generic) else 0
            user = 0 if isinstance(c, ir.Function) else 1
            return (user, -exact, generic)

        return sorted(matches, key=score)[0]

    # -- rules
    def rule(self, r: A.Rule, env: Env) -> ir.Rule:
        if self.depth == 0 and not getattr(_deep_state, "active", False):
            return deep_call(self.rule, r, env)
        meth = getattr(self, "r_" + type(r).__name__)
        self.depth += 1
        try:
            if self.depth > MAX_NESTING:
                raise _too_deep(r.span, "rule")
            return meth(r, env)
        except RecursionError:          # no deep stack could be had: the error is still located
            raise _too_deep(r.span, "rule", stack=True) from None
        finally:
            self.depth -= 1

    def r_SkipRule(self, r, env):
        return ir.Skip(r.span)

    def location(self, loc: A.Term, env: Env, allow_monitored: bool = False):
        if isinstance(loc, A.VarRef):
            v = env.vars.get(loc.name)
            if v is None:
                raise AsmTypeError(loc.span, f"undeclared variable {loc.name}")
            return ("var", v, v.type)
        if not isinstance(loc, A.Apply) or loc.op is not None:
            raise AsmTypeError(loc.span, "the left-hand side of an update must be a location or a variable")
        x = self.t_Apply(loc, env)
        if not isinstance(x, ir.Loc):
            raise AsmTypeError(loc.span, f"{loc.name} is a library function, not a location that can be updated")
        f = x.func
        if f.kind == "monitored" and not allow_monitored:
            raise AsmTypeError(loc.span, f"{f.name} is monitored: the machine cannot update it")
        if f.kind in ("static", "derived"):
            raise AsmTypeError(loc.span, f"{f.name} is {f.kind}: only dynamic functions can be updated")
        return ("loc", x, f.codomain)

    def r_UpdateRule(self, r: A.UpdateRule, env):
        kind, target, ty = self.location(r.location, env)
        val = self.term(r.value, env)
        if not T.compatible(val.type, ty):
            raise AsmTypeError(r.value.span, f"the value has domain {val.type}, "
                                             f"not compatible with the location's domain {ty}")
        if kind == "var":
            return ir.UpdateVar(r.span, target, val)
        return ir.Update(r.span, target.func, target.args, val)

    def r_BlockRule(self, r: A.BlockRule, env):
        return ir.Block(r.span, r.kind, [self.rule(x, env) for x in r.rules])

    def r_IfRule(self, r: A.IfRule, env):
        return ir.If(r.span, self.bool_term(r.cond, env), self.rule(r.then, env),
                     self.rule(r.other, env) if r.other is not None else None)

    def r_SwitchRule(self, r: A.SwitchRule, env):
        subj = self.term(r.subject, env)
        cases = [(self.term(c, env), self.rule(b, env)) for c, b in r.cases]
        return ir.SwitchRule(r.span, subj, cases, self.rule(r.otherwise, env) if r.otherwise is not None else None)

    def r_LetRule(self, r: A.LetRule, env):
        bindings = []
        inner = env
        for name, span, val in r.bindings:
            v_ir = self.term(val, inner)
            var = ir.Var(name, v_ir.type, span, self.uid())
            bindings.append((var, v_ir))
            inner = inner.bind(var)
        return ir.LetRule(r.span, bindings, self.rule(r.body, inner))

    def r_ChooseRule(self, r: A.ChooseRule, env):
        bs, inner = self.bindings(r.bindings, env)
        guard = self.bool_term(r.guard, inner) if r.guard is not None else None
        return ir.Choose(r.span, bs, guard, self.rule(r.body, inner),
                         self.rule(r.ifnone, env) if r.ifnone is not None else None)

    def r_ForallRule(self, r: A.ForallRule, env):
        bs, inner = self.bindings(r.bindings, env)
        guard = self.bool_term(r.guard, inner) if r.guard is not None else None
        return ir.Forall(r.span, bs, guard, self.rule(r.body, inner))

    def r_ExtendRule(self, r: A.ExtendRule, env):
        dom = self.domain(r.domain, r.domain_span)
        ok = isinstance(dom, T.Domain) and dom.dynamic and (
            dom.kind == "abstract" or (dom.kind == "subset" and isinstance(T.root(dom), T.Domain)
                                       and T.root(dom).kind == "abstract"))
        if not ok:
            raise AsmTypeError(r.domain_span, f"extend needs a dynamic abstract domain; {r.domain} is not one")
        vs = [ir.Var(n, dom, s, self.uid()) for n, s in r.vars]
        return ir.Extend(r.span, dom, vs, self.rule(r.body, env.bind(*vs)))

    def r_CallRule(self, r: A.CallRule, env):
        args = [self.term(a, env) for a in r.args]
        cands = self.scope.rules.get(r.name, [])
        if not cands:
            raise AsmTypeError(r.span, f"unknown rule {r.name}")
        by_arity = [c for c in cands if len(c.params) == len(args)]
        if not by_arity:
            raise AsmTypeError(r.span, f"{r.name} takes {len(cands[0].params)} argument(s), not {len(args)}")
        match = [c for c in by_arity if all(T.compatible(a.type, p.type, strict=True) for a, p in zip(args, c.params))]
        if not match:
            # AsmetaL accepts a rule argument of the super-domain (checked when the rule runs)
            match = [c for c in by_arity if all(T.compatible(a.type, p.type) for a, p in zip(args, c.params))]
        if len(match) > 1:
            exact = [c for c in match if all(a.type is p.type for a, p in zip(args, c.params))]
            match = exact or match
        if not match:
            got = ", ".join(str(a.type) for a in args)
            want = ", ".join(str(p.type) for p in by_arity[0].params)
            raise AsmTypeError(r.span, f"{r.name} expects ({want}), called with ({got})")
        return ir.CallRule(r.span, match[0], args, r.turbo)

    def r_TurboReturnRule(self, r: A.TurboReturnRule, env):
        kind, target, ty = self.location(r.location, env, allow_monitored=True)
        call = self.r_CallRule(r.call, env)
        placeholder = ir.Const(T.UNDEF, r.span, None)
        upd = ir.UpdateVar(r.span, target, placeholder) if kind == "var" else ir.Update(
            r.span, target.func, target.args, placeholder)
        return ir.TurboReturn(r.span, upd, call)

    def r_TermCallRule(self, r: A.TermCallRule, env):
        term = self.term(r.term, env)
        if not (isinstance(term.type, T.Struct) and term.type.kind == "Rule") and term.type is not T.UNDEF:
            raise AsmTypeError(r.term.span, f"a term used as a rule must be rule-valued; this one has domain {term.type}")
        args = [self.term(a, env) for a in r.args]
        return ir.TermCall(r.span, term, args)

    def r_LoopRule(self, r: A.LoopRule, env):
        cond = self.bool_term(r.cond, env) if r.cond is not None else None
        return ir.Loop(r.span, r.kind, cond, self.rule(r.body, env))

    def r_LocalRule(self, r: A.LocalRule, env):
        d = r.decl
        domain = []
        if d.domain is not None:
            dt = self.type_of(d.domain)
            domain = list(dt.args) if isinstance(dt, T.Struct) and dt.kind == "Prod" else [dt]
        func = ir.Function(d.name, "local", domain, self.type_of(d.codomain), self.mod.name, d.span)
        self.mod.local_functions.append(func)
        saved = self.scope
        self.scope = _LocalScope(self.scope, d.name, func)
        try:
            init = self.rule(r.init, env)
            body = self.rule(r.body, env)
        finally:
            self.scope = saved
        return ir.LocalRule(r.span, func, init, body)


STEP_OPS = {"next": 1, "updated": 1, "changed": 1, "updatedBy": 2}


def _step_op(self, t: A.Apply, env: Env) -> ir.Term:
    name = t.name
    want = STEP_OPS[name]
    if len(t.args) != want:
        raise AsmTypeError(t.name_span or t.span, f"{name} takes {want} argument(s), not {len(t.args)}")
    if getattr(self, "in_next", False):
        # a step property sees one step: the state before it and the state after it
        raise AsmTypeError(t.name_span or t.span, f"{name}(...) inside next(...): a step property sees one step "
                                                  f"(the state before it and the one after), so the term in "
                                                  f"next(...) is read in the state after the step already")
    if name == "next":
        self.in_next = True
        try:
            inner = self.term(t.args[0], env)
        finally:
            self.in_next = False
        return ir.StepOp(inner.type, t.span, name, [inner])
    args = []
    if name == "updatedBy":
        who = self.term(t.args[0], env)
        if not (T.agent_like(who.type) or who.type is T.UNDEF):
            raise AsmTypeError(t.args[0].span, f"updatedBy needs an agent (an element of Agent or of a domain "
                                               f"that is a subset of it), not a value of {who.type}")
        args.append(who)
    loc_t = t.args[-1]
    loc = self.term(loc_t, env)
    if not isinstance(loc, ir.Loc) or not loc.func.is_location or loc.func.kind == "monitored":
        raise AsmTypeError(loc_t.span, f"{name} needs a location of a controlled function, such as f(x)")
    args.append(loc)
    return ir.StepOp(T.BOOLEAN, t.span, name, args)


Resolver.step_op = _step_op


def _dynamic_domain(t) -> bool:
    """Is ``t`` a dynamic domain in the sense of ASMETA's static/derived check?

    A dynamic abstract domain (Agent and Reserve are), a dynamic subset domain
    whose direct base is an abstract domain, or ``Seq`` of one of those.
    ``Powerset`` and ``Prod`` of such domains are not (ASMETA asks the question
    of the structured domain itself); Bag, Map and Rule are not either."""
    if isinstance(t, T.Struct):
        return t.kind == "Seq" and len(t.args) == 1 and _dynamic_named(t.args[0])
    return _dynamic_named(t)


def _dynamic_named(t) -> bool:
    if not isinstance(t, T.Domain) or not t.dynamic:
        return False
    if t.kind == "abstract":
        return True
    return t.kind == "subset" and isinstance(t.base, T.Domain) and t.base.kind == "abstract"


def dynamic_parts(body: ir.Term) -> list[str]:
    """The dynamic entities a definition body mentions, as ASMETA's parser finds them.

    A function applied that is not static (controlled, monitored, shared, out,
    local, derived; ``self`` and ``result`` are controlled), and a variable
    written in the body whose domain is dynamic (see :func:`_dynamic_domain`).
    The walk visits what ASMETA's visitor visits: for ``forall`` the variables
    and the guard (not the ranges); for ``exists`` the ranges and the guard; a
    sequence comprehension its ranges and guard; a bag comprehension its ranges
    and term; a set comprehension everything; ``let`` its variables, values and
    body.  ``exists unique`` is walked as ``exists`` (ASMETA's visitor has no
    case for it and stops with an internal error).  Iterative: deep bodies do
    not exhaust the Python stack."""
    found: list[str] = []
    seen: set[str] = set()

    def note(text: str) -> None:
        if text not in seen:
            seen.add(text)
            found.append(text)

    def var(v: ir.Var) -> None:
        if _dynamic_domain(v.type):
            note(f"{v.name} (a variable of the dynamic domain {v.type})")

    stack: list = [body]
    while stack:
        x = stack.pop()
        if x is None:
            continue
        if isinstance(x, ir.Loc):
            if x.func.kind != "static":
                note(x.func.name)
            stack.extend(reversed(x.args))
        elif isinstance(x, ir.VarRef):
            var(x.var)
        elif isinstance(x, (ir.Call, ir.Temporal, ir.StepOp)):
            stack.extend(reversed(x.args))
        elif isinstance(x, ir.Cond):
            stack.extend((x.other, x.then, x.cond))
        elif isinstance(x, ir.Switch):
            stack.append(x.other)
            for c, r in reversed(x.cases):
                stack.extend((r, c))
            stack.append(x.subject)
        elif isinstance(x, ir.Let):
            for v, _ in x.bindings:
                var(v)
            stack.append(x.body)
            stack.extend(reversed([t for _, t in x.bindings]))
        elif isinstance(x, ir.Quant):
            stack.append(x.guard)
            if x.kind == "forall":
                for v, _ in x.bindings:
                    var(v)
            else:
                stack.extend(reversed([r for _, r in x.bindings]))
        elif isinstance(x, ir.Compr):
            ranges = [r for _, r in x.bindings]
            if x.kind == "seq":
                stack.append(x.guard)
                stack.extend(reversed(ranges))
            elif x.kind == "bag":
                stack.append(x.body)
                stack.extend(reversed(ranges))
            else:
                for v, _ in x.bindings:
                    var(v)
                stack.extend((x.body2, x.body, x.guard))
                stack.extend(reversed(ranges))
        elif isinstance(x, (ir.Collection, ir.TupleLit)):
            stack.extend(reversed(x.items))
        elif isinstance(x, ir.Range):
            stack.extend((x.step, x.end, x.start))
        elif isinstance(x, ir.MapLit):
            for k, v in reversed(x.pairs):
                stack.extend((v, k))
        # constants, domain terms (typed Powerset(D), never dynamic) and rule terms: nothing
    return found


def _asmeta_fits(formal, actual, depth: int = 0) -> bool:
    """Does an argument of domain ``actual`` select a function declared on ``formal``?

    ASMETA's rule for picking among overloaded functions: the same domain; a subset
    domain against its base (either way round, one level, as a base that is not itself
    a subset); structured domains component by component; a generic or undef argument
    fits anything; otherwise domains are compared by name."""
    if formal is actual or actual is T.UNDEF or depth > 20:
        return True
    if isinstance(actual, T.Domain) and actual.kind == "any":
        return True
    if isinstance(formal, T.Domain) and formal.kind == "subset":
        if isinstance(actual, T.Domain) and actual.kind == "subset":
            return False
        return formal.base is not None and _asmeta_fits(formal.base, actual, depth + 1)
    if isinstance(actual, T.Domain) and actual.kind == "subset":
        if isinstance(formal, T.Domain) and formal.kind == "any":
            return True
        return actual.base is not None and _asmeta_fits(formal, actual.base, depth + 1)
    if isinstance(formal, T.Struct) and isinstance(actual, T.Struct):
        return (formal.kind == actual.kind and len(formal.args) == len(actual.args)
                and all(_asmeta_fits(f, a, depth + 1) for f, a in zip(formal.args, actual.args)))
    if isinstance(formal, T.Domain) and formal.kind == "any":
        return True
    return str(formal) == str(actual)


def _arity(c) -> int:
    if isinstance(c, stdlib.Signature):
        return len(c.params)
    return c.arity


def _sig_text(c) -> str:
    if isinstance(c, stdlib.Signature):
        return f"{c.name}({', '.join(map(str, c.params))})"
    return f"{c.name}({', '.join(map(str, c.domain))})"


# ----------------------------------------------------------------- whole modules
def resolve_module(loader: Loader, mod: Module, root: bool) -> None:
    if mod.resolved:
        return
    mod.resolved = True
    res = Resolver(loader, mod)
    syn = mod.syntax
    # domain definitions (definitions section)
    for dd in syn.domain_defs:
        dom = res.domain(dd.name, dd.span)
        body = res.term(dd.body, Env())
        if not isinstance(dom, T.Domain) or dom.kind not in ("subset", "abstract", "enum"):
            raise AsmTypeError(dd.span, f"domain {dd.name} cannot be defined")
        et = T.element_type(body.type)
        if et is None or not (T.compatible(et, dom) or et is T.UNDEF):
            raise AsmTypeError(dd.body.span, f"the definition of {dd.name} must be a set of its elements, "
                                             f"not a term of domain {body.type}")
        dom.definition = body
    # function definitions
    for fd in syn.function_defs:
        # The module's own functions and those it imports (ASMETA looks the name up among all
        # declared functions, the latest declared first): a module may define a static or
        # derived function that an imported module declares.
        cands = [f for f in reversed(mod.scope.functions.get(fd.name, [])) if isinstance(f, ir.Function)]
        if not cands:
            raise AsmTypeError(fd.name_span or fd.span, f"definition of an undeclared function {fd.name!r}")
        params_t = [res.type_of(p.type) for p in fd.params]
        func = None
        for f in cands:
            if f.arity == len(params_t) and all(a is b or a == b for a, b in zip(f.domain, params_t)):
                func = f
                break
        if func is None:
            for f in cands:
                if f.arity == len(params_t) and f.body is None:
                    func = f
                    break
        if func is None:
            raise AsmTypeError(fd.name_span or fd.span,
                               f"the definition of {fd.name} has {len(params_t)} parameter(s) but the function has arity "
                               f"{cands[0].arity}")
        for pt, dt, p in zip(params_t, func.domain, fd.params):
            if not (T.compatible(pt, dt) and T.compatible(dt, pt)):
                raise AsmTypeError(p.span, f"parameter {p.name} has domain {pt}, but {fd.name} is declared on {dt}")
        if func.body is not None:
            raise AsmTypeError(fd.name_span or fd.span, f"function {fd.name} is defined twice")
        vs = [ir.Var(p.name, pt, p.span, loader.uid()) for p, pt in zip(fd.params, params_t)]
        res.used = set()
        res.temporal_ok = True      # LTL/CTL pattern functions are defined with temporal operators
        body = res.term(fd.body, Env().bind(*vs))
        res.temporal_ok = False
        used, res.used = res.used, None
        if not T.compatible(body.type, func.codomain):
            raise AsmTypeError(fd.body.span, f"the definition of {fd.name} has domain {body.type}, "
                                             f"not compatible with its codomain {func.codomain}")
        # ASMETA's rule (StaticDerivedChecker): a static definition mentions nothing dynamic,
        # a derived one at least one dynamic function or variable of a dynamic domain.
        dyn = dynamic_parts(body) if func.kind in ("static", "derived") else []
        if func.kind == "static" and dyn:
            raise AsmTypeError(fd.name_span or fd.span,
                               f"static function {fd.name} uses dynamic function(s) {', '.join(dyn)} in its "
                               f"definition (declare it derived)")
        if func.kind == "derived" and not dyn:
            raise AsmTypeError(fd.name_span or fd.span,
                               f"derived function {fd.name} uses no dynamic function (nor a variable of a dynamic "
                               f"domain) in its definition (declare it static)")
        if func.kind not in ("static", "derived"):
            raise AsmTypeError(fd.name_span or fd.span,
                               f"{fd.name} is {func.kind}: only static and derived functions are defined in "
                               f"'definitions' (initialise it in an init block)")
        func.params = vs
        func.body = body
    # rule bodies
    # mod.rules was made from syn.rules, one declaration per syntax rule, in the same order
    # (one pass: a spec of many rules resolves in linear time)
    if len(mod.rules) != len(syn.rules):
        raise AssertionError("rule declarations and their syntax differ in number")
    for rd, src in zip(mod.rules, syn.rules):
        res.in_rule = rd
        env = Env().bind(*rd.params)
        rd.body = res.rule(src.body, env)
    res.in_rule = None
    # properties
    props = []
    count = {"invariant": 0, "ctl": 0, "ltl": 0, "invar": 0, "justice": 0, "compassion": 0}
    for p in syn.properties:
        count[p.kind] += 1
        res.temporal_ok = p.kind in ("ctl", "ltl")
        for item in p.over:
            if not mod.scope.has(item.name) and item.name not in T.BASICS:
                raise AsmTypeError(item.span, f"invariant over unknown name {item.name!r}")
        body = res.bool_term(p.body, Env())
        body2 = res.bool_term(p.body2, Env()) if p.body2 is not None else None
        res.temporal_ok = False
        name = p.name or f"{p.kind}_{count[p.kind]}"
        props.append(ir.Property(p.kind, name, body, p.span, body2, [i.name for i in p.over]))
    mod.properties = props
    # initial states (of the root asm only: a module's inits are never used)
    inits = []
    for ib in syn.inits:
        doms = []
        for dd in ib.domains:
            dom = res.domain(dd.name, dd.span)
            doms.append((dom, res.term(dd.body, Env())))
        funcs = []
        for fi in ib.functions:
            cands = [f for f in mod.scope.functions.get(fi.name, []) if isinstance(f, ir.Function)]
            params_t = [res.type_of(p.type) for p in fi.params]
            func = next((f for f in cands if f.arity == len(params_t) and all(
                a is b or a == b for a, b in zip(f.domain, params_t))), None) or next(
                (f for f in cands if f.arity == len(params_t)), None)
            if func is None:
                if not cands:
                    raise AsmTypeError(fi.name_span or fi.span, f"initialisation of an unknown function {fi.name!r}")
                raise AsmTypeError(fi.name_span or fi.span,
                                   f"the initialisation of {fi.name} has {len(params_t)} parameter(s) but the "
                                   f"function has arity {cands[0].arity}")
            vs = [ir.Var(p.name, pt, p.span, loader.uid()) for p, pt in zip(fi.params, params_t)]
            body = res.term(fi.body, Env().bind(*vs))
            if not T.compatible(body.type, func.codomain, strict=True):
                raise AsmTypeError(fi.body.span, f"the initial value of {fi.name} has domain {body.type}, "
                                                 f"not compatible with its codomain {func.codomain}")
            if func.kind in ("static", "derived"):
                raise AsmTypeError(fi.name_span or fi.span,
                                   f"{fi.name} is {func.kind}: it is defined in 'definitions', not initialised")
            funcs.append((func, vs, body, fi.span))
        agents = []
        for ag in ib.agents:
            dom = res.domain(ag.domain, ag.span)
            call = res.r_CallRule(ag.program, Env())
            agents.append(ir.AgentInit(dom, call.rule, call.args, ag.span))
        inits.append(ir.InitState(ib.name, ib.default, doms, funcs, agents, ib.span))
    mod.inits = inits


def load_spec(path: str) -> ir.Spec:
    """Read, resolve and type-check the spec at ``path`` and everything it imports."""
    return deep_call(_load_spec, path)


def _load_spec(path: str) -> ir.Spec:
    with gc_paused():
        return _load_spec_now(path)


def _load_spec_now(path: str) -> ir.Spec:
    loader = Loader()
    root = loader.load_root(path)
    for mod in loader.order:
        if mod.library is None or mod.library == "TimeLibrary":
            resolve_module(loader, mod, mod is root)
    if loader.time is not None and not loader.time.resolved:
        resolve_module(loader, loader.time, False)
    syn = root.syntax
    # every user function and domain of every module, in a fixed order
    mods = [m for m in loader.order]
    if loader.time is not None and loader.time not in mods:
        mods.insert(0, loader.time)
    functions: list[ir.Function] = []
    domains: list[T.Type] = []
    rules: list[ir.RuleDecl] = []
    for m in mods:
        functions.extend(m.functions)
        domains.extend(m.domains)
        rules.extend(m.rules)
    functions = loader.std.functions + functions
    for i, f in enumerate(functions):
        f.index = i
    # each local function has its own number after the table, so its locations are its own
    local_functions = [f for m in mods for f in m.local_functions]
    for i, f in enumerate(local_functions, len(functions)):
        f.index = i
    main = None
    if syn.main is not None:
        main = next(r for r in root.rules if r.name == syn.main.name and len(r.params) == len(syn.main.params))
        if main.params:
            raise AsmTypeError(syn.main.span, "the main rule takes no parameters")
    if not root.syntax.is_module and syn.inits and not any(i.default for i in syn.inits):
        raise AsmTypeError(syn.span, "an asm with init blocks needs one 'default init'")
    static_elements: dict = {}
    for f in functions:
        if f.kind == "static" and f.arity == 0 and isinstance(f.codomain, T.Domain):
            r = f.codomain
            if r.kind == "abstract" or (r.kind == "subset" and T.root(r).kind == "abstract"):
                static_elements.setdefault(r, []).append(abstract_value(r.name, f.name))
    props = []
    for m in mods:
        if m is root:
            props.extend(getattr(m, "properties", []))
    spec = ir.Spec(syn.name, path, syn.asyncr, functions, domains, rules, main, getattr(root, "inits", []),
                   props, [m.path for m in mods], static_elements, loader.std.functions[0], loader.std.functions[1],
                   root.scope)
    spec.is_module = syn.is_module
    spec.local_functions = local_functions
    spec.loader = loader
    spec.root_module = root
    return spec


def check_file(path: str) -> ir.Spec | None:
    """Parse and check one file; None for an empty file (which AsmetaL accepts)."""
    p = os.path.abspath(path)
    stem = Path(p).stem
    if stem in REFUSED:
        raise AsmError(Span(path, 1, 1), f"{Path(path).name} names a library that asmcheck provides itself; "
                                         f"it is not read as a spec (import it instead)")
    syntax = parse_file(path)
    if syntax is None:
        return None
    if syntax.name != Path(p).stem:
        raise AsmError(syntax.name_span or syntax.span,
                       f"the {'module' if syntax.is_module else 'asm'} name {syntax.name!r} differs from its file "
                       f"name {Path(p).name!r}")
    return load_spec(path)
