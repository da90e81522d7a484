"""Front-end rules taken from ASMETA's parser (asmeta.parser), each on a small spec.

- Overloaded function names across imported modules: ASMETA looks a name up among all
  declared functions, the latest declared first, and takes the first whose domain fits the
  argument's domain (AsmetaParserUtility.getFunction with OCL_Checker.compareFixingAnyDomain).
- Static and derived definitions (StaticDerivedChecker with DynamicInTermFinder): a static
  definition mentions nothing dynamic; a derived one mentions a function that is not static
  or a variable whose domain is dynamic (a dynamic abstract domain -- Agent and Reserve are
  -- a dynamic subset of an abstract domain, or a Seq of one).
- A module may define a static or derived function that an imported module declares
  (ASMParser.jj, FunctionDefinition: the name is looked up among all declared functions).

Every expectation below was also the verdict of ASMETA's AsmetaLc on the same text.
"""
import pytest

from asmcheck.errors import AsmError
from asmcheck.semantics import ir
from asmcheck.semantics.resolve import check_file

pytestmark = pytest.mark.engines("none")

STD = "import StandardLibrary\n"


def _spec(name, signature, definitions):
    return f"asm {name}\n{STD}signature:\n{signature}\ndefinitions:\n{definitions}\n"


# (label, signature, definitions, None when accepted / (line, col, fragment) of the error)
DEFINITIONS = [
    ("derived over an Agent variable, static constants in a switch",
     "\tabstract domain PubKey\n\tderived pubkey: Agent -> PubKey\n\tstatic agentA: Agent\n\tstatic agentB: Agent\n"
     "\tstatic pubKeyA: PubKey\n\tstatic pubKeyB: PubKey",
     "\tfunction pubkey($a in Agent) =\n\t\tswitch($a)\n\t\t\tcase agentA: pubKeyA\n\t\t\tcase agentB: pubKeyB\n"
     "\t\tendswitch", None),
    ("derived over a sequence of a dynamic abstract domain",
     "\tdynamic abstract domain Vertex\n\tderived push: Prod(Vertex, Seq(Vertex)) -> Seq(Vertex)",
     "\tfunction push($v in Vertex, $sv in Seq(Vertex)) = append($sv, $v)", None),
    ("derived over a dynamic subset of a dynamic abstract domain",
     "\tdynamic abstract domain X\n\tdynamic domain Y subsetof X\n\tderived d: Y -> Boolean",
     "\tfunction d($s in Y) = $s = $s", None),
    ("forall whose variable ranges over a dynamic domain",
     "\tdynamic abstract domain X\n\tderived d: Boolean", "\tfunction d = (forall $x in X with true)", None),
    ("exists whose range is a controlled function",
     "\tcontrolled c: Powerset(Integer)\n\tderived d: Boolean", "\tfunction d = (exists $x in c with true)", None),
    ("set comprehension whose guard reads a controlled function",
     "\tcontrolled c: Integer\n\tderived d: Powerset(Integer)", "\tfunction d = {$x in {1, 2} | $x > c : $x}", None),
    ("derived reading self", "\tderived d: Integer", "\tfunction d = let ($a = self) in 3 endlet", None),
    ("derived of integers only",
     "\tderived d: Integer -> Integer", "\tfunction d($i in Integer) = $i * 2", (6, 11, "uses no dynamic function")),
    ("derived over a static subset of a dynamic domain",
     "\tdynamic abstract domain X\n\tdomain Y subsetof X\n\tderived d: Y -> Boolean",
     "\tfunction d($s in Y) = $s = $s", (8, 11, "uses no dynamic function")),
    ("derived over a powerset of a dynamic domain (not dynamic for ASMETA)",
     "\tdynamic abstract domain X\n\tderived d: Powerset(X) -> Boolean",
     "\tfunction d($s in Powerset(X)) = isEmpty($s)", (7, 11, "uses no dynamic function")),
    ("forall: the range is not looked at, only its variable and guard",
     "\tcontrolled c: Powerset(Integer)\n\tderived d: Boolean",
     "\tfunction d = (forall $x in c with true)", (7, 11, "uses no dynamic function")),
    ("sequence comprehension: the term is not looked at",
     "\tcontrolled c: Integer\n\tderived d: Seq(Integer)",
     "\tfunction d = [$x in [1, 2] | true : $x + c]", (7, 11, "uses no dynamic function")),
    ("a collection literal of constants",
     "\tderived d: Powerset(Integer)", "\tfunction d = {1, 2}", (6, 11, "uses no dynamic function")),
    ("a parameter over Agent that the body never mentions",
     "\tderived d: Agent -> Integer", "\tfunction d($i in Agent) = let ($a = 1) in $a endlet",
     (6, 11, "uses no dynamic function")),
    ("static over an Agent variable",
     "\tstatic s: Agent -> Boolean", "\tfunction s($a in Agent) = $a = $a",
     (6, 11, "static function s uses dynamic function(s) $a (a variable of the dynamic domain Agent)")),
]


@pytest.mark.parametrize("label,sig,defs,expect", DEFINITIONS, ids=[c[0] for c in DEFINITIONS])
def test_static_and_derived_definitions(tmp_path, label, sig, defs, expect):
    path = tmp_path / "D.asm"
    path.write_text(_spec("D", sig, defs), encoding="utf-8")
    if expect is None:
        spec = check_file(str(path))
        assert any(f.body is not None for f in spec.functions if f.kind in ("static", "derived"))
        return
    line, col, fragment = expect
    with pytest.raises(AsmError) as info:
        check_file(str(path))
    err = info.value
    assert (err.span.line, err.span.col) == (line, col), err.render()
    assert fragment in err.message, err.render()


