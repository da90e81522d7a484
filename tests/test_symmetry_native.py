"""Symmetry reduction on the native engine (``--symmetry``, native_sym.c): the same classes,
transitions, verdicts and concrete traces as the Python engine's symmetric run (the whole JSON
report but the timings and the engine's name), since both store the same representative of
each class; every state the native search stores is its own Python canonical form.  What the
native canonical form does not handle (a function with several positions over a symmetric
domain) stays on the Python engine, with the reason.  A differential over the corpus specs that
get a symmetry compares the two engines' symmetric runs.

Engines: native (each case is compared with the Python engine's run, the reference)."""
from __future__ import annotations

import json
import sys

import pytest

import asmcheck
from asmcheck.explore.symmetry import detect

from conftest import ASMETA
from helpers import write
from test_symmetry import BINGO, LINK, MUTEX, NAMES, PHILS, SWAP, _check_concrete, _rows

pytestmark = pytest.mark.engines("native")

IGNORED_KEYS = ("seconds", "engine", "compile_seconds", "engine_note")


def _json(run) -> dict:
    return {k: v for k, v in run.json().items() if k not in IGNORED_KEYS}


def _both(model, **kw):
    """(native run, Python run) of the symmetric search, the same options."""
    nat = model.explore(engine="native", symmetry=True, **kw)
    py = model.explore(engine="python", symmetry=True, **kw)
    assert nat.engine == "native" and py.engine == "python"
    return nat, py


def _stored_canonical(run, model):
    """Every state the native search stored is the Python canonical form of itself."""
    ex = run.explorer
    sym = detect(model.machine, list(model.state_props) + list(model.step_props) + list(model.temporal))
    for sid in range(ex.n_states):
        st = ex.state(sid)
        assert sym.canon(st)[0] == st, sid


# two symmetric domains, a relation over both (several positions), a function from one to the
# other, a value of one stored, locations made undef again: 7,129 states, 653 classes
MIX = """asm Mix
import StandardLibrary
import CTLLibrary
signature:
	enum domain Ag = {AA | AB | AC}
	enum domain Res = {RX | RY}
	dynamic controlled rel: Prod(Ag, Res) -> Boolean
	dynamic controlled owner: Res -> Ag
	dynamic controlled mark: Ag -> Boolean
	dynamic controlled lastA: Ag
definitions:
	CTLSPEC ef((forall $r in Res with isDef(owner($r))))
	CTLSPEC ag(not((exists $a in Ag with mark($a) and lastA = $a)))
	main rule r_Main =
		choose $a in Ag, $r in Res with true do
			if rel($a, $r) then
				par
					rel($a, $r) := false
					owner($r) := undef
					mark($a) := not(mark($a))
				endpar
			else
				par
					rel($a, $r) := true
					owner($r) := $a
					lastA := $a
				endpar
			endif
default init s0:
	function rel($a in Ag, $r in Res) = false
	function mark($a in Ag) = false
"""

# a counter per process (Integer locations over the symmetric domain, made undef again), a flag and
# the last process: the native form orders the counters' entries by their integers
COUNTERS = """asm Counters
import StandardLibrary
import CTLLibrary
signature:
	enum domain P = {PA | PB | PC | PD}
	dynamic controlled cnt: P -> Integer
	dynamic controlled flag: P -> Boolean
	dynamic controlled who: P
definitions:
	CTLSPEC ef((forall $p in P with cnt($p) = 2))
	main rule r_Main =
		choose $p in P with isUndef(cnt($p)) or cnt($p) < 3 do
			par
				if isUndef(cnt($p)) then cnt($p) := 0 else if cnt($p) < 2 then cnt($p) := cnt($p) + 1
				else cnt($p) := undef endif endif
				flag($p) := not(flag($p))
				who := $p
			endpar
default init s0:
	function cnt($p in P) = 0
	function flag($p in P) = false
"""

