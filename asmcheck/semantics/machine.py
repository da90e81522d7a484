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
import time

from ..errors import AsmError, AsmRuntimeError, NO_SPAN, Span
from . import ir
from . import types as T
from .state import UpdateSet, apply_updates, dom_key, is_dom_key
from .values import SetV, show
from .analysis import infinite_ranges, is_subdomain, mentions_monitored, reads_functions
from .choice import (Choice, Chooser, DeadlineReached, DrawingChooser, Enumerator, InputChooser, NO_VALUE, NoAlternative, Prune, RandomChooser,
                     Sampler, ScriptChooser, TooManySuccessors, next_prefix)
from .rules import MAX_LOOP, RuleExecutor
from .resolve import deep_active, deep_call
from .terms import LONG_MAX, LONG_MIN, Ctx, TermEvaluator, Thunk, Undetermined


# The public names of the step function's parts, importable from here as before the split.
__all__ = ["Machine", "Choice", "Chooser", "DeadlineReached", "DrawingChooser", "Enumerator", "InputChooser", "NO_VALUE", "NoAlternative", "Prune",
           "RandomChooser", "Sampler", "ScriptChooser", "TooManySuccessors", "MAX_LOOP", "LONG_MAX", "LONG_MIN",
           "Ctx", "Thunk", "Undetermined"]


