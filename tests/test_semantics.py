"""Each rule and term form, through the one step function."""
import pytest

from asmcheck.errors import AsmRuntimeError, InconsistentUpdate
from asmcheck.semantics.machine import RandomChooser

from helpers import machine, run, spec, successor_views, view
from asmcheck.semantics.printer import location_text

pytestmark = pytest.mark.engines("none")


def test_par_collects_updates_and_same_value_is_fine(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer\n\tcontrolled y: Integer",
                               "\tmain rule r_main = par x := 1 y := 2 x := 1 endpar"))
    assert run(m) == {"x": "1", "y": "2"}


def test_inconsistent_update_names_location_values_and_both_positions(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = par\n\t\tx := 1\n\t\tx := 2\n\tendpar"))
    with pytest.raises(InconsistentUpdate) as info:
        run(m)
    err = info.value
    assert err.message == "inconsistent update of x: 1 and 2"
    assert (err.span.line, err.span.col) == (8, 3)
    assert err.notes[0][0].line == 7
    assert "x := 1 is here" in err.render()


def test_seq_later_rules_see_earlier_updates_and_override(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer\n\tcontrolled y: Integer\n\tcontrolled z: Integer",
                               "\tmain rule r_main = seq\n\t\tx := 1\n\t\tpar y := x + 1 z := x endpar\n"
                               "\t\tx := 5\n\tendseq", "\tfunction x = 0"))
    assert run(m) == {"x": "5", "y": "2", "z": "1"}


def test_seq_inside_par_still_clashes_with_a_sibling(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = par\n\t\tseq x := 1 x := 2 endseq\n\t\tx := 1\n\tendpar"))
    with pytest.raises(InconsistentUpdate):
        run(m)


def test_if_else_and_undef_guard_is_an_error(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer\n\tcontrolled b: Boolean",
                               "\tmain rule r_main = if b then x := 1 else x := 2 endif", "\tfunction b = false"))
    assert run(m) == {"b": "false", "x": "2"}
    m = machine(tmp_path, spec("\tcontrolled x: Integer\n\tcontrolled b: Boolean",
                               "\tmain rule r_main = if b then x := 1 endif"))
    with pytest.raises(AsmRuntimeError) as info:
        run(m)
    assert "undef" in info.value.message and info.value.span.line == 7


def test_three_valued_logic_and_undef_arithmetic(tmp_path):
    m = machine(tmp_path, spec(
        "\tcontrolled u: Boolean\n\tcontrolled n: Integer\n\tcontrolled r1: Boolean\n\tcontrolled r2: Boolean\n"
        "\tcontrolled r3: Boolean\n\tcontrolled r4: Boolean\n\tcontrolled r5: Integer\n\tcontrolled r6: Boolean",
        "\tmain rule r_main = par\n\t\tr1 := false and u\n\t\tr2 := true or u\n\t\tr3 := true and u\n"
        "\t\tr4 := isUndef(u)\n\t\tr5 := n + 1\n\t\tr6 := (n = undef)\n\tendpar"))
    assert run(m) == {"r1": "false", "r2": "true", "r4": "true", "r6": "true"}


def test_switch_rule_and_term_without_match(tmp_path):
    m = machine(tmp_path, spec(
        "\tenum domain C = {AA | BB | CC}\n\tcontrolled c: C\n\tcontrolled x: Integer\n\tcontrolled y: Integer",
        "\tmain rule r_main = par\n\t\tswitch c case AA: x := 1 case BB: x := 2 otherwise x := 3 endswitch\n"
        "\t\ty := switch c case AA: 10 endswitch\n\tendpar", "\tfunction c = BB"))
    assert run(m) == {"c": "BB", "x": "2"}


