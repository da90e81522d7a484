"""The public Python API: load a spec, explore it, check it, simulate it, run Z3 on it.

``import asmcheck`` re-exports what is here (see docs/api.md, whose examples run as tests).
The command line (:mod:`asmcheck.cli`) is written on top of this module: it parses
arguments, calls these functions and prints what they return.  This module prints nothing
and picks no exit code of a process; it only says which one a result stands for
(``exit_code``).

Engine selection lives in one place, :func:`choose_engine`.

It is one module of a little over 900 lines because it is the whole public surface: the
Model, Exploration, Simulation, BmcResult and Gate classes return one another, and keeping
them side by side keeps that surface readable in one place (option parsing already lives
apart, in :mod:`asmcheck.options`).
"""
from __future__ import annotations

import os
import re
import signal
import sys
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

from .errors import AsmError, UsageError, interrupt_reason
from .parallel import parse_workers  # noqa: F401  (re-exported: --workers N|auto)
from .options import default_max_memory, monitored_ranges, parse_int_range, parse_range  # noqa: F401
from .explore.bfs import Explorer, ReplayError, Result, Stop, TimeLimit, TimeUp, memory_text
from .explore.store import memory_in_use  # noqa: F401  (part of the API)
from .semantics.choice import DeadlineReached
from .props.files import properties_for, strip_comments
from .props import spec_properties
from .props.load import load_machine
from .report import gate as _gate
from .report.trace import build_trace, explore_violation_lines, failing_json, temporal_json, temporal_text, \
    trace_json, trace_text

EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_INCOMPLETE = 0, 1, 2, 3

__all__ = ["load", "parse", "check", "Simulation", "scenario_report", "scenario_json", "scenario", "find_specs", "Model", "Exploration", "Violation", "Trace", "Gate",
           "BmcResult", "AsmError", "UsageError", "parse_range", "parse_int_range", "default_max_memory",
           "choose_engine", "TimeUp", "ReplayError", "ReplayMismatch", "EXIT_OK", "EXIT_VIOLATED", "EXIT_ERROR", "EXIT_INCOMPLETE"]

# ----------------------------------------------------------------- loading
def load(path, *, import_path=(), monitored=None, int_range=None, properties=None,
         default_properties: bool = True, unknown_monitored: str = "error", properties_must_apply: bool = True,
         max_loop=None) -> "Model":
    """Parse and type-check the spec at ``path`` (with its imports) and find the properties
    that apply to it.  Raises :class:`AsmError` (located) or :class:`UsageError`.

    ``unknown_monitored="ignore"`` leaves out the ``monitored`` names the spec does not
    declare at all, and ``properties_must_apply=False`` the ``properties`` files that do not
    name it (the gate gives one set of options to many specs).  ``max_loop`` bounds the
    iterations of one while/iterate within a step (10,000 by default)."""
    from .semantics.machine import Machine
    path = os.fspath(path)
    _set_import_path(import_path)
    _check_readable(path, "spec")
    options: dict = {}
    if int_range is not None:
        options["int_range"] = parse_int_range(int_range)
    if max_loop is not None:
        options["max_loop"] = _max_loop(max_loop)
    spec, machine = load_machine(path, options)
    if monitored and unknown_monitored == "ignore":
        declared = {f.name for f in spec.functions}
        monitored = {k: v for k, v in dict(monitored).items() if k in declared}
    if monitored:
        ranges = monitored_ranges(machine, dict(monitored))
        options["monitored_ranges"] = ranges
        machine = Machine(spec, options)
    files = [os.fspath(p) for p in properties] if properties else None
    for p in files or ():
        _check_readable(p, "property file")
    state_props, step_props = spec_properties(machine)
    extra_state, extra_step, temporal = properties_for(spec, machine, path, files, use_default=default_properties,
                                                       must_apply=properties_must_apply)
    return Model(path, spec, machine, state_props + extra_state, step_props + extra_step, temporal, options,
                 files, default_properties)


def _set_import_path(import_path) -> None:
    """The folders searched for imports from now on (the ``-I`` option)."""
    from .semantics.resolve import set_import_path
    dirs = [os.fspath(d) for d in import_path or ()]
    for d in dirs:
        if not os.path.isdir(d):
            raise UsageError(f"--import-path {d}: no such folder")
    set_import_path(os.path.abspath(d) for d in dirs)


def _check_readable(path: str, what: str) -> None:
    """A file to read must be a regular file (not a folder, a device or a pipe); a missing
    file is left to the reader, which says so."""
    import stat
    try:
        st = os.stat(path)
    except OSError:
        return
    a = "an" if what[0] in "aeiou" else "a"
    if stat.S_ISDIR(st.st_mode):
        raise AsmError(None, f"{path}: is a folder, not {a} {what}")
    if not stat.S_ISREG(st.st_mode):
        # the reader's own refusal (located at 1:1, naming the kind of file), without opening it
        from .syntax.parser import read_source_bytes
        read_source_bytes(path)
        raise AsmError(None, f"{path}: is not a regular file; asmcheck reads {a} {what} only from a regular file")


@dataclass
class PropertyInfo:
    name: str
    kind: str                  # invariant step ltl ctl justice compassion
    location: str = ""         # file:line:col of its declaration
    source: str = "spec"       # spec, or the property file's path


