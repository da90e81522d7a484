"""ITF traces (Apalache/Quint's Informal Trace Format): counterexamples, lassos and testgen paths,
validated with itf-py; a golden file pins the ITF of one counterexample."""
import json

import pytest

from asmcheck.review.itf import explore_itf, itf_value, temporal_itf
from asmcheck.review.testgen import testgen_itf as itf_of_tests
from asmcheck.semantics.values import SetV, SeqV
from conftest import ROOT

pytestmark = pytest.mark.engines("python")

itf_py = pytest.importorskip("itf_py", reason="itf-py is not installed (pip install itf-py; the test extra has it)")

GOLDEN = ROOT / "tests" / "data" / "golden" / "producer_consumer_reader_takes_writer_array.inv_no_concurrent_rw.itf.json"


def _valid(doc):
    """itf-py reads it, writes it back the same, and every state gives every variable a value."""
    tr = itf_py.trace_from_json(doc)
    back = itf_py.trace_to_json(tr)            # and writes it again
    assert back["vars"] == doc["vars"] and len(back["states"]) == len(doc["states"])
    assert tr.vars == doc["vars"] and tr.loop == doc.get("loop")
    for st in doc["states"]:
        assert set(st) - {"#meta"} == set(doc["vars"])
    assert [s["#meta"]["index"] for s in doc["states"]] == list(range(len(doc["states"])))
    if "loop" in doc:
        assert 0 <= doc["loop"] < len(doc["states"])
    return tr


def test_golden_counterexample(monkeypatch):
    monkeypatch.chdir(ROOT)
    (doc,) = explore_itf("specs/buggy/producer_consumer_reader_takes_writer_array.asm")
    tr = _valid(doc)
    assert json.dumps(doc, indent=1) + "\n" == GOLDEN.read_text()
    assert len(tr.states) == 6 and tr.loop is None
    last = tr.states[-1].values
    # the reader reads the array the writer writes: the invariant inv_no_concurrent_rw fails
    assert last["readingArr"] == {("consumer", "SB1"): 1} and last["writingArr"] == {("producer", "SB1"): 1}


def test_lasso_has_loop(monkeypatch):
    monkeypatch.chdir(ROOT)
    docs = temporal_itf("specs/temporal/peterson.asm")
    assert [d["#meta"]["description"] for d in docs] == [
        "counterexample of ltlSpec_p1_enters on peterson, a lasso back to state 2",
        "counterexample of ltlSpec_p2_enters on peterson, a lasso back to state 2",
        "counterexample of ctlSpec_p1_enters on peterson, a lasso back to state 2"]
    d = docs[0]
    tr = _valid(d)
    assert (len(tr.states), tr.loop) == (3, 2)
    assert d["#meta"]["loop-step"] == {"choices": ["choose at peterson.asm:59:3: $p = p2"]}
    assert tr.states[2].values["pc"] == {"p1": "WAIT", "p2": "WAIT"}


def test_testgen_paths(monkeypatch):
    monkeypatch.chdir(ROOT)
    docs = itf_of_tests("specs/sb_async_master.asm", "branch")
    assert len(docs) == 11
    for d in docs:
        _valid(d)
    assert sum(len(d["states"]) - 1 for d in docs) == 45


def test_values():
    assert itf_value(None) == {"#unserializable": "undef"}
    assert itf_value(3) == {"#bigint": "3"}
    assert itf_value(True) is True
    assert itf_value(SetV([2, 1])) == {"#set": [{"#bigint": "1"}, {"#bigint": "2"}]}
    assert itf_value(SeqV([1])) == [{"#bigint": "1"}]
    assert itf_value((1, "a")) == {"#tup": [{"#bigint": "1"}, "a"]}
    assert itf_value(1.5) == {"#unserializable": "1.5"}


def test_documents_of_api_violations(monkeypatch):
    """itf_documents reads what the public API's violations carry: the replayed trace, or the
    temporal result's lasso."""
    from types import SimpleNamespace
    from asmcheck.explore.bfs import Explorer
    from asmcheck.props.files import properties_for
    from asmcheck.report.trace import build_trace
    from asmcheck.review.itf import itf_documents, load_machine as _load
    from asmcheck.temporal import check_temporal
    monkeypatch.chdir(ROOT)
    path = "specs/buggy/producer_consumer_reader_takes_writer_array.asm"
    spec, m = _load(path)
    xs, xt, _ = properties_for(spec, m, path, None, use_default=True)
    ex = Explorer(m, state_props=xs, step_props=xt)
    res = ex.run()
    vs = [SimpleNamespace(raw=v, trace=SimpleNamespace(raw=build_trace(ex, v))) for v in res.violations]
    (doc,) = itf_documents(m, vs, path)
    assert json.dumps(doc, indent=1) + "\n" == GOLDEN.read_text()
    path = "specs/temporal/peterson.asm"
    spec, m = _load(path)
    _, _, temporal = properties_for(spec, m, path, None, use_default=True)
    ex = Explorer(m, keep_graph=True)
    ex.run()
    results = [SimpleNamespace(raw=r) for r in check_temporal(ex, temporal) if not r.holds]
    docs = itf_documents(m, results, path)
    assert [(len(d["states"]), d["loop"]) for d in docs] == [(3, 2), (3, 2), (3, 2)]
    assert docs == temporal_itf(path)


def test_command_line(capsys, monkeypatch):
    from asmcheck.cli import main
    monkeypatch.chdir(ROOT)
    spec = "specs/buggy/producer_consumer_reader_takes_writer_array.asm"
    assert main(["explore", spec, "--format", "itf"]) == 1
    (doc,) = json.loads(capsys.readouterr().out)
    assert json.dumps(doc, indent=1) + "\n" == GOLDEN.read_text()
    assert main(["bmc", spec, "-k", "6", "--format", "itf"]) == 1
    (doc,) = json.loads(capsys.readouterr().out)
    tr = _valid(doc)
    assert len(tr.states) == 6 and doc["#meta"]["description"].endswith("inv_no_concurrent_rw on "
                                                                      "producer_consumer_reader_takes_writer_array")
    assert main(["explore", "specs/temporal/peterson.asm", "--format", "itf"]) == 1
    docs = json.loads(capsys.readouterr().out)
    assert [(len(d["states"]), d["loop"]) for d in docs] == [(3, 2), (3, 2), (3, 2)]
    assert main(["testgen", "specs/sb_async_master.asm", "--format", "itf"]) == 0
    docs = json.loads(capsys.readouterr().out)
    assert len(docs) == 11 and all(_valid(d) for d in docs)
