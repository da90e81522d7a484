"""Symmetry reduction (``--symmetry``, ``explore(symmetry=True)``): which elements are
interchangeable and why not, the number of classes (checked against a full exploration whose
states are grouped into classes here, by trying every renaming), the verdicts (equal to the
full exploration's), concrete traces replayed through the step function, the refusals and
the hint of a search stopped by a limit."""
from __future__ import annotations

import json
from itertools import permutations

import pytest

import asmcheck
from asmcheck.explore.bfs import Explorer
from asmcheck.semantics.values import EnumValue

from conftest import ASMETA
from helpers import write

pytestmark = pytest.mark.engines("python")

# four interchangeable processes (no literal names one), three phases named by literals
MUTEX = """asm Mutex
import StandardLibrary
import CTLLibrary
import LTLLibrary
signature:
	enum domain Proc = {PA | PB | PC | PD}
	enum domain Phase = {IDLE | WAIT | CRIT}
	dynamic controlled st: Proc -> Phase
	dynamic controlled last: Proc
	derived busy: Boolean
definitions:
	function busy = (exists $q in Proc with st($q) = CRIT)
	invariant over st: not (exists $p in Proc, $q in Proc with $p != $q and st($p) = CRIT and st($q) = CRIT)
	CTLSPEC ag(ef((forall $p in Proc with st($p) = IDLE)))
	CTLSPEC ef((forall $p in Proc with st($p) = WAIT))
	CTLSPEC ag(not((forall $p in Proc with st($p) = WAIT)))
	LTLSPEC g(f(busy))
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

# a small tombola: numbers 1..8, a card of 2, 4 and 7 (literals), five numbers on no card
BINGO = """asm Bingo
import StandardLibrary
import CTLLibrary
signature:
	domain Num subsetof Integer
	dynamic controlled drawn: Num -> Boolean
	dynamic controlled hit: Num -> Boolean
	static card: Num -> Boolean
	derived full: Boolean
definitions:
	domain Num = {1 : 8}
	function card($n in Num) = $n = 2 or $n = 4 or $n = 7
	function full = hit(2) and hit(4) and hit(7)
	invariant over drawn: not(drawn(2) and drawn(7))
	CTLSPEC ef(full)
	CTLSPEC ag(not(full))
	main rule r_Main =
		if not(full) then
			choose $n in Num with not(drawn($n)) do
				par
					drawn($n) := true
					if card($n) then hit($n) := true endif
				endpar
		endif
default init s0:
	function drawn($n in Num) = false
	function hit($n in Num) = false
"""

# two interchangeable elements swap their flags at every step: the only successor of each
# state is another state of its class (no deadlock), while a search over classes sees a loop
SWAP = """asm Swap
import StandardLibrary
signature:
	enum domain Side = {LL | RR}
	dynamic controlled on: Side -> Boolean
	dynamic controlled started: Boolean
definitions:
	main rule r_Main =
		if not(started) then
			choose $s in Side with true do par on($s) := true started := true endpar
		else
			forall $s in Side do on($s) := not(on($s))
		endif
default init s0:
	function on($s in Side) = false
	function started = false