class Model:
    """A loaded spec: its IR (``spec``), its step function (``machine``) and the properties
    that apply to it."""

    def __init__(self, path, spec, machine, state_props, step_props, temporal, options=None, prop_files=None,
                 default_properties=True):
        self.path = path
        self.spec = spec
        self.machine = machine
        self.name = spec.name
        self.state_props = state_props
        self.step_props = step_props
        self.temporal = temporal
        self.options = dict(options or {})
        self.prop_files = prop_files
        self.default_properties = default_properties

    @property
    def properties(self) -> list[PropertyInfo]:
        out = []
        for p in self.state_props + self.step_props + list(self.temporal):
            span = getattr(p, "span", None)
            loc = str(span) if span is not None and getattr(span, "line", 0) else ""
            out.append(PropertyInfo(p.name, getattr(p, "kind", "invariant"), loc,
                                    getattr(p, "source", "spec") or "spec"))
        return out

    def property_files(self) -> list[str]:
        """The property files that were looked at for this spec (given, and those beside it)."""
        from .props.files import default_property_files
        out = list(self.prop_files or [])
        if self.default_properties:
            out += [p for p in default_property_files(self.path) if p not in out]
        return out

    def candidate_property_files(self) -> list[str]:
        """Property files that name this spec in their ``applies to`` line but were not
        found by the search (in ``properties/`` folders above the spec and above the
        import path's folders)."""
        from .props.files import read_prop_file
        from .semantics.resolve import import_path as search_path
        seen = set(os.path.abspath(p) for p in self.property_files())
        roots = [Path(self.path).resolve().parent] + [Path(d) for d in search_path()] + [Path.cwd()]
        out = []
        for root in roots:
            p = root
            for _ in range(6):
                cand = p / "properties"
                if cand.is_dir():
                    for f in sorted(cand.glob("*.prop")):
                        a = os.path.abspath(f)
                        if a in seen:
                            continue
                        seen.add(a)
                        try:
                            pf = read_prop_file(str(f))
                        except AsmError:
                            continue
                        if pf.applies is not None and self.name in pf.applies:
                            out.append(str(f))
                if p.parent == p:
                    break
                p = p.parent
        return out

    # ------------------------------------------------------------- explore
    def explore(self, properties=None, *, engine: str = "auto", workers: int = 1, max_states=None,
                max_depth=None, max_seconds=None, max_memory=None, deadlock: bool = False, fair=(),
                graph: bool = False, progress=None, started=None, warn=None, cluster=None, bitstate=None,
                worker_memory=None, symmetry: bool = False) -> "Exploration":
        """Explore every reachable state (breadth first) and check the properties.

        ``workers`` > 1 partitions the states among worker processes, ``cluster`` (a Ray address,
        'auto' or 'local') among Ray actors, with the result of one worker; ``bitstate`` (BITS)
        runs a bitstate search (see :mod:`asmcheck.parallel`).

        ``max_seconds`` bounds the wall-clock time of the whole call (counted from ``started``, a
        ``time.perf_counter()`` reading, when given: the command line counts from its start).
        ``warn(message)`` is called with warnings found while the search runs (a location that
        keeps taking new values, for instance).  A recursion that does not end in the spec raises
        :class:`AsmError` at the rule or function that recurses.

        ``symmetry``: explore one state per class of states that differ only by a renaming of
        interchangeable domain elements (see :mod:`asmcheck.explore.symmetry`); the counts are
        then counts of classes, on the Python engine."""
        try:
            return _explore(self, properties, engine=engine, workers=workers, max_states=max_states,
                            max_depth=max_depth, max_seconds=max_seconds, max_memory=max_memory, deadlock=deadlock,
                            fair=fair, graph=graph, progress=progress, started=started, warn=warn,
                            scaling={"cluster": cluster, "bitstate": bitstate, "worker_memory": worker_memory},
                            symmetry=symmetry)
        except RecursionError as exc:
            from .errors import located_recursion_error
            raise located_recursion_error(exc, self.path) from None

    # ------------------------------------------------------------- swarm
    def swarm(self, *, walks: int = 32, depth: int = 100, seed=None, workers="auto", cluster=None,
              deadlock: bool = False, fair=(), color: bool = False):
        """Random walks (``walks`` of up to ``depth`` steps) that check every property on every
        state met, in parallel (``workers``, or Ray tasks on ``cluster``): a report with
        ``json()``, ``lines`` (the text report) and ``violated``.  Random walks prove nothing;
        :meth:`explore` does."""
        from .parallel.run import swarm_report
        return swarm_report(self, walks=walks, depth=depth, seed=seed, workers=workers, cluster=cluster,
                            deadlock=deadlock, fair=fair, color=color)

    # ------------------------------------------------------------- simulate
    def simulate(self, steps: int = 10, *, seed=None, random: bool = False, inputs=None) -> "Simulation":
        """One run: the initial state and one record per step (``number``, ``choices``,
        ``changed``, ``state``, ``violated``, ``error``); it stops at an error or a violated
        invariant.  ``inputs``: a file of monitored values (``location = value`` lines, ``---``
        between steps) or the list of per-step dicts it reads as."""
        from .semantics.machine import Machine
        from .simulate import read_inputs, simulate
        if steps < 0:
            raise UsageError("the number of steps must be 0 or more")
        machine = Machine(self.spec, {**self.options, "dedupe": False})
        if isinstance(inputs, (str, os.PathLike)):
            _check_readable(os.fspath(inputs), "input file")
            inputs = read_inputs(os.fspath(inputs))
        if random and seed is None:
            seed = 0
        done: list = []
        try:
            for st in simulate(machine, steps, seed=seed, random_choices=random, inputs=inputs):
                done.append(st)
        except KeyboardInterrupt as exc:
            # Ctrl-C (or SIGTERM): the steps so far are the run (``interrupted`` says why it is short)
            sim = Simulation(self, machine, done)
            sim.interrupted = interrupt_reason(exc)
            return sim
        return Simulation(self, machine, done)

    # ------------------------------------------------------------- bmc
    def bmc(self, k: int, *, induction: bool = False, properties=None, assume=None, aux=(), infer: bool = False,
            first: bool = False, loop_bound=None, max_seconds=None) -> "BmcResult":
        """Z3 bounded model checking to depth ``k`` (or k-induction for k = 1..K)."""
        from .smt.bmc import ReplayMismatch as Mismatch
        from .smt.check import check as smt_check
        if k < 0:
            raise UsageError("-k must be 0 or more")
        try:
            model, out, targets = smt_check(self.spec, self.machine, list(self.state_props), list(self.step_props),
                                            k=k, induction=induction, properties=properties, assume=assume,
                                            aux=aux, infer=infer, first=first, loop_bound=loop_bound,
                                            max_seconds=max_seconds)
        except Mismatch as e:
            raise ReplayMismatch(str(e)) from None
        return BmcResult(self, model, out, targets, k, induction)

    # ------------------------------------------------------------- conform / scenario
    def conform(self, transcript):
        """Check an ASMETA simulator transcript against the spec: (transcript, None) when it
        conforms, else (transcript, the first step that does not)."""
        from .conform import conform, read_transcript
        _check_readable(os.fspath(transcript), "transcript")
        tr = read_transcript(os.fspath(transcript))
        return tr, conform(self.machine, tr)

    def scenario(self, path, *, max_until: int = 100_000, seed=None):
        """Run an Avalla scenario (it loads its own spec, normally this one) with this model's
        --int-range and --max-loop."""
        return scenario(path, max_until=max_until, seed=seed, int_range=self.options.get("int_range"),
                        max_loop=self.options.get("max_loop"))


class Simulation:
    """The steps of :meth:`Model.simulate` (a sequence), and their renderings."""

    def __init__(self, model, machine, steps):
        self.model = model
        self.machine = machine
        self.steps = steps
        self.interrupted = ""       # why the run stopped before its steps ('interrupted (Ctrl-C)'), or ""

    def __iter__(self):
        return iter(self.steps)

    def __len__(self):
        return len(self.steps)

    def __getitem__(self, i):
        return self.steps[i]

    @property
    def ok(self) -> bool:
        return not any(st.error is not None or st.violated for st in self.steps)

    @property
    def exit_code(self) -> int:
        return EXIT_OK if self.ok and not self.interrupted else EXIT_VIOLATED if not self.ok else EXIT_INCOMPLETE

    def stopped_note(self) -> str:
        """'interrupted (Ctrl-C) after step 12', or '' for a run that took its steps."""
        if not self.interrupted:
            return ""
        return f"{self.interrupted} " + (f"after step {self.steps[-1].number}" if self.steps else "before the initial state")

    def text(self) -> str:
        from .report.simulation import simulation_text
        note = self.stopped_note()
        return "\n".join(simulation_text(self.machine, self.steps)[0] + ([note] if note else [])) + "\n"

    def asmeta(self) -> str:
        from .report.simulation import simulation_asmeta
        return "\n".join(simulation_asmeta(self.machine, self.steps)[0]) + "\n"

    def json(self) -> dict:
        from .report.simulation import simulation_json
        doc = simulation_json(self.machine, self.model.name, self.steps)[0]
        if self.interrupted:
            doc["interrupted"] = self.stopped_note()
        return doc


def parse(path, *, import_path=()) -> object:
    """Parse and type-check a spec (with its imports): its IR, or None for an empty file.
    Raises :class:`AsmError` (located) when it does not parse or type-check."""
    from .semantics.resolve import check_file
    path = os.fspath(path)
    _set_import_path(import_path)
    _check_readable(path, "spec")
    return check_file(path)


def scenario_report(outcome, verbose: bool = False) -> list[str]:
    """A scenario's outcome as ``asmcheck scenario`` prints it."""
    from .avalla.report import text_report
    return text_report(outcome, verbose)


def scenario_json(outcome) -> dict:
    from .avalla.report import json_report
    return json_report(outcome)


class ReplayMismatch(Exception):
    """A trace found by Z3 does not replay through the step function (an internal error)."""


def scenario(path, *, max_until: int = 100_000, seed=None, import_path=(), int_range=None, max_loop=None):
    """Run the Avalla scenario at ``path``: an :class:`asmcheck.avalla.runner.Outcome`.
    ``int_range`` and ``max_loop`` bound the scenario's spec as they bound :func:`load`'s (a
    choose or quantifier over Integer, a while loop).  There is no ``monitored``: a scenario
    gives the monitored functions their values with ``set``, as AsmetaV does."""
    from .avalla.runner import run_scenario
    _set_import_path(import_path)
    _check_readable(os.fspath(path), "scenario")
    options: dict = {}
    if int_range is not None:
        options["int_range"] = parse_int_range(int_range)
    if max_loop is not None:
        options["max_loop"] = _max_loop(max_loop)
    return run_scenario(os.fspath(path), max_until=max_until, seed=seed, options=options)


def _max_loop(n) -> int:
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise UsageError(f"max_loop must be a positive number of iterations, not {n!r}")
    return n


def max_states_error(flag: str, value: int, depth_zero: str = "max_depth=0") -> str:
    """The usage error of a state limit below 1 (``flag`` as the caller spells it): the initial states
    are always found, so a limit of 0 cannot stop before them (it stopped after the first state's
    successors, as 1 does); a depth limit of 0 (``depth_zero``) checks the initial states alone."""
    hint = f" (the initial states are always explored; {depth_zero} checks them alone)" if value == 0 else ""
    return f"{flag} must be 1 or more, not {value}{hint}"


# ----------------------------------------------------------------- engines
def choose_engine(model: Model, engine: str, *, keep_graph: bool, step_props, has_invar: bool) -> str:
    """The engine to try first: ``native`` or ``python``.  ``auto`` and ``native`` try the
    native engine, which refuses (``Unsupported``, with its reason) what it cannot run;
    ``auto`` then falls back to the Python engine and keeps the reason.  The only place
    that decides."""
    if engine not in ("auto", "python", "native"):
        raise UsageError(f"unknown engine {engine!r} (auto, python or native)")
    if engine == "auto":
        engine = auto_engine()
    return "python" if engine == "python" else "native"


def auto_engine() -> str:
    """What ``engine='auto'`` means: the environment variable ASMCHECK_ENGINE (``python`` pins
    the Python engine, ``native`` insists on the native one; the test suite runs engine-neutral
    tests under both), else ``auto``."""
    value = os.environ.get("ASMCHECK_ENGINE", "auto").strip().lower() or "auto"
    if value not in ("auto", "python", "native"):
        raise UsageError(f"ASMCHECK_ENGINE={value!r}: expected auto, python or native")
    return value