# six interchangeable switches: some are turned on one by one, then all flip at every step; a
# state with three on flips into another state of its class (moved, so no deadlock)
FLIP = """asm Flip
import StandardLibrary
signature:
	enum domain S = {SA | SB | SC | SD | SE | SF}
	dynamic controlled on: S -> Boolean
	dynamic controlled phase: Boolean
definitions:
	main rule r_Main =
		if phase then
			forall $s in S do on($s) := not(on($s))
		else
			choose $b in Boolean with true do
				if $b then phase := true
				else choose $s in S with not(on($s)) do on($s) := true endif
		endif
default init s0:
	function on($s in S) = false
	function phase = false
"""

CASES = [
    # (spec, classes, transitions, rows with --deadlock)
    (MUTEX, 17, 35, [("invariant_1", "holds"), ("deadlock", "holds"), ("ctl_1", "holds"), ("ctl_2", "holds"),
                     ("ctl_3", "violated"), ("ltl_1", "holds"), ("ltl_2", "violated")]),
    (BINGO, 48, 113, [("invariant_1", "violated"), ("deadlock", "violated"), ("ctl_1", "holds"),
                      ("ctl_2", "violated")]),
    (PHILS, 30, 84, [("invariant_1", "violated"), ("deadlock", "holds")]),
    (SWAP, 2, 2, [("deadlock", "holds")]),
    (LINK, 19, 40, [("invariant_1", "holds"), ("deadlock", "violated"), ("ctl_1", "holds"), ("ctl_2", "holds"),
                    ("ctl_3", "violated")]),
    (MIX, 653, 3495, [("deadlock", "holds"), ("ctl_1", "holds"), ("ctl_2", "violated")]),
    (COUNTERS, 81, 201, [("deadlock", "holds"), ("ctl_1", "holds")]),
    (FLIP, 14, 21, [("deadlock", "holds")]),
]


@pytest.mark.parametrize("fast", [True, False], ids=["one-number", "rank-lists"])
@pytest.mark.parametrize("text,classes,transitions,rows", CASES, ids=["Mutex", "Bingo", "Phils", "Swap", "Link", "Mix",
                                                                          "Counters", "Flip"])
def test_the_same_classes_verdicts_and_traces_as_the_python_engine(tmp_path, monkeypatch, text, classes, transitions,
                                                                    rows, fast):
    """Both ways native_sym.c compares signatures (one 64-bit number an element, or its list of
    ranks) give the Python engine's representatives."""
    from asmcheck.explore import symmetry
    monkeypatch.setattr(symmetry, "NATIVE_FAST", fast)
    model = asmcheck.load(write(tmp_path, text))
    nat, py = _both(model, deadlock=True)
    assert (nat.states, nat.transitions) == (py.states, py.transitions) == (classes, transitions)
    assert _rows(nat) == _rows(py) == rows
    assert _json(nat) == _json(py)
    assert nat.symmetry_lines() == py.symmetry_lines()
    for v in nat.violations:
        if v.trace is not None and v.trace.raw is not None:
            _check_concrete(model, v.trace)
    _stored_canonical(nat, model)
    # without the deadlock check too
    nat, py = _both(model)
    assert _json(nat) == _json(py)


def test_the_generated_tables_are_numbers_and_the_same_each_time(tmp_path):
    """The C source of a symmetric search is the same for two loads of the spec, and its symmetry
    tables hold numbers only (no text of the spec)."""
    import re
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.explore.symmetry import native_tables
    srcs, tables = [], []
    for text in (MIX, MIX):
        model = asmcheck.load(write(tmp_path, text))
        sym = detect(model.machine, list(model.temporal))
        ex = NativeExplorer(model.machine, symmetry=sym)
        srcs.append(ex._regenerate(ex.gen.cn_k).generate())      # (the explorer does not keep its source)
        tables.append(native_tables(sym, ex.gen))
    assert srcs[0] == srcs[1] and tables[0] == tables[1] and tables[0] in srcs[0]
    tables = tables[0].splitlines()
    assert len(tables) > 20 and "#define SYM_MULTI 1" in tables
    for ln in tables:
        assert re.fullmatch(r"(static const \w+ SYM_\w+\[\] = \{(-?\d+(ULL)?(, )?)*\};|#define SYM_\w+ -?\d+)", ln), ln


