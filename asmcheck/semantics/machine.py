"""The step function: the IR compiled once into Python closures.

One :class:`Machine` serves the simulator, the explorer and the replay of every
trace.  Nondeterminism (``choose`` branches, monitored inputs) goes through a
*chooser*: the step asks it which alternative to take at each choice point.
A simulation picks one alternative; :meth:`Machine.successors` enumerates every
sequence of choices by re-running the step with each prefix (so every successor
is produced by the same code that replays a trace).

Nothing here executes text from a spec: closures are built from the IR only.
"""
from __future__ import annotations

import itertools
import random
from dataclasses import dataclass

from ..errors import AsmError, AsmRuntimeError, NO_SPAN, Span
from . import ir
from . import types as T
from .state import UpdateSet, apply_in_place, apply_updates, dom_key, is_dom_key, same_value
from .stdlib import BuiltinError
from .values import (AbstractValue, BagV, EnumValue, MapV, RuleValue, SeqV, SetV, fresh_value, show, vkey,
                     abstract_value)

MAX_LOOP = 10_000


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


def _wrap64(r):
    """Integers are 64-bit in ASMETA: arithmetic wraps around like Java's long."""
    return ((r - LONG_MIN) % (1 << 64)) + LONG_MIN


class Ctx:
    """Evaluation context of one step."""

    __slots__ = ("st", "env", "mon", "chooser", "self_", "machine", "agent", "rule", "fresh", "base", "prune",
                 "depth", "lazy", "post", "ups")

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


@dataclass
class Choice:
    """One choice point of a step, as recorded for traces."""

    kind: str            # "choose" or "monitored"
    label: str           # the choose rule's position, or the monitored location
    n: int               # number of alternatives
    index: int           # the alternative taken
    value: object        # the value taken (monitored) or the variable bindings (choose)
    pick: int = -1       # its position among all the options (== index unless restricted)
    nested: list | None = None   # choices made inside a choose body (enumerating choosers)

    def __post_init__(self):
        if self.pick < 0:
            self.pick = self.index


# ----------------------------------------------------------------- choosers
_NO_VALUE = object()


class Chooser:
    """Takes the first alternative at every choice point."""

    # Enumerating choosers see one alternative per distinct effect of a choose rule
    # (its bindings are local to its body, so only the effect can matter afterwards).
    enumerates = False
    memo = None

    def sub(self, prefix):
        return _Enumerator(prefix)

    def __init__(self):
        self.log: list[Choice] = []

    def value(self, label, dom):
        """A monitored value from an infinite domain (only a simulation can pick one)."""
        return _NO_VALUE

    def choose(self, kind, label, options, values_repr=None) -> int:
        self.log.append(Choice(kind, label, len(options), 0, options[0] if options else None))
        return 0


class RandomChooser(Chooser):
    def __init__(self, seed: int):
        super().__init__()
        self.rng = random.Random(seed)

    def choose(self, kind, label, options, values_repr=None) -> int:
        i = self.rng.randrange(len(options))
        self.log.append(Choice(kind, label, len(options), i, options[i]))
        return i

    def value(self, label, dom):
        r = T.root(dom)
        if r is T.NATURAL:
            v = self.rng.randrange(0, 101)
        elif r is T.INTEGER:
            v = self.rng.randrange(-100, 101)
        elif r is T.REAL:
            v = round(self.rng.uniform(-100, 100), 3)
        elif r is T.STRING:
            v = "s" + str(self.rng.randrange(100))
        else:
            return _NO_VALUE
        self.log.append(Choice("monitored", label, 0, 0, v))
        return v


class ScriptChooser(Chooser):
    """Replays a recorded sequence of choice indexes; extra choice points take 0."""

    enumerates = True

    def __init__(self, indexes):
        super().__init__()
        self.indexes = list(indexes)

    def choose(self, kind, label, options, values_repr=None) -> int:
        pos = len(self.log)
        i = self.indexes[pos] if pos < len(self.indexes) else 0
        if isinstance(i, tuple):
            i = i[1]
        if i >= len(options):
            raise AsmRuntimeError(None, f"replay: choice {pos} has {len(options)} alternatives, the trace asks for "
                                        f"number {i}")
        self.log.append(Choice(kind, label, len(options), i, options[i]))
        return i


class InputChooser(Chooser):
    """Monitored values from a table (location text -> value); choose takes the first."""

    def __init__(self, values: dict, fallback: Chooser | None = None):
        super().__init__()
        self.values = values
        self.fallback = fallback

    def value(self, label, dom):
        if label in self.values:
            v = self.values[label]
            self.log.append(Choice("monitored", label, 0, 0, v))
            return v
        if self.fallback is not None:
            v = self.fallback.value(label, dom)
            if v is not _NO_VALUE:
                self.log.append(self.fallback.log.pop())
            return v
        return _NO_VALUE

    def choose(self, kind, label, options, values_repr=None) -> int:
        if kind == "monitored" and label in self.values:
            want = self.values[label]
            for i, o in enumerate(options):
                if same_value(o, want):
                    self.log.append(Choice(kind, label, len(options), i, o))
                    return i
            raise AsmRuntimeError(None, f"the value {show(want)} given for {label} is not in its domain")
        if self.fallback is not None:
            i = self.fallback.choose(kind, label, options, values_repr)
            self.log.append(self.fallback.log.pop())
            return i
        self.log.append(Choice(kind, label, len(options), 0, options[0] if options else None))
        return 0