"""


def _perm_state(machine, st: dict, doms: dict, perm: dict) -> dict:
    """``st`` with elements renamed by ``perm`` at the positions the functions declare over
    ``doms`` (names of the domains): written here, apart from asmcheck.explore.symmetry."""
    out = {}
    funcs = machine.spec.functions
    for k, v in st.items():
        if type(k) is tuple and k[0] != "#dom":
            f = funcs[k[0]]
            args = tuple(perm.get(a, a) if getattr(f.domain[i], "name", None) in doms else a
                         for i, a in enumerate(k[1]))
            k = (k[0], args)
        else:
            f = funcs[k] if type(k) is int else None
        if f is not None and getattr(f.codomain, "name", None) in doms and v is not None:
            v = perm.get(v, v)
        out[k] = v
    return out


def _classes(machine, states: list, free: dict) -> list:
    """The class key of each state: the least text of the state over every renaming of the
    ``free`` elements (domain name -> elements)."""
    names = list(free)
    perms = [{}]
    for d in names:
        els = free[d]
        perms = [{**p, **dict(zip(els, q))} for p in perms for q in permutations(els)]
    keys = []
    for st in states:
        keys.append(min(repr(sorted((repr(k), repr(v)) for k, v in _perm_state(machine, st, set(names), p).items()))
                        for p in perms))
    return keys


def _full(model):
    ex = Explorer(model.machine, keep_graph=True)
    r = ex.run()
    assert r.verdict != "incomplete"
    states = [ex.state(i) for i in range(ex.n_states)]
    return ex, states


def _expected_counts(model, free):
    ex, states = _full(model)
    keys = _classes(model.machine, states, free)
    pairs = {(keys[a], keys[b]) for a, b, _ in ex.edges}
    return len(set(keys)), len(pairs), len(states), ex


def _enum(model, dom, names):
    d = next(x for x in model.spec.domains if x.name == dom)
    return [e for e in d.elements if e.name in names]


def _rows(run):
    return [(r["property"], r["verdict"]) for r in run.rows]


def test_mutex_classes_and_verdicts(tmp_path):
    model = asmcheck.load(write(tmp_path, MUTEX))
    free = {"Proc": _enum(model, "Proc", {"PA", "PB", "PC", "PD"})}
    classes, class_edges, states, _ = _expected_counts(model, free)
    assert (states, classes, class_edges) == (112, 17, 35)
    full = model.explore(engine="python", deadlock=True)
    red = model.explore(engine="python", deadlock=True, symmetry=True)
    assert (full.states, full.transitions) == (112, 428)
    assert (red.states, red.transitions) == (classes, class_edges)
    assert _rows(red) == _rows(full) == [
        ("invariant_1", "holds"), ("deadlock", "holds"), ("ctl_1", "holds"), ("ctl_2", "holds"),
        ("ctl_3", "violated"), ("ltl_1", "holds"), ("ltl_2", "violated")]
    assert red.symmetry_lines() == [
        "symmetry: states and transitions are counted up to the symmetry of Proc's 4 unnamed elements",
        "  symmetry: Proc: 4 of its 4 elements are interchangeable",
        "  symmetry: Phase: no symmetry: every one of its 3 elements is named by a literal"]
    assert red.engine == "python" and red.engine_note == ""
    assert full.symmetry is None and full.symmetry_lines() == []


def _check_concrete(model, trace):
    """Each state of ``trace`` is the real initial state or a successor of the state before, as
    the step function makes it; returns the states."""
    m = model.machine
    sts = [s.state for s in trace.raw.steps]
    assert any(sts[0] == st for _, st in m.initial_states())
    for a, b in zip(sts, sts[1:]):
        assert any(nxt == b for _, _, nxt, _ in m.successors(a)), (a, b)
    return sts


def test_mutex_temporal_counterexamples_are_concrete(tmp_path):
    model = asmcheck.load(write(tmp_path, MUTEX))
    red = model.explore(engine="python", symmetry=True)
    full = model.explore(engine="python")
    by_name = {v.property: v for v in red.violations}
    full_by_name = {v.property: v for v in full.violations}
    assert sorted(by_name) == sorted(full_by_name) == ["ctl_3", "ltl_2"]
    for name in ("ctl_3", "ltl_2"):
        sts = _check_concrete(model, by_name[name].trace)
        assert len(sts) == len(full_by_name[name].trace.raw.steps)
    # ctl_3's counterexample reaches a state where every process waits
    last = by_name["ctl_3"].trace.raw.steps[-1].state
    wait = next(e for e in _enum(model, "Phase", {"WAIT"}))
    assert sorted(v.name for k, v in last.items() if type(k) is tuple) == ["WAIT"] * 4
    assert all(v is wait for k, v in last.items() if type(k) is tuple)


def test_bingo_integer_subset(tmp_path):
    model = asmcheck.load(write(tmp_path, BINGO))
    free = {"Num": [1, 3, 5, 6, 8]}
    classes, class_edges, states, _ = _expected_counts(model, free)
    assert (states, classes, class_edges) == (256, 48, 113)
    full = model.explore(engine="python", deadlock=True)
    red = model.explore(engine="python", deadlock=True, symmetry=True)
    assert (red.states, red.transitions) == (classes, class_edges)
    assert _rows(red) == _rows(full) == [("invariant_1", "violated"), ("deadlock", "violated"),
                                         ("ctl_1", "holds"), ("ctl_2", "violated")]
    assert red.symmetry_lines()[:2] == [
        "symmetry: states and transitions are counted up to the symmetry of Num's 5 unnamed elements",
        "  symmetry: Num: 5 of its 8 elements are interchangeable (named: 2, 4, 7)"]
    doc = red.json()
    assert doc["symmetry"] == {"reduced": True, "counts": "classes",
                               "domains": [{"domain": "Num", "interchangeable": 5, "elements": 8}],
                               "explain": ["Num: 5 of its 8 elements are interchangeable (named: 2, 4, 7)"]}
    assert "symmetry" not in full.json()


def test_bingo_traces_replay_from_the_real_initial_state(tmp_path):
    model = asmcheck.load(write(tmp_path, BINGO))
    red = model.explore(engine="python", deadlock=True, symmetry=True)
    full = model.explore(engine="python", deadlock=True)
    for v, w in zip(red.violations, full.violations):
        assert v.property == w.property
        sts = _check_concrete(model, v.trace)
        # shortest traces: as long as the full exploration's
        assert len(sts) == len(w.trace.raw.steps)
    inv = next(v for v in red.violations if v.property == "invariant_1")
    last = inv.trace.raw.steps[-1].state
    drawn = next(f.index for f in model.spec.functions if f.name == "drawn")
    assert last[(drawn, (2,))] is True and last[(drawn, (7,))] is True
    # the deadlock: a full card (4 steps: 2, 4 and 7 come out, with one number before them or not)
    dl = next(v for v in red.violations if v.property == "deadlock")
    hit = next(f.index for f in model.spec.functions if f.name == "hit")
    end = dl.trace.raw.steps[-1].state
    assert all(end[(hit, (n,))] for n in (2, 4, 7))
    assert len(dl.trace.raw.steps) == 4


def test_a_successor_in_the_same_class_is_no_deadlock(tmp_path):
    model = asmcheck.load(write(tmp_path, SWAP))
    full = model.explore(engine="python", deadlock=True)
    red = model.explore(engine="python", deadlock=True, symmetry=True)
    assert (full.states, full.transitions) == (3, 4)
    assert (red.states, red.transitions) == (2, 2)
    assert _rows(red) == _rows(full) == [("deadlock", "holds")]
    assert red.symmetry_lines()[1] == "  symmetry: Side: 2 of its 2 elements are interchangeable"


REFUSED = [
    # (what the rule does besides drawing $n, the explanation line of Num)
    ("x := $n + 1", "Num: no symmetry: a value of Num is an argument of + (line 11, column 60)"),
    ("if $n < 3 then x := 1 endif", "Num: no symmetry: a value of Num is an argument of < (line 11, column 58)"),
    ("drawn(x) := true", "Num: no symmetry: a value of Integer is used where Num is expected (an argument of drawn) "
                         "(line 11, column 61)"),
    ("if $n = 1 or $n = 2 or $n = 3 then x := 1 endif",
     "Num: no symmetry: only one of its 4 elements is named by no literal"),
    ("if $n = x then x := 1 endif", "Num: no symmetry: a value of Num is compared with a value of Integer "
                                    "(line 11, column 58)"),
]


@pytest.mark.parametrize("rule,line", REFUSED)
def test_refusal_reasons(tmp_path, rule, line):
    spec = f"""asm Refused
