"""A step property sees one step: a step operator inside next(...) is an error at its own name."""
import pytest

from asmcheck.cli import main
from helpers import write

pytestmark = pytest.mark.engines("python")

SPEC = ("asm c\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
        "\tmain rule r_Main = if x < 3 then x := x + 1 endif\ndefault init s0:\n\tfunction x = 0\n")


@pytest.mark.parametrize("body, col, op", [
    ("next(next(x)) = x", 17, "next"),
    ("next(changed(x))", 17, "changed"),
    ("x = 0 or next(x + 1 = 1 and updated(x))", 40, "updated"),
])
def test_a_step_operator_inside_next_is_an_error(tmp_path, capsys, body, col, op):
    path = write(tmp_path, SPEC)
    prop = tmp_path / "p.prop"
    prop.write_text(f"applies to c\nstep s_nn: {body}\n")
    assert main(["explore", path, "--properties", str(prop)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{prop}:2:{col}: {op}(...) inside next(...): a step property sees one step")


def test_next_alone_and_beside_a_step_operator_is_accepted(tmp_path, capsys):
    path = write(tmp_path, SPEC)
    prop = tmp_path / "p.prop"
    prop.write_text("applies to c\nstep s_ok: changed(x) implies next(x) = x + 1\n")
    assert main(["explore", path, "--properties", str(prop), "--engine", "python"]) == 0
    assert "s_ok" in capsys.readouterr().out
