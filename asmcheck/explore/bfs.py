"""Breadth-first exploration of every reachable state.

Each distinct state is stored once (as a frozen tuple, see :mod:`.store`), with
a pointer to the state it was first reached from and the choices of that step,
so the shortest path to any state is rebuilt by following parents and is
*replayed* through the step function before anyone sees it.
"""
from __future__ import annotations

import sys
import time
from array import array
from dataclasses import dataclass, field

from ..errors import AsmError, AsmRuntimeError, InconsistentUpdate, interrupt_reason
from ..semantics.choice import DeadlineReached
from ..semantics.machine import Machine, ScriptChooser, TooManySuccessors, Undetermined
from ..semantics import types as T
from ..semantics.state import is_dom_key, same_value
from ..semantics.values import BagV, MapV, SeqV, SetV
from .canonical import Canonicalizer, ranged_domains
from .store import Layout


@dataclass
class Violation:
    prop: object                 # ir.Property (or a pseudo property for deadlocks / errors)
    state: int                   # id of the violating state (for transition properties: the target)
    source: int = -1             # for a transition property: the source state id
    picks: tuple = ()            # the choices of the violating transition
    message: str = ""
    error: AsmError | None = None


@dataclass(frozen=True)
class TimeLimit:
    """Why a run stopped on its time limit, in fields: ``seconds``, the limit (None: not known);
    ``detail``, what the run was doing then (', while enumerating the successors of state 4 (...)',
    ' in the LTL/CTL phase'; '' for a search stopped between two states).  :meth:`text` is the
    one place that writes it as a reason."""
    seconds: float | None = None
    detail: str = ""

    def text(self) -> str:
        head = "time limit reached" if self.seconds is None else f"time limit {self.seconds} s reached"
        return head + self.detail



def memory_text(n: int) -> str:
    """A memory limit as a reason names it: in MB, or in bytes under one MB (a limit of 1 byte is
    not "0 MB")."""
    return f"{n / 2**20:,.0f} MB" if n >= 2**20 else f"{n:,} byte{'' if n == 1 else 's'}"

class Stop:
    """Why a search ended before it covered every state, in one word (:attr:`Result.stop`), set
    where the reason text is set; the checks that depend on how a search stopped read this, never
    the reason's words.  ``""``: the search covered every state."""
    STATES = "states"               # the state limit (checked between two states)
    DEPTH = "depth"                 # the depth limit (a state at the bound is not expanded)
    TIME = "time"                   # the time limit
    MEMORY = "memory"               # the memory limit, or the memory ran out
    SHARE = "memory share"          # a worker of the partitioned search went over its share of the memory
    STEP_FAILED = "step failed"     # a state's steps could not be enumerated (an error outside any branch)
    TOO_MANY = "too many"           # a state with more sequences of choices than the search follows
    FIRST = "first violation"       # stopped at the first violation
    INTERRUPT = "interrupt"         # Ctrl-C or SIGTERM
    INTERNAL = "internal"           # an internal error after the search (the LTL/CTL phase)
    #: the bounds checked between two states: the states and steps recorded are those of one
    #: sequential search, whatever the number of workers
    BOUNDS = frozenset({STATES, DEPTH})
    #: the limits a user sets (a reduction such as --symmetry may let the search end within them)
    LIMITS = frozenset({STATES, DEPTH, TIME, MEMORY})


@dataclass
class Result:
    verdict: str                 # holds violated incomplete
    states: int
    transitions: int
    depth: int
    seconds: float
    violations: list = field(default_factory=list)
    reason: str = ""             # why incomplete
    checked: list = field(default_factory=list)    # the properties checked
    time_limit: TimeLimit | None = None            # the reason in fields, when the time limit ended the run
    stop: str = ""               # why incomplete, in one word (a :class:`Stop`); "" with an empty reason

    @property
    def stopped_early(self) -> bool:
        """A limit (or an error) ended the search before it covered every state, so a property
        not violated so far is undecided, even beside a violation of another one."""
        return self.verdict == "incomplete" or bool(self.reason)


class TimeUp(BaseException):
    """Raised (by a timer) when the wall-clock limit of a run has passed; like
    KeyboardInterrupt it ends a search with what it has covered."""


