"""Running an Avalla scenario against the spec it loads, with AsmetaV's semantics.

ASMETA's validator (AsmetaV) translates a scenario into an asm: the spec's monitored and
shared functions become controlled ones, every ``set`` is an update of that location, and a
new main rule walks through the commands.  asmcheck runs the commands directly on the step
function, with the same effects:

* ``set loc := v;``   updates ``loc`` in the current state (monitored locations included);
  the value stays until the next ``set`` of that location, as in AsmetaV.  A monitored
  location the scenario never sets reads as undef.
* ``check t;``        evaluates ``t`` in the current state; a failed (or undef) check is
  reported with the values of the locations it reads, and the run goes on.
* ``step``            one step of the main rule (``step;`` is accepted as well).
* ``step until c;``   steps while ``c`` is false (at most ``max_until`` steps).
* ``exec r;``         fires the rule ``r`` on the current state (one extra state, not a step
  of the main rule).
* ``pick $x [in r_rule] := v;``  the next step's choose rule that binds ``$x`` (in ``r_rule``)
  takes ``v``; as in AsmetaV, a value outside the range or one that makes the guard false
  for every choice of the other variables is reported, and the run stops.
* ``begin NAME ... end`` runs its commands where it is written; ``execblock [FILE:]NAME;``
  runs them again (FILE is another scenario in the same folder, without ``.avalla``).
* ``invariant NAME: t;`` (and the spec's own invariants) are checked in the initial state,
  after every step and exec, and after sets, before the state is used; a violation stops
  the run (AsmetaV stops there too).

Other choose rules take their first alternative (or a random one, with a seed), so runs are
deterministic.  Every term and rule is parsed and resolved before the run starts: a bad
scenario is an input error with a position, and nothing runs.
"""
from __future__ import annotations

import itertools
import math
import os
from dataclasses import dataclass, field, fields, is_dataclass

from ..errors import AsmError, AsmRuntimeError, AsmTypeError, Span
from ..semantics import ir
from ..semantics import types as T
from ..semantics.machine import Choice, Chooser, Ctx, DrawingChooser, Machine, RandomChooser
from ..semantics.state import UpdateSet, apply_updates, same_value
from ..semantics.values import SetV, show
from . import syntax as S
from .terms import ScenarioResolver

MAX_UNTIL = 100_000     # AsmetaV runs a step until without bound
_DYNAMIC = ("controlled", "monitored", "shared", "out", "local", "derived")


# ----------------------------------------------------------------- results
@dataclass
class Event:
    """One line of the report."""

    kind: str                   # check step until exec set pick invariant error
    span: Span | None
    state: int                  # how many steps and execs came before (0: the initial state)
    text: str = ""
    ok: bool | None = None
    values: list = field(default_factory=list)      # [(location text, value text)]
    message: str = ""
    via: tuple = ()             # the execblock commands that led here (spans)
    error: AsmError | None = None
    note: str = ""


@dataclass
class Outcome:
    scenario: str
    path: str
    spec_path: str
    events: list
    steps: int = 0              # steps of the main rule
    execs: int = 0
    stopped: str | None = None  # why the run ended early

    @property
    def checks(self) -> list:
        return [e for e in self.events if e.kind == "check"]

    @property
    def passed(self) -> int:
        return sum(1 for e in self.checks if e.ok)

    @property
    def failed(self) -> int:
        return sum(1 for e in self.checks if not e.ok)

    @property
    def ok(self) -> bool:
        return self.failed == 0 and self.stopped is None

    @property
    def result(self) -> str:
        return "pass" if self.ok else "fail"


class _OutOfRange(Exception):
    """A picked value outside the range of its variable (an input error of the scenario)."""

    def __init__(self, error: AsmError):
        super().__init__(error.message)
        self.error = error


class _Stop(Exception):
    """Ends the run (the event has been recorded)."""


# ----------------------------------------------------------------- preparation
@dataclass
class _Cmd:
    node: object                # a syntax.Command
    via: tuple
    fn: object = None           # compiled term / rule
    term: object = None         # IR (for the values of a check)
    extra: object = None


