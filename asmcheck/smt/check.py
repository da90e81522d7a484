"""Load a spec and its properties, build the model, run BMC or k-induction."""
from __future__ import annotations

import re

from ..errors import SOURCES, AsmTypeError, Span, UsageError
from .bmc import Model, run_bmc, run_induction


def aux_properties(spec, machine, terms: list[str]) -> list:
    """``--aux 'name: term'`` / ``--aux 'term'`` as state properties named aux1, aux2, ..."""
    from ..props import StateProperty
    from ..props.files import PropDecl, resolve_decl
    from ..semantics.analysis import mentions_monitored

    out = []
    for i, text in enumerate(terms, 1):
        path = f"<aux {i}>"
        SOURCES.add(path, text)
        m = re.match(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*:(?!=)", text)
        if m:
            name, col = m.group(1), m.end() + 1
            body = text[m.end():]
        else:
            name, col, body = f"aux{i}", 1, text
        decl = PropDecl("invariant", name, body, 1, col, path, Span(path, 1, 1))
        prop = resolve_decl(spec, decl)
        prop.source = "aux"
        if mentions_monitored(prop.body):
            raise AsmTypeError(Span(path, 1, col), f"auxiliary invariant {name} reads a monitored function")
        out.append(StateProperty(prop, machine))
    return out


def load(path: str, args):
    """(spec, machine, state properties, step properties, temporal, aux properties)."""
    from ..commands import _load, machine_options
    from ..props import spec_properties
    from ..props.files import properties_for

    spec, machine = _load(path, machine_options(args))
    state_props, step_props = spec_properties(machine)
    extra_state, extra_step, temporal = properties_for(
        spec, machine, path, getattr(args, "properties", None),
        use_default=not getattr(args, "no_default_properties", False))
    state_props += extra_state
    step_props += extra_step
    aux = aux_properties(spec, machine, getattr(args, "aux", None) or [])
    names = {p.name for p in state_props + step_props}
    for a in aux:
        if a.name in names:
            raise UsageError(f"--aux {a.name}: a property of that name exists already")
        names.add(a.name)
    return spec, machine, state_props, step_props, temporal, aux


def select_properties(state_props, step_props, aux, args):
    """Targets (--property, default all) and the properties the model includes."""
    names = [p.name for p in state_props + step_props]
    targets = list(getattr(args, "property", None) or [])
    assume = list(getattr(args, "assume", None) or [])
    for n in targets + assume:
        if n not in names and n != "error":
            raise UsageError(f"no property named {n!r} (the properties: {', '.join(names) or 'none'})")
    if not targets:
        targets = names + ["error"]
        keep = set(names)
    else:
        keep = set(targets) | (set(assume) if assume else set(names))
    st = [p for p in state_props if p.name in keep]
    sp = [p for p in step_props if p.name in keep]
    return targets, st, sp


def check(path: str, args):
    """Run the engine; return (spec, machine, model, outcome, temporal, targets)."""
    spec, machine, state_props, step_props, temporal, aux = load(path, args)
    targets, st, sp = select_properties(state_props, step_props, aux, args)
    model = Model(machine, st, sp, aux_props=aux, loop_bound=getattr(args, "loop_bound", None))
    if args.induction:
        for p in model.props:
            if p.name not in targets and p.kind != "error":
                p.aux = True          # a property of the spec used only to strengthen the induction
        out = run_induction(model, args.k, targets=targets, max_seconds=args.max_seconds,
                            infer=getattr(args, "infer", False))
    else:
        out = run_bmc(model, args.k, stop_at_first=args.first, max_seconds=args.max_seconds,
                      targets=set(targets))
    return spec, machine, model, out, temporal, targets
