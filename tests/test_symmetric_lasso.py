"""A lasso found under symmetry reduction goes back to its loop's first state up to a renaming of
the interchangeable elements: the text, the gate and the HTML say so (not "the elements made by
extend", which the spec has none of)."""
from __future__ import annotations

import pytest

import asmcheck
from asmcheck.cli import main

pytestmark = pytest.mark.engines("python")

# last remembers who entered: the lasso under symmetry comes back to its loop state with PB and
# PC swapped
MUTEX = """asm Mutex
import StandardLibrary
import LTLLibrary
signature:
	enum domain Proc = {PA | PB | PC}
	enum domain Phase = {IDLE | WAIT | CRIT}
	dynamic controlled st: Proc -> Phase
	dynamic controlled last: Proc
	derived busy: Boolean
definitions:
	function busy = (exists $q in Proc with st($q) = CRIT)
	LTLSPEC g(busy implies x(busy))
	main rule r_Main =
		choose $p in Proc with true do
			if st($p) = IDLE then
				st($p) := WAIT
			else if st($p) = WAIT and not(busy) then
				par
					st($p) := CRIT
					last := $p
				endpar
			else if st($p) = CRIT then
				st($p) := IDLE
			endif endif endif
default init s0:
	function st($p in Proc) = IDLE
"""

NOTE = "(up to the symmetry of Proc's 3 unnamed elements)"


def test_the_lasso_says_it_returns_up_to_the_symmetry(write_spec, capsys):
    path = write_spec(MUTEX, "Mutex")
    run = asmcheck.load(path).explore(symmetry=True)
    assert (run.states, run.transitions, run.verdict) == (13, 25, "violated")
    assert main(["explore", path, "--symmetry"]) == 1
    out = capsys.readouterr().out
    lines = [ln for ln in out.splitlines() if "<-" in ln]
    assert lines == ["  step 4: r_Main chooses $p = PB  <- the loop starts here (state 4)",
                     "  step 7: r_Main chooses $p = PB  <- back to state 4 " + NOTE]
    assert "made by extend" not in out


def test_the_gate_and_the_html_say_it_too(write_spec, tmp_path, capsys):
    path = write_spec(MUTEX, "Mutex")
    html = tmp_path / "gate.html"
    assert main(["check", path, "--symmetry", "--html", str(html)]) == 1
    out = capsys.readouterr().out
    assert "<- back to state 4 " + NOTE in out
    assert "state 7 is state 4 again (up to the symmetry of Proc&#x27;s 3 unnamed elements)" in html.read_text()


def test_a_lasso_back_to_the_same_concrete_state_has_no_note(write_spec, capsys):
    """Without symmetry the lasso goes back to the very state its loop starts at: no note."""
    path = write_spec(MUTEX, "Mutex")
    assert main(["explore", path, "--engine", "python"]) == 1
    out = capsys.readouterr().out
    lines = [ln for ln in out.splitlines() if "<-" in ln]
    assert lines == ["  step 4: r_Main chooses $p = PA  <- the loop starts here (state 4)",
                     "  step 7: r_Main chooses $p = PA  <- back to state 4"]


def test_the_json_names_the_symmetry_of_the_lasso(write_spec, capsys):
    import json
    from test_report_formats import validator
    path = write_spec(MUTEX, "Mutex")
    assert main(["explore", path, "--symmetry", "--format", "json"]) == 1
    (v,) = json.loads(capsys.readouterr().out)["violations"]
    assert (v["loop_start"], v["loop_up_to"]) == (4, "the symmetry of Proc's 3 unnamed elements")
    validator("trace").validate(v)
    assert main(["explore", path, "--format", "json", "--engine", "python"]) == 1
    (v,) = json.loads(capsys.readouterr().out)["violations"]
    assert v["loop_start"] == 4 and "loop_up_to" not in v