@dataclass
class _Choose:
    rule: ir.RuleDecl
    node: ir.Choose
    label: str
    names: list


@dataclass
class _PickInfo:
    var: str
    chooses: list               # the _Choose rules it fixes
    value_fn: object
    value_ir: ir.Term


class Scenario:
    """A scenario read, its spec loaded and every command resolved: ready to run."""

    def __init__(self, path: str, max_until: int = MAX_UNTIL, seed: int | None = None,
                 options: dict | None = None):
        """``options``: the machine's (``int_range``, ``monitored_ranges``, ``max_loop``, ...)."""
        self.path = path
        self.max_until = max_until
        self.seed = seed
        self.syntax = S.read_scenario(path)
        self.spec_path = self._spec_path()
        self.spec = self._load_spec()
        self.monitored = _monitored_to_controlled(self.spec)
        self.machine = Machine(self.spec, {**(options or {}), "dedupe": False})
        self.resolver = ScenarioResolver(self.spec)
        self._files: dict[str, S.Scenario] = {os.path.abspath(path): self.syntax}
        self.chooses = _choose_rules(self.spec)
        self.invariants = []
        for inv in self.syntax.invariants:
            term = self.resolver.check_term(inv.term)
            self.invariants.append((inv, term, self.machine.term(term)))
        self.commands: list[_Cmd] = []
        self._flatten(self.syntax, self.syntax.elements, (), [])
        self._compiled: dict[int, tuple] = {}
        for c in self.commands:
            self._resolve(c)

    # -- the spec
    def _spec_path(self) -> str:
        """The spec to load: the path as given (absolute, or from the working folder), else relative
        to the scenario's folder."""
        load = self.syntax.load
        if len(load) >= 2 and load[0] == load[-1] == '"':
            load = load[1:-1]
        if os.path.isfile(load):
            return os.path.normpath(load)
        # as AsmetaV joins them: an absolute-looking path is still taken under the scenario's folder
        here = os.path.dirname(self.path)
        cand = os.path.normpath(os.path.join(here, load.lstrip("/")))
        if not os.path.isfile(cand) and "\\" in load:
            # a path written with Windows separators
            alt = os.path.normpath(os.path.join(here, load.replace("\\", "/").lstrip("/")))
            if os.path.isfile(alt):
                return alt
        return cand

    def _load_spec(self):
        from ..semantics.resolve import check_file
        sp = self.syntax.load_span
        if not os.path.isfile(self.spec_path):
            raise AsmError(sp, f"cannot find the spec to load: {self.spec_path} does not exist")
        if not self.spec_path.endswith(".asm"):
            raise AsmError(sp, f"the spec to load must be an .asm file, not {self.syntax.load}")
        try:
            spec = check_file(self.spec_path)
        except AsmError as err:
            err.notes.append((sp, f"loaded by scenario {self.syntax.name}"))
            raise
        if spec is None:
            raise AsmError(sp, f"{self.syntax.load} is empty: nothing to run")
        if spec.main is None:
            raise AsmError(sp, f"{spec.name} has no main rule: a scenario needs one to run "
                               f"(is it a module?)")
        return spec

    # -- blocks
    def _other_file(self, name: str, cmd: S.ExecBlock) -> S.Scenario:
        path = os.path.join(os.path.dirname(self.path), name + ".avalla")
        key = os.path.abspath(path)
        sc = self._files.get(key)
        if sc is None:
            if not os.path.isfile(path):
                raise AsmError(cmd.span, f"execblock {name}:{cmd.block}: no scenario {path}")
            sc = self._files[key] = S.read_scenario(path)
        return sc

    def _flatten(self, sc: S.Scenario, elements, via: tuple, stack: list) -> None:
        for e in elements:
            if isinstance(e, S.Block):
                key = (os.path.abspath(sc.path), e.name)
                if key in stack:
                    raise AsmError(e.name_span, f"block {e.name} runs itself (through execblock)")
                self._flatten(sc, e.elements, via, stack + [key])
            elif isinstance(e, S.ExecBlock):
                target = self._other_file(e.scenario, e) if e.scenario is not None else sc
                block = next((b for b in target.blocks() if b.name == e.block), None)
                if block is None:
                    where = f"scenario {target.name} ({target.path})" if e.scenario is not None else "this scenario"
                    raise AsmError(e.block_span, f"no block {e.block} in {where}")
                key = (os.path.abspath(target.path), block.name)
                if key in stack:
                    raise AsmError(e.span, f"execblock {e.block}: the block runs itself")
                self._flatten(target, block.elements, via + (e.span,), stack + [key])
            else:
                self.commands.append(_Cmd(e, via))

    # -- terms and rules
    def _resolve(self, c: _Cmd) -> None:
        node = c.node
        hit = self._compiled.get(id(node))
        if hit is not None:
            c.fn, c.term, c.extra = hit
            return
        res, m = self.resolver, self.machine
        if isinstance(node, S.Check):
            c.term = res.check_term(node.term)
            c.fn = m.term(c.term)
        elif isinstance(node, S.StepUntil):
            c.term = res.check_term(node.cond)
            c.fn = m.term(c.term)
        elif isinstance(node, S.Set):
            c.term = res.set_rule(node.span, node.location, node.value)
            c.fn = m.rule(c.term)
        elif isinstance(node, S.Exec):
            c.term = res.exec_rule(node.rule)
            c.fn = m.rule(c.term)
        elif isinstance(node, S.Pick):
            c.extra = self._resolve_pick(node)
        self._compiled[id(node)] = (c.fn, c.term, c.extra)

    def _resolve_pick(self, p: S.Pick) -> _PickInfo:
        if p.value.text.strip() == "undef":
            raise AsmTypeError(p.value.span, "picking the value undef is not allowed")
        with_var = [c for c in self.chooses if p.var in c.names]
        if p.rule is not None:
            # as AsmetaV matches them: 'r_x(D1,D2)' is r_x over D1, D2, and 'r_x' is the r_x without
            # parameters (not an overload that has some)
            want = p.rule.replace(" ", "").replace("(", "_").replace(",", "_").replace(")", "")
            rules = [r for r in self.spec.rules if _asmetav_signature(r) == want]
            if not rules:
                raise AsmTypeError(p.rule_span, f"no rule {p.rule} in {self.spec.name}")
            found = [c for c in with_var if c.rule in rules]
            if not found:
                raise AsmTypeError(p.var_span, f"no choose rule in {p.rule} binds {p.var}")
        else:
            found = with_var
            if not found:
                raise AsmTypeError(p.var_span, f"no choose rule in {self.spec.name} binds {p.var}")
            if len({id(c.rule) for c in found}) > 1:
                names = ", ".join(sorted({_signature(c.rule) for c in found}))
                raise AsmTypeError(p.var_span, f"more than one choose rule binds {p.var} (in {names}): "
                                               f"say which with 'pick {p.var} in r_rule := ...'")
        value = self.resolver.value_term(p.value)
        for c in found:
            var = next(v for v, _ in c.node.bindings if v.name == p.var)
            if not T.compatible(value.type, var.type) and not (var.type is T.NATURAL and value.type is T.INTEGER):
                raise AsmTypeError(p.value.span, f"{p.var} ranges over {var.type}; the value has domain {value.type}")
        return _PickInfo(p.var, found, self.machine.term(value), value)

    # -- running
    def run(self) -> Outcome:
        return _Run(self).run()


