"""The simulator's rules as ASMETA's simulator (AsmetaS) applies them: reals, intervals,
choose over infinite domains, nondeterministic initial values, loops and limits."""
import pytest

from asmcheck.errors import AsmRuntimeError
from asmcheck.semantics.machine import RandomChooser

from helpers import machine, run, spec, view

pytestmark = pytest.mark.engines("both")


REALS = ("\tcontrolled a: Real\n\tcontrolled b: Real\n\tcontrolled c: Real\n\tcontrolled ia: Integer\n"
         "\tcontrolled ib: Integer\n\tcontrolled ic: Integer\n\tcontrolled id: Integer\n\tcontrolled fl: Integer\n"
         "\tcontrolled e1: Boolean\n\tcontrolled e2: Boolean\n\tcontrolled p: Real\n\tcontrolled s: String\n"
         "\tcontrolled m: Real\n\tcontrolled q: Real\n\tcontrolled z: Boolean")


def test_real_edge_cases_follow_javas_doubles(tmp_path):
    # AsmetaS: div is a double division, rtoi is Double.longValue(), floor narrows to int,
    # pwr is Math.pow, eq is Double.equals, max is Double.compareTo, toString is Double.toString
    m = machine(tmp_path, spec(REALS, "\tmain rule r_main = par\n"
                               "\t\ta := 1.0 / 0.0\n\t\tb := -1.0 / 0.0\n\t\tc := 0.0 / 0.0\n"
                               "\t\tia := rtoi(1.0 / 0.0)\n\t\tib := rtoi(-1.0 / 0.0)\n\t\tic := rtoi(0.0 / 0.0)\n"
                               "\t\tid := rtoi(-2.7)\n\t\tfl := floor(10000000000.0)\n"
                               "\t\te1 := (0.0 / 0.0) = (0.0 / 0.0)\n\t\te2 := (0.0 / 0.0) < 1.0\n"
                               "\t\tp := pwr(10.0, 400.0)\n\t\ts := toString(1.0 / 0.0)\n"
                               "\t\tm := max(1.0, 0.0 / 0.0)\n\t\tq := 1 / 0\n\t\tz := abs(0.0) = 0.0\n"
                               "\tendpar"))
    assert run(m) == {"a": "Infinity", "b": "-Infinity", "c": "NaN", "ia": "9223372036854775807",
                      "ib": "-9223372036854775808", "ic": "0", "id": "-2", "fl": "2147483647",
                      "e1": "true", "e2": "false", "p": "Infinity", "s": '"Infinity"', "m": "NaN",
                      "q": "Infinity", "z": "false"}


def test_real_interval_with_a_step_is_counted_in_decimal(tmp_path):
    # ASMETA's parser expands {0.6 : 0.9, 0.1} with BigDecimal (AsmetaParserUtility): 0.6, 0.7, 0.8, 0.9
    m = machine(tmp_path, spec("\tdomain D subsetof Real\n\tcontrolled x: D\n\tcontrolled n: Integer",
                               "\tdomain D = {0.6 : 0.9, 0.1}\n"
                               "\tmain rule r_main = par x := 0.9 n := size(D) endpar", "\tfunction x = 0.6"))
    assert run(m) == {"x": "0.9", "n": "4"}
    assert [repr(v) for v in m.domain_values(m.spec.functions[[f.name for f in m.spec.functions].index("x")]
                                             .codomain, None, None)] == ["0.6", "0.7", "0.8", "0.9"]
    m2 = machine(tmp_path, spec("\tcontrolled s: Seq(Real)", "\tmain rule r_main = s := [0.0 : 0.3, 0.1]"))
    assert run(m2) == {"s": "[0.0, 0.1, 0.2, 0.3]"}


LOOP = ("\tcontrolled n: Integer", "\tmain rule r_main =\n\t\twhile n < 20000 do\n\t\t\tn := n + 1", "\tfunction n = 0")


