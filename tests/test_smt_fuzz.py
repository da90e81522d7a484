"""Differential tests: Z3 bounded model checking against explicit search on small random ASMs.

Hypothesis writes tiny specs over Boolean, enum and small-integer locations (with undef,
a function over an enum, a monitored input, derived functions, a macro) whose main rule
nests par / seq / if / switch / let / choose / forall, with invariants and step properties
(next, updated, changed).  Both engines must give every property the same first violation
depth (run-time errors included) up to the same bound.
"""
import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as st

from asmcheck.smt.differential import agree, explicit_depths, z3_depths

# Z3 against the Python explorer (explore.bfs.Explorer, whatever ASMCHECK_ENGINE says): one run,
# the examples being derandomized (a second run on [auto] made the same ones)
pytestmark = pytest.mark.engines("python")

DEPTH = 4
ENUM = ["AA", "BB", "CC"]


class Gen:
    def __init__(self, draw):
        self.draw = draw
        self.n = 0

    def pick(self, items):
        return items[self.draw(st.integers(0, len(items) - 1))]

    def fresh(self):
        self.n += 1
        return f"$v{self.n}"

    # terms ---------------------------------------------------------------
    def bterm(self, d, env):
        leaves = ["b0", "b1", "m0", "true", "false", "dflag", "isDef(b1)", "isUndef(b1)"]
        if d <= 0:
            return self.pick(leaves)
        k = self.draw(st.integers(0, 13))
        if k <= 2:
            return self.pick(leaves)
        if k == 3:
            return f"f({self.earg(env)})"
        if k == 4:
            return f"not({self.bterm(d - 1, env)})"
        if k == 5:
            return f"({self.bterm(d - 1, env)} {self.pick(['and', 'or', 'implies'])} {self.bterm(d - 1, env)})"
        if k == 6:
            return f"({self.eterm(d - 1, env)} {self.pick(['=', '!='])} {self.eterm(d - 1, env)})"
        if k == 7:
            return f"({self.iterm(d - 1, env)} {self.pick(['<', '<=', '='])} {self.iterm(d - 1, env)})"
        if k == 8:
            v = self.fresh()
            q = self.pick(["exists", "forall"])
            return f"({q} {v} in E with {self.bterm(d - 1, {**env, v: 'E'})})"
        if k == 9:
            return f"dsel({self.earg(env)})"
        if k == 10:
            return f"if {self.bterm(d - 1, env)} then {self.bterm(d - 1, env)} else {self.bterm(d - 1, env)} endif"
        if k == 11:
            v = self.fresh()
            return f"(exist unique {v} in S with g({v}) = {self.pick(ENUM)})"
        if k == 12:
            vs = [x for x, t in env.items() if t == "E"]
            return f"f({vs[0]})" if vs else "b0"
        return f"(switch e0 case AA: {self.bterm(d - 1, env)} otherwise {self.bterm(d - 1, env)} endswitch)"

    def earg(self, env):
        vs = [x for x, t in env.items() if t == "E"]
        return self.pick(vs + ENUM + ["e0"])

    def iarg(self, env):
        vs = [x for x, t in env.items() if t == "S"]
        return self.pick(vs + ["0", "1", "2", "3", "n0"])

    def eterm(self, d, env):
        k = self.draw(st.integers(0, 4 if d > 0 else 1))
        if k == 0:
            return self.earg(env)
        if k == 1:
            return self.pick(ENUM + ["e0"])
        if k == 2:
            return f"g({self.iarg(env)})"
        return f"if {self.bterm(d - 1, env)} then {self.eterm(d - 1, env)} else {self.eterm(d - 1, env)} endif"

    def iterm(self, d, env):
        k = self.draw(st.integers(0, 4 if d > 0 else 1))
        if k <= 1:
            return self.iarg(env)
        if k == 2:
            return f"({self.iterm(d - 1, env)} + 1)"
        if k == 3:
            return f"(({self.iterm(d - 1, env)} + 1) mod 4)"
        return f"({self.iterm(d - 1, env)} - 1)"

    # rules ---------------------------------------------------------------
    def rule(self, d, env, macro=True):
        k = self.draw(st.integers(0, 6 if d <= 0 else 18))
        if k == 0:
            return f"b0 := {self.bterm(1, env)}"
        if k == 1:
            return f"b1 := {self.pick([self.bterm(1, env), 'undef'])}"
        if k == 2:
            return f"e0 := {self.eterm(1, env)}"
        if k == 3:
            return f"n0 := {self.iterm(1, env)}"
        if k == 4:
            return f"f({self.earg(env)}) := {self.bterm(1, env)}"
        if k == 5:
            return f"g({self.iarg(env)}) := {self.eterm(1, env)}"
        if k == 6:
            return "skip"
        if k in (7, 8):
            n = self.draw(st.integers(2, 3))
            return "par " + " ".join(self.rule(d - 1, env, macro) for _ in range(n)) + " endpar"
        if k == 9:
            return "seq " + " ".join(self.rule(d - 1, env, macro) for _ in range(2)) + " endseq"
        if k in (10, 11):
            other = f" else {self.rule(d - 1, env, macro)}" if self.draw(st.booleans()) else ""
            return f"if {self.bterm(2, env)} then {self.rule(d - 1, env, macro)}{other} endif"
        if k == 12:
            v = self.fresh()
            env2 = {**env, v: "E"}
            guard = f" with {self.bterm(2, env2)}" if self.draw(st.booleans()) else ""
            ifnone = f" ifnone {self.rule(0, env, macro)}" if self.draw(st.booleans()) else ""
            return f"choose {v} in E{guard} do {self.rule(d - 1, env2, macro)}{ifnone}"
        if k == 13:
            v = self.fresh()
            env2 = {**env, v: "S"}
            return f"forall {v} in S with {self.bterm(1, env2)} do {self.rule(d - 1, env2, macro)}"
        if k == 14:
            return (f"switch e0 case AA: {self.rule(d - 1, env, macro)} case BB: {self.rule(d - 1, env, macro)} "
                    f"otherwise {self.rule(d - 1, env, macro)} endswitch")
        if k == 15 or k == 16 and not macro:
            v = self.fresh()
            return f"let ({v} = {self.iterm(1, env)}) in {self.rule(d - 1, {**env, v: 'S'}, macro)} endlet"
        if k == 17:
            # terminates: n0 grows (or the par clashes)
            return f"while ({self.bterm(1, env)}) and n0 < 3 do par n0 := n0 + 1 {self.rule(0, env, macro)} endpar"
        if k == 18:
            val = self.pick(["true", "false"])
            return f"iterate if n0 > 0 and {self.bterm(1, env)} then par n0 := n0 - 1 b1 := {val} endpar endif enditerate"
        if macro:
            return f"r_m[{self.earg(env)}]"
        return "skip"