def _signature(r: ir.RuleDecl) -> str:
    if not r.params:
        return r.name
    return f"{r.name}({','.join(str(p.type) for p in r.params)})"


def _asmetav_signature(r: ir.RuleDecl) -> str:
    """AsmetaV's key of a rule declaration: its name, then '_' and each parameter's domain name."""
    return r.name + "".join("_" + str(p.type) for p in r.params)


def _monitored_to_controlled(spec) -> list:
    """As AsmetaV does: the scenario gives monitored (and shared) locations their values.
    Returns the functions changed."""
    out = []
    for f in spec.functions:
        if f.kind in ("monitored", "shared"):
            f.kind = "controlled"
            out.append(f)
    return out


def _walk_ir(node, visit, seen=None):
    """Visit every IR term and rule below ``node`` (not the bodies of called rules)."""
    if seen is None:
        seen = set()
    if isinstance(node, (list, tuple)):
        for x in node:
            _walk_ir(x, visit, seen)
        return
    if not is_dataclass(node) or isinstance(node, (ir.RuleDecl, ir.Function, ir.Var)) or isinstance(node, type):
        return
    if id(node) in seen:
        return
    seen.add(id(node))
    visit(node)
    for f in fields(node):
        if f.name in ("type", "span"):
            continue
        _walk_ir(getattr(node, f.name), visit, seen)