def test_a_successor_moved_into_its_own_class_is_no_deadlock(tmp_path):
    """Swap: the only successor of each state is the other state of its class; the native search
    stores the class once, and still sees no deadlock (the step changed the state)."""
    model = asmcheck.load(write(tmp_path, SWAP))
    run = model.explore(engine="native", symmetry=True, deadlock=True)
    assert (run.states, run.transitions) == (2, 2)
    assert _rows(run) == [("deadlock", "holds")]


def test_the_mutex_trace_is_the_python_engines(tmp_path):
    """The representative is the Python engine's: the same BFS tree, so the same concrete trace,
    step for step (the choices name the concrete trace's elements)."""
    model = asmcheck.load(write(tmp_path, MUTEX))
    nat, py = _both(model)
    got = [(v.property, [s.state for s in v.trace.raw.steps]) for v in nat.violations]
    want = [(v.property, [s.state for s in v.trace.raw.steps]) for v in py.violations]
    assert got == want and len(got) == 2
    assert [(p, len(s)) for p, s in got] == [("ctl_3", 5), ("ltl_2", 8)]


def test_a_string_location_stays_on_the_python_engine(tmp_path, monkeypatch, capsys):
    monkeypatch.delenv("ASMCHECK_ENGINE", raising=False)
    model = asmcheck.load(write(tmp_path, NAMES))
    run = model.explore(engine="auto", symmetry=True)
    assert run.engine == "python" and (run.states, run.transitions) == (10, 13)
    why = "--symmetry: tag over P holds values of String, which the native canonical form does not order"
    assert run.engine_note == why
    from asmcheck.cli import main
    path = write(tmp_path, NAMES)
    assert main(["explore", "--symmetry", path]) == 0
    assert f"  (native engine not used: {why})" in capsys.readouterr().out.splitlines()


def test_a_map_beside_several_positions_stays_on_the_python_engine(tmp_path, monkeypatch):
    """A function over Integer (one map value in the native layout) beside a function with several
    positions over the symmetric domain: the Python engine, with the reason."""
    monkeypatch.delenv("ASMCHECK_ENGINE", raising=False)
    text = LINK.replace("asm Link", "asm LinkMap").replace(
        "\tdynamic controlled edge: Prod(Node, Node) -> Boolean\n",
        "\tdynamic controlled edge: Prod(Node, Node) -> Boolean\n\tdynamic controlled seen: Integer -> Boolean\n").replace(
        "\t\t\t\tedge($b, $a) := true\n", "\t\t\t\tedge($b, $a) := true\n\t\t\t\tseen(1) := true\n")
    assert "seen(1) := true" in text
    run = asmcheck.load(write(tmp_path, text)).explore(engine="auto", symmetry=True)
    assert run.engine == "python" and (run.states, run.transitions) == (19, 40)
    assert run.engine_note == ("--symmetry: seen's locations are one map value in the native layout, beside a function "
                               "with several positions over a symmetric domain")


def test_the_multi_form_has_a_bound_on_numberings(tmp_path, monkeypatch):
    """A state whose canonical form would try more numberings than the bound: the native search
    stops, and the Python engine takes the run (Link's initial state: 4! numberings)."""
    from asmcheck.explore import symmetry
    monkeypatch.delenv("ASMCHECK_ENGINE", raising=False)
    monkeypatch.setattr(symmetry, "NATIVE_MAX_NUMBERINGS", 6)
    model = asmcheck.load(write(tmp_path, LINK))
    run = model.explore(engine="auto", symmetry=True)
    assert run.engine == "python" and (run.states, run.transitions) == (19, 40)
    assert run.engine_note == ("--symmetry: a state whose canonical form tries more than 6 numberings of the "
                               "interchangeable elements")


