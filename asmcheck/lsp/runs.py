"""Long runs started from the editor: explore with a time limit, simulate N steps.

This is the only module of the language server that runs specs; it returns
plain data (verdicts with the property's position, trace texts) that the
server turns into diagnostics and documents.  A run is cancelled by the
``cancelled`` callback (checked with each progress report of the explorer).
"""
from __future__ import annotations

import argparse
import io
from contextlib import redirect_stdout
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import AsmError, Span


class Cancelled(Exception):
    """The editor cancelled the run."""


@dataclass
class Settings:
    """What a workspace of specs needs without flags."""

    import_path: list[str] = field(default_factory=list)     # -I DIR
    int_range: str | None = None                             # --int-range LO..HI
    monitored: list[str] = field(default_factory=list)       # --monitored NAME=LO..HI
    explore_seconds: float = 30.0                            # the time limit of the Explore lens
    simulate_steps: int = 10

    def args(self, **extra) -> argparse.Namespace:
        ns = argparse.Namespace(int_range=self.int_range, monitored=list(self.monitored) or None,
                                max_states=None, max_depth=None, max_seconds=self.explore_seconds,
                                deadlock=False, properties=None, no_default_properties=False,
                                engine="python", fair=[], format="text")
        for k, v in extra.items():
            setattr(ns, k, v)
        return ns

    def cli_flags(self) -> list[str]:
        out: list[str] = []
        for d in self.import_path:
            out += ["-I", d]
        if self.int_range:
            out += ["--int-range", self.int_range]
        for m in self.monitored:
            out += ["--monitored", m]
        return out


@dataclass
class Verdict:
    name: str
    kind: str
    verdict: str                     # holds violated incomplete "cannot be checked"
    span: Span | None                # where the property is written (spec or property file)
    trace: str | None = None         # the counterexample, as `asmcheck explore` prints it


@dataclass
class ExploreOutcome:
    spec: str
    verdict: str
    states: int
    transitions: int
    depth: int
    seconds: float
    reason: str
    verdicts: list[Verdict]

    @property
    def summary(self) -> str:
        s = (f"{self.spec}: {self.states:,} states, {self.transitions:,} transitions, depth {self.depth}, "
             f"{self.seconds:.2f} s: {self.verdict}")
        return s + (f" ({self.reason})" if self.reason else "")


def explore(path: str, settings: Settings, progress=None, cancelled=None) -> ExploreOutcome:
    """Explore the spec saved at ``path`` with the settings' time limit; raise Cancelled when asked to stop.

    ``progress(states, depth, transitions, seconds)`` is called about twice a second.
    """
    from ..commands import _load, machine_options
    from ..commands_explore import _property_table
    from ..explore.bfs import Explorer
    from ..props import spec_properties
    from ..props.files import properties_for
    from ..report.trace import build_trace, trace_text

    args = settings.args()
    spec, machine = _load(path, machine_options(args))
    state_props, step_props = spec_properties(machine)
    extra_state, extra_step, temporal = properties_for(spec, machine, path, None, use_default=True)
    state_props += extra_state
    step_props += extra_step

    def report(states, depth, transitions, secs):
        if cancelled is not None and cancelled():
            raise Cancelled()
        if progress is not None:
            progress(states, depth, transitions, secs)

    ex = Explorer(machine, max_states=None, max_depth=None, max_seconds=settings.explore_seconds,
                  deadlock=False, progress=report, keep_graph=bool(temporal),
                  state_props=state_props, step_props=step_props)
    result = ex.run()
    if cancelled is not None and cancelled():
        raise Cancelled()
    traces: dict[str, str] = {}
    for v in result.violations:
        tr = build_trace(ex, v)
        where = f" ({v.prop.span.short()})" if getattr(v.prop, "span", None) is not None and v.prop.span.line else ""
        what = "deadlock" if v.prop.name == "deadlock" else f"{v.prop.name}{where} is violated"
        steps = len(tr.steps) - 1
        head = (f"{what}" + (f": {v.message}" if v.message else "") +
                f" -- shortest trace, {steps} step{'s' if steps != 1 else ''}" +
                (" (the last step breaks it)" if tr.kind == "step" else "") + ":")
        traces.setdefault(v.prop.name, "\n".join([head] + ["  " + line for line in trace_text(machine, tr, False)]))
    temporal_results = []
    if temporal and result.verdict != "incomplete":
        from ..temporal import check_temporal
        temporal_results = check_temporal(ex, temporal, fair=[])
        for t in temporal_results:
            if not t.holds:
                result.verdict = "violated"
                traces.setdefault(t.name, "\n".join(t.text(machine, False)))
    spans = {}
    for p in result.checked:
        spans.setdefault(p.name, getattr(p, "span", None))
    for t in temporal_results:
        spans.setdefault(t.name, getattr(t.prop, "span", None))
    verdicts = [Verdict(row["property"], row["kind"], row["verdict"], spans.get(row["property"]),
                        traces.get(row["property"]))
                for row in _property_table(result, temporal_results)]
    return ExploreOutcome(spec.name, result.verdict, result.states, result.transitions, result.depth,
                          result.seconds, result.reason, verdicts)


def simulate(path: str, settings: Settings, steps: int | None = None) -> str:
    """What ``asmcheck simulate FILE -n N`` prints for the spec saved at ``path``."""
    from ..commands import cmd_simulate
    args = settings.args(file=path, steps=steps or settings.simulate_steps, seed=None, random=False,
                         input=None, format="text")
    buf = io.StringIO()
    try:
        with redirect_stdout(buf):
            cmd_simulate(args)
    except AsmError as err:
        buf.write(err.render() + "\n")
    return buf.getvalue()


def spec_name(path: str) -> str:
    return Path(path).stem
