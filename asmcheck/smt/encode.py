"""The IR as a Z3 transition relation.

Every location (a controlled/shared/out function applied to arguments from its finite
domain) is one bit-vector variable over the *value table* of its codomain (undef is one
code; a wide integer range is read as a bit-vector integer, with native arithmetic).  One step of the main rule is executed *symbolically*, once, over generic
"current" variables: terms evaluate to guarded unions of concrete values
(:mod:`.sym`), applying the same StandardLibrary code as the step function; rules
collect guarded writes.  ``choose`` gets a fresh choice variable per execution, a
monitored location a fresh input variable per step; ``forall``, quantifiers and
comprehensions are expanded over their (finite) ranges, macro calls are inlined.

The result (:class:`StepEncoding`) holds, over the generic variables:

* ``nxt``: the code of every location after the step;
* ``errs``: conditions under which the step raises a run-time error (undef guard,
  inconsistent update, value out of its subset domain, ...);
* ``overflow``: conditions under which the step leaves what the encoding can represent
  (an Integer location leaving its ``--int-range``, a location outside its function's
  domain): a bounded answer past such a state would be unsound, so it makes it ``unknown``;
* ``constraints``: ranges of choice and input variables and the guards of ``choose``.

Constructs the encoding cannot represent raise :class:`AsmError` naming them and
their source position; the encoding never approximates.

Why this walk over the rule forms is not the step function's (semantics/terms.py and
semantics/rules.py), and why it is one module of about 1,300 lines:

* the step function compiles each IR node to a closure over *concrete* values and runs one
  branch: ``if`` and ``switch`` evaluate their guard and take one side, ``choose`` asks a
  Chooser for one binding and the explorer enumerates the others by running the step again;
  here every node is visited *once*, over guarded unions, and every branch is taken under its
  path condition ``pc`` (``choose`` becomes a fresh Z3 variable constrained by its guard);
* updates: the step function applies an update set to a dict and raises on a clash; here
  writes are guarded and merged per location, and a clash is a condition in ``errs``;
* loops: the step function runs ``while``/``iterate`` until they stop; here they are unrolled
  ``loop_bound`` times and a further iteration is an ``overflow`` (the answer becomes unknown);
* ``extend`` allocates a fresh element in the step function and is not encodable here.

A walker shared by both would have to abstract the value domain, the control flow, the
choices, the update sets and the loops at once, i.e. be both visitors behind one interface.
What does not differ is shared: the StandardLibrary functions (semantics/stdlib.py, applied
to each combination of concrete values), the static analyses (semantics/analysis.py:
is_simple, free_uids, ordered, has_sequencing, abstract_codomain) and 64-bit wrapping
(semantics/terms.wrap64).  The term visitors (``t_*``) and rule visitors (``r_*``) call each
other on every node (rules evaluate terms; turbo calls and rule-valued terms run rules), so
:class:`Encoder` stays one class in one module.
"""
from __future__ import annotations

import itertools

import z3

from ..errors import AsmError, NO_SPAN
from ..semantics import ir
from ..semantics import types as T
from ..semantics.machine import Chooser, Ctx, LONG_MAX, LONG_MIN, Undetermined
from ..semantics.terms import wrap64
from ..semantics.analysis import abstract_codomain, free_uids, has_sequencing, is_simple, ordered
from ..semantics.stdlib import BuiltinError
from ..semantics.values import BagV, MapV, RuleValue, SeqV, SetV, abstract_value, show
from . import sym
from .sym import AND, ERR, ERRU, FALSE, NOT, OR, TRUE, U, UNDEF, const, make, mapn, select, select_many

MAX_TABLE = 4096          # values of one location's codomain
MAX_INLINE = 64           # nesting of macro calls / definitions being inlined
LOOP_BOUND = 16           # turns of a while / iterate loop unrolled in one step


class Unsupported(AsmError):
    """A construct the Z3 encoding cannot represent."""

    kind = "unsupported"


def unsupported(span, what: str) -> Unsupported:
    return Unsupported(span if span is not None and span.line else None,
                       f"the Z3 engine cannot encode {what}")


class Thunk:
    """A macro argument passed by name (see machine.Thunk): re-evaluated where it is used."""

    __slots__ = ("term", "env", "self_", "loc")

    def __init__(self, term, env, self_, loc=None):
        self.term = term
        self.env = env
        self.self_ = self_
        self.loc = loc


class Write:
    __slots__ = ("guard", "value", "agent")

    def __init__(self, guard, value: U, agent: U):
        self.guard = guard
        self.value = value
        self.agent = agent


class Summary:
    """The combined effect of the writes of one location: updated?, value, agent, clash."""

    __slots__ = ("guard", "value", "agent", "clash")

    def __init__(self, guard, value, agent, clash):
        self.guard = guard
        self.value = value
        self.agent = agent
        self.clash = clash


def summarize(writes: list) -> Summary:
    if len(writes) == 1:
        w = writes[0]
        return Summary(w.guard, w.value, w.agent, FALSE)
    guard = OR([w.guard for w in writes])
    agent = select_many([(w.guard, w.agent) for w in writes[:-1]], writes[-1].agent)
    # the value: the first write's that happens (they must all agree, else the step clashes)
    value = select_many([(w.guard, w.value) for w in writes[:-1]], writes[-1].value)
    codes = [w.value.code for w in writes]
    if any(sym.has_sym(w.value) for w in writes):
        clash = OR([AND(w.guard, NOT(OR([sym.is_err(w.value), sym.same(w.value, value)]))) for w in writes])
    elif all(c is not None for c in codes) and all(c[0] is codes[0][0] for c in codes):
        clash = OR([AND(w.guard, NOT(sym.EQ(w.value.code[1], value.code[1]))) for w in writes])
    else:
        groups: dict = {}
        order = []
        for w in writes:
            for g, v in w.value.alts:
                if v is ERR:
                    continue
                k = sym.vk(v)
                if k not in groups:
                    groups[k] = []
                    order.append(k)
                groups[k].append(AND(w.guard, g))
        gs = [OR(groups[k]) for k in order]
        clash = OR([AND(a, b) for a, b in itertools.combinations(gs, 2)])
    return Summary(guard, value, agent, clash)


class Problem:
    """A guarded condition with its source position and a message (errors, overflows)."""

    __slots__ = ("guard", "span", "message")

    def __init__(self, guard, span, message):
        self.guard = guard
        self.span = span
        self.message = message