def test_the_cli_names_the_native_engine(tmp_path, capsys, monkeypatch):
    from asmcheck.cli import main
    monkeypatch.delenv("ASMCHECK_ENGINE", raising=False)
    path = write(tmp_path, BINGO)
    code = main(["explore", "--symmetry", path])
    lines = capsys.readouterr().out.splitlines()
    assert code == 1
    assert lines[0].startswith("Bingo.asm: 48 states, 113 transitions, depth 8, ") and lines[0].endswith(
        "native engine")
    assert lines[1] == "symmetry: states and transitions are counted up to the symmetry of Num's 5 unnamed elements"


def test_threads_give_the_same_report(tmp_path, monkeypatch):
    """--workers 3 with --symmetry: the native threads (chunks of three or four states, so that the
    threads do expand them) give the one-thread report; the Python engine's workers refuse."""
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    monkeypatch.setenv("ASMCHECK_THREAD_MAX_CHUNK", "4")
    for text in (MUTEX, BINGO, SWAP, PHILS, LINK, MIX, COUNTERS, FLIP):
        model = asmcheck.load(write(tmp_path, text))
        one = model.explore(engine="native", symmetry=True, deadlock=True)
        three = model.explore(engine="native", symmetry=True, deadlock=True, workers=3)
        chunks = three.explorer.thread_stats()["parallel_chunks"]
        assert three.explorer.workers == 3 and (chunks > 0 or text is SWAP)
        a, b = _json(one), _json(three)
        a.pop("workers", None), b.pop("workers", None)
        assert a == b
    with pytest.raises(asmcheck.UsageError, match="^--symmetry runs in one process"):
        model.explore(engine="python", symmetry=True, workers=2)
    names = asmcheck.load(write(tmp_path, NAMES))
    with pytest.raises(asmcheck.UsageError, match=r"^--symmetry with --workers runs on the native engine's threads, "
                                                  r"which cannot run Names.asm: --symmetry: tag over P holds values "
                                                  r"of String, which the native canonical form does not order "
                                                  r"\(drop --workers\)$"):
        names.explore(engine="auto", symmetry=True, workers=2)


# a step fails when it chooses a process already on: the representative's failing branch chooses
# another element than the concrete trace's (PA, the one the trace turned on)
FAIL = """asm Fail
import StandardLibrary
signature:
	enum domain P = {PA | PB | PC}
	dynamic controlled on: P -> Boolean
	dynamic controlled x: Integer
definitions:
	main rule r_Main =
		choose $p in P with true do
			if on($p) then
				par
					x := 1
					x := 2
				endpar
			else
				on($p) := true
			endif
default init s0:
	function on($p in P) = false
	function x = 0
"""


@pytest.mark.parametrize("engine", ["native", "python"])
def test_the_failing_choices_name_the_concrete_elements(tmp_path, engine):
    model = asmcheck.load(write(tmp_path, FAIL))
    run = model.explore(engine=engine, symmetry=True)
    assert run.engine == engine and (run.states, run.transitions) == (4, 3)
    (v,) = run.violations
    steps = v.trace.raw.steps
    assert [c.value for s in steps[1:] for c in s.choices] == [{"$p": _elem(model, "PA")}]
    assert [(c.kind, c.value) for c in v.trace.raw.failing] == [("choose", {"$p": _elem(model, "PA")})]
    # the failing branch is one of the concrete state's own
    errors: list = []
    list(model.machine.successors(steps[-1].state, errors=errors))
    assert any(e.choices == v.trace.raw.failing for e in errors)
    doc = run.json()["violations"][0]["failing_step"]
    assert doc["choices"] == [{"kind": "choose", "at": "choose at Fail.asm:9:3", "value": {"$p": "PA"}}]


def _elem(model, name):
    d = next(d for d in model.spec.domains if getattr(d, "name", "") == "P")
    return next(e for e in d.elements if e.name == name)


def _corpus(rel):
    path = ASMETA / rel
    if not path.exists():
        pytest.skip(f"the ASMETA corpus is not at {ASMETA}")
    return asmcheck.load(str(path))


