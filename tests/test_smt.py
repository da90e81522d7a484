"""The Z3 engine (asmcheck bmc): exact depths and verdicts, replayed traces, k-induction,
unsupported constructs, and the benchmark twins."""
import json
import subprocess
import sys

import pytest

from asmcheck.cli import main
from asmcheck.smt.differential import agree, explicit_depths

from conftest import ROOT, need_bench

# Z3 and the Python step function (which replays Z3's traces): ASMCHECK_ENGINE is read only by
# explore, so the module runs once; the one test that runs explore runs on both engines
pytestmark = pytest.mark.engines("python")

SB_ASYNC_MASTER = str(ROOT / "specs" / "sb_async_master.asm")

# the invariants that make inv_exclusive of the correct twins 1-inductive
TWIN_AUX = ["w_of_wb0: wb0 implies w = 0", "w_of_wb1: wb1 implies w = 1",
            "w_of_rb0: rb0 implies w = 1", "w_of_rb1: rb1 implies w = 0",
            "busy_wb0: wb0 implies wpc != 0", "busy_wb1: wb1 implies wpc != 0",
            "rd_rb0: rb0 implies not rd", "rd_rb1: rb1 implies not rd"]


def twin(tmp_path, t, k, bug=False):
    bench = need_bench()
    args = [sys.executable, str(bench / "gen_swing.py"), str(t), str(k)] + (["--bug"] if bug else []) + [str(tmp_path)]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout.strip()
    return out


def run_json(capsys, *argv):
    code = main(["bmc", *argv, "--format", "json"])
    out = capsys.readouterr().out
    return code, json.loads(out)


# ----------------------------------------------------------------- the twins
def test_twin_bug_found_at_depth_13(tmp_path, capsys):
    path = twin(tmp_path, 7, 16, bug=True)
    code, res = run_json(capsys, path, "-k", "14")
    assert code == 1
    assert res["engine"] == "z3" and res["verdict"] == "violated"
    for key in ("spec", "verdict", "states", "transitions", "depth", "seconds", "properties", "violations"):
        assert key in res
    [v] = res["violations"]
    assert v["property"] == "inv_exclusive" and v["kind"] == "state" and v["depth"] == 13
    trace = v["trace"]
    assert [s["step"] for s in trace] == list(range(14))            # a 13-step trace, 14 states
    last = trace[-1]["state"]
    assert (last["wb0"] and last["rb0"]) or (last["wb1"] and last["rb1"])
    # explicit breadth-first search: the same depth
    assert explicit_depths(path, 14).depths == {"inv_exclusive": 13}


def test_twin_bug_not_within_12(tmp_path, capsys):
    path = twin(tmp_path, 7, 16, bug=True)
    code, res = run_json(capsys, path, "-k", "12")
    assert code == 0 and res["verdict"] == "holds-to-depth" and res["depth"] == 12
    assert res["violations"] == []


@pytest.mark.slow
def test_twin_correct_holds_to_30(tmp_path, capsys):
    path = twin(tmp_path, 7, 16)
    code, res = run_json(capsys, path, "-k", "30")
    assert code == 0
    assert res["verdict"] == "holds-to-depth" and res["depth"] == 30 and res["violations"] == []
    assert {r["property"]: r["verdict"] for r in res["properties"]} == {
        "inv_exclusive": "holds-to-depth", "error": "holds-to-depth"}


def test_twin_induction_with_aux(tmp_path, capsys):
    path = twin(tmp_path, 7, 16)
    argv = [path, "-k", "2", "--induction"]
    for a in TWIN_AUX:
        argv += ["--aux", a]
    code, res = run_json(capsys, *argv)
    assert code == 0 and res["verdict"] == "proved"
    rows = {r["property"]: r for r in res["properties"]}
    inv = rows["inv_exclusive"]
    assert inv["verdict"] == "proved" and inv["k"] == 1
    # inv_exclusive rests directly on the four w_of_* and, through them, on the other four
    assert set(inv["needed"]) == {a.split(":")[0] for a in TWIN_AUX}
    assert inv["lemmas"] == ["isDef(w)"]
    assert rows["w_of_wb0"]["needed"] == ["busy_wb0"] and rows["w_of_wb0"]["auxiliary"]
    assert rows["error"]["verdict"] == "proved"


