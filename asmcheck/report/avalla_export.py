"""Counterexamples as Avalla scenarios (the language of ASMETA's validator, AsmetaV).

The scenario replays the counterexample step by step, so that ASMETA users can run it in
their own tools (AsmetaV) or with ``asmcheck scenario``:

* ``check loc = v;`` for every location of the initial state, and after each step for every
  location the step changed (``check isUndef(loc);`` for undef): while the run follows the
  counterexample these checks pass;
* before each step, ``set loc := v;`` for every monitored location the step reads (Avalla
  keeps a value until the next ``set``, so every value the step reads is set again), and
  ``pick $x := v;`` for every choose rule whose choice matters (``pick $x in r_rule := v;``
  when more than one rule binds ``$x``);
* at the end, the violation:

  - an invariant: ``check <the invariant>;`` -- this check **fails**, in the state that
    violates it (for an invariant of the spec the validator already stops there, as AsmetaV
    does, with the invariant reported as violated);
  - a step property (``next``, ``updated``, ``updatedBy``, ``changed``): Avalla cannot state
    a property of a step; the checks of the last step pin the violating step down and a
    comment quotes the property;
  - a deadlock, an error, or an LTL/CTL lasso: a comment says what happens from there.

So a scenario exported from a counterexample *fails at the violation* (for invariants) or
passes with every check (for step properties): either way every check before the end passes
exactly when the run is the counterexample's.

Limits: an element made by ``extend`` has no name in AsmetaL, so locations and values that
involve one are not checked or set (a comment says so, naming the element as the trace's
display names do, which are the names a run of the scenario gives it); a choose rule that runs more than
once in one step with different choices cannot be fixed by ``pick`` (a comment says so); the
initial state is the one the validator builds (a spec whose initialisation chooses is
replayed with its first choices).
"""
from __future__ import annotations

import os
import re
from pathlib import Path

from ..version import __version__
from ..semantics.choice import next_prefix

_GOOD = re.compile(r"[!-#%-9<-~]+")         # Avalla's GOOD_CHARS_NO_COLON


def scenario_name(text: str) -> str:
    name = re.sub(r"[^!-#%-9<-~]", "_", text)
    return name or "counterexample"


def scenario_file_name(spec_name: str, prop_name: str) -> str:
    safe = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{spec_name}.{prop_name}")
    return f"{safe}.avalla"


def load_path(spec_path: str, out_path: str | None) -> str:
    """The spec's path as the scenario's ``load`` names it: relative to the scenario's folder."""
    spec_abs = os.path.abspath(spec_path)
    if out_path is None:
        p = Path(spec_abs).as_posix()
    else:
        here = os.path.dirname(os.path.abspath(out_path))
        try:
            common = os.path.commonpath([spec_abs, here])
            rel = os.path.relpath(spec_abs, here)
        except ValueError:      # another drive
            common, rel = "", spec_abs
        # relative when the two share a folder below the root, else absolute
        p = Path(rel if common and os.path.dirname(common) != common else spec_abs).as_posix()
    if not _GOOD.fullmatch(p.replace(":", "#")):
        p = f'"{p}"'
    return p


def _fresh(v) -> bool:
    """A value that has no name in AsmetaL (an element made by ``extend``)."""
    from ..semantics.values import AbstractValue, BagV, MapV, SeqV, SetV
    if isinstance(v, AbstractValue):
        return v.serial > 0
    if isinstance(v, (tuple, list, SeqV, BagV)):
        return any(_fresh(x) for x in v)
    if isinstance(v, SetV):
        return any(_fresh(x) for x in v.ordered())
    if isinstance(v, MapV):
        return any(_fresh(k) or _fresh(x) for k, x in v)
    return False


def _key_fresh(key) -> bool:
    return type(key) is tuple and len(key) == 2 and isinstance(key[1], tuple) and _fresh(key[1])


def _checks(machine, keys, state, out: list) -> None:
    from ..semantics.printer import location_text, printable
    from ..semantics.state import is_dom_key
    from ..semantics.values import show
    for k in keys:
        if is_dom_key(k):
            out.append(f"// not checked: the elements of {k[1]} (made by extend)")
            continue
        if not printable(machine, k):
            continue
        v = state.get(k)
        loc = location_text(machine, k)
        if _key_fresh(k) or _fresh(v):
            out.append(f"// not checked: {loc} = {show(v)} (an element made by extend has no name)")
        elif v is None:
            out.append(f"check isUndef({loc});")
        else:
            out.append(f"check {loc} = {show(v)};")


