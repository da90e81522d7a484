"""asmcheck's verdicts against ASMETA's own parser on the corpus (../shared/asmeta/MANIFEST.tsv).

Every file ASMETA accepts is accepted; at least 90 % of the files it rejects are rejected,
each with a file, line and column.
"""
import time

import pytest

from asmcheck.errors import AsmError
from asmcheck.semantics.resolve import check_file

from conftest import need_asmeta

pytestmark = pytest.mark.engines("none")


def _manifest(root):
    rows = []
    for line in (root / "MANIFEST.tsv").read_text().splitlines()[1:]:
        path, verdict = line.split("\t")
        rows.append((path, verdict))
    return rows


def _verdicts():
    root = need_asmeta()
    out = []
    for path, verdict in _manifest(root):
        try:
            check_file(str(root / path))
            ours, err = "accepts", None
        except AsmError as e:
            ours, err = "rejects", e
        out.append((path, verdict, ours, err))
    return out


@pytest.fixture(scope="module")
def verdicts():
    t0 = time.perf_counter()
    v = _verdicts()
    v.append(("__seconds__", time.perf_counter() - t0, None, None))
    return v


def test_accept_rate(verdicts):
    rows = [r for r in verdicts if r[0] != "__seconds__"]
    acc = [r for r in rows if r[1] == "accepts"]
    ok = [r for r in acc if r[2] == "accepts"]
    missing = [(r[0], str(r[3])) for r in acc if r[2] != "accepts"]
    assert missing == []
    assert len(ok) == len(acc) and any("RTPatternLibrary" in r[0] for r in ok) and any("tutorial" in r[0] for r in ok)


def test_reject_rate(verdicts):
    rows = [r for r in verdicts if r[0] != "__seconds__"]
    rej = [r for r in rows if r[1] == "rejects"]
    caught = [r for r in rej if r[2] == "rejects"]
    missed = [r[0] for r in rej if r[2] != "rejects"]
    assert len(caught) / len(rej) >= 0.90, missed
    # each rejection is located: file, line and column
    for r in rej:
        if r[2] == "rejects":
            assert r[3].span is not None and r[3].span.line >= 1 and r[3].span.col >= 1, (r[0], r[3].message)


def test_report(verdicts, capsys):
    """Print the numbers (seen with ``pytest -s``)."""
    rows = [r for r in verdicts if r[0] != "__seconds__"]
    secs = [r[1] for r in verdicts if r[0] == "__seconds__"][0]
    acc = [r for r in rows if r[1] == "accepts"]
    rej = [r for r in rows if r[1] == "rejects"]
    with capsys.disabled():
        print(f"\ncorpus: {len(rows)} files; ASMETA accepts {len(acc)}, asmcheck accepts "
              f"{sum(r[2] == 'accepts' for r in acc)} of them; ASMETA rejects {len(rej)}, asmcheck rejects "
              f"{sum(r[2] == 'rejects' for r in rej)} of them; {secs:.1f} s")
