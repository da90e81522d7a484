import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))
ASMETA = SHARED / "asmeta"
BENCH = SHARED / "bench"


def need_asmeta():
    if not (ASMETA / "MANIFEST.tsv").exists():
        pytest.skip(f"the ASMETA corpus is not at {ASMETA} (set ASMCHECK_SHARED to the shared folder)")
    return ASMETA


def need_bench():
    if not (BENCH / "gen_swing.py").exists():
        pytest.skip(f"the benchmark twins are not at {BENCH}")
    return BENCH


@pytest.fixture
def asmeta():
    return need_asmeta()


@pytest.fixture
def write_spec(tmp_path):
    """Write a spec named after its asm/module header into tmp_path; return its path."""
    def _write(text: str, name: str | None = None) -> str:
        import re
        if name is None:
            m = re.search(r"\b(?:asm|module)\s+([A-Za-z_][A-Za-z0-9_]*)", text)
            name = m.group(1) if m else "Spec"
        p = tmp_path / f"{name}.asm"
        p.write_text(text, encoding="utf-8")
        return str(p)
    return _write
