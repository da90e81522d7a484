"""LTL, CTL and fairness on the explored state graph (asmcheck/temporal)."""
from __future__ import annotations

import json
import random
import time
from pathlib import Path

import pytest

from asmcheck.cli import main
from asmcheck.props.load import load_machine
from asmcheck.explore.bfs import Explorer
from asmcheck.props.files import properties_for
from asmcheck.report.trace import temporal_json, temporal_text
from asmcheck.temporal import check_temporal
from asmcheck.temporal.ctl import CTL
from asmcheck.temporal.formula import AF, AG, AU, AX, EF, EG, EU, EX, And, Implies, Not, Or
from asmcheck.temporal.kripke import Kripke, _finish_classes
from asmcheck.temporal.ltl import check_ltl

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parent.parent
TEMPORAL = ROOT / "specs" / "temporal"
SPECS = ROOT / "specs"


def check(path, prop_files=None, fair=(), drop_fairness=False):
    """Explore ``path`` and check its temporal properties: {name: TemporalResult}."""
    path = str(path)
    spec, machine = load_machine(path)
    _, _, temporal = properties_for(spec, machine, path, prop_files, use_default=False)
    if drop_fairness:
        temporal = [p for p in temporal if p.kind not in ("justice", "compassion")]
    ex = Explorer(machine, keep_graph=True)
    res = ex.run()
    assert res.verdict != "incomplete"
    results = check_temporal(ex, temporal, fair=list(fair))
    return machine, {r.name: r for r in results}


def states_of(machine, r):
    """The replayed trace of a result as a list of {location text: value} dicts."""
    return [step["state"] for step in temporal_json(r, machine)["trace"]]


# ----------------------------------------------------------------- mutual exclusion and fairness
def test_peterson_starves_without_fairness():
    m, res = check(TEMPORAL / "peterson.asm")
    assert res["ctlSpec_mutex"].holds
    for name in ("ltlSpec_p1_enters", "ltlSpec_p2_enters", "ctlSpec_p1_enters"):
        assert not res[name].holds, name
    r = res["ltlSpec_p1_enters"]
    j = temporal_json(r, m)
    loop = j["loop_start"]
    assert loop is not None
    states = states_of(m, r)
    # the last state closes the loop; p1 waits in every state of the cycle and never enters
    assert states[-1] == states[loop]
    assert all(s["pc(p1)"] == "WAIT" for s in states[loop:])
    # in the loop only p2 is scheduled
    picks = [c["value"]["$p"] for e in j["trace"][loop + 1:] for c in e["choices"]]
    assert set(picks) == {"p2"}


@pytest.mark.parametrize("how", ["--fair", "JUSTICE"])
def test_peterson_no_starvation_under_weak_fairness(how):
    if how == "--fair":
        _, res = check(TEMPORAL / "peterson.asm", fair=["Proc"])
    else:
        _, res = check(TEMPORAL / "peterson.asm", [str(TEMPORAL / "peterson_fair.prop")])
    assert all(r.holds for r in res.values()), {n: r.verdict for n, r in res.items()}


def test_spinlock_needs_strong_fairness():
    m, res = check(TEMPORAL / "spinlock.asm", fair=["Proc"])
    r = res["ltlSpec_p1_enters"]
    assert not r.holds
    states = states_of(m, r)
    loop = temporal_json(r, m)["loop_start"]
    cycle = states[loop:]
    # weakly fair: both processes move in the cycle, but p1 only ever sees the lock taken
    assert all(s["pc(p1)"] == "WAIT" for s in cycle)
    assert any(s.get("holder") == "p2" for s in cycle)
    _, res = check(TEMPORAL / "spinlock.asm", [str(TEMPORAL / "spinlock_strong.prop")], fair=["Proc"])
    assert res["ltlSpec_p1_enters"].holds


# ----------------------------------------------------------------- LTL lassos, CTL through EF, past
def test_counter_ctl_and_ltl_verdicts():
    _, res = check(TEMPORAL / "counter.asm")
    verdicts = {n: r.holds for n, r in res.items()}
    assert verdicts == {
        "ctlSpec_reset_possible": True,       # holds, but only through EF
        "ctlSpec_reset_inevitable": False,
        "ctlSpec_two_reachable": True,
        "ctlSpec_can_stay_away": True,
        "ctlSpec_au": True,
        "ltlSpec_reset_often": False,
        "ltlSpec_never_two_twice": True,
        "ltlSpec_before_two": True,
        "ltlSpec_once_one": True,
        "ltlSpec_zero_since": True,
        "ltlSpec_historically": True,
        "ltlSpec_wrong_past": False,
    }