import StandardLibrary
signature:
	domain Num subsetof Integer
	dynamic controlled drawn: Num -> Boolean
	dynamic controlled x: Integer
	dynamic controlled nxt: Num -> Num
definitions:
	domain Num = {{1 : 4}}
	main rule r_Main =
		choose $n in Num with true do par drawn($n) := true {rule} endpar
default init s0:
	function drawn($n in Num) = false
	function x = 0
"""
    model = asmcheck.load(write(tmp_path, spec))
    red = model.explore(engine="python", symmetry=True)
    full = model.explore(engine="python")
    assert (red.states, red.transitions) == (full.states, full.transitions)
    assert red.symmetry_lines() == ["symmetry: no reduction (no domain has interchangeable elements)",
                                    "  symmetry: " + line]
    assert red.engine_note != "symmetry reduction (--symmetry) runs on the Python engine"


def test_a_literal_in_a_property_file_names_an_element(tmp_path):
    model = asmcheck.load(write(tmp_path, BINGO))
    p = tmp_path / "bingo.prop"
    p.write_text("applies to Bingo\ninvariant three_late: not(drawn(3) and not(drawn(2)))\n", encoding="utf-8")
    sym = _detect(model)
    assert [d.describe() for d in sym.domains] == ["Num's 5 unnamed elements"]
    model2 = asmcheck.load(str(tmp_path / "Bingo.asm"), properties=[str(p)])
    assert "three_late" in [q.name for q in model2.state_props]
    sym2 = _detect(model2)
    assert [d.describe() for d in sym2.domains] == ["Num's 4 unnamed elements"]


def _detect(model):
    from asmcheck.explore.symmetry import detect
    return detect(model.machine, list(model.state_props) + list(model.step_props) + list(model.temporal))


def test_a_limit_names_the_flag(tmp_path):
    model = asmcheck.load(write(tmp_path, BINGO))
    run = model.explore(engine="python", max_states=10)
    assert run.verdict in ("incomplete", "violated")
    assert run.symmetry_hint == ("hint: Num's 5 unnamed elements are interchangeable; --symmetry explores one "
                                 "state per class of such states")
    assert run.json()["hint"] == run.symmetry_hint
    done = model.explore(engine="python")
    assert done.symmetry_hint == "" and "hint" not in done.json()


def test_which_engine_reduces(tmp_path, monkeypatch):
    """The native engine reduces what its canonical form orders (its tests are in
    test_symmetry_native.py); a String location over the symmetric domain stays on the Python
    engine, with the reason."""
    model = asmcheck.load(write(tmp_path, BINGO))
    with pytest.raises(asmcheck.UsageError, match="^--symmetry runs in one process \\(or on the native engine's "
                                                  "threads, --workers N\\): it cannot be combined with --cluster, "
                                                  "--bitstate or the Python engine's workers$"):
        model.explore(engine="python", symmetry=True, workers=2)
    with pytest.raises(asmcheck.UsageError, match="^symmetry must be True or False, not 'yes'$"):
        model.explore(engine="python", symmetry="yes")
    monkeypatch.delenv("ASMCHECK_ENGINE", raising=False)
    run = model.explore(engine="auto", symmetry=True)
    assert run.engine == "native" and (run.states, run.transitions) == (48, 113)
    names = asmcheck.load(write(tmp_path, NAMES))
    why = "--symmetry: tag over P holds values of String, which the native canonical form does not order"
    with pytest.raises(asmcheck.UsageError, match="^the native explorer cannot run Names.asm: " + why + "$"):
        names.explore(engine="native", symmetry=True)
    run = names.explore(engine="auto", symmetry=True)
    assert run.engine == "python" and (run.states, run.transitions) == (10, 13)
    assert run.engine_note == why
    assert run.json()["engine_note"] == "native engine not used: " + why


# a name per process: a String location over the symmetric domain
NAMES = """asm Names
import StandardLibrary
signature:
	enum domain P = {PA | PB | PC}
	dynamic controlled tag: P -> String
