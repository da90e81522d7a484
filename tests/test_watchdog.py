"""The time limit's watchdog (the alarm that stops a step running long inside the step function)
never loses the time-out: an alarm that comes while a generator is being closed (the term
evaluator's bindings, dropped once an ``exist`` has its witness) or inside a ``__del__`` would
raise where Python drops the exception ("Exception ignored in ..."); the watchdog puts it off to a
safe point, and the run ends with the time-limit verdict and its message.

The alarm is sent at those points by the test itself (the evaluator's bindings wrapped), not by
the clock: the run's own limit (600 s) is never reached."""
from __future__ import annotations

import gc
import re
import signal
import sys
import time

import pytest

from asmcheck.cli import main
from asmcheck.semantics.machine import Machine

from helpers import write

pytestmark = [pytest.mark.engines("python"),
              pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="no interval timer on this platform")]

# each step evaluates an exist and a forall over two variables (the evaluator's bindings are a
# generator; the exist drops it after the witness, which closes it); 2,000 states
QUANTS = """asm Quants
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled x: Integer
	controlled y: Integer
definitions:
	domain D = {0 : 5}
	invariant inv_x over x: x >= 0
	main rule r_main = if x < 1999 then par
		if (exist $i in D, $j in D with $i + $j = 3) then x := x + 1 endif
		if (forall $i in D, $j in D with $i + $j >= 0) then y := (y + 1) mod 2 endif
	endpar endif
default init s0:
	function x = 0
	function y = 0
"""


class AlarmAtCleanup:
    """Wraps the evaluator's bindings: the ``at``-th time a generator of them is closed (GeneratorExit
    in flight), or dropped with an object whose ``__del__`` runs then (``where="del"``), ``signum``
    (SIGALRM, the watchdog's) is sent to the process; the next bindings wait (up to 5 s) for the watchdog's
    TimeUp at that safe point."""

    def __init__(self, monkeypatch, where: str, at: int = 50, signum=signal.SIGALRM):
        self.where, self.at, self.closed, self.sent, self.waited = where, at, 0, False, False
        orig = Machine._iter_bindings
        me = self

        class Alarm:
            def __del__(self):
                signal.raise_signal(signum)

        def bindings(machine, ctx, ranges):
            if me.sent and not me.waited:
                me.waited = True
                time.sleep(5)           # (a sleep the alarm's handler interrupts)
            try:
                yield from orig(machine, ctx, ranges)
            finally:
                if sys.exc_info()[0] is GeneratorExit and not me.sent:
                    me.closed += 1
                    if me.closed == me.at:
                        me.sent = True
                        if me.where == "del":
                            alarm = Alarm()
                            del alarm
                        else:
                            signal.raise_signal(signum)
        monkeypatch.setattr(Machine, "_iter_bindings", bindings)


@pytest.mark.parametrize("where", ["generator", "del"])
def test_an_alarm_at_a_cleanup_ends_the_run_with_the_time_limit(tmp_path, capsys, monkeypatch, where):
    path = write(tmp_path, QUANTS)
    gc.collect()
    alarm = AlarmAtCleanup(monkeypatch, where)
    dropped = []            # (what Python prints as "Exception ignored in ...")
    monkeypatch.setattr(sys, "unraisablehook", dropped.append)
    code = main(["explore", path, "--engine", "python", "--max-seconds", "600"])
    out, err = capsys.readouterr()
    assert alarm.sent
    assert [(type(u.exc_value).__name__, repr(u.object)) for u in dropped] == []
    assert "Exception ignored" not in err and "Traceback" not in err, err
    assert err == ""
    assert code == 3, out
    # (the alarm came in state 49's step: the 50th exist)
    lines = out.splitlines()
    assert re.fullmatch(r"Quants\.asm: 50 states, 49 transitions, depth 49, [\d.]+ s, python engine", lines[0])
    assert lines[1:] == ["  inv_x                                    incomplete",
                         "incomplete: time limit 600.0 s reached",
                         "verdict: incomplete"]


def test_without_an_alarm_the_wrapped_run_is_complete(tmp_path, capsys, monkeypatch):
    # (the wrapper changes nothing else: the same spec, no alarm sent, is explored in full)
    path = write(tmp_path, QUANTS)
    alarm = AlarmAtCleanup(monkeypatch, "generator", at=10**9)
    assert main(["explore", path, "--engine", "python", "--max-seconds", "600"]) == 0
    out = capsys.readouterr().out
    assert not alarm.sent
    assert out.splitlines()[0].startswith("Quants.asm: 2,000 states, ")


@pytest.mark.parametrize("where", ["generator", "del"])
def test_a_sigterm_at_a_cleanup_ends_the_run_as_interrupted(tmp_path, capsys, monkeypatch, where):
    # (the same for SIGTERM, which ends a command as Ctrl-C does: put off to a safe point)
    path = write(tmp_path, QUANTS)
    gc.collect()
    alarm = AlarmAtCleanup(monkeypatch, where, signum=signal.SIGTERM)
    dropped = []
    monkeypatch.setattr(sys, "unraisablehook", dropped.append)
    code = main(["explore", path, "--engine", "python"])
    out, err = capsys.readouterr()
    assert alarm.sent
    assert [(type(u.exc_value).__name__, repr(u.object)) for u in dropped] == []
    assert (code, err) == (3, "")
    lines = out.splitlines()
    assert re.fullmatch(r"Quants\.asm: 50 states, 49 transitions, depth 49, [\d.]+ s, python engine", lines[0])
    assert lines[1:] == ["  inv_x                                    incomplete",
                         "incomplete: interrupted (SIGTERM)",
                         "verdict: incomplete"]
