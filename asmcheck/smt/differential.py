"""Z3 against explicit search: the depth of the first violation of every property.

Both engines answer the same question: "which properties have a violation within depth
d, and at which depth is the first?".  The explorer's depth of a violation is the length
of its shortest trace (for a step property, the depth of the violating step's source + 1).
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass
class Depths:
    depths: dict           # property name -> depth of its first violation (within the bound)
    complete: bool = True  # False when the explorer stopped early (every property violated)
    seconds: float = 0.0
    exact_to: int | None = None   # z3: beyond this depth the encoding could not represent a step


def load(path: str, prop_files=None, use_default=True, options=None):
    from ..props.load import load_machine, load_properties

    spec, machine = load_machine(path, options or {})
    state_props, step_props, _ = load_properties(spec, machine, path, prop_files, use_default)
    return spec, machine, state_props, step_props


def explicit_depths(path: str, d: int, prop_files=None, use_default=True, options=None) -> Depths:
    from ..explore.bfs import Explorer

    spec, machine, state_props, step_props = load(path, prop_files, use_default, options)
    ex = Explorer(machine, max_depth=d, state_props=state_props, step_props=step_props)
    res = ex.run()
    out = {}
    for v in res.violations:
        out[v.prop.name] = ex.depth_of[v.source] + 1 if v.source >= 0 else ex.depth_of[v.state]
    names = {p.name for p in state_props + step_props}
    complete = not (names and names <= set(out))
    return Depths(out, complete, res.seconds)


def z3_depths(path: str, d: int, prop_files=None, use_default=True, options=None) -> Depths:
    from .bmc import Model, run_bmc

    spec, machine, state_props, step_props = load(path, prop_files, use_default, options)
    out = run_bmc(Model(machine, state_props, step_props), d)
    return Depths(dict(out.depths), True, out.seconds, out.overflow_at)


def agree(ex: Depths, z: Depths) -> str | None:
    """None when the answers agree, else what differs.

    The explorer does not expand a state whose step raises an error, and stops once every
    property is violated; so when errors occur only the first violation depth over all
    properties (errors included) must agree, and properties the explorer did not reach
    are not compared."""
    e, s = ex.depths, z.depths
    if z.exact_to is not None:
        # the encoding cannot represent a step from a state at that depth (verdict unknown):
        # compare up to it (that state's own errors are among what z3 cannot see)
        def keep(k, v):
            return v < z.exact_to or (v == z.exact_to and k != "error")
        e = {k: v for k, v in e.items() if keep(k, v)}
        s = {k: v for k, v in s.items() if keep(k, v)}
    first_e = min(e.values(), default=None)
    first_s = min(s.values(), default=None)
    if first_e != first_s:
        return f"first violation at depth {first_e} (explicit) vs {first_s} (z3): {e} vs {s}"
    errors = "error" in e or "error" in s
    for name in set(e) | set(s):
        if name == "error":
            if "error" in e and e.get("error") != s.get("error"):
                return f"error: depth {e.get('error')} (explicit) vs {s.get('error')} (z3)"
            if "error" in s and "error" not in e and ex.complete:
                return f"error at depth {s['error']} found by z3 only"
            continue
        if errors:
            # past an error state the explorer stops; compare what both reached before it
            cut = min(v for k, v in list(e.items()) + list(s.items()) if k == "error")
            if e.get(name, cut + 1) <= cut or s.get(name, cut + 1) <= cut:
                if e.get(name) != s.get(name):
                    return f"{name}: depth {e.get(name)} (explicit) vs {s.get(name)} (z3)"
            continue
        if e.get(name) != s.get(name):
            if name not in e and not ex.complete:
                continue
            return f"{name}: depth {e.get(name)} (explicit) vs {s.get(name)} (z3)"
    return None