# ----------------------------------------------------------------- locations
class Locations:
    """The encoded locations of a spec: keys, value tables, generic variables."""

    def __init__(self, machine):
        self.m = machine
        spec = machine.spec
        self.tables: dict = {}        # function index -> Table
        self.keys: dict = {}          # function index -> {args tuple: key}
        self.reason: dict = {}        # function index -> why it cannot be encoded
        self.order: list = []         # every encoded key, in a fixed order
        self.kid: dict = {}           # key -> small integer id
        for f in spec.functions:
            if not f.is_location or f.kind in ("monitored", "static"):
                continue
            if f is spec.self_func or f is spec.result_func:
                continue
            why = self._why_not(f)
            if why is not None:
                self.reason[f.index] = why
                continue
            doms = [machine.domain_values(d, None, f.span) for d in f.domain]
            keys = {}
            for combo in itertools.product(*doms):
                key = machine.key_of(f, tuple(combo))
                keys[tuple(combo)] = key
                self.kid[key] = len(self.order)
                self.order.append(key)
            self.keys[f.index] = keys

    def _why_not(self, f: ir.Function) -> str | None:
        m = self.m
        if f.index in m.lazy:
            return f"the function {f.name}, initialised over an infinite domain"
        if f.kind == "local":
            return f"the local function {f.name}"
        cod = f.codomain
        if isinstance(cod, T.Struct) and cod.kind == "Rule":
            return f"the rule-valued function {f.name}"
        if isinstance(cod, T.Struct) and cod.kind in ("Seq", "Bag", "Map"):
            what = {"Seq": "sequences", "Bag": "bags", "Map": "maps"}[cod.kind]
            return f"the function {f.name}, whose values are {what} ({cod})"
        if T.root(cod) is T.REAL or any(T.root(d) is T.REAL for d in f.domain):
            return f"Real arithmetic (the function {f.name} ranges over Real)"
        for d in f.domain:
            try:
                vals = m.domain_values(d, None, f.span)
            except Undetermined:
                return f"the function {f.name}, whose domain {d} is infinite"
            if len(vals) > MAX_TABLE:
                return f"the function {f.name}, whose domain {d} has {len(vals)} elements"
        try:
            vals = m.domain_values(cod, None, f.span)
        except Undetermined:
            return f"the function {f.name}, whose codomain {cod} is infinite (bound it with a subset domain, " \
                   f"or give --int-range LO..HI)"
        if len(vals) + 1 > MAX_TABLE:
            return f"the function {f.name}, whose codomain {cod} has {len(vals)} values"
        if isinstance(cod, T.Domain) and cod.dynamic:
            return f"the function {f.name}, whose codomain {cod} is a dynamic domain"
        self.tables[f.index] = sym.Table([None] + list(vals), f.name)
        return None

    def table_of_key(self, key):
        return self.tables[key if type(key) is int else key[0]]

    def check_func(self, f: ir.Function, span):
        if f.index in self.reason:
            raise unsupported(span, self.reason[f.index])

    def var(self, key, prefix: str):
        t = self.table_of_key(key)
        return z3.BitVec(f"{prefix}{self.kid[key]}", t.width)

    def text(self, key) -> str:
        return self.m.location_text(key)


# ----------------------------------------------------------------- contexts
class SCtx:
    """Symbolic evaluation context: the state view, variables, self, the step's records."""

    __slots__ = ("enc", "view", "env", "self_", "post", "ups", "depth")

    def __init__(self, enc, view, env=None, self_=UNDEF, post=None, ups=None):
        self.enc = enc
        self.view = view          # View
        self.env = env if env is not None else {}
        self.self_ = self_
        self.post = post          # View of the state after the step (step properties)
        self.ups = ups            # the step's writes (step properties)
        self.depth = 0

    def derive(self, **kw):
        c = SCtx(self.enc, kw.get("view", self.view), kw.get("env", self.env), kw.get("self_", self.self_),
                 kw.get("post", self.post), kw.get("ups", self.ups))
        c.depth = self.depth
        return c


class View:
    """Location values: generic variables, overridden inside seq blocks."""

    __slots__ = ("locs", "prefix", "over", "cache", "parent")

    def __init__(self, locs: Locations, prefix: str, parent=None):
        self.locs = locs
        self.prefix = prefix
        self.over: dict = {}
        self.cache: dict = {} if parent is None else parent.cache
        self.parent = parent

    def child(self) -> "View":
        v = View(self.locs, self.prefix, self)
        v.over = dict(self.over)
        return v

    def read(self, key) -> U:
        u = self.over.get(key)
        if u is not None:
            return u
        u = self.cache.get(key)
        if u is None:
            t = self.locs.table_of_key(key)
            u = t.union(self.locs.var(key, self.prefix))
            self.cache[key] = u
        return u


