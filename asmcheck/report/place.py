"""A violation found by another search than explore's (Z3's bmc, the swarm's random walks),
shown as ``asmcheck explore`` shows one, and the property's formula and location as the JSON
violations carry them (as ``check --json`` rows do)."""
from __future__ import annotations

from .describe import property_text, span_location
from .trace import describe_trace, violation_head, violation_lines


def _plain(prop) -> bool:
    """A property of the spec (not deadlock, not a step that fails)."""
    return getattr(prop, "kind", "") not in ("deadlock", "error") and \
        getattr(prop, "name", "") not in ("deadlock", "error")


def property_place(prop) -> dict:
    """The formula (its term on one line, '' for deadlock and a step that fails) and the
    location (null when unknown; for a step that fails, where it fails) of a violated property."""
    formula = property_text(prop) if _plain(prop) else ""
    loc = span_location(getattr(prop, "span", None), getattr(prop, "name", None) if formula else None)
    return {"formula": formula, "location": loc.json() if loc is not None else None}


def found_violation_lines(machine, prop, trace, message: str, color: bool = False,
                          what: str = "counterexample") -> list[str]:
    """A violation of ``prop`` with its replayed ``trace`` (explore.trace.Trace), as explore
    shows one: what is violated and where, the summary, the formula, then the trace."""
    span = getattr(prop, "span", None)
    where = f" ({span.short()})" if span is not None and getattr(span, "line", 0) else ""
    head = violation_head(prop.name, getattr(prop, "kind", ""), where, message)
    formula = property_text(prop) if _plain(prop) else ""
    return violation_lines(head, describe_trace(machine, trace), color, formula, what=what)