definitions:
	main rule r_Main =
		choose $p in P with tag($p) != "bb" do
			if tag($p) = "a" then tag($p) := "bb" else tag($p) := "a" endif
default init s0:
	function tag($p in P) = ""
"""


def test_cli(tmp_path, capsys):
    from asmcheck.cli import main
    path = write(tmp_path, BINGO)
    code = main(["explore", "--symmetry", "--engine", "python", path])
    text = capsys.readouterr().out
    assert code == 1
    lines = text.splitlines()
    assert lines[0].startswith("Bingo.asm: 48 states, 113 transitions, depth 8, ")
    assert lines[1] == "symmetry: states and transitions are counted up to the symmetry of Num's 5 unnamed elements"
    code = main(["explore", "--symmetry", "--engine", "python", "--format", "json", path])
    doc = json.loads(capsys.readouterr().out)
    assert (doc["states"], doc["transitions"], doc["symmetry"]["reduced"]) == (48, 113, True)
    code = main(["explore", "--max-states", "5", "--engine", "python", path])
    text = capsys.readouterr().out
    assert "hint: Num's 5 unnamed elements are interchangeable; --symmetry explores one state per class of such " \
           "states" in text.splitlines()


def test_check_cli(tmp_path, capsys):
    from asmcheck.cli import main
    path = write(tmp_path, MUTEX)
    code = main(["check", "--symmetry", "--engine", "python", path])
    lines = capsys.readouterr().out.splitlines()
    assert code == 1        # ctl_3 and ltl_2 are violated
    rows = [ln.split() for ln in lines if ln.startswith(path)]
    assert [(r[1], r[2], r[3]) for r in rows] == [
        ("invariant_1", "holds", "17"), ("ctl_1", "holds", "17"), ("ctl_2", "holds", "17"),
        ("ctl_3", "VIOLATED", "17"), ("ltl_1", "holds", "17"), ("ltl_2", "VIOLATED", "17")]
    assert lines[-1] == f"symmetry: the states of {path} are counted up to the symmetry of Proc's 4 unnamed elements"
    main(["check", "--engine", "python", path])
    plain = capsys.readouterr().out
    assert "symmetry" not in plain and " 112 " in plain
    main(["check", "--engine", "python", "--max-states", "20", path])
    assert capsys.readouterr().out.splitlines()[-1] == (
        f"{path}: hint: Proc's 4 unnamed elements are interchangeable; --symmetry explores one state per class of "
        f"such states")


# a property quantified around a temporal operator is checked once per process, each time with
# atoms that name it: no symmetry (the reduced search would give ctl_1 violated here)
PER_JOB = """asm PerJob
import StandardLibrary
import CTLLibrary
signature:
	enum domain Job = {JA | JB | JC}
	enum domain Status = {RDY | RUN | FIN}
	controlled st: Job -> Status
	monitored fin: Job -> Boolean
