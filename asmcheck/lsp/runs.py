"""Long runs started from the editor: explore with a time limit, simulate N steps.

This is the only module of the language server that runs specs, and it does so through
asmcheck's public API (:func:`asmcheck.load`); it returns plain data (verdicts with the
property's position, trace texts) that the server turns into diagnostics and documents.  A run
is cancelled by the ``cancelled`` callback, checked with each progress report of the explorer.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..errors import Span


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

    def load(self, path: str):
        """The spec at ``path`` with these settings, as :func:`asmcheck.load` reads it."""
        from .. import api
        mons = {}
        for item in self.monitored:
            if "=" not in item:
                raise api.UsageError(f"asmetal.monitored expects NAME=LO..HI or NAME=v1,v2,..., not {item!r}")
            name, values = item.split("=", 1)
            mons[name.strip()] = api.parse_range(values, f"asmetal.monitored {name.strip()}")
        return api.load(path, import_path=self.import_path, monitored=mons or None,
                        int_range=self.int_range or None)


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
    model = settings.load(path)

    def report(states, depth, transitions, secs):
        if cancelled is not None and cancelled():
            raise Cancelled()
        if progress is not None:
            progress(states, depth, transitions, secs)

    # the Python engine reports progress (and so can be cancelled) whatever the spec
    run = model.explore(engine="python", max_seconds=settings.explore_seconds, progress=report)
    if cancelled is not None and cancelled():
        raise Cancelled()
    traces: dict[str, str] = {}
    safety = [v for v in run.violations if not hasattr(v.raw, "holds")]
    for v, lines in zip(safety, run.violation_text()):
        traces.setdefault(v.property, "\n".join(lines))
    failed = [t for t in run.temporal if not t.holds]
    for t, lines in zip(failed, run.temporal_text()):
        traces.setdefault(t.name, "\n".join(lines))
    spans: dict[str, Span | None] = {}
    for p in list(model.state_props) + list(model.step_props) + list(model.temporal):
        spans.setdefault(p.name, getattr(p, "span", None))
    verdicts = [Verdict(row["property"], row["kind"], row["verdict"], spans.get(row["property"]),
                        traces.get(row["property"]))
                for row in run.rows]
    return ExploreOutcome(model.name, run.verdict, run.states, run.transitions, run.depth, run.seconds,
                          run.reason, verdicts)


def simulate(path: str, settings: Settings, steps: int | None = None) -> str:
    """What ``asmcheck simulate FILE -n N`` prints for the spec saved at ``path``."""
    model = settings.load(path)
    return model.simulate(steps or settings.simulate_steps).text()


def spec_name(path: str) -> str:
    return Path(path).stem