def test_while_bound_is_an_option_and_the_error_names_the_loop(tmp_path):
    m = machine(tmp_path, spec(*LOOP))
    with pytest.raises(AsmRuntimeError) as info:
        run(m)
    assert info.value.message == ("the while at S.asm:7:3 did not end after 10000 iterations in one step "
                                  "(raise the bound with --max-loop)")
    assert (info.value.span.line, info.value.span.col) == (7, 3)
    assert run(machine(tmp_path, spec(*LOOP), max_loop=30000)) == {"n": "20000"}


def test_a_deadline_stops_a_long_step(tmp_path):
    import time
    from asmcheck.semantics.machine import DeadlineReached
    m = machine(tmp_path, spec("\tcontrolled x: Integer\n\tcontrolled y: Integer",
                               "\tmain rule r_main =\n\t\tchoose $a in {0 : 100000}, $b in {0 : 100000} "
                               "with $a + $b = 200000 do par x := $a y := $b endpar"),
                deadline=time.monotonic() + 0.5)
    t0 = time.monotonic()
    with pytest.raises(DeadlineReached):
        m.successors(m.initial_state())
    assert time.monotonic() - t0 < 5
    # a while + extend step
    m = machine(tmp_path, spec("\tdynamic abstract domain Item\n\tcontrolled n: Integer",
                               "\tmain rule r_main =\n\t\twhile true do\n\t\t\textend Item with $i do n := n + 1",
                               "\tfunction n = 0"), max_loop=10 ** 9, deadline=time.monotonic() + 0.5)
    t0 = time.monotonic()
    with pytest.raises(DeadlineReached):
        run(m)
    assert time.monotonic() - t0 < 5


def test_a_failing_step_carries_its_inputs(tmp_path):
    from asmcheck.errors import InconsistentUpdate
    m = machine(tmp_path, spec("\tmonitored go: Boolean\n\tcontrolled x: Integer",
                               "\tmain rule r_main = par\n\t\tx := 1\n\t\tif go then x := 2 endif\n\tendpar"))
    with pytest.raises(InconsistentUpdate) as info:
        m.successors(m.initial_state())
    assert [(c.kind, c.label, c.value) for c in info.value.choices] == [("monitored", "go", True)]


CHOOSE_INF = ("\tcontrolled x: Integer\n\tcontrolled n: Natural\n\tcontrolled r: Real\n\tcontrolled k: Integer",
              "\tmain rule r_main = par\n"
              "\t\tchoose $i in Integer with true do x := $i\n"
              "\t\tchoose $j in Natural with true do n := $j\n"
              "\t\tchoose $q in Real with true do r := $q\n"
              "\t\tchoose $a in Integer, $b in {7, 8} with true do k := $b\n"
              "\tendpar")


def test_choose_over_an_infinite_domain_draws_in_a_simulation(tmp_path):
    # RuleEvaluator.visitChoose: a range over Integer, Natural or Real is an InfiniteCollection whose
    # getRndValue draws a 32-bit int, a Natural in [0, 2^31 - 1) or a Real in [0, 1); only with guard true
    import random
    from asmcheck.semantics.machine import DrawingChooser
    from asmcheck.simulate import simulate
    m = machine(tmp_path, spec(*CHOOSE_INF))
    rng = random.Random(1)
    want_x = rng.randrange(-(1 << 31), 1 << 31)
    want_n = rng.randrange(0, (1 << 31) - 1)
    want_r = rng.random()
    assert run(m, chooser_factory=lambda: DrawingChooser(1)) == {
        "x": str(want_x), "n": str(want_n), "r": repr(want_r), "k": "7"}
    runs = [[(s.number, sorted((str(k), str(v)) for k, v in s.changed.items())) for s in simulate(m, 3)]
            for _ in range(2)]
    assert runs[0] == runs[1] and len(runs[0]) == 4
    steps = list(simulate(m, 2, seed=5))
    assert [c.label for c in steps[1].choices] == ["choose at S.asm:10:3", "choose at S.asm:11:3",
                                                   "choose at S.asm:12:3", "choose at S.asm:13:3",
                                                   "choose at S.asm:13:3"]


