"""The options of one simulation and those of a swarm (simulate --swarm) are not mixed: each was
ignored in the other mode without a word (--steps 5 with --swarm ran walks of 100 steps, --input
with --swarm was not even read, --depth without --swarm ran the 10 steps of one simulation), and
--swarm-workers 0 was called --workers."""
from __future__ import annotations

import pytest

from asmcheck.cli import main

from helpers import write

pytestmark = pytest.mark.engines("none")

COUNT = """asm Count
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_x over x: x < 3
	main rule r_main = if x < 7 then x := x + 1 endif
default init s0:
	function x = 0
"""

ONE = "is an option of one simulation, not of --swarm"
SWARM = "is an option of --swarm (the random walks); one simulation runs -n/--steps steps"


@pytest.mark.parametrize("args, message", [
    (["--swarm", "2", "--steps", "5"], f"--steps {ONE} (use --depth for the steps of each walk)"),
    (["--swarm", "2", "-n", "5"], f"--steps {ONE} (use --depth for the steps of each walk)"),
    (["--swarm", "2", "--input", "inputs.txt"], f"--input {ONE} (the walks choose the monitored values at random)"),
    (["--swarm", "2", "--format", "asmeta"], f"--format asmeta {ONE} (a swarm's report is text or json)"),
    (["--depth", "5"], f"--depth {SWARM}"),
    (["--swarm-workers", "2"], f"--swarm-workers {SWARM}"),
    (["--cluster", "local"], f"--cluster {SWARM}"),
    (["--swarm", "2", "--swarm-workers", "0"], "--swarm-workers expects 1 to 255 workers, not 0"),
])
def test_options_of_the_other_mode_are_usage_errors(tmp_path, capsys, args, message):
    path = write(tmp_path, COUNT)
    assert main(["simulate", path, *args]) == 2
    assert capsys.readouterr() == ("", f"asmcheck: error: {message}\n")


def test_each_mode_with_its_own_options(tmp_path, capsys):
    path = write(tmp_path, COUNT)
    assert main(["simulate", path, "--swarm", "2", "--depth", "3", "--swarm-workers", "1"]) == 1
    assert capsys.readouterr().out.startswith("Count.asm: swarm of 2 walks of up to 3 steps (seed 0): ")
    assert main(["simulate", path, "-n", "2"]) == 0
    assert capsys.readouterr().out.splitlines() == ["state 0 (initial)", "    x = 0", "step 1: r_main", "    x = 1",
                                                    "step 2: r_main", "    x = 2"]