#: how soon the watchdog (and the command line's SIGTERM) tries again when its signal came at a point
#: where an exception would be lost or would cut a clean-up short (see :func:`unsafe_to_raise`)
WATCHDOG_RETRY = 0.01

# the frames whose exceptions Python drops ("Exception ignored in ...") or that restore what a
# block changed: the alarm waits until they have returned
_CLEANUP_FRAMES = frozenset({"__del__", "__exit__", "__aexit__"})


def unsafe_to_raise(frame) -> bool:
    """Whether an exception raised by a signal's handler (the time limit's watchdog, SIGTERM) where
    the signal interrupted the main thread (``frame``) could be lost or cut a clean-up short: a
    generator being closed (its GeneratorExit in flight, e.g. the term evaluator's bindings dropped
    after an ``exist`` found a witness: Python prints "Exception ignored in <generator ...>" and
    drops the exception), a ``__del__`` or a ``with`` statement's ``__exit__`` (a deadline
    restored, a timer disarmed) on the stack."""
    if sys.exc_info()[0] is GeneratorExit:
        return True
    while frame is not None:
        if frame.f_code.co_name in _CLEANUP_FRAMES:
            return True
        frame = frame.f_back
    return False


@contextmanager
def _watchdog(seconds, explorer=None):
    """Raise :class:`TimeUp` in the main thread ``seconds`` from now (a safety net for a step
    that runs long inside the step function; the searches check their time limit
    themselves).  Not once ``explorer`` has left its search loop (``finishing``): what it
    found is then a result, and the report of it is not cut short.  An alarm that comes where
    the exception would be lost or would cut a clean-up short (:func:`unsafe_to_raise`) is put
    off by :data:`WATCHDOG_RETRY` seconds, until the block has a safe point; none once the block
    is over."""
    if (seconds is None or threading.current_thread() is not threading.main_thread()
            or not hasattr(signal, "setitimer")):
        yield
        return
    armed = True

    def fire(signum, frame):
        if not armed or (explorer is not None and getattr(explorer, "finishing", False)):
            return
        if unsafe_to_raise(frame):
            signal.setitimer(signal.ITIMER_REAL, WATCHDOG_RETRY)
            return
        raise TimeUp()
    old = signal.signal(signal.SIGALRM, fire)
    # (a bound beyond about three years needs no alarm: the platform's timer cannot hold it)
    signal.setitimer(signal.ITIMER_REAL, min(max(seconds, 0.001), 1e8))
    try:
        yield
    finally:
        armed = False
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


@contextmanager
def _deadline(machine, seconds):
    """The step function stops a step that runs past ``seconds`` from now (it raises
    DeadlineReached); the deadline is lifted afterwards, so traces replay in full."""
    if seconds is None:
        yield
        return
    old = machine.deadline
    machine.deadline = time.monotonic() + seconds
    try:
        yield
    finally:
        machine.deadline = old


# the grace a search has past its time limit before the watchdog stops it from outside
WATCHDOG_GRACE = 1.0


def _checked_out_of_time(ex, state_props, deadlock, seconds) -> Result:
    """The result of a native search whose time limit ended the check of the states where a step
    fails (the Python step function recovers their errors, :meth:`NativeExplorer._failed_steps`):
    incomplete, with the search's counts and how far the check got; no violation is reported, as
    the errors (and the order of the violations) are not known."""
    states, transitions, depth = getattr(ex, "counts", (getattr(ex, "nstates", 0), 0, 0))
    done, total = getattr(ex, "failed_checked", (0, 0))
    stop = TimeLimit(ex.max_seconds, f" while the Python step function recovered the errors of the states where "
                                     f"a step fails ({done:,} of {total:,} checked, after a search of "
                                     f"{states:,} states)")
    result = Result("incomplete", states, transitions, depth, seconds, [], stop.text(), list(state_props))
    result.time_limit = stop
    result.stop = Stop.TIME
    result.deadlock_checked = deadlock
    result.engine = "native"
    result.workers = ex.workers
    result.compile_seconds = getattr(ex, "compile_seconds", 0.0)
    return result


def _label_atoms(machine, temporal):
    """For the native explorer: the first initial state -> the atoms of the temporal properties
    (None without LTL/CTL properties)."""
    props = [p for p in temporal if p.kind in ("ltl", "ctl", "justice", "compassion")]
    if not any(p.kind in ("ltl", "ctl") for p in props):
        return None

    def atoms(state):
        from .temporal import label_atoms
        return label_atoms(machine, props, state)
    return atoms


def _quotient_plan(machine, temporal, fair, graph):
    """For the native explorer: the atoms of the temporal quotient it records in its search (see
    temporal.quotient_plan), None when the checks need the edges."""
    from .temporal import quotient_plan
    return quotient_plan(machine, temporal, list(fair or []), bool(graph))