class Machine(TermEvaluator, RuleExecutor):
    """The step function: terms (:class:`TermEvaluator`) and rules (:class:`RuleExecutor`) compiled
    into closures, plus the initial states, the step and the enumeration of successors."""

    #: evaluations between two looks at the clock when a deadline is set
    TICKS = 1024

    def __init__(self, spec: ir.Spec, options: dict | None = None):
        """``options``: ``monitored_ranges``, ``int_range``, ``dedupe``; ``max_loop`` (iterations of
        one ``while``/``iterate`` within a step, default :data:`MAX_LOOP`); ``deadline`` (a
        ``time.monotonic()`` value: past it, a step raises :class:`DeadlineReached`, checked every
        :attr:`TICKS` loop iterations, bindings and successors, so one long step is stopped too)."""
        self.spec = spec
        self.options = options or {}
        self.max_loop = int(self.options.get("max_loop") or MAX_LOOP)
        self.deadline = self.options.get("deadline")
        self._ticks = 0
        self.functions = spec.functions
        self.fname = [f.name for f in spec.functions] + [f.name for f in spec.local_functions]
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
        self.init_terms: dict = {}  # function index -> (params, body IR): the other inits with parameters
        if init is not None:
            for ag in init.agents:
                self.agent_programs[ag.domain] = ag
            for func, params, body, span in init.functions:
                if params and not self._enumerable([p.type for p in params]):
                    self.lazy[func.index] = (params, body)
                elif params:
                    # read at arguments outside the domain (undef), the init term gives the value,
                    # as the simulator computes an initial value on a location's first read
                    self.init_terms[func.index] = (params, body)
        self.keep_undef = frozenset(self.lazy)
        self._lazy_fns: dict = {}
        self.main = self._deep(self.rule_fn, spec.main) if spec.main is not None else None
        self.invariants = []
        for p in spec.properties:
            if p.kind == "invariant":
                self.invariants.append((p, self._deep(self.term, p.body), mentions_monitored(p.body)))

    @staticmethod
    def _deep(fn, *args):
        """``fn(*args)``, again on a thread with a deep stack when the spec nests too deeply for this one."""
        try:
            return fn(*args)
        except RecursionError:
            if deep_active():
                raise
            return deep_call(fn, *args)

    def unbounded_properties(self, props=None) -> list:
        """The errors a property over an infinite domain would raise when evaluated, found before
        any state is explored: one :class:`Undetermined` (at the range) per quantifier, comprehension
        or choose term of the properties (default: the spec's) whose range is Integer, Natural
        (without --int-range), Real or String.  An explorer reports them as input errors (exit 2),
        as a rule over such a range is, rather than as a violation in the initial state."""
        out = []
        for p in (self.spec.properties if props is None else props):
            body = getattr(p, "body", p)
            for rg, dom in infinite_ranges(body, self.int_range is not None):
                out.append(Undetermined(rg.span, f"the property {getattr(p, 'name', '')} quantifies over "
                                                 f"{dom}, which is infinite: asmcheck cannot evaluate it (bound the "
                                                 f"variable with a subset domain" +
                                        (", or give --int-range LO..HI)" if dom in (T.INTEGER, T.NATURAL) else ")")))
        return out

    def tick(self):
        """Count one evaluation; every :attr:`TICKS`, raise :class:`DeadlineReached` if the deadline passed."""
        self._ticks += 1
        if self._ticks >= self.TICKS:
            self._ticks = 0
            if self.deadline is not None and time.monotonic() >= self.deadline:
                raise DeadlineReached("the time limit was reached inside a step")

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
            if dom is T.REAL:
                raise Undetermined(span, "the domain Real is infinite: asmcheck cannot enumerate it (bound it "
                                         "with a subset domain or an interval, or give the values of a monitored "
                                         "function with --monitored NAME=V1,V2,...)")
            raise Undetermined(span, f"the domain {dom} is infinite: asmcheck cannot enumerate it "
                                     f"(bound it with a subset domain, or give --int-range LO..HI)")
        if isinstance(dom, T.Struct):
            if dom.kind == "Prod":
                size = self._product_size(dom, ctx, span)
                if size > self.MAX_PRODUCT:
                    raise Undetermined(span, f"the domain {dom} has {size:,} elements: too many to enumerate")
                parts = [self.domain_values(a, ctx, span) for a in dom.args]
                # a product is read again at every read of a monitored location over it: kept
                # for the same factors (an abstract factor may have grown since)
                try:
                    key = ("Prod", dom, tuple(tuple(p) for p in parts))
                    cached = self._domain_cache.get(key)
                except TypeError:
                    key = cached = None
                if cached is not None:
                    return cached
                tick = self.tick
                out = []
                for p in itertools.product(*parts):
                    tick()
                    out.append(tuple(p))
                if key is not None and len(self._domain_cache) < 4096:
                    self._domain_cache[key] = out
                return out
            if dom.kind == "Powerset":
                # (the size of a product of domains first: its elements are not made to be counted)
                size = self._product_size(dom.args[0], ctx, span)
                if size is not None and size > 16:
                    raise Undetermined(span, f"Powerset of a domain with {size:,} elements is too large to enumerate")
                base = self.domain_values(dom.args[0], ctx, span)
                if len(base) > 16:
                    raise Undetermined(span, f"Powerset of a domain with {len(base)} elements is too large to enumerate")
                out = []
                for r in range(len(base) + 1):
                    for c in itertools.combinations(base, r):
                        out.append(SetV(c))
                return out
        raise Undetermined(span, f"the domain {dom} cannot be enumerated")

    #: the elements of a product domain enumerated, at most (its elements are made one by one)
    MAX_PRODUCT = 10_000_000

    def _product_size(self, dom, ctx, span):
        """The number of elements of a product domain (or of a subset of one without a definition),
        from its factors' sizes; None for any other domain."""
        if isinstance(dom, T.Domain) and dom.kind == "subset" and dom.definition is None and dom.root() is not dom:
            dom = dom.root()
        if not (isinstance(dom, T.Struct) and dom.kind == "Prod"):
            return None
        size = 1
        for a in dom.args:
            sub = self._product_size(a, ctx, span)
            size *= sub if sub is not None else len(self.domain_values(a, ctx, span))
        return size

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
            params, body = self.lazy[idx] if idx in self.lazy else self.init_terms[idx]
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
                if is_subdomain(d, dom):
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
                    if isinstance(d, T.Domain) and d.dynamic and is_subdomain(d, dom)]
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

    # -------------------------------------------------------------- steps
    def initial_state(self, chooser: Chooser | None = None) -> dict:
        """The default initial state: init blocks evaluated in the empty state.

        Inits may read monitored functions; ``chooser`` decides their values (the first
        value when none is given).  Functions initialised over an infinite domain keep
        their init term and evaluate it when a location is first read."""
        st: dict = {}
        init = self.spec.default_init
        ctx = Ctx(self, st, chooser or Chooser())
        ctx.init = True
        if init is not None:
            for dom, body in init.domains:
                if isinstance(dom, T.Domain) and dom.kind in ("abstract", "subset"):
                    v = self.term(body)(ctx)
                    if isinstance(dom, T.Domain) and dom.kind == "subset" and not T.agent_like(dom) and \
                            not (isinstance(T.root(dom), T.Domain) and T.root(dom).kind == "abstract"):
                        self._domain_cache[dom] = list(v.ordered()) if isinstance(v, SetV) else list(v)
            for func, params, body, span in self._init_order():
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

    def _init_order(self) -> list:
        """The function initialisations in an order where an initial value that reads another
        function's initial value comes after it (``function current($m in Fsm) = initial($m)``).
        ASMETA's simulator computes an initial value when the location is first read, so such
        reads see the other initial value; otherwise the declaration order is kept."""
        order = getattr(self, "_init_order_cache", None)
        if order is not None:
            return order
        items = list(self.spec.default_init.functions)
        index = {func.index: i for i, (func, _, _, _) in enumerate(items)}
        deps = [sorted(index[j] for j in reads_functions(body) if j in index and index[j] != i)
                for i, (_, _, body, _) in enumerate(items)]
        done: list = []
        state = [0] * len(items)        # 0 new, 1 in progress, 2 placed

        def place(i):
            if state[i]:
                return                  # placed, or a cycle: keep the declaration order
            state[i] = 1
            for j in deps[i]:
                place(j)
            state[i] = 2
            done.append(items[i])
        for i in range(len(items)):
            place(i)
        self._init_order_cache = done
        return done

    def initial_states(self, fixed=None, parse=None, limit: int = 100_000):
        """Every initial state (more than one when inits read monitored functions), with the
        choices that lead to each."""
        prefix: list[int] = []
        out = []
        while True:
            self.tick()
            ch = Enumerator(prefix, fixed, parse)
            st = self.initial_state(ch)
            out.append((ch.log, st))
            if len(out) >= limit:
                raise TooManySuccessors(None, f"more than {limit} initial states")
            prefix = next_prefix(ch.log)
            if prefix is None:
                return out

    def _run_main(self, state: dict, chooser: Chooser, prune):
        ctx = Ctx(self, state, chooser)
        ctx.prune = prune
        ups = UpdateSet()
        if self.main is not None:
            try:
                self.main(ctx, ups)
            except AsmError as e:
                # the monitored values the failing step had read (a temporal property reads
                # them in the step that fails, as in every other step)
                if getattr(e, "mon", None) is None:
                    e.mon = dict(ctx.mon)
                raise
        return ups, ctx

    def step(self, state: dict, chooser: Chooser, prune=None) -> tuple[UpdateSet, dict, Ctx]:
        """One step from ``state``: the update set, the next state and the context (monitored values)."""
        log = list(chooser.log)
        try:
            ups, ctx = self._run_main(state, chooser, prune)
        except RecursionError:
            if deep_active():
                raise
            # a deeply nested rule: the step again, from scratch, on a thread with a deep stack
            chooser.log[:] = log
            ups, ctx = deep_call(self._run_main, state, chooser, prune)
        try:
            nxt = apply_updates(state, ups, self.keep_undef)
        except AsmError as e:
            if getattr(e, "mon", None) is None:
                e.mon = dict(ctx.mon)
            raise
        if ctx.lazy:
            for k, v in ctx.lazy.items():
                if k not in nxt and k not in ups.locs:
                    nxt[k] = v
        return ups, nxt, ctx

    def successors(self, state: dict, limit: int = 1_000_000, fixed=None, parse=None, prune=None, errors=None):
        """Every (choices, update set, next state, monitored values) from ``state``.

        ``prune`` (a function of location key, value and seq depth) may raise Prune to cut
        the sequences of choices that cannot lead to a wanted successor.  With ``errors`` (a
        list), a sequence of choices whose step fails is skipped and its error appended there
        (following a transcript, a branch that fails is not the step the simulator made);
        without it the error ends the enumeration.  Each appended error carries ``choices``
        (the choices log of its step) and ``mon`` (the monitored values it had read)."""
        prefix: list[int] = []
        out = []
        memo: dict = {}
        ch = None
        runs = 0
        try:
            while True:
                self.tick()
                ch = Enumerator(prefix, fixed, parse)
                runs += 1
                ch.memo = memo
                try:
                    ups, nxt, ctx = self.step(state, ch, prune)
                    out.append((ch.log, ups, nxt, ctx.mon))
                except Prune:
                    pass
                except AsmError as e:
                    # the inputs and choices of the failing step, for its trace
                    if getattr(e, "choices", None) is None:
                        e.choices = list(ch.log)
                    if errors is None or isinstance(e, (Undetermined, TooManySuccessors)):
                        raise
                    errors.append(e)
                if len(out) >= limit:
                    err = TooManySuccessors(None, f"more than {limit:,} successors of one state")
                    err.choices = list(ch.log)
                    raise err
                # next prefix: the last choice point with an untried alternative
                prefix = next_prefix(ch.log)
                if prefix is None:
                    return out
        except BaseException as exc:
            # stopped from outside (a time limit, an interrupt) while enumerating: say how far the
            # enumeration of this state's step got, and through which choices
            if not isinstance(exc, AsmError) and getattr(exc, "enumerated", None) is None:
                try:
                    exc.enumerated = runs
                    exc.choices = list(ch.log) if ch is not None else []
                except AttributeError:
                    pass
            raise

    def sample_successors(self, state: dict, samples: int, seed: int = 0, fixed=None, parse=None):
        """Successors along random sequences of choices (for branchings too big to enumerate)."""
        rng = random.Random(seed)
        for _ in range(samples):
            ch = Sampler(rng, fixed, parse)
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
