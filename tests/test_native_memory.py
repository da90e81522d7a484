"""The memory the native search takes: its tables grow with what they hold, and what they keep
is kept compactly, with the Python engine's states, counts and order all the same.

* The canonical forms kept for specs that extend domains (native_canon.c): a key as the bytes
  of its words that differ from the first key's, the result as the bytes that differ from the key.
* The packed store (native_bfs.c): a word's field takes the bits of four times the values its
  dictionary holds (not the next power of two), the fields packed into record words.

Engines: both (python is the reference, native is checked)."""
import ctypes
import os

import pytest

from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native import NativeExplorer
from asmcheck.explore.native_build import compiler
from asmcheck.semantics.machine import Machine
from asmcheck.semantics.resolve import check_file
from helpers import both, native_search, write

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


# ten Integer locations (a word each), each taking twenty values: a field of 6 bits each (room
# for 64 values; four times 9 values when it last grew), 60 bits in all: one record word (fields
# of the next power of two, 8 bits, took two)
FIELDS = """asm Fields

import StandardLibrary

signature:
	controlled t: Integer
	controlled a1: Integer
	controlled a2: Integer
	controlled a3: Integer
	controlled a4: Integer
	controlled a5: Integer
	controlled a6: Integer
	controlled a7: Integer
	controlled a8: Integer
	controlled a9: Integer

definitions:

	main rule r_main =
		choose $v in {0 : 19} with true do
			par
				t := $v
				a1 := (t + 1) mod 20
				a2 := (t + 2) mod 20
				a3 := (t + 3) mod 20
				a4 := (t + 4) mod 20
				a5 := (t + 5) mod 20
				a6 := (t + 6) mod 20
				a7 := (t + 7) mod 20
				a8 := (t + 8) mod 20
				a9 := (t + 9) mod 20
			endpar

default init s0:
	function t = 0
	function a1 = 0
	function a2 = 0
	function a3 = 0
	function a4 = 0
	function a5 = 0
	function a6 = 0
	function a7 = 0
	function a8 = 0
	function a9 = 0
"""


def test_fields_of_six_bits_pack_ten_words_into_one(tmp_path, capsys):
    path = write(tmp_path, FIELDS)
    r1, ex1, par1, st1 = native_search(path, packed=True)
    assert ex1.gen.nwords == 10 and ex1.dll.asm_packed_words() == 1
    r0, ex0, par0, st0 = native_search(path, packed=False)
    assert ex0.dll.asm_packed_words() == -1
    assert (r1.states, r1.transitions, r1.depth) == (r0.states, r0.transitions, r0.depth) == (401, 8020, 2)
    assert par1 == par0 and st1 == st0
    code, out = both(tmp_path, capsys, FIELDS)
    assert (code, out["states"], out["transitions"]) == (0, 401, 8020)
