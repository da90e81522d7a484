"""Temporal formulas: the IR of a CTLSPEC / LTLSPEC turned into a small formula tree.

A formula is a tuple ``(op, *args)``:

* ``("true",)``, ``("false",)``, ``("ap", i)`` -- atom number ``i`` of an :class:`Atoms` table
  (a maximal subterm without temporal operators, with the values of the quantified
  variables it sees);
* ``("not", f)``, ``("and", f, g)``, ``("or", f, g)``;
* CTL core: ``("EX", f)``, ``("EU", f, g)``, ``("EG", f)`` -- every other CTLLibrary operator
  and pattern is rewritten into these, exactly as AsmetaSMV writes them for NuSMV
  (``aw(p, q)`` is ``!E[!q U !(p | q)]``, ``absenceBefore(p, r)`` is
  ``aw(!p | AG !r, r)``, ...);
* LTL: ``("X", f)``, ``("U", f, g)``, ``("R", f, g)`` (LTLLibrary ``v``, NuSMV ``V``) and the
  past operators ``("Y", f)``, ``("Z", f)``, ``("S", f, g)``, ``("T", f, g)``;
  ``g f`` are ``false R f`` and ``true U f``, ``h o`` are ``not(true S not f)`` and
  ``true S f``.

Quantifiers over finite domains whose body holds temporal operators
(``forall $j in Job with ag(...)``) are expanded into conjunctions / disjunctions, and
derived functions whose definitions use temporal operators are inlined.
"""
from __future__ import annotations

from ..errors import AsmError, SOURCES, Span
from ..semantics import ir
from ..semantics.machine import Chooser, Ctx
from ..semantics.analysis import mentions_monitored

TRUE = ("true",)
FALSE = ("false",)

CTL_OPS = frozenset("ag ef ax ex eg af au eu aw ew absenceG absenceBefore absenceAfter absenceBetween "
                    "absenceAfterUntil ap pb exN axN".split())
LTL_OPS = frozenset("x g f u v y z h o s t".split())


class FormulaError(AsmError):
    """A temporal property asmcheck cannot turn into a formula."""


def span_text(span: Span | None, limit: int = 200) -> str:
    """The source text of a span (joined on one line), or '' when unknown."""
    if span is None or not span.line or not span.end_line:
        return ""
    lines = []
    for ln in range(span.line, span.end_line + 1):
        text = SOURCES.line(span.path, ln)
        if text is None:
            return ""
        if ln == span.end_line:
            text = text[: max(span.end_col - 1, 0)]
        if ln == span.line:
            text = text[max(span.col - 1, 0):] if ln != span.end_line else text[max(span.col - 1, 0):]
        lines.append(text.strip())
    out = " ".join(x for x in lines if x)
    return out if len(out) <= limit else out[: limit - 3] + "..."


# ----------------------------------------------------------------- constructors (with simplification)
def temporal_free(f) -> bool:
    """Whether ``f`` is a boolean combination of atoms (a state formula: no temporal operator)."""
    op = f[0]
    if op in ("true", "false", "ap"):
        return True
    if op in ("not", "and", "or"):
        return all(temporal_free(x) for x in f[1:])
    return False


def Not(f):
    if f[0] == "not":
        return f[1]
    if f == TRUE:
        return FALSE
    if f == FALSE:
        return TRUE
    return ("not", f)


def And(f, g):
    if f == FALSE or g == FALSE:
        return FALSE
    if f == TRUE:
        return g
    if g == TRUE:
        return f
    if f == g:
        return f
    return ("and", f, g)


def Or(f, g):
    if f == TRUE or g == TRUE:
        return TRUE
    if f == FALSE:
        return g
    if g == FALSE:
        return f
    if f == g:
        return f
    return ("or", f, g)


def Implies(f, g):
    return Or(Not(f), g)


def Iff(f, g):
    return Or(And(f, g), And(Not(f), Not(g)))


def EX(f):
    return ("EX", f)


def EU(f, g):
    return ("EU", f, g)


def EG(f):
    return ("EG", f)