def test_battleship():
    """battleship.asm: its board functions have two positions over Coord, whose columns 1 and 4
    are interchangeable; 296 classes (NuSMV: true, true, true, true)."""
    model = _corpus("asm_examples/examples/battleship.asm")
    nat, py = _both(model, deadlock=True)
    assert (nat.states, nat.transitions) == (296, 832)
    assert _rows(nat)[1:] == [("ctl_1", "holds"), ("ctl_2", "holds"), ("ctl_3", "holds"), ("ctl_4", "holds")]
    assert _json(nat) == _json(py)
    _stored_canonical(nat, model)


@pytest.mark.parametrize("bound", [{"max_depth": 3}, {"max_states": 500}, {"max_depth": 3, "deadlock": True}],
                         ids=["depth", "states", "deadlock"])
def test_parking_bounded(bound):
    """parking.asm (Column's columns 2 and 5 interchangeable): its step ends with merged chooses,
    whose other combinations the native search makes by patching the first one's words (mc_tail),
    each then made its class's representative.  Bounded, as the Python engine takes minutes for the
    whole space; no LTL/CTL property is decided on the part explored under symmetry."""
    model = _corpus("asm_examples/examples/parking.asm")
    nat, py = _both(model, **bound)
    assert _json(nat) == _json(py)
    assert nat.states == {"max_depth": 368, "max_states": 503}["max_depth" if "max_depth" in bound else "max_states"]
    assert all(r["verdict"] == "incomplete" for r in nat.rows if r["kind"] == "ctl")
    _stored_canonical(nat, model)


@pytest.mark.slow
def test_tombola():
    """tombola.asm: 11,264 classes (NuSMV: EF true, EG true, AG false); the Python symmetric run
    takes about 7 s."""
    model = _corpus("asm_examples/examples/tombola.asm")
    nat, py = _both(model, deadlock=True)
    assert (nat.states, nat.transitions, nat.depth) == (11_264, 60_063, 30)
    assert _rows(nat) == [("deadlock", "violated"), ("ctl_1", "holds"), ("ctl_2", "holds"), ("ctl_3", "violated")]
    assert _json(nat) == _json(py)
    ctl3 = next(v for v in nat.violations if v.property == "ctl_3")
    assert len(_check_concrete(model, ctl3.trace)) == 10


# ------------------------------------------------------------------ the corpus differential
MAX_STATES = 3000       # a spec whose symmetric run needs more is outside the comparison
MAX_SECONDS = 2         # the Python engine's time bound per spec (the compared specs take at most
                        # about 1 s; NEVER_FINISH: the skipped ones that spent the whole bound on one state)
SHARDS = 4              # the differential runs as SHARDS tests, every SHARDS-th spec each
# Specs whose Python run cannot end within MAX_SECONDS on any machine: one state's step chooses among
# at least the product of these input sizes (tens of millions of sequences of choices), of which the
# Python engine enumerates a few thousand in 2 s.  They are outside the comparison ('skip') without
# spending the bound to find it (28 s of the differential).
ERTMS = "asm_examples/examples/ermts_etcs/"
NEVER_FINISH = {
    "asm_examples/erinda/for_atgt.asm": "state 11: 1,001 x 721 x 451",
    **{ERTMS + f"models/{name}.asm": "state 0: 6,400 x 201 x 80" for name in (
        "ertms_hl3_integer_disco_lostint_lengthchanged", "ertms_hl3_integer_disco_lostint_lengthchanged_reco_sweep",
        "ertms_hl3_integer_disco_lostint_lengthchanged_reco_sweep_timer")},
    **{ERTMS + f"models/{name}.asm": "state 0: 6,400 x 6,400 x 201" for name in (
        "ertms_hl3_integer_disco_lostint_lengthchanged_reco", "ertms_hl3_integer_disconnected_train",
        "integer_train")},
    ERTMS + "models/ertms_hl3_integer_train.asm": "state 0: 6,400 x 80 x 80",
    **{ERTMS + f"scenarios/ertms_hl3_scenario{i}.asm": "state 0: 6,400 x 201 x 80" for i in (1, 4, 6, 9)},
    ERTMS + "scenarios/ertms_hl3_scenario7.asm": "state 0: 10,000 x 100 x 100",
    ERTMS + "scenarios/ertms_hl3_scenario8.asm": "state 0: 6,400 x 6,400 x 201",
}