definitions:
	INVAR (forall $j in Job with fin($j) implies st($j) = RUN)
	CTLSPEC (forall $j in Job with ag(fin($j) implies ax(st($j) = FIN)))
	CTLSPEC ef((forall $j in Job with st($j) = FIN))
	main rule r_Main =
		par
			choose $j1 in Job with st($j1) = RDY do st($j1) := RUN
			forall $j2 in Job with st($j2) = RUN do if fin($j2) then st($j2) := FIN endif
		endpar
default init s0:
	function st($j in Job) = RDY
"""


def test_a_quantifier_around_a_temporal_operator(tmp_path):
    model = asmcheck.load(write(tmp_path, PER_JOB))
    red = model.explore(engine="python", symmetry=True)
    full = model.explore(engine="python")
    assert (red.states, red.transitions) == (full.states, full.transitions) == (21, 66)
    assert _rows(red) == _rows(full) == [("ctl_1", "holds"), ("ctl_2", "holds")]
    assert red.symmetry_lines() == [
        "symmetry: no reduction (no domain has interchangeable elements)",
        "  symmetry: Job: no symmetry: a property binds a variable of Job around a temporal operator "
        "(line 11, column 10)",
        "  symmetry: Status: no symmetry: every one of its 3 elements is named by a literal"]


def test_fairness_keeps_every_state(tmp_path):
    model = asmcheck.load(write(tmp_path, MUTEX))
    red = model.explore(engine="python", symmetry=True, fair=["all"])
    assert (red.states, red.transitions) == (112, 428)
    assert red.symmetry_lines() == [
        "symmetry: no reduction (--fair makes each agent or choice fair on its own, which a class of states "
        "does not keep)",
        "  symmetry: --fair makes each agent or choice fair on its own, which a class of states does not keep"]


@pytest.mark.parametrize("text,free", [(MUTEX, {"Proc": ("PA", "PB", "PC", "PD")}), (BINGO, {"Num": (1, 3, 5, 6, 8)})],
                         ids=["mutex", "bingo"])
def test_the_canonical_form_is_one_per_class(tmp_path, text, free):
    """Over every state of the full exploration and every renaming of the interchangeable
    elements: the canonical form of the renamed state is the state's own, and the form worked
    out from a parent (canon_from) is the one worked out from scratch."""
    model = asmcheck.load(write(tmp_path, text))
    sym = _detect(model)
    (dom, names), = free.items()
    els = _enum(model, dom, set(names)) if isinstance(names[0], str) else list(names)
    assert [d.free for d in sym.domains] == [els]
    ex, states = _full(model)
    m = model.machine
    forms = set()
    for st in states:
        rep, perm = sym.canon(st)
        assert sym.apply(st, perm) == rep
        forms.add(repr(sorted((repr(k), repr(v)) for k, v in rep.items())))
        for q in permutations(els):
            image = _perm_state(m, st, {dom}, dict(zip(els, q)))
            assert sym.canon(image)[0] == rep
        for _, _, nxt, _ in m.successors(st):
            assert sym.canon_from(st, nxt) == sym.canon(nxt)
    keys = _classes(m, states, {dom: els})
    assert len(forms) == len(set(keys))


# an abstract domain: its elements are its static constants; boss is used (named), the three
# others are not
PHILS = """asm Phils
import StandardLibrary
signature:
	abstract domain Phil
	enum domain PState = {THINK | HUNGRY | EAT}
	dynamic controlled ps: Phil -> PState
	static ph1: Phil
	static ph2: Phil
	static ph3: Phil
	static boss: Phil