def _explore(model: Model, properties, *, engine, workers, max_states, max_depth, max_seconds, max_memory,
             deadlock, fair, graph, progress, started=None, warn=None, scaling=None,
             symmetry=False) -> "Exploration":
    from .options import unbounded_monitored
    t0 = time.perf_counter()
    unbounded_monitored(model.machine)
    # a property that quantifies over an infinite domain cannot be evaluated: an input error at
    # its range (as the same quantifier in a rule is), not a violation in the initial state
    bodies = [p for p in model.spec.properties if p.kind in ("invariant", "invar")]
    for p in list(model.state_props) + list(model.step_props):
        ir_prop = getattr(p, "prop", None)
        if getattr(ir_prop, "body", None) is not None and ir_prop not in bodies:
            bodies.append(ir_prop)
    unbounded = model.machine.unbounded_properties(bodies)
    if unbounded:
        raise unbounded[0]
    begin = started if started is not None else t0
    machine, spec = model.machine, model.spec
    state_props, step_props, temporal = list(model.state_props), list(model.step_props), list(model.temporal)
    if properties is not None:
        want = list(properties)
        names = [p.name for p in state_props + step_props + temporal]
        for n in want:
            if n not in names:
                raise UsageError(f"no property named {n!r} (the properties: {', '.join(names) or 'none'})")
        state_props = [p for p in state_props if p.name in want]
        step_props = [p for p in step_props if p.name in want]
        temporal = [p for p in temporal if p.name in want or p.kind in ("justice", "compassion")]
    for name, v, kinds in (("workers", workers, (int,)), ("max_states", max_states, (int,)),
                           ("max_depth", max_depth, (int,)), ("max_seconds", max_seconds, (int, float)),
                           ("max_memory", max_memory, (int, float))):
        if v is not None and (isinstance(v, bool) or not isinstance(v, kinds)):
            raise UsageError(f"{name} must be {'an integer' if kinds == (int,) else 'a number'}, not {v!r}")
    if workers is not None and workers < 1:
        raise UsageError("workers must be 1 or more")
    if max_states is not None and max_states < 1:
        raise UsageError(max_states_error("max_states", max_states))
    if max_depth is not None and max_depth < 0:
        raise UsageError("max_depth must be 0 or more")
    if max_seconds is not None and not max_seconds >= 0:
        raise UsageError("max_seconds must be 0 or more")
    if isinstance(fair, str):
        raise UsageError(f"fair must be a list of domain names (or 'all'), not the string {fair!r}")
    domains = {getattr(d, "name", None) for d in spec.domains}
    for name in fair or ():
        if name != "all" and name not in domains:
            raise UsageError(f"--fair {name}: the spec has no domain {name}"
                             + (f" (its domains: {', '.join(sorted(n for n in domains if n))})" if domains else ""))
    if max_memory is None:
        max_memory = default_max_memory()
    elif max_memory <= 0:
        max_memory = None
    keep_graph = bool(graph) or any(p.kind in ("ltl", "ctl") for p in temporal)
    has_invar = any(p.kind == "invar" for p in spec.properties)
    if engine == "auto":
        engine = auto_engine()
    which = choose_engine(model, engine, keep_graph=keep_graph, step_props=step_props, has_invar=has_invar)
    if not isinstance(symmetry, bool):
        raise UsageError(f"symmetry must be True or False, not {symmetry!r}")
    sym = _symmetry(model, state_props, step_props, temporal, engine, workers, scaling, fair, which,
                    graph) if symmetry else None
    sym_python = _symmetry_python(sym, which, graph)
    if sym_python:
        which = "python"
    if sym is None and warn is not None:
        progress = _hinting(progress, warn, lambda: _symmetry_hint(model, state_props, step_props, temporal))
    # the searches get the time left of the whole run
    search_seconds = None if max_seconds is None else max(max_seconds - (t0 - begin), 0.0)
    ex = None
    result = None
    interrupted = False
    refused = sym_python if engine != "python" else ""
    from .parallel import run as scaled
    scaled.check_options(workers, **(scaling or {}))
    # more workers on the native engine: threads inside its search (the same result as one);
    # a cluster or bitstate search, or a spec the native engine refuses, takes the partitioned
    # search on the Python step function
    native_threads = which == "native" and scaled.native_threads(workers, **(scaling or {}))
    if scaled.wanted(workers, **(scaling or {})) and not native_threads:
        ex, result = scaled.explore_model(model, state_props, step_props, workers=workers, **(scaling or {}),
                                          max_states=max_states, max_depth=max_depth, max_seconds=search_seconds,
                                          max_memory=max_memory, deadlock=deadlock, engine=engine,
                                          keep_graph=keep_graph, progress=progress)
    elif which == "native":
        from .explore.native import NativeExplorer, Unsupported
        try:
            try:
                ex = NativeExplorer(machine, max_states=max_states, max_depth=max_depth, max_seconds=search_seconds,
                                    deadlock=deadlock, state_props=state_props, step_props=step_props,
                                    keep_graph=keep_graph, max_memory=scaled.native_memory(max_memory, workers,
                                                                                          **(scaling or {})),
                                    progress=progress, warn=warn, workers=scaled.parse_workers(workers or 1),
                                    label_atoms=_label_atoms(machine, temporal),
                                    step_quotient=_quotient_plan(machine, temporal, fair, graph),
                                    symmetry=sym)
            except RecursionError:
                raise Unsupported("the spec nests more deeply than the C generator follows") from None
            if max_seconds is not None:
                # the engine's compile (a cache miss) comes out of the whole run's time: the search
                # gets what is left (the compile itself is not cut short: it is cached for the next run)
                ex.max_seconds = search_seconds = max(max_seconds - (time.perf_counter() - begin), 0.0)
            try:
                # the Python step function that recovers the errors of the states where a step
                # fails has the time the search had
                ex.check_deadline = None if search_seconds is None else time.monotonic() + search_seconds
                try:
                    result = ex.run()
                except DeadlineReached:
                    result = _checked_out_of_time(ex, state_props, deadlock, time.perf_counter() - t0)
                if graph:
                    # every step with its choices, checked against the native edges (else the Python engine)
                    if result.verdict == "incomplete":
                        raise Unsupported("--graph on a search that stopped before its end")
                    ex.graph_edges()
            except KeyboardInterrupt as exc:
                interrupted = True
                if result is not None:
                    # the search was over: the Ctrl-C came while the graph's steps were enumerated
                    # (the counts and verdicts of the search stay)
                    result.reason = f"{interrupt_reason(exc)} while the state graph's steps were enumerated"
                    result.stop = Stop.INTERRUPT
                    if result.verdict == "holds":
                        result.verdict = "incomplete"
                else:
                    result = Result("incomplete", *ex.counts_so_far(), time.perf_counter() - t0, [],
                                    interrupt_reason(exc), list(state_props))
                    result.stop = Stop.INTERRUPT
                    result.deadlock_checked = deadlock
                    result.engine = "native"
                    result.workers = ex.workers
        except Unsupported as e:
            if engine == "native":
                raise UsageError(f"the native explorer cannot run {Path(model.path).name}: {e}") from None
            if sym is not None and sym.active and scaled.wanted(workers, **(scaling or {})):
                raise UsageError(f"--symmetry with --workers runs on the native engine's threads, which cannot run "
                                 f"{Path(model.path).name}: {e} (drop --workers)") from None
            ex = None
            refused = str(e)
            if max_seconds is not None:
                # the Python engine gets what is left of the whole run: a native search that stopped
                # on something it does not handle has spent its part
                search_seconds = max(max_seconds - (time.perf_counter() - begin), 0.0)
    if ex is None and native_threads:
        ex, result = scaled.explore_model(model, state_props, step_props, workers=workers, **(scaling or {}),
                                          max_states=max_states, max_depth=max_depth, max_seconds=search_seconds,
                                          max_memory=max_memory, deadlock=deadlock, engine="python",
                                          keep_graph=keep_graph, progress=progress)
        result.native_refused = refused
        interrupted = getattr(result, "interrupted", False)
    if ex is None:
        ex = Explorer(machine, max_states=max_states, max_depth=max_depth, max_seconds=search_seconds,
                      deadlock=deadlock, progress=progress, keep_graph=keep_graph, state_props=state_props,
                      step_props=step_props, max_memory=max_memory, memory=memory_in_use, warn=warn,
                      symmetry=sym)
        with _watchdog(None if search_seconds is None else search_seconds + WATCHDOG_GRACE, ex), \
                _deadline(machine, search_seconds):
            result = ex.run()
        result.engine = "python"
        result.native_refused = refused
        interrupted = getattr(result, "interrupted", False)
    stop = getattr(result, "time_limit", None)
    if max_seconds is not None and stop is not None:
        # the whole command's limit (the search had what was left of it); what the search was
        # doing when it stopped stays
        result.time_limit = replace(stop, seconds=max_seconds)
        result.reason = result.time_limit.text()
    temporal_results = []
    temporal_note = ""
    temporal_stop = ""          # why the LTL/CTL phase stopped (a Stop)
    temporal_error = ""
    checked_temporal = [p for p in temporal if p.kind in ("ltl", "ctl")]
    # the invariants, step properties and deadlock are decided by the search alone: a limit met in
    # the LTL/CTL phase after a complete search leaves them decided
    result.search_stopped_early = result.stopped_early
    if checked_temporal and result.stopped_early and not interrupted and _partial_ok(ex, result):
        temporal_results, temporal_note = _partial_temporal(ex, temporal, fair, result, max_seconds, begin, machine,
                                                            max_memory)
    elif checked_temporal and not result.stopped_early and not interrupted:
        # (a search stopped early, even with a violation found, has a partial graph: its LTL/CTL
        # properties are decided above, or stay incomplete)
        from .temporal import check_temporal
        left = None if max_seconds is None else max_seconds - (time.perf_counter() - begin)
        try:
            if left is not None and left <= 0:
                raise TimeUp()
            with _watchdog(left), _deadline(machine, left):
                temporal_results = check_temporal(ex, temporal, fair=list(fair or []))
        except (TimeUp, DeadlineReached):
            temporal_note, temporal_stop = TimeLimit(max_seconds, " in the LTL/CTL phase").text(), Stop.TIME
            temporal_results = []
        except KeyboardInterrupt as exc:
            interrupted = True
            temporal_note, temporal_stop = f"{interrupt_reason(exc)} in the LTL/CTL phase", Stop.INTERRUPT
            temporal_results = []
        except MemoryError:
            temporal_note, temporal_stop = "out of memory in the LTL/CTL phase", Stop.MEMORY
            temporal_results = []
        except AsmError:
            raise
        except Exception as exc:        # an internal error: reported on the rows (the gate goes on)
            temporal_error = f"internal error in LTL/CTL checking: {type(exc).__name__}: {exc}"
        if temporal_note:
            if not result.reason:
                result.reason, result.stop = temporal_note, temporal_stop
            if result.verdict == "holds":
                result.verdict = "incomplete"
    elif checked_temporal and result.stopped_early:
        if sym is not None and sym.active and result.stop in Stop.BOUNDS | {Stop.MEMORY} and not interrupted:
            # (its stored states are class representatives: the check of a partial state space is
            # not made for them)
            result.reason = f"{result.reason}; under symmetry reduction a partial state space decides no " \
                            f"LTL/CTL property"
        temporal_note = result.reason
    for t in temporal_results:
        if not t.holds and result.verdict != "violated" and not t.message:
            result.verdict = "violated"
    result.seconds = time.perf_counter() - t0
    result.symmetry = sym
    if sym is None and not interrupted and result.stop in Stop.LIMITS:
        result.symmetry_hint = _symmetry_hint(model, state_props, step_props, temporal)
    run = Exploration(model, ex, result, temporal, temporal_results, checked_temporal, interrupted)
    run.temporal_error = temporal_error
    if any(getattr(t, "decided_on", None) is not None for t in temporal_results) and result.verdict == "incomplete":
        # every property decided on the partial state space, none violated: the run's verdict
        # is the rows' (the gate's), not the search's
        if all(r["verdict"] == "holds" for r in run.rows):
            result.verdict = "holds"
    if temporal_error and result.verdict == "holds":
        # the LTL/CTL properties were not checked: nothing says they hold
        result.verdict = "incomplete"
        if not result.reason:
            result.reason, result.stop = temporal_error, Stop.INTERNAL
    return run


