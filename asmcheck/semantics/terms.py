"""Terms: the evaluation of IR terms into closures (the :class:`TermEvaluator` half of the Machine)."""
from __future__ import annotations

import itertools
from decimal import Decimal

from ..errors import AsmRuntimeError
from . import ir
from . import types as T
from .state import same_value
from .stdlib import BuiltinError
from .values import (AbstractValue, BagV, MapV, RuleValue, SeqV, SetV, show, abstract_value)
from .analysis import abstract_codomain, free_uids, is_constant, ordered
from .choice import NO_VALUE


class Undetermined(AsmRuntimeError):
    """A choice that cannot be enumerated (an unbounded monitored domain, for instance)."""



class Thunk:
    """A macro argument passed by name: re-evaluated where the body uses it.

    When the argument is a location (``r_m[f(x)]``), ``loc`` holds the function index
    and the argument closures, so an update of the parameter updates that location."""

    __slots__ = ("fn", "env", "self_", "loc")

    def __init__(self, fn, env, self_, loc=None):
        self.fn = fn
        self.env = env
        self.self_ = self_
        self.loc = loc



MISSING = object()



LONG_MIN = -(1 << 63)



LONG_MAX = (1 << 63) - 1
# the elements of one interval ({lo : hi} or {lo : hi, step}) that are built, at most: ten million
# Integers are about a gigabyte of Python objects
MAX_INTERVAL = 10_000_000



def wrap64(r):
    """Integers are 64-bit in ASMETA: arithmetic wraps around like Java's long."""
    return ((r - LONG_MIN) % (1 << 64)) + LONG_MIN



