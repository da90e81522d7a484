"""Z3 against breadth-first search on every spec of specs/ and specs/buggy/: the same
first violation depth for every property (invariants, the property file's step
properties, run-time errors) up to the same bound."""
from pathlib import Path

import pytest

from asmcheck.smt.differential import agree, explicit_depths, z3_depths

pytestmark = pytest.mark.engines("none")

ROOT = Path(__file__).resolve().parent.parent
BUGGY = sorted((ROOT / "specs" / "buggy").glob("*.asm"))
CORRECT = sorted((ROOT / "specs").glob("*.asm"))


def expected_safety(path):
    """The properties a seeded-bug spec says it breaks that are invariants or step properties
    (an LTL/CTL one is out of bounded model checking's reach)."""
    from asmcheck.props.files import expected_violations
    from asmcheck.smt.differential import load
    _, _, state_props, step_props = load(str(path))
    names = {p.name for p in state_props + step_props}
    return expected_violations(str(path)) & names


@pytest.mark.parametrize("path", BUGGY, ids=[p.stem for p in BUGGY])
def test_buggy_specs_caught_at_bfs_depth(path):
    d = 10
    ex = explicit_depths(str(path), d)
    z = z3_depths(str(path), d)
    assert agree(ex, z) is None
    # the same violations at the same depths, the seeded one among them
    assert z.depths == ex.depths
    for name in expected_safety(path):
        assert name in z.depths


@pytest.mark.parametrize("path", CORRECT, ids=[p.stem for p in CORRECT])
def test_correct_specs_agree(path):
    d = 6
    ex = explicit_depths(str(path), d)
    z = z3_depths(str(path), d)
    assert agree(ex, z) is None
    assert z.depths == ex.depths == {}


@pytest.mark.slow
@pytest.mark.parametrize("path", [p for p in CORRECT if p.stem != "visual_servoing"],
                         ids=[p.stem for p in CORRECT if p.stem != "visual_servoing"])
def test_correct_specs_agree_deeper(path):
    ex = explicit_depths(str(path), 11)
    z = z3_depths(str(path), 11)
    assert z.depths == ex.depths == {}


@pytest.mark.slow
def test_twin_differential_every_depth(tmp_path):
    from test_smt import twin
    for bug in (False, True):
        path = twin(tmp_path / ("bug" if bug else "ok"), 7, 16, bug=bug)
        for d in (0, 5, 12, 13):
            ex = explicit_depths(path, d)
            z = z3_depths(path, d)
            assert agree(ex, z) is None, (bug, d)
            assert z.depths == ({"inv_exclusive": 13} if bug and d >= 13 else {})
