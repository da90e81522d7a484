"""Deep and large specs: deep nesting resolves or is a located error, name resolution is linear."""
import re

import pytest

from asmcheck.errors import AsmError
from asmcheck.semantics import ir, resolve
from asmcheck.semantics.resolve import MAX_NESTING, check_file
from asmcheck.syntax.parser import parse_file

pytestmark = pytest.mark.engines("both")


def _nested_ifs(n):
    body = "x := 0"
    for i in range(n):
        body = f"if x = {i % 7} then {body} endif"
    return body


def _spec(name, sig, main):
    return (f"asm {name}\nimport StandardLibrary\nsignature:\n{sig}\ndefinitions:\n\tmain rule r_main = {main}\n"
            f"default init s0:\n\tfunction x = 0\n")


def _if_depth(rule):
    depth = 0
    while isinstance(rule, ir.If):
        depth += 1
        rule = rule.then
    assert isinstance(rule, ir.Update)
    return depth


def test_eight_hundred_nested_ifs(tmp_path):
    p = tmp_path / "Ifs.asm"
    p.write_text(_spec("Ifs", "\tcontrolled x: Integer", _nested_ifs(800)))
    spec = check_file(str(p))
    assert _if_depth(spec.main.body) == 800


@pytest.mark.parametrize("op,sig,init", [("+", "\tcontrolled x: Integer", "0"), ("and", "\tcontrolled x: Boolean", "true")])
def test_flat_chain_of_350(tmp_path, op, sig, init):
    p = tmp_path / "Chain.asm"
    p.write_text(_spec("Chain", sig, "x := " + f" {op} ".join(["x"] * 350)).replace("function x = 0", f"function x = {init}"))
    spec = check_file(str(p))
    t, n = spec.main.body.value, 1
    while isinstance(t, ir.Call) and t.name in ("plus", "and"):
        t, n = t.args[0], n + 1
    assert n == 350 and isinstance(t, ir.Loc)


def test_nesting_beyond_the_limit_is_a_located_error(tmp_path):
    n = MAX_NESTING + 500
    text = _spec("Deep", "\tcontrolled x: Integer", _nested_ifs(n))
    p = tmp_path / "Deep.asm"
    p.write_text(text)
    with pytest.raises(AsmError) as info:
        check_file(str(p))
    err = info.value
    # if number k is at depth k, its guard at k+1 and the guard's operands at k+2: the first
    # construct past the limit is the left operand of the guard of if number MAX_NESTING - 1
    line6 = text.split("\n")[5]
    ifs = [m.start() for m in re.finditer(r"\bif ", line6)]
    assert (err.span.line, err.span.col) == (6, ifs[MAX_NESTING - 2] + 1 + len("if "))
    assert "nests too deeply" in err.message
    assert len(err.render().splitlines()) == 3


class _CountingList(list):
    """A list that counts the elements handed out by iteration."""

    handed = 0
    limit = 0

    def __iter__(self):
        for x in list.__iter__(self):
            _CountingList.handed += 1
            if _CountingList.handed > _CountingList.limit:
                raise AssertionError("the rules are scanned again and again (quadratic name resolution)")
            yield x


def test_name_resolution_is_linear(tmp_path, monkeypatch):
    """20,000 rules: each rule's declaration is paired with its syntax once (no rescans)."""
    n = 20_000
    lines = ["asm Many", "import StandardLibrary", "signature:", "\tcontrolled x: Integer", "definitions:"]
    lines += [f"\trule r_{i} = x := {i}" for i in range(n)]
    lines += ["\tmain rule r_main = r_7[]", "default init s0:", "\tfunction x = 0", ""]
    p = tmp_path / "Many.asm"
    p.write_text("\n".join(lines))
    run = resolve.Declarer.run

    def counting_run(self):
        run(self)
        self.mod.rules = _CountingList(self.mod.rules)
    monkeypatch.setattr(resolve.Declarer, "run", counting_run)
    _CountingList.handed = 0
    # a few passes over the rules, never one per rule (that would be n * n = 4e8 elements)
    _CountingList.limit = 5 * (n + 1)
    spec = check_file(str(p))
    assert len(spec.rules) == n + 1
    assert spec.main.body.rule.name == "r_7"
    assert 0 < _CountingList.handed <= 5 * (n + 1)