@pytest.mark.parametrize("t,k", [(31, 128), (63, 250)])
def test_larger_twins(tmp_path, capsys, t, k):
    # the wide integer ranges (clocks 0..T, sequence numbers mod K) are bit-vector arithmetic
    bug = twin(tmp_path / "bug", t, k, bug=True)
    code, res = run_json(capsys, bug, "-k", "13")
    assert code == 1 and [(v["property"], v["depth"]) for v in res["violations"]] == [("inv_exclusive", 13)]
    ok = twin(tmp_path / "ok", t, k)
    argv = [ok, "-k", "1", "--induction"]
    for a in TWIN_AUX:
        argv += ["--aux", a]
    code, res = run_json(capsys, *argv)
    assert code == 0 and res["verdict"] == "proved"


def test_twin_induction_without_aux_is_unknown(tmp_path, capsys):
    path = twin(tmp_path, 7, 16)
    code, res = run_json(capsys, path, "-k", "3", "--induction")
    assert code == 3 and res["verdict"] == "unknown"
    assert {r["property"]: r["verdict"] for r in res["properties"]}["inv_exclusive"] == "unknown"
    assert "not inductive up to k=3" in res["unknown"]


def test_twin_induction_infers_lemmas(tmp_path, capsys):
    path = twin(tmp_path, 7, 16)
    code, res = run_json(capsys, path, "-k", "1", "--induction", "--infer")
    assert code == 0 and res["verdict"] == "proved"
    inv = {r["property"]: r for r in res["properties"]}["inv_exclusive"]
    # which lemmas Houdini keeps depends on Z3's models; some tie the arrays to w
    assert inv["needed"] == [] and any(" w = " in f" {x}" for x in inv["lemmas"])


def test_twin_bug_induction_reports_the_violation(tmp_path, capsys):
    path = twin(tmp_path, 7, 16, bug=True)
    argv = [path, "-k", "13", "--induction"]
    for a in TWIN_AUX[:4]:
        argv += ["--aux", a]
    code, res = run_json(capsys, *argv)
    assert code == 1 and res["verdict"] == "violated"
    depths = {v["property"]: v["depth"] for v in res["violations"]}
    # the reader's buggy choice of array breaks an auxiliary invariant first
    assert depths == {"w_of_rb1": 10, "inv_exclusive": 13}
    rows = {r["property"]: r for r in res["properties"]}
    assert rows["w_of_rb1"]["auxiliary"] and rows["w_of_rb1"]["verdict"] == "violated"


def test_text_output(tmp_path, capsys):
    path = twin(tmp_path, 7, 16, bug=True)
    code = main(["bmc", path, "-k", "13"])
    out = capsys.readouterr().out
    assert code == 1
    assert "inv_exclusive                            violated at depth 13" in out
    assert "inv_exclusive (" in out and " is violated -- shortest counterexample, 13 steps:\n  formula: " in out
    assert "  step 13: r_main chooses $a = " in out and "verdict: violated" in out


# ----------------------------------------------------------------- specs of the project
@pytest.mark.engines("both")
def test_json_matches_explore_shape(tmp_path, capsys):
    path = write(tmp_path, "shape", SHAPE)
    code = main(["explore", path, "--format", "json", "--no-default-properties", "--properties", SHAPE_PROPS(tmp_path)])
    ex = json.loads(capsys.readouterr().out)
    code2, bm = run_json(capsys, path, "-k", "4", "--no-default-properties", "--properties", SHAPE_PROPS(tmp_path))
    assert code == code2 == 1
    # the explorer's own timing and engine keys aside, the two reports have one shape
    assert set(ex) - {"compile_seconds", "engine_note"} <= set(bm)
    assert bm["verdict"] == ex["verdict"] == "violated"
    ev = {v["property"]: v for v in ex["violations"]}
    for v in bm["violations"]:
        assert set(v) >= set(ev[v["property"]])
        assert v["kind"] == ev[v["property"]]["kind"]
        assert len(v["trace"]) == len(ev[v["property"]]["trace"])
        assert set(v["trace"][0]) == set(ev[v["property"]]["trace"][0])