def _partial_ok(ex, result) -> bool:
    """Whether the explorer's partial state graph can decide LTL/CTL properties: the Python
    explorer's, or the native one's (both record every step of an expanded state).  On threads,
    only after a state or depth limit: the threads then stop where one thread stops, with the
    same states and steps (so the report is the same for any number of workers); a memory limit
    stops them at the end of a chunk."""
    if type(ex) is Explorer:
        # (not under symmetry reduction: its stored states are class representatives, left to the
        # complete check)
        return bool(getattr(ex, "keep_graph", False)) and getattr(ex, "sym", None) is None
    if type(ex).__name__ == "NativeExplorer" and getattr(ex, "engine", "") == "native":
        if getattr(ex, "sym", None) is not None:
            return False        # (symmetry reduction: as the Python explorer's)
        one = ex.workers <= 1 and not ex.threaded
        return bool(ex.keep_graph) and (one or result.stop in Stop.BOUNDS)
    if type(ex).__name__ == "PartitionedExplorer":
        # the partitioned search (processes or Ray actors) cuts a level where the sequential search
        # stops at its state or depth limit, with the same states and steps (a worker's memory share
        # or the time limit stops it at the end of a level instead)
        return bool(getattr(ex, "keep_graph", False)) and result.stop in Stop.BOUNDS
    return False


#: the memory the LTL/CTL check of a partial state space takes, per state explored, at most about
#: (tombola.asm on the native engine: 6.8 GB at 21,664,623 states, of which 2.4 GB the search's)
PARTIAL_BYTES_PER_STATE = 250


def _partial_temporal(ex, temporal, fair, result, max_seconds, begin, machine, max_memory=None):
    """The LTL/CTL properties decided on the state graph a search left when it stopped early
    (:func:`asmcheck.temporal.partial.check_partial`): (results, note).  Not tried when the memory bound leaves no room for it (the reason
    says so)."""
    from .temporal.partial import check_partial
    note = result.reason
    left = None if max_seconds is None else max_seconds - (time.perf_counter() - begin)
    got: list = []
    if result.stop == Stop.STEP_FAILED:
        # a state without successors: the complete check could not run either
        return [], note
    need = PARTIAL_BYTES_PER_STATE * int(getattr(ex, "n_states", 0) or 0)
    if max_memory is not None and need > 2**24:
        used = memory_in_use() or 0
        if used + need > max_memory:
            result.reason = (f"{result.reason}; no memory left to decide LTL/CTL properties on the states explored "
                             f"(about {memory_text(need)} more, over the bound of {memory_text(max_memory)}): "
                             f"bound the search with --max-states")
            return [], note
    if getattr(ex, "lists_kept", "all") != "all":
        # the search recorded only the successor lists the complete check reads (temporal/need.py;
        # a state or depth bound keeps them all)
        if result.stop == Stop.MEMORY and not (left is not None and left <= 0):
            result.reason = (f"{result.reason}; LTL/CTL properties are decided on the states explored only when "
                             f"--max-states or --max-depth bounds the search")
        return [], note
    try:
        if left is not None and left <= 0:
            raise TimeUp()
        why_not: list = []
        with _watchdog(left), _deadline(machine, left):
            # the Python explorer records a state's steps as they come: a stop other than the
            # state or depth limit (checked between two states) may have cut the last state's
            got = check_partial(ex, temporal, fair=list(fair or []),
                                stopped_inside=type(ex) is Explorer and result.stop not in Stop.BOUNDS,
                                notes=why_not)
        if why_not:
            # (fairness constraints, INVAR: why no LTL/CTL property is decided on the states explored)
            result.reason = "; ".join([result.reason] + why_not)
    except (TimeUp, DeadlineReached, MemoryError, KeyboardInterrupt):
        got = []                # (the properties stay incomplete, as the search is)
    except AsmError:
        raise
    except Exception as exc:        # an internal error: the properties stay incomplete, and say why
        result.reason = f"{result.reason}; LTL/CTL on the partial state space: internal error: " \
                        f"{type(exc).__name__}: {exc}"
        got = []
    return got, note


SYMMETRY_PYTHON = "symmetry reduction (--symmetry) runs on the Python engine"


def _symmetry(model, state_props, step_props, temporal, engine, workers, scaling, fair, which="python",
              graph=False):
    """The symmetry a search with ``symmetry=True`` reduces (explore.symmetry.Symmetry, possibly
    without any interchangeable element: its ``lines`` say why)."""
    from .explore.symmetry import Symmetry, detect
    from .parallel import run as scaled
    if scaled.wanted(workers, **(scaling or {})) and not (which == "native" and
                                                          scaled.native_threads(workers, **(scaling or {}))):
        raise UsageError("--symmetry runs in one process (or on the native engine's threads, --workers N): it "
                         "cannot be combined with --cluster, --bitstate or the Python engine's workers")
    if fair:
        why = "--fair makes each agent or choice fair on its own, which a class of states does not keep"
        return Symmetry([], [why], why)
    try:
        sym = detect(model.machine, list(state_props) + list(step_props) + list(temporal))
    except Exception as exc:        # noqa: BLE001 - an analysis that fails reduces nothing
        why = f"the analysis failed ({type(exc).__name__}: {exc})"
        return Symmetry([], [why], why)
    why = _symmetry_python(sym, which, graph)
    if why and engine == "native":
        raise UsageError(f"the native explorer cannot run {Path(model.path).name} with --symmetry: "
                         f"{why} (use --engine auto or python)")
    if why and scaled.wanted(workers, **(scaling or {})):
        raise UsageError(f"--symmetry with --workers runs on the native engine's threads, which cannot reduce "
                         f"{Path(model.path).name}: {why} (drop --workers)")
    return sym


def _symmetry_python(sym, which, graph) -> str:
    """Why a symmetric search runs on the Python engine ('' when the native engine reduces it, or
    nothing is reduced)."""
    from .explore.symmetry import native_reason
    if sym is None or not sym.active or which != "native":
        return ""
    if graph:
        return f"{SYMMETRY_PYTHON} with --graph"
    why = native_reason(sym)
    return f"{SYMMETRY_PYTHON}: {why}" if why else ""


#: a search without --symmetry that runs this long (seconds) says, while it goes on, that the
#: model has interchangeable elements (the hint a limit's end gives): a search that will not end
#: in the memory or the time there is is better stopped and run again with --symmetry
SYMMETRY_HINT_SECONDS = 10.0


def _hinting(progress, warn, hint):
    """``progress`` (or nothing) for a search, and after SYMMETRY_HINT_SECONDS of it, once,
    ``warn`` with ``hint()`` (when it has one)."""
    t0 = time.perf_counter()
    said = [False]

    def report(states, depth, transitions, secs):
        if not said[0] and time.perf_counter() - t0 >= SYMMETRY_HINT_SECONDS:
            said[0] = True
            text = hint()
            if text:
                warn(f"{text} (this search goes on)")
        if progress is not None:
            progress(states, depth, transitions, secs)
    return report


def _symmetry_hint(model, state_props, step_props, temporal) -> str:
    """For a search a limit stopped: a one-line hint naming --symmetry when the model has
    interchangeable elements ('' otherwise)."""
    from .explore.symmetry import detect
    try:
        sym = detect(model.machine, list(state_props) + list(step_props) + list(temporal))
    except Exception:       # noqa: BLE001 - a hint only: never a reason for a run to fail
        return ""
    if not sym.active:
        return ""
    what = _and_words([d.describe() for d in sym.domains])
    return f"hint: {what} are interchangeable; --symmetry explores one state per class of such states"


def _and_words(parts: list) -> str:
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


# ----------------------------------------------------------------- results
class Trace:
    """A replayed counterexample (or witness): ``steps`` and three renderings."""

    def __init__(self, model: Model, trace, prop, *, temporal=None):
        self.model = model
        self.raw = trace                  # explore.trace.Trace
        self.prop = prop
        self.temporal = temporal          # the temporal.TemporalResult it comes from
        self.steps = trace.steps
        self.kind = trace.kind
        self.loop_start = None
        if temporal is not None:
            got = temporal.trace()
            self.loop_start = got[1] if got else None

    def text(self, color: bool = False) -> str:
        """The trace as ``asmcheck explore`` prints it (per step the choices, inputs and what changed)."""
        return "\n".join(trace_text(self.model.machine, self.raw, color, self.loop_start)) + "\n"

    def json(self) -> list:
        """The trace as JSON (docs/trace.schema.json)."""
        return trace_json(self.model.machine, self.raw)

    def avalla(self, out_path: str | None = None) -> str:
        """An Avalla scenario that replays the trace (``out_path``: where it will be written,
        for its ``load`` line)."""
        from .report.avalla_export import trace_scenario
        return trace_scenario(self.model.machine, self.raw, spec_path=self.model.path, out_path=out_path,
                              prop=self.prop, loop=self.loop_start)


def relative_location(result) -> str | None:
    """The location (``FILE:LINE:COL``) of a search's run-time error, the first step found to
    fail ("" when it has none), or None when no step failed."""
    v = next((v for v in result.violations if v.prop.name == "error"), None)
    if v is None:
        return None
    span = getattr(v.prop, "span", None)
    return str(span) if span is not None and getattr(span, "line", 0) else ""