def EF(f):
    return EU(TRUE, f)


def AX(f):
    return Not(EX(Not(f)))


def AG(f):
    return Not(EF(Not(f)))


def AF(f):
    return Not(EG(Not(f)))


def AU(f, g):
    # A[f U g] = !(E[!g U (!f & !g)] | EG !g)
    return Not(Or(EU(Not(g), And(Not(f), Not(g))), EG(Not(g))))


def AW(p, q):
    # AsmetaSMV: aw(p, q) = !E[ !q U !(p | q)]
    return Not(EU(Not(q), Not(Or(p, q))))


def EW(p, q):
    # AsmetaSMV: ew(p, q) = E[p U q] | EG(p)
    return Or(EU(p, q), EG(p))


# ----------------------------------------------------------------- atoms
class Atom:
    __slots__ = ("term", "env", "fn", "monitored", "text", "index")

    def __init__(self, term, env, fn, monitored, text, index):
        self.term = term
        self.env = env            # uid -> value of the quantified variables it reads
        self.fn = fn              # compiled term: fn(ctx) -> value
        self.monitored = monitored
        self.text = text
        self.index = index


class Atoms:
    """The atomic propositions of every formula checked together (shared labels)."""

    def __init__(self, machine):
        self.machine = machine
        self.items: list[Atom] = []
        self._key: dict = {}
        self._compiled: dict = {}

    def add(self, term: ir.Term, env: dict, text: str | None = None) -> int:
        envkey = tuple(sorted(env.items(), key=lambda kv: kv[0]))
        try:
            key = (id(term), envkey)
            hash(key)
        except TypeError:
            key = (id(term), repr(envkey))
        i = self._key.get(key)
        if i is not None:
            return i
        fn = self._compiled.get(id(term))
        if fn is None:
            fn = self._compiled[id(term)] = (term, self.machine.term(term))
        fn = fn[1]
        if text is None:
            text = span_text(term.span) or f"<term at {term.span.short()}>"
            if env:
                from ..semantics.values import show
                names = _var_names(term)
                binds = ", ".join(f"{names.get(u, '$?')} = {show(v)}" for u, v in envkey)
                text = f"{text} [{binds}]"
        i = len(self.items)
        self.items.append(Atom(term, dict(env), fn, mentions_monitored(term), text, i))
        self._key[key] = i
        return i


def _var_names(term) -> dict:
    out = {}
    seen = set()

    def walk(x):
        if id(x) in seen:
            return
        seen.add(id(x))
        if isinstance(x, ir.VarRef):
            out[x.var.uid] = x.var.name
        if isinstance(x, ir.Term):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(term)
    return out


# ----------------------------------------------------------------- IR -> formula
_BOOL_CALLS = {"and", "or", "not", "implies", "iff", "xor"}