# ----------------------------------------------------------------- the encoder
class Encoder:
    """Symbolic execution of terms and rules (one instance per spec)."""

    def __init__(self, machine, locs: Locations | None = None):
        self.m = machine
        self.spec = machine.spec
        self.locs = locs or Locations(machine)
        self.static_cache: dict = {}
        self.pure_cache: dict = {}
        self._compiled: dict = {}
        self.nchoice = 0
        self.loop_bound = LOOP_BOUND
        # per step being encoded
        self.errs: list = []
        self.overflow: list = []
        self.constraints: list = []
        self.mon: dict = {}
        self.choice_vars: list = []
        self.mon_vars: list = []
        self.mon_tables: dict = {}

    # -------------------------------------------------------------- problems
    def error(self, guard, span, message):
        if not sym.is_f(guard):
            self.errs.append(Problem(guard, span, message))

    def overflowed(self, guard, span, message):
        if not sym.is_f(guard):
            self.overflow.append(Problem(guard, span, message))

    # -------------------------------------------------------------- terms
    def ev(self, t: ir.Term, ctx: SCtx) -> U:
        try:
            return getattr(self, "t_" + type(t).__name__)(t, ctx)
        except sym.TooWide as e:
            raise unsupported(t.span, str(e)) from None

    def t_Const(self, t, ctx):
        return const(t.value)

    def t_VarRef(self, t, ctx):
        try:
            v = ctx.env[t.var.uid]
        except KeyError:
            return ERRU
        if type(v) is Thunk:
            return self.ev(v.term, ctx.derive(env=v.env, self_=v.self_))
        return v

    def t_Loc(self, t, ctx):
        f = t.func
        if f is self.spec.self_func:
            return ctx.self_
        if f.kind == "static" and f.arity == 0 and abstract_codomain(f):
            return const(abstract_value(f.codomain.name, f.name))
        if f.kind in ("static", "derived") and f.body is not None:
            return self.defined(f, t, ctx)
        if f.kind == "static" and f.body is None:
            return UNDEF
        args = [self.ev(a, ctx) for a in t.args]
        if f.kind == "monitored":
            return self.monitored(f, args, t.span)
        self.locs.check_func(f, t.span)
        return self.read_loc(f, args, ctx.view)

    def key_union(self, f, args: list) -> U:
        return mapn(args, lambda *vs: ERR if any(v is ERR for v in vs) else tuple(vs))

    def read_loc(self, f, args: list, view: View) -> U:
        keys = self.locs.keys[f.index]
        if not args:
            return view.read(f.index)
        ku = self.key_union(f, args)
        cases = []
        for g, vals in ku.alts:
            if vals is ERR:
                cases.append((g, ERRU))
                continue
            key = keys.get(vals)
            # a location outside the function's domain is never written (that is an overflow)
            cases.append((g, view.read(key) if key is not None else UNDEF))
        if len(cases) == 1:
            return cases[0][1]
        return select_many(cases[:-1], cases[-1][1])

    def defined(self, f: ir.Function, t: ir.Loc, ctx: SCtx) -> U:
        args = [self.ev(a, ctx) for a in t.args]
        if self.is_pure(f):
            return mapn(args, lambda *vs: self.eval_pure(f, vs, t.span))
        if ctx.depth > MAX_INLINE:
            raise unsupported(t.span, f"the recursive definition of {f.name}")
        env = {p.uid: a for p, a in zip(f.params, args)}
        sub = ctx.derive(env=env)
        sub.depth = ctx.depth + 1
        body = self.ev(f.body, sub)
        err = OR([sym.is_err(a) for a in args])
        return select(err, ERRU, body) if not sym.is_f(err) else body

    def is_pure(self, f: ir.Function) -> bool:
        """A definition that reads no dynamic function (its value depends on its arguments only)."""
        r = self.pure_cache.get(f)
        if r is None:
            self.pure_cache[f] = True     # recursion: assume pure while looking
            r = _reads_no_state(f.body, self.spec, set())
            self.pure_cache[f] = r
        return r

    def eval_pure(self, f: ir.Function, vals, span):
        if any(v is ERR for v in vals):
            return ERR
        key = (f, tuple(sym.vk(v) for v in vals))
        if key in self.static_cache:
            return self.static_cache[key]
        fn = self._compiled.get(f)
        if fn is None:
            fn = self._compiled[f] = self.m.term(f.body)
        ctx = Ctx(self.m, {}, Chooser())
        ctx.env = {p.uid: v for p, v in zip(f.params, vals)}
        try:
            v = fn(ctx)
        except Undetermined as e:
            raise unsupported(e.span or span, e.message) from None
        except AsmError:
            v = ERR
        self.static_cache[key] = v
        return v

    def monitored(self, f: ir.Function, args: list, span) -> U:
        try:
            options = self.m.monitored_options(f, None, span)
        except Undetermined as e:
            raise unsupported(e.span or span, f"the monitored function {f.name}: {e.message}") from None
        table = self.mon_tables.get(f.index)
        if table is None:
            table = self.mon_tables[f.index] = sym.Table(list(options), f.name)
        ku = self.key_union(f, args)
        cases = []
        for g, vals in ku.alts:
            if vals is ERR:
                cases.append((g, ERRU))
                continue
            key = self.m.key_of(f, vals)
            u = self.mon.get(key)
            if u is None:
                if len(table) == 0:
                    raise unsupported(span, f"the monitored function {f.name} with no value")
                x = z3.BitVec(f"m{len(self.mon_vars)}", table.width)
                self.mon_vars.append((x, key, table))
                self.constraints.append(table.in_range(x))
                u = self.mon[key] = table.union(x)
            cases.append((g, u))
        if len(cases) == 1:
            return cases[0][1]
        return select_many(cases[:-1], cases[-1][1])

    def t_Call(self, t, ctx):
        name = t.name
        if name == "program":
            a = self.ev(t.args[0], ctx)
            return sym.map1(a, lambda v: self._program(v, t.span))
        args = [self.ev(a, ctx) for a in t.args]
        if name == "and":
            return mapn(args, _and)
        if name == "or":
            return mapn(args, _or)
        if name == "implies":
            return mapn(args, _implies)
        if name in ("eq", "neq") and len(args) == 2:
            a, b = args
            err = OR([sym.is_err(a), sym.is_err(b)])
            eq = sym.same(a, b)
            yes, no = (True, False) if name == "eq" else (False, True)
            return make([(err, ERR), (AND(NOT(err), eq), yes), (AND(NOT(err), NOT(eq)), no)])
        if name == "not":
            return sym.map1(args[0], lambda x: ERR if x is ERR else (None if x is None else not x))
        impl = t.impl
        if impl is None:
            raise unsupported(t.span, f"the function {name}")
        if name in _SYM_OPS and any(sym.has_sym(a) for a in args):
            return _arith(name, args, impl)
        return mapn(args, lambda *vs: _concrete(name, impl, vs))

    def _program(self, agent, span):
        if agent is ERR:
            return ERR
        try:
            return self.m.program_of(agent, span)
        except AsmError:
            return ERR

    def t_Temporal(self, t, ctx):
        return ERRU

    def t_StepOp(self, t, ctx):
        if ctx.post is None:
            return ERRU
        op = t.op
        if op == "next":
            return self.ev(t.args[0], ctx.derive(view=ctx.post))
        loc = t.args[-1]
        f = loc.func
        if op == "changed":
            before = self.ev(loc, ctx)
            after = self.ev(loc, ctx.derive(view=ctx.post))
            err = OR([sym.is_err(before), sym.is_err(after)])
            eq = sym.same(before, after)
            return make([(err, ERR), (AND(NOT(err), eq), False), (AND(NOT(err), NOT(eq)), True)])
        self.locs.check_func(f, loc.span)
        args = [self.ev(a, ctx) for a in loc.args]
        ku = self.key_union(f, args)
        agent = self.ev(t.args[0], ctx) if op == "updatedBy" else None
        cases = []
        for g, vals in ku.alts:
            if vals is ERR:
                cases.append((g, ERRU))
                continue
            key = self.locs.keys[f.index].get(vals)
            writes = ctx.ups.get(key) if key is not None else None
            if not writes:
                cases.append((g, const(False)))
                continue
            s = summarize(writes)
            if op == "updated":
                cases.append((g, make([(s.guard, True), (NOT(s.guard), False)])))
            else:
                err = sym.is_err(agent)
                eq = sym.same(s.agent, agent)
                cases.append((g, make([(NOT(s.guard), False), (AND(s.guard, err), ERR),
                                       (AND(s.guard, NOT(err), eq), True),
                                       (AND(s.guard, NOT(err), NOT(eq)), False)])))
        if len(cases) == 1:
            return cases[0][1]
        return select_many(cases[:-1], cases[-1][1])

    def t_DomainTerm(self, t, ctx):
        return const(SetV(self.domain_values(t.domain, t.span)))

    def domain_values(self, dom, span) -> list:
        if isinstance(dom, T.Domain) and dom.dynamic and not T.agent_like(dom):
            raise unsupported(span, f"the dynamic domain {dom}")
        try:
            return self.m.domain_values(dom, None, span)
        except Undetermined as e:
            raise unsupported(e.span or span, f"a range over {dom}: {e.message}") from None

    def t_Cond(self, t, ctx):
        c = self.ev(t.cond, ctx)
        yes, no = sym.is_true(c), sym.is_false(c)
        cases = []
        if not sym.is_f(yes):
            cases.append((yes, self.ev(t.then, ctx)))
        if not sym.is_f(no):
            cases.append((no, self.ev(t.other, ctx) if t.other is not None else UNDEF))
        return select_many(cases, ERRU)

    def t_Switch(self, t, ctx):
        subj = self.ev(t.subject, ctx)
        cases = [(sym.is_err(subj), ERRU)]
        for ct, rt in t.cases:
            c = self.ev(ct, ctx)
            cases.append((sym.is_err(c), ERRU))
            m = sym.same(subj, c)
            if not sym.is_f(m):
                cases.append((m, self.ev(rt, ctx)))
        other = self.ev(t.other, ctx) if t.other is not None else UNDEF
        return select_many(cases, other)

    def t_Let(self, t, ctx):
        env = dict(ctx.env)
        sub = ctx.derive(env=env)
        errs = []
        for v, x in t.bindings:
            val = self.ev(x, sub)
            errs.append(sym.is_err(val))
            env[v.uid] = val
        body = self.ev(t.body, sub)
        err = OR(errs)
        return select(err, ERRU, body) if not sym.is_f(err) else body

    # ranges: [(guard, [env | ERR, ...])], the sequences of bindings a range walks through
    def bindings(self, binds, ctx: SCtx) -> list:
        bound = set()
        plan = []
        for v, r in binds:
            plan.append((v, r, bool(free_uids(r) & bound)))
            bound.add(v.uid)
        if len(plan) > 1 and not any(dep for _, _, dep in plan):
            # independent ranges: all evaluated first (as the step function does)
            lists = [self.range_items(r, ctx) for _, r, _ in plan]
            out = []
            for combo in itertools.product(*lists):
                g = AND(*[c[0] for c in combo])
                if sym.is_f(g):
                    continue
                if any(c[1] is ERR for c in combo):
                    out.append((g, [ERR]))
                    continue
                seq = []
                for vals in itertools.product(*[c[1] for c in combo]):
                    seq.append({v.uid: const(x) for (v, _, _), x in zip(plan, vals)})
                out.append((g, seq))
            return out
        return self._nested(plan, 0, ctx, {}, TRUE)

    def _nested(self, plan, i, ctx, binding: dict, g) -> list:
        if i == len(plan):
            return [(g, [binding])]
        v, r, _ = plan[i]
        sub = ctx.derive(env={**ctx.env, **binding}) if binding else ctx
        out = []
        for g2, items in self.range_items(r, sub):
            gg = AND(g, g2)
            if sym.is_f(gg):
                continue
            if items is ERR:
                out.append((gg, [ERR]))
                continue
            seqs = [(gg, [])]
            for x in items:
                b2 = dict(binding)
                b2[v.uid] = const(x)
                rest = self._nested(plan, i + 1, ctx, b2, TRUE)
                nxt = []
                for ga, la in seqs:
                    if la and la[-1] is ERR:
                        nxt.append((ga, la))
                        continue
                    for gb, lb in rest:
                        gab = AND(ga, gb)
                        if not sym.is_f(gab):
                            nxt.append((gab, la + lb))
                seqs = nxt
            out.extend(seqs)
        return out

    def range_items(self, r: ir.Term, ctx: SCtx) -> list:
        """[(guard, ordered list of elements | ERR)]"""
        if isinstance(r, ir.DomainTerm):
            return [(TRUE, self.domain_values(r.domain, r.span))]
        u = self.ev(r, ctx)
        out = []
        for g, coll in u.alts:
            if coll is ERR or coll is None:
                out.append((g, ERR))
                continue
            try:
                out.append((g, ordered(coll, r.span)))
            except (AsmError, TypeError):
                out.append((g, ERR))
        return out

    def _guard_of(self, guard, env, ctx) -> U:
        if guard is None:
            return const(True)
        return self.ev(guard, ctx.derive(env={**ctx.env, **env}))

    def t_Quant(self, t, ctx):
        alts = []
        for g, seq in self.bindings(t.bindings, ctx):
            if t.kind == "exists_unique":
                r0, r1 = const(False), const(True)
                for item in reversed(seq):
                    if item is ERR:
                        r0 = r1 = ERRU
                        continue
                    G = self._guard_of(t.guard, item, ctx)
                    yes, no = sym.is_true(G), sym.is_false(G)
                    r0, r1 = (select_many([(yes, r1), (no, r0)], ERRU),
                              select_many([(yes, const(False)), (no, r1)], ERRU))
                res = r0
            else:
                forall = t.kind == "forall"
                res = const(forall)
                for item in reversed(seq):
                    if item is ERR:
                        res = ERRU
                        continue
                    G = self._guard_of(t.guard, item, ctx)
                    yes, no = sym.is_true(G), sym.is_false(G)
                    if forall:
                        res = select_many([(yes, res), (no, const(False))], ERRU)
                    else:
                        res = select_many([(yes, const(True)), (no, res)], ERRU)
            alts.append((g, res))
        return select_many(alts[:-1], alts[-1][1]) if alts else const(t.kind == "forall")

    def t_Compr(self, t, ctx):
        kind = t.kind
        alts = []
        for g, seq in self.bindings(t.bindings, ctx):
            acc = const(())
            for item in seq:
                if item is ERR:
                    acc = ERRU
                    break
                sub = ctx.derive(env={**ctx.env, **item})
                G = self.ev(t.guard, sub) if t.guard is not None else const(True)
                yes, no = sym.is_true(G), sym.is_false(G)
                if sym.is_f(yes):
                    acc = select(no, acc, ERRU)
                    continue
                body = self.ev(t.body, sub)
                if t.body2 is not None:
                    b2 = self.ev(t.body2, sub)
                    body = mapn([body, b2], lambda a, b: ERR if a is ERR or b is ERR else (a, b))
                added = mapn([acc, body], lambda a, b: ERR if a is ERR or b is ERR else a + (b,))
                acc = select_many([(yes, added), (no, acc)], ERRU)
            alts.append((g, acc))
        u = select_many(alts[:-1], alts[-1][1]) if alts else const(())

        def build(items):
            if items is ERR:
                return ERR
            if kind == "set":
                return SetV(items)
            if kind == "seq":
                return SeqV(items)
            if kind == "bag":
                return BagV.of(items)
            return MapV.of(items)
        return sym.map1(u, build)

    def t_Collection(self, t, ctx):
        items = [self.ev(x, ctx) for x in t.items]
        kind = t.kind

        def build(*vs):
            if any(v is ERR for v in vs):
                return ERR
            if kind == "set":
                return SetV(vs)
            if kind == "seq":
                return SeqV(vs)
            return BagV.of(vs)
        return mapn(items, build)

    def t_Range(self, t, ctx):
        parts = [self.ev(t.start, ctx), self.ev(t.end, ctx),
                 self.ev(t.step, ctx) if t.step is not None else const(1)]
        kind = t.kind

        def build(lo, hi, st):
            if lo is ERR or hi is ERR or st is ERR or lo is None or hi is None or st is None:
                return ERR
            try:
                if st <= 0:
                    return ERR
                vals = []
                x = lo
                while x <= hi:
                    vals.append(x)
                    x += st
                    if len(vals) > 100_000:
                        return ERR
            except TypeError:
                return ERR
            if kind == "set":
                return SetV(vals)
            if kind == "seq":
                return SeqV(vals)
            return BagV.of(vals)
        return mapn(parts, build)

    def t_MapLit(self, t, ctx):
        flat = []
        for k, v in t.pairs:
            flat.append(self.ev(k, ctx))
            flat.append(self.ev(v, ctx))

        def build(*vs):
            if any(v is ERR for v in vs):
                return ERR
            return MapV.of(list(zip(vs[0::2], vs[1::2])))
        return mapn(flat, build)

    def t_TupleLit(self, t, ctx):
        items = [self.ev(x, ctx) for x in t.items]
        return mapn(items, lambda *vs: ERR if any(v is ERR for v in vs) else tuple(vs))

    def t_RuleRef(self, t, ctx):
        return const(RuleValue(t.rule))

    # -------------------------------------------------------------- rules
    def ex(self, r: ir.Rule, ctx: SCtx, pc, ups: dict) -> None:
        if sym.is_f(pc):
            return
        try:
            getattr(self, "r_" + type(r).__name__)(r, ctx, pc, ups)
        except sym.TooWide as e:
            raise unsupported(r.span, str(e)) from None

    def r_Skip(self, r, ctx, pc, ups):
        pass

    def write(self, f: ir.Function, args: list, value: U, ctx: SCtx, pc, ups: dict, span) -> None:
        self.locs.check_func(f, span)
        err = OR([sym.is_err(value)] + [sym.is_err(a) for a in args])
        self.error(AND(pc, err), span, "a term of the update cannot be evaluated")
        cod = f.codomain
        if isinstance(cod, T.Domain) and cod.kind == "subset" and cod.definition is not None:
            allowed = self.domain_values(cod, span)
            bad = _outside(value, allowed)
            self.error(AND(pc, bad), span, f"value out of domain {cod.name} (the codomain of {f.name})")
        keys = self.locs.keys[f.index]
        if not args:
            ups.setdefault(f.index, []).append(Write(pc, value, ctx.self_))
            return
        ku = self.key_union(f, args)
        for g, vals in ku.alts:
            if vals is ERR:
                continue
            key = keys.get(vals)
            if key is None:
                self.overflowed(AND(pc, g), span, f"an update of {f.name}({', '.join(show(v) for v in vals)}), "
                                                  f"outside the domain of {f.name}")
                continue
            ups.setdefault(key, []).append(Write(AND(pc, g), value, ctx.self_))

    def r_Update(self, r, ctx, pc, ups):
        value = self.ev(r.value, ctx)
        args = [self.ev(a, ctx) for a in r.args]
        self.write(r.func, args, value, ctx, pc, ups, r.span)

    def r_UpdateVar(self, r, ctx, pc, ups):
        uid = r.var.uid
        cur = ctx.env.get(uid)
        value = self.ev(r.value, ctx)
        if type(cur) is Thunk and cur.loc is not None:
            f, arg_terms = cur.loc
            sub = ctx.derive(env=cur.env, self_=cur.self_)
            args = [self.ev(a, sub) for a in arg_terms]
            self.error(AND(pc, sym.is_err(value)), r.span, "the value cannot be evaluated")
            self.locs.check_func(f, r.span)
            if not args:
                ups.setdefault(f.index, []).append(Write(pc, value, ctx.self_))
                return
            self.write(f, args, value, ctx, pc, ups, r.span)
            return
        if type(cur) is Thunk:
            old = self.ev(cur.term, ctx.derive(env=cur.env, self_=cur.self_))
        else:
            old = cur if isinstance(cur, U) else UNDEF
        ctx.env[uid] = select(pc, value, old)

    def r_Block(self, r, ctx, pc, ups):
        if r.kind == "par":
            for x in r.rules:
                self.ex(x, ctx, pc, ups)
            return
        work = ctx.view.child()
        sub_ctx = ctx.derive(view=work)
        local: dict = {}
        for x in r.rules:
            sub: dict = {}
            self.ex(x, sub_ctx, pc, sub)
            for key, writes in sub.items():
                s = summarize(writes)
                self.error(s.clash, x.span, f"inconsistent update of {self.locs.text(key)}")
                work.over[key] = select(s.guard, s.value, work.read(key))
                old = local.get(key)
                if old is None:
                    local[key] = Write(s.guard, s.value, s.agent)
                else:
                    local[key] = Write(OR([old.guard, s.guard]), select(s.guard, s.value, old.value),
                                       select(s.guard, s.agent, old.agent))
        for key, w in local.items():
            ups.setdefault(key, []).append(w)

    def r_If(self, r, ctx, pc, ups):
        c = self.ev(r.cond, ctx)
        self.error(AND(pc, sym.not_bool(c)), r.cond.span, "the guard is undef")
        self.ex(r.then, ctx, AND(pc, sym.is_true(c)), ups)
        if r.other is not None:
            self.ex(r.other, ctx, AND(pc, sym.is_false(c)), ups)

    def r_SwitchRule(self, r, ctx, pc, ups):
        subj = self.ev(r.subject, ctx)
        self.error(AND(pc, sym.is_err(subj)), r.span, "the switch subject cannot be evaluated")
        reach = AND(pc, NOT(sym.is_err(subj)))
        for ct, body in r.cases:
            if sym.is_f(reach):
                return
            c = self.ev(ct, ctx)
            self.error(AND(reach, sym.is_err(c)), r.span, "a case cannot be evaluated")
            reach = AND(reach, NOT(sym.is_err(c)))
            m = sym.same(subj, c)
            self.ex(body, ctx, AND(reach, m), ups)
            reach = AND(reach, NOT(m))
        if r.other is not None:
            self.ex(r.other, ctx, reach, ups)

    def r_LetRule(self, r, ctx, pc, ups):
        env = dict(ctx.env)
        sub = ctx.derive(env=env)
        errs = []
        for v, x in r.bindings:
            val = self.ev(x, sub)
            errs.append(sym.is_err(val))
            env[v.uid] = val
        err = OR(errs)
        self.error(AND(pc, err), r.span, "a let binding cannot be evaluated")
        self.ex(r.body, sub, AND(pc, NOT(err)), ups)

    def r_Choose(self, r, ctx, pc, ups):
        uids = [v.uid for v, _ in r.bindings]
        for g, seq in self.bindings(r.bindings, ctx):
            gp = AND(pc, g)
            if sym.is_f(gp):
                continue
            if any(item is ERR for item in seq):
                self.error(gp, r.span, "the range of choose cannot be evaluated")
                continue
            guards = [self._guard_of(r.guard, item, ctx) for item in seq]
            err = OR([sym.not_bool(G) for G in guards])
            self.error(AND(gp, err), r.span, "the choose condition is undef")
            ok = AND(gp, NOT(err))
            yes = [sym.is_true(G) for G in guards]
            some = OR(yes)
            none = NOT(some)
            if r.ifnone is not None:
                self.ex(r.ifnone, ctx, AND(ok, none), ups)
            if sym.is_f(some):
                continue
            n = len(seq)
            if n == 1:
                self._with(r.body, ctx, seq[0], AND(ok, some), ups)
                continue
            width = max(1, (n - 1).bit_length())
            x = z3.BitVec(f"c{self.nchoice}", width)
            self.nchoice += 1
            self.choice_vars.append(x)
            picks = [x == z3.BitVecVal(i, width) for i in range(n)]
            if n != 1 << width:
                self.constraints.append(z3.ULT(x, z3.BitVecVal(n, width)))
            self.constraints.append(z3.Implies(some, OR([AND(p, y) for p, y in zip(picks, yes)])))
            binding = {uid: make([(p, item[uid].alts[0][1]) for p, item in zip(picks, seq)]) for uid in uids}
            self._with(r.body, ctx, binding, AND(ok, some), ups)

    def r_Forall(self, r, ctx, pc, ups):
        for g, seq in self.bindings(r.bindings, ctx):
            gp = AND(pc, g)
            if sym.is_f(gp):
                continue
            for item in seq:
                if item is ERR:
                    self.error(gp, r.span, "the range of forall cannot be evaluated")
                    break
                G = self._guard_of(r.guard, item, ctx)
                self.error(AND(gp, sym.not_bool(G)), r.span, "the forall condition is undef")
                self._with(r.body, ctx, item, AND(gp, sym.is_true(G)), ups)

    def _with(self, body, ctx, binding: dict, pc, ups):
        """Run body with variables bound in the current environment, restored afterwards
        (other variables the body assigns keep their new values, as in the step function)."""
        env = ctx.env
        saved = {u: env[u] for u in binding if u in env}
        env.update(binding)
        try:
            self.ex(body, ctx, pc, ups)
        finally:
            for u in binding:
                if u in saved:
                    env[u] = saved[u]
                else:
                    env.pop(u, None)

    def r_Extend(self, r, ctx, pc, ups):
        raise unsupported(r.span, f"extend (new elements of {r.domain})")

    def r_CallRule(self, r, ctx, pc, ups):
        rd = r.rule
        if ctx.depth > MAX_INLINE:
            raise unsupported(r.span, f"the recursive rule {rd.name}")
        by_name = not r.turbo and has_sequencing(rd)
        vals = []
        errs = []
        for a in r.args:
            if r.turbo:
                v = self.ev(a, ctx)
                errs.append(sym.is_err(v))
            elif isinstance(a, ir.VarRef):
                v = ctx.env.get(a.var.uid)
                if v is None:
                    v = self.ev(a, ctx)
            elif isinstance(a, ir.Loc) and a.func.is_location and a.func.kind != "monitored" and not (
                    a.func.kind == "static"):
                v = Thunk(a, ctx.env, ctx.self_, (a.func, a.args))
            elif by_name and not is_simple(a):
                v = Thunk(a, ctx.env, ctx.self_)
            else:
                v = self.ev(a, ctx)
                errs.append(sym.is_err(v))
            vals.append(v)
        err = OR(errs)
        self.error(AND(pc, err), r.span, f"an argument of {rd.name} cannot be evaluated")
        sub = ctx.derive(env={p.uid: v for p, v in zip(rd.params, vals)})
        sub.depth = ctx.depth + 1
        if rd.body is None:
            raise unsupported(r.span, f"the rule {rd.name} without a body")
        self.ex(rd.body, sub, AND(pc, NOT(err)), ups)

    def r_TermCall(self, r, ctx, pc, ups):
        rv = self.ev(r.term, ctx)
        args = [self.ev(a, ctx) for a in r.args]
        for g, v in rv.alts:
            gp = AND(pc, g)
            if sym.is_f(gp):
                continue
            if not isinstance(v, RuleValue):
                self.error(gp, r.span, "the rule to run is undef" if v is None else "not a rule")
                continue
            rd = v.rule
            vals = args if args else [const(x) for x in v.args]
            if len(vals) != len(rd.params):
                self.error(gp, r.span, f"{rd.name} takes {len(rd.params)} argument(s)")
                continue
            err = OR([sym.is_err(a) for a in vals])
            self.error(AND(gp, err), r.span, "an argument cannot be evaluated")
            if ctx.depth > MAX_INLINE:
                raise unsupported(r.span, f"the recursive rule {rd.name}")
            sub = ctx.derive(env={p.uid: a for p, a in zip(rd.params, vals)},
                             self_=const(v.agent) if v.agent is not None else ctx.self_)
            sub.depth = ctx.depth + 1
            self.ex(rd.body, sub, AND(gp, NOT(err)), ups)

    def r_TurboReturn(self, r, ctx, pc, ups):
        raise unsupported(r.span, "a turbo rule returning a value")

    def r_Loop(self, r, ctx, pc, ups):
        """while / iterate, unrolled LOOP_BOUND times: each turn runs on the state the turns
        before made (as a seq); a loop that may still go on after the last turn is an
        overflow (the answer becomes unknown), never cut short silently."""
        if r.kind == "whilerec":
            raise unsupported(r.span, "the whilerec loop")
        work = ctx.view.child()
        sub_ctx = ctx.derive(view=work)
        local: dict = {}
        active = pc
        for _ in range(self.loop_bound):
            if sym.is_f(active):
                break
            if r.cond is not None:
                c = self.ev(r.cond, sub_ctx)
                self.error(AND(active, sym.not_bool(c)), r.cond.span, "the loop condition is undef")
                active = AND(active, sym.is_true(c))
            sub: dict = {}
            self.ex(r.body, sub_ctx, active, sub)
            summaries = {key: summarize(writes) for key, writes in sub.items()}
            for key, s_ in summaries.items():
                self.error(s_.clash, r.span, f"inconsistent update of {self.locs.text(key)}")
            if r.cond is None:
                # iterate: ends (without this turn's updates) when the body changes nothing
                changed = OR([AND(s_.guard, NOT(sym.same(s_.value, work.read(key)))) for key, s_ in summaries.items()])
                active = AND(active, changed)
            for key, s_ in summaries.items():
                g = AND(active, s_.guard)
                work.over[key] = select(g, s_.value, work.read(key))
                old = local.get(key)
                if old is None:
                    local[key] = Write(g, s_.value, s_.agent)
                else:
                    local[key] = Write(OR([old.guard, g]), select(g, s_.value, old.value), select(g, s_.agent, old.agent))
        if not sym.is_f(active):
            more = active
            if r.cond is not None:
                c = self.ev(r.cond, sub_ctx)
                more = AND(active, NOT(sym.is_false(c)))
            self.overflowed(more, r.span, f"the {r.kind} loop running more than {self.loop_bound} times "
                                          f"(raise --loop-bound)")
        for key, w in local.items():
            ups.setdefault(key, []).append(w)

    def r_LocalRule(self, r, ctx, pc, ups):
        raise unsupported(r.span, "local functions of a rule")