def verdict_text(row: dict) -> str:
    """A row's verdict as the text report shows it: ``holds, relative to the run-time error at
    FILE:LINE:COL`` for a verdict relative to an error."""
    rel = row.get("relative_to")
    part = partial_text(row.get("decided_on"))
    if rel is None:
        return row["verdict"] + part
    where = f" at {Path(rel.rsplit(':', 2)[0]).name}:{':'.join(rel.rsplit(':', 2)[1:])}" if rel else ""
    return f"{row['verdict']}, relative to the run-time error{where}{part}"


def partial_text(decided_on) -> str:
    """`` (decided on the N states explored)`` for a verdict decided on a partial state space
    ("" for one on the whole state space)."""
    return "" if decided_on is None else f" (decided on the {decided_on:,} states explored)"


def _property_place(prop) -> dict:
    from .report.place import property_place
    return property_place(prop)


def _violation_json(v) -> dict:
    out = {"property": v.property, "kind": v.trace.kind, "message": v.message,
           **_property_place(v.trace.prop), "trace": v.trace.json()}
    failing = failing_json(v.trace.raw)
    if failing is not None:
        out["failing_step"] = failing
    return out


@dataclass
class Violation:
    property: str
    kind: str               # state step deadlock error ltl ctl
    message: str
    location: str
    trace: Trace | None
    raw: object = None      # the engine's record (explore.bfs.Violation or temporal.TemporalResult)

    def text(self, color: bool = False) -> str:
        """A safety violation with its shortest trace, as ``asmcheck explore`` prints it: what is
        violated and where, the formula, then per step the rule, its choices, the inputs it read
        and what changed."""
        from .report.trace import explore_violation_lines
        if self.trace is None or hasattr(self.raw, "holds"):
            return ""
        return "\n".join(explore_violation_lines(self.trace.model.machine, self.raw, self.trace.raw, color)) + "\n"


class Exploration:
    """What :meth:`Model.explore` found."""

    def __init__(self, model, explorer, result, temporal, temporal_results, checked_temporal, interrupted):
        self.model = model
        self.explorer = explorer
        self.result = result
        self.temporal_props = temporal
        self.temporal = temporal_results
        self.checked_temporal = checked_temporal
        self.interrupted = interrupted
        self.states = result.states
        self.transitions = result.transitions
        self.depth = result.depth
        self.seconds = result.seconds
        self.engine = getattr(result, "engine", "python")
        # the workers that shared the search (threads of the native engine, or worker processes)
        self.workers = int(getattr(result, "workers", 1) or 1)
        # why the native engine did not run this search ("" when it did, or was not asked)
        self.engine_note = getattr(result, "native_refused", "") if self.engine == "python" else ""
        # seconds spent compiling the native engine (0.0 when it came from the cache)
        self.compile_seconds = float(getattr(explorer, "compile_seconds", 0.0) or 0.0)
        self._violations = None
        # symmetry=True: explore.symmetry.Symmetry (its ``lines`` explain it), else None
        self.symmetry = getattr(result, "symmetry", None)
        # a search stopped by a limit on a model with interchangeable elements: the hint naming
        # --symmetry ("" otherwise)
        self.symmetry_hint = getattr(result, "symmetry_hint", "")

    def symmetry_lines(self) -> list:
        """What --symmetry adds to the text report: the reduction (or why there is none), one
        line per candidate domain."""
        sym = self.symmetry
        if sym is None:
            return []
        if sym.active:
            head = f"symmetry: states and transitions are counted up to {sym.describe()}"
        else:
            head = f"symmetry: no reduction ({sym.reason})"
        return [head] + [f"  symmetry: {line}" for line in sym.lines]

    def symmetry_json(self) -> dict:
        sym = self.symmetry
        if sym is None:
            return {}
        return {"symmetry": {"reduced": sym.active, "counts": "classes" if sym.active else "states",
                             "domains": [{"domain": d.name, "interchangeable": len(d.free), "elements": len(d.values)}
                                         for d in sym.domains],
                             "explain": list(sym.lines), **({"reason": sym.reason} if sym.reason else {})}}

    @property
    def verdict(self) -> str:
        return self.result.verdict

    def scaling_lines(self) -> list:
        """What a scaling mode adds to the text report (the bitstate search's miss probability)."""
        return list(getattr(self.result, "notes", ()))

    def scaling_json(self) -> dict:
        """What a scaling mode adds to the JSON report."""
        bits = getattr(self.result, "bitstate", None)
        out = {"bitstate": bits} if bits else {}
        note = getattr(self.result, "scaling_note", "")
        if note:
            out["scaling_note"] = note
        return out

    @property
    def reason(self) -> str:
        return self.result.reason

    @property
    def stop(self) -> str:
        """Why the search stopped before its end, in one word (explore.bfs.Stop: ``states``,
        ``depth``, ``time``, ``memory``, ``interrupt``, ...); "" for a search that covered every state."""
        return self.result.stop

    @property
    def exit_code(self) -> int:
        return {"violated": EXIT_VIOLATED, "incomplete": EXIT_INCOMPLETE}.get(self.verdict, EXIT_OK)

    @property
    def relative_to(self) -> str | None:
        """Where the run-time error is (``FILE:LINE:COL`` of the first step found to fail) when a
        step fails: the properties are then checked on the well-defined steps, and a verdict that
        is not a violation by a well-defined trace holds *relative to the error*; None otherwise."""
        return relative_location(self.result)

    @property
    def rows(self) -> list[dict]:
        """One row per property checked: property, kind, verdict (and ``relative_to``, the
        run-time error's location, on the verdicts relative to it)."""
        result = self.result
        bad = {v.prop.name for v in result.violations}
        incomplete = getattr(result, "search_stopped_early", result.stopped_early)
        rel = self.relative_to
        rows = []

        def row(name, kind, verdict, relative=False):
            r = {"property": name, "kind": kind, "verdict": verdict}
            if relative and rel is not None and verdict in ("holds", "violated"):
                r["relative_to"] = rel
            return r
        for p in result.checked:
            # a violation of an invariant or step property has a well-defined trace: not relative
            verdict = "violated" if p.name in bad else ("incomplete" if incomplete else "holds")
            rows.append(row(p.name, getattr(p, "kind", "invariant"), verdict, verdict == "holds"))
        for v in result.violations:
            if v.prop.name in ("deadlock", "error"):
                rows.append({"property": v.prop.name, "kind": v.prop.kind, "verdict": "violated"})
        if getattr(result, "deadlock_checked", False) and "deadlock" not in bad:
            rows.append(row("deadlock", "deadlock", "incomplete" if incomplete else "holds", True))
        done = set()
        for t in self.temporal:
            verdict = getattr(t, "verdict", None) or ("holds" if t.holds else "violated")
            if verdict == "error":
                verdict = "cannot be checked"
            rows.append(row(t.name, t.kind, verdict, getattr(t, "relative_to", None) is not None))
            if getattr(t, "decided_on", None) is not None:
                rows[-1]["decided_on"] = t.decided_on
            done.add(t.name)
        first = len(rows) - len(done)
        for p in self.checked_temporal:
            if p.name not in done:
                rows.append({"property": p.name, "kind": p.kind, "verdict": "incomplete"})
        if any("decided_on" in r for r in rows[first:]):
            # verdicts decided on a partial state space beside incomplete ones: in declaration order
            order = {p.name: i for i, p in enumerate(self.checked_temporal)}
            rows[first:] = sorted(rows[first:], key=lambda r: order.get(r["property"], -1))
        return rows

    @property
    def verdicts(self) -> dict:
        return {r["property"]: r["verdict"] for r in self.rows}

    @property
    def checked(self) -> int:
        """How many properties were checked (deadlock and run-time errors not counted)."""
        return len(self.result.checked) + len(self.checked_temporal)

    @property
    def violations(self) -> list[Violation]:
        """Every violation with its shortest trace, replayed through the step function."""
        if self._violations is None:
            out = []
            for v in self.result.violations:
                tr = build_trace(self.explorer, v)
                span = getattr(v.prop, "span", None)
                loc = str(span) if span is not None and getattr(span, "line", 0) else ""
                kind = tr.kind if v.prop.name not in ("deadlock", "error") else v.prop.name
                out.append(Violation(v.prop.name, kind, v.message, loc, Trace(self.model, tr, v.prop), v))
            for t in self.temporal:
                if t.holds or t.message:
                    continue
                got = t.trace()
                span = getattr(t.prop, "span", None)
                loc = str(span) if span is not None and getattr(span, "line", 0) else ""
                out.append(Violation(t.name, t.kind, "", loc,
                                     Trace(self.model, got[0], t.prop, temporal=t) if got else None, t))
            self._violations = out
        return self._violations

    def traces(self):
        """[(engine violation, explore.trace.Trace)] of the state and step violations."""
        return [(v.raw, v.trace.raw) for v in self.violations if not hasattr(v.raw, "holds")]

    def violation_text(self, color: bool = False) -> list[list[str]]:
        """The text of each state and step violation (an invariant, a step property, a deadlock,
        a step that fails): what is violated, its formula, and its shortest trace."""
        return [explore_violation_lines(self.model.machine, v.raw, v.trace.raw, color)
                for v in self.violations if not hasattr(v.raw, "holds")]

    def temporal_text(self, color: bool = False) -> list[list[str]]:
        """The text of each violated temporal property (with its replayed counterexample)."""
        out = []
        for t in self.temporal:
            if t.holds:
                continue
            lines = list(temporal_text(t, self.model.machine, color))
            n = getattr(t, "decided_on", None)
            if n is not None and not t.message:
                # a verdict of the partial state space: the path holds whatever the rest would be
                lines.insert(1, f"  decided on the {n:,} states explored: every continuation of the states "
                                f"not expanded keeps this counterexample")
            out.append(lines)
        return out

    def json(self) -> dict:
        """The report of ``asmcheck explore --format json``."""
        r = self.result
        out = {
            "spec": self.model.name,
            "verdict": r.verdict,
            "states": r.states,
            "transitions": r.transitions,
            "depth": r.depth,
            "seconds": round(r.seconds, 3),
            "engine": self.engine,
            **({"workers": self.workers} if self.workers > 1 else {}),
            "compile_seconds": round(self.compile_seconds, 3),
            "properties": self.rows,
            "violations": [_violation_json(v) for v in self.violations if not hasattr(v.raw, "holds")]
                          + [{**temporal_json(t, self.model.machine), **_property_place(t.prop),
                              **({"decided_on": t.decided_on} if getattr(t, "decided_on", None) is not None else {})}
                             for t in self.temporal if not t.holds],
        }
        if self.engine_note:
            out["engine_note"] = f"native engine not used: {self.engine_note}"
        if r.reason:
            out["incomplete"] = r.reason
        out.update(self.symmetry_json())
        if self.symmetry_hint:
            out["hint"] = self.symmetry_hint
        return out

    def outcome(self, *, strict: bool = False, root=None, avalla_dir=None, temporal_error: str = "",
                expectations: bool = True):
        """This run as a gate row set (:class:`asmcheck.report.gate.SpecOutcome`);
        ``expectations=False`` ignores the spec's ``// asmcheck: expect violated`` lines."""
        return _gate.build_outcome(self.model.path, self.model.spec, self.model.machine, self.explorer, self.result,
                                   self.temporal_props, self.temporal, strict=strict, root=root,
                                   avalla_dir=avalla_dir, temporal_error=temporal_error, expectations=expectations)

    def graph(self):
        """The explored state graph as a networkx MultiDiGraph (needs ``explore(graph=True)``):
        nodes are state numbers with ``label`` (the state), ``depth`` and ``initial``; edges carry
        the choices of the step."""
        from .report.graph import highlight_of, state_graph
        if not getattr(self.explorer, "keep_graph", False):
            raise UsageError("the state graph was not kept: explore with graph=True")
        return state_graph(self.explorer, highlight_of(self.explorer, self.result.violations))

    def write_graph(self, path: str) -> str:
        """Write the state graph (DOT or GraphML), counterexamples highlighted; returns a
        warning to show ("" when none: a graph over 500 states is written, with one)."""
        from .report.graph import READABLE_STATES, highlight_of, write_graph
        n = write_graph(self.explorer, path, highlight_of(self.explorer, self.result.violations))
        if n > READABLE_STATES:
            return (f"the graph in {path} has {n:,} states; over {READABLE_STATES} a drawing of it is hard to read "
                    f"(bound the search with --max-depth, or give fewer monitored values)")
        return ""

    def write_avalla(self, out: str) -> list[str]:
        from .report.avalla_export import explore_avalla
        return explore_avalla(out, self.model.machine, self.model.path, self.traces())

    def html(self) -> str:
        from .report import html as html_report
        # one verdict: the rows are judged as explore judges (a violation fails, expected or not), as the title
        return html_report.html_report([self.outcome(expectations=False)], self.exit_code, title="asmcheck explore")

    def write_html(self, path: str) -> None:
        from .report import html as html_report
        html_report.write(path, self.html())