def _picks(step_choices, chooses, out: list) -> None:
    from ..semantics.values import show
    from .describe import flat_choices
    names_by_rule: dict = {}
    for label, (rd, node) in chooses.by_label.items():
        for var, _ in node.bindings:
            names_by_rule.setdefault(var.name, set()).add(id(rd))
    done: dict = {}
    for c in flat_choices(step_choices):
        if c.kind != "choose" or not isinstance(c.value, dict):
            continue
        rd, node = chooses.node(c.label)
        for var, val in c.value.items():
            key = (c.label, var)
            if key in done:
                if not _same(done[key], val):
                    out.append(f"// the {c.label} runs more than once in this step, with {var} = "
                               f"{show(done[key])} and {var} = {show(val)}: a pick cannot fix both")
                continue
            done[key] = val
            if _fresh(val):
                out.append(f"// not picked: {var} = {show(val)} (an element made by extend has no name)")
                continue
            qual = ""
            if rd is not None and len(names_by_rule.get(var, ())) > 1:
                if not rd.name.startswith("r_"):
                    out.append(f"// cannot pick {var} := {show(val)}: more than one rule binds {var}, and "
                               f"{rd.name} cannot be named in a pick (rule names there start with r_)")
                    continue
                qual = f" in {rd.name}"
            out.append(f"pick {var}{qual} := {show(val)};")


def _same(a, b) -> bool:
    from ..semantics.state import same_value
    return same_value(a, b)


def _sets(machine, mon: dict, out: list) -> None:
    from ..semantics.printer import location_text
    from .trace import key_order
    from ..semantics.values import show
    for k in sorted(mon, key=lambda k: key_order(machine, k)):
        v = mon[k]
        loc = location_text(machine, k)
        if _key_fresh(k) or _fresh(v):
            out.append(f"// not set: {loc} := {show(v)} (an element made by extend has no name)")
        elif v is None:
            out.append(f"// not set: {loc} is undef")
        else:
            out.append(f"set {loc} := {show(v)};")


def violating_inputs(machine, prop, state: dict, mon: dict) -> dict:
    """The monitored values (location key -> value) with which an invariant over monitored
    functions is false in ``state``: ``mon`` (the next step's inputs) completed with values
    of the locations the step did not read."""
    from ..errors import AsmError
    from ..semantics.machine import Ctx, Enumerator
    fn = getattr(prop, "fn", None)
    if fn is None:
        return dict(mon or {})
    prefix: list = []
    while True:
        ch = Enumerator(prefix)
        ctx = Ctx(machine, state, ch)
        if mon:
            ctx.mon = dict(mon)
        try:
            v = fn(ctx)
        except AsmError:
            v = None
        if v is not True:
            return dict(ctx.mon)
        prefix = next_prefix(ch.log)
        if prefix is None:
            return dict(mon or {})