class PseudoProperty:
    def __init__(self, name, kind, span=None, body=None):
        self.name = name
        self.kind = kind
        self.span = span
        self.body = body
        self.source = "explorer"
        self.expect = None


DEADLOCK = PseudoProperty("deadlock", "deadlock")


def _choice_points(choices) -> tuple[str, str]:
    """(the choice points of a step with the most alternatives, the way to bound them)."""
    points = sorted((c for c in (choices or ()) if c.n > 1), key=lambda c: -c.n)[:3]
    what = ", ".join(f"{c.label} ({c.n:,} values)" for c in points)
    hint = ""
    if any(c.kind == "monitored" for c in points):
        hint = "; bound the monitored inputs with --monitored NAME=LO..HI or NAME=V1,V2"
    elif points:
        hint = "; bound the ranges of the chooses (a smaller domain, or --int-range)"
    return what, hint


def too_many_reason(machine: Machine, err) -> str:
    """Why a state's successors could not all be enumerated: the limit, and the choices of the
    step with the most alternatives (a monitored function or a choose over a large range), with
    the way to bound them."""
    what, hint = _choice_points(getattr(err, "choices", None))
    return f"{err.message}" + (f": the step chooses among {what}" if what else "") + hint


#: from this many sequences of choices of one state's step, a search stopped inside the
#: enumeration says so (the branching, not the number of states, is what took the time)
SLOW_ENUMERATION = 1_000


def stopped_inside(enumerated: int, choices, sid: int | None) -> str:
    """What a search stopped by a time limit or an interrupt was doing, when it was deep in the
    enumeration of state ``sid``'s successors (``enumerated`` sequences of choices so far, the
    last through ``choices``): '' otherwise."""
    if enumerated < SLOW_ENUMERATION or sid is None:
        return ""
    what, hint = _choice_points(choices)
    return (f", while enumerating the successors of state {sid} ({enumerated:,} sequences of choices so far"
            + (f"; its step chooses among {what}" if what else "") + ")" + hint)


def error_edge(sid: int, err) -> tuple:
    """The record of a failing branch of state ``sid``'s step kept for asmcheck.temporal:
    (state, choices, the error), the error without the frames of the step."""
    err.__traceback__ = None      # its frames would hold on to the step's data
    return sid, tuple(c.pick for c in (err.choices or ())), err


DRIFT_SPAN = 1024


def drifted(prev, window) -> bool:
    """Whether an Integer location's values moved past those of the previous watch: ``prev`` and
    ``window`` are the (least, greatest) values of the states stored between two watches (None:
    no state).  A counter whose values wrapped round at 64 bits keeps taking new values without
    a new least or greatest value; its windows still move, one beyond the other, and the two
    span many values (DRIFT_SPAN: a location with a few values moves between them by chance)."""
    if prev is None or window is None:
        return False
    (plo, phi), (wlo, whi) = prev, window
    return ((wlo >= phi and whi > phi) or (whi <= plo and wlo < plo)) and \
        max(whi, phi) - min(wlo, plo) >= DRIFT_SPAN


#: a sequence, set, bag, map or string is named as growing only once its size is this much
#: above the size first watched: a bounded buffer (a queue of three) takes new greatest sizes
#: at a few watches by chance, from the empty one up to its bound
SIZE_SPAN = 16


class SizeWatch:
    """Watches the sequences, sets, bags, maps and strings of the states found for one that keeps
    growing: each call looks at the state found last, and a location whose value is longer than
    ever before at three calls, and at least SIZE_SPAN longer than at the first call, is named
    (the search may then not end, and each state is larger than the one before)."""

    def __init__(self, machine):
        self.m = machine
        self.first: dict = {}         # location -> the size met at the first call
        self.best: dict = {}          # location -> the greatest size met at a call
        self.streak: dict = {}
        self.named: set = set()

    def watch(self, state: dict, depth: int) -> list[str]:
        out = []
        for k, v in state.items():
            if not isinstance(v, (SeqV, SetV, BagV, MapV, str)):
                continue
            n = len(v)
            best = self.best.get(k)
            if best is None:
                self.first[k] = self.best[k] = n
                continue
            if n <= best or k in self.named:
                continue
            self.best[k] = n
            self.streak[k] = self.streak.get(k, 0) + 1
            if self.streak[k] >= 3 and n - self.first[k] >= SIZE_SPAN:
                self.named.add(k)
                out.append(f"{self.m.location_text(k)} keeps growing level after level (size {n:,} at depth "
                           f"{depth}): the search may not end; bound it in the model (a guard on its size), "
                           f"or stop the search with --max-depth or --max-states")
        return out