def test_choose_over_an_infinite_domain_in_explore_asks_for_a_bound(tmp_path):
    from asmcheck.semantics.machine import Undetermined
    m = machine(tmp_path, spec(*CHOOSE_INF))
    with pytest.raises(Undetermined) as info:
        m.successors(m.initial_state())
    assert info.value.message.startswith("the domain Integer is infinite") and "--int-range" in info.value.message
    assert (info.value.span.line, info.value.span.col) == (10, 16)
    bounded = machine(tmp_path, spec("\tcontrolled x: Integer", "\tmain rule r_main = "
                                     "choose $i in Integer with true do x := $i"), int_range=(-1, 1))
    assert sorted(v["x"] for v in __import__("helpers").successor_views(bounded)) == ["-1", "0", "1"]


def test_choose_over_an_infinite_domain_with_a_guard_is_an_error(tmp_path):
    from asmcheck.semantics.machine import DrawingChooser
    m = machine(tmp_path, spec("\tcontrolled x: Integer", "\tmain rule r_main = "
                               "choose $i in Integer with $i > 0 do x := $i"))
    with pytest.raises(AsmRuntimeError) as info:
        run(m, chooser_factory=lambda: DrawingChooser(1))
    assert info.value.message.startswith("choose over the infinite domain Integer with a guard")
    assert (info.value.span.line, info.value.span.col) == (6, 47)


INIT_CHOICE = ("\tenum domain Account = {AA | BB}\n\tcontrolled balance: Account -> Integer\n"
               "\tcontrolled total: Integer\n\tcontrolled pick: Integer",
               "\tmain rule r_main = par total := balance(AA) + balance(BB) pick := chooseone({5, 6}) endpar",
               "\tfunction balance($a in Account) = chooseone({1000, 2000, 3000})\n\tfunction total = 0")


def test_nondeterministic_initial_values_explore_simulate_conform(tmp_path):
    from asmcheck.conform import conform, read_transcript
    from asmcheck.semantics.values import show
    from asmcheck.simulate import simulate
    from helpers import view
    m = machine(tmp_path, spec(*INIT_CHOICE))
    inits = m.initial_states()
    balances = sorted((view(m, st)["balance(AA)"], view(m, st)["balance(BB)"]) for _, st in inits)
    assert balances == [(a, b) for a in ("1000", "2000", "3000") for b in ("1000", "2000", "3000")]
    # simulate takes the first value, or a random one
    first = list(simulate(m, 1))
    assert [(c.kind, c.value) for c in first[0].choices] == [("chooseone", 1000), ("chooseone", 1000)]
    assert view(m, first[1].state)["total"] == "2000"
    drawn = {tuple(c.value for c in list(simulate(m, 0, seed=s))[0].choices) for s in range(12)}
    assert len(drawn) > 1 and drawn <= {(a, b) for a in (1000, 2000, 3000) for b in (1000, 2000, 3000)}
    # in a rule chooseone is a function (its first element), not a choice: one successor
    assert [view(m, nxt)["pick"] for _, _, nxt, _ in m.successors(inits[0][1])] == ["5"]
    # a transcript in which ASMETA drew 2000 (its hash order) conforms
    t = tmp_path / "s.trace"
    t.write_text("<State 1 (controlled)>\nbalance(AA)=2000\nbalance(BB)=2000\npick=5\ntotal=4000\n"
                 "</State 1 (controlled)>\n")
    assert conform(m, read_transcript(str(t))) is None
    t.write_text("<State 1 (controlled)>\nbalance(AA)=2000\nbalance(BB)=2000\npick=5\ntotal=4500\n"
                 "</State 1 (controlled)>\n")
    assert conform(m, read_transcript(str(t))) is not None