def test_let_bindings_are_sequential(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = let ($a = 3, $b = $a + 1) in x := $a * $b endlet"))
    assert run(m) == {"x": "12"}


def test_choose_branches_over_every_value_and_ifnone(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = choose $v in {1, 2, 3} with $v > 1 do x := $v ifnone x := 0"))
    assert successor_views(m) == [{"x": "2"}, {"x": "3"}]
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = choose $v in {1, 2, 3} with $v > 5 do x := $v ifnone x := 0"))
    assert successor_views(m) == [{"x": "0"}]


def test_choose_alternatives_with_the_same_effect_are_one_successor(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = choose $v in {1 : 10} with true do if $v < 4 then x := 1 endif"))
    assert successor_views(m) == [{"x": "1"}, {}]


def test_forall_and_multiple_variables(tmp_path):
    m = machine(tmp_path, spec("\tdomain Small subsetof Integer\n\tcontrolled f: Prod(Small, Small) -> Integer",
                               "\tdomain Small = {0 : 1}\n"
                               "\tmain rule r_main = forall $i in Small, $j in Small with $i <= $j do f($i, $j) := $i + $j"))
    assert run(m) == {"f(0, 0)": "0", "f(0, 1)": "1", "f(1, 1)": "2"}


def test_extend_makes_fresh_elements_numbered_per_domain(tmp_path):
    m = machine(tmp_path, spec("\tdynamic abstract domain Item\n\tcontrolled owner: Item -> Integer\n"
                               "\tcontrolled count: Integer",
                               "\tmain rule r_main = extend Item with $a, $b do par owner($a) := 1 owner($b) := 2 "
                               "count := size(Item) endpar"))
    after1 = run(m, 1)
    assert after1 == {"Item": "{Item!1, Item!2}", "owner(Item!1)": "1", "owner(Item!2)": "2", "count": "0"}
    after2 = run(m, 2)
    assert after2["Item"] == "{Item!1, Item!2, Item!3, Item!4}" and after2["count"] == "2"


def test_macro_arguments_are_passed_by_name(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled f: Integer\n\tcontrolled y: Integer",
                               "\tmacro rule r_m($x in Integer) = seq f := 5 y := $x endseq\n"
                               "\tmacro rule r_set($l in Integer, $v in Integer) = $l := $v\n"
                               "\tmain rule r_main = r_m[f]",
                               "\tfunction f = 1"))
    assert run(m) == {"f": "5", "y": "5"}
    m = machine(tmp_path, spec("\tcontrolled f: Integer",
                               "\tmacro rule r_set($l in Integer, $v in Integer) = $l := $v\n"
                               "\tmain rule r_main = r_set[f, 7]"))
    assert run(m) == {"f": "7"}


def test_turbo_call_by_value_and_return_through_result(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled f: Integer\n\tcontrolled y: Integer",
                               "\tturbo rule r_t($x in Integer) = seq f := 5 y := $x endseq\n"
                               "\tturbo rule r_sq($x in Integer) in Integer = result := $x * $x\n"
                               "\tmain rule r_main = seq r_t(f) f <- r_sq(4) endseq",
                               "\tfunction f = 1"))
    out = run(m)
    assert out["y"] == "1" and out["f"] == "16" and out["result"] == "16"


def test_while_and_iterate(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = while x < 5 do x := x + 1", "\tfunction x = 0"))
    assert run(m) == {"x": "5"}
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = iterate if x < 3 then x := x + 1 endif enditerate",
                               "\tfunction x = 0"))
    assert run(m) == {"x": "3"}


def test_monitored_functions_are_inputs_over_their_domain(tmp_path):
    m = machine(tmp_path, spec("\tenum domain C = {AA | BB | CC}\n\tmonitored m: C\n\tmonitored b: Boolean\n"
                               "\tcontrolled x: C",
                               "\tmain rule r_main = if b then x := m endif"))
    assert successor_views(m) == [{}, {"x": "AA"}, {"x": "BB"}, {"x": "CC"}]


def test_monitored_integer_needs_a_bound(tmp_path):
    from asmcheck.semantics.machine import Undetermined
    text = spec("\tmonitored m: Integer\n\tcontrolled x: Integer", "\tmain rule r_main = x := m")
    with pytest.raises(Undetermined) as info:
        successor_views(machine(tmp_path, text))
    assert "--monitored m=LO..HI" in info.value.message
    m = machine(tmp_path, text, monitored_ranges={"m": [1, 2]})
    assert successor_views(m) == [{"x": "1"}, {"x": "2"}]


def test_derived_static_and_agents(tmp_path):
    m = machine(tmp_path, spec(
        "\tdomain Worker subsetof Agent\n\tstatic w1: Worker\n\tstatic w2: Worker\n"
        "\tcontrolled cnt: Worker -> Integer\n\tderived total: Integer\n\tstatic two: Integer",
        "\tfunction two = 2\n\tfunction total = cnt(w1) + cnt(w2)\n"
        "\trule r_work = cnt(self) := cnt(self) + two\n"
        "\tmain rule r_main = forall $w in Worker do program($w)",
        "\tfunction cnt($w in Worker) = 0\n\tagent Worker: r_work[]"))
    assert run(m) == {"cnt(w1)": "2", "cnt(w2)": "2"}


def test_step_chooses_the_agent_to_run(tmp_path):
    m = machine(tmp_path, spec(
        "\tdomain Worker subsetof Agent\n\tstatic w1: Worker\n\tstatic w2: Worker\n"
        "\tcontrolled cnt: Worker -> Integer",
        "\trule r_work = cnt(self) := cnt(self) + 1\n"
        "\tmain rule r_main = choose $w in Worker with true do program($w)",
        "\tfunction cnt($w in Worker) = 0\n\tagent Worker: r_work[]"))
    assert successor_views(m) == [{"cnt(w1)": "1", "cnt(w2)": "0"}, {"cnt(w1)": "0", "cnt(w2)": "1"}]


def test_value_out_of_a_subset_domain_is_a_runtime_error(tmp_path):
    m = machine(tmp_path, spec("\tdomain Small subsetof Integer\n\tcontrolled s: Small",
                               "\tdomain Small = {0 : 3}\n\tmain rule r_main = s := s + 1", "\tfunction s = 3"))
    with pytest.raises(AsmRuntimeError) as info:
        run(m)
    assert "out of domain" in info.value.message