def _declared_finite(typ) -> bool:
    """A subset domain given by its elements: its locations take no other value."""
    return isinstance(typ, T.Domain) and typ.kind == "subset" and typ.definition is not None


class _Growth:
    """Watches the Integer locations of the states found for one that keeps taking new values
    level after level (a counter without a bound, a growing population): the search may then
    not end, and the user is told which location it is while it runs.  Each location keeps the
    least and greatest value met and the depth where the last new one was met; :meth:`watch`,
    called a few times a second, names a location that took a new least or greatest value at
    the level just searched, or whose values moved past those of the previous call
    (:func:`drifted`), at three of its calls (as the native engine does between slices)."""

    def __init__(self, machine, layout):
        self.m = machine
        self.layout = layout
        self.known = 0                # layout slots classified so far
        self.slots: list[int] = []    # the slots of Integer and Natural locations
        self.lo: dict = {}
        self.hi: dict = {}
        self.grew: dict = {}
        self.window: dict = {}        # slot -> [least, greatest] of the states noted since the last watch
        self.prev: dict = {}          # the same, before the last watch
        self.depth = -1               # the depth of the last call of watch
        self.streak: dict = {}

    def _classify(self) -> None:
        keys = self.layout.keys
        fns = self.m.functions
        for i in range(self.known, len(keys)):
            k = keys[i]
            f = k if type(k) is int else (k[0] if type(k) is tuple and type(k[0]) is int else None)
            if f is not None and f < len(fns) and T.root(fns[f].codomain) in (T.INTEGER, T.NATURAL) \
                    and not _declared_finite(fns[f].codomain):
                self.slots.append(i)
        self.known = len(keys)

    def note(self, fz: tuple, depth: int, parent: tuple | None) -> None:
        """Notes the values of a new state ``fz`` (those equal to its ``parent``'s were noted
        when the parent was new, as in the native search)."""
        if self.known != len(self.layout.keys):
            self._classify()
        lo, hi, grew = self.lo, self.hi, self.grew
        n = len(fz)
        for i in self.slots:
            if i >= n:
                continue
            v = fz[i]
            if type(v) is not int or (parent is not None and i < len(parent) and parent[i] == v):
                continue
            w = self.window.get(i)
            if w is None:
                self.window[i] = [v, v]
            elif v < w[0]:
                w[0] = v
            elif v > w[1]:
                w[1] = v
            if v < lo.get(i, v + 1):
                lo[i] = v
                grew[i] = depth
            if v > hi.get(i, v - 1):
                hi[i] = v
                grew[i] = depth

    def watch(self, depth: int) -> list[str]:
        """The warnings of this call (a location is named once)."""
        if depth == self.depth:
            return []
        self.depth = depth
        out = []
        window, self.window = self.window, {}
        prev, self.prev = self.prev, window
        for i, d in self.grew.items():
            if (d >= depth - 1 or drifted(prev.get(i), window.get(i))) and self.streak.get(i, 0) < 3:
                self.streak[i] = self.streak.get(i, 0) + 1
                if self.streak[i] == 3:
                    out.append(f"{self.m.location_text(self.layout.keys[i])} keeps taking new values level after "
                               f"level (range {self.lo[i]}..{self.hi[i]} at depth {depth}): the search may not end; "
                               f"bound it in the model (a subset domain or a guard), or stop the search with "
                               f"--max-depth or --max-states")
        return out