definitions:
	invariant over ps: not(ps(boss) = EAT and (exists $p in Phil with $p != boss and ps($p) = EAT))
	main rule r_Main =
		choose $p in Phil with true do
			switch ps($p)
				case THINK: ps($p) := HUNGRY
				case HUNGRY: ps($p) := EAT
				case EAT: ps($p) := THINK
			endswitch
default init s0:
	function ps($p in Phil) = THINK
"""


def test_an_abstract_domain(tmp_path):
    model = asmcheck.load(write(tmp_path, PHILS))
    els = [e for e in next(v for d, v in model.machine.static_elements.items() if d.name == "Phil")
           if e.name != "boss"]
    assert [e.name for e in els] == ["ph1", "ph2", "ph3"]
    classes, class_edges, states, _ = _expected_counts(model, {"Phil": els})
    assert (states, classes, class_edges) == (81, 30, 84)
    full = model.explore(engine="python", deadlock=True)
    red = model.explore(engine="python", deadlock=True, symmetry=True)
    assert (red.states, red.transitions) == (30, 84)
    assert _rows(red) == _rows(full) == [("invariant_1", "violated"), ("deadlock", "holds")]
    assert red.symmetry_lines()[1] == "  symmetry: Phil: 3 of its 4 elements are interchangeable (named: boss)"
    (v,) = red.violations
    sts = _check_concrete(model, v.trace)
    assert len(sts) == len(full.violations[0].trace.raw.steps) == 5


# a function and a relation over the nodes: several positions over one symmetric domain
LINK = """asm Link
import StandardLibrary
import CTLLibrary
signature:
	enum domain Node = {NA | NB | NC | ND}
	dynamic controlled link: Node -> Node
	dynamic controlled edge: Prod(Node, Node) -> Boolean
definitions:
	invariant over link: (forall $a in Node with isUndef(link($a)) or link($a) != $a)
	CTLSPEC ef((forall $a in Node with isDef(link($a))))
	CTLSPEC ag((exists $a in Node with not(edge($a, $a))))
	CTLSPEC ag(not((exists $a in Node, $b in Node with link($a) = $b and link($b) = $a)))
	main rule r_Main =
		choose $a in Node, $b in Node with $a != $b and isUndef(link($a)) do
			par
				link($a) := $b
				edge($b, $a) := true
			endpar
default init s0:
	function edge($a in Node, $b in Node) = false
