"""The native explorer enumerates a choose as the Python engine does: one alternative per distinct
effect of its body (its update set), in the order first met, so that a choose over many candidates
with few effects (``choose $p in 1..100`` under a forall) costs the distinct effects, not the
product of the candidates.  Each small spec runs on both engines (pinned with --engine): the JSON
reports (states, transitions, depth, verdicts, traces) must be equal apart from the engine and
the times, and the native run must not fall back.

Engines: both (python is the reference, native is checked)."""
import pytest

from conftest import ASMETA
from helpers import both, write

pytestmark = pytest.mark.engines("native")


def summary(out):
    return out["verdict"], out["states"], out["transitions"], out["depth"]


# four places, each one busy leaves along a choose over 100 probabilities with two effects:
# 100^4 sequences of choices from the state where all are busy (the native engine refused more than
# 1,000,000 before), 2^4 once merged; the invariant breaks when all four are busy
LOTS = """\
asm Lots
import StandardLibrary
signature:
	domain Place subsetof Integer
	domain Prob subsetof Integer
	controlled busy: Place -> Boolean
	monitored arrive: Boolean
definitions:
	domain Place = {1 : 4}
	domain Prob = {1 : 100}
	rule r_leave($i in Place, $p in Prob) =
		if $p <= $i * 20 then busy($i) := false endif
	invariant inv_not_all over busy: not(busy(1) and busy(2) and busy(3) and busy(4))
	main rule r_Main =
		par
			if arrive then
				choose $i in Place with not(busy($i)) do busy($i) := true
			endif
			forall $j in Place with busy($j) do
				choose $p in Prob with true do r_leave[$j, $p]
		endpar
default init s0:
	function busy($i in Place) = false
"""

# a sibling makes the update one alternative makes too (f := 1): the alternatives are still two
# update sets ({f := 1} and {}), a third one changes g; the second choose's candidates depend on h
ABSORB = """\
asm Absorb
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled f: Small
	controlled g: Small
	controlled h: Small
definitions:
	domain Small = {0 : 3}
	main rule r_Main =
		par
			f := 1
			choose $p in Small with true do
				par
					if $p < 2 then f := 1 endif
					if $p = 3 then g := (g + 1) mod 4 endif
				endpar
			choose $q in Small with $q >= h do h := ($q + g) mod 4
		endpar
default init s0:
	function f = 0
	function g = 0
	function h = 0
"""

# the last choice points are merged chooses: their other combinations are written without running
# the step again, unless another update of the step touches what they update -- here f := 1 when
# g = 3, the same update as the first choose's first alternative (made once in the update buffer)
AFTER = """\
asm After
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled f: Small
	controlled g: Small
	controlled h: Small
definitions:
	domain Small = {0 : 3}
	main rule r_Main =
		par
			choose $p in Small with true do
				if $p < 2 then f := 1 else g := $p endif
			choose $q in Small with true do
				if $q = 0 then h := (h + 2) mod 4 endif
			if g = 3 then f := 1 endif
		endpar
default init s0:
	function f = 0
	function g = 0
	function h = 0
"""

# chooses inside a seq block read the working state (x already incremented), so their outcomes
# cannot be kept for the next run of the step: computed at every visit
IN_SEQ = """\
asm InSeq
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled x: Small
	controlled y: Small
	controlled z: Small
definitions:
	domain Small = {0 : 3}
	rule r_set($a in Small) =
		if $a > x then y := $a else y := x endif
	main rule r_Main =
		seq
			x := (x + 1) mod 4
			choose $a in Small with $a != z do r_set[$a]
			forall $b in Small with $b = y do
				choose $c in Small with true do
					if $c mod 2 = 0 then z := $b endif
		endseq
default init s0:
	function x = 0
	function y = 0
	function z = 0
"""

# one alternative clashes with a sibling's update (f := 2 and f := 3 when n = 2)
CLASH = """\
asm Clash
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled f: Small
	controlled n: Small
definitions:
	domain Small = {0 : 3}
	main rule r_Main =
		par
			n := (n + 1) mod 4
			if n = 2 then f := 2 endif
			choose $p in Small with true do
				if $p >= n then f := $p endif
		endpar
default init s0:
	function f = 0
	function n = 0
"""