def test_ltl_refuted_only_by_a_lasso():
    m, res = check(TEMPORAL / "counter.asm")
    r = res["ltlSpec_reset_often"]
    j = temporal_json(r, m)
    assert j["kind"] == "ltl" and j["verdict"] == "violated"
    loop = j["loop_start"]
    states = states_of(m, r)
    assert loop is not None and states[-1] == states[loop]
    # every finite prefix can still reach c = 0: the refutation is the cycle avoiding it
    assert all(s["c"] != 0 for s in states[loop:])
    assert [s["c"] for s in states] == [0, 1, 2, 1, 2]
    text = "\n".join(temporal_text(r, m))
    assert "  step 2: r_main chooses $v = 2  <- the loop starts here (state 2)" in text
    assert "  step 4: r_main chooses $v = 2  <- back to state 2" in text
    assert "counterexample, 4 steps: a lasso, 2 steps to the loop, then a loop of 2 steps repeated for ever:" in text


def test_ctl_af_counterexample_is_a_lasso_and_ef_witness_a_path():
    m, res = check(TEMPORAL / "counter.asm")
    r = res["ctlSpec_reset_inevitable"]
    states = states_of(m, r)
    loop = temporal_json(r, m)["loop_start"]
    assert loop is not None and all(s["c"] != 0 for s in states[loop:])
    w = res["ctlSpec_two_reachable"]
    assert w.holds and w.witness
    assert [s["c"] for s in states_of(m, w)] == [0, 1, 2]


def test_monitored_values_belong_to_the_state_that_reads_them():
    # as in AsmetaSMV: `req` is read in the state the step starts from
    m, res = check(TEMPORAL / "request_ack.asm")
    assert {n: r.holds for n, r in res.items()} == {
        "ctlSpec_ack_next": True, "ctlSpec_ack_now": False, "ctlSpec_no_req_when_busy": True,
        "ltlSpec_ack_next": True, "ltlSpec_ack_after_req": True}
    r = res["ctlSpec_ack_now"]
    j = temporal_json(r, m)
    assert j["inputs_step"] is True
    # the last step shows req = true read in a state where ack is still false
    last = j["trace"][-1]
    assert [c["value"] for c in last["choices"]] == [True]
    assert j["trace"][-2]["state"]["ack"] is False


# ----------------------------------------------------------------- the pattern library
SB = ["sb_async_master", "sb_sync_master", "sb_sync_slave", "sb_async_slave", "producer_consumer"]


@pytest.mark.parametrize("name", SB)
def test_pattern_machines_are_left_under_fairness(name):
    _, res = check(SPECS / f"{name}.asm")
    assert res and all(r.holds for r in res.values()), {n: r.verdict for n, r in res.items()}


@pytest.mark.parametrize("name", ["sb_sync_master", "sb_async_master"])
def test_pattern_machines_starve_without_fairness(name):
    m, res = check(SPECS / f"{name}.asm", drop_fairness=True)
    r = res["ltlSpec_master_leaves"]
    assert not r.holds
    states = states_of(m, r)
    loop = temporal_json(r, m)["loop_start"]
    assert all(s["sbState(master)"] is not None for s in states[loop:])


def test_weak_fairness_of_the_tasks_is_the_justice_of_the_spec():
    _, res = check(SPECS / "sb_sync_master.asm", drop_fairness=True, fair=["Task"])
    assert all(r.holds for r in res.values())


def test_seeded_starvation_sync_master_without_watchdog():
    m, res = check(SPECS / "buggy" / "sb_sync_master_no_watchdog.asm")
    assert {n: r.holds for n, r in res.items()} == {"ltlSpec_master_leaves": False, "ltlSpec_slave_leaves": True}
    r = res["ltlSpec_master_leaves"]
    j = temporal_json(r, m)
    loop = j["loop_start"]
    states = states_of(m, r)
    cycle = states[loop:]
    assert states[-1] == states[loop]
    # the master spins in MANAGING_SB for ever, while both tasks keep being scheduled
    assert all(s["sbState(master)"] == "MANAGING_SB" for s in cycle)
    assert {s["scheduled"] for s in cycle} == {"master", "slave"}
    assert j["fairness"] == ["JUSTICE scheduled = master", "JUSTICE scheduled = slave"]