def test_replay_mismatch_is_an_internal_error(tmp_path, monkeypatch, capsys):
    from asmcheck.smt import bmc

    real = bmc.Model.decode

    def corrupt(self, model, ns, n):
        states = real(self, model, ns, n)
        states[-1] = dict(states[0])          # not what the step function reaches
        return states
    monkeypatch.setattr(bmc.Model, "decode", corrupt)
    code = main(["bmc", twin(tmp_path, 7, 16, bug=True), "-k", "13"])
    cap = capsys.readouterr()
    assert code == 2
    assert "internal error" in cap.err and "does not replay" in cap.err
    assert "shortest counterexample" not in cap.out and "verdict" not in cap.out


def test_induction_proves_step_properties(capsys):
    code, res = run_json(capsys, SB_ASYNC_MASTER, "-k", "1", "--induction",
                         "--property", "stp_slave_never_moves_indexes", "--property", "inv_indexes_distinct")
    assert code == 0 and res["verdict"] == "proved"
    rows = {r["property"]: r for r in res["properties"]}
    assert rows["stp_slave_never_moves_indexes"]["verdict"] == "proved"
    assert rows["stp_slave_never_moves_indexes"]["needed"] == []
    assert rows["inv_indexes_distinct"]["k"] == 1


def test_property_selection(tmp_path, capsys):
    path = write(tmp_path, "shape", SHAPE)
    props = SHAPE_PROPS(tmp_path)
    code, res = run_json(capsys, path, "-k", "6", "--properties", props, "--property", "inv_lo")
    assert code == 1
    assert [v["property"] for v in res["violations"]] == ["inv_lo"]
    assert [r["property"] for r in res["properties"]] == ["inv_lo", "error"]
    assert main(["bmc", SB_ASYNC_MASTER, "--property", "nope"]) == 2
    assert "no property named 'nope'" in capsys.readouterr().err


# ----------------------------------------------------------------- semantics: errors, inputs, ranges
HEAD = "asm {name}\nimport StandardLibrary\nsignature:\n"

# two agents taking turns on a lock; a step property (updatedBy) and invariants
SHAPE = """\tdomain Task subsetof Agent
\tdomain S subsetof Integer
\tstatic t1: Task
\tstatic t2: Task
\tdynamic controlled holder: Task
\tdynamic controlled n: S
definitions:
\tdomain S = {0 : 3}
\trule r_work =
\t\tif isUndef(holder) then holder := self
\t\telse if holder = self then par n := (n + 1) mod 4 holder := undef endpar endif endif
\tinvariant inv_lo over n: n < 2
\tmain rule r_main = choose $t in Task with true do program($t)
default init s0:
\tfunction n = 0
\tagent Task: r_work[]
"""


def SHAPE_PROPS(tmp_path):
    p = tmp_path / "shape.prop"
    p.write_text("applies to shape\n"
                 "step stp_only_t1_counts: (forall $t in Task with updatedBy($t, n) implies $t = t1)\n"
                 "invariant inv_hi: n < 3\n")
    return str(p)


def write(tmp_path, name, text):
    p = tmp_path / f"{name}.asm"
    p.write_text(HEAD.format(name=name) + text)
    return str(p)