def test_deep_term_outside_a_spec(tmp_path):
    """A long conjunction in a property file or a scenario: parsed and resolved like a spec's."""
    from asmcheck.semantics.resolve import Env, Resolver
    from asmcheck.syntax.parser import parse_term
    p = tmp_path / "B.asm"
    p.write_text("asm B\nimport StandardLibrary\nsignature:\n\tcontrolled b: Boolean\ndefinitions:\n"
                 "\tmain rule r_main = skip\ndefault init s0:\n\tfunction b = true\n")
    spec = check_file(str(p))
    text = " and ".join(["b"] * 1500)
    term = parse_term(text, "B.prop", (4, 9))
    assert (term.span.line, term.span.col) == (4, 9)
    assert (term.span.end_line, term.span.end_col) == (4, 9 + len(text))
    body = Resolver(spec.loader, spec.root_module).bool_term(term, Env())
    n = 1
    while isinstance(body, ir.Call) and body.name == "and":
        body, n = body.args[0], n + 1
    assert n == 1500 and isinstance(body, ir.Loc)


def test_without_a_deep_stack_the_error_is_still_located(tmp_path, monkeypatch):
    monkeypatch.setattr(resolve, "_DEEP_STACK", 1 << 62)      # a stack that cannot be had
    p = tmp_path / "Ifs.asm"
    p.write_text(_spec("Ifs", "\tcontrolled x: Integer", _nested_ifs(800)))
    with pytest.raises(AsmError) as info:
        check_file(str(p))
    err = info.value
    assert err.span.path == str(p) and err.span.line == 6 and err.span.col > 21
    assert "nests too deeply: this term is deeper than the stack allows" in err.message


def test_recursive_rules(tmp_path):
    from asmcheck.semantics.ir import recursive_rules
    p = tmp_path / "R.asm"
    p.write_text("asm R\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
                 "\trule r_a = r_b[]\n\trule r_b = if x > 0 then r_a[] endif\n"
                 "\trule r_c($n in Integer) = if $n > 0 then r_c[$n - 1] endif\n"
                 "\trule r_d = par r_a[] r_e[] endpar\n\trule r_e = x := 1\n"
                 "\tturbo rule r_f = r_f()\n"
                 "\tmain rule r_main = r_d[]\ndefault init s0:\n\tfunction x = 0\n")
    spec = check_file(str(p))
    assert [r.name for r in recursive_rules(spec.rules)] == ["r_a", "r_b", "r_c", "r_f"]


@pytest.mark.parametrize("closed", [False, True])
def test_recursive_rules_on_a_long_chain(tmp_path, closed):
    n = 5000
    lines = ["asm Chain", "import StandardLibrary", "signature:", "\tcontrolled x: Integer", "definitions:"]
    lines += [f"\trule r_{i} = r_{i + 1}[]" for i in range(n)]
    lines += [f"\trule r_{n} = " + ("r_0[]" if closed else "x := 1"), "\tmain rule r_main = r_0[]",
              "default init s0:", "\tfunction x = 0", ""]
    p = tmp_path / "Chain.asm"
    p.write_text("\n".join(lines))
    from asmcheck.semantics.ir import recursive_rules
    spec = check_file(str(p))
    got = recursive_rules(spec.rules)
    assert len(got) == (n + 1 if closed else 0)


@pytest.mark.engines("native")
def test_eight_hundred_nested_ifs_explore(tmp_path):
    """The machine compiles and runs a rule nested 800 deep (on a deep stack when this one is too
    shallow); the C generator declines it and says why, and the Python engine explores it.
    Engines: auto (python after the native engine's refusal)."""
    import asmcheck
    body = "x := (x + 1) mod 3"
    for i in range(800):
        body = f"if x >= {-1 - i} then {body} endif"
    p = tmp_path / "Ifs.asm"
    p.write_text(_spec("Ifs", "\tcontrolled x: Integer", body))
    res = asmcheck.load(str(p)).explore()
    assert (res.states, res.transitions, res.engine) == (3, 3, "python")
    assert res.engine_note == "the spec nests more deeply than the C generator follows"