def corpus_name(path) -> str:
    """A corpus spec's path under the ASMETA folder (another spec's whole path)."""
    try:
        return path.relative_to(ASMETA).as_posix()
    except ValueError:
        return str(path)


def symmetric_specs() -> list:
    """The corpus specs (as test_native_diff lists them) in which symmetry.detect finds
    interchangeable elements."""
    from test_native_diff import corpus, extra_args
    out = []
    for p in corpus():
        args = extra_args(p)
        try:
            model = asmcheck.load(str(p), import_path=args[1:] if args else ())
            sym = detect(model.machine, list(model.state_props) + list(model.step_props) + list(model.temporal))
        except Exception:       # noqa: BLE001 - a spec that does not load gets no symmetry
            continue
        if sym.active:
            out.append(p)
    return out


def compare(path) -> tuple[str, str]:
    """('native' | 'python' (the run stays on the Python engine; detail: why) | 'skip' | 'differs',
    detail) for the symmetric runs of ``path``, with and without --deadlock."""
    from test_native_diff import extra_args, run_cli
    for more in ([], ["--deadlock"]):
        base = ["explore", str(path), "--symmetry", "--format", "json", "--max-states", str(MAX_STATES),
                *extra_args(path), *more]
        code, out, err = run_cli(base + ["--engine", "python", "--max-seconds", str(MAX_SECONDS)], MAX_SECONDS + 3)
        if code is None or code not in (0, 1, 3):
            return "skip", f"Python engine: exit {code}"
        py = json.loads(out)
        if code == 3 or py["verdict"] == "incomplete":
            return "skip", f"Python engine: {py.get('incomplete') or 'incomplete'}"
        code_n, out_n, err_n = run_cli(base + ["--engine", "auto"], 60)
        if code_n != code:
            return "differs", f"exit code {code_n} (python {code}) {more}: {err_n.strip()[:200]}"
        nat = json.loads(out_n)
        if nat.get("engine") != "native":
            return "python", nat.get("engine_note", "")
        a = {k: v for k, v in py.items() if k not in IGNORED_KEYS}
        b = {k: v for k, v in nat.items() if k not in IGNORED_KEYS}
        if a != b:
            keys = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
            return "differs", f"{more}: different {', '.join(keys)}"
    return "native", f"{py['states']} classes"


@pytest.fixture(scope="module")
def all_symmetric_specs():
    if not ASMETA.exists():
        pytest.skip(f"the ASMETA corpus is not at {ASMETA}")
    specs = symmetric_specs()
    assert len(specs) >= 40
    return specs


@pytest.mark.slow
@pytest.mark.corpus
@pytest.mark.parametrize("index", range(SHARDS))
def test_corpus_differential(all_symmetric_specs, index):
    """The corpus specs that get a symmetry (every SHARDS-th from ``index``): the same report on
    both engines, native wherever the native canonical form allows."""
    assert set(NEVER_FINISH) <= {corpus_name(p) for p in all_symmetric_specs}
    results = {str(p): ("skip", f"Python engine: {NEVER_FINISH[corpus_name(p)]} sequences of choices")
               if corpus_name(p) in NEVER_FINISH else compare(p) for p in all_symmetric_specs[index::SHARDS]}
    differs = {k: v for k, v in results.items() if v[0] == "differs"}
    assert not differs
    native = [k for k, v in results.items() if v[0] == "native"]
    # every reason a compared spec stays on the Python engine is the native canonical form's
    for k, (o, d) in results.items():
        if o == "python":
            assert "symmetry reduction (--symmetry) runs on the Python engine" in d or "cannot" in d, (k, d)
    # 25 of the 50 run native (this machine, 2026-11): at least 2 in each shard
    assert len(native) >= 2, results


if __name__ == "__main__":      # python tests/test_symmetry_native.py [SPEC...]: the differential's lines
    for p in sys.argv[1:] or symmetric_specs():
        print(*compare(p), p, flush=True)
