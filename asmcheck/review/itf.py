"""Traces in the Informal Trace Format (ITF) of Apalache and Quint.

One ITF trace per run: ``vars`` are the spec's controlled (and out) functions, each state gives
every variable a value, ``loop`` the state a lasso goes back to.  Values:

* booleans and strings as JSON; integers as ``{"#bigint": "n"}``; enum and abstract elements as
  their names (strings); sets ``{"#set": [..]}``, sequences JSON lists, tuples ``{"#tup": [..]}``,
  maps ``{"#map": [[k, v], ..]}``;
* a function with arguments is a map from its argument (a tuple when there are several) to
  its value, holding the defined locations only; a 0-ary location that is undef, and a value ITF
  has no form for (reals, bags, rules), is ``{"#unserializable": "<ASMETA text>"}``;
* the elements ``extend`` added to a domain: a variable named after the domain, a set.

Each state's ``#meta`` holds its ``index`` and, for the states after a step, the monitored
values the step read (``inputs``) and its choices (``choices``), as ASMETA's text.
"""
from __future__ import annotations

from .. import __version__
from ..semantics.state import is_dom_key
from ..semantics.values import AbstractValue, BagV, EnumValue, MapV, SeqV, SetV, show

ITF_DOC = "https://apalache-mc.org/docs/adr/015adr-trace.html"


def itf_value(v):
    t = type(v)
    if v is None:
        return {"#unserializable": "undef"}
    if t is bool or t is str:
        return v
    if t is int:
        return {"#bigint": str(v)}
    if t is EnumValue or t is AbstractValue:
        return v.name
    if t is SetV:
        return {"#set": [itf_value(x) for x in sorted(v.ordered(), key=show)]}
    if t is SeqV:
        return [itf_value(x) for x in v]
    if t is tuple:
        return {"#tup": [itf_value(x) for x in v]}
    if t is MapV:
        return {"#map": [[itf_value(k), itf_value(x)] for k, x in v]}
    return {"#unserializable": show(v)}


def _vars(machine, states) -> list[tuple]:
    """(name, function index or domain key) of every variable, in a fixed order."""
    from .common import LIBRARY_MODULES
    out = []
    for f in machine.spec.functions:
        if f.module in LIBRARY_MODULES or f is machine.spec.self_func or f is machine.spec.result_func:
            continue
        if f.kind in ("controlled", "out", "shared"):
            out.append((f.name, f.index))
    doms = sorted({k for st in states for k in st if is_dom_key(k)}, key=lambda k: k[1])
    out += [(k[1], k) for k in doms]
    return out


def state_values(machine, st: dict, variables) -> dict:
    by_func: dict = {}
    for k, v in st.items():
        if is_dom_key(k) or type(k) is int:
            continue
        by_func.setdefault(k[0], []).append((k[1], v))
    out = {}
    for name, ref in variables:
        if is_dom_key(ref):
            out[name] = {"#set": [itf_value(x) for x in sorted(st.get(ref, ()), key=show)]}
        elif machine.functions[ref].arity == 0:
            out[name] = itf_value(st.get(ref))
        else:
            pairs = sorted(by_func.get(ref, []), key=lambda kv: show(kv[0]))
            out[name] = {"#map": [[itf_value(a[0]) if len(a) == 1 else itf_value(tuple(a)), itf_value(v)]
                                  for a, v in pairs if v is not None]}
    return out


def trace_itf(machine, trace, *, source: str, description: str, loop: int | None = None, inputs=None) -> dict:
    """The ITF document of a :class:`~asmcheck.report.trace.Trace` (``loop``: the index of the
    state a lasso goes back to)."""
    from ..report.trace import choice_text, flat_choices
    states = [s.display for s in trace.steps]
    variables = _vars(machine, states)
    doc = {"#meta": {"format": "ITF", "format-description": ITF_DOC, "source": source,
                     "description": description, "generated-by": "asmcheck"},
           "vars": [n for n, _ in variables], "states": []}
    for i, s in enumerate(trace.steps):
        meta: dict = {"index": i}
        if i > 0:
            ch = [choice_text(c) for c in flat_choices(s.shown_choices()) if c.kind == "choose"]
            if ch:
                meta["choices"] = ch
            mon = inputs[i] if inputs is not None and i < len(inputs) else {}
            if mon:
                meta["inputs"] = {machine.location_text(k): show(s.show(v)) for k, v in sorted(
                    mon.items(), key=lambda kv: machine.location_text(kv[0]))}
        doc["states"].append({"#meta": meta, **state_values(machine, s.display, variables)})
    if loop is not None:
        # ITF's lasso: the last state steps back to states[loop]; the trace repeats that state
        # at its end, which goes (its step's inputs and choices move to the trace's #meta)
        if len(doc["states"]) > loop + 1 and trace.steps[-1].display == trace.steps[loop].display:
            last = doc["states"].pop()
            doc["#meta"]["loop-step"] = {k: v for k, v in last["#meta"].items() if k != "index"}
        elif getattr(trace, "up_to", ""):
            # (--symmetry: the last state is states[loop] with the interchangeable elements renamed)
            doc["#meta"]["loop-up-to"] = trace.up_to
        doc["loop"] = loop
    return doc