def test_master_without_release_does_not_starve_the_slave():
    # the seeded fault (no release on exit) is repaired by the master's next move, so both
    # liveness properties hold: the variant breaks only its step property
    m, res = check(SPECS / "buggy" / "sb_async_master_no_release.asm")
    assert {n: r.holds for n, r in res.items()} == {"ltlSpec_master_leaves": True, "ltlSpec_slave_leaves": True}


def test_seeded_starvation_slave_without_recheck():
    m, res = check(SPECS / "buggy" / "sb_async_slave_no_recheck.asm")
    assert res["ltlSpec_slave_leaves"].holds is False
    r = res["ltlSpec_slave_leaves"]
    states = states_of(m, r)
    loop = temporal_json(r, m)["loop_start"]
    # on the cycle the slave never leaves its pattern machine
    assert all(s["sbState(slave)"] is not None for s in states[loop:])


# ----------------------------------------------------------------- the command
def test_explore_json_and_text_report_the_lasso(capsys):
    path = str(SPECS / "buggy" / "sb_sync_master_no_watchdog.asm")
    assert main(["explore", path, "--format", "json", "--no-default-properties"]) == 1
    out = json.loads(capsys.readouterr().out)
    rows = {r["property"]: r["verdict"] for r in out["properties"]}
    assert rows["ltlSpec_master_leaves"] == "violated" and rows["ltlSpec_slave_leaves"] == "holds"
    (v,) = [v for v in out["violations"] if v["property"] == "ltlSpec_master_leaves"]
    assert v["kind"] == "ltl" and isinstance(v["loop_start"], int)
    assert v["trace"][-1]["state"] == v["trace"][v["loop_start"]]["state"]
    assert main(["explore", path, "--no-default-properties"]) == 1
    text = capsys.readouterr().out
    assert "ltlSpec_master_leaves (sb_sync_master_no_watchdog.asm:354:2) is violated" in text
    assert "<- the loop starts here (state 4)" in text and "<- back to state 4" in text


def test_output_is_deterministic(capsys):
    path = str(TEMPORAL / "spinlock.asm")
    outs = []
    for _ in range(2):
        main(["explore", path, "--format", "json", "--fair", "Proc"])
        out = json.loads(capsys.readouterr().out)
        out.pop("seconds", None)
        out.pop("compile_seconds", None)
        outs.append(json.dumps(out, sort_keys=False))
    assert outs[0] == outs[1]
    assert '"loop_start"' in outs[0]


def test_ten_thousand_states_in_seconds():
    path = str(TEMPORAL / "grid.asm")
    spec, machine = load_machine(path)
    _, _, temporal = properties_for(spec, machine, path, [str(TEMPORAL / "grid_fair.prop")], use_default=False)
    ex = Explorer(machine, keep_graph=True)
    assert ex.run().states == 9800
    t0 = time.perf_counter()
    res = {r.name: r for r in check_temporal(ex, temporal)}
    secs = time.perf_counter() - t0
    assert all(r.holds for r in res.values())
    t0 = time.perf_counter()
    res = {r.name: r for r in check_temporal(ex, [p for p in temporal if p.kind in ("ltl", "ctl")])}
    secs2 = time.perf_counter() - t0
    assert {n: r.holds for n, r in res.items()} == {
        "ctlSpec_origin_reachable": True, "ctlSpec_a_inevitable": False, "ctlSpec_a_fair": False,
        "ltlSpec_a_often": False, "ltlSpec_b_after_a": True}
    assert secs < 30 and secs2 < 30, (secs, secs2)


# ----------------------------------------------------------------- LTL against CTL on random graphs
def random_kripke(rng, n, natoms, deadlocks=False, njustice=0):
    K = Kripke()
    K.n = n
    K.sid = list(range(n))
    K.cls = list(range(n))
    succ = []
    for v in range(n):
        k = rng.randint(0 if deadlocks else 1, 3)
        succ.append(sorted({rng.randrange(n) for _ in range(k)}))
    K.cls_succ = succ
    K.init = sorted({rng.randrange(n) for _ in range(2)})
    for a in range(natoms):
        K.label[a] = bytearray(rng.random() < 0.5 for _ in range(n))
    for j in range(njustice):
        K.justice.append((f"j{j}", bytearray(rng.random() < 0.4 for _ in range(n))))
    _finish_classes(K)
    return K


