"""Simulation: one run of a spec, step by step, through the shared step function."""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from .errors import SOURCES, AsmError, Span
from .semantics import types as T
from .semantics.machine import DrawingChooser, InputChooser, Machine, RandomChooser
from .semantics.printer import parse_asmeta_value, split_top
from .semantics.values import BagV, MapV, SeqV, SetV


@dataclass
class SimStep:
    number: int
    choices: list                  # Choice records (choose branches and monitored inputs)
    changed: dict                  # location key -> new value (None: became undef)
    state: dict
    monitored: dict
    violated: list = field(default_factory=list)
    error: AsmError | None = None


class InputText(str):
    """A value as written in an inputs file, with its position there (``span``) and the
    position of its location (``loc_span``)."""

    span: Span | None = None
    loc_span: Span | None = None


def read_inputs(path: str) -> list[dict]:
    """Monitored values per step: ``location = value`` lines; a line ``---`` ends a step.

    Values are written as ASMETA prints them (``true``, ``3``, ``RED``, ``"text"``, ``[1,2,3]``,
    ``{AA,BB}``, ``<1,1>``, ``(1,true)``, ``{A->1}``); each keeps its position for error messages."""
    try:
        text = open(path, encoding="utf-8", errors="replace").read()
    except OSError as e:
        raise AsmError(None, f"{path}: cannot read inputs: {e.strerror or e}") from None
    SOURCES.add(path, text)
    steps: list[dict] = [{}]
    for no, line in enumerate(text.splitlines(), 1):
        s = line.split("//", 1)[0].strip()
        if not s:
            continue
        if s == "---":
            steps.append({})
            continue
        m = re.match(r"^(.+?)\s*=\s*(.+)$", s)
        if not m:
            raise AsmError(Span(path, no, 1), "expected 'location = value' or '---'")
        raw = m.group(2).strip()
        val = raw[1:-1] if len(raw) >= 2 and raw[0] == raw[-1] == '"' else raw
        val = InputText(val)
        lcol = line.index(s) + 1
        val.loc_span = Span(path, no, lcol)
        val.span = Span(path, no, lcol + m.start(2))
        steps[-1][m.group(1).replace(" ", "")] = val
    return steps


def _unquote(v):
    """Strings inside a structured input value may be written with quotes."""
    if type(v) is str and len(v) >= 2 and v[0] == v[-1] == '"':
        return v[1:-1]
    if type(v) is tuple:
        return tuple(_unquote(x) for x in v)
    if isinstance(v, SeqV):
        return SeqV([_unquote(x) for x in v])
    if isinstance(v, SetV):
        return SetV([_unquote(x) for x in v])
    if isinstance(v, BagV):
        return BagV.of([_unquote(x) for x in v])
    if isinstance(v, MapV):
        return MapV.of([(_unquote(a), _unquote(b)) for a, b in v])
    return v


def parse_inputs(machine: Machine, inputs: list[dict]) -> list[dict]:
    """The inputs as values: location text (as the machine writes it) -> value of the function's
    codomain.  A location that is not a monitored function's, or a value that is not one of its
    codomain (a malformed Seq, a Set of the wrong elements, an enum constant that does not exist),
    is an input error at its position in the file."""
    by_name: dict = {}
    for f in machine.functions:
        by_name.setdefault(f.name, []).append(f)
    out = []
    for block in inputs:
        parsed = {}
        for loc, text in block.items():
            span = getattr(text, "span", None)
            lspan = getattr(text, "loc_span", None) or span
            name, paren, rest = loc.partition("(")
            if paren and not rest.endswith(")"):
                raise AsmError(lspan, f"{loc} is not a location (expected NAME or NAME(ARGS))")
            args = split_top(rest[:-1]) if paren else []
            funcs = [f for f in by_name.get(name, []) if f.arity == len(args)]
            if not funcs:
                raise AsmError(lspan, f"no function {name} with {len(args)} argument(s) in {machine.spec.name}")
            mon = [f for f in funcs if f.kind == "monitored"]
            if not mon:
                raise AsmError(lspan, f"{name} is a {funcs[0].kind} function, not a monitored one: the inputs "
                                      f"give values of monitored functions")
            key = value = problem = None
            for f in mon:
                try:
                    vals = tuple(_unquote(parse_asmeta_value(a, t, machine)) for a, t in zip(args, f.domain))
                except (ValueError, IndexError):
                    problem = problem or (lspan, f"the arguments of {loc} are not values of the domain of {name}")
                    continue
                try:
                    value = _unquote(parse_asmeta_value(str(text), f.codomain, machine))
                except (ValueError, IndexError):
                    value = None
                    problem = (span, f"{text} is not a value of {f.codomain} (the codomain of {name})")
                    continue
                if value is not None and not _in_codomain(machine, f, value):
                    problem = (span, f"{text} is not a value of {f.codomain} (the codomain of {name})")
                    continue
                key = machine.key_of(f, vals)
                break
            if key is None:
                raise AsmError(*problem)
            parsed[machine.location_text(key)] = value
        out.append(parsed)
    return out


def _in_codomain(machine: Machine, f, value) -> bool:
    from .semantics.state import same_value
    if f.codomain is T.NATURAL:
        return type(value) is int and value >= 0
    try:
        allowed = machine.domain_values(f.codomain, None, f.span)
    except AsmError:
        return True         # an infinite codomain: parsing checked the form of the value
    return any(same_value(value, a) for a in allowed)


def simulate(machine: Machine, steps: int, seed: int | None = None, random_choices: bool = False,
             inputs: list[dict] | None = None):
    """Run ``steps`` steps; yield the initial state then one SimStep per step (stops at an error
    or an invariant violation)."""
    def chooser_for(k):
        # choose takes the first candidate, unless random; a choose over Integer, Natural or Real,
        # which has no first, draws from a source seeded by the step number
        base = RandomChooser((seed or 0) * 1_000_003 + k) if (random_choices or seed is not None) \
            else DrawingChooser(k)
        j = max(k - 1, 0)       # the first block of the inputs is for step 1 (and the initial state)
        if values is not None and j < len(values):
            return InputChooser(values[j], base)
        return base

    values = None
    if inputs is not None:
        values = parse_inputs(machine, inputs)

    ch0 = chooser_for(0)
    state = machine.initial_state(ch0)
    bad = machine.check_invariants(state)
    yield SimStep(0, ch0.log, dict(state), state, getattr(machine, "init_mon", {}), bad)
    if bad:
        return
    for k in range(1, steps + 1):
        ch = chooser_for(k)
        try:
            ups, new, ctx = machine.step(state, ch)
            mon_bad = machine.check_invariants(state, ctx.mon, which="monitored")
        except AsmError as e:
            yield SimStep(k, ch.log, {}, state, {}, [], e)
            return
        if mon_bad:
            yield SimStep(k, ch.log, {}, state, ctx.mon, mon_bad)
            return
        changed = {}
        for key in set(state) | set(new):
            if state.get(key) is not new.get(key) and not _same(state.get(key), new.get(key)):
                changed[key] = new.get(key)
        state = new
        try:
            bad = machine.check_invariants(state)
        except AsmError as e:
            yield SimStep(k, ch.log, changed, state, ctx.mon, [], e)
            return
        yield SimStep(k, ch.log, changed, state, ctx.mon, bad)
        if bad:
            return


def _same(a, b):
    from .semantics.state import same_value
    return same_value(a, b)