"""


def test_several_positions_over_one_domain(tmp_path):
    model = asmcheck.load(write(tmp_path, LINK))
    free = {"Node": _enum(model, "Node", {"NA", "NB", "NC", "ND"})}
    classes, class_edges, states, _ = _expected_counts(model, free)
    assert (states, classes, class_edges) == (256, 19, 40)
    full = model.explore(engine="python", deadlock=True)
    red = model.explore(engine="python", deadlock=True, symmetry=True)
    assert (red.states, red.transitions) == (19, 40)
    assert _rows(red) == _rows(full) == [("invariant_1", "holds"), ("deadlock", "violated"), ("ctl_1", "holds"),
                                         ("ctl_2", "holds"), ("ctl_3", "violated")]
    for v, w in zip(red.violations, full.violations):
        assert len(_check_concrete(model, v.trace)) == len(w.trace.raw.steps)
    # one form per class, over every renaming
    sym = _detect(model)
    ex, sts = _full(model)
    els = free["Node"]
    for st in sts:
        rep = sym.canon(st)[0]
        for q in permutations(els):
            assert sym.canon(_perm_state(model.machine, st, {"Node"}, dict(zip(els, q))))[0] == rep


def test_several_positions_over_a_large_domain(tmp_path):
    spec = """asm Ring
import StandardLibrary
signature:
	domain Pos subsetof Integer
	dynamic controlled nxt: Pos -> Pos
definitions:
	domain Pos = {1 : 7}
	main rule r_Main = choose $a in Pos, $b in Pos with isUndef(nxt($a)) do nxt($a) := $b
"""
    model = asmcheck.load(write(tmp_path, spec))
    red = model.explore(engine="python", symmetry=True, max_states=50)
    assert red.symmetry_lines() == [
        "symmetry: no reduction (no domain has interchangeable elements)",
        "  symmetry: Pos: no symmetry: nxt has several positions over Pos, and Pos has 7 interchangeable elements "
        "(the exact canonical form of such a function tries up to 7! renamings; at most 720 are tried) "
        "(line 5, column 21)"]


def _corpus(rel):
    path = ASMETA / rel
    if not path.exists():
        pytest.skip(f"the ASMETA corpus is not at {ASMETA}")
    return asmcheck.load(str(path))


def test_battleship_against_nusmv():
    """battleship.asm: the columns 1 and 4 are interchangeable (2 and 3 are named); its board
    functions have two positions over Coord.  NuSMV: true, true, true, true."""
    model = _corpus("asm_examples/examples/battleship.asm")
    red = model.explore(engine="python", symmetry=True)
    assert (red.states, red.transitions) == (296, 832)
    assert _rows(red) == [("ctl_1", "holds"), ("ctl_2", "holds"), ("ctl_3", "holds"), ("ctl_4", "holds")]
    assert red.symmetry_lines()[:2] == [
        "symmetry: states and transitions are counted up to the symmetry of Coord's 2 unnamed elements",
        "  symmetry: Coord: 2 of its 4 elements are interchangeable (named: 2, 3)"]
    classes, class_edges, states, _ = _expected_counts(model, {"Coord": [1, 4]})
    assert (states, classes, class_edges) == (480, 296, 832)


@pytest.mark.slow
def test_tombola_against_nusmv():
    """tombola.asm: about 10^9 states; 21 of its 30 numbers are on no card and in no property.
    NuSMV: EF true, EG true, AG false."""
    model = _corpus("asm_examples/examples/tombola.asm")
    red = model.explore(engine="python", symmetry=True, deadlock=True)
    assert (red.states, red.transitions, red.depth) == (11_264, 60_063, 30)
    assert _rows(red) == [("deadlock", "violated"), ("ctl_1", "holds"), ("ctl_2", "holds"), ("ctl_3", "violated")]
    assert red.symmetry_lines()[1] == ("  symmetry: Numero: 21 of its 30 elements are interchangeable "
                                       "(named: 1, 2, 5, 7, 12, 14, 18, 25, 26)")
    ctl3 = next(v for v in red.violations if v.property == "ctl_3")
    sts = _check_concrete(model, ctl3.trace)
    assert len(sts) == 10       # the ten numbers of the two cards, drawn one by one