class _Enumerator(Chooser):
    """Follows a prefix of alternative numbers, then takes the first; records what it saw.

    ``fixed`` maps a monitored location's text to a predicate on candidate values: only
    the values it accepts are alternatives (used to follow a transcript).  ``Choice.index``
    is the number of the alternative among those allowed, ``Choice.pick`` its position
    among all the options.
    """

    enumerates = True

    def __init__(self, prefix, fixed=None, parse=None):
        super().__init__()
        self.prefix = prefix
        self.fixed = fixed
        self.parse = parse

    def sub(self, prefix):
        return _Enumerator(prefix, self.fixed, self.parse)

    memo = None

    def choose(self, kind, label, options, values_repr=None) -> int:
        pos = len(self.log)
        i = self.prefix[pos] if pos < len(self.prefix) else 0
        allowed = None
        if self.fixed is not None and kind == "monitored" and label in self.fixed:
            ok = self.fixed[label]
            allowed = [j for j, o in enumerate(options) if ok(o)]
            if not allowed:
                raise NoAlternative(None, f"no value of {label} matches the one given")
        if allowed is None:
            self.log.append(Choice(kind, label, len(options), i, options[i], i))
            return i
        j = allowed[i]
        self.log.append(Choice(kind, label, len(allowed), i, options[j], j))
        return j

    def value(self, label, dom):
        if self.parse is not None and self.fixed is not None and label in self.fixed:
            v = self.parse(label, dom)
            if v is not _NO_VALUE:
                self.log.append(Choice("monitored", label, 1, 0, v, 0))
                return v
        return _NO_VALUE


class Prune(Exception):
    """Raised by a ``prune`` check: this sequence of choices cannot lead where wanted."""


class TooManySuccessors(AsmRuntimeError):
    """The successors of one state exceed the given bound."""


class _Sampler(_Enumerator):
    """Random alternatives (within ``fixed``), for searching huge branchings."""

    enumerates = False

    def __init__(self, rng, fixed=None, parse=None):
        super().__init__([], fixed, parse)
        self.rng = rng

    def choose(self, kind, label, options, values_repr=None) -> int:
        self.prefix = [c.index for c in self.log] + [self.rng.randrange(self._count(kind, label, options))]
        return super().choose(kind, label, options, values_repr)

    def _count(self, kind, label, options):
        if self.fixed is not None and kind == "monitored" and label in self.fixed:
            ok = self.fixed[label]
            n = sum(1 for o in options if ok(o))
            return max(n, 1)
        return len(options)


class NoAlternative(AsmRuntimeError):
    """A transcript asks for a value the spec does not allow."""


