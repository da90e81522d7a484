"""Bounded model checking and k-induction over the encoding of :mod:`.encode`.

Depths follow the explorer's: a state property is violated at the depth of the state, a
step property at the depth of the step's target, a run-time error at the depth of the
state whose step raises.  ``bmc(k)`` checks states 0..k, steps into states 1..k and
errors of states 0..k-1 (what ``Explorer(max_depth=k)`` checks).

Every violation Z3 finds is decoded into states and replayed by the explicit step
function (the state must be initial, each state a successor of the one before, and the
property must fail on the explicit evaluation) before it becomes a :class:`Trace`; a
mismatch raises :class:`ReplayMismatch`, an internal error, never a counterexample.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import z3

from ..errors import AsmError
from ..explore.trace import Trace, TraceStep
from ..semantics.machine import Prune, Enumerator
from ..semantics.state import same_value
from ..semantics.values import show
from . import sym
from .encode import Encoder, Locations, StepEncoding, unsupported
from .sym import AND, NOT, OR
from ..semantics.choice import next_prefix


class ReplayMismatch(Exception):
    """A trace found by Z3 does not replay through the step function (an internal error)."""


class ErrorProperty:
    """The pseudo property 'no step raises a run-time error' (the explorer's 'error')."""

    name = "error"
    kind = "error"
    span = None
    source = "explorer"
    expect = None
    prop = None


@dataclass
class Prop:
    """A property as the engine sees it."""

    name: str
    kind: str                 # state: checked on states; step: on transitions; error
    wrapper: object           # StateProperty / StepProperty / MonitoredInvariant / ErrorProperty
    viol: object = None       # generic violation condition
    aux: bool = False         # an auxiliary invariant (--aux / --assume)
    lemma: bool = False       # a candidate lemma made by the engine (definedness, --infer)
    clause: tuple = ()        # a lemma's literals: (location key, code, positive); it is their disjunction


@dataclass
class Found:
    prop: Prop
    depth: int
    trace: Trace
    message: str = ""


@dataclass
class Outcome:
    verdict: str                      # violated holds-to-depth proved unknown
    depth: int                        # unrollings made
    seconds: float
    found: list = field(default_factory=list)
    props: list = field(default_factory=list)
    verdicts: dict = field(default_factory=dict)   # name -> verdict
    depths: dict = field(default_factory=dict)     # name -> violation depth
    reason: str = ""
    induction: dict = field(default_factory=dict)  # name -> {"k": n, "needed": [names]}
    unknown_at: int | None = None
    overflow_at: int | None = None                  # depth of the first state whose step the encoding cannot represent


# ----------------------------------------------------------------- the model
class Model:
    """The encoded spec: initial states, the step, the properties; instantiated per depth."""

    def __init__(self, machine, state_props, step_props, aux_props=(), check_errors=True, loop_bound=None):
        self.m = machine
        self.locs = Locations(machine)
        self.enc = Encoder(machine, self.locs)
        if loop_bound is not None:
            self.enc.loop_bound = loop_bound
        self.step = StepEncoding(machine, self.enc)
        self.props: list[Prop] = []
        for p in list(state_props) + list(aux_props):
            is_aux = any(p is a for a in aux_props)
            if hasattr(p, "check_state"):
                self.props.append(Prop(p.name, "state", p, self.step.state_violation(p.prop.body), aux=is_aux))
            else:
                self.props.append(Prop(p.name, "step", p, self.step.step_violation(p.prop.body), aux=is_aux))
        for p in step_props:
            self.props.append(Prop(p.name, "step", p, self.step.step_violation(p.prop.body)))
        if check_errors:
            self.props.append(Prop("error", "error", ErrorProperty()))
        st = self.step
        self.constraints = AND(*st.constraints)
        self.err = OR([e.guard for e in st.errs])
        self.ovf = OR([o.guard for o in st.overflow])
        self.order = self.locs.order
        self.cur = [self.locs.var(k, StepEncoding.CUR) for k in self.order]
        self.nxt_vars = [self.locs.var(k, StepEncoding.NXT) for k in self.order]
        self.next_eq = [(self.locs.var(k, StepEncoding.NXT), st.nxt[k]) for k in self.order]
        self.free = list(self.enc.choice_vars) + [x for x, _, _ in self.enc.mon_vars]
        self._init_states()
        self._frames: dict = {}

    def _init_states(self):
        m = self.m
        inits = m.initial_states()
        spans = {}
        if m.spec.default_init is not None:
            for func, _, _, span in m.spec.default_init.functions:
                spans[func.index] = span
        self.inits = []
        forms = []
        for log, st in inits:
            codes = {}
            for key, v in st.items():
                fidx = key if type(key) is int else key[0]
                if key in self.locs.kid:
                    c = self.locs.table_of_key(key).code_of(v)
                    if c is None:
                        raise unsupported(spans.get(fidx), f"the initial value {show(v)} of {self.locs.text(key)} "
                                                           f"(outside the values of its codomain)")
                    codes[key] = c
                elif type(fidx) is not int or (fidx not in self.locs.reason and fidx in self.locs.keys):
                    raise unsupported(spans.get(fidx) if type(fidx) is int else None,
                                      f"the initial location {self.locs.text(key)}")
            self.inits.append((log, st))
            eqs = []
            for k, x in zip(self.order, self.cur):
                t = self.locs.table_of_key(k)
                eqs.append(x == t.const(codes.get(k, t.code_of(None))))
            forms.append(AND(*eqs))
        self.init = OR(forms)

    # -------------------------------------------------------------- instantiation
    def svars(self, ns: str, i: int):
        return [z3.BitVec(f"{ns}{i}_{j}", x.size()) for j, x in enumerate(self.cur)]

    def frame(self, ns: str, i: int) -> dict:
        """The step from state i to state i+1 (and properties at i) in namespace ns."""
        key = (ns, i)
        fr = self._frames.get(key)
        if fr is not None:
            return fr
        a = self.svars(ns, i)
        b = self.svars(ns, i + 1)
        pairs = list(zip(self.cur, a)) + list(zip(self.nxt_vars, b))
        for x in self.free:
            pairs.append((x, z3.Const(f"{ns}{i}:{x}", x.sort())))

        def sub(e):
            if sym.is_t(e) or sym.is_f(e):
                return e
            return z3.substitute(e, *pairs)
        cons = sub(self.constraints)
        err = sub(self.err)
        ovf = sub(self.ovf)
        nxt = AND(*[y == sub(e) for y, (_, e) in zip(b, self.next_eq)])
        fr = {
            "vars": a, "next_vars": b,
            "cons": cons, "err": err, "ovf": ovf,
            "trans": AND(cons, NOT(err), NOT(ovf), nxt),
            "viol": {p.name: sub(p.viol) for p in self.props if p.viol is not None},
        }
        self._frames[key] = fr
        return fr

    def state_vars(self, ns, i):
        return self.frame(ns, i)["vars"]

    def init_at(self, ns: str):
        vs = self.state_vars(ns, 0)
        return z3.substitute(self.init, *zip(self.cur, vs)) if not (sym.is_t(self.init) or sym.is_f(self.init)) \
            else self.init

    def ranges(self, ns, i):
        out = []
        for k, x in zip(self.order, self.state_vars(ns, i)):
            out.append(self.locs.table_of_key(k).in_range(x))
        return AND(*out)

    def violation(self, p: Prop, ns: str, d: int):
        """The condition of a violation of p at depth d (given the transitions before)."""
        if p.kind == "state":
            return self.frame(ns, d)["viol"][p.name]
        if p.kind == "step":
            fr = self.frame(ns, d - 1)
            return AND(fr["trans"], fr["viol"][p.name])
        fr = self.frame(ns, d)
        return AND(fr["cons"], fr["err"])

    def overflow_at(self, ns, d):
        fr = self.frame(ns, d)
        return AND(fr["cons"], NOT(fr["err"]), fr["ovf"])

    # -------------------------------------------------------------- decoding
    def decode(self, model, ns: str, n: int) -> list[dict]:
        """States 0..n of a model, as the step function's dicts."""
        base = {}
        for key, v in self.inits[0][1].items():
            if key not in self.locs.kid:
                base[key] = v
        states = []
        for i in range(n + 1):
            st = dict(base)
            for key, x in zip(self.order, self.state_vars(ns, i)):
                code = model.eval(x, model_completion=True).as_long()
                t = self.locs.table_of_key(key)
                v = t.values[code] if code < len(t.values) else None
                if v is not None:
                    st[key] = v
            states.append(st)
        return states


def same_state(a: dict, b: dict) -> bool:
    if a.keys() != b.keys():
        return False
    return all(same_value(a[k], b[k]) for k in a)


def all_successors(machine, state):
    """Every (choices, update set, next state, monitored values) from state; choices whose
    step raises are skipped (Machine.successors stops at them)."""
    prefix: list = []
    memo: dict = {}
    while True:
        ch = Enumerator(prefix)
        ch.memo = memo
        try:
            ups, nxt, ctx = machine.step(state, ch)
            yield ch.log, ups, nxt, ctx.mon
        except (Prune, AsmError):
            pass
        prefix = next_prefix(ch.log)
        if prefix is None:
            return


def replay(model: Model, prop: Prop, states: list[dict]) -> tuple[Trace, str]:
    """Check a decoded trace against the step function; build the Trace shown to users."""
    m = model.m
    log0 = None
    for log, st in model.inits:
        if same_state(st, states[0]):
            log0 = log
            break
    if log0 is None:
        raise ReplayMismatch("the first state is not an initial state")
    steps = [TraceStep(0, log0, states[0], dict(states[0]), None)]
    message = ""
    n = len(states) - 1
    for i in range(n):
        cur, want = states[i], states[i + 1]
        match = None
        last = prop.kind == "step" and i == n - 1
        for log, ups, nxt, mon in all_successors(m, cur):
            if not same_state(nxt, want):
                continue
            if last:
                try:
                    ok = prop.wrapper.check_step(m, cur, ups, nxt, mon)
                except AsmError as e:
                    ok = False
                    message = f"cannot be evaluated: {e.message}"
                if ok:
                    continue
            match = (log, ups, nxt)
            break
        if match is None:
            what = "violates the property" if last else "is a successor"
            raise ReplayMismatch(f"no step from state {i} reaches state {i + 1} that {what}")
        log, ups, nxt = match
        changed = {k: nxt.get(k) for k in set(cur) | set(nxt) if not same_value(cur.get(k), nxt.get(k))}
        steps.append(TraceStep(i + 1, log, nxt, changed, ups))
    kind = "step" if prop.kind == "step" else "state"
    if prop.kind == "state":
        try:
            ok = prop.wrapper.check_state(m, states[-1])
        except AsmError as e:
            ok = False
            message = f"cannot be evaluated: {e.message}"
        if ok:
            raise ReplayMismatch(f"{prop.name} holds in the last state")
    wrapper, failing = prop.wrapper, None
    if prop.kind == "error":
        try:
            m.successors(states[-1])
        except AsmError as e:
            message = e.message
            # shown as explore shows it: where the step fails, with the inputs and choices it had taken
            wrapper = ErrorProperty()
            wrapper.span = e.span
            failing = list(getattr(e, "choices", None) or [])
        else:
            raise ReplayMismatch("the last state's step raises no error")
    return Trace(wrapper, steps, kind, message, failing), message


# ----------------------------------------------------------------- BMC
class BMC:
    """Incremental bounded model checking (namespace 'b')."""

    def __init__(self, model: Model, deadline: float | None = None):
        self.model = model
        self.s = z3.SolverFor("QF_BV")
        self.s.add(model.init_at("b"))
        self.depth = 0           # transitions asserted so far
        self.deadline = deadline

    def _check(self, cond, want_model=False):
        """sat / unsat / unknown (on a time-out) for cond on top of the path; with
        want_model, (result, model or None)."""
        if sym.is_f(cond):
            return (z3.unsat, None) if want_model else z3.unsat
        if self.deadline is not None:
            left = self.deadline - time.perf_counter()
            if left <= 0:
                return (z3.unknown, None) if want_model else z3.unknown
            self.s.set("timeout", max(1, int(left * 1000)))
        self.s.push()
        self.s.add(cond)
        r = self.s.check()
        mdl = self.s.model() if want_model and r == z3.sat else None
        self.s.pop()
        return (r, mdl) if want_model else r

    def extend_to(self, d: int):
        while self.depth < d:
            self.s.add(self.model.frame("b", self.depth)["trans"])
            self.depth += 1

    def find(self, p: Prop, d: int):
        """A replayed violation of p at depth d, None if there is none, 'unknown' on a time-out."""
        need = d - 1 if p.kind == "step" else d
        self.extend_to(need)
        cond = self.model.violation(p, "b", d)
        r, mdl = self._check(cond, want_model=True)
        if r == z3.unsat:
            return None
        if r != z3.sat:
            return "unknown"
        states = self.model.decode(mdl, "b", d)
        trace, message = replay(self.model, p, states)
        return Found(p, d, trace, message)

    def any_violation(self, props, d) -> object:
        conds = []
        for p in props:
            if p.kind == "step" and d == 0:
                continue
            need = d - 1 if p.kind == "step" else d
            self.extend_to(need)
            conds.append(self.model.violation(p, "b", d))
        if not conds:
            return z3.unsat
        return self._check(OR(conds))

    def drop_false(self, model, lemmas, d):
        """The names of the lemmas violated at depth d (None on a time-out)."""
        out = set()
        todo = list(lemmas)
        while todo:
            conds = [model.violation(p, "b", d) for p in todo]
            r, mdl = self._check(OR(conds), want_model=True)
            if r == z3.unsat:
                break
            if r != z3.sat:
                return None
            bad = [p for p, c in zip(todo, conds) if z3.is_true(mdl.eval(c, model_completion=True))]
            if not bad:
                return None
            out.update(p.name for p in bad)
            todo = [p for p in todo if p.name not in out]
        return out

    def overflow(self, d):
        self.extend_to(d)
        r, mdl = self._check(self.model.overflow_at("b", d), want_model=True)
        if r == z3.sat:
            return _overflow_message(self.model, mdl, d)
        return None if r == z3.unsat else "unknown"


def _overflow_message(model: Model, mdl, d: int) -> str:
    pairs = list(zip(model.cur, model.state_vars("b", d)))
    for x in model.free:
        pairs.append((x, z3.Const(f"b{d}:{x}", x.sort())))
    for o in model.step.overflow:
        g = o.guard if sym.is_t(o.guard) else z3.substitute(o.guard, *pairs)
        if z3.is_true(mdl.eval(g, model_completion=True)):
            where = f" ({o.span.short()})" if o.span is not None and o.span.line else ""
            return f"{o.message}{where}, reachable at depth {d}"
    return f"a value the encoding cannot represent, reachable at depth {d}"


def run_bmc(model: Model, k: int, *, stop_at_first=False, max_seconds=None, targets=None) -> Outcome:
    t0 = time.perf_counter()
    deadline = t0 + max_seconds if max_seconds else None
    bmc = BMC(model, deadline)
    props = [p for p in model.props if targets is None or p.name in targets or p.kind == "error" or p.aux]
    open_ = list(props)
    out = Outcome("holds-to-depth", k, 0.0, props=props)
    timed_out = False
    for d in range(k + 1):
        if not open_:
            break
        check = [p for p in open_ if not (p.kind == "error" and d >= k) and not (p.kind == "step" and d == 0)]
        r = bmc.any_violation(check, d)
        if r == z3.unknown:
            timed_out = True
            out.unknown_at = d
            break
        if r == z3.sat:
            for p in check:
                f = bmc.find(p, d)
                if f == "unknown":
                    timed_out = True
                    break
                if f is not None:
                    out.found.append(f)
                    out.verdicts[p.name] = "violated"
                    out.depths[p.name] = d
                    open_.remove(p)
            if timed_out:
                out.unknown_at = d
                break
            if stop_at_first and out.found:
                out.depth = d           # the other properties hold to this depth only
                break
        if d < k and out.reason == "":
            o = bmc.overflow(d)
            if o == "unknown":
                timed_out = True
                out.unknown_at = d
                break
            if o is not None:
                out.reason = o
                out.overflow_at = d
    out.seconds = time.perf_counter() - t0
    for p in props:
        out.verdicts.setdefault(p.name, "holds-to-depth")
    if out.found:
        out.verdict = "violated"
    elif timed_out:
        out.verdict = "unknown"
        out.reason = out.reason or f"time limit reached at depth {out.unknown_at}"
        for p in props:
            if out.verdicts[p.name] == "holds-to-depth":
                out.verdicts[p.name] = "unknown"
    elif out.reason:
        out.verdict = "unknown"
        for p in props:
            if out.verdicts[p.name] == "holds-to-depth":
                out.verdicts[p.name] = "unknown"
    return out


# ----------------------------------------------------------------- k-induction
MAX_LEMMAS = 20000
SMALL_TABLE = 4


def make_lemmas(model: Model, infer: bool) -> list[Prop]:
    """Candidate lemmas over single locations: 'isDef(l)' for every location, and with
    ``infer`` every two-literal clause 'l1 = a or l2 != b' over locations with few values.
    k-induction keeps the ones it can prove (Houdini); the others are dropped silently."""
    locs = model.locs
    out = []
    lits = []
    for key in model.order:
        t = locs.table_of_key(key)
        text = locs.text(key)
        cn = t.code_of(None)
        if cn is not None and len(t) > 1:
            out.append(Prop(f"isDef({text})", "state", None, lemma=True, clause=((key, cn, False),)))
        if infer and len(t) <= SMALL_TABLE:
            for code, v in enumerate(t.values):
                if v is None:
                    continue
                if v is True:
                    pos, neg = text, f"not {text}"
                elif v is False:
                    pos, neg = f"not {text}", text
                else:
                    pos, neg = f"{text} = {show(v)}", f"{text} != {show(v)}"
                lits.append((key, pos, (key, code, True)))
                lits.append((key, neg, (key, code, False)))
    if infer:
        n = 0
        for i, (k1, t1, p1) in enumerate(lits):
            for k2, t2, p2 in lits[i + 1:]:
                if k1 == k2:
                    continue
                if _looks_negative(t1):
                    text = f"{_neg_text(t1)} implies {t2}"
                elif _looks_negative(t2):
                    text = f"{_neg_text(t2)} implies {t1}"
                else:
                    text = f"{t1} or {t2}"
                out.append(Prop(text, "state", None, lemma=True, clause=(p1, p2)))
                n += 1
                if n > MAX_LEMMAS:
                    raise AsmError(None, f"--infer: more than {MAX_LEMMAS} candidate lemmas; give auxiliary "
                                         f"invariants with --aux instead")
    return out


def prefilter(model: Model, lemmas: list[Prop], max_states: int = 3000, max_seconds: float = 5.0) -> list[Prop]:
    """The lemmas true in the first states a breadth-first search of the step function
    reaches (most false candidates go here, cheaply; Z3 checks the rest)."""
    if not lemmas:
        return lemmas
    t0 = time.perf_counter()
    locs = model.locs
    tables = {key: locs.table_of_key(key) for key in model.order}
    seen = set()
    frontier = []
    for _, st in model.inits:
        seen.add(_freeze(st))
        frontier.append(st)
    alive = list(lemmas)
    while frontier and alive:
        nxt = []
        for st in frontier:
            codes = {}
            for key, t in tables.items():
                codes[key] = t.code_of(st.get(key))
            alive = [p for p in alive if any((codes[k] == c) == pos for k, c, pos in p.clause)]
            if len(seen) >= max_states or time.perf_counter() - t0 > max_seconds:
                return alive
            for _, _, n, _ in all_successors(model.m, st):
                f = _freeze(n)
                if f not in seen:
                    seen.add(f)
                    nxt.append(n)
        frontier = nxt
    return alive


def clause_violation(model: Model, clause) -> object:
    """A lemma's violation over the generic variables: every literal false."""
    var = dict(zip(model.order, model.cur))
    out = []
    for key, code, positive in clause:
        t = model.locs.table_of_key(key)
        eq = sym.EQ(var[key], t.const(code))
        out.append(NOT(eq) if positive else eq)
    return AND(*out)


def _freeze(st: dict):
    return frozenset((k, sym.vk(v)) for k, v in st.items())


def _looks_negative(t: str) -> bool:
    return t.startswith("not ") or " != " in t


def _neg_text(t: str) -> str:
    if t.startswith("not "):
        return t[4:]
    if " != " in t:
        return t.replace(" != ", " = ", 1)
    if " = " in t:
        return t.replace(" = ", " != ", 1)
    return f"not {t}"


class Induction:
    """The inductive step: n transitions from an arbitrary state (namespace 'k')."""

    def __init__(self, model: Model, n: int, props, deadline=None):
        self.model = model
        self.n = n
        self.s = z3.SolverFor("QF_BV")
        self.deadline = deadline
        ns = "k"
        self.s.add(model.ranges(ns, 0))
        for j in range(n):
            self.s.add(model.frame(ns, j)["trans"])
        # the states before the last are pairwise distinct (a shortest counterexample is)
        vs = [model.state_vars(ns, j) for j in range(n)]
        for a in range(n):
            for b in range(a + 1, n):
                self.s.add(OR([x != y for x, y in zip(vs[a], vs[b])]))
        self.lits = {}
        self.lit_prop = {}
        for i, p in enumerate(props):
            lit = z3.Bool(f"assume!{i}")
            self.lits[p.name] = lit
            self.lit_prop[lit.get_id()] = p.name
            conds = []
            for j in range(n):
                if p.kind == "state":
                    conds.append(NOT(self.model.frame("k", j)["viol"][p.name]))
                elif p.kind == "step" and j >= 1:
                    conds.append(NOT(self.model.frame("k", j - 1)["viol"][p.name]))
            if conds:
                self.s.add(z3.Implies(lit, AND(*conds)))

    def bad(self, p: Prop):
        return self.model.violation(p, "k", self.n)

    def check(self, names, bad):
        """(result, model, names in the unsat core)"""
        if self.deadline is not None:
            left = self.deadline - time.perf_counter()
            if left <= 0:
                return z3.unknown, None, None
            self.s.set("timeout", max(1, int(left * 1000)))
        self.s.push()
        self.s.add(bad)
        r = self.s.check(*[self.lits[n] for n in names])
        mdl = self.s.model() if r == z3.sat else None
        core = [self.lit_prop[c.get_id()] for c in self.s.unsat_core()] if r == z3.unsat else None
        self.s.pop()
        return r, mdl, core

    def support(self, p: Prop, proved: list[str], minimize: bool) -> list[str] | None:
        """The proved invariants p's inductive step needs (None if it does not go through)."""
        others = [q for q in proved if q != p.name]
        bad = self.bad(p)
        r, _, core = self.check([p.name] + others, bad)
        if r != z3.unsat:
            return None
        need = [q for q in others if q in set(core)]
        if minimize:
            for q in list(need):
                trial = [x for x in need if x != q]
                r, _, core2 = self.check([p.name] + trial, bad)
                if r == z3.unsat:
                    keep = set(core2)
                    need = [x for x in trial if x in keep]
        return need


def run_induction(model: Model, k: int, *, targets: list[str], max_seconds=None, infer=False,
                  prefilter_seconds: float = 5.0) -> Outcome:
    """k-induction for every depth up to k: proved (with the auxiliary invariants it needed),
    violated at a depth (a replayed trace), or unknown up to k."""
    t0 = time.perf_counter()
    deadline = t0 + max_seconds if max_seconds else None
    lemmas = prefilter(model, make_lemmas(model, infer), max_seconds=prefilter_seconds)
    for p in lemmas:
        p.viol = clause_violation(model, p.clause)
    model.props.extend(lemmas)
    model._frames.clear()
    props = list(model.props)
    by_name = {p.name: p for p in props}
    shown = [p for p in props if not p.lemma]
    out = Outcome("unknown", k, 0.0, props=shown)
    bmc = BMC(model, deadline)
    live = list(props)            # neither violated nor proved yet
    proved: dict = {}             # name -> n
    support: dict = {}            # name -> [names]
    solvers: dict = {}            # n -> Induction
    base_done = -1
    timed_out = False
    real_targets = [t for t in targets if t in by_name]
    for n in range(1, k + 1):
        # base case: no violation at depths 0..n (lemmas violated there are dropped)
        for d in range(base_done + 1, n + 1):
            check = [p for p in live if not p.lemma and not (p.kind == "step" and d == 0)]
            r = bmc.any_violation(check, d)
            if r == z3.unknown:
                timed_out = True
                break
            if r == z3.sat:
                for p in check:
                    f = bmc.find(p, d)
                    if f == "unknown":
                        timed_out = True
                        break
                    if f is not None:
                        out.found.append(f)
                        out.verdicts[p.name] = "violated"
                        out.depths[p.name] = d
                        live.remove(p)
            if timed_out:
                break
            dropped = bmc.drop_false(model, [p for p in live if p.lemma], d)
            if dropped is None:
                timed_out = True
                break
            live = [p for p in live if p.name not in dropped]
            o = bmc.overflow(d)
            if o == "unknown":
                timed_out = True
                break
            if o is not None:
                out.reason = o
            base_done = d
        if timed_out or out.reason:
            break
        if all(out.verdicts.get(t) == "violated" for t in real_targets):
            break
        # inductive step, Houdini style: drop what fails at the end until the rest is inductive
        ind = solvers[n] = Induction(model, n, props, deadline)
        facts = list(proved)
        cand = [p for p in live if p.name not in proved]
        while cand:
            bad = OR([ind.bad(p) for p in cand])
            r, mdl, _ = ind.check(facts + [p.name for p in cand], bad)
            if r == z3.unknown:
                timed_out = True
                break
            if r == z3.unsat:
                for p in cand:
                    proved[p.name] = n
                    if not p.lemma:
                        out.verdicts[p.name] = "proved"
                break
            failing = [p for p in cand if z3.is_true(mdl.eval(ind.bad(p), model_completion=True))]
            if not failing:
                failing = cand[:]
            cand = [p for p in cand if p not in failing]
        if timed_out:
            break
        live = [p for p in live if p.name not in proved]
        if all(t in proved or out.verdicts.get(t) == "violated" for t in real_targets):
            break
    # which proved invariants each proved property needs, transitively
    names = list(proved)
    for name in names:
        if by_name[name].lemma:
            continue
        closure = _closure(name, by_name, proved, solvers, support)
        out.induction[name] = {"k": proved[name],
                               "needed": [q for q in closure if not by_name[q].lemma],
                               "lemmas": [q for q in closure if by_name[q].lemma]}
    out.seconds = time.perf_counter() - t0
    out.depth = max(base_done, 0)
    for p in shown:
        out.verdicts.setdefault(p.name, "unknown")
    tv = [out.verdicts[t] for t in real_targets]
    if any(v == "violated" for v in tv):
        out.verdict = "violated"
    elif tv and all(v == "proved" for v in tv):
        out.verdict = "proved"
    else:
        out.verdict = "unknown"
        if timed_out:
            out.reason = out.reason or "time limit reached"
        elif not out.reason:
            out.reason = f"not inductive up to k={k}"
    return out


def _closure(name, by_name, proved, solvers, support) -> list[str]:
    """Every proved invariant name's proof relies on (supports of supports)."""
    seen = []
    todo = [name]
    while todo:
        q = todo.pop(0)
        if q not in support:
            n = proved[q]
            earlier = [x for x in proved if proved[x] <= n]
            sup = solvers[n].support(by_name[q], earlier, minimize=not by_name[q].lemma)
            support[q] = sup or []
        for x in support[q]:
            if x != name and x not in seen:
                seen.append(x)
                todo.append(x)
    order = {p: i for i, p in enumerate(by_name)}
    return sorted(seen, key=lambda x: order[x])
