"""Two more specs the native engine runs instead of handing them to the Python engine, each run on
both engines (pinned with --engine: equal JSON reports, the counts written here).

- A derived function declared without a definition reads as undef, as the Python step function
  reads it (from the state, where nothing puts a value).  The native engine refused the spec
  ("the function keyBB"); the Yahalom protocol models of the corpus declare two such keys.
- A state may hold more than 64 elements of a domain made by ``extend``: the engine starts again
  with more element slots, up to 256 (it stopped at 64).  Elements made in one step of a seq block
  are still limited to 64.

Engines: both (python is the reference, native is checked)."""
import json

import pytest

from asmcheck.cli import main
from asmcheck.explore.native_build import compiler
from conftest import need_asmeta
from helpers import both, engine_free

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

# keyBB, ready, level and keyOf are declared and never defined: undef wherever they are read
DECLARED = """\
asm Declared
import StandardLibrary
signature:
	enum domain Who = {AA | BB}
	abstract domain Key
	static keyAA: Key
	derived keyBB: Key
	derived ready: Boolean
	derived level: Who -> Integer
	derived keyOf: Who -> Key
	controlled holder: Who -> Key
	controlled turn: Who
	controlled n: Integer
	monitored pick: Who
definitions:
	function keyOf($w in Who) =
		switch($w)
			case AA: keyAA
			case BB: keyBB
		endswitch
	main rule r_Main =
		par
			holder(pick) := keyOf(pick)
			if isUndef(ready) and n < 5 then n := n + 1 endif
			if isUndef(level(turn)) then turn := pick endif
		endpar
default init s0:
	function turn = AA
	function n = 0
"""

# one more token a step, a hundred in the end: 101 states
HUNDRED = """\
asm Hundred
import StandardLibrary
signature:
	dynamic abstract domain Tok
	controlled pool: Powerset(Tok)
	controlled made: Integer
definitions:
	main rule r_Main =
		if made < 100 then
			extend Tok with $t do
				par
					pool := including(pool, $t)
					made := made + 1
				endpar
		endif
default init s0:
	function pool = {}
	function made = 0
"""


def test_derived_functions_declared_without_definition_run_native(tmp_path, capsys):
    code, out = both(tmp_path, capsys, DECLARED)
    assert code == 0
    assert (out["verdict"], out["states"], out["transitions"], out["depth"]) == ("no property checked", 15, 30, 5)


def test_a_hundred_elements_of_one_domain_run_native(tmp_path, capsys):
    code, out = both(tmp_path, capsys, HUNDRED)
    assert code == 0
    assert (out["verdict"], out["states"], out["transitions"], out["depth"]) == ("no property checked", 101, 101, 100)


@pytest.mark.parametrize("rel, states, transitions", [
    ("examples/Yahalom/Yahalom.asm", 322, 362),
    ("examples/Yahalom/FlawedYahalom.asm", 322, 362),
    ("examples/Yahalom/oldVersions/YahalomVerbose.asm", 74, 86),
])
def test_yahalom_runs_native_with_the_python_engines_report(rel, states, transitions, capsys):
    spec = need_asmeta() / "asm_examples" / rel
    outs = []
    for engine in ("native", "python"):
        code = main(["explore", str(spec), "--format", "json", "--engine", engine, "--max-depth", "13"])
        report = json.loads(capsys.readouterr().out)
        assert report["engine"] == engine
        outs.append((code, engine_free(report, engine)))
    assert outs[0] == outs[1]
    code, out = outs[0]
    # a step fails (an inconsistent update): the error property is violated
    assert (code, out["verdict"], out["states"], out["transitions"]) == (1, "violated", states, transitions)
    assert [v["property"] for v in out["violations"]] == ["error"]