_SYM_OPS = {"plus", "minus", "mult", "lt", "le", "gt", "ge", "mod", "idiv"}


def _arith(name: str, args: list, impl) -> U:
    """Integer operations with symbolic operands, as bit-vector terms (64-bit wrap-around
    as the step function's)."""
    combos = [(TRUE, [])]
    for u in args:
        combos = [(AND(g, g2), vals + [v]) for g, vals in combos for g2, v in u.alts if not sym.is_f(AND(g, g2))]
    out = []
    for g, vals in combos:
        if any(v is ERR for v in vals):
            out.append((g, ERR))
            continue
        if any(v is None for v in vals):
            out.append((g, None))
            continue
        if not all(type(v) in (int, sym.SymInt) for v in vals):
            # not integers after all (Reals, ...): split the symbolic ones into values
            sub = mapn([make([(TRUE, v)]) for v in vals], lambda *vs: _concrete(name, impl, vs))
            out.extend((AND(g, g2), v) for g2, v in sub.alts)
            continue
        ops = [v if type(v) is sym.SymInt else sym.SymInt.of(v) for v in vals]
        out.extend((AND(g, g2), v) for g2, v in _sym_op(name, ops))
    return make(out)


def _concrete(name, impl, vals):
    if any(v is ERR for v in vals):
        return ERR
    if len(vals) == 2 and name in _FAST2:
        x, y = vals
        if x is None or y is None:
            return None
        try:
            r = _FAST2[name](x, y)
        except TypeError:
            return ERR
        if type(r) is int and not (LONG_MIN <= r <= LONG_MAX):
            return wrap64(r)
        return r
    try:
        return impl(*vals)
    except (BuiltinError, TypeError, ValueError, ZeroDivisionError, OverflowError, AttributeError, IndexError):
        return ERR