def _choose_rules(spec) -> list[_Choose]:
    out = []
    for rd in spec.rules:
        if rd.body is None:
            continue

        def visit(n, rd=rd):
            if isinstance(n, ir.Choose):
                out.append(_Choose(rd, n, f"choose at {n.span.short()}", [v.name for v, _ in n.bindings]))
        _walk_ir(rd.body, visit)
    return out


def _has_var(node) -> bool:
    found = []

    def visit(n):
        if isinstance(n, ir.VarRef):
            found.append(n)
    _walk_ir(node, visit)
    return bool(found)


def _locations(term) -> list:
    """The locations a term reads whose arguments do not depend on bound variables."""
    out = []

    def visit(n):
        if isinstance(n, ir.Loc) and n.func.kind in _DYNAMIC and not _has_var(n.args):
            out.append(n)
    _walk_ir(term, visit)
    return out


# ----------------------------------------------------------------- choosers
class _PickChooser(Chooser):
    """Choose rules fixed by ``pick`` take the picked values; the others ask ``base``."""

    def __init__(self, base: Chooser, picks: dict):
        super().__init__()
        self.base = base
        self.picks = picks          # label -> [(var, value, pick command)]
        self.log = base.log

    def value(self, label, dom):
        return self.base.value(label, dom)

    def draw(self, label, var, dom):
        """A picked value of a choose over Integer, Natural or Real; else the base draws one."""
        for v, val, _ in self.picks.get(label, ()):
            if v == var:
                self.log.append(Choice("choose", label, 0, 0, {var: val}))
                return val
        return self.base.draw(label, var, dom)

    def choose(self, kind, label, options, values_repr=None) -> int:
        fixed = self.picks.get(label) if kind == "choose" else None
        if not fixed:
            return self.base.choose(kind, label, options, values_repr)
        allowed = [i for i, o in enumerate(options)
                   if isinstance(o, dict) and all(same_value(o.get(var), val) for var, val, _ in fixed)]
        if not allowed:
            var, val, cmd = fixed[0]
            picked = ", ".join(f"{v} = {show(x)}" for v, x, _ in fixed)
            raise AsmRuntimeError(cmd.span, f"the {label} has no choice with {picked}")
        i = self.base.choose(kind, label, [options[j] for j in allowed], values_repr)
        return allowed[i]