class BmcResult:
    """What :meth:`Model.bmc` found."""

    def __init__(self, model, z3model, out, targets, k, induction):
        self.model = model
        self.z3model = z3model
        self.outcome = out
        self.targets = targets
        self.k = k
        self.induction = induction
        self.verdict = out.verdict
        self.depth = out.depth
        self.seconds = out.seconds
        self.reason = out.reason
        self.verdicts = dict(out.verdicts)

    @property
    def exit_code(self) -> int:
        return {"violated": EXIT_VIOLATED, "unknown": EXIT_INCOMPLETE}.get(self.verdict, EXIT_OK)

    @property
    def violations(self) -> list[Violation]:
        out = []
        for f in self.outcome.found:
            prop = f.trace.prop           # the property (for 'error': where the step fails)
            span = getattr(prop, "span", None)
            loc = str(span) if span is not None and getattr(span, "line", 0) else ""
            out.append(Violation(f.prop.name, f.trace.kind if f.prop.kind != "error" else "error", f.message, loc,
                                 Trace(self.model, f.trace, prop), f))
        return out

    def violation_text(self, color: bool = False) -> list[list[str]]:
        """Each violation as ``asmcheck explore`` shows one: what is violated and where, the
        summary, the formula, then the replayed trace."""
        from .report.place import found_violation_lines
        return [found_violation_lines(self.model.machine, v.trace.prop, v.trace.raw, v.message, color)
                for v in self.violations]

    def violation_json(self) -> list[dict]:
        """The violations as ``asmcheck bmc --format json`` writes them (those of explore, with
        the depth)."""
        out = []
        for v in self.violations:
            d = {"property": v.property, "kind": v.trace.kind, "message": v.message,
                 **_property_place(v.trace.prop), "depth": v.raw.depth, "trace": v.trace.json()}
            if v.trace.raw.failing is not None:
                d["failing_step"] = failing_json(v.trace.raw)
            out.append(d)
        return out

    @property
    def rows(self) -> list[dict]:
        rows = []
        out = self.outcome
        for p in out.props:
            r = {"property": p.name, "kind": getattr(p.wrapper, "kind", p.kind), "verdict": out.verdicts[p.name]}
            if p.name in out.depths:
                r["depth"] = out.depths[p.name]
            if p.name in out.induction:
                r["k"] = out.induction[p.name]["k"]
                r["needed"] = out.induction[p.name]["needed"]
                r["lemmas"] = out.induction[p.name]["lemmas"]
            if p.aux:
                r["auxiliary"] = True
            rows.append(r)
        return rows

    @property
    def not_checked(self) -> list[str]:
        """The temporal properties BMC does not check."""
        return [p.name for p in self.model.temporal if p.kind in ("ltl", "ctl")]


# ----------------------------------------------------------------- the gate
# the clock the per-spec times of the gate are read from (tests replace it to get fixed times)
CLOCK = time.perf_counter


def find_specs(paths) -> list[str]:
    """The ``.asm`` files under ``paths``, in order: a file as given, a folder walked (sorted,
    modules and hidden folders left out)."""
    out: list[str] = []
    for p in paths:
        p = os.fspath(p)
        path = Path(p)
        if path.is_file():
            out.append(p)
        elif path.is_dir():
            for f in sorted(path.rglob("*.asm")):
                rel = f.relative_to(path)
                if any(part.startswith(".") for part in rel.parts[:-1]):
                    continue
                if not f.is_file():
                    # a pipe or a device named *.asm is not read while walking: it is listed, and the
                    # gate reports it as an input error (it was asked to check that folder)
                    out.append(str(f))
                    continue
                if _is_module(f):
                    continue
                out.append(str(f))
        elif path.exists():
            raise UsageError(f"{p}: not a regular file or folder")
        else:
            raise UsageError(f"{p}: no such file or folder")
    seen = set()
    uniq = []
    for f in out:
        key = os.path.abspath(f)
        if key not in seen:
            seen.add(key)
            uniq.append(f)
    return uniq


def _is_module(path: Path) -> bool:
    from .syntax.parser import decode_source, read_source_bytes
    try:
        text = decode_source(read_source_bytes(path))   # regular files only: a FIFO would block
    except AsmError:
        return False
    m = re.search(r"\b(asm|module)\s+[A-Za-z_]", strip_comments(text))
    return bool(m) and m.group(1) == "module"