def _result(e, lo, hi):
    """A symbolic integer for e, whose mathematical value lies in [lo, hi] (wrapped to 64 bits)."""
    if lo < LONG_MIN or hi > LONG_MAX:
        e = sym.sx(e, 64) if e.size() < 64 else (z3.Extract(63, 0, e) if e.size() > 64 else e)
        return sym.SymInt(e, LONG_MIN, LONG_MAX)
    w = sym.sbits(lo, hi)
    if e.size() > w:
        e = z3.Extract(w - 1, 0, e)
    return sym.SymInt(e, lo, hi)


def _sym_op(name, ops):
    if len(ops) == 1:
        a = ops[0]
        if name == "minus":
            w = max(a.width, sym.sbits(-a.hi, -a.lo)) + 1
            return [(TRUE, _result(-sym.sx(a.e, w), -a.hi, -a.lo))]
        return [(TRUE, a)]
    a, b = ops
    if name in ("lt", "le", "gt", "ge"):
        w = max(a.width, b.width)
        x, y = sym.sx(a.e, w), sym.sx(b.e, w)
        c = {"lt": x < y, "le": x <= y, "gt": x > y, "ge": x >= y}[name]      # signed comparisons
        return [(c, True), (NOT(c), False)]
    if name in ("plus", "minus", "mult"):
        if name == "plus":
            lo, hi = a.lo + b.lo, a.hi + b.hi
        elif name == "minus":
            lo, hi = a.lo - b.hi, a.hi - b.lo
        else:
            ends = [a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi]
            lo, hi = min(ends), max(ends)
        w = min(max(a.width, b.width, sym.sbits(lo, hi)) + (a.width + b.width if name == "mult" else 1), 128)
        x, y = sym.sx(a.e, w), sym.sx(b.e, w)
        e = x + y if name == "plus" else (x - y if name == "minus" else x * y)
        return [(TRUE, _result(e, lo, hi))]
    # mod, idiv: Java's remainder and division (truncating); by zero is an error
    zero = sym.EQ(b.e, z3.BitVecVal(0, b.width)) if b.lo <= 0 <= b.hi else FALSE
    w = max(a.width, b.width) + 1
    x, y = sym.sx(a.e, w), sym.sx(b.e, w)
    m = max(abs(b.lo), abs(b.hi))
    if name == "mod":
        e = z3.SRem(x, y)
        if a.lo >= 0:
            lo, hi = 0, min(a.hi, m - 1)
        elif a.hi <= 0:
            lo, hi = max(a.lo, -(m - 1)), 0
        else:
            lo, hi = -(m - 1), m - 1
    else:
        e = x / y          # bvsdiv: truncates toward zero
        big = max(abs(a.lo), abs(a.hi))
        lo, hi = -big, big
    lo, hi = min(lo, hi), max(lo, hi)
    return [(zero, ERR), (NOT(zero), _result(e, lo, hi))]