def load_machine(path: str, options=None):
    """The spec and its (plain) machine."""
    from ..semantics.machine import Machine
    from .common import load_spec
    spec = load_spec(path)
    return spec, Machine(spec, dict(options or {}))


def violation_itf(machine, explorer, violation, source: str) -> dict:
    """The ITF of the shortest counterexample of a violation found by the explorer."""
    from ..report.gate import step_inputs
    from ..report.trace import build_trace
    tr = build_trace(explorer, violation)
    name = getattr(violation.prop, "name", "property")
    return trace_itf(machine, tr, source=source, inputs=step_inputs(machine, tr),
                     description=f"shortest counterexample of {name} on {machine.spec.name}")


def explore_itf(path: str, options=None, prop_files=None) -> list[dict]:
    """Explore ``path`` with its properties (the spec's, its default property files and
    ``prop_files``); the ITF of each counterexample of a state or step property."""
    from ..explore.bfs import Explorer
    from ..props import spec_properties
    from ..props.files import properties_for
    spec, machine = load_machine(path, options)
    sp, tp = spec_properties(machine)
    xs, xt, _ = properties_for(spec, machine, path, prop_files, use_default=True)
    ex = Explorer(machine, state_props=sp + xs, step_props=tp + xt)
    res = ex.run()
    return [violation_itf(machine, ex, v, path) for v in res.violations]


def temporal_itf(path: str, options=None, prop_files=None) -> list[dict]:
    """The ITF of each LTL/CTL counterexample of ``path`` (a lasso carries ``loop``)."""
    from ..explore.bfs import Explorer
    from ..props.files import properties_for
    from ..report.gate import step_inputs
    from ..temporal import check_temporal
    spec, machine = load_machine(path, options)
    _, _, temporal = properties_for(spec, machine, path, prop_files, use_default=True)
    ex = Explorer(machine, keep_graph=True)
    ex.run()
    out = []
    for r in check_temporal(ex, temporal):
        if r.holds:
            continue
        got = r.trace()
        if got is None:
            continue
        tr, loop, _ = got
        name = getattr(r.prop, "name", "property")
        out.append(trace_itf(machine, tr, source=path, loop=loop, inputs=step_inputs(machine, tr),
                             description=f"counterexample of {name} on {spec.name}"
                                         + (f", a lasso back to state {loop}" if loop is not None else "")))
    return out


def itf_documents(machine, violations, source: str) -> list[dict]:
    """The ITF of each counterexample of a list of the public API's violations (explore's and
    bmc's: ``v.trace.raw`` is the replayed trace; an LTL/CTL result gives its lasso)."""
    from ..report.gate import step_inputs
    out = []
    for v in violations:
        raw = getattr(v, "raw", v)
        loop = None
        if hasattr(raw, "holds"):              # an LTL/CTL result
            got = raw.trace()
            if got is None:
                continue
            tr, loop, _ = got
        else:
            tr = v.trace.raw
        name = getattr(getattr(raw, "prop", None), "name", None) or getattr(v, "property", "property")
        if hasattr(raw, "holds"):
            desc = f"counterexample of {name} on {machine.spec.name}" + (
                f", a lasso back to state {loop}" if loop is not None else "")
        else:
            desc = f"shortest counterexample of {name} on {machine.spec.name}"
        out.append(trace_itf(machine, tr, source=source, loop=loop, inputs=step_inputs(machine, tr),
                             description=desc))
    return out