SUB = """module Sub
import StandardLibrary
export *
signature:
\tstatic capacity: Integer
\tstatic twice: Integer
definitions:
\tfunction twice = 2
"""


def _main(name, defs, imp="import Sub"):
    return (f"asm {name}\nimport StandardLibrary\n{imp}\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
            f"{defs}\n\tmain rule r_main = x := capacity + twice\ndefault init s0:\n\tfunction x = 0\n")


def test_definition_of_an_imported_static_function(tmp_path):
    (tmp_path / "Sub.asm").write_text(SUB)
    (tmp_path / "Main.asm").write_text(_main("Main", "\tfunction capacity = 3"))
    spec = check_file(str(tmp_path / "Main.asm"))
    cap = next(f for f in spec.functions if f.name == "capacity")
    assert cap.module == "Sub" and isinstance(cap.body, ir.Const) and cap.body.value == 3
    # also through an import list that names it
    (tmp_path / "Main2.asm").write_text(_main("Main2", "\tfunction capacity = 4", "import Sub(capacity, twice)"))
    spec = check_file(str(tmp_path / "Main2.asm"))
    assert next(f for f in spec.functions if f.name == "capacity").body.value == 4


@pytest.mark.parametrize("defs,line,col,fragment", [
    ("\tfunction capacity = 3\n\tfunction capacity = 4", 8, 11, "function capacity is defined twice"),
    ("\tfunction twice = 3", 7, 11, "function twice is defined twice"),
    ("\tfunction capacity = x", 7, 11, "static function capacity uses dynamic function(s) x"),
    ("\tfunction nothing = 3", 7, 11, "definition of an undeclared function 'nothing'"),
])
def test_definition_of_an_imported_function_errors(tmp_path, defs, line, col, fragment):
    (tmp_path / "Sub.asm").write_text(SUB)
    (tmp_path / "Main.asm").write_text(_main("Main", defs))
    with pytest.raises(AsmError) as info:
        check_file(str(tmp_path / "Main.asm"))
    err = info.value
    assert (err.span.line, err.span.col) == (line, col), err.render()
    assert fragment in err.message, err.render()


CAM = """module Cam
import StandardLibrary
export *
signature:
\tdomain Camera subsetof Agent
\tenum domain CameraState = {IDLE | SHOOTING}
\tcontrolled state: Camera -> CameraState
definitions:
\trule r_cam = state(self) := SHOOTING
"""

HEAL = """module Heal
import StandardLibrary
import Cam
export *
signature:
\tdomain Healer subsetof Agent
\tenum domain HealingState = {WAITING | FAILED}
\tcontrolled state: Healer -> HealingState
definitions:
\trule r_heal = state(self) := FAILED
"""

TOP = """asm Top
import StandardLibrary
import Cam
import Heal
signature:
\tstatic cam1: Camera
\tstatic heal1: Healer
definitions:
\tmain rule r_main =
\t\tpar
\t\t\tstate(cam1) := IDLE
\t\t\tstate(heal1) := WAITING
\t\t\tr_heal[]
\t\tendpar
default init s0:
\tfunction state($c in Camera) = IDLE
\tfunction state($h in Healer) = WAITING
"""


def _updates(rule):
    out, stack = [], [rule]
    while stack:
        r = stack.pop()
        if isinstance(r, ir.Update):
            out.append(r)
        elif isinstance(r, ir.Block):
            stack.extend(r.rules)
    return sorted(out, key=lambda u: (u.span.line, u.span.col))


def test_overloaded_function_across_modules(tmp_path):
    for name, text in (("Cam", CAM), ("Heal", HEAL), ("Top", TOP)):
        (tmp_path / f"{name}.asm").write_text(text)
    # the module that declares the second 'state' uses it on self (an Agent): its own, the latest declared
    heal = check_file(str(tmp_path / "Heal.asm"))
    r_heal = next(r for r in heal.rules if r.name == "r_heal")
    assert [(u.func.module, str(u.func.domain[0])) for u in _updates(r_heal.body)] == [("Heal", "Healer")]
    top = check_file(str(tmp_path / "Top.asm"))
    assert [(u.func.module, str(u.func.domain[0])) for u in _updates(top.main.body)] == [
        ("Cam", "Camera"), ("Heal", "Healer")]
    assert [(f.module, v[0].name if v else None) for f, v, _, _ in top.default_init.functions] == [
        ("Cam", "$c"), ("Heal", "$h")]


def test_overloaded_function_on_agent_takes_the_latest_declared(tmp_path):
    for name, text in (("Cam", CAM), ("Heal", HEAL)):
        (tmp_path / f"{name}.asm").write_text(text)
    (tmp_path / "Top2.asm").write_text("asm Top2\nimport StandardLibrary\nimport Cam\nimport Heal\nsignature:\n"
                                       "definitions:\n\tmain rule r_main = state(self) := SHOOTING\n")
    with pytest.raises(AsmError) as info:
        check_file(str(tmp_path / "Top2.asm"))
    err = info.value
    assert (err.span.line, err.span.col) == (7, 36), err.render()
    assert "domain CameraState, not compatible with the location's domain HealingState" in err.message