def test_integers_wrap_around_like_javas_long(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = x := x * 10", "\tfunction x = 1000000000000000000"))
    assert run(m) == {"x": str(10 ** 19 - 2 ** 64)}


def test_library_functions(tmp_path):
    m = machine(tmp_path, spec(
        "\tcontrolled s: Seq(Integer)\n\tcontrolled t: Powerset(Integer)\n\tcontrolled a: Integer\n"
        "\tcontrolled b: Integer\n\tcontrolled c: Natural\n\tcontrolled d: Seq(String)\n\tcontrolled e: Real",
        "\tmain rule r_main = par\n\t\ts := append(excluding([1, 2, 1, 3], 1), 9)\n"
        "\t\tt := union(difference({1, 2, 3}, {2}), {7})\n\t\ta := -7 mod 3\n\t\tb := idiv(-7, 2)\n"
        "\t\tc := iton(length([1, 2, 3]))\n\t\td := split(\"a b c\", \" \")\n\t\te := 7 / 2\n\tendpar"))
    assert run(m) == {"s": "[2, 1, 3, 9]", "t": "{1, 3, 7}", "a": "-1", "b": "-3", "c": "3",
                      "d": '["a", "b", "c"]', "e": "3.5"}


def test_random_simulation_is_reproducible(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled x: Integer",
                               "\tmain rule r_main = choose $v in {1 : 100} with true do x := $v"), dedupe=False)
    a = run(m, 3, lambda: RandomChooser(7))
    b = run(m, 3, lambda: RandomChooser(7))
    assert a == b


def test_two_local_functions_are_two_locations(tmp_path):
    # each local function has its own number: x and y do not share one location
    m = machine(tmp_path, spec("\tcontrolled a: Integer\n\tcontrolled b: Integer",
                               "\trule r_two =\n\t\tlocal x : Integer [ x := 1 ]\n\t\tlocal y : Integer [ y := 2 ]\n"
                               "\t\tpar\n\t\t\ta := x\n\t\t\tb := y\n\t\tendpar\n\tmain rule r_main = r_two[]",
                               "\tfunction a = 0\n\tfunction b = 0"))
    assert run(m) == {"a": "1", "b": "2"}


def test_updates_of_a_local_function_stay_in_its_rule(tmp_path):
    # x := 7 is made within the local rule (a reads the initial 1, in parallel) and is not a
    # location of the next state
    m = machine(tmp_path, spec("\tcontrolled a: Integer",
                               "\trule r_one =\n\t\tlocal x : Integer [ x := 1 ]\n"
                               "\t\tpar\n\t\t\tx := 7\n\t\t\ta := x\n\t\tendpar\n\tmain rule r_main = r_one[]",
                               "\tfunction a = 0"))
    st = m.initial_state()
    (log, ups, nxt, mon), = m.successors(st)
    assert nxt == {k: v for k, v in nxt.items() if location_text(m, k) == "a"}
    assert view(m, nxt) == {"a": "1"}


def test_a_recursive_turbo_rule_has_its_own_local_per_call(tmp_path):
    # the factorial of 5 through a local x per call (an inner call's x := ... is not the outer's)
    m = machine(tmp_path, spec("\tcontrolled valore: Integer\n\tcontrolled fact: Integer",
                               "\tturbo rule r_fact($n in Integer) in Integer =\n"
                               "\t\tlocal x : Integer [ x := 1 ]\n"
                               "\t\tif $n = 1 then result := 1\n"
                               "\t\telse seq\n\t\t\tx <- r_fact($n - 1)\n\t\t\tresult := $n * x\n\t\tendseq endif\n"
                               "\tmain rule r_main = fact <- r_fact(valore)",
                               "\tfunction valore = 5\n\tfunction fact = 0"))
    out = run(m)
    assert (out["valore"], out["fact"]) == ("5", "120")
    assert "x" not in out


def test_an_inconsistent_update_of_a_local_function_names_it(tmp_path):
    m = machine(tmp_path, spec("\tcontrolled a: Integer",
                               "\trule r_one =\n\t\tlocal x : Integer [ x := 1 ]\n"
                               "\t\tpar\n\t\t\tx := 7\n\t\t\tx := 8\n\t\tendpar\n\tmain rule r_main = r_one[]",
                               "\tfunction a = 0"))
    with pytest.raises(InconsistentUpdate) as info:
        run(m)
    assert info.value.message == "inconsistent update of x: 7 and 8"


def test_a_product_domain_follows_a_factor_that_extend_grows(tmp_path):
    # the values of Prod(Item, Boolean) are kept between reads; an extend of Item gives new ones
    m = machine(tmp_path, spec("\tdynamic abstract domain Item\n\tmonitored pick: Prod(Item, Boolean)\n"
                               "\tcontrolled flag: Boolean",
                               "\tmain rule r_main = par extend Item with $a do skip "
                               "if size(Item) > 0 then flag := second(pick) endif endpar"))
    st = m.initial_states()[0][1]
    counts = []
    for _ in range(4):
        succ = m.successors(st)
        counts.append(len(succ))
        st = succ[0][2]
    assert counts == [1, 2, 4, 6]
