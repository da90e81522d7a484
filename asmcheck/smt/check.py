"""Build the Z3 model of a loaded spec and its properties, run BMC or k-induction."""
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


def check(spec, machine, state_props, step_props, *, k: int, induction: bool = False, properties=None,
          assume=None, aux=(), infer: bool = False, first: bool = False, loop_bound=None, max_seconds=None):
    """Run the engine on a loaded spec and its properties; return (model, outcome, targets).

    ``properties``: the names to check (default: all, and run-time errors); ``assume``: with
    ``properties``, the others that may strengthen k-induction; ``aux``: ``'name: term'``
    auxiliary invariants (checked too)."""
    aux_props = aux_properties(spec, machine, list(aux or []))
    names = {p.name for p in state_props + step_props}
    for a in aux_props:
        if a.name in names:
            raise UsageError(f"--aux {a.name}: a property of that name exists already")
        names.add(a.name)
    targets, st, sp = select_properties(state_props, step_props, properties, assume)
    model = Model(machine, st, sp, aux_props=aux_props, loop_bound=loop_bound)
    if induction:
        for p in model.props:
            if p.name not in targets and p.kind != "error":
                p.aux = True          # a property of the spec used only to strengthen the induction
        out = run_induction(model, k, targets=targets, max_seconds=max_seconds, infer=infer)
    else:
        out = run_bmc(model, k, stop_at_first=first, max_seconds=max_seconds, targets=set(targets))
    return model, out, targets


def select_properties(state_props, step_props, properties=None, assume=None):
    """Targets (``properties``, default all) and the properties the model includes."""
    names = [p.name for p in state_props + step_props]
    targets = list(properties or [])
    assume = list(assume or [])
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