def _real_interval(lo, hi, step) -> list:
    """A Real interval counted in decimal, as ASMETA's parser expands it (BigDecimal): the elements
    of ``{0.6 : 0.9, 0.1}`` are exactly 0.6, 0.7, 0.8 and 0.9, each the double nearest its decimal."""
    d_lo, d_hi, d_st = (Decimal(repr(float(x))) if type(x) is float else Decimal(x) for x in (lo, hi, step))
    if not all(d.is_finite() for d in (d_lo, d_hi, d_st)):
        raise ValueError("an interval bound is not a finite number")
    n = int((d_hi - d_lo) // d_st) + 1 if d_hi >= d_lo else 0
    if n > MAX_INTERVAL:
        raise OverflowError(n)
    out = []
    x = d_lo
    while x <= d_hi:
        out.append(float(x))
        x += d_st
    return out



class Ctx:
    """Evaluation context of one step."""

    __slots__ = ("st", "env", "mon", "chooser", "self_", "machine", "agent", "rule", "fresh", "base", "prune",
                 "depth", "lazy", "post", "ups", "init")

    def __init__(self, machine, state, chooser):
        self.machine = machine
        self.st = state
        self.base = state
        self.prune = None    # a check of each update (used to follow a transcript)
        self.depth = 0       # nesting of seq/loops (their later updates override earlier ones)
        self.lazy = {}       # lazily initialised locations read in this step
        self.post = None     # step properties: the state after the step
        self.ups = None      # step properties: the update set of the step
        self.env = {}
        self.mon = {}
        self.chooser = chooser
        self.self_ = None
        self.agent = None
        self.rule = None
        self.fresh = {}      # domain name -> next serial handed out in this step
        self.init = False    # evaluating the initial state: chooseone is a choice point



class TermEvaluator:
    """Compiles IR terms into closures ``fn(ctx) -> value``; mixed into :class:`Machine`."""

    # -------------------------------------------------------------- terms
    def term(self, t: ir.Term):
        fn = getattr(self, "c_" + type(t).__name__)(t)
        return fn

    def c_Const(self, t: ir.Const):
        v = t.value
        return lambda ctx: v

    def c_VarRef(self, t: ir.VarRef):
        uid = t.var.uid
        name = t.var.name
        span = t.span

        def var(ctx):
            try:
                v = ctx.env[uid]
            except KeyError:
                raise AsmRuntimeError(span, f"variable {name} is not bound here") from None
            if type(v) is Thunk:
                saved_env, saved_self = ctx.env, ctx.self_
                ctx.env, ctx.self_ = v.env, v.self_
                try:
                    return v.fn(ctx)
                finally:
                    ctx.env, ctx.self_ = saved_env, saved_self
            return v
        return var

    def c_Loc(self, t: ir.Loc):
        f = t.func
        args = [self.term(a) for a in t.args]
        idx = f.index
        span = t.span
        if f is self.spec.self_func:
            return lambda ctx: ctx.self_
        if f.kind == "static" and f.arity == 0 and abstract_codomain(f):
            # a 0-ary static function of an abstract domain names one of its elements
            val = abstract_value(f.codomain.name, f.name)
            return lambda ctx: val
        if f.kind in ("static", "derived") and f.body is not None:
            return self._defined(f, args, span)
        if f.kind == "static" and f.body is None:
            return lambda ctx: None
        if f.kind == "monitored":
            return self._monitored(f, args, span)
        if idx in self.lazy:
            default = self._lazy_default(idx)

            def lazy_read(ctx):
                vals = tuple(a(ctx) for a in args)
                key = (idx, vals)
                v = ctx.st.get(key, MISSING)
                if v is MISSING:
                    v = ctx.lazy.get(key, MISSING)
                    if v is MISSING:
                        # first read: the init term gives the value, which the location keeps
                        v = ctx.lazy[key] = default(ctx, vals)
                return v
            return lazy_read
        if not args:
            return lambda ctx: ctx.st.get(idx)
        if idx in self.init_terms:
            init_default = self._lazy_default(idx)

            def read_with_init(ctx):
                vals = tuple(a(ctx) for a in args)
                key = (idx, vals)
                v = ctx.st.get(key)
                if v is None and None in vals and key not in ctx.st:
                    # an argument outside the domain (undef): the init term gives the value
                    return init_default(ctx, vals)
                return v
            return read_with_init
        if len(args) == 1:
            a0 = args[0]
            return lambda ctx: ctx.st.get((idx, (a0(ctx),)))
        if len(args) == 2:
            a0, a1 = args
            return lambda ctx: ctx.st.get((idx, (a0(ctx), a1(ctx))))
        return lambda ctx: ctx.st.get((idx, tuple(a(ctx) for a in args)))

    def _defined(self, f: ir.Function, args, span):
        """A static or derived function with a definition: evaluate its body."""
        holder = {}
        uids = [p.uid for p in f.params]
        static = f.kind == "static"
        cache = self._static_cache

        def body_fn():
            b = holder.get("b")
            if b is None:
                if f in self._compiling:
                    # a recursive definition: compile lazily through the holder
                    return lambda ctx: holder["b"](ctx)
                self._compiling.add(f)
                try:
                    b = self.term(f.body)
                finally:
                    self._compiling.discard(f)
                holder["b"] = b
            return b

        if not args:
            def ev0(ctx):
                if static:
                    key = (f, ())
                    if key in cache:
                        return cache[key]
                b = body_fn()
                saved, saved_init = ctx.env, ctx.init
                ctx.env = {}
                ctx.init = False        # a definition is not an initial value: chooseone is not a choice
                try:
                    v = b(ctx)
                finally:
                    ctx.env, ctx.init = saved, saved_init
                if static:
                    cache[(f, ())] = v
                return v
            return ev0

        def ev(ctx):
            vals = tuple(a(ctx) for a in args)
            if static:
                key = (f, vals)
                try:
                    return cache[key]
                except KeyError:
                    pass
                except TypeError:
                    static_ok = False
            b = body_fn()
            saved, saved_init = ctx.env, ctx.init
            ctx.env = dict(zip(uids, vals))
            ctx.init = False
            try:
                v = b(ctx)
            finally:
                ctx.env, ctx.init = saved, saved_init
            if static:
                try:
                    cache[(f, vals)] = v
                except TypeError:
                    pass
            return v
        return ev

    def _monitored(self, f: ir.Function, args, span):
        idx = f.index
        machine = self

        def mon(ctx):
            vals = tuple(a(ctx) for a in args)
            key = idx if not vals else (idx, vals)
            try:
                return ctx.mon[key]
            except KeyError:
                pass
            label = machine.location_text(key)
            try:
                options = machine.monitored_options(f, ctx, span)
            except Undetermined:
                v = ctx.chooser.value(label, f.codomain)
                if v is NO_VALUE:
                    raise
                ctx.mon[key] = v
                return v
            i = ctx.chooser.choose("monitored", label, options)
            v = options[i]
            ctx.mon[key] = v
            return v
        return mon

    def monitored_options(self, f: ir.Function, ctx, span) -> list:
        rng = self.monitored_ranges.get(f.name)
        if rng is not None:
            return list(rng)
        try:
            return self.domain_values(f.codomain, ctx, span)
        except Undetermined:
            raise Undetermined(f.span, f"monitored function {f.name} ranges over {f.codomain}, which is infinite: "
                                       f"give its values with --monitored {f.name}=LO..HI (or --int-range LO..HI)")

    def c_Call(self, t: ir.Call):
        name = t.name
        args = [self.term(a) for a in t.args]
        span = t.span
        if name == "program":
            a0 = args[0]
            machine = self

            def program(ctx):
                agent = a0(ctx)
                return machine.program_of(agent, span)
            return program
        impl = t.impl
        if name == "and":
            a, b = args

            def and_(ctx):
                x = a(ctx)
                if x is False:
                    return False
                y = b(ctx)
                if y is False:
                    return False
                if x is None or y is None:
                    return None
                return True
            return and_
        if name == "or":
            a, b = args

            def or_(ctx):
                x = a(ctx)
                if x is True:
                    return True
                y = b(ctx)
                if y is True:
                    return True
                if x is None or y is None:
                    return None
                return False
            return or_
        if name == "implies":
            a, b = args

            def implies(ctx):
                x = a(ctx)
                if x is False:
                    return True
                y = b(ctx)
                if y is True:
                    return True
                if x is None or y is None:
                    return None
                return False
            return implies
        if name == "eq" and len(args) == 2:
            a, b = args
            return lambda ctx: same_value(a(ctx), b(ctx))
        if name == "neq" and len(args) == 2:
            a, b = args
            return lambda ctx: not same_value(a(ctx), b(ctx))
        if name == "not":
            a = args[0]

            def not_(ctx):
                x = a(ctx)
                return None if x is None else not x
            return not_

        if name == "chooseone" and len(args) == 1:
            a0 = args[0]
            label = f"chooseone at {span.short()}"

            def chooseone(ctx):
                c = a0(ctx)
                if ctx.init and c is not None and len(c) > 1:
                    # a nondeterministic initial value: every element is an initial state
                    options = ordered(c, span)
                    return options[ctx.chooser.choose("chooseone", label, options)]
                return impl(c)
            return chooseone

        def call(ctx):
            vals = [x(ctx) for x in args]
            try:
                return impl(*vals)
            except BuiltinError as e:
                raise AsmRuntimeError(span, str(e)) from None
            except (TypeError, ValueError, ZeroDivisionError, OverflowError, AttributeError, IndexError) as e:
                raise AsmRuntimeError(span, f"{name}({', '.join(show(v) for v in vals)}) is not defined") from None
        if len(args) == 2 and name in ("plus", "minus", "mult", "lt", "le", "gt", "ge"):
            a, b = args
            op = {"plus": lambda x, y: x + y, "minus": lambda x, y: x - y, "mult": lambda x, y: x * y,
                  "lt": lambda x, y: x < y, "le": lambda x, y: x <= y, "gt": lambda x, y: x > y,
                  "ge": lambda x, y: x >= y}[name]

            def fast2(ctx):
                x = a(ctx)
                y = b(ctx)
                if x is None or y is None:
                    return None
                try:
                    r = op(x, y)
                except TypeError:
                    raise AsmRuntimeError(span, f"{name}({show(x)}, {show(y)}) is not defined") from None
                if type(r) is int and not (LONG_MIN <= r <= LONG_MAX):
                    return wrap64(r)
                return r
            return fast2
        return call

    def program_of(self, agent, span):
        if agent is None:
            raise AsmRuntimeError(span, "program(undef): no agent")
        for dom, ag in self.agent_programs.items():
            if isinstance(dom, T.Domain) and agent in self._abstract_values(dom, None) or (
                    isinstance(agent, AbstractValue) and isinstance(dom, T.Domain) and agent.domain == dom.name):
                return RuleValue.bound(ag.rule, agent, ag.args)
        raise AsmRuntimeError(span, f"agent {show(agent)} has no program (no 'agent ...' initialisation)")

    def c_Temporal(self, t: ir.Temporal):
        span = t.span
        op = t.op

        def temporal(ctx):
            raise AsmRuntimeError(span, f"the temporal operator {op} has no value in a single state")
        return temporal

    def c_StepOp(self, t: ir.StepOp):
        span = t.span
        op = t.op
        if op == "next":
            inner = self.term(t.args[0])

            def nxt(ctx):
                if ctx.post is None:
                    raise AsmRuntimeError(span, "next(...) has a value only in a step property")
                saved, saved_base = ctx.st, ctx.base
                ctx.st = ctx.base = ctx.post
                try:
                    return inner(ctx)
                finally:
                    ctx.st, ctx.base = saved, saved_base
            return nxt
        loc = t.args[-1]
        idx = loc.func.index
        argfns = [self.term(a) for a in loc.args]
        agent = self.term(t.args[0]) if op == "updatedBy" else None
        read = self.term(loc)

        def key_of(ctx):
            vals = tuple(a(ctx) for a in argfns)
            return idx if not vals else (idx, vals)

        def stepop(ctx):
            ups = ctx.ups
            if ups is None:
                raise AsmRuntimeError(span, f"{op}(...) has a value only in a step property")
            key = key_of(ctx)
            if op == "updated":
                return key in ups.locs
            if op == "updatedBy":
                u = ups.locs.get(key)
                return u is not None and same_value(u.agent, agent(ctx))
            before = read(ctx)
            saved, saved_base = ctx.st, ctx.base
            ctx.st = ctx.base = ctx.post
            try:
                after = read(ctx)
            finally:
                ctx.st, ctx.base = saved, saved_base
            return not same_value(before, after)
        return stepop

    def c_DomainTerm(self, t: ir.DomainTerm):
        dom = t.domain
        span = t.span
        machine = self
        return lambda ctx: SetV(machine.domain_values(dom, ctx, span))

    def c_Cond(self, t: ir.Cond):
        c = self.term(t.cond)
        a = self.term(t.then)
        b = self.term(t.other) if t.other is not None else (lambda ctx: None)
        span = t.cond.span

        def cond(ctx):
            g = c(ctx)
            if g is True:
                return a(ctx)
            if g is False:
                return b(ctx)
            raise AsmRuntimeError(span, "the condition is undef")
        return cond

    def c_Switch(self, t: ir.Switch):
        subj = self.term(t.subject)
        cases = [(self.term(c), self.term(r)) for c, r in t.cases]
        other = self.term(t.other) if t.other is not None else None

        def switch(ctx):
            v = subj(ctx)
            for c, r in cases:
                if same_value(v, c(ctx)):
                    return r(ctx)
            return other(ctx) if other is not None else None
        return switch

    def c_Let(self, t: ir.Let):
        binds = [(v.uid, self.term(x)) for v, x in t.bindings]
        body = self.term(t.body)

        def let(ctx):
            env = ctx.env
            saved = dict(env)
            try:
                for uid, x in binds:
                    env[uid] = x(ctx)
                return body(ctx)
            finally:
                env.clear()
                env.update(saved)
        return let

    def _ranges(self, bindings):
        """Compiled ranges of ``$x in D`` bindings: each gives the elements as an ordered list."""
        out = []
        bound = set()
        for v, r in bindings:
            out.append((v.uid, self._range_list(r, v.name), r.span, bool(free_uids(r) & bound)))
            bound.add(v.uid)
        return out

    def _range_list(self, r: ir.Term, var: str = ""):
        span = r.span
        if isinstance(r, ir.DomainTerm):
            dom = r.domain
            machine = self
            return lambda ctx: machine.domain_values(dom, ctx, span)
        if is_constant(r):
            cache = {}

            def const_items(ctx):
                items = cache.get("v")
                if items is None:
                    items = cache["v"] = ordered(self.term(r)(ctx), span, var)
                return items
            return const_items
        fn = self.term(r)
        return lambda ctx: ordered(fn(ctx), span, var)

    def _iter_bindings(self, ctx, ranges):
        """Yield once per combination of values, with the variables bound in ctx.env
        (restored afterwards).  Later ranges may use earlier variables."""
        env = ctx.env
        tick = self.tick
        saved = {uid: env[uid] for uid, _, _, _ in ranges if uid in env}
        try:
            if len(ranges) == 1:
                uid, items, _, _ = ranges[0]
                for x in items(ctx):
                    tick()
                    env[uid] = x
                    yield
            elif not any(dep for _, _, _, dep in ranges):
                lists = [items(ctx) for _, items, _, _ in ranges]
                uids = [uid for uid, _, _, _ in ranges]
                for combo in itertools.product(*lists):
                    tick()
                    for uid, x in zip(uids, combo):
                        env[uid] = x
                    yield
            else:
                yield from self._nested(ctx, ranges, 0)
        finally:
            for uid, _, _, _ in ranges:
                if uid in saved:
                    env[uid] = saved[uid]
                else:
                    env.pop(uid, None)

    def _nested(self, ctx, ranges, i):
        if i == len(ranges):
            yield
            return
        uid, items, _, _ = ranges[i]
        tick = self.tick
        for x in items(ctx):
            tick()
            ctx.env[uid] = x
            yield from self._nested(ctx, ranges, i + 1)

    def c_Quant(self, t: ir.Quant):
        ranges = self._ranges(t.bindings)
        guard = self.term(t.guard) if t.guard is not None else (lambda ctx: True)
        kind = t.kind
        span = t.guard.span if t.guard is not None else t.span
        machine = self

        if len(ranges) == 1 and kind in ("forall", "exists"):
            uid, items, _, _ = ranges[0]
            want = kind == "exists"

            def quant1(ctx):
                env = ctx.env
                had = uid in env
                old = env.get(uid)
                try:
                    for x in items(ctx):
                        env[uid] = x
                        g = guard(ctx)
                        if g is None:
                            raise AsmRuntimeError(span, "the quantifier's condition is undef")
                        if g is want:
                            return want
                    return not want
                finally:
                    if had:
                        env[uid] = old
                    else:
                        env.pop(uid, None)
            return quant1

        def quant(ctx):
            count = 0
            for _ in machine._iter_bindings(ctx, ranges):
                g = guard(ctx)
                if g is None:
                    raise AsmRuntimeError(span, "the quantifier's condition is undef")
                if kind == "forall":
                    if not g:
                        return False
                elif g:
                    count += 1
                    if kind == "exists":
                        return True
                    if count > 1:
                        return False
            if kind == "forall":
                return True
            if kind == "exists":
                return False
            return count == 1
        return quant

    def c_Compr(self, t: ir.Compr):
        ranges = self._ranges(t.bindings)
        guard = self.term(t.guard) if t.guard is not None else None
        body = self.term(t.body)
        body2 = self.term(t.body2) if t.body2 is not None else None
        kind = t.kind
        machine = self

        def compr(ctx):
            out = []
            for _ in machine._iter_bindings(ctx, ranges):
                if guard is not None:
                    g = guard(ctx)
                    if g is None:
                        raise AsmRuntimeError(t.span, "the comprehension's condition is undef")
                    if not g:
                        continue
                out.append((body(ctx), body2(ctx)) if body2 is not None else body(ctx))
            if kind == "set":
                return SetV(out)
            if kind == "seq":
                return SeqV(out)
            if kind == "bag":
                return BagV.of(out)
            return MapV.of(out)
        return compr

    def c_Collection(self, t: ir.Collection):
        items = [self.term(x) for x in t.items]
        kind = t.kind
        if kind == "set":
            return lambda ctx: SetV([x(ctx) for x in items])
        if kind == "seq":
            return lambda ctx: SeqV([x(ctx) for x in items])
        return lambda ctx: BagV.of([x(ctx) for x in items])

    def c_Range(self, t: ir.Range):
        a = self.term(t.start)
        b = self.term(t.end)
        step = self.term(t.step) if t.step is not None else (lambda ctx: 1)
        kind = t.kind
        span = t.span

        def rng(ctx):
            lo, hi, st = a(ctx), b(ctx), step(ctx)
            if lo is None or hi is None or st is None:
                raise AsmRuntimeError(span, "an interval bound is undef")
            if st <= 0:
                raise AsmRuntimeError(span, f"the step of an interval must be positive, not {show(st)}")
            vals = []
            if type(lo) is float or type(hi) is float or type(st) is float:
                try:
                    vals = _real_interval(lo, hi, st)
                except ValueError:
                    raise AsmRuntimeError(span, "an interval bound is not a finite number") from None
                except OverflowError as e:
                    raise AsmRuntimeError(span, f"this interval has {e.args[0]:,} elements: more than asmcheck "
                                                f"builds ({MAX_INTERVAL:,}); narrow it") from None
            else:
                n = (hi - lo) // st + 1 if hi >= lo else 0
                if n > MAX_INTERVAL:
                    raise AsmRuntimeError(span, f"this interval has {n:,} elements: more than asmcheck builds "
                                                f"({MAX_INTERVAL:,}); narrow it")
                vals = list(range(lo, hi + 1, st))
            if kind == "set":
                return SetV(vals)
            if kind == "seq":
                return SeqV(vals)
            return BagV.of(vals)
        return rng

    def c_MapLit(self, t: ir.MapLit):
        pairs = [(self.term(k), self.term(v)) for k, v in t.pairs]
        return lambda ctx: MapV.of([(k(ctx), v(ctx)) for k, v in pairs])

    def c_TupleLit(self, t: ir.TupleLit):
        items = [self.term(x) for x in t.items]
        return lambda ctx: tuple(x(ctx) for x in items)

    def c_RuleRef(self, t: ir.RuleRef):
        val = RuleValue(t.rule)
        return lambda ctx: val
