"""The time limit of a partitioned search (--workers N on the Python step function, and the Ray
actors of --cluster, which run the same partitions) stops a step that runs long, as the sequential
search's does: the workers' step function has the deadline.  A level was waited for to its end, and
a step that runs for minutes ran for minutes past --max-seconds."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import write
from test_cli_reliability import SLOW_STEP     # one step enumerates 64 million bindings of a choose

pytestmark = pytest.mark.engines("python")

ROOT = Path(__file__).resolve().parent.parent


def test_a_step_that_runs_long_ends_at_the_time_limit_with_workers(tmp_path):
    path = write(tmp_path, SLOW_STEP)
    r = subprocess.run([sys.executable, "-m", "asmcheck", "explore", path, "--engine", "python", "--workers", "2",
                        "--max-seconds", "1"], capture_output=True, text=True, timeout=120,
                       env={**os.environ, "PYTHONPATH": str(ROOT), "NO_COLOR": "1"})
    assert (r.returncode, r.stderr) == (3, "")
    lines = r.stdout.splitlines()
    assert lines[0].startswith("SlowStep.asm: 1 states, 0 transitions, depth 0, ")
    assert lines[0].endswith(" s, python engine, 2 workers")
    assert lines[1:] == ["  inv_x                                    incomplete",
                         "incomplete: time limit 1.0 s reached",
                         "verdict: incomplete"]