def _comment_block(text: str, width: int = 92) -> list[str]:
    """``text`` as '// ' lines of at most about ``width`` characters."""
    out, line = [], ""
    for word in text.split(" "):
        if line and len(line) + 1 + len(word) > width - 3:
            out.append("// " + line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    if line:
        out.append("// " + line)
    return out


def trace_scenario(machine, trace, *, spec_path: str, out_path: str | None = None, prop=None,
                   chooses=None, inputs=None, name: str | None = None, root: str | None = None,
                   loop: int | None = None) -> str:
    """The Avalla scenario that replays ``trace`` (a report.trace.Trace).

    ``out_path`` is where the scenario will be written (its ``load`` is relative to it);
    ``prop`` the violated property (defaults to ``trace.prop``)."""
    from .describe import ChooseIndex, display_path, property_text, shown_inputs, span_location, step_inputs, \
        step_records
    from .trace import step_header
    prop = prop if prop is not None else trace.prop
    spec = machine.spec
    if chooses is None:
        chooses = ChooseIndex(spec)
    if inputs is None:
        inputs = step_inputs(machine, trace)
    records = step_records(machine, trace, chooses, root, inputs)
    pname = getattr(prop, "name", "property")
    pkind = getattr(prop, "kind", "invariant")
    where = span_location(getattr(prop, "span", None), pname, root)
    source = getattr(prop, "source", "spec")
    kind_text = {"invariant": "invariant", "step": "step property", "deadlock": "deadlock check",
                 "error": "runtime error", "ltl": "LTL property", "ctl": "CTL property"}.get(pkind, pkind)
    if loop is None:
        loop = getattr(trace, "loop_start", None)
    nsteps = len(trace.steps) - 1
    state_inv = pkind == "invariant"
    before_last = state_inv and trace.kind == "step"    # an invariant over monitored values
    lines = [f"// Generated by asmcheck {__version__} from the shortest counterexample of {pname}",
             f"// ({kind_text}" + (f", {where}" if where else "") + f") on {spec.name}: {nsteps} "
             f"step{'s' if nsteps != 1 else ''}."]
    if state_inv:
        how = ("Every check passes while the run follows the counterexample; the last check, the "
               "invariant itself, fails: that is the violation.")
        if source == "spec":
            how += " (The validator stops at the violated invariant of the spec before it.)"
    elif pkind == "step":
        how = ("Every check passes while the run follows the counterexample; its last step is the one "
               "that violates the step property (quoted at the end).")
    else:
        how = "Every check passes while the run follows the counterexample."
    lines += _comment_block("set: the monitored values each step reads; pick: the choices of its choose "
                            "rules; check: the locations the step changed. " + how)
    lines.append(f"scenario {scenario_name(name or f'{spec.name}_{pname}')}")
    lines.append(f"load {load_path(spec_path, out_path)}")
    lines.append("")
    init = trace.steps[0]
    if any(c.index != 0 for c in init.choices):
        lines.append("// warning: the initialisation of this counterexample takes other choices than the first,")
        lines.append("// which the validator takes: the checks of state 0 may fail")
    lines.append("// state 0 (initial)")
    from .trace import key_order
    _checks(machine, sorted(init.display, key=lambda k: key_order(machine, k)), init.display, lines)
    for i, (st, rec) in enumerate(zip(trace.steps[1:], records[1:]), start=1):
        lines.append("")
        last = i == nsteps
        if loop is not None and i == loop + 1:
            lines.append(f"// the cycle starts: state {loop} on")
        lines.append("// " + step_header(rec))
        mon = inputs[i] if i < len(inputs) else {}
        if last and before_last:
            # found in the canonical state before the step, shown under display names
            _sets(machine, shown_inputs(st, violating_inputs(machine, prop, trace.steps[i - 1].state, mon)), lines)
            break
        _sets(machine, shown_inputs(st, mon), lines)
        _picks(st.shown_choices(), chooses, lines)
        lines.append("step")
        _checks(machine, sorted(st.changed, key=lambda k: key_order(machine, k)), st.display, lines)
    lines.append("")
    text = property_text(prop)
    msg = getattr(trace, "message", "")
    if state_inv:
        lines.append(f"// {pname} is violated " + ("with the monitored values set above"
                                                   if before_last else "in this state") + ": this check fails")
        if text:
            lines.append(f"check {text};")
        else:
            lines.append(f"// (the text of {pname} is not available)")
    elif pkind == "step":
        lines.append(f"// the last step violates {pname}" + (f": {msg}" if msg else ""))
        if text:
            lines.append(f"//   {text}")
        lines += _comment_block("Avalla cannot state a property of a step (next, updated, updatedBy, "
                                "changed): the checks of the last step pin it down.")
    elif pkind == "deadlock":
        lines.append(f"// deadlock: {msg or 'from this state no step leads elsewhere'}")
    elif pkind == "error":
        lines.append(f"// from this state a step fails: {msg}")
    elif loop is not None:
        lines.append(f"// {pname} is violated: the state is now state {loop} again, and steps {loop + 1} to "
                     f"{nsteps} repeat for ever")
        if text:
            lines.append(f"//   {text}")
    else:
        lines.append(f"// {pname} is violated" + (f": {msg}" if msg else ""))
    return "\n".join(lines) + "\n"


def write_scenario(path: str, text: str) -> None:
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    Path(path).write_text(text, encoding="utf-8")


def explore_avalla(out: str, machine, spec_path: str, traces) -> list[str]:
    """For ``asmcheck explore --avalla OUT``: write one scenario per counterexample
    (``traces``: [(Violation, Trace)]).  One counterexample goes to OUT; with several, each
    goes to OUT's stem + '.' + property + '.avalla' (or into OUT when it is a folder).
    Returns the paths written."""
    written = []
    is_dir = out.endswith(("/", os.sep)) or os.path.isdir(out) or not out.endswith(".avalla")
    for v, tr in traces:
        if is_dir:
            target = os.path.join(out, scenario_file_name(machine.spec.name, v.prop.name))
        elif len(traces) == 1:
            target = out
        else:
            target = out[: -len(".avalla")] + "." + re.sub(r"[^A-Za-z0-9_.-]", "_", v.prop.name) + ".avalla"
        write_scenario(target, trace_scenario(machine, tr, spec_path=spec_path, out_path=target, prop=v.prop))
        written.append(target)
    return written
