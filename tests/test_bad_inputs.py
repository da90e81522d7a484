"""Labelled bad inputs: each must fail with an exact line, column and message."""
import pytest

from asmcheck.errors import AsmError
from asmcheck.semantics.resolve import check_file

pytestmark = pytest.mark.engines("none")

HEAD = "asm T\nimport StandardLibrary\nsignature:\n"

# (label, spec text, line, column, a piece of the message)
CASES = [
    ("missing signature", "asm T\nimport StandardLibrary\ndefinitions:\n", 3, 1, "expected"),
    ("lower-case enum constant",
     HEAD + "\tenum domain Color = {RED | green}\ndefinitions:\n", 4, 29, "enum constant"),
    ("one capital then underscore is a domain name",
     HEAD + "\tenum domain Tick = {W_TICK}\ndefinitions:\n", 4, 22, "two capitals"),
    ("rule name without r_",
     HEAD + "definitions:\n\trule go = skip\n", 5, 7, "rule names start with 'r_'"),
    ("variable without $",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = forall i in Integer do x := 1\n",
     6, 28, "variables start with '$'"),
    ("unterminated string",
     HEAD + "\tcontrolled s: String\ndefinitions:\n\tmain rule r_main = s := \"abc\n", 6, 26, "string"),
    ("par with one rule",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = par x := 1 endpar\n", 6, 32, "unexpected 'endpar'"),
    ("missing endif",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = if x = 1 then x := 2\n", 6, 41, "end of file"),
    ("bad character",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = x := 1 # 2\n", 6, 28, "unexpected character '#'"),
    ("reserved word as function name",
     HEAD + "\tcontrolled seq: Integer\ndefinitions:\n", 4, 13, "'seq' is a reserved word"),
    ("function declared after definitions keyword",
     HEAD + "definitions:\n\tcontrolled x: Integer\n", 5, 2, "unexpected 'controlled'"),
    ("domain after function",
     HEAD + "\tcontrolled x: Integer\n\tabstract domain D\ndefinitions:\n", 5, 2, "unexpected 'abstract'"),
    ("unknown function",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = x := y + 1\n", 6, 26, "unknown function 'y'"),
    ("unknown domain",
     HEAD + "\tcontrolled x: Widget\ndefinitions:\n", 4, 16, "unknown domain 'Widget'"),
    ("unknown enum constant",
     HEAD + "\tenum domain C = {AA | BB}\n\tcontrolled c: C\ndefinitions:\n\tmain rule r_main = c := CC\n",
     7, 26, "unknown enum constant 'CC'"),
    ("duplicate enum symbol",
     HEAD + "\tenum domain C = {AA | BB | AA}\ndefinitions:\n", 4, 29, "duplicate"),
    ("enum constant of the wrong domain",
     HEAD + "\tenum domain C = {AA | BB}\n\tenum domain E = {XX | YY}\n\tcontrolled c: C\ndefinitions:\n"
            "\tmain rule r_main = c := XX\n", 8, 26, "not compatible"),
    ("wrong arity",
     HEAD + "\tcontrolled f: Integer -> Integer\ndefinitions:\n\tmain rule r_main = f(1, 2) := 3\n",
     6, 21, "takes 1 argument(s), not 2"),
    ("wrong argument domain",
     HEAD + "\tcontrolled f: Integer -> Integer\ndefinitions:\n\tmain rule r_main = f(true) := 3\n",
     6, 21, "no f applies to (Boolean)"),
    ("natural and integer do not mix",
     HEAD + "\tcontrolled n: Natural\ndefinitions:\n\tmain rule r_main = n := n + 1\n",
     6, 28, "no plus applies to (Natural, Integer)"),
    ("value of the wrong domain",
     HEAD + "\tcontrolled b: Boolean\ndefinitions:\n\tmain rule r_main = b := 3\n", 6, 26, "not compatible"),
    ("update of a monitored function",
     HEAD + "\tmonitored m: Integer\ndefinitions:\n\tmain rule r_main = m := 3\n", 6, 21, "monitored"),
    ("update of a static function",
     HEAD + "\tstatic k: Integer\ndefinitions:\n\tfunction k = 3\n\tmain rule r_main = k := 4\n",
     7, 21, "only dynamic functions can be updated"),
    ("undeclared variable",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = x := $y\n", 6, 26, "undeclared variable $y"),
    ("unknown rule",
     HEAD + "definitions:\n\tmain rule r_main = r_missing[]\n", 5, 21, "unknown rule r_missing"),
    ("rule called with wrong arity",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\trule r_set($v in Integer) = x := $v\n"
            "\tmain rule r_main = r_set[1, 2]\n", 7, 21, "takes 1 argument(s), not 2"),
    ("non-boolean guard",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = if x then x := 1 endif\n",
     6, 24, "expected a Boolean term"),
    ("static function using a dynamic one",
     HEAD + "\tcontrolled x: Integer\n\tstatic k: Integer\ndefinitions:\n\tfunction k = x + 1\n", 7, 11,
     "static function k uses dynamic"),
    ("derived function using no dynamic one",
     HEAD + "\tderived d: Integer -> Integer\ndefinitions:\n\tfunction d($i in Integer) = $i * 2\n", 6, 11,
     "uses no dynamic function"),
    ("definition with the wrong number of parameters",
     HEAD + "\tstatic k: Integer -> Integer\ndefinitions:\n\tfunction k = 3\n", 6, 11, "0 parameter(s)"),
    ("definition of an undeclared function",
     HEAD + "definitions:\n\tfunction nope = 3\n", 5, 11, "undeclared function 'nope'"),
    ("extend of a static domain",
     HEAD + "\tabstract domain D\n\tcontrolled x: Integer\ndefinitions:\n"
            "\tmain rule r_main = extend D with $d do x := 1\n", 7, 28, "dynamic abstract domain"),
    ("local function in the signature",
     HEAD + "\tlocal l: Integer\ndefinitions:\n", 4, 8, "local function"),
    ("controlled function defined in definitions",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tfunction x = 3\n", 6, 11, "init block"),
    ("temporal operator outside a property",
     "asm T\nimport StandardLibrary\nimport CTLLibrary\nsignature:\n\tcontrolled b: Boolean\ndefinitions:\n"
     "\tmain rule r_main = b := ag(b)\n", 7, 26, "temporal operator ag"),
    ("invariant over an unknown name",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tinvariant inv_a over y: x > 0\n", 6, 23, "unknown name 'y'"),
    ("init of an unknown function",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\ndefault init s0:\n\tfunction z = 1\n", 7, 11, "unknown function 'z'"),
    ("init value of the wrong domain",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\ndefault init s0:\n\tfunction x = true\n", 7, 15, "not compatible"),
    ("init blocks without a default",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = skip\ninit s0:\n\tfunction x = 1\n",
     8, 16, "expected 'default'"),
    ("argument of a subset of an abstract domain",
     HEAD + "\tabstract domain Animal\n\tdomain Dog subsetof Animal\n\tstatic a: Animal\n"
            "\tcontrolled f: Dog -> Integer\ndefinitions:\n\tmain rule r_main = f(a) := 1\n", 9, 21, "no f applies to (Animal)"),
    ("set of mixed domains",
     HEAD + "\tcontrolled s: Powerset(Integer)\ndefinitions:\n\tmain rule r_main = s := {1, true}\n", 6, 30,
     "collection"),
    ("main rule with parameters",
     HEAD + "definitions:\n\tmain rule r_main($x in Integer) = skip\n", 5, 12, "no parameters"),
    ("import not found",
     "asm T\nimport StandardLibrary\nimport ./nowhere/Missing\nsignature:\ndefinitions:\n", 3, 1, "import not found"),
    ("a CTL operator without its library",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tCTLSPEC ag(x >= 0)\n", 6, 10,
     "unknown function 'ag' (ag is defined in CTLLibrary: import CTLLibrary)"),
    ("an LTL operator without its library",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tLTLSPEC g(x >= 0)\n", 6, 10,
     "unknown function 'g' (g is defined in LTLLibrary: import LTLLibrary)"),
    ("a bare name that is also an LTL operator",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = x := y\n", 6, 26, "unknown function 'y'"),
    ("JUSTICE after a property",
     HEAD + "\tmonitored go: Boolean\ndefinitions:\n\tinvariant over go: go or not go\n\tJUSTICE go\n", 7, 2,
     "unexpected 'JUSTICE'; expected 'CTLSPEC', 'LTLSPEC', 'ctlspec', 'default', 'init', 'invariant', 'ltlspec', "
     "'main', ... (JUSTICE and COMPASSION constraints come before the properties (invariant, CTLSPEC, LTLSPEC))"),
    ("rule declaration after the main rule",
     HEAD + "\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = r_a[]\n\trule r_a = x := 1\n", 7, 2,
     "(rule declarations come before the main rule)"),
    ("function definition after a rule declaration",
     HEAD + "\tderived y: Integer\ndefinitions:\n\trule r_a = skip\n\tfunction y = 1\n", 7, 2,
     "(function definitions come before rule declarations)"),
    ("domain initialisation after a function initialisation",
     HEAD + "\tdomain D subsetof Integer\n\tcontrolled x: Integer\ndefinitions:\n\tmain rule r_main = skip\n"
            "default init s0:\n\tfunction x = 0\n\tdomain D = {1 : 2}\n", 10, 2,
     "(domain definitions come before function definitions)"),
    ("file name differs from the asm name", "asm Other\nimport StandardLibrary\nsignature:\ndefinitions:\n",
     1, 5, "differs from its file name"),
]


@pytest.mark.parametrize("label,text,line,col,fragment", CASES, ids=[c[0] for c in CASES])
def test_bad_input(tmp_path, label, text, line, col, fragment):
    path = tmp_path / "T.asm"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(AsmError) as info:
        check_file(str(path))
    err = info.value
    assert (err.span.line, err.span.col) == (line, col), err.render()
    assert fragment in err.message, err.render()
    rendered = err.render()
    assert rendered.startswith(f"{path}:{line}:{col}: ")
    assert "^" in rendered.splitlines()[2]


def test_circular_import(tmp_path):
    (tmp_path / "A.asm").write_text("module A\nimport B\nexport *\nsignature:\ndefinitions:\n")
    (tmp_path / "B.asm").write_text("module B\nimport A\nexport *\nsignature:\ndefinitions:\n")
    with pytest.raises(AsmError) as info:
        check_file(str(tmp_path / "A.asm"))
    assert "circular import" in info.value.message
    assert info.value.span.line == 2 and info.value.span.col == 1


def test_count_of_labelled_cases():
    assert len(CASES) >= 30


@pytest.mark.parametrize("body,message", [
    ("CTLSPEC ag(true)", "unknown function 'ag' (ag is defined in CTLLibrary: import CTLLibrary)"),
    ("main rule r_main = x := y", "unknown function 'y'"),
    ("main rule r_main = x := max(x, 1)", "unknown function 'max' (max is defined in StandardLibrary: import StandardLibrary)"),
])
def test_an_unknown_name_from_a_library_names_the_import(tmp_path, body, message):
    path = tmp_path / "T.asm"
    path.write_text(f"asm T\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n\t{body}\n", encoding="utf-8")
    with pytest.raises(AsmError) as info:
        check_file(str(path))
    assert info.value.message == message
