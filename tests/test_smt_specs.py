"""Z3 against breadth-first search on every spec of specs/ and specs/buggy/: the same
first violation depth for every property (invariants, the property file's step
properties, run-time errors) up to the same bound."""
from pathlib import Path

import pytest

from asmcheck.smt.differential import agree, explicit_depths, z3_depths

from test_smt import EXPECTED_BUGGY

ROOT = Path(__file__).resolve().parent.parent
BUGGY = sorted((ROOT / "specs" / "buggy").glob("*.asm"))
CORRECT = sorted((ROOT / "specs").glob("*.asm"))


@pytest.mark.parametrize("path", BUGGY, ids=[p.stem for p in BUGGY])
def test_buggy_specs_caught_at_bfs_depth(path):
    # one step past the deepest expected violation (the explorer's cost grows fast with depth)
    d = max(EXPECTED_BUGGY[path.stem].values(), default=7) + 1
    ex = explicit_depths(str(path), d)
    z = z3_depths(str(path), d)
    assert agree(ex, z) is None
    assert z.depths == ex.depths == EXPECTED_BUGGY[path.stem]


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