# ----------------------------------------------------------------- the run
class _Run:
    def __init__(self, sc: Scenario):
        self.sc = sc
        self.m = sc.machine
        self.out = Outcome(sc.syntax.name, sc.path, sc.spec_path, [])
        self.steps = 0
        self.execs = 0
        self.last = "initial"       # what made the current state: initial, step, or the exec's position
        self.state: dict = {}
        self.dirty = True           # the state has not had its invariants checked
        self.picks: list = []       # (pick command, _PickInfo) for the next step
        self.k = 0                  # choosers made (for the random seed)
        self.spec_invariants = [(p, self.m.term(p.body)) for p in self.m.spec.properties if p.kind == "invariant"]
        self._locs: dict = {}       # id(term) -> [(function, argument closures, closure)]

    def chooser(self) -> Chooser:
        self.k += 1
        if self.sc.seed is None:
            return DrawingChooser(self.k)
        return RandomChooser(self.sc.seed * 1_000_003 + self.k)

    def event(self, kind, cmd: _Cmd | None, span=None, **kw) -> Event:
        ev = Event(kind, span if span is not None else (cmd.node.span if cmd else None), self.steps + self.execs,
                   via=cmd.via if cmd else (), **kw)
        self.out.events.append(ev)
        return ev

    def stop(self, reason: str) -> None:
        self.out.stopped = reason
        raise _Stop()

    def run(self) -> Outcome:
        try:
            try:
                self.state = self.m.initial_state(self.chooser())
            except AsmError as err:
                self.event("error", None, err.span, message=f"the initial state cannot be built: {err.message}",
                           error=err)
                self.stop("runtime error")
            for c in self.sc.commands:
                getattr(self, "do_" + type(c.node).__name__)(c)
            self.invariants()
        except _Stop:
            pass
        self.out.steps = self.steps
        self.out.execs = self.execs
        return self.out

    # -- values
    def values(self, term, state) -> list:
        """The locations a term reads (those not under a quantifier) and their values."""
        locs = self._locs.get(id(term))
        if locs is None:
            locs = self._locs[id(term)] = [(loc.func, [self.m.term(a) for a in loc.args], self.m.term(loc))
                                           for loc in _locations(term)]
        out = []
        seen = set()
        for func, arg_fns, fn in locs:
            try:
                ctx = Ctx(self.m, state, Chooser())
                args = [a(ctx) for a in arg_fns]
                v = fn(ctx)
            except AsmError:
                continue
            text = func.name + (f"({','.join(show(a) for a in args)})" if args else "")
            if text not in seen:
                seen.add(text)
                out.append((text, show(v)))
        return out

    def evaluate(self, fn, state):
        ctx = Ctx(self.m, state, Chooser())
        return fn(ctx)

    # -- invariants
    def invariants(self) -> None:
        if not self.dirty:
            return
        self.dirty = False
        where = {"initial": "in the initial state", "step": f"after step {self.steps}"}.get(
            self.last, f"after the exec at line {self.last}")
        for inv, term, fn in self.sc.invariants:
            try:
                v = self.evaluate(fn, self.state)
            except AsmError as err:
                self.event("invariant", None, inv.name_span, text=inv.name, ok=False, error=err,
                           message=f"scenario invariant {inv.name} cannot be evaluated {where}: {err.message}")
                self.stop(f"invariant {inv.name}")
            if v is not True:
                self.event("invariant", None, inv.name_span, text=inv.name, ok=False,
                           values=self.values(term, self.state),
                           message=f"scenario invariant {inv.name} is {'undef' if v is None else 'violated'} {where}")
                self.stop(f"invariant {inv.name}")
        for prop, fn in self.spec_invariants:
            try:
                v = self.evaluate(fn, self.state)
            except AsmError as err:
                self.event("invariant", None, prop.span, text=prop.name, ok=False, error=err,
                           message=f"invariant {prop.name} of the spec cannot be evaluated {where}: {err.message}")
                self.stop(f"invariant {prop.name}")
            if v is not True:
                self.event("invariant", None, prop.span, text=prop.name, ok=False,
                           values=self.values(prop.body, self.state),
                           message=f"invariant {prop.name} of the spec is {'undef' if v is None else 'violated'} {where}")
                self.stop(f"invariant {prop.name}")

    # -- commands
    def do_Check(self, c: _Cmd) -> None:
        node: S.Check = c.node
        try:
            v = self.evaluate(c.fn, self.state)
        except AsmError as err:
            self.event("check", c, text=node.term.display(), ok=False, values=self.values(c.term, self.state),
                       message=f"cannot be evaluated: {err.message}", error=err)
            return
        msg = "" if v is True or v is False else "the term is undef"
        self.event("check", c, text=node.term.display(), ok=v is True, values=self.values(c.term, self.state),
                   message=msg)

    def do_Set(self, c: _Cmd) -> None:
        node: S.Set = c.node
        self.fire(c, c.fn, "set")
        self.event("set", c, text=f"{node.location.display()} := {node.value.display()}", ok=True)
        self.dirty = True

    def do_Pick(self, c: _Cmd) -> None:
        node: S.Pick = c.node
        # a later pick of the same variable (for the same rules) replaces an earlier one
        self.picks = [(p, info) for p, info in self.picks
                      if not (p.var == node.var and {id(x) for x in info.chooses} == {id(x) for x in c.extra.chooses})]
        self.picks.append((node, c.extra))
        self.event("pick", c, text=f"{node.var} := {node.value.display()}", ok=True)

    def do_Step(self, c: _Cmd) -> None:
        self.invariants()
        chooser = self.pick_chooser(c)
        self.step(c, chooser)
        self.picks = []
        self.event("step", c, text=f"step {self.steps}", ok=True)
        self.invariants()

    def do_StepUntil(self, c: _Cmd) -> None:
        node: S.StepUntil = c.node
        start = self.steps
        while True:
            self.invariants()
            try:
                v = self.evaluate(c.fn, self.state)
            except AsmError as err:
                self.event("until", c, text=node.cond.display(), ok=False, error=err,
                           values=self.values(c.term, self.state),
                           message=f"the condition cannot be evaluated after {self.steps - start} step(s): "
                                   f"{err.message}")
                self.stop("step until")
            if v is True:
                break
            if self.steps - start >= self.sc.max_until:
                self.event("until", c, text=node.cond.display(), ok=False, values=self.values(c.term, self.state),
                           message=f"the condition is still {'undef' if v is None else 'false'} after "
                                   f"{self.sc.max_until} steps (the limit; see --max-until)")
                self.stop("step until")
            chooser = self.pick_chooser(c)
            self.step(c, chooser)
            self.invariants()
        self.picks = []
        self.event("until", c, text=node.cond.display(), ok=True,
                   message=f"reached after {self.steps - start} step(s)")

    def do_Exec(self, c: _Cmd) -> None:
        node: S.Exec = c.node
        self.invariants()
        self.fire(c, c.fn, "exec", self.pick_chooser(c))
        self.execs += 1
        self.last = str(node.span.line)
        self.event("exec", c, text=node.rule.display(), ok=True)
        self.dirty = True
        self.invariants()

    # -- helpers
    def fire(self, c: _Cmd, fn, what: str, chooser=None) -> None:
        """Fire a rule on the current state (a set or an exec)."""
        ctx = Ctx(self.m, self.state, chooser or self.chooser())
        ups = UpdateSet()
        try:
            fn(ctx, ups)
            nxt = apply_updates(self.state, ups, self.m.keep_undef)
        except AsmError as err:
            self.event("error", c, message=f"{what} failed: {err.message}", note=self.unset_note(), error=err,
                       ok=False)
            self.stop("runtime error")
        for k, v in ctx.lazy.items():
            if k not in nxt and k not in ups.locs:
                nxt[k] = v
        self.state = nxt

    def step(self, c: _Cmd, chooser) -> None:
        try:
            ups, nxt, ctx = self.m.step(self.state, chooser)
        except AsmError as err:
            self.event("error", c, message=f"step {self.steps + 1} failed: {err.message}", note=self.unset_note(),
                       error=err, ok=False)
            self.stop("runtime error")
        self.state = nxt
        self.steps += 1
        self.last = "step"
        self.dirty = True

    def unset_note(self) -> str:
        """The monitored locations the scenario has not set (they read as undef)."""
        unset = []
        for f in self.sc.monitored:
            if f.arity == 0:
                if f.index not in self.state:
                    unset.append(f.name)
                continue
            try:
                doms = [self.m.domain_values(d, Ctx(self.m, self.state, Chooser()), f.span) for d in f.domain]
            except AsmError:
                doms = None
            if doms is None or math.prod(len(d) for d in doms) > 10_000:
                if not any(type(k) is tuple and k[0] == f.index for k in self.state):
                    unset.append(f"{f.name}(...)")
                continue
            for args in itertools.product(*doms):
                if (f.index, tuple(args)) not in self.state:
                    unset.append(f"{f.name}({','.join(show(a) for a in args)})")
        if not unset:
            return ""
        shown = ", ".join(unset[:12]) + (f" and {len(unset) - 12} more" if len(unset) > 12 else "")
        return f"monitored locations read as undef until the scenario sets them; not set: {shown}"

    def pick_chooser(self, c: _Cmd) -> Chooser:
        base = self.chooser()
        if not self.picks:
            return base
        table: dict = {}
        for p, info in self.picks:
            try:
                value = self.evaluate(info.value_fn, self.state)
            except AsmError as err:
                self.event("pick", None, p.span, ok=False, error=err, text=f"{p.var} := {p.value.display()}",
                           message=f"the picked value cannot be evaluated: {err.message}")
                self.stop("pick")
            for ch in info.chooses:
                self.feasible(p, ch, value)
                table.setdefault(ch.label, []).append((p.var, value, p))
        return _PickChooser(base, table)

    def feasible(self, p: S.Pick, ch: _Choose, value) -> None:
        """AsmetaV's checks of a pick: the value is in the range of its variable, and some
        choice of the other variables satisfies the guard."""
        node = ch.node
        own = {v.uid for v, _ in node.bindings}
        outer = []

        def visit(n):
            if isinstance(n, ir.VarRef) and n.var.uid not in own:
                outer.append(n)
        _walk_ir([r for _, r in node.bindings] + ([node.guard] if node.guard is not None else []), visit)
        if outer:
            return      # the range or guard reads variables of the enclosing rule: checked when it runs
        picked = {v.uid: value for v, _ in node.bindings if v.name == p.var}
        # other picks of the same choose rule
        for q, info in self.picks:
            if q is not p and any(x is ch for x in info.chooses):
                try:
                    qv = self.evaluate(info.value_fn, self.state)
                except AsmError:
                    continue
                for v, _ in node.bindings:
                    if v.name == q.var:
                        picked[v.uid] = qv
        ctx = Ctx(self.m, self.state, Chooser())
        ctx.env = dict(picked)
        text = f"{p.var} := {p.value.display()}"
        try:
            for v, rng in node.bindings:
                if v.uid in picked and isinstance(rng, ir.DomainTerm) and rng.domain in (T.INTEGER, T.NATURAL,
                                                                                          T.REAL):
                    x = picked[v.uid]
                    if rng.domain is T.NATURAL and not (type(x) is int and x >= 0):
                        raise _OutOfRange(AsmError(p.value.span, f"pick {text}: {show(x)} is not in the range of "
                                                                 f"{v.name} (Natural) in {_signature(ch.rule)}"))
                    continue
                if v.uid in picked:
                    items = self.m.term(rng)(ctx)
                    if isinstance(items, SetV):
                        items = items.ordered()
                    elif items is not None and hasattr(items, "__iter__") and not isinstance(items, (str, dict)):
                        items = list(items)
                    if items is not None and not any(same_value(x, picked[v.uid]) for x in items):
                        msg = f"{show(picked[v.uid])} is not in the range of {v.name} in {_signature(ch.rule)}"
                        if isinstance(rng, ir.DomainTerm):
                            # outside the variable's domain: AsmetaV throws, an error in the scenario (exit 2)
                            raise _OutOfRange(AsmError(p.value.span, f"pick {text}: {msg} (the domain "
                                                                     f"{rng.domain})"))
                        # outside a range term: AsmetaV's run fails (the choose rule finds no choice)
                        self.event("pick", None, p.span, ok=False, text=text, message=msg)
                        self.stop("pick")
            rest = [(v, r) for v, r in node.bindings if v.uid not in picked]
            guard = node.guard if node.guard is not None else ir.Const(T.BOOLEAN, node.span, True)
            test = ir.Quant(T.BOOLEAN, node.span, "exists", rest, guard) if rest else guard
            ok = self.m.term(test)(ctx)
        except _OutOfRange as bad:
            raise bad.error from None
        except AsmError:
            return      # an infinite range, say: the choose rule checks the value when it runs
        if ok is not True:
            self.event("pick", None, p.span, ok=False, text=text,
                       message=f"with this value the guard of the choose rule in {_signature(ch.rule)} "
                               f"({ch.node.span.short()}) is false for every choice")
            self.stop("pick")


def run_scenario(path: str, max_until: int = MAX_UNTIL, seed: int | None = None,
                 options: dict | None = None) -> Outcome:
    """Read, resolve and run a scenario (AsmError on an input error).  ``options`` are the
    machine's: ``int_range`` and ``monitored_ranges`` (as --int-range / --monitored give them to
    explore), ``max_loop``."""
    return Scenario(path, max_until, seed, options).run()
