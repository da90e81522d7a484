"""The compiled LTL kernel (temporal/kernel.c: the product and its fair components over arrays)
gives exactly what the Python code of temporal/ltl.py gives: the same verdicts, product sizes and
counterexample lassos, with justice (JUSTICE, --fair, g(f(p)) assumptions) and compassion.
Engines pinned: python and native explorers, kernel on and off."""
from __future__ import annotations

from pathlib import Path

import pytest

from asmcheck import api
from asmcheck.explore.native_build import compiler
from asmcheck.temporal import kernel

ROOT = Path(__file__).resolve().parent.parent
TEMPORAL = ROOT / "specs" / "temporal"

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the kernel is not built")]

CASES = [
    ("counter.asm", None, ()),
    ("peterson.asm", None, ()),
    ("peterson.asm", None, ("Proc",)),
    ("peterson.asm", "peterson_fair.prop", ()),
    ("spinlock.asm", None, ("Proc",)),
    ("spinlock.asm", "spinlock_strong.prop", ("Proc",)),
    ("request_ack.asm", None, ()),
    ("grid.asm", "grid_fair.prop", ()),
]


def _rows(spec, prop, fair, engine, enabled):
    kernel.ENABLED = enabled
    try:
        props = [str(TEMPORAL / prop)] if prop else None
        model = api.load(str(TEMPORAL / spec), properties=props)
        run = model.explore(engine=engine, fair=fair)
        return [(r.name, r.kind, r.holds, list(r.nodes), r.loop, r.stats.get("product_states"), r.message)
                for r in run.temporal]
    finally:
        kernel.ENABLED = True


@pytest.mark.parametrize("spec,prop,fair", CASES)
@pytest.mark.parametrize("engine", ["python", "auto"])
def test_kernel_equals_python_code(spec, prop, fair, engine):
    with_kernel = _rows(spec, prop, fair, engine, True)
    without = _rows(spec, prop, fair, engine, False)
    assert with_kernel == without
    assert any(kind == "ltl" for _, kind, *_ in with_kernel) or spec == "counter.asm"


def test_kernel_is_used():
    kernel.ENABLED = True
    assert kernel.library() is not None


def test_counter_lasso_and_product_sizes():
    rows = {r[0]: r for r in _rows("counter.asm", None, (), "auto", True)}
    name, kind, holds, nodes, loop, product, _ = rows["ltlSpec_reset_often"]
    # 0 -> 1 -> 2 -> 1 -> 2 ...: the loop starts at the third node; 7 product states
    assert (holds, nodes, loop, product) == (False, [0, 1, 2, 1], 2, 7)
    assert rows["ltlSpec_never_two_twice"][2:] == (True, [], None, 4, "")