def test_runtime_error_found_and_replayed(tmp_path, capsys):
    path = write(tmp_path, "clash", """\tdomain S subsetof Integer
\tdynamic controlled n: S
\tdynamic controlled b: Boolean
definitions:
\tdomain S = {0 : 3}
\tmain rule r_main = par
\t\tn := n + 1
\t\tif n = 2 then n := 0 endif
\tendpar
default init s0:
\tfunction n = 0
""")
    code, res = run_json(capsys, path, "-k", "5")
    assert code == 1
    [v] = res["violations"]
    assert v["property"] == "error" and v["depth"] == 2 and len(v["trace"]) == 3
    assert "inconsistent update of n" in v["message"]
    assert explicit_depths(path, 5).depths == {"error": 2}


def test_value_out_of_subset_domain_is_an_error(tmp_path, capsys):
    path = write(tmp_path, "outdom", """\tdomain S subsetof Integer
\tdynamic controlled n: S
definitions:
\tdomain S = {0 : 2}
\tmain rule r_main = n := n + 1
default init s0:
\tfunction n = 0
""")
    code, res = run_json(capsys, path, "-k", "4")
    assert code == 1
    [v] = res["violations"]
    assert v["property"] == "error" and v["depth"] == 2 and "out of domain" in v["message"]


def test_undef_guard_is_an_error(tmp_path, capsys):
    path = write(tmp_path, "undefg", """\tdynamic controlled a: Boolean
\tdynamic controlled b: Boolean
definitions:
\tmain rule r_main = if a then b := true else par a := undef b := false endpar endif
default init s0:
\tfunction a = false
""")
    code, res = run_json(capsys, path, "-k", "3")
    [v] = res["violations"]
    assert v["property"] == "error" and v["depth"] == 1 and "undef" in v["message"]


def test_monitored_inputs(tmp_path, capsys):
    path = write(tmp_path, "mon", """\tdomain S subsetof Integer
\tdynamic monitored m: Integer
\tdynamic monitored go: Boolean
\tdynamic controlled c: S
definitions:
\tdomain S = {0 : 3}
\tinvariant inv_c over c: c != 3
\tmain rule r_main = if go and m > 1 and c < 3 then c := c + 1 endif
default init s0:
\tfunction c = 0
""")
    code, res = run_json(capsys, path, "-k", "5", "--monitored", "m=0..2")
    assert code == 1
    [v] = res["violations"]
    assert v["property"] == "inv_c" and v["depth"] == 3
    choices = v["trace"][1]["choices"]
    assert {c["at"]: c["value"] for c in choices} == {"go": True, "m": 2}
    assert explicit_depths(path, 5, options={"monitored_ranges": {"m": [0, 1, 2]}}).depths == {"inv_c": 3}


LOOPS = """\tdomain S subsetof Integer
\tdynamic controlled c: S
\tdynamic controlled d: S
\tdynamic controlled k: S
\tdynamic monitored go: Boolean
definitions:
\tdomain S = {0 : 5}
\tinvariant inv_d over d: d < 4
\tmain rule r_main =
\t\tif go then
\t\t\tseq
\t\t\t\tc := 0
\t\t\t\twhile c < k do par c := c + 1 d := c endpar
\t\t\t\tif k < 5 then k := k + 1 endif
\t\t\tendseq
\t\telse
\t\t\titerate if c > 0 then c := c - 1 endif enditerate
\t\tendif
default init s0:
\tfunction c = 0
\tfunction d = 0
\tfunction k = 0
"""


def test_loops_are_unrolled(tmp_path, capsys):
    path = write(tmp_path, "loops", LOOPS)
    code, res = run_json(capsys, path, "-k", "7")
    assert code == 1 and [(v["property"], v["depth"]) for v in res["violations"]] == [("inv_d", 6)]
    assert explicit_depths(path, 7).depths == {"inv_d": 6}
    # a loop that may run longer than the bound: unknown, never a wrong 'holds'
    code, res = run_json(capsys, path, "-k", "7", "--loop-bound", "3")
    assert code == 3 and res["verdict"] == "unknown"
    assert "loop running more than 3 times" in res["unknown"]


