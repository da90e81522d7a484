"""Simulation: one run of a spec, step by step, through the shared step function."""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from .errors import AsmError, AsmRuntimeError, Span
from .semantics import types as T
from .semantics.machine import Chooser, InputChooser, Machine, RandomChooser, NO_VALUE
from .semantics.printer import show_asmeta
from .semantics.state import is_dom_key


@dataclass
class SimStep:
    number: int
    choices: list                  # Choice records (choose branches and monitored inputs)
    changed: dict                  # location key -> new value (None: became undef)
    state: dict
    monitored: dict
    violated: list = field(default_factory=list)
    error: AsmError | None = None


def read_inputs(path: str) -> list[dict]:
    """Monitored values per step: ``location = value`` lines; a line ``---`` ends a step.

    Values are written as asmcheck prints them (``true``, ``3``, ``RED``, ``"text"``)."""
    try:
        text = open(path, encoding="utf-8", errors="replace").read()
    except OSError as e:
        raise AsmError(None, f"{path}: cannot read inputs: {e.strerror or e}") from None
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
        val = m.group(2).strip()
        if len(val) >= 2 and val[0] == val[-1] == '"':
            val = val[1:-1]
        steps[-1][m.group(1).replace(" ", "")] = val
    return steps


class _TextInputs(InputChooser):
    """Monitored values given as text (matched against the values of the domain)."""

    def __init__(self, values: dict, fallback):
        super().__init__({}, fallback)
        self.texts = values

    def choose(self, kind, label, options, values_repr=None) -> int:
        if kind == "monitored" and label in self.texts:
            want = self.texts[label]
            for i, o in enumerate(options):
                if show_asmeta(o) == want:
                    from .semantics.machine import Choice
                    self.log.append(Choice(kind, label, len(options), i, o))
                    return i
            raise AsmRuntimeError(None, f"the input {label} = {want} is not a value of its domain")
        i = self.fallback.choose(kind, label, options, values_repr)
        self.log.append(self.fallback.log.pop())
        return i

    def value(self, label, dom):
        if label in self.texts:
            text = self.texts[label]
            r = T.root(dom)
            try:
                v = int(text) if r in (T.INTEGER, T.NATURAL) else float(text) if r is T.REAL else text
            except ValueError:
                raise AsmRuntimeError(None, f"the input {label} = {text} is not a value of {dom}") from None
            from .semantics.machine import Choice
            self.log.append(Choice("monitored", label, 0, 0, v))
            return v
        v = self.fallback.value(label, dom)
        if v is not NO_VALUE:
            self.log.append(self.fallback.log.pop())
        return v


def simulate(machine: Machine, steps: int, seed: int | None = None, random_choices: bool = False,
             inputs: list[dict] | None = None):
    """Run ``steps`` steps; yield the initial state then one SimStep per step (stops at an error
    or an invariant violation)."""
    def chooser_for(k):
        base = RandomChooser((seed or 0) * 1_000_003 + k) if (random_choices or seed is not None) else Chooser()
        j = max(k - 1, 0)       # the first block of the inputs is for step 1 (and the initial state)
        if inputs is not None and j < len(inputs):
            return _TextInputs(inputs[j], base)
        return base

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
