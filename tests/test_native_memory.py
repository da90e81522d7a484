"""The memory the native search takes: its tables grow with what they hold, and what they keep
is kept compactly, with the Python engine's states, counts and order all the same.

* The canonical forms kept for specs that extend domains (native_canon.c): a key as the bytes
  of its words that differ from the first key's, the result as the bytes that differ from the key.

Engines: both (python is the reference, native is checked)."""
import ctypes
import os

import pytest

from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native import NativeExplorer
from asmcheck.explore.native_build import compiler
from asmcheck.semantics.machine import Machine
from asmcheck.semantics.resolve import check_file
from helpers import write

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

# accounts made by extend, whose balances take values that differ from each other in every byte
# (undef is the least 64-bit number, -2^62 and 2^40 are far from 5 and -1): the kept forms' keys
# and results differ from the first key in whole words, not in a byte or two
WIDE = """asm Wide

import StandardLibrary

signature:
	dynamic abstract domain Acc
	controlled bal: Acc -> Integer
	controlled made: Integer

definitions:

	main rule r_main =
		par
			if made < 4 then
				extend Acc with $a do
					made := made + 1
			endif
			if made >= 1 then
				choose $x in Acc with true do
					choose $v in {-1, 1099511627776, -4611686018427387904, 5} with bal($x) != $v do
						bal($x) := $v
			endif
		endpar

default init s0:
	function made = 0
"""


def explore_both(tmp_path, text):
    """Both explorers over ``text``: the states (as dicts, in discovery order) must be equal;
    the native search's counts and its canonical-form tables (asm_canon_stats)."""
    spec = check_file(write(tmp_path, text))
    py = Explorer(Machine(spec, {}))
    r_py = py.run()
    nat = NativeExplorer(Machine(spec, {}))
    try:
        r_nat = nat.run()
        assert [py.state(i) for i in range(py.n_states)] == [nat.state(i) for i in range(nat.n_states)]
        stats = (ctypes.c_int64 * 8)()
        nat.dll.asm_canon_stats(stats)
    finally:
        nat.close()
    assert (r_nat.states, r_nat.transitions, r_nat.depth) == (r_py.states, r_py.transitions, r_py.depth)
    return (r_nat.states, r_nat.transitions, r_nat.depth), list(stats)


@pytest.mark.parametrize("whole_keys", [False, True], ids=["bytes", "whole"])
def test_kept_canonical_forms_of_values_that_differ_in_every_byte(tmp_path, monkeypatch, whole_keys):
    # the same states in the same order as the Python engine, with the forms kept as the bytes
    # that differ (the default) or as whole keys (-DCN_NO_DIFF); the same forms are kept either
    # way, and as bytes they take less than half the whole keys' room
    flags = os.environ.get("ASMCHECK_CFLAGS") or "-O1"
    if whole_keys:
        monkeypatch.setenv("ASMCHECK_CFLAGS", flags + " -DCN_NO_DIFF")
    counts, stats = explore_both(tmp_path, WIDE)
    assert counts == (89, 705, 5)
    forms, used, allocated, key_words = stats[0], stats[1], stats[2], stats[7]
    assert forms == 423
    assert used <= allocated
    whole = key_words * 8           # a key's words whole
    if whole_keys:
        assert used >= (forms + 1) * whole
    else:
        assert 2 * used < forms * whole


def test_a_search_run_again_in_one_process_starts_from_a_zeroed_context(tmp_path):
    # the search's working context (native_bfs.c: mapped, not a static array, so that only the
    # pages a search writes become resident) is given back and reads as zeros at the next
    # asm_start: the same states, counts and order, run after run, on one thread and on two
    text = WIDE.replace("made < 4", "made < 3")
    spec = check_file(write(tmp_path, text))
    py = Explorer(Machine(spec, {}))
    r_py = py.run()
    want = [py.state(i) for i in range(py.n_states)]
    assert (r_py.states, r_py.transitions, r_py.depth) == (40, 269, 4)
    for workers in (1, 2):
        nat = NativeExplorer(Machine(spec, {}), workers=workers)
        try:
            for _ in range(3):
                r = nat.run()
                assert (r.states, r.transitions, r.depth) == (40, 269, 4)
                assert [nat.state(i) for i in range(nat.n_states)] == want
        finally:
            nat.close()