def make_spec(draw):
    g = Gen(draw)
    b0 = g.pick(["true", "false"])
    e0 = g.pick(ENUM)
    n0 = g.pick(["0", "1", "2"])
    b1 = draw(st.sampled_from([None, "true", "false"]))
    macro_body = g.rule(1, {"$p": "E"}, macro=False)
    main = g.rule(3, {})
    if draw(st.booleans()):
        # a counter that walks through the states, so violations happen deeper
        main = f"par {main} if {g.bterm(1, {})} then n0 := (n0 + 1) mod 4 endif endpar"
    invs = []
    for _ in range(draw(st.integers(1, 2))):
        k = draw(st.integers(0, 4))
        if k == 0:
            invs.append(g.bterm(2, {}))
        elif k == 1:
            invs.append(f"n0 != {g.pick([x for x in '0123' if x != n0])}")
        elif k == 2:
            invs.append(f"e0 != {g.pick([x for x in ENUM if x != e0])}")
        elif k == 3:
            invs.append(f"(g({g.pick('0123')}) != {g.pick(ENUM)} or {g.bterm(1, {})})")
        else:
            invs.append(f"({g.bterm(1, {})} implies n0 < {g.pick('123')})")
    steps = []
    if draw(st.booleans()):
        cand = [f"({g.bterm(1, {})} implies next({g.bterm(1, {})}))", "not updated(e0)",
                "changed(n0) implies n0 < 2", "not (updated(b0) and not changed(b0))",
                f"updated(f({g.pick(ENUM)})) implies next(b0)", "next(e0) != CC or e0 = CC"]
        steps = [g.pick(cand)]
    lines = ["asm Fz", "import StandardLibrary", "signature:",
             "\tenum domain E = {AA | BB | CC}", "\tdomain S subsetof Integer",
             "\tdynamic controlled b0: Boolean", "\tdynamic controlled b1: Boolean",
             "\tdynamic controlled e0: E", "\tdynamic controlled n0: S",
             "\tdynamic controlled f: E -> Boolean", "\tdynamic controlled g: S -> E",
             "\tdynamic monitored m0: Boolean",
             "\tderived dflag: Boolean", "\tderived dsel: E -> Boolean",
             "definitions:", "\tdomain S = {0 : 3}",
             "\tfunction dflag = (b0 and e0 = AA)",
             "\tfunction dsel($a in E) = (f($a) or $a = e0)",
             f"\trule r_m($p in E) = {macro_body}"]
    for i, t in enumerate(invs):
        lines.append(f"\tinvariant inv_{i} over b0: {t}")
    lines += [f"\tmain rule r_main = {main}", "default init s0:",
              f"\tfunction b0 = {b0}", f"\tfunction e0 = {e0}", f"\tfunction n0 = {n0}",
              f"\tfunction f($x in E) = ($x = {g.pick(ENUM)})",
              f"\tfunction g($y in S) = {g.pick(ENUM)}"]
    if b1 is not None:
        lines.append(f"\tfunction b1 = {b1}")
    spec = "\n".join(lines) + "\n"
    props = None
    if steps:
        props = "applies to Fz\n" + "".join(f"step stp_{i}: {t}\n" for i, t in enumerate(steps))
    return spec, props