# ----------------------------------------------------------------- the machine
class Machine:
    def __init__(self, spec: ir.Spec, options: dict | None = None):
        self.spec = spec
        self.options = options or {}
        self.functions = spec.functions
        self.fname = [f.name for f in spec.functions]
        self._static_cache: dict = {}
        self._domain_cache: dict = {}
        self._abstract_cache: dict = {}
        self._rule_cache: dict = {}
        self._compiling: set = set()
        self.monitored_ranges: dict = dict(self.options.get("monitored_ranges", {}))
        self.int_range = self.options.get("int_range")
        self.static_elements = {d: list(v) for d, v in spec.static_elements.items()}
        self.agent_programs = {}
        self.dedupe = self.options.get("dedupe", True)
        init = spec.default_init
        self.lazy: dict = {}        # function index -> (params, body IR): inits over infinite domains
        if init is not None:
            for ag in init.agents:
                self.agent_programs[ag.domain] = ag
            for func, params, body, span in init.functions:
                if params and not self._enumerable([p.type for p in params]):
                    self.lazy[func.index] = (params, body)
        self.keep_undef = frozenset(self.lazy)
        self._lazy_fns: dict = {}
        self.main = self.rule_fn(spec.main) if spec.main is not None else None
        self.invariants = []
        for p in spec.properties:
            if p.kind == "invariant":
                self.invariants.append((p, self.term(p.body), _mentions_monitored(p.body)))

    # -------------------------------------------------------------- text of locations
    def location_text(self, key) -> str:
        if type(key) is int:
            return self.fname[key]
        if is_dom_key(key):
            return key[1]
        f, args = key
        return f"{self.fname[f]}({','.join(show(a) for a in args)})"

    def key_of(self, func: ir.Function, args: tuple):
        return func.index if not args else (func.index, args)

    # -------------------------------------------------------------- domains
    def domain_values(self, dom: T.Type, ctx: Ctx | None, span: Span) -> list:
        """The elements of a domain, in a fixed order."""
        if isinstance(dom, T.Domain):
            if dom is T.BOOLEAN:
                return [False, True]
            if dom.kind == "enum":
                return list(dom.elements)
            if dom.kind == "subset":
                if dom.definition is not None:
                    cached = self._domain_cache.get(dom)
                    if cached is None:
                        v = self.term(dom.definition)(ctx or Ctx(self, {}, Chooser()))
                        cached = list(v.ordered()) if isinstance(v, SetV) else list(v)
                        self._domain_cache[dom] = cached
                    return cached
                root = dom.root()
                if isinstance(root, T.Domain) and root.kind == "abstract":
                    return self._abstract_values(dom, ctx)
                return self.domain_values(root, ctx, span) if root is not dom else []
            if dom.kind == "abstract":
                return self._abstract_values(dom, ctx)
            if dom in (T.INTEGER, T.NATURAL) and self.int_range is not None:
                lo, hi = self.int_range
                return list(range(max(lo, 0) if dom is T.NATURAL else lo, hi + 1))
            if dom is T.UNDEF:
                return [None]
            raise Undetermined(span, f"the domain {dom} is infinite: asmcheck cannot enumerate it "
                                     f"(bound it with a subset domain, or give --int-range LO..HI)")
        if isinstance(dom, T.Struct):
            if dom.kind == "Prod":
                parts = [self.domain_values(a, ctx, span) for a in dom.args]
                return [tuple(p) for p in itertools.product(*parts)]
            if dom.kind == "Powerset":
                base = self.domain_values(dom.args[0], ctx, span)
                if len(base) > 16:
                    raise Undetermined(span, f"Powerset of a domain with {len(base)} elements is too large to enumerate")
                out = []
                for r in range(len(base) + 1):
                    for c in itertools.combinations(base, r):
                        out.append(SetV(c))
                return out
        raise Undetermined(span, f"the domain {dom} cannot be enumerated")

    def _enumerable(self, types) -> bool:
        try:
            for t in types:
                self.domain_values(t, None, NO_SPAN)
            return True
        except Undetermined:
            return False

    def _lazy_default(self, idx):
        """The initial value of a location of a function initialised over an infinite domain,
        evaluated when the location is first read (in the state of that moment)."""
        fn = self._lazy_fns.get(idx)
        if fn is None:
            params, body = self.lazy[idx]
            uids = [p.uid for p in params]
            holder = {}

            def default(ctx, vals):
                b = holder.get("b")
                if b is None:
                    b = holder["b"] = self.term(body)
                saved = ctx.env
                ctx.env = dict(zip(uids, vals))
                try:
                    return b(ctx)
                finally:
                    ctx.env = saved
            fn = self._lazy_fns[idx] = default
        return fn

    def _abstract_values(self, dom: T.Domain, ctx: Ctx | None) -> list:
        info = self._abstract_cache.get(dom)
        if info is None:
            out = []
            for d, els in self.static_elements.items():
                if _is_subdomain(d, dom):
                    out.extend(els)
            if dom is T.AGENT:
                for d, els in self.static_elements.items():
                    if T.agent_like(d) and d is not dom:
                        out.extend(e for e in els if e not in out)
            seen = set()
            static = []
            for e in out:
                if e not in seen:
                    seen.add(e)
                    static.append(e)
            # the domains whose extend-made elements belong to dom
            keys = [dom_key(d.name) for d in self.spec.domains
                    if isinstance(d, T.Domain) and d.dynamic and _is_subdomain(d, dom)]
            info = self._abstract_cache[dom] = (static, keys)
        static, keys = info
        if ctx is None or not keys:
            return static
        st = ctx.st
        extra = [e for k in keys for e in st.get(k, ())]
        if not extra:
            return static
        seen = set(static)
        res = list(static)
        for e in extra:
            if e not in seen:
                seen.add(e)
                res.append(e)
        return res

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
        if f.kind == "static" and f.arity == 0 and _abstract_codomain(f):
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
                saved = ctx.env
                ctx.env = {}
                try:
                    v = b(ctx)
                finally:
                    ctx.env = saved
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
            saved = ctx.env
            ctx.env = dict(zip(uids, vals))
            try:
                v = b(ctx)
            finally:
                ctx.env = saved
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
                if v is _NO_VALUE:
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
                    return _wrap64(r)
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
            out.append((v.uid, self._range_list(r), r.span, bool(_free_uids(r) & bound)))
            bound.add(v.uid)
        return out

    def _range_list(self, r: ir.Term):
        span = r.span
        if isinstance(r, ir.DomainTerm):
            dom = r.domain
            machine = self
            return lambda ctx: machine.domain_values(dom, ctx, span)
        if _is_constant(r):
            cache = {}

            def const_items(ctx):
                items = cache.get("v")
                if items is None:
                    items = cache["v"] = _ordered(self.term(r)(ctx), span)
                return items
            return const_items
        fn = self.term(r)
        return lambda ctx: _ordered(fn(ctx), span)

    def _iter_bindings(self, ctx, ranges):
        """Yield once per combination of values, with the variables bound in ctx.env
        (restored afterwards).  Later ranges may use earlier variables."""
        env = ctx.env
        saved = {uid: env[uid] for uid, _, _, _ in ranges if uid in env}
        try:
            if len(ranges) == 1:
                uid, items, _, _ = ranges[0]
                for x in items(ctx):
                    env[uid] = x
                    yield
            elif not any(dep for _, _, _, dep in ranges):
                lists = [items(ctx) for _, items, _, _ in ranges]
                uids = [uid for uid, _, _, _ in ranges]
                for combo in itertools.product(*lists):
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
        for x in items(ctx):
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
            x = lo
            while x <= hi:
                vals.append(x)
                x += st
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

    # -------------------------------------------------------------- rules
    def rule_fn(self, rd: ir.RuleDecl):
        """The compiled body of a declared rule (compiled once, recursion allowed)."""
        fn = self._rule_cache.get(rd)
        if fn is None:
            holder = {}
            self._rule_cache[rd] = lambda ctx, ups: holder["f"](ctx, ups)
            compiled = self.rule(rd.body)
            name = rd.name

            def run(ctx, ups):
                saved = ctx.rule
                ctx.rule = name
                try:
                    compiled(ctx, ups)
                finally:
                    ctx.rule = saved
            holder["f"] = run
            self._rule_cache[rd] = run
            fn = run
        return fn

    def rule(self, r: ir.Rule):
        return getattr(self, "r_" + type(r).__name__)(r)

    def r_Skip(self, r):
        return lambda ctx, ups: None

    def r_Update(self, r: ir.Update):
        f = r.func
        idx = f.index
        args = [self.term(a) for a in r.args]
        val = self.term(r.value)
        span = r.span
        machine = self
        check = self._range_check(f, span)
        if not args:
            def upd0(ctx, ups):
                v = val(ctx)
                if check is not None:
                    check(ctx, v)
                if ctx.prune is not None:
                    ctx.prune(idx, v, ctx.depth)
                ups.add(idx, v, span, ctx.self_, ctx.rule, machine)
            return upd0

        def upd(ctx, ups):
            v = val(ctx)
            key = (idx, tuple(a(ctx) for a in args))
            if check is not None:
                check(ctx, v)
            if ctx.prune is not None:
                ctx.prune(key, v, ctx.depth)
            ups.add(key, v, span, ctx.self_, ctx.rule, machine)
        return upd

    def _range_check(self, f: ir.Function, span):
        """Values assigned to a location whose codomain is a finite subset domain must belong to it."""
        cod = f.codomain
        if not (isinstance(cod, T.Domain) and cod.kind == "subset" and cod.definition is not None):
            return None
        machine = self
        cache = {}

        def check(ctx, v):
            if v is None:
                return
            allowed = cache.get("s")
            if allowed is None:
                allowed = set(machine.domain_values(cod, ctx, span))
                cache["s"] = allowed
            if v not in allowed:
                raise AsmRuntimeError(span, f"value out of domain: {show(v)} is not in {cod.name} "
                                            f"(the codomain of {f.name})")
        return check

    def r_UpdateVar(self, r: ir.UpdateVar):
        uid = r.var.uid
        val = self.term(r.value)
        span = r.span
        machine = self

        def updvar(ctx, ups):
            cur = ctx.env.get(uid)
            v = val(ctx)
            if type(cur) is Thunk and cur.loc is not None:
                # a macro parameter bound to a location: update that location
                idx, argfns = cur.loc
                saved_env, saved_self = ctx.env, ctx.self_
                ctx.env, ctx.self_ = cur.env, cur.self_
                try:
                    vals = tuple(a(ctx) for a in argfns)
                finally:
                    ctx.env, ctx.self_ = saved_env, saved_self
                ups.add(idx if not vals else (idx, vals), v, span, ctx.self_, ctx.rule, machine)
                return
            ctx.env[uid] = v
        return updvar

    def r_Block(self, r: ir.Block):
        rules = [self.rule(x) for x in r.rules]
        machine = self
        if r.kind == "par":
            def par(ctx, ups):
                for x in rules:
                    x(ctx, ups)
            return par

        def seq(ctx, ups):
            saved = ctx.st
            work = dict(saved)
            ctx.st = work
            ctx.depth += 1
            local = UpdateSet()
            try:
                for x in rules:
                    sub = UpdateSet()
                    x(ctx, sub)
                    apply_in_place(work, sub, machine.keep_undef)
                    _merge_seq(local, sub)
            finally:
                ctx.st = saved
                ctx.depth -= 1
            ups.merge_par(local, machine)
        return seq

    def r_If(self, r: ir.If):
        c = self.term(r.cond)
        a = self.rule(r.then)
        b = self.rule(r.other) if r.other is not None else None
        span = r.cond.span

        def if_(ctx, ups):
            g = c(ctx)
            if g is True:
                a(ctx, ups)
            elif g is False:
                if b is not None:
                    b(ctx, ups)
            else:
                raise AsmRuntimeError(span, "the guard is undef")
        return if_

    def r_SwitchRule(self, r: ir.SwitchRule):
        subj = self.term(r.subject)
        cases = [(self.term(c), self.rule(b)) for c, b in r.cases]
        other = self.rule(r.other) if r.other is not None else None

        def switch(ctx, ups):
            v = subj(ctx)
            for c, b in cases:
                if same_value(v, c(ctx)):
                    b(ctx, ups)
                    return
            if other is not None:
                other(ctx, ups)
        return switch

    def r_LetRule(self, r: ir.LetRule):
        binds = [(v.uid, self.term(x)) for v, x in r.bindings]
        body = self.rule(r.body)

        def let(ctx, ups):
            env = ctx.env
            saved = dict(env)
            try:
                for uid, x in binds:
                    env[uid] = x(ctx)
                body(ctx, ups)
            finally:
                env.clear()
                env.update(saved)
        return let

    def r_Choose(self, r: ir.Choose):
        ranges = self._ranges(r.bindings)
        guard = self.term(r.guard) if r.guard is not None else None
        body = self.rule(r.body)
        ifnone = self.rule(r.ifnone) if r.ifnone is not None else None
        uids = [v.uid for v, _ in r.bindings]
        names = [v.name for v, _ in r.bindings]
        span = r.span
        gspan = r.guard.span if r.guard is not None else r.span
        label = f"choose at {span.short()}"
        machine = self
        dedupe = self.dedupe
        node = object()

        pure = not (r.guard is not None and _mentions_monitored(r.guard)) and not any(
            _mentions_monitored(rg) for _, rg in r.bindings)
        NONE = ()

        def candidates(ctx):
            cands = []
            if guard is None and len(ranges) == 1:
                return [(x,) for x in ranges[0][1](ctx)]
            for _ in machine._iter_bindings(ctx, ranges):
                if guard is not None:
                    g = guard(ctx)
                    if g is None:
                        raise AsmRuntimeError(gspan, "the choose condition is undef")
                    if not g:
                        continue
                cands.append(tuple(ctx.env[u] for u in uids))
            return cands

        def choose(ctx, ups):
            ch = ctx.chooser
            if dedupe and ch.enumerates:
                memo = ch.memo
                key = None
                outcomes = None
                if memo is not None and pure and ctx.st is ctx.base:
                    try:
                        key = (node, tuple(ctx.env.items()), tuple(ctx.mon.items()),
                               tuple(ctx.fresh.items()), ctx.self_)
                        outcomes = memo.get(key)
                    except TypeError:
                        key = None
                if outcomes is None:
                    cands = candidates(ctx)
                    outcomes = machine._choose_outcomes(ctx, cands, uids, names, body) if cands else NONE
                    if key is not None:
                        memo[key] = outcomes
                if not outcomes and outcomes is not NONE:
                    raise Prune()
                if outcomes is NONE:
                    if ifnone is not None:
                        ifnone(ctx, ups)
                    return
                if len(outcomes) == 1:
                    i = 0
                else:
                    i = ch.choose("choose", label, [o[3] for o in outcomes])
                    ch.log[-1].nested = outcomes[i][5]
                sub, mon_after, fresh_after, bindings, exc, nested = outcomes[i]
                if exc is not None:
                    raise exc
                ctx.mon = dict(mon_after)
                ctx.fresh = dict(fresh_after)
                ups.merge_par(sub, machine)
                return
            cands = candidates(ctx)
            if not cands:
                if ifnone is not None:
                    ifnone(ctx, ups)
                return
            options = [dict(zip(names, c)) for c in cands]
            i = ch.choose("choose", label, options) if len(cands) > 1 else _one(ctx, label, options)
            env = ctx.env
            saved = {u: env[u] for u in uids if u in env}
            try:
                for u, v in zip(uids, cands[i]):
                    env[u] = v
                body(ctx, ups)
            finally:
                for u in uids:
                    if u in saved:
                        env[u] = saved[u]
                    else:
                        env.pop(u, None)
        return choose

    def _choose_outcomes(self, ctx, cands, uids, names, body):
        """The distinct effects of a choose body over all candidates and nested choices:
        [(update set, monitored cache after, fresh counters after, bindings, error, nested log)]."""
        outcomes = []
        seen = {}
        env = ctx.env
        saved_vals = {u: env[u] for u in uids if u in env}
        outer_ch, outer_mon, outer_fresh = ctx.chooser, ctx.mon, ctx.fresh
        try:
            for cand in cands:
                for u, v in zip(uids, cand):
                    env[u] = v
                prefix: list = []
                while True:
                    sub_ch = outer_ch.sub(prefix)
                    ctx.chooser = sub_ch
                    ctx.mon = dict(outer_mon)
                    ctx.fresh = dict(outer_fresh)
                    sub = UpdateSet()
                    exc = None
                    pruned = False
                    try:
                        body(ctx, sub)
                    except AsmError as e:
                        exc = e
                    except Prune:
                        pruned = True
                    if pruned:
                        log = sub_ch.log
                        j = len(log) - 1
                        while j >= 0 and log[j].index + 1 >= log[j].n:
                            j -= 1
                        if j < 0:
                            break
                        prefix = [c.index for c in log[:j]] + [log[j].index + 1]
                        continue
                    new_mon = tuple((k, v) for k, v in ctx.mon.items() if k not in outer_mon)
                    if exc is None:
                        key = (frozenset((k, _hkey(u.value), u.agent) for k, u in sub.locs.items()),
                               tuple(sub.fresh), new_mon)
                    else:
                        key = ("error", str(exc), new_mon)
                    if key not in seen:
                        seen[key] = len(outcomes)
                        outcomes.append((sub, ctx.mon, ctx.fresh, dict(zip(names, cand)), exc, sub_ch.log))
                    log = sub_ch.log
                    j = len(log) - 1
                    while j >= 0 and log[j].index + 1 >= log[j].n:
                        j -= 1
                    if j < 0:
                        break
                    prefix = [c.index for c in log[:j]] + [log[j].index + 1]
        finally:
            ctx.chooser, ctx.mon, ctx.fresh = outer_ch, outer_mon, outer_fresh
            for u in uids:
                if u in saved_vals:
                    env[u] = saved_vals[u]
                else:
                    env.pop(u, None)
        if not outcomes and ctx.prune is not None:
            raise Prune()
        return outcomes

    def r_Forall(self, r: ir.Forall):
        ranges = self._ranges(r.bindings)
        guard = self.term(r.guard) if r.guard is not None else None
        body = self.rule(r.body)
        gspan = r.guard.span if r.guard is not None else r.span
        machine = self

        def forall(ctx, ups):
            for _ in machine._iter_bindings(ctx, ranges):
                if guard is not None:
                    g = guard(ctx)
                    if g is None:
                        raise AsmRuntimeError(gspan, "the forall condition is undef")
                    if not g:
                        continue
                body(ctx, ups)
        return forall

    def r_Extend(self, r: ir.Extend):
        dom = r.domain
        name = dom.name
        uids = [v.uid for v in r.vars]
        body = self.rule(r.body)
        machine = self

        def extend(ctx, ups):
            env = ctx.env
            saved = {u: env[u] for u in uids if u in env}
            try:
                for u in uids:
                    el = machine.fresh_element(ctx, name)
                    ups.fresh.append((name, el))
                    env[u] = el
                body(ctx, ups)
            finally:
                for u in uids:
                    if u in saved:
                        env[u] = saved[u]
                    else:
                        env.pop(u, None)
        return extend

    def fresh_element(self, ctx: Ctx, domain: str):
        k = ctx.fresh.get(domain)
        if k is None:
            existing = ctx.st.get(dom_key(domain), ())
            k = 1 + max((e.serial for e in existing), default=0)
        ctx.fresh[domain] = k + 1
        return fresh_value(domain, k)

    def r_CallRule(self, r: ir.CallRule):
        rd = r.rule
        args = [self.term(a) for a in r.args]
        uids = [p.uid for p in rd.params]
        machine = self
        by_name = not r.turbo and _has_sequencing(rd)
        # how each argument is passed: 0 value, 1 by name, 2 variable (its binding as is),
        # 3 location by name (updatable through the parameter)
        modes = []
        locs = []
        for a in r.args:
            if r.turbo:
                modes.append(0)
                locs.append(None)
            elif isinstance(a, ir.VarRef):
                modes.append(2)
                locs.append(a.var.uid)
            elif isinstance(a, ir.Loc) and a.func.is_location and a.func.kind != "monitored" and not (
                    a.func.kind == "static"):
                modes.append(3)
                locs.append((a.func.index, [self.term(x) for x in a.args]))
            elif by_name and not _is_simple(a):
                modes.append(1)
                locs.append(None)
            else:
                modes.append(0)
                locs.append(None)
        plan = list(zip(args, modes, locs))
        body_holder = {}

        def call(ctx, ups):
            fn = body_holder.get("f")
            if fn is None:
                fn = machine.rule_fn(rd)
                body_holder["f"] = fn
            vals = []
            env = ctx.env
            for a, mode, extra in plan:
                if mode == 0:
                    vals.append(a(ctx))
                elif mode == 2:
                    v = env.get(extra, MISSING)
                    vals.append(a(ctx) if v is MISSING else v)
                elif mode == 3:
                    vals.append(Thunk(a, env, ctx.self_, extra))
                else:
                    vals.append(Thunk(a, env, ctx.self_))
            saved = ctx.env
            ctx.env = dict(zip(uids, vals))
            try:
                fn(ctx, ups)
            finally:
                ctx.env = saved
        return call

    def r_TurboReturn(self, r: ir.TurboReturn):
        call = self.rule(r.call)
        target = r.target
        res_idx = self.spec.result_func.index
        machine = self
        if isinstance(target, ir.Update):
            f = target.func
            idx = f.index
            args = [self.term(a) for a in target.args]
            span = target.span

            def tret(ctx, ups):
                sub = UpdateSet()
                call(ctx, sub)
                u = sub.locs.get(res_idx)
                v = u.value if u is not None else None
                ups.merge_par(sub, machine)
                key = idx if not args else (idx, tuple(a(ctx) for a in args))
                ups.add(key, v, span, ctx.self_, ctx.rule, machine)
            return tret
        uid = target.var.uid

        def tret_var(ctx, ups):
            sub = UpdateSet()
            call(ctx, sub)
            u = sub.locs.get(res_idx)
            ups.merge_par(sub, machine)
            ctx.env[uid] = u.value if u is not None else None
        return tret_var

    def r_TermCall(self, r: ir.TermCall):
        term = self.term(r.term)
        args = [self.term(a) for a in r.args]
        span = r.span
        machine = self

        def tcall(ctx, ups):
            rv = term(ctx)
            if rv is None:
                raise AsmRuntimeError(span, "the rule to run is undef")
            if not isinstance(rv, RuleValue):
                raise AsmRuntimeError(span, f"{show(rv)} is not a rule")
            rd = rv.rule
            vals = [a(ctx) for a in args] if args else list(rv.args)
            if len(vals) != len(rd.params):
                raise AsmRuntimeError(span, f"{rd.name} takes {len(rd.params)} argument(s), not {len(vals)}")
            saved_env, saved_self = ctx.env, ctx.self_
            ctx.env = dict(zip([p.uid for p in rd.params], vals))
            if rv.agent is not None:
                ctx.self_ = rv.agent
            try:
                machine.rule_fn(rd)(ctx, ups)
            finally:
                ctx.env, ctx.self_ = saved_env, saved_self
        return tcall

    def r_Loop(self, r: ir.Loop):
        cond = self.term(r.cond) if r.cond is not None else None
        body = self.rule(r.body)
        span = r.span
        kind = r.kind

        machine = self

        def loop(ctx, ups):
            saved = ctx.st
            work = dict(saved)
            ctx.st = work
            ctx.depth += 1
            local = UpdateSet()
            try:
                for _ in range(MAX_LOOP):
                    if cond is not None:
                        g = cond(ctx)
                        if g is None:
                            raise AsmRuntimeError(r.cond.span, "the loop condition is undef")
                        if not g:
                            break
                    sub = UpdateSet()
                    body(ctx, sub)
                    if cond is None and all(same_value(work.get(k), u.value)
                                            for k, u in sub.locs.items()) and not sub.fresh:
                        break
                    apply_in_place(work, sub, machine.keep_undef)
                    _merge_seq(local, sub)
                else:
                    raise AsmRuntimeError(span, f"{kind} did not end after {MAX_LOOP} iterations")
            finally:
                ctx.st = saved
                ctx.depth -= 1
            ups.merge_par(local, machine)
        return loop

    def r_LocalRule(self, r: ir.LocalRule):
        init = self.rule(r.init)
        body = self.rule(r.body)
        machine = self

        def local(ctx, ups):
            saved = ctx.st
            work = dict(saved)
            ctx.st = work
            try:
                sub = UpdateSet()
                init(ctx, sub)
                apply_in_place(work, sub, machine.keep_undef)
                body(ctx, ups)
            finally:
                ctx.st = saved
        return local

    # -------------------------------------------------------------- steps
    def initial_state(self, chooser: Chooser | None = None) -> dict:
        """The default initial state: init blocks evaluated in the empty state.

        Inits may read monitored functions; ``chooser`` decides their values (the first
        value when none is given).  Functions initialised over an infinite domain keep
        their init term and evaluate it when a location is first read."""
        st: dict = {}
        init = self.spec.default_init
        ctx = Ctx(self, st, chooser or Chooser())
        if init is not None:
            for dom, body in init.domains:
                if isinstance(dom, T.Domain) and dom.kind in ("abstract", "subset"):
                    v = self.term(body)(ctx)
                    if isinstance(dom, T.Domain) and dom.kind == "subset" and not T.agent_like(dom) and \
                            not (isinstance(T.root(dom), T.Domain) and T.root(dom).kind == "abstract"):
                        self._domain_cache[dom] = list(v.ordered()) if isinstance(v, SetV) else list(v)
            for func, params, body, span in init.functions:
                if func.index in self.lazy:
                    continue
                fn = self.term(body)
                if not params:
                    ctx.env = {}
                    v = fn(ctx)
                    if v is not None:
                        st[func.index] = v
                    continue
                uids = [p.uid for p in params]
                doms = [self.domain_values(p.type, ctx, p.span) for p in params]
                for combo in itertools.product(*doms):
                    ctx.env = dict(zip(uids, combo))
                    v = fn(ctx)
                    if v is not None:
                        st[(func.index, tuple(combo))] = v
                ctx.env = {}
        self.init_mon = ctx.mon
        return st

    def initial_states(self, fixed=None, parse=None, limit: int = 100_000):
        """Every initial state (more than one when inits read monitored functions), with the
        choices that lead to each."""
        prefix: list[int] = []
        out = []
        while True:
            ch = _Enumerator(prefix, fixed, parse)
            st = self.initial_state(ch)
            out.append((ch.log, st))
            if len(out) >= limit:
                raise TooManySuccessors(None, f"more than {limit} initial states")
            log = ch.log
            j = len(log) - 1
            while j >= 0 and log[j].index + 1 >= log[j].n:
                j -= 1
            if j < 0:
                return out
            prefix = [c.index for c in log[:j]] + [log[j].index + 1]

    def step(self, state: dict, chooser: Chooser, prune=None) -> tuple[UpdateSet, dict, Ctx]:
        """One step from ``state``: the update set, the next state and the context (monitored values)."""
        ctx = Ctx(self, state, chooser)
        ctx.prune = prune
        ups = UpdateSet()
        if self.main is not None:
            self.main(ctx, ups)
        nxt = apply_updates(state, ups, self.keep_undef)
        if ctx.lazy:
            for k, v in ctx.lazy.items():
                if k not in nxt and k not in ups.locs:
                    nxt[k] = v
        return ups, nxt, ctx

    def successors(self, state: dict, limit: int = 1_000_000, fixed=None, parse=None, prune=None):
        """Every (choices, update set, next state, monitored values) from ``state``.

        ``prune`` (a function of location key, value and seq depth) may raise Prune to cut
        the sequences of choices that cannot lead to a wanted successor."""
        prefix: list[int] = []
        out = []
        memo: dict = {}
        while True:
            ch = _Enumerator(prefix, fixed, parse)
            ch.memo = memo
            try:
                ups, nxt, ctx = self.step(state, ch, prune)
                out.append((ch.log, ups, nxt, ctx.mon))
            except Prune:
                pass
            if len(out) >= limit:
                raise TooManySuccessors(None, f"more than {limit} successors of one state")
            # next prefix: the last choice point with an untried alternative
            log = ch.log
            j = len(log) - 1
            while j >= 0 and log[j].index + 1 >= log[j].n:
                j -= 1
            if j < 0:
                return out
            prefix = [c.index for c in log[:j]] + [log[j].index + 1]

    def sample_successors(self, state: dict, samples: int, seed: int = 0, fixed=None, parse=None):
        """Successors along random sequences of choices (for branchings too big to enumerate)."""
        rng = random.Random(seed)
        for _ in range(samples):
            ch = _Sampler(rng, fixed, parse)
            ups, nxt, ctx = self.step(state, ch)
            yield ch.log, ups, nxt, ctx.mon

    def check_invariants(self, state: dict, mon: dict | None = None, which: str = "state"):
        """The names of the invariants violated in ``state`` (``which``: state / monitored)."""
        bad = []
        for prop, fn, with_mon in self.invariants:
            if (which == "state") == with_mon:
                continue
            ctx = Ctx(self, state, Chooser())
            if mon is not None:
                ctx.mon = dict(mon)
            v = fn(ctx)
            if v is None:
                raise AsmRuntimeError(prop.span, f"invariant {prop.name} is undef")
            if v is False:
                bad.append(prop)
        return bad