_FAST2 = {"plus": lambda x, y: x + y, "minus": lambda x, y: x - y, "mult": lambda x, y: x * y,
          "lt": lambda x, y: x < y, "le": lambda x, y: x <= y, "gt": lambda x, y: x > y,
          "ge": lambda x, y: x >= y}


def _and(x, y):
    if x is ERR:
        return ERR
    if x is False:
        return False
    if y is ERR:
        return ERR
    if y is False:
        return False
    if x is None or y is None:
        return None
    return True


def _or(x, y):
    if x is ERR:
        return ERR
    if x is True:
        return True
    if y is ERR:
        return ERR
    if y is True:
        return True
    if x is None or y is None:
        return None
    return False


def _implies(x, y):
    if x is ERR:
        return ERR
    if x is False:
        return True
    if y is ERR:
        return ERR
    if y is True:
        return True
    if x is None or y is None:
        return None
    return False


def _outside(u: U, allowed: list):
    """The guard of a defined value not in ``allowed`` (the step function's range check)."""
    ints = [v for v in allowed if type(v) is int]
    contiguous = len(ints) == len(allowed) and ints and ints == list(range(ints[0], ints[0] + len(ints)))
    out = []
    for g, v in u.alts:
        if type(v) is sym.SymInt:
            if contiguous:
                lo, hi = ints[0], ints[-1]
                w = max(v.width, sym.sbits(lo, hi))
                e = sym.sx(v.e, w)
                out.append(AND(g, OR([(e < z3.BitVecVal(lo, w)) if v.lo < lo else FALSE,
                                      (e > z3.BitVecVal(hi, w)) if v.hi > hi else FALSE])))
            else:
                out.append(AND(g, sym.guard_of(sym.expand(U([(TRUE, v)])),
                                               lambda x: not _member(x, allowed))))
        elif v is not ERR and v is not None and not _member(v, allowed):
            out.append(g)
    return OR(out)


