"""The CI property gate over all of specs/ (the correct models, the seeded bugs, the temporal
examples) passes with --strict-expect: no violation that a spec does not declare."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.slow
def test_check_specs_strict_expect_passes():
    out = subprocess.run([sys.executable, "-m", "asmcheck", "check", "specs", "--strict-expect",
                          "--traces", "none", "--json", "-"], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout[-4000:] + out.stderr[-4000:]
    res = json.loads(out.stdout)
    assert res["gate"] == "pass"
    s = res["summary"]
    assert (s["failed"], s["tolerated"], s["incomplete"], s["errors"]) == (0, 0, 0, 0)
    paths = {r["path"] for r in res["specs"]}
    assert {"specs/sb_async_master.asm", "specs/buggy/sb_async_master_no_release.asm"} <= paths