def check_one(tmp_path, spec, props):
    path = tmp_path / "Fz.asm"
    path.write_text(spec)
    files = None
    if props is not None:
        pf = tmp_path / "fz.prop"
        pf.write_text(props)
        files = [str(pf)]
    ex = explicit_depths(str(path), DEPTH, files, use_default=False)
    z = z3_depths(str(path), DEPTH, files, use_default=False)
    diff = agree(ex, z)
    assert diff is None, f"{diff}\n--- spec\n{spec}\n--- properties\n{props}"
    return ex, z


FUZZ = settings(max_examples=25, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                     HealthCheck.filter_too_much])


@FUZZ
@given(st.data())
def test_random_specs_agree(tmp_path, data):
    spec, props = make_spec(data.draw)
    check_one(tmp_path, spec, props)


@FUZZ
@given(st.data())
def test_random_specs_agree_with_symbolic_integers(tmp_path, data):
    # every integer range read as a bit-vector term (normally only ranges of more than 8 values)
    from asmcheck.smt import sym
    saved = sym.SYM_MIN
    sym.SYM_MIN = 0
    try:
        spec, props = make_spec(data.draw)
        check_one(tmp_path, spec, props)
    finally:
        sym.SYM_MIN = saved


@pytest.mark.slow
@settings(max_examples=80, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                     HealthCheck.filter_too_much])
@given(st.data())
def test_random_specs_agree_more(tmp_path, data):
    spec, props = make_spec(data.draw)
    check_one(tmp_path, spec, props)


def check_induction(tmp_path, spec, props, k, infer):
    """k-induction never proves what explicit search refutes, and finds violations at the
    explorer's depth."""
    from asmcheck.explore.bfs import Explorer
    from asmcheck.smt.bmc import Model, run_induction
    from asmcheck.smt.differential import load

    path = tmp_path / "Fz.asm"
    path.write_text(spec)
    files = None
    if props is not None:
        pf = tmp_path / "fz.prop"
        pf.write_text(props)
        files = [str(pf)]
    _, machine, sp, stp = load(str(path), files, use_default=False)
    ex = Explorer(machine, state_props=sp, step_props=stp, max_states=4_000)
    res = ex.run()
    assume(res.verdict != "incomplete" or res.violations)
    bad = {v.prop.name: (ex.depth_of[v.source] + 1 if v.source >= 0 else ex.depth_of[v.state])
           for v in res.violations}
    _, machine, sp, stp = load(str(path), files, use_default=False)
    model = Model(machine, sp, stp)
    names = [p.name for p in model.props]
    out = run_induction(model, k, targets=names, infer=infer, prefilter_seconds=0.5)
    for name, verdict in out.verdicts.items():
        if verdict == "proved":
            assert name not in bad, f"{name} proved, but explicit search violates it at depth {bad[name]}\n{spec}"
            if name == "error" or "error" not in bad:
                assert res.verdict == "holds" or name not in bad
        if verdict == "violated" and "error" not in bad and "error" not in out.depths:
            assert bad.get(name) == out.depths[name], f"{name}\n{spec}\n{props}"


@FUZZ
@given(st.data())
def test_random_specs_induction_is_sound(tmp_path, data):
    spec, props = make_spec(data.draw)
    check_induction(tmp_path, spec, props, 2, infer=False)


@pytest.mark.slow
@settings(max_examples=12, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                     HealthCheck.filter_too_much])
@given(st.data())
def test_random_specs_induction_with_lemmas_is_sound(tmp_path, data):
    spec, props = make_spec(data.draw)
    check_induction(tmp_path, spec, props, 2, infer=True)