def test_integer_range_overflow_is_unknown(tmp_path, capsys):
    path = write(tmp_path, "cnt", """\tdynamic controlled c: Integer
definitions:
\tinvariant inv_c over c: c < 5
\tmain rule r_main = c := c + 1
default init s0:
\tfunction c = 0
""")
    code, res = run_json(capsys, path, "-k", "6", "--int-range", "0..10")
    assert code == 1 and res["violations"][0]["depth"] == 5
    code, res = run_json(capsys, path, "-k", "6", "--int-range", "0..3")
    assert code == 3 and res["verdict"] == "unknown"
    assert "outside what the encoding represents, reachable at depth 3" in res["unknown"]


UNSUPPORTED = [
    ("extend", """\tdynamic abstract domain Tok
\tdynamic controlled holder: Tok
definitions:
\tmain rule r_main = extend Tok with $t do holder := $t
""", 7, 21, "cannot encode extend"),
    ("sequence location", """\tdynamic controlled q: Seq(Boolean)
definitions:
\tmain rule r_main = q := append(q, true)
default init s0:
\tfunction q = []
""", 6, 33, "q, whose values are sequences"),
    ("unbounded integer", """\tdynamic controlled c: Integer
definitions:
\tmain rule r_main = c := c + 1
default init s0:
\tfunction c = 0
""", 6, 26, "codomain Integer is infinite"),
    ("whilerec loop", """\tdomain S subsetof Integer
\tdynamic controlled c: S
definitions:
\tdomain S = {0 : 3}
\tmain rule r_main = whilerec c < 3 do c := c + 1
default init s0:
\tfunction c = 0
""", 8, 21, "cannot encode the whilerec loop"),
    ("real arithmetic", """\tdynamic controlled r: Real
definitions:
\tmain rule r_main = r := r + 0.5
default init s0:
\tfunction r = 0.0
""", 6, 26, "Real arithmetic"),
    ("infinite range", """\tdynamic controlled b: Boolean
definitions:
\tmain rule r_main = forall $i in Integer with $i < 3 do b := true
""", 6, 34, "a range over Integer"),
    ("unbounded monitored", """\tdynamic monitored m: Integer
\tdynamic controlled b: Boolean
definitions:
\tmain rule r_main = if m > 0 then b := true endif
""", 4, 20, "monitored function m"),
    ("rule-valued location", """\tdynamic controlled todo: Rule
\tdynamic controlled b: Boolean
definitions:
\trule r_a = b := true
\tmain rule r_main = todo
default init s0:
\tfunction todo = <<r_a>>
""", 8, 21, "rule-valued function todo"),
]


@pytest.mark.parametrize("label,text,line,col,msg", UNSUPPORTED, ids=[u[0] for u in UNSUPPORTED])
def test_unsupported_constructs(tmp_path, capsys, label, text, line, col, msg):
    path = write(tmp_path, "uns", text)
    code = main(["bmc", path, "-k", "2"])
    out = capsys.readouterr().err          # input errors go to stderr
    assert code == 2
    first = out.splitlines()[0]
    assert first.startswith(f"{path}:{line}:{col}: the Z3 engine cannot encode"), first
    assert msg in first


def test_auxiliary_term_errors_are_located(tmp_path, capsys):
    path = twin(tmp_path, 7, 16)
    code = main(["bmc", path, "--induction", "--aux", "nope: wb0 implies zz = 1"])
    out = capsys.readouterr().err
    assert code == 2 and out.startswith("<aux 1>:1:") and "zz" in out


def test_differential_agree_helper_detects_a_difference():
    from asmcheck.smt.differential import Depths
    assert agree(Depths({"p": 3}), Depths({"p": 3})) is None
    assert "depth 3 (explicit) vs 4 (z3)" in agree(Depths({"p": 3}), Depths({"p": 4}))
    assert agree(Depths({}), Depths({"q": 2})) is not None
