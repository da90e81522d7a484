"""The project's own models, specs/ and specs/buggy/: pinned state counts, verdicts and
counterexamples, through the CI property gate (`asmcheck check FILE --strict-expect --json -`).

Every correct spec satisfies every property that applies to it (its own invariants and
LTLSPECs under its JUSTICE constraints, and properties/swinging_buffer.prop) over its whole
state space; every seeded-bug variant violates exactly the one property its
`// asmcheck: expect violated NAME` line names, with a shortest replayed counterexample of
the pinned length. A change to a count, a verdict or a trace length fails here: update the
table in specs/README.md together with the pins below.
"""
import json
import re
from pathlib import Path

import pytest

from asmcheck.cli import main

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parent.parent

# the properties of properties/swinging_buffer.prop: each applies to every spec pinned here
PROP_FILE = {"inv_no_concurrent_rw", "stp_lock_release_on_exit", "stp_slave_never_moves_indexes",
             "stp_failed_slave_no_interference", "stp_indexes_moved_under_lock"}

# correct spec -> (states, transitions)
CORRECT = {
    "specs/sb_async_master.asm": (219, 512),
    "specs/sb_sync_master.asm": (395, 1054),
    "specs/sb_sync_slave.asm": (267, 662),
    "specs/sb_async_slave.asm": (483, 1232),
    "specs/producer_consumer.asm": (245, 639),
    "specs/visual_servoing.asm": (5219, 20583),
}

# seeded-bug spec -> (states, transitions, the property it breaks, steps of its
# counterexample, step the loop goes back to for an LTL lasso / None for a safety trace)
BUGGY = {
    "specs/buggy/sb_async_master_no_release.asm": (207, 484, "stp_lock_release_on_exit", 4, None),
    "specs/buggy/sb_sync_master_no_watchdog.asm": (357, 948, "ltlSpec_master_leaves", 9, 4),
    "specs/buggy/sb_sync_slave_moves_indexes.asm": (267, 662, "stp_slave_never_moves_indexes", 4, None),
    "specs/buggy/sb_sync_slave_clears_lock.asm": (387, 1038, "stp_failed_slave_no_interference", 4, None),
    "specs/buggy/sb_async_slave_no_recheck.asm": (165, 392, "ltlSpec_slave_leaves", 9, 3),
    "specs/buggy/producer_consumer_reader_takes_writer_array.asm": (245, 639, "inv_no_concurrent_rw", 5, None),
    "specs/buggy/visual_servoing_swap_without_lock.asm": (5201, 20523, "stp_indexes_moved_under_lock", 6, None),
}


def _params(paths):
    return [pytest.param(p, id=Path(p).stem, marks=[pytest.mark.slow] if "visual_servoing" in p else [])
            for p in paths]


def check(path, capsys, monkeypatch):
    """Run the gate on one spec; return (exit code, the spec's JSON record)."""
    monkeypatch.chdir(ROOT)
    code = main(["check", path, "--strict-expect", "--traces", "none", "--json", "-"])
    out = json.loads(capsys.readouterr().out)
    (rec,) = out["specs"]
    assert rec["error"] is None and rec["incomplete"] is None, rec
    return code, rec


def violated(rec):
    return {p["property"] for p in rec["properties"] if p["verdict"] != "holds"}


def test_every_spec_is_pinned():
    on_disk = {str(p.relative_to(ROOT)) for p in (ROOT / "specs").glob("*.asm")}
    on_disk |= {str(p.relative_to(ROOT)) for p in (ROOT / "specs" / "buggy").glob("*.asm")}
    assert on_disk == set(CORRECT) | set(BUGGY)


@pytest.mark.parametrize("path", _params(CORRECT))
def test_correct_spec_satisfies_all_its_properties(path, capsys, monkeypatch):
    code, rec = check(path, capsys, monkeypatch)
    assert code == 0
    assert (rec["states"], rec["transitions"]) == CORRECT[path]
    assert rec["expected_violations"] == []
    assert violated(rec) == set()
    names = {p["property"] for p in rec["properties"]}
    assert PROP_FILE <= names  # swinging_buffer.prop applies
    assert any(n.startswith("ltlSpec_") for n in names)
    assert all(p["verdict"] == "holds" and p["status"] == "pass" for p in rec["properties"])


@pytest.mark.parametrize("path", _params(BUGGY))
def test_buggy_spec_violates_exactly_its_property(path, capsys, monkeypatch):
    states, transitions, target, steps, loop_start = BUGGY[path]
    code, rec = check(path, capsys, monkeypatch)
    assert code == 0  # --strict-expect: any other violation would fail the gate
    assert (rec["states"], rec["transitions"]) == (states, transitions)
    assert rec["expected_violations"] == [target]
    assert violated(rec) == {target}
    names = {p["property"] for p in rec["properties"]}
    assert PROP_FILE <= names  # swinging_buffer.prop applies
    (bad,) = [p for p in rec["properties"] if p["property"] == target]
    assert (bad["verdict"], bad["expected"], bad["status"]) == ("violated", True, "pass")
    ce = bad["counterexample"]
    assert len(ce["trace"]) - 1 == steps
    assert [e["step"] for e in ce["trace"]] == list(range(steps + 1))
    assert ce.get("loop_start") == loop_start
    if loop_start is not None:
        # a lasso: the last state is the state the loop goes back to
        assert ce["trace"][-1]["state"] == ce["trace"][loop_start]["state"]


@pytest.mark.parametrize("path", list(BUGGY))
def test_buggy_spec_header_documents_the_change(path):
    text = (ROOT / path).read_text(encoding="utf-8")
    target = BUGGY[path][2]
    first, rest = text.split("\n", 1)
    assert first == f"// asmcheck: expect violated {target}"
    header = rest[:rest.index("*/")]
    assert "SEEDED BUG -- copy of specs/" in header
    assert f"Breaks: {target}" in header
    assert "Why nothing else breaks" in header
    base = re.search(r"copy of (specs/\w+\.asm)", header).group(1)
    assert base in CORRECT
    # the body marks the change(s) and keeps the file's own asm name
    assert "SEEDED BUG" in rest[rest.index("*/"):]
    assert re.search(rf"^asm {Path(path).stem}$", text, re.M)


def test_variants_cover_every_paper_property_and_a_liveness_one():
    targets = [t for _, _, t, _, _ in BUGGY.values()]
    assert len(targets) >= 6
    assert PROP_FILE <= set(targets)
    assert any(t.startswith("ltlSpec_") for t in targets)