class Explorer:
    MAX_SUCCESSORS = 1_000_000      # the sequences of choices enumerated from one state, at most
    REPORT_SECONDS = 0.25           # between two looks at the memory, the growing locations and progress

    def __init__(self, machine: Machine, *, max_states=None, max_depth=None, max_seconds=None,
                 deadlock=False, progress=None, keep_graph=False, state_props=None, step_props=None,
                 stop_at_first=False, max_memory=None, memory=None, warn=None, symmetry=None):
        self.m = machine
        # symmetry reduction (explore.symmetry.Symmetry, active): one state per class of states
        # that differ only by a renaming of interchangeable elements
        self.sym = symmetry if symmetry is not None and symmetry.active else None
        self.layout = Layout()
        gc = {d.name for d in machine.spec.domains if getattr(d, "dynamic", False)} - ranged_domains(machine.spec)
        self.canon = Canonicalizer(machine, gc)
        self.uses_extend = _uses_extend(machine.spec)
        self.max_states = max_states
        self.max_depth = max_depth
        self.max_seconds = max_seconds
        self.max_memory = max_memory      # bytes of resident memory, read with ``memory()``
        self.memory = memory
        self.deadlock = deadlock
        self.progress = progress
        self.warn = warn                  # called with each warning found while the search runs
        self.warnings: list = []
        self.growth = _Growth(machine, self.layout)
        self.sizes = SizeWatch(machine)
        self.keep_graph = keep_graph
        self.edges: list = []
        # the branches whose step fails (keep_graph): (state id, choices, the AsmError), in the
        # order found; the temporal checker gives each one a transition to a halt (see
        # asmcheck.temporal), the state graph itself holds the well-defined transitions only
        self.error_edges: list = []
        self.stop_at_first = stop_at_first
        # properties: the spec's invariants plus what the caller adds
        self.state_props = list(state_props or [])
        self.step_props = list(step_props or [])
        self.index: dict = {}
        self.frozen: list = []
        self.parent = array("l")
        self.depth_of = array("l")
        self.via: list = []
        self.init_picks: list = []
        # INVAR constraints: only states (and steps, with their monitored values) that satisfy
        # them exist, as in the SMV translation of the spec
        self.invars = [machine.term(p.body) for p in machine.spec.properties if p.kind == "invar"]

    def _invar_ok(self, st: dict, mon=None) -> bool:
        if not self.invars:
            return True
        from ..props import evaluate_all
        for fn in self.invars:
            if not any(v is True for v in evaluate_all(self.m, fn, st, mon)):
                return False
        return True

    # -------------------------------------------------------------- helpers
    def _norm(self, st: dict) -> dict:
        if self.sym is not None:
            return self.sym.canon(st)[0]
        return self.canon(st) if self.uses_extend else st

    def normalise(self, st: dict) -> tuple[dict, dict]:
        """The canonical form of ``st`` and the renaming that made it (raw element ->
        canonical element, for the elements that changed their name)."""
        if self.sym is not None:
            return self.sym.canon(st)[0], {}
        if not self.uses_extend:
            return st, {}
        out = self.canon(st)
        return out, dict(self.canon.last_mapping)

    def _add(self, st: dict, parent: int, picks, depth: int):
        fz = self.layout.freeze(st)
        sid = self.index.get(fz)
        if sid is not None:
            return sid, False
        sid = len(self.frozen)
        self.index[fz] = sid
        self.frozen.append(fz)
        self.parent.append(parent)
        self.depth_of.append(depth)
        self.via.append(picks)
        self.growth.note(fz, depth, self.frozen[parent] if parent >= 0 else None)
        return sid, True

    def state(self, sid: int) -> dict:
        return self.layout.thaw(self.frozen[sid])

    @property
    def n_states(self) -> int:
        return len(self.frozen)

    def edge_arrays(self) -> tuple[array, array]:
        """The recorded edges (keep_graph) as two arrays (sources, targets), without choices."""
        return array("q", [e[0] for e in self.edges]), array("q", [e[1] for e in self.edges])

    # -------------------------------------------------------------- the search
    def run(self) -> Result:
        m = self.m
        t0 = time.perf_counter()
        violations: list[Violation] = []
        violated: set = set()
        transitions = 0
        reason = ""
        stop = ""

        def record(v: Violation):
            key = v.prop.name
            if key in violated:
                return
            violated.add(key)
            violations.append(v)

        try:
            inits = m.initial_states()
        except Undetermined:
            raise
        frontier = []
        for log, st in inits:
            if not self._invar_ok(st):
                continue
            sid, new = self._add(self._norm(st), -1, tuple(c.pick for c in log), 0)
            if new:
                frontier.append(sid)
        max_depth_seen = 0
        all_props = [p for p in self.state_props] + [p for p in self.step_props]
        total_props = len(all_props) + (1 if self.deadlock else 0)
        depth = 0
        incomplete = False
        last_report = t0
        interrupted = False
        current = None
        time_limit = None
        try:
            while frontier:
                next_frontier = []
                for sid in frontier:
                    current = sid
                    st = self.state(sid)
                    # state properties
                    for prop in self.state_props:
                        if prop.name in violated:
                            continue
                        try:
                            ok = prop.check_state(m, st)
                        except AsmError as e:
                            record(Violation(prop, sid, message=f"cannot be evaluated: {e.message}", error=e))
                            continue
                        if not ok:
                            record(Violation(prop, sid))
                    if self.stop_at_first and violations:
                        incomplete = True
                        reason, stop = reason or "stopped at the first violation", stop or Stop.FIRST
                        frontier = []
                        break
                    if self.max_depth is not None and depth >= self.max_depth:
                        incomplete = True
                        reason, stop = f"depth limit {self.max_depth} reached", Stop.DEPTH
                        continue
                    # successors: the well-defined ones; each branch whose step fails is an
                    # error (the first one found is the 'error' violation, with its trace)
                    failed: list = []
                    try:
                        succ = self.admitted_successors(st, failed)
                    except Undetermined:
                        raise
                    except TooManySuccessors as e:
                        # a limit, not a property of the spec: the search stops, incomplete, and
                        # says which choices multiply (the last sequence of choices enumerated)
                        incomplete = True
                        reason, stop = too_many_reason(m, e), Stop.TOO_MANY
                        next_frontier = []
                        frontier = []
                        break
                    except AsmError as e:
                        # not one branch: the successors cannot be enumerated
                        err = PseudoProperty("error", "error", e.span)
                        record(Violation(err, sid, message=e.message, error=e))
                        incomplete = True
                        reason, stop = reason or "a step could not be computed", stop or Stop.STEP_FAILED
                        continue
                    for e in failed:
                        if "error" not in violated:
                            err = PseudoProperty("error", "error", e.span)
                            record(Violation(err, sid, message=e.message, error=e))
                        if self.keep_graph:
                            self.error_edges.append(error_edge(sid, e))
                    targets = []
                    moved = False       # (symmetry) a successor in the state's class, but not the state
                    for picks, ups, raw, nxt, mon in succ:
                        tid, new = self._add(nxt, sid, picks, depth + 1)
                        if tid == sid and self.sym is not None and not moved:
                            moved = self.layout.freeze(raw) != self.frozen[sid]
                        targets.append(tid)
                        if self.keep_graph:
                            self.edges.append((sid, tid, picks))
                        for prop in self.step_props:
                            if prop.name in violated:
                                continue
                            try:
                                ok = prop.check_step(m, st, ups, raw, mon)
                            except AsmError as e:
                                record(Violation(prop, tid, sid, picks, message=f"cannot be evaluated: {e.message}", error=e))
                                continue
                            if not ok:
                                # the trace to a step violation ends with this transition
                                record(Violation(prop, tid, sid, picks))
                        if new:
                            next_frontier.append(tid)
                    # a transition is a pair (state, successor): choices with the same effect count once
                    transitions += len(set(targets))
                    # a state where a step fails is not a deadlock: the error is reported
                    if self.deadlock and "deadlock" not in violated and not failed and all(t == sid for t in targets) \
                            and not moved:
                        record(Violation(DEADLOCK, sid, message="no successor" if not targets else
                                         "the only successor is the state itself"))
                    if self.max_states is not None and len(self.frozen) >= self.max_states:
                        incomplete = True
                        reason, stop = f"state limit {self.max_states} reached", Stop.STATES
                        next_frontier = []
                        frontier = []
                        break
                    now = time.perf_counter()
                    if self.max_seconds is not None and now - t0 >= self.max_seconds:
                        incomplete = True
                        time_limit = TimeLimit(self.max_seconds)
                        reason, stop = time_limit.text(), Stop.TIME
                        next_frontier = []
                        frontier = []
                        break
                    if now - last_report > self.REPORT_SECONDS:
                        last_report = now
                        if self.max_memory is not None and self.memory is not None and \
                                self.memory() > self.max_memory:
                            incomplete = True
                            reason = f"memory limit {memory_text(self.max_memory)} reached"
                            stop = Stop.MEMORY
                            next_frontier = []
                            frontier = []
                            break
                        if self.progress is not None:
                            self.progress(len(self.frozen), depth, transitions, now - t0)
                        watched = [] if depth == self.growth.depth else (
                            self.growth.watch(depth) + self.sizes.watch(self.state(len(self.frozen) - 1), depth))
                        for msg in watched:
                            self.warnings.append(msg)
                            if self.warn is not None:
                                self.warn(msg)
                    if self.stop_at_first and violations:
                        incomplete = True
                        reason, stop = reason or "stopped at the first violation", stop or Stop.FIRST
                        next_frontier = []
                        frontier = []
                        break
                    if total_props and len(violated - {"error"}) >= total_props and not self.keep_graph:
                        # every property is already violated: nothing more to learn
                        next_frontier = []
                        frontier = []
                        incomplete_ok = True
                        break
                if next_frontier:
                    depth += 1
                    max_depth_seen = depth
                frontier = next_frontier
        except KeyboardInterrupt as exc:
            incomplete = interrupted = True
            reason = interrupt_reason(exc) + stopped_inside(getattr(exc, "enumerated", 0) or 0,
                                                            getattr(exc, "choices", None), current)
            stop = Stop.INTERRUPT
        except (TimeUp, DeadlineReached) as exc:
            incomplete = True
            time_limit = TimeLimit(self.max_seconds, stopped_inside(getattr(exc, "enumerated", 0) or 0,
                                                                    getattr(exc, "choices", None), current))
            reason, stop = time_limit.text(), Stop.TIME
        except MemoryError:
            incomplete = True
            reason, stop = "out of memory", Stop.MEMORY
        if time_limit is not None and self.warnings:
            time_limit = TimeLimit(time_limit.seconds, time_limit.detail + "; " + self.warnings[-1])
            reason = time_limit.text()
        self.finishing = True       # the search is over: what follows makes its result
        secs = time.perf_counter() - t0
        if violations:
            verdict = "violated"
        elif incomplete:
            verdict = "incomplete"
        else:
            verdict = "holds"
        res = Result(verdict, len(self.frozen), transitions, max(self.depth_of) if len(self.depth_of) else 0,
                     secs, violations, reason if incomplete else "", all_props)
        res.deadlock_checked = self.deadlock
        res.interrupted = interrupted
        res.time_limit = time_limit
        res.stop = stop if incomplete else ""
        return res

    # -------------------------------------------------------------- traces
    def path_to(self, sid: int) -> list[int]:
        path = []
        while sid != -1:
            path.append(sid)
            sid = self.parent[sid]
        return path[::-1]

    def replay(self, path: list[int], last_picks: tuple | None = None, last_target: int | None = None):
        """Re-run the steps of ``path`` through the step function; check that each step
        reaches the stored state.  Returns [(state dict, choices log, update set, mon, raw
        successor, renaming)]: the state is canonical (as stored), the raw successor the
        state as the step function made it from the previous one (None for the initial
        state) and the renaming the canonicaliser's (raw element -> canonical element)."""
        steps = [(self.via[path[i + 1]], path[i + 1]) for i in range(len(path) - 1)]
        if last_picks is not None:
            steps.append((last_picks, last_target))
        return self.replay_steps(path[0], steps)

    def replay_steps(self, first: int, steps: list) -> list:
        """Replay from the stored initial state ``first`` the ``steps`` [(choices, stored target
        state)], checking each target; the entries are those of :meth:`replay`."""
        if self.sym is not None:
            return self._replay_concrete(first, steps)
        m = self.m
        ch = ScriptChooser(self.via[first])
        st0 = self._norm(m.initial_state(ch))
        if not self.is_stored(st0, first):
            raise ReplayError("the initial state does not replay")
        out = [(st0, ch.log, None, getattr(m, "init_mon", {}), None, None)]
        cur = st0
        for picks, dst in steps:
            ch = ScriptChooser(picks)
            ups, raw, ctx = m.step(cur, ch)
            nxt, mapping = self.normalise(raw)
            if not self.is_stored(nxt, dst):
                raise ReplayError(f"step to state {dst} does not replay")
            out.append((nxt, ch.log, ups, ctx.mon, raw, mapping))
            cur = nxt
        return out

    def _replay_concrete(self, first: int, steps: list) -> list:
        """:meth:`replay_steps` under symmetry reduction: the stored states are class
        representatives, the trace is concrete.  From the real initial state, each step takes the
        successor of the concrete state that is the image of the stored step (the representative's
        step under the renaming that maps the representative to the concrete state), found among
        the concrete state's successors as the step function makes them; its class is checked
        against the stored target."""
        m, sym = self.m, self.sym
        ch = ScriptChooser(self.via[first])
        cur = m.initial_state(ch)
        rep, perm = sym.canon(cur)
        if not self.is_stored(rep, first):
            raise ReplayError("the initial state does not replay")
        tau = sym.inverse(perm)         # representative -> concrete
        out = [(cur, ch.log, None, getattr(m, "init_mon", {}), None, None)]
        for picks, dst in steps:
            ups, raw, _ = m.step(rep, ScriptChooser(picks))
            nrep, perm = sym.canon(raw)
            if not self.is_stored(nrep, dst):
                raise ReplayError(f"step to state {dst} does not replay")
            want = self.layout.freeze(sym.apply(raw, tau))
            found = None
            for log, cups, nxt, mon in m.successors(cur, limit=self.MAX_SUCCESSORS, errors=[]):
                if self.layout.freeze(nxt) == want:
                    found = (nxt, log, cups, mon, None, None)
                    break
            if found is None:
                raise ReplayError(f"step to state {dst} has no concrete counterpart")
            out.append(found)
            cur, rep = found[0], nrep
            tau = sym.compose(sym.inverse(perm), tau)
        return out

    def admitted_successors(self, st: dict, errors: list | None = None) -> list:
        """The successors of ``st`` that the INVAR constraints admit, in the step function's
        order: (choices, update set, the successor as the step made it, the same under canonical
        names, monitored values).  Without ``errors``, an AsmError of the step is raised here,
        before any successor; with it (a list), the well-defined successors are returned and the
        error of each branch whose step fails is appended (those whose monitored values the
        INVAR constraints exclude are dropped, as their successors would be)."""
        out = []
        failed: list | None = [] if errors is not None else None
        for log, ups, nxt, mon in self.m.successors(st, limit=self.MAX_SUCCESSORS, errors=failed):
            if self.invars and not (self._invar_ok(st, mon) and self._invar_ok(nxt)):
                continue
            # stored under canonical names; step properties see the successor as the step made it,
            # so an extend-made element keeps its identity across the step
            out.append((tuple(c.pick for c in log), ups, nxt,
                        self._norm(nxt) if self.sym is None else self.sym.canon_from(st, nxt)[0], mon))
        if failed:
            for e in failed:
                if not self.invars or self._invar_ok(st, getattr(e, "mon", None)):
                    errors.append(e)
        return out

    def is_stored(self, st: dict, sid: int) -> bool:
        """Is ``st`` (in canonical names) the stored state ``sid``?  A replay checks each step with it."""
        return self.layout.freeze(st) == self.frozen[sid]


class ReplayError(Exception):
    """A stored trace does not replay through the step function (an internal error)."""


def _uses_extend(spec) -> bool:
    from ..semantics import ir
    found = False
    seen = set()

    def walk(x):
        nonlocal found
        if found or id(x) in seen:
            return
        seen.add(id(x))
        if isinstance(x, ir.Extend):
            found = True
            return
        if isinstance(x, (ir.Term, ir.Rule)):
            for v in vars(x).values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)
    for r in spec.rules:
        walk(r.body)
    return found