def test_a_property_over_an_infinite_domain_is_found_before_the_search(tmp_path):
    m = machine(tmp_path, spec("\tdomain Small subsetof Integer\n\tcontrolled x: Integer",
                               "\tdomain Small = {1 : 3}\n"
                               "\tinvariant inv_a over x: (forall $i in Integer with $i > x implies $i > 0)\n"
                               "\tinvariant inv_b over x: (exists $i in Small with $i = x + 1)\n"
                               "\tinvariant inv_c over x: (exists $r in Real with $r > 0.0)\n"
                               "\tmain rule r_main = x := 1", "\tfunction x = 0"))
    errs = m.unbounded_properties()
    assert [(e.span.line, e.span.col, e.message) for e in errs] == [
        (8, 40, "the property inv_a quantifies over Integer, which is infinite: asmcheck cannot evaluate it "
                "(bound the variable with a subset domain, or give --int-range LO..HI)"),
        (10, 40, "the property inv_c quantifies over Real, which is infinite: asmcheck cannot evaluate it "
                 "(bound the variable with a subset domain)")]
    bounded = machine(tmp_path, spec("\tcontrolled x: Integer", "\tinvariant inv_a over x: "
                                     "(forall $i in Integer with $i > x implies $i > 0)\n\tmain rule r_main = x := 1",
                                     "\tfunction x = 0"), int_range=(-2, 2))
    assert bounded.unbounded_properties() == []


def test_an_initial_value_that_reads_another_initial_value(tmp_path):
    # ASMETA's simulator computes an initial value when its location is first read, so
    # `currentState($m) = initialState($m)` sees initialState's initial value, whatever the order of
    # the lines; the choose over outgoing(currentState) then has a range (not undef)
    m = machine(tmp_path, spec("\tenum domain St = {SA | SB}\n\tenum domain Fsm = {MM}\n"
                               "\tcontrolled current: Fsm -> St\n\tcontrolled initial: Fsm -> St\n"
                               "\tcontrolled outgoing: St -> Powerset(St)",
                               "\tmain rule r_main = choose $t in outgoing(current(MM)) with true do current(MM) := $t",
                               "\tfunction current($m in Fsm) = initial($m)\n"
                               "\tfunction outgoing($s in St) = if $s = SA then {SB} else {SA} endif\n"
                               "\tfunction initial($m in Fsm) = SA"))
    st = m.initial_state()
    assert (view(m, st)["current(MM)"], view(m, st)["initial(MM)"]) == ("SA", "SA")
    assert [view(m, nxt)["current(MM)"] for _, _, nxt, _ in m.successors(st)] == ["SB"]


def test_a_location_read_at_an_undef_argument_takes_its_initial_value(tmp_path):
    # the simulator computes an initial value on a location's first read, for any arguments:
    # accessible(currCard) with currCard undef is true (function accessible($c in Card) = true)
    m = machine(tmp_path, spec("\tenum domain Card = {CA | CB}\n\tcontrolled cur: Card\n"
                               "\tcontrolled accessible: Card -> Boolean\n\tcontrolled seen: Boolean",
                               "\tmain rule r_main = if not(accessible(cur)) then seen := true else seen := false endif",
                               "\tfunction accessible($c in Card) = true"))
    assert run(m) == {"accessible(CA)": "true", "accessible(CB)": "true", "seen": "false"}


def test_a_monitored_argument_the_macro_does_not_use_is_not_read(tmp_path):
    # the simulator substitutes a macro's arguments into its body: a monitored location passed as
    # an argument is read only where the body uses it (no 'taking' line otherwise)
    m = machine(tmp_path, spec("\tmonitored cur: Integer\n\tcontrolled on: Boolean\n\tcontrolled y: Integer",
                               "\trule r_check($c in Integer) = if on then y := $c endif\n"
                               "\tmain rule r_main = r_check[cur]", "\tfunction on = false\n\tfunction y = 0"))
    assert [(log, view(m, nxt)) for log, _, nxt, _ in m.successors(m.initial_state())] == [
        ([], {"on": "false", "y": "0"})]