P, Q = ("ap", 0), ("ap", 1)
LTL_CTL = [
    (("R", ("false",), P), AG(P)),
    (("U", ("true",), P), AF(P)),
    (("X", P), AX(P)),
    (("U", P, Q), AU(P, Q)),
    (("R", P, Q), Not(EU(Not(P), Not(Q)))),
    (("R", ("false",), Implies(P, ("U", ("true",), Q))), AG(Implies(P, AF(Q)))),
    (("R", ("false",), ("U", ("true",), P)), AG(AF(P))),
    (("R", ("false",), Implies(P, ("X", Q))), AG(Implies(P, AX(Q)))),
    (Or(("R", ("false",), P), ("U", ("true",), Q)), None),
]


@pytest.mark.parametrize("seed", range(60))
def test_ltl_agrees_with_ctl_on_random_graphs(seed):
    rng = random.Random(seed)
    K = random_kripke(rng, rng.randint(1, 9), 2, deadlocks=seed % 3 == 0, njustice=seed % 4 // 2)
    ctl = CTL(K)
    for ltl_f, ctl_f in LTL_CTL:
        r = check_ltl(K, ltl_f)
        if ctl_f is not None:
            holds, bad = ctl.check(ctl_f)
            assert r.holds == holds, (seed, ltl_f)
            if not holds:
                # the CTL counterexample is a path of the structure (a lasso when it loops)
                nodes, loop = ctl.explain(ctl_f, bad, False)
                assert nodes[0] == bad
                ends = [nodes[loop]] if loop is not None else []
                for a, b in zip(nodes, nodes[1:] + ends):
                    assert b in K.succ(a)
        if not r.holds:
            # the lasso is a path of the structure from an initial node
            nodes, loop = r.nodes, r.loop
            assert nodes[0] in K.init and loop is not None
            for a, b in zip(nodes, nodes[1:] + [nodes[loop]]):
                assert b in K.succ(a)


def test_ctl_basics_on_a_small_graph():
    # 0 -> 1 -> 2 -> 2, 0 -> 3 -> 3; p at 2, q at 3
    K = Kripke()
    K.n = 4
    K.sid = list(range(4))
    K.cls = list(range(4))
    K.cls_succ = [[1, 3], [2], [2], [3]]
    K.init = [0]
    K.label = {0: bytearray([0, 0, 1, 0]), 1: bytearray([0, 0, 0, 1])}
    _finish_classes(K)
    c = CTL(K)
    assert c.check(EF(P))[0] and not c.check(AF(P))[0]
    assert c.check(AF(Or(P, Q)))[0] and c.check(EG(Not(P)))[0] and not c.check(EX(P))[0]
    assert c.check(EX(EX(P)))[0] and c.check(AX(AX(Or(P, Q))))[0]
    assert not c.check(AG(Not(P)))[0]
    nodes, loop = c.explain(AG(Not(P)), 0, False)
    assert nodes == [0, 1, 2] and loop is None
    nodes, loop = c.explain(AF(P), 0, False)
    assert nodes == [0, 3] and loop == 1
    # under the justice constraint "p infinitely often" the path through 3 is unfair
    K.justice = [("p", K.label[0])]
    c = CTL(K)
    assert c.check(AF(P))[0] and c.check(AG(EF(P)))[0]
    assert list(c.fair) == [1, 1, 1, 0]


# ----------------------------------------------------------------- LTL (with past) against lassos
def eval_lasso(f, K, nodes, loop):
    """The truth of LTL formula f at every position of the lasso nodes[:loop] nodes[loop:]^w."""
    n = len(nodes)
    nxt = [i + 1 if i + 1 < n else loop for i in range(n)]
    op = f[0]
    if op == "true":
        return [True] * n
    if op == "false":
        return [False] * n
    if op == "ap":
        return [K.label[f[1]][v] == 1 for v in nodes]
    args = [eval_lasso(x, K, nodes, loop) for x in f[1:]]
    if op == "not":
        return [not x for x in args[0]]
    if op == "and":
        return [x and y for x, y in zip(*args)]
    if op == "or":
        return [x or y for x, y in zip(*args)]
    if op == "X":
        return [args[0][nxt[i]] for i in range(n)]
    if op in ("U", "R"):
        a, b = args
        val = [op == "R"] * n
        while True:
            new = [(b[i] or (a[i] and val[nxt[i]])) if op == "U" else (b[i] and (a[i] or val[nxt[i]]))
                   for i in range(n)]
            if new == val:
                return val
            val = new
    if op in ("Y", "Z"):
        return [args[0][i - 1] if i > 0 else op == "Z" for i in range(n)]
    a, b = args
    val = []
    for i in range(n):
        prev = val[i - 1] if i > 0 else None
        if op == "S":
            val.append(b[i] or (a[i] and bool(prev)))
        else:
            val.append(b[i] and (a[i] or prev is None or prev))
    return val


def unrolled(nodes, loop, copies=4):
    cyc = nodes[loop:]
    return nodes + cyc * (copies - 1), loop + len(cyc) * (copies - 1)


def lassos(K, max_len):
    def walk(path):
        v = path[-1]
        for w in K.succ(v):
            if w in path:
                yield list(path), path.index(w)
            if len(path) < max_len:
                yield from walk(path + [w])
    for v in K.init:
        yield from walk([v])


def fair_lasso(K, nodes, loop):
    return all(any(lab[v] for v in nodes[loop:]) for _, lab in K.justice)


def H(f):
    return Not(("S", ("true",), Not(f)))


def O(f):
    return ("S", ("true",), f)


G = lambda f: ("R", ("false",), f)   # noqa: E731
F = lambda f: ("U", ("true",), f)    # noqa: E731
PAST_AND_FUTURE = [
    G(Implies(P, O(Q))),
    G(Implies(("Y", P), Q)),
    F(And(P, H(Q))),
    G(Implies(Q, ("S", P, Q))),
    G(Or(("T", P, Q), ("Z", P))),
    Implies(G(F(P)), G(F(Q))),
    G(Implies(P, ("X", ("U", P, Q)))),
    F(G(Or(P, ("Y", ("Y", Q))))),
]


@pytest.mark.parametrize("seed", range(40))
def test_ltl_with_past_against_lasso_enumeration(seed):
    rng = random.Random(1000 + seed)
    K = random_kripke(rng, rng.randint(1, 4), 2, njustice=seed % 3 // 2)
    runs = [(nodes, loop) for nodes, loop in lassos(K, 5) if fair_lasso(K, nodes, loop)]
    for f in PAST_AND_FUTURE:
        r = check_ltl(K, f)
        bad = [(nodes, loop) for nodes, loop in runs if not eval_lasso(f, K, *unrolled(nodes, loop))[0]]
        if bad:
            assert not r.holds, (seed, f, bad[0])
        if r.holds:
            assert not bad
        else:
            # the counterexample is a fair lasso of the structure that violates f
            assert fair_lasso(K, r.nodes, r.loop)
            assert not eval_lasso(f, K, *unrolled(r.nodes, r.loop))[0], (seed, f, r.nodes, r.loop)


FAIR_FAIL = """asm FairFail
import StandardLibrary
import LTLLibrary
signature:
	enum domain Task = {TA | TB}
	controlled n: Integer
	controlled x: Integer
definitions:
	LTLSPEC g(f(n = 0))
	main rule r_main = choose $t in Task with true do
		if $t = TA then par x := 1 x := 2 endpar else n := (n + 1) mod 2 endif
default init s0:
	function n = 0
	function x = 0
"""


def test_agent_fairness_over_a_spec_whose_steps_fail(tmp_path, capsys):
    # TA's move always fails: under --fair Task an agent is enabled where it has a well-defined
    # move, and the failing move halts the run (in state 1 here, where n = 1 for ever)
    path = tmp_path / "FairFail.asm"
    path.write_text(FAIR_FAIL)
    code = main(["explore", str(path), "--fair", "Task", "--format", "json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 1
    assert (out["states"], out["transitions"]) == (2, 2)
    ltl = next(r for r in out["violations"] if r["property"] == "ltl_1")
    assert ltl["verdict"] == "violated" and ltl["fairness"] == ["weak fairness of every Task"]
    assert ltl["relative_to"].endswith("FairFail.asm:11:30")
    assert [[c["value"]["$t"] for c in s["choices"]] for s in ltl["trace"]] == [[], ["TB"]]
    assert [s["state"]["n"] for s in ltl["trace"]] == [0, 1]
    assert ltl["failing_step"]["choices"][0]["value"] == {"$t": "TA"}
    assert ltl["failing_message"] == "inconsistent update of x: 1 and 2"
