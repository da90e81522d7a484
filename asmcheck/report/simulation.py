"""A simulation run rendered: text (the choices and what changed per step), ASMETA's
``<State n (controlled)>`` blocks, and JSON."""
from __future__ import annotations

from ..semantics.printer import asmeta_state_lines, location_sort_key, location_text, location_text_asmeta, \
    show_asmeta
from ..semantics.state import is_dom_key
from ..semantics.values import show
from .describe import Choice
from .trace import json_value, key_order, step_header


def _problems(st, out: list) -> bool:
    bad = False
    if st.error is not None:
        out.append(st.error.render())
        bad = True
    for p in st.violated:
        out.append(f"{p.span}: invariant {p.name} is violated" +
                   (" in the initial state" if st.number == 0 else f" after step {st.number}"))
        bad = True
    return bad


def simulation_text(machine, steps) -> tuple[list[str], bool]:
    """(lines, whether an error or a violated invariant ended the run).  Each step as a trace
    shows it (:func:`.trace.step_header`): the rule that chose what, the monitored values it
    read, then the locations it changed."""
    from .describe import ChooseIndex, StepRecord, choose_records, flat_choices, read_records
    chooses = ChooseIndex(machine.spec)
    out = []
    bad = False
    for st in steps:
        choices = []
        if st.number > 0:
            reads = read_records(machine, st.monitored) if st.monitored else [
                Choice("monitored", f"{c.label} = {show(c.value)}") for c in flat_choices(st.choices)
                if c.kind == "monitored"]
            choices = choose_records(st.choices, chooses) + reads
        out.append(step_header(StepRecord(st.number, chooses.main, choices, {}, {})))
        for k, v in sorted(st.changed.items(), key=lambda kv: key_order(machine, kv[0])):
            if is_dom_key(k):
                out.append(f"    {k[1]} = {{{', '.join(e.name for e in (v or ()))}}}")
            else:
                out.append(f"    {location_text(machine, k)} = {show(v)}")
        if not st.changed and st.number > 0 and st.error is None and not st.violated:
            out.append("    (no change)")
        bad = _problems(st, out) or bad
    return out, bad


def simulation_asmeta(machine, steps) -> tuple[list[str], bool]:
    """ASMETA's simulator output: per step the monitored values taken and the controlled state."""
    out = []
    bad = False
    last = None
    for st in steps:
        last = st
        if st.number > 0:
            for c in st.choices:
                if c.kind == "monitored":
                    out.append(f"taking {show_asmeta(c.value)} for {c.label}")
            if st.monitored and st.error is None:
                out.append(f"<State {st.number - 1} (monitored)>")
                for k in sorted(st.monitored, key=lambda k: location_sort_key(machine, k)):
                    out.append(f"{location_text_asmeta(machine, k)}={show_asmeta(st.monitored[k])}")
                out.append(f"</State {st.number - 1} (monitored)>")
            if st.error is None and not (st.violated and not st.changed and st.number > 0):
                out.append(f"<State {st.number} (controlled)>")
                out.extend(asmeta_state_lines(machine, st.state))
                out.append(f"</State {st.number} (controlled)>")
        bad = _problems(st, out) or bad
    out.append("Final state:")
    if last is not None:
        out.extend(asmeta_state_lines(machine, last.state))
    return out, bad


def simulation_json(machine, spec_name: str, steps) -> tuple[dict, bool]:
    docs = []
    bad = False
    for st in steps:
        docs.append({
            "step": st.number,
            "choices": [{"kind": c.kind, "label": c.label, "value": json_value(c.value)} for c in st.choices],
            "changed": {location_text(machine, k) if not is_dom_key(k) else k[1]: json_value(v)
                        for k, v in sorted(st.changed.items(), key=lambda kv: key_order(machine, kv[0]))},
            "violated": [p.name for p in st.violated],
            "error": None if st.error is None else str(st.error),
        })
        bad = bad or st.error is not None or bool(st.violated)
    return {"spec": spec_name, "steps": docs}, bad