class Gate:
    """What :func:`check` found: one :class:`asmcheck.report.gate.SpecOutcome` per spec."""

    def __init__(self, outcomes, root=None):
        self.outcomes = outcomes
        self.root = root

    @property
    def exit_code(self) -> int:
        return _gate.exit_code(self.outcomes)

    def text(self, color: bool = False, timings: bool = True, traces: str = "failing", table: bool = True) -> str:
        from .report.text import check_text
        return check_text(self.outcomes, self.exit_code, color, timings, traces, table)

    def json(self, timings: bool = True) -> dict:
        from .report import report_json
        return report_json.check_json(self.outcomes, self.exit_code, timings)

    def junit(self, timings: bool = True) -> str:
        from .report import junit
        return junit.junit_xml(self.outcomes, timings)

    def sarif(self) -> dict:
        from .report import sarif
        return sarif.sarif_log(self.outcomes, self.exit_code, root=self.root)

    def html(self, timings: bool = True) -> str:
        from .report import html
        return html.html_report(self.outcomes, self.exit_code, timings)

    def write(self, *, json=None, junit=None, sarif=None, html=None) -> None:
        """Write the reports asked for (paths; ``json="-"`` is left to the caller)."""
        from .report import html as html_report, junit as junit_report, report_json, sarif as sarif_report
        if json and json != "-":
            report_json.write(json, self.json())
        if junit:
            junit_report.write(junit, self.junit())
        if sarif:
            sarif_report.write(sarif, self.sarif())
        if html:
            html_report.write(html, self.html())

    def json_text(self) -> str:
        from .report import report_json
        return report_json.dumps(self.json())


def check_spec(path: str, *, strict: bool = False, avalla_dir=None, root=None, clock=None, import_path=(),
               monitored=None, int_range=None, properties=None, default_properties=True, **explore):
    """Explore one spec and judge its properties: a SpecOutcome (never raises for the spec's
    own errors: they become its input-error row)."""
    clock = clock or CLOCK
    t0 = clock()
    try:
        model = load(path, import_path=import_path, monitored=monitored, int_range=int_range,
                     properties=properties, default_properties=default_properties, unknown_monitored="ignore",
                     properties_must_apply=False)
        declared = {getattr(d, "name", None) for d in model.spec.domains}
        if explore.get("fair"):
            # (the gate's --fair names the domains of some of its specs: each spec takes those it has)
            explore = {**explore, "fair": [d for d in explore["fair"] if d == "all" or d in declared]}
        run = model.explore(**explore)
        out = run.outcome(strict=strict, root=root, avalla_dir=avalla_dir, temporal_error=run.temporal_error)
        out.interrupted = run.interrupted
        # symmetry=True: the states are classes (the gate's table says so under it)
        out.symmetry = run.symmetry.describe() if run.symmetry is not None and run.symmetry.active else ""
        out.symmetry_hint = run.symmetry_hint
        # the names of its domains and monitored functions (the gate's check of --fair and --monitored)
        out.declared = {"domain": declared, "function": {f.name for f in model.spec.functions}}
        if not out.properties:
            out.properties = [_gate.judge(_gate.PropertyOutcome("(no property)", "input", "none",
                                                                message=no_property_message(model)), False, False)]
    except UsageError:
        raise
    except AsmError as err:
        return _gate.error_outcome(path, err, root, clock() - t0)
    except ReplayError as err:
        return _gate.error_outcome(path, AsmError(None, f"internal error: a counterexample does not replay ({err})"),
                                   root, clock() - t0)
    except RecursionError as exc:
        from .errors import located_recursion_error
        return _gate.error_outcome(path, located_recursion_error(exc, path), root, clock() - t0)
    except (KeyboardInterrupt, MemoryError, TimeUp) as exc:
        why = (interrupt_reason(exc) if isinstance(exc, KeyboardInterrupt) else
               "out of memory" if isinstance(exc, MemoryError) else TimeLimit().text())
        out = _gate.SpecOutcome(_gate.display_path(path, root), "", "incomplete", reason=why, seconds=clock() - t0)
        out.properties = [_gate.judge(_gate.PropertyOutcome("(not checked)", "input", "incomplete", message=why),
                                      False, False)]
        out.interrupted = isinstance(exc, KeyboardInterrupt)
        return out
    except Exception as exc:               # an internal error: this spec fails, the others are checked
        return _gate.error_outcome(path, AsmError(None, f"{path}: internal error: {type(exc).__name__}: {exc}"),
                                   root, clock() - t0)
    out.seconds = clock() - t0
    if avalla_dir is not None:
        from .report.avalla_export import write_scenario
        for row in out.properties:
            cx = row.counterexample
            if cx is not None and cx.avalla is not None:
                write_scenario(os.path.join(avalla_dir, os.path.basename(cx.avalla_path)), cx.avalla)
    return out


def no_property_message(model: Model) -> str:
    """What to say when nothing applies to a spec: where property files naming it are."""
    files = model.candidate_property_files()
    if files:
        return (f"{model.name} declares none and no property file found applies to it; "
                f"property files that name it: {', '.join(files)} (give them with --properties)")
    return (f"{model.name} declares none and no property file applies to it (put one in a "
            f"properties/ folder beside it, or give it with --properties)")


def check(paths=("specs",), *, strict_expect: bool = False, avalla_dir=None, root=None, clock=None, progress=None,
          **options) -> Gate:
    """The CI gate: explore every spec under ``paths`` with the properties that apply to it.
    ``options`` are those of :func:`load` and :meth:`Model.explore`."""
    specs = find_specs(list(paths) or ["specs"])
    if not specs:
        raise UsageError("no .asm specs under " + ", ".join(os.fspath(p) for p in paths))
    outcomes = []
    for i, path in enumerate(specs):
        if progress is not None:
            progress(path)
        o = check_spec(path, strict=strict_expect, avalla_dir=avalla_dir, root=root, clock=clock, **options)
        outcomes.append(o)
        if getattr(o, "interrupted", False):
            # Ctrl-C: what was checked so far is the report, and the specs left are listed unchecked
            why = f"{o.reason or interrupt_reason()} before this spec"
            for rest in specs[i + 1:]:
                left = _gate.SpecOutcome(_gate.display_path(rest, root), "", "incomplete", reason=why)
                left.properties = [_gate.judge(_gate.PropertyOutcome("(not checked)", "input", "incomplete",
                                                                     message=why), False, False)]
                outcomes.append(left)
            break
    names = unused_names(outcomes, options) if not any(getattr(o, "interrupted", False) for o in outcomes) else []
    outcomes += unused_property_files(specs, options.get("properties"), root)
    outcomes += names
    return Gate(outcomes, root)


def unused_names(outcomes, options) -> list:
    """Input-error outcomes for the ``fair`` domains and ``monitored`` functions that none of the
    checked specs declares (each spec takes the names it has, so a typo would otherwise pass the
    gate with nothing constrained); not judged when a spec could not be loaded."""
    seen = [getattr(o, "declared", None) for o in outcomes]
    if not seen or None in seen:
        return []
    out = []
    for flag, kind, names in (("--fair", "domain", [d for d in options.get("fair") or () if d != "all"]),
                              ("--monitored", "function", list(dict(options.get("monitored") or {})))):
        for name in names:
            if not any(name in d[kind] for d in seen):
                out.append(_gate.error_outcome(f"{flag} {name}", UsageError(
                    f"{flag} {name}: none of the checked specs has a {kind} {name}"), None))
                out[-1].subject = "option"
    return out


def unused_property_files(specs, given, root=None) -> list:
    """Input-error outcomes for the files given with ``properties`` to a gate run whose
    ``applies to`` line names none of the checked specs (a typo would otherwise pass the
    gate with nothing checked).  Files found beside the specs may name specs kept elsewhere
    (read through the import path), so they are not judged here."""
    from .props.files import read_prop_file
    checked = set()
    for path in specs:
        try:
            checked.add(_asm_name(Path(path)))
        except OSError:
            pass
    out = []
    for p in given or ():
        p = os.fspath(p)
        try:
            pf = read_prop_file(p)
        except AsmError as err:
            out.append(_gate.error_outcome(p, err, root))
            continue
        if pf.applies is None or "*" in pf.applies or checked & set(pf.applies):
            continue
        out.append(_gate.error_outcome(p, AsmError(pf.applies_span, f"the property file {p} applies to "
                                                                    f"{', '.join(pf.applies)}: none of the checked "
                                                                    f"specs has that name; fix its 'applies to' "
                                                                    f"line"), root))
        out[-1].subject = "property file"
    return out


def _asm_name(path: Path) -> str:
    from .syntax.parser import decode_source, read_source_bytes
    try:
        text = decode_source(read_source_bytes(path))   # regular files only: a FIFO would block
    except AsmError:
        return path.stem
    m = re.search(r"\b(?:asm|module)\s+([A-Za-z_][A-Za-z0-9_]*)", strip_comments(text))
    return m.group(1) if m else path.stem
