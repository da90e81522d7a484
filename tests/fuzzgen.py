"""Random small AsmetaL specs for the differential test of the native engine against the Python
engine (tests/test_native_fuzz.py, scripts/fuzz_native.py).

``spec(seed)`` gives one spec, the same for the same seed: an enum domain, an Integer subset, a
few controlled functions (0-ary and unary, Boolean, enum, Integer-subset and Integer valued; by
the seed's draw also a sequence, a set, a pair, a dynamic abstract domain grown by extend, two
agents running one program), monitored inputs, a derived function, a macro rule, and a main rule
built from every rule form the generator knows (update, par, seq, if, switch, let, choose with
and without ifnone, forall, while, macro call, program of an agent, extend, skip) and terms
(arithmetic with negative operands, quantifiers, let, switch, comprehension), with invariants
(one may read a monitored function), JUSTICE, and CTL/LTL properties over the state.  Terms are well typed; values may still leave a domain, and updates
may clash: those are run-time errors both engines must report alike.
"""
from __future__ import annotations

import random

ENUM = ("AA", "BB", "CC")
DMAX = 3            # domain D = {0 : DMAX}


class Gen:
    def __init__(self, seed: int):
        self.r = random.Random(seed)
        r = self.r
        self.seq = r.random() < 0.35          # a Seq(E) location
        self.ext = r.random() < 0.2           # an abstract domain grown by extend
        self.mon = r.random() < 0.6           # monitored inputs
        self.intc = r.random() < 0.4          # an Integer counter (bounded by mod)
        self.sets = r.random() < 0.35         # a Powerset(Col) location
        self.tup = r.random() < 0.3           # a Prod(Col, Num) location
        self.agents = r.random() < 0.3        # two agents running one program (self)
        self.arith = r.random() < 0.4         # negative operands of mod/idiv, abs, min, max
        self.in_agent = False
        self.terms = r.random() < 0.4         # let, switch and comprehension terms, quantifiers over Num
        self.fair = r.random() < 0.25         # a JUSTICE constraint
        self.turbo = r.random() < 0.3         # a turbo rule returning a value (loc <- r_t(a))
        self.undef = r.random() < 0.3         # a location set to undef and tested for it
        self.maps = r.random() < 0.25         # a Map(Col, Num) location
        self.strs = r.random() < 0.2          # a String location
        self.reals = r.random() < 0.2         # a Real location
        self.bags = r.random() < 0.2          # a Bag(Col) location
        self.bound: list[tuple[str, str]] = []    # ($var, type) in scope
        self.in_macro = False                      # (the macro calls no macro: no recursion)

    # -- terms ---------------------------------------------------------------------------
    def pick(self, xs):
        return xs[self.r.randrange(len(xs))]

    def var(self, typ: str):
        vs = [v for v, t in self.bound if t == typ]
        return self.pick(vs) if vs and self.r.random() < 0.6 else None

    def e(self, d: int = 0) -> str:
        r = self.r
        v = self.var("E")
        if v:
            return v
        k = r.randrange(5 if d < 2 else 3)
        if k == 0:
            return self.pick(ENUM)
        if k == 1:
            return "c"
        if k == 2:
            return "he(" + self.pick(ENUM) + ")"
        if k == 3:
            return f"if {self.b(d + 1)} then {self.e(d + 1)} else {self.e(d + 1)} endif"
        if self.tup and r.random() < 0.4:
            return "first(pr)"
        if self.seq and r.random() < 0.4:
            # (undef on an empty sequence or out of range: an error where a value is needed)
            return self.pick(["first(sq)", "last(sq)", f"at(sq, {r.randint(0, 2)}n)"])
        return "mE" if self.mon else "c"

    def dterm(self, d: int = 0) -> str:
        """A term of the domain D (an Integer between 0 and DMAX), or one that may leave it."""
        r = self.r
        v = self.var("D")
        if v:
            return v
        k = r.randrange(8 if d < 2 else 4)
        if k == 0:
            return str(r.randint(0, DMAX))
        if k == 1:
            return "x"
        if k == 2:
            return "y"
        if k == 3:
            return f"fv({self.e(d + 1)})"
        if k == 4:
            return f"({self.dterm(d + 1)} + {self.dterm(d + 1)}) mod {DMAX + 1}"
        if k == 5:
            return f"({self.dterm(d + 1)} * {self.dterm(d + 1)}) mod {DMAX + 1}"
        if k == 6:
            return f"dd({self.e(d + 1)})"
        if k == 7 and self.arith and r.random() < 0.6:
            a, b = self.dterm(d + 1), self.dterm(d + 1)
            return self.pick([f"({a} - {b} - 1) mod {DMAX + 1}", f"abs({a} - {b})", f"min({a}, {b})",
                              f"max({a}, {b})", f"idiv({a} - {b}, 2) + 1", f"({a} - {b}) mod {DMAX + 1}"])
        if k == 7 and self.terms and r.random() < 0.6:
            v = f"$k{d}"
            a = self.dterm(d + 1)
            k2 = r.randrange(3)
            if k2 == 0:
                self.bound.append((v, "D"))
                body = self.dterm(d + 1)
                self.bound.pop()
                return f"let ({v} = {a}) in ({body} + {v}) mod {DMAX + 1} endlet"
            if k2 == 1:
                return f"switch {self.e(d + 1)} case AA: {a} case BB: {self.dterm(d + 1)} otherwise 0 endswitch"
            return f"size({{$s{d} in Col | gb($s{d}) : $s{d}}})"
        if k == 7 and self.maps and r.random() < 0.5:
            return f"at(mp, {self.e(d + 1)})"          # (undef where the map has no such key)
        if k == 7 and self.bags and r.random() < 0.5:
            return f"ntoi(count(bg, {self.e(d + 1)}))"
        if k == 7 and self.tup and r.random() < 0.5:
            return "second(pr)"
        if k == 7 and self.in_agent and r.random() < 0.5:
            return "wpos(self)"
        return f"if {self.b(d + 1)} then {self.dterm(d + 1)} else {self.dterm(d + 1)} endif"

    def b(self, d: int = 0) -> str:
        r = self.r
        v = self.var("B")
        if v and r.random() < 0.5:
            return v
        k = r.randrange(11 if d < 2 else 5)
        if k == 0:
            return "bb"
        if k == 1:
            return f"gb({self.e(d + 1)})"
        if k == 2:
            return f"{self.dterm(d + 1)} {self.pick(['=', '!=', '<', '<=', '>', '>='])} {self.dterm(d + 1)}"
        if k == 3:
            return f"{self.e(d + 1)} {self.pick(['=', '!='])} {self.e(d + 1)}"
        if k == 4:
            return ("mB" if self.mon else "bb")
        if k == 5:
            return f"not({self.b(d + 1)})"
        if k == 6:
            return f"({self.b(d + 1)} {self.pick(['and', 'or', 'xor', 'implies', 'iff'])} {self.b(d + 1)})"
        if k == 7:
            q = self.pick(["forall", "exist", "exist unique"])
            v = f"$q{d}"
            self.bound.append((v, "E"))
            body = self.b(d + 1)
            self.bound.pop()
            return f"({q} {v} in Col with {body})"
        if k == 8 and self.terms and r.random() < 0.4:
            v = f"$r{d}"
            self.bound.append((v, "D"))
            body = self.b(d + 1)
            self.bound.pop()
            return f"({self.pick(['exist', 'forall'])} {v} in Num with {body})"
        if k == 8 and self.seq:
            return self.pick([f"length(sq) {self.pick(['<', '>=', '='])} {r.randint(0, 2)}",
                              f"contains(sq, {self.e(d + 1)})", f"count(sq, {self.e(d + 1)}) > 0",
                              f"indexOf(sq, {self.e(d + 1)}) >= 0"])
        if k == 9 and self.undef and r.random() < 0.5:
            return self.pick(["y = undef", "y != undef", f"(y = undef or y < {r.randint(1, DMAX)})",
                              f"(y != undef and y > {r.randint(0, 2)})"])
        if k == 9 and self.intc:
            return f"n {self.pick(['<', '>', '='])} {r.randint(-2, 4)}"
        if k == 10 and self.sets and r.random() < 0.5:
            return self.pick([f"contains(st, {self.e(d + 1)})", f"size(st) {self.pick(['<', '='])} {r.randint(0, 3)}",
                              "isEmpty(st)", f"notin(st, {self.e(d + 1)})"])
        if k == 10 and self.strs and r.random() < 0.5:
            return self.pick(['sv = "a"', 'sv != "ab"', f'sv = toString({self.dterm(d + 1)})', 'sv != "b"'])
        if k == 10 and self.reals and r.random() < 0.5:
            return self.pick([f"rv < {self.pick(['1.0', '1.5', '2.25'])}", "rv = 0.5", f"rv * 2.0 >= itor({self.dterm(d + 1)})"])
        if k == 10 and self.ext:
            return f"(exist $o in Obj with own($o) = {self.e(d + 1)})"
        return "bb"

    # -- rules ---------------------------------------------------------------------------
    def update(self, d: int) -> str:
        r = self.r
        opts = ["x", "y", "fv", "gb", "bb", "c", "he"]
        if self.seq:
            opts.append("sq")
        if self.intc:
            opts.append("n")
        if self.sets:
            opts.append("st")
        if self.tup:
            opts.append("pr")
        for flag, name in ((self.maps, "mp"), (self.strs, "sv"), (self.reals, "rv"), (self.bags, "bg")):
            if flag:
                opts.append(name)
        if self.in_agent:
            opts += ["wpos", "wpos"]
        loc = self.pick(opts)
        if loc in ("x", "y") and self.turbo and r.random() < 0.3:
            return f"{loc} <- r_t({self.e(d)})"
        if loc == "y" and self.undef and r.random() < 0.3:
            return "y := undef"
        if loc == "mp":
            return self.pick([f"mp := assign(mp, {self.e(d)}, {self.dterm(d)})", "mp := {AA -> 0}",
                              f"if at(mp, {self.e(d)}) != undef then mp := assign(mp, BB, (at(mp, BB) + 1) mod {DMAX + 1}) endif"])
        if loc == "sv":
            return self.pick(['sv := "a"', 'sv := "ab"', f"sv := toString({self.dterm(d)})",
                              'if sv = "a" then sv := sv + "b" endif'])
        if loc == "rv":
            return self.pick(["if rv < 2.0 then rv := rv + 0.5 endif", "rv := rv / 2.0", "rv := 0.25",
                              f"rv := itor({self.dterm(d)}) / 4.0"])
        if loc == "bg":
            e = self.e(d)
            return self.pick([f"if ntoi(count(bg, {e})) < 2 then bg := including(bg, {e}) endif",
                              f"bg := excluding(bg, {self.e(d)})", "bg := <>"])
        if loc == "pr":
            return self.pick([f"pr := ({self.e(d)}, {self.dterm(d)})",
                              f"pr := (he(first(pr)), (second(pr) + 1) mod {DMAX + 1})"])
        if loc == "wpos":
            return self.pick([f"wpos(self) := (wpos(self) + 1) mod {DMAX + 1}", f"wpos(self) := {self.dterm(d)}",
                              f"if wpos(self) < {r.randint(1, DMAX)} then x := wpos(self) endif"])
        if loc == "st":
            return self.pick([f"st := including(st, {self.e(d)})", f"st := excluding(st, {self.e(d)})",
                              f"st := union(st, {{{self.e(d)}, {self.e(d)}}})", "st := {}",
                              f"st := intersection(st, {{{self.e(d)}}})"])
        if r.random() < 0.45:
            # a change of the location's own value: the state space grows step after step
            if loc in ("x", "y"):
                return f"{loc} := ({loc} + {r.randint(1, 2)}) mod {DMAX + 1}"
            if loc == "fv":
                e = self.e(d)
                return f"fv({e}) := (fv({e}) + 1) mod {DMAX + 1}"
            if loc == "gb":
                e = self.e(d)
                return f"gb({e}) := not(gb({e}))"
            if loc == "bb":
                return "bb := not(bb)"
            if loc == "c":
                return "c := he(c)"
            if loc == "he":
                return f"he({self.e(d)}) := c"
        if loc in ("x", "y"):
            return f"{loc} := {self.dterm(d)}"
        if loc == "fv":
            return f"fv({self.e(d)}) := {self.dterm(d)}"
        if loc == "gb":
            return f"gb({self.e(d)}) := {self.b(d)}"
        if loc == "he":
            return f"he({self.e(d)}) := {self.e(d)}"
        if loc == "bb":
            return f"bb := {self.b(d)}"
        if loc == "c":
            return f"c := {self.e(d)}"
        if loc == "n":
            if r.random() < 0.3:
                # 64-bit wrap: 2^62 * 2^62 is 0, (2^62 + 1) * 2^62 is 2^62
                return "n := (n + 1) * 4611686018427387904"
            return f"n := (n + {r.randint(-1, 2)}) mod {r.randint(3, 5)}"
        # sq: bounded growth
        k = r.randrange(3)
        if k == 0:
            return f"if length(sq) < 3 then sq := append(sq, {self.e(d)}) endif"
        if k == 1:
            return self.pick(["if length(sq) > 0 then sq := tail(sq) endif",
                              f"if length(sq) < 3 then sq := prepend({self.e(d)}, sq) endif",
                              "if length(sq) >= 2 then sq := subSequence(sq, 1n, 2n) endif",
                              f"if length(sq) > 0 and length(sq) < 3 then sq := insertAt(sq, 1n, {self.e(d)}) endif",
                              f"sq := excluding(sq, {self.e(d)})"])
        return "sq := []"

    def rule(self, d: int = 0) -> str:
        r = self.r
        if d >= 4:
            return self.update(d)
        k = r.randrange(14)
        if k <= 2:
            return self.update(d)
        if k == 3:
            return "par\n" + "\n".join(self.rule(d + 1) for _ in range(r.randint(2, 3))) + "\nendpar"
        if k == 4:
            return "seq\n" + "\n".join(self.rule(d + 1) for _ in range(r.randint(2, 3))) + "\nendseq"
        if k == 5:
            els = f" else {self.rule(d + 1)}" if r.random() < 0.6 else ""
            return f"if {self.b(d)} then {self.rule(d + 1)}{els} endif"
        if k in (6, 7):
            v = f"$c{d}"
            g = self.b(d) if r.random() < 0.7 else None
            self.bound.append((v, "E"))
            g = self.b(d) if g is not None else None
            body = self.rule(d + 1)
            self.bound.pop()
            none = f" ifnone {self.rule(d + 1)}" if r.random() < 0.3 else ""
            dom = self.pick(["Col", "Col", "Num"]) if k == 7 else "Col"
            if k == 7 and dom == "Col" and (self.sets or self.seq) and r.random() < 0.5:
                dom = self.pick((["st"] if self.sets else []) + (["sq"] if self.seq else []))
            if dom == "Num":
                # a choice over the Integer subset: the variable is of type D
                self.bound.append((v, "D"))
                body = self.rule(d + 1)
                self.bound.pop()
                g = None
            return f"choose {v} in {dom if dom in ('Col', 'Num', 'st', 'sq') else 'Col'}{' with ' + g if g else ''} do {body}{none}"
        if k == 8:
            v = f"$a{d}"
            self.bound.append((v, "E"))
            g = self.b(d) if r.random() < 0.5 else None
            # an update indexed by the variable mostly (others may clash: an error to agree on)
            if r.random() < 0.7:
                body = self.pick([f"fv({v}) := {self.dterm(d + 1)}", f"gb({v}) := {self.b(d + 1)}",
                                  f"he({v}) := {self.e(d + 1)}"])
            else:
                body = self.rule(d + 1)
            self.bound.pop()
            return f"forall {v} in Col{' with ' + g if g else ''} do {body}"
        if k == 9:
            v = f"$l{d}"
            t = self.dterm(d)
            self.bound.append((v, "D"))
            body = self.rule(d + 1)
            self.bound.pop()
            return f"let ({v} = {t}) in {body} endlet"
        if k == 10:
            cases = list(ENUM)
            r.shuffle(cases)
            n = r.randint(1, 3)
            arms = " ".join(f"case {c}: {self.rule(d + 1)}" for c in cases[:n])
            other = f" otherwise {self.rule(d + 1)}" if r.random() < 0.5 else ""
            return f"switch {self.e(d)} {arms}{other} endswitch"
        if k == 11 and r.random() < 0.25:
            loc = self.pick(["x", "y"])
            if r.random() < 0.5:
                return f"while {loc} < {r.randint(1, DMAX)} do {loc} := {loc} + 1"
            return f"iterate if {loc} < {r.randint(1, DMAX)} then {loc} := {loc} + 1 endif enditerate"
        if k == 11 and r.random() < 0.3:
            # two variables: a pair of values chosen, or every pair
            a, b = f"$p{d}", f"$q{d}"
            self.bound += [(a, "E"), (b, "D")]
            g = self.b(d + 1)
            body = (f"fv({a}) := {b}" if r.random() < 0.6 else self.rule(d + 1))
            self.bound = self.bound[:-2]
            if r.random() < 0.5:
                return f"choose {a} in Col, {b} in Num with {g} do {body}"
            return f"forall {a} in Col, {b} in Num with {g} and {b} = fv({a}) do {body}"
        if k == 11 and r.random() < 0.2:
            # a seq in a forall's body: each value's rules in sequence, the values in parallel
            v = f"$s{d}"
            self.bound.append((v, "E"))
            body = f"seq gb({v}) := not(gb({v})) fv({v}) := if gb({v}) then 1 else 2 endif endseq"
            self.bound.pop()
            return f"forall {v} in Col with {self.b(d)} do {body}"
        if k == 11 and not self.in_macro:
            return f"r_macro[{self.e(d)}]"
        if k == 12 and self.ext:
            v = f"$n{d}"
            w = f"$w{d}"
            return (f"let ({w} = {self.e(d)}) in if (forall $z in Obj with own($z) != {w}) then "
                    f"extend Obj with {v} do own({v}) := {w} endif endlet")
        if k == 12 and self.ext is False:
            return "skip"
        if self.ext and r.random() < 0.5:
            # a choice among the objects (an element of a dynamic domain stays in it for ever:
            # objects are made only while a colour has none and keep their colour, so that the
            # domain stays finite)
            return f"choose $o in Obj with own($o) != {self.e(d)} do c := own($o)"
        return self.update(d)

    def state_b(self) -> str:
        """A Boolean term over controlled functions only (for properties)."""
        saved = self.mon
        self.mon = False
        t = self.b(1)
        self.mon = saved
        return t

    # -- the spec ------------------------------------------------------------------------
    def spec(self, name: str) -> str:
        r = self.r
        sig = [
            "\tenum domain Col = {" + " | ".join(ENUM) + "}",
            "\tdomain Num subsetof Integer",
            "\tcontrolled x: Num", "\tcontrolled y: Num", "\tcontrolled fv: Col -> Num",
            "\tcontrolled gb: Col -> Boolean", "\tcontrolled he: Col -> Col", "\tcontrolled bb: Boolean",
            "\tcontrolled c: Col",
            "\tderived dd: Col -> Num",
        ]
        if self.seq:
            sig.append("\tcontrolled sq: Seq(Col)")
        if self.intc:
            sig.append("\tcontrolled n: Integer")
        if self.sets:
            sig.append("\tcontrolled st: Powerset(Col)")
        if self.tup:
            sig.append("\tcontrolled pr: Prod(Col, Num)")
        if self.maps:
            sig.append("\tcontrolled mp: Map(Col, Num)")
        if self.strs:
            sig.append("\tcontrolled sv: String")
        if self.reals:
            sig.append("\tcontrolled rv: Real")
        if self.bags:
            sig.append("\tcontrolled bg: Bag(Col)")
        if self.agents:
            sig.insert(sig.index("\tdomain Num subsetof Integer") + 1, "\tdomain Worker subsetof Agent")
            sig += ["\tstatic w1: Worker", "\tstatic w2: Worker", "\tcontrolled wpos: Worker -> Num"]
        if self.mon:
            sig += ["\tmonitored mB: Boolean", "\tmonitored mE: Col"]
        if self.ext:
            sig.insert(0, "\tdynamic abstract domain Obj")
            sig.append("\tcontrolled own: Obj -> Col")
        defs = [f"\tdomain Num = {{0 : {DMAX}}}"]
        saved = self.mon
        self.mon = False
        self.bound.append(("$p", "E"))
        defs.append(f"\tfunction dd($p in Col) = if gb($p) then fv($p) else {self.dterm(2)} endif")
        self.bound.pop()
        self.mon = saved
        self.bound.append(("$m", "E"))
        self.in_macro = True
        macro = self.rule(2)
        self.in_macro = False
        self.bound.pop()
        defs.append(f"\trule r_macro($m in Col) =\n\t\t{macro}")
        if self.turbo:
            self.bound.append(("$u", "E"))
            self.in_macro = True
            t1, t2 = self.dterm(2), self.dterm(2)
            cond = self.b(2)
            self.in_macro = False
            self.bound.pop()
            defs.append(f"\tturbo rule r_t($u in Col) in Num =\n\t\tif {cond} then result := {t1} "
                        f"else seq\n\t\t\tresult := {t2}\n\t\t\tresult := (result + 1) mod {DMAX + 1}\n\t\tendseq endif")
        if self.agents:
            self.in_agent = True
            body = self.rule(2)
            self.in_agent = False
            defs.append(f"\trule r_work =\n\t\t{body}")
        props = []
        for i in range(r.randint(0, 2)):
            props.append(f"\tinvariant inv_{i} over x, bb: {self.state_b()}")
        if self.mon and r.random() < 0.3:
            # an invariant that reads a monitored function: checked before the step's updates
            props.append(f"\tinvariant inv_m over mB: mB or {self.state_b()}")
        if self.fair:
            props.insert(0, f"\tJUSTICE {self.state_b()}")
        for i in range(r.randint(0, 2)):
            p = self.pick(["ag", "ef", "af", "eg"])
            props.append(f"\tCTLSPEC {p}({self.state_b()})")
        for i in range(r.randint(0, 2)):
            k = r.randrange(3)
            if k == 0:
                props.append(f"\tLTLSPEC g({self.state_b()})")
            elif k == 1:
                props.append(f"\tLTLSPEC f({self.state_b()})")
            else:
                props.append(f"\tLTLSPEC g(implies({self.state_b()}, f({self.state_b()})))")
        # a main rule that branches: a choose, and one to three other rules beside it
        v = "$t"
        self.bound.append((v, self.pick(["E", "E", "D"])))
        dom = "Col" if self.bound[-1][1] == "E" else "Num"
        g = f" with {self.b(1)}" if r.random() < 0.5 else ""
        first = f"choose {v} in {dom}{g} do {self.rule(1)}"
        self.bound.pop()
        rest = [self.rule(1) for _ in range(r.randint(1, 3))]
        if self.agents:
            rest[0] = self.pick(["choose $wk in Worker do program($wk)", "forall $wk in Worker do program($wk)",
                                 "program(w1)"])
        main = "par\n" + "\n".join([first] + rest) + "\nendpar"
        init = [f"\tfunction x = {r.randint(0, DMAX)}", f"\tfunction y = {r.randint(0, DMAX)}",
                f"\tfunction fv($e in Col) = {r.randint(0, DMAX)}",
                f"\tfunction gb($e in Col) = {self.pick(['true', 'false', '$e = AA'])}",
                f"\tfunction he($e in Col) = {self.pick(['$e', 'AA', 'CC'])}",
                f"\tfunction bb = {self.pick(['true', 'false'])}", f"\tfunction c = {self.pick(ENUM)}"]
        if self.seq:
            init.append("\tfunction sq = []")
        if self.intc:
            init.append("\tfunction n = 0")
        if self.sets:
            init.append(f"\tfunction st = {self.pick(['{}', '{AA}', '{BB, CC}'])}")
        if self.tup:
            init.append(f"\tfunction pr = ({self.pick(ENUM)}, {r.randint(0, DMAX)})")
        if self.maps:
            init.append(f"\tfunction mp = {self.pick(['{AA -> 1}', '{BB -> 0, CC -> 3}'])}")
        if self.strs:
            init.append("\tfunction sv = " + self.pick(['"a"', '""']))
        if self.reals:
            init.append(f"\tfunction rv = {self.pick(['0.0', '1.5'])}")
        if self.bags:
            init.append(f"\tfunction bg = {self.pick(['<>', '<AA, AA>'])}")
        if self.agents:
            init += [f"\tfunction wpos($w in Worker) = {r.randint(0, DMAX)}", "\tagent Worker: r_work[]"]
        lines = [f"asm {name}", "import StandardLibrary", "import CTLLibrary", "import LTLLibrary", "signature:",
                 *sig, "definitions:", *defs, *props, "\tmain rule r_main =", "\t\t" + main.replace("\n", "\n\t\t"),
                 "default init s0:", *init]
        return "\n".join(lines) + "\n"


    def prop_file(self, name: str) -> str:
        """A property file for the spec ``name``: step properties (the state before, next(t) after,
        updated/changed, updatedBy) and an invariant."""
        r = self.r
        out = [f"applies to {name}"]
        for i in range(r.randint(1, 3)):
            k = r.randrange(5)
            if k == 0:
                body = f"{self.state_b()} implies next({self.state_b()})"
            elif k == 1:
                loc = self.pick(["x", "y", "bb", "c", f"fv({self.pick(ENUM)})", f"gb({self.pick(ENUM)})"])
                body = f"updated({loc}) implies {self.pick(['changed', 'updated'])}({loc})"
            elif k == 2:
                e = self.pick(ENUM)
                body = f"changed(fv({e})) implies next(fv({e})) {self.pick(['>', '!=', '<'])} fv({e})"
            elif k == 3 and self.agents:
                body = "(forall $w in Worker with updated(wpos($w)) implies updatedBy($w, wpos($w)))"
            else:
                body = f"next(x) = x or next({self.state_b()})"
            out.append(f"step stp_{i}:\n\t{body}")
        if r.random() < 0.5:
            out.append(f"invariant inv_file:\n\t{self.state_b()}")
        return "\n".join(out) + "\n"


def spec(seed: int) -> str:
    return Gen(seed).spec(f"fz{seed}")


def spec_and_props(seed: int) -> tuple[str, str]:
    """The spec of ``seed`` and a property file for it (drawn after the spec: the spec is
    ``spec(seed)``)."""
    g = Gen(seed)
    text = g.spec(f"fz{seed}")
    return text, g.prop_file(f"fz{seed}")