# agents: the same choose in each agent's program; the outcomes are kept per agent (self)
AGENTS = """\
asm Agents
import StandardLibrary
signature:
	domain Id subsetof Integer
	domain Agt subsetof Agent
	domain Prob subsetof Integer
	controlled on: Agt -> Boolean
	controlled turns: Id
	static a1: Agt
	static a2: Agt
definitions:
	domain Id = {0 : 3}
	domain Prob = {1 : 50}
	rule r_flip($p in Prob) =
		if self = a1 then
			if $p > 25 then on(self) := not(on(self)) endif
		else
			if $p > 40 then on(self) := not(on(self)) endif
		endif
	rule r_prog =
		choose $p in Prob with true do r_flip[$p]
	main rule r_Main =
		par
			turns := (turns + 1) mod 4
			forall $a in Agt with true do program($a)
		endpar
default init s0:
	function on($a in Agt) = false
	function turns = 0
	agent Agt: r_prog[]
"""


def test_many_candidates_two_effects(tmp_path, capsys):
    code, out = both(tmp_path, capsys, LOTS)
    assert code == 1
    assert summary(out) == ("violated", 16, 189, 4)
    (v,) = out["violations"]
    assert v["property"] == "inv_not_all"
    # the shortest trace: a car arrives at each place in turn, the first place's choose (merged
    # to its first alternative, $p = 1: it leaves) not taken once it is busy
    assert [step.get("changed") for step in v["trace"][1:]] == [
        {"busy(1)": True}, {"busy(2)": True}, {"busy(3)": True}, {"busy(4)": True}]
    # each step names the first candidate of each effect taken
    assert v["trace"][2]["choices"][-1]["value"] == {"$p": 21}


def test_same_update_as_a_sibling(tmp_path, capsys):
    code, out = both(tmp_path, capsys, ABSORB, "--deadlock")
    assert code == 0
    assert summary(out) == ("holds", 17, 88, 3)


def test_an_update_after_the_last_choices(tmp_path, capsys):
    code, out = both(tmp_path, capsys, AFTER, "--deadlock")
    assert code == 0
    assert summary(out) == ("holds", 11, 54, 2)


def test_choose_in_seq(tmp_path, capsys):
    code, out = both(tmp_path, capsys, IN_SEQ, "--deadlock")
    assert code == 0
    assert summary(out) == ("holds", 40, 153, 5)


def test_agents_keep_their_outcomes_apart(tmp_path, capsys):
    code, out = both(tmp_path, capsys, AGENTS, "--deadlock")
    assert code == 0
    assert summary(out)[0] == "holds"
    assert summary(out)[1:] == (16, 64, 4)


def test_clash_with_a_sibling(tmp_path):
    """A step error in a merged alternative: the native search reports it at the state and with
    the message the Python engine gives, and explores the well-defined successors of the failing
    state as it does."""
    from asmcheck.explore.bfs import Explorer
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.explore.native_build import compiler
    from asmcheck.semantics.machine import Machine
    from asmcheck.semantics.resolve import check_file
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    m = Machine(check_file(write(tmp_path, CLASH)), {})
    found = []
    for E in (NativeExplorer, Explorer):
        r = E(m).run()
        found.append((r.verdict, [(v.prop.name, v.state, v.message) for v in r.violations]))
    assert found[0] == found[1] == ("violated", [("error", 5, "inconsistent update of f: 2 and 3")])


def test_parking_runs_native():
    """ASMETA's parking example: 15 places, each occupied one leaves along a choose over 100
    probabilities with two effects.  Every subset of free places is reached; from a state with k
    occupied places there are 2^k ways to leave, times 16 - k (no arrival, or one at each free
    place; one when none is free): 18 * 3^14 transitions."""
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.explore.native_build import compiler
    from asmcheck.semantics.machine import Machine
    from asmcheck.semantics.resolve import check_file
    path = ASMETA / "asm_examples/examples/parking.asm"
    if not path.exists():
        pytest.skip(f"the ASMETA corpus is not at {ASMETA}")
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    r = NativeExplorer(Machine(check_file(str(path)), {})).run()
    assert (r.verdict, r.states, r.transitions, r.depth) == ("holds", 2 ** 15, 18 * 3 ** 14, 15)
    assert r.transitions == 86_093_442