def _merge_seq(ups: UpdateSet, sub: UpdateSet) -> None:
    ups.locs.update(sub.locs)
    ups.fresh.extend(sub.fresh)


def _one(ctx, label, options):
    return 0


def _hkey(v):
    """A hashable stand-in for a value that keeps True apart from 1."""
    return (type(v) is bool, v)


def _ordered(coll, span) -> list:
    if coll is None:
        raise AsmRuntimeError(span, "the range is undef")
    if isinstance(coll, SetV):
        return coll.ordered()
    if isinstance(coll, MapV):
        return [k for k, _ in coll]
    return list(coll)


def _is_constant(t: ir.Term) -> bool:
    """A term with no variables and no dynamic function: its value never changes."""
    if isinstance(t, ir.Const):
        return True
    if isinstance(t, (ir.Collection, ir.TupleLit)):
        return all(_is_constant(x) for x in t.items)
    if isinstance(t, ir.Range):
        return _is_constant(t.start) and _is_constant(t.end) and (t.step is None or _is_constant(t.step))
    if isinstance(t, ir.Call) and t.name not in ("program",):
        return all(_is_constant(x) for x in t.args)
    return False


def _free_uids(t) -> set:
    out = set()

    def walk(x):
        if isinstance(x, ir.VarRef):
            out.add(x.var.uid)
        if isinstance(x, (ir.Term, ir.Rule)):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(t)
    return out