class Builder:
    """Turns property bodies into formulas over a shared :class:`Atoms` table."""

    def __init__(self, machine, atoms: Atoms, state: dict):
        self.machine = machine
        self.atoms = atoms
        self.state = state        # a state to evaluate quantifier ranges and constants in

    # does the term hold a temporal operator (or a formula-valued parameter)?
    def temporal_in(self, t, fparams: dict, seen=None) -> bool:
        seen = set() if seen is None else seen
        if id(t) in seen:
            return False
        seen.add(id(t))
        if isinstance(t, ir.Temporal):
            return True
        if isinstance(t, ir.VarRef):
            return t.var.uid in fparams
        if isinstance(t, ir.Loc) and t.func.kind in ("derived", "static") and t.func.body is not None:
            if any(self.temporal_in(a, fparams, seen) for a in t.args):
                return True
            return self.temporal_in(t.func.body, {}, seen)
        if isinstance(t, ir.Term):
            for v in vars(t).values():
                if isinstance(v, (ir.Term, list, tuple)) and self._any(v, fparams, seen):
                    return True
        return False

    def _any(self, v, fparams, seen) -> bool:
        if isinstance(v, ir.Term):
            return self.temporal_in(v, fparams, seen)
        if isinstance(v, (list, tuple)):
            return any(self._any(x, fparams, seen) for x in v)
        return False

    def _ctx(self, env):
        ctx = Ctx(self.machine, self.state, Chooser())
        ctx.env = dict(env)
        return ctx

    def build(self, t: ir.Term, kind: str, env: dict | None = None, fparams: dict | None = None):
        env = env or {}
        fparams = fparams or {}
        if not self.temporal_in(t, fparams):
            if isinstance(t, ir.Const) and t.value is True:
                return TRUE
            if isinstance(t, ir.Const) and t.value is False:
                return FALSE
            return ("ap", self.atoms.add(t, env))
        b = lambda x: self.build(x, kind, env, fparams)   # noqa: E731
        if isinstance(t, ir.VarRef):
            return fparams[t.var.uid]
        if isinstance(t, ir.Temporal):
            return self._temporal(t, kind, env, fparams)
        if isinstance(t, ir.Call) and t.name in _BOOL_CALLS:
            a = [b(x) for x in t.args]
            if t.name == "and":
                return And(a[0], a[1])
            if t.name == "or":
                return Or(a[0], a[1])
            if t.name == "not":
                return Not(a[0])
            if t.name == "implies":
                return Implies(a[0], a[1])
            if t.name == "iff":
                return Iff(a[0], a[1])
            return Not(Iff(a[0], a[1]))
        if isinstance(t, ir.Call) and t.name in ("eq", "neq") and len(t.args) == 2:
            f = Iff(b(t.args[0]), b(t.args[1]))
            return f if t.name == "eq" else Not(f)
        if isinstance(t, ir.Cond) and t.other is not None and not self.temporal_in(t.cond, fparams):
            c = b(t.cond)
            return Or(And(c, b(t.then)), And(Not(c), b(t.other)))
        if isinstance(t, ir.Quant) and t.kind in ("forall", "exists") and t.guard is not None:
            out = None
            for binding in self._bindings(t, env):
                inner = dict(env)
                inner.update(binding)
                f = self.build(t.guard, kind, inner, fparams)
                if out is None:
                    out = f
                else:
                    out = And(out, f) if t.kind == "forall" else Or(out, f)
            if out is None:
                return TRUE if t.kind == "forall" else FALSE
            return out
        if isinstance(t, ir.Loc) and t.func.body is not None and t.func.params is not None:
            # a derived function defined with temporal operators: inline its definition
            from ..semantics import types as T
            from ..semantics.machine import Thunk
            sub = {}
            venv = dict(env)
            for p, a in zip(t.func.params, t.args):
                if self.temporal_in(a, fparams) or p.type is T.BOOLEAN:
                    sub[p.uid] = b(a)
                else:
                    # passed by name: evaluated in the state where the atom is evaluated
                    venv[p.uid] = Thunk(self.machine.term(a), dict(env), None)
            return self.build(t.func.body, kind, venv, sub)
        raise FormulaError(t.span, f"asmcheck cannot check a temporal operator inside this term "
                                   f"({type(t).__name__}{' ' + t.name if isinstance(t, ir.Call) else ''})")

    def _bindings(self, t: ir.Quant, env):
        ranges = self.machine._ranges(t.bindings)
        ctx = self._ctx(env)
        out = []
        for _ in self.machine._iter_bindings(ctx, ranges):
            out.append({uid: ctx.env[uid] for uid, _, _, _ in ranges})
        return out

    def _const_int(self, t, env) -> int:
        v = self.machine.term(t)(self._ctx(env))
        if type(v) is not int:
            raise FormulaError(t.span, "the number of steps must be a constant integer")
        return v

    def _temporal(self, t: ir.Temporal, kind: str, env, fparams):
        op = t.op
        if kind == "ltl" and op not in LTL_OPS:
            raise FormulaError(t.span, f"the CTL operator {op} cannot appear in an LTLSPEC")
        if kind != "ltl" and op not in CTL_OPS:
            raise FormulaError(t.span, f"the LTL operator {op} cannot appear in a CTLSPEC")
        b = lambda x: self.build(x, kind, env, fparams)   # noqa: E731
        if kind == "ltl":
            a = [b(x) for x in t.args]
            if op == "x":
                return ("X", a[0])
            if op == "g":
                return ("R", FALSE, a[0])
            if op == "f":
                return ("U", TRUE, a[0])
            if op == "u":
                return ("U", a[0], a[1])
            if op == "v":
                return ("R", a[0], a[1])
            if op == "y":
                return ("Y", a[0])
            if op == "z":
                return ("Z", a[0])
            if op == "h":
                return Not(("S", TRUE, Not(a[0])))
            if op == "o":
                return ("S", TRUE, a[0])
            if op == "s":
                return ("S", a[0], a[1])
            return ("T", a[0], a[1])
        if op in ("exN", "axN"):
            n = self._const_int(t.args[1], env)
            if n < 1:
                raise FormulaError(t.span, f"{op} needs a number of steps of at least 1")
            f = b(t.args[0])
            for _ in range(n):
                f = EX(f) if op == "exN" else AX(f)
            return f
        a = [b(x) for x in t.args]
        if op == "ag":
            return AG(a[0])
        if op == "ef":
            return EF(a[0])
        if op == "ax":
            return AX(a[0])
        if op == "ex":
            return EX(a[0])
        if op == "eg":
            return EG(a[0])
        if op == "af":
            return AF(a[0])
        if op == "au":
            return AU(a[0], a[1])
        if op == "eu":
            return EU(a[0], a[1])
        if op == "aw":
            return AW(a[0], a[1])
        if op == "ew":
            return EW(a[0], a[1])
        if op == "absenceG":
            return AG(Not(a[0]))
        if op == "absenceBefore":          # A[(!P | AG(!R)) W R]
            p, r = a
            return AW(Or(Not(p), AG(Not(r))), r)
        if op == "absenceAfter":           # AG(Q -> AG(!P))
            p, q = a
            return AG(Implies(q, AG(Not(p))))
        if op == "absenceBetween":         # AG(Q & !R -> A[(!P | AG(!R)) W R])
            p, q, r = a
            return AG(Implies(And(q, Not(r)), AW(Or(Not(p), AG(Not(r))), r)))
        if op == "absenceAfterUntil":      # AG(Q & !R -> A[!P W R])
            p, q, r = a
            return AG(Implies(And(q, Not(r)), AW(Not(p), r)))
        if op == "ap":                     # S precedes P, globally: A[!P W S]
            p, s = a
            return AW(Not(p), s)
        if op == "pb":                     # S precedes P before R: A[(!P | AG(!R)) W (S | R)]
            p, s, r = a
            return AW(Or(Not(p), AG(Not(r))), Or(s, r))
        raise FormulaError(t.span, f"unknown temporal operator {op}")


def atoms_of(f, out=None) -> set:
    out = set() if out is None else out
    if f[0] == "ap":
        out.add(f[1])
    else:
        for x in f[1:]:
            if isinstance(x, tuple):
                atoms_of(x, out)
    return out


def show_formula(f, atoms: Atoms) -> str:
    op = f[0]
    if op == "true":
        return "TRUE"
    if op == "false":
        return "FALSE"
    if op == "ap":
        return atoms.items[f[1]].text
    if op == "not":
        return "!" + _paren(f[1], atoms)
    if op in ("and", "or"):
        sym = " & " if op == "and" else " | "
        return _paren(f[1], atoms) + sym + _paren(f[2], atoms)
    if op in ("EU", "U", "R", "S", "T"):
        word = {"EU": "U", "U": "U", "R": "V", "S": "S", "T": "T"}[op]
        inner = f"{show_formula(f[1], atoms)} {word} {show_formula(f[2], atoms)}"
        return f"E[{inner}]" if op == "EU" else f"({inner})"
    return f"{op} " + _paren(f[1], atoms)


def _paren(f, atoms):
    s = show_formula(f, atoms)
    if f[0] in ("and", "or"):
        return f"({s})"
    return s
