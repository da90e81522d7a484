"""The native search does not evaluate a step property in a step that leaves it true by its form:
``[A implies] forall $x in D with G implies B`` (A and the quantifier over constant domains unable to
fail) where G is false because the step updated no location of the functions that its updated /
changed terms name (Generator.true_sets; native_bfs.c skip_of).  Each spec here is explored by
both engines (equal JSON reports): the properties where the shortcut must not hide anything -- the
step updates the location (also with the value it had), or a term evaluated before G fails.

Engines: both (python is the reference, native is checked)."""
import re

import pytest

from asmcheck.explore import native
from asmcheck.explore.native_build import compiler
from helpers import both, write

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

# t counts 0, 1, 2, 3, 0, ...; at t = 2 one a(i) (a monitored choice) moves on, at t = 3 b(1) is
# updated with the value it has
SPEC = """\
asm SkipStep
import StandardLibrary
signature:
	domain Id subsetof Integer
	domain Ctr subsetof Integer
	controlled a: Id -> Ctr
	controlled b: Id -> Ctr
	controlled g: Id -> Boolean
	controlled t: Ctr
	monitored which: Id
definitions:
	domain Id = {1 : 2}
	domain Ctr = {0 : 3}
	main rule r_Main =
		par
			t := (t + 1) mod 4
			if t = 2 then a(which) := (a(which) + 1) mod 4 endif
			if t = 3 then b(1) := b(1) endif
		endpar
default init s0:
	function a($i in Id) = 0
	function b($i in Id) = 0
	function t = 0
"""

PROPS = {
    # broken by the second update of a(1) or a(2) (to 2): the steps that update a are evaluated
    "p_updated": "(forall $i in Id with updated(a($i)) implies next(a($i)) != 2)",
    # broken by the first update of b(1), which does not change it
    "p_same_value": "(forall $i in Id with updated(b($i)) implies false)",
    # broken by the first update of a (with or, one set: both functions)
    "p_either": "(forall $i in Id with (updated(b($i)) or updated(a($i))) implies false)",
    # a and b are never updated in the same step (with and, two sets: either one)
    "p_both": "(forall $i in Id with (updated(b($i)) and updated(a($i))) implies false)",
    # b never changes
    "p_changed": "(forall $i in Id with changed(b($i)) implies false)",
    # the first conjunct fails (g undef: an undef condition) in every step, before updated(a(i))
    "p_first_fails": "(forall $i in Id with ((exists $j in Id with g($j)) and updated(a($i))) implies false)",
    # the antecedent fails in every step
    "p_antecedent_fails": "((exists $j in Id with g($j)) implies (forall $i in Id with updated(a($i)) implies false))",
}


def explore(tmp_path, capsys, name):
    props = tmp_path / f"{name}.prop"
    props.write_text(f"step {name}:\n\t{PROPS[name]}\n", encoding="utf-8")
    return both(tmp_path, capsys, SPEC, "--no-default-properties", "--properties", str(props))


def trace_length(report):
    (v,) = report["violations"]
    return len(v["trace"]) - 1


def test_a_step_that_updates_the_guard_location_is_evaluated(tmp_path, capsys):
    code, out = explore(tmp_path, capsys, "p_updated")
    assert code == 1
    assert (out["verdict"], out["states"], out["transitions"]) == ("violated", 13, 12)
    assert trace_length(out) == 7


def test_an_update_with_the_same_value_is_an_update(tmp_path, capsys):
    code, out = explore(tmp_path, capsys, "p_same_value")
    assert code == 1
    assert (out["verdict"], out["states"], out["transitions"]) == ("violated", 6, 5)
    assert trace_length(out) == 4


def test_an_or_of_updates_is_false_only_when_neither_is_updated(tmp_path, capsys):
    code, out = explore(tmp_path, capsys, "p_either")
    assert code == 1
    assert (out["verdict"], out["states"], out["transitions"]) == ("violated", 5, 4)
    assert trace_length(out) == 3


def test_an_and_of_updates_is_false_when_either_is_not_updated(tmp_path, capsys):
    code, out = explore(tmp_path, capsys, "p_both")
    assert code == 0
    assert (out["verdict"], out["states"], out["transitions"]) == ("holds", 64, 80)


def test_a_guard_on_locations_never_changed_holds(tmp_path, capsys):
    code, out = explore(tmp_path, capsys, "p_changed")
    assert code == 0
    assert (out["verdict"], out["states"], out["transitions"]) == ("holds", 64, 80)


@pytest.mark.parametrize("name", ["p_first_fails", "p_antecedent_fails"])
def test_a_failing_term_before_the_guard_is_reported_at_the_first_step(tmp_path, capsys, name):
    code, out = explore(tmp_path, capsys, name)
    assert code == 1
    assert (out["verdict"], out["states"], out["transitions"]) == ("violated", 2, 1)
    assert trace_length(out) == 1


def test_the_properties_the_generator_lets_the_search_skip(tmp_path, monkeypatch):
    """How many sets of slots each property gets (SKIP_SET_OFF): one, one, one (or: the union), two
    (and: either), one, and none where a term evaluated before the guard may fail."""
    import asmcheck
    sources = []
    real = native.build_library

    def keep(src):
        sources.append(src)
        return real(src)

    monkeypatch.setattr(native, "build_library", keep)
    props = tmp_path / "all.prop"
    props.write_text("".join(f"step {n}:\n\t{t}\n" for n, t in PROPS.items()), encoding="utf-8")
    res = asmcheck.load(write(tmp_path, SPEC), properties=[str(props)], default_properties=False).explore(engine="native")
    assert res.engine == "native"
    (src,) = [s for s in sources if "SKIP_SET_OFF" in s]
    assert re.search(r"SKIP_SET_OFF\[\] = \{([^}]*)\}", src).group(1) == "0, 1, 2, 3, 5, 6, 6, 6"