def _abstract_codomain(f: ir.Function) -> bool:
    c = f.codomain
    return isinstance(c, T.Domain) and isinstance(T.root(c), T.Domain) and T.root(c).kind == "abstract"


def _is_subdomain(d: T.Type, of: T.Type) -> bool:
    seen = 0
    while isinstance(d, T.Domain) and seen < 50:
        if d is of:
            return True
        if d.kind != "subset" or d.base is None:
            return False
        d = d.base
        seen += 1
    return d is of


def _is_simple(t: ir.Term) -> bool:
    """Terms whose value cannot change within a step: constants and variables."""
    return isinstance(t, (ir.Const, ir.VarRef, ir.RuleRef, ir.DomainTerm)) or (
        isinstance(t, ir.Loc) and t.func.kind == "static" and all(_is_simple(a) for a in t.args))


def _has_sequencing(rd: ir.RuleDecl, seen=None) -> bool:
    """Could the body see a location change mid-step (seq, loops, nested calls that do)?"""
    seen = set() if seen is None else seen
    if rd in seen:
        return False
    seen.add(rd)
    found = False

    def walk(x):
        nonlocal found
        if found:
            return
        if isinstance(x, ir.Block) and x.kind == "seq" or isinstance(x, (ir.Loop, ir.LocalRule)):
            found = True
            return
        if isinstance(x, ir.CallRule):
            if _has_sequencing(x.rule, seen):
                found = True
                return
        if isinstance(x, ir.TermCall):
            found = True
            return
        if isinstance(x, ir.Rule):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(rd.body)
    return found


def _mentions_monitored(t: ir.Term, seen=None) -> bool:
    seen = set() if seen is None else seen
    found = False

    def walk(x):
        nonlocal found
        if found:
            return
        if isinstance(x, ir.Loc):
            f = x.func
            if f.kind == "monitored":
                found = True
                return
            if f.body is not None and f not in seen:
                seen.add(f)
                walk(f.body)
        if isinstance(x, ir.Term):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    walk(t)
    return found