def _member(v, allowed) -> bool:
    # the step function checks `v in set(allowed)` (Python equality)
    try:
        return v in set(allowed)
    except TypeError:
        return any(v == a for a in allowed)


def _reads_no_state(t, spec, seen: set) -> bool:
    """No dynamic function, no self, no step operator anywhere in t (through definitions)."""
    ok = True

    def walk(x):
        nonlocal ok
        if not ok:
            return
        if isinstance(x, ir.Loc):
            f = x.func
            if f is spec.self_func or f.is_dynamic:
                ok = False
                return
            if f.body is not None and f not in seen:
                seen.add(f)
                walk(f.body)
        if isinstance(x, (ir.StepOp, ir.Temporal, ir.RuleRef)):
            ok = False
            return
        if isinstance(x, ir.Call) and x.name == "program":
            ok = False
            return
        if isinstance(x, ir.DomainTerm) and isinstance(x.domain, T.Domain) and x.domain.dynamic:
            ok = False
            return
        if isinstance(x, ir.Term):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(t)
    return ok


# ----------------------------------------------------------------- the step relation
class StepEncoding:
    """One step of the main rule over generic variables (see the module docstring)."""

    CUR = "x"
    NXT = "y"

    def __init__(self, machine, enc: Encoder):
        self.m = machine
        self.enc = enc
        self.locs = enc.locs
        spec = machine.spec
        self.cur_view = View(self.locs, self.CUR)
        self.nxt_view = View(self.locs, self.NXT)
        enc.errs, enc.overflow, enc.constraints, enc.mon = [], [], [], {}
        ups: dict = {}
        ctx = SCtx(enc, self.cur_view)
        if spec.main is None or spec.main.body is None:
            raise AsmError(None, f"{spec.name} has no main rule")
        enc.ex(spec.main.body, ctx, TRUE, ups)
        self.ups = ups
        self.nxt: dict = {}
        for key in self.locs.order:
            cur = self.locs.var(key, self.CUR)
            writes = ups.get(key)
            if not writes:
                self.nxt[key] = cur
                continue
            s = summarize(writes)
            table = self.locs.table_of_key(key)
            code, missing = sym.encode(s.value, table)
            enc.error(s.clash, NO_SPAN, f"inconsistent update of {self.locs.text(key)}")
            enc.overflowed(AND(s.guard, missing, NOT(sym.is_err(s.value))), NO_SPAN,
                           f"a value of {self.locs.text(key)} outside what the encoding represents")
            self.nxt[key] = sym.ITE(s.guard, code, cur)
        self.errs = list(enc.errs)
        self.overflow = list(enc.overflow)
        self.constraints = list(enc.constraints)

    # properties over this step: state (current variables), step (current, next, writes, inputs)
    def state_violation(self, body: ir.Term):
        enc = self.enc
        before = (len(enc.errs), len(enc.overflow), len(enc.constraints))
        u = enc.ev(body, SCtx(enc, self.cur_view))
        self._no_side_effects(before, body)
        return NOT(sym.is_true(u))

    def step_violation(self, body: ir.Term):
        enc = self.enc
        before = (len(enc.errs), len(enc.overflow), len(enc.constraints))
        ctx = SCtx(enc, self.cur_view, post=self.nxt_view, ups=self.ups)
        u = enc.ev(body, ctx)
        # monitored locations the property reads and the step does not get their own inputs
        self.constraints = list(enc.constraints)
        self._no_side_effects((before[0], before[1], len(enc.constraints)), body)
        return NOT(sym.is_true(u))

    def _no_side_effects(self, before, body):
        enc = self.enc
        if (len(enc.errs), len(enc.overflow), len(enc.constraints)) != before:
            raise unsupported(body.span, "this property (it runs rules)")
