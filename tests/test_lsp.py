"""The language server end to end: a real LSP client (pytest-lsp) talks to ``asmcheck lsp`` over stdio."""
from __future__ import annotations

import asyncio
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pygls", reason="the language server needs the 'lsp' extra (pip install '.[lsp]')")
pytest.importorskip("lsprotocol", reason="the language server needs the 'lsp' extra (pip install '.[lsp]')")
pytest_lsp = pytest.importorskip("pytest_lsp", reason="the end-to-end tests need pytest-lsp (pip install '.[test]')")

from lsprotocol import types as lsp  # noqa: E402
from pygls.uris import from_fs_path  # noqa: E402
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities  # noqa: E402

from asmcheck.syntax.parser import decode_source  # noqa: E402
from conftest import ASMETA, ROOT  # noqa: E402
from test_bad_inputs import CASES  # noqa: E402

pytestmark = pytest.mark.engines("python")

SERVER = [sys.executable, "-m", "asmcheck", "lsp"]
ENV = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
RTP = ASMETA / "asm_examples" / "RTPatternLibrary"


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER, server_env=ENV))
async def client(lsp_client: LanguageClient):
    caps = client_capabilities("visual-studio-code")
    caps.workspace.code_lens = None          # the test client does not answer workspace/codeLens/refresh
    await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=caps,
        root_uri=from_fs_path(str(ROOT)),
        initialization_options={"asmetal": {"exploreTimeLimit": 60}}))
    yield
    await lsp_client.shutdown_session()


async def _until(check, what: str, seconds: float = 60) -> None:
    """Wait until ``check()`` holds (notifications that come together are handled before a wait)."""
    for _ in range(int(seconds / 0.05)):
        if check():
            return
        await asyncio.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


async def _diagnostics(client: LanguageClient, uri: str) -> None:
    """Wait for the next diagnostics of ``uri`` (call ``client.diagnostics.pop(uri)`` before the change)."""
    await _until(lambda: uri in client.diagnostics, f"diagnostics of {uri}")


async def _open(client: LanguageClient, path: Path, text: str | None = None) -> str:
    uri = from_fs_path(str(path))
    client.diagnostics.pop(uri, None)
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(
        uri=uri, language_id="asmetal", version=1,
        text=decode_source(path.read_bytes()) if text is None else text)))
    await _diagnostics(client, uri)
    return uri


def _cli_positions(paths: list[Path]) -> dict[str, tuple[int, int, str]]:
    """``asmcheck parse`` on each file: the line, column and message it prints."""
    r = subprocess.run([sys.executable, "-m", "asmcheck", "parse", *map(str, paths)], capture_output=True,
                       text=True, cwd=ROOT)
    out = r.stdout + r.stderr
    found = {}
    for p in paths:
        m = re.search(rf"^{re.escape(str(p))}:(\d+):(\d+): (.*)$", out, re.M)
        assert m, f"the CLI printed no position for {p}:\n{out}"
        found[str(p)] = (int(m.group(1)), int(m.group(2)), m.group(3))
    return found


@pytest.mark.asyncio
async def test_bad_inputs_carry_the_cli_position(client: LanguageClient, tmp_path):
    paths = []
    for i, (label, text, line, col, fragment) in enumerate(CASES):
        d = tmp_path / f"case{i:02d}"
        d.mkdir()
        (d / "T.asm").write_text(text, encoding="utf-8")
        paths.append(d / "T.asm")
    cli = _cli_positions(paths)
    for (label, text, line, col, fragment), path in zip(CASES, paths):
        uri = await _open(client, path)
        diags = client.diagnostics[uri]
        assert len(diags) == 1, (label, diags)
        d = diags[0]
        cl, cc, msg = cli[str(path)]
        assert (d.range.start.line + 1, d.range.start.character + 1) == (cl, cc) == (line, col), label
        assert d.message == msg, label
        assert d.severity == lsp.DiagnosticSeverity.Error


@pytest.mark.asyncio
async def test_error_in_an_imported_module_shows_on_the_import_line(client: LanguageClient, tmp_path):
    (tmp_path / "Lib.asm").write_text("module Lib\nimport StandardLibrary\nexport *\nsignature:\n"
                                      "\tcontrolled x: Widget\ndefinitions:\n", encoding="utf-8")
    main = tmp_path / "Main.asm"
    main.write_text("asm Main\nimport StandardLibrary\nimport Lib\nsignature:\ndefinitions:\n"
                    "\tmain rule r_main = skip\n", encoding="utf-8")
    uri = await _open(client, main)
    [d] = client.diagnostics[uri]
    assert (d.range.start.line, d.range.start.character) == (2, 0)
    assert (d.range.end.line, d.range.end.character) == (2, 10)
    assert d.message == "Lib.asm:5:16: unknown domain 'Widget'"
    [rel] = d.related_information
    assert rel.location.uri == from_fs_path(str(tmp_path / "Lib.asm"))
    assert (rel.location.range.start.line, rel.location.range.start.character) == (4, 15)
    assert rel.message == "unknown domain 'Widget'"


@pytest.mark.asyncio
async def test_saving_an_imported_module_updates_its_importers(client: LanguageClient, tmp_path):
    lib = tmp_path / "Lib.asm"
    lib.write_text("module Lib\nimport StandardLibrary\nexport *\nsignature:\n\tcontrolled x: Integer\n"
                   "definitions:\n", encoding="utf-8")
    main = tmp_path / "Main.asm"
    main.write_text("asm Main\nimport StandardLibrary\nimport Lib\nsignature:\ndefinitions:\n"
                    "\tmain rule r_main = y := 1\n", encoding="utf-8")
    main_uri = await _open(client, main)
    [d] = client.diagnostics[main_uri]
    assert d.message == "unknown function 'y'" and d.range.start.line == 5
    lib_uri = await _open(client, lib)
    fixed = lib.read_text().replace("x: Integer", "y: Integer")
    client.diagnostics.pop(lib_uri)
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=lib_uri, version=2),
        [lsp.TextDocumentContentChangeWholeDocument(text=fixed)]))
    await _diagnostics(client, lib_uri)
    lib.write_text(fixed, encoding="utf-8")
    client.text_document_did_save(lsp.DidSaveTextDocumentParams(lsp.TextDocumentIdentifier(lib_uri)))
    await _until(lambda: list(client.diagnostics[main_uri]) == [], "the importer's diagnostics to clear")


@pytest.mark.asyncio
async def test_diagnostics_follow_edits(client: LanguageClient, tmp_path):
    path = tmp_path / "T.asm"
    good = "asm T\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n" \
           "\tmain rule r_main = x := x + 1\n"
    uri = await _open(client, path, good)
    assert list(client.diagnostics[uri]) == []
    client.diagnostics.pop(uri)
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
        [lsp.TextDocumentContentChangePartial(
            range=lsp.Range(lsp.Position(5, 25), lsp.Position(5, 26)), text="y")]))
    await _diagnostics(client, uri)
    [d] = client.diagnostics[uri]
    assert d.message == "unknown function 'y'"
    assert (d.range.start.line, d.range.start.character) == (5, 25)


SPEC = """asm Shop
import StandardLibrary
signature:
\tenum domain Color = {RED | GREEN}
\tdomain Slot subsetof Integer
\t// how many items are on each slot
\tcontrolled stock: Slot -> Integer
\tcontrolled light: Color
definitions:
\tdomain Slot = {1 : 3}
\trule r_fill($s in Slot, $n in Integer) =
\t\tlet ($old = stock($s)) in
\t\t\tforall $k in Slot with $k = $s do stock($k) := $old + $n
\t\tendlet
\tinvariant inv_nonneg over stock: (forall $q in Slot with stock($q) >= 0)
\tmain rule r_main =
\t\tchoose $c in Slot with true do
\t\t\tpar
\t\t\t\tr_fill[$c, 1]
\t\t\t\tlight := RED
\t\t\tendpar
default init s0:
\tfunction stock($s in Slot) = 0
\tfunction light = GREEN
"""


def _at(line: int, needle: str, nth: int = 0, text: str = SPEC) -> lsp.Position:
    """The position of the nth occurrence of ``needle`` on 0-based ``line`` of ``text``."""
    s = text.split("\n")[line]
    col = -1
    for _ in range(nth + 1):
        col = s.index(needle, col + 1)
    return lsp.Position(line, col)


def _labels(items) -> set[str]:
    return {i.label for i in (items.items if isinstance(items, lsp.CompletionList) else items)}


@pytest.mark.asyncio
async def test_completion_offers_the_variables_in_scope(client: LanguageClient, tmp_path):
    path = tmp_path / "Shop.asm"
    uri = await _open(client, path, SPEC)
    assert list(client.diagnostics[uri]) == []

    async def complete(pos: lsp.Position):
        return _labels(await client.text_document_completion_async(lsp.CompletionParams(
            lsp.TextDocumentIdentifier(uri), pos)))

    # inside the forall of r_fill, at 'stock($k)'
    inner = await complete(_at(12, "stock($k)"))
    assert {"$s", "$n", "$old", "$k"} <= inner
    assert "$c" not in inner and "$q" not in inner
    assert {"stock", "light", "r_fill", "r_main", "Slot", "Color", "RED", "GREEN", "plus", "Integer"} <= inner
    # inside the let, outside the forall
    in_let = await complete(_at(11, "stock"))
    assert {"$s", "$n", "$old"} <= in_let and "$k" not in in_let
    # in the main rule: only $c
    main_vars = {x for x in await complete(_at(18, "r_fill")) if x.startswith("$")}
    assert main_vars == {"$c"}
    # while typing, the text does not parse: the last text that did gives the scopes
    client.diagnostics.pop(uri)
    client.text_document_did_change(lsp.DidChangeTextDocumentParams(
        lsp.VersionedTextDocumentIdentifier(uri=uri, version=2),
        [lsp.TextDocumentContentChangePartial(range=lsp.Range(_at(19, "light"), _at(19, "light")),
                                              text="stock($")]))
    await _diagnostics(client, uri)
    assert len(client.diagnostics[uri]) == 1
    typing = await complete(lsp.Position(19, _at(19, "light").character + len("stock($")))
    assert {x for x in typing if x.startswith("$")} == {"$c"} and "stock" in typing


@pytest.mark.asyncio
async def test_symbols_hover_and_local_navigation(client: LanguageClient, tmp_path):
    path = tmp_path / "Shop.asm"
    uri = await _open(client, path, SPEC)
    syms = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(lsp.TextDocumentIdentifier(uri)))
    got = [(s.name, s.kind, s.detail) for s in syms]
    assert got == [
        ("Color", lsp.SymbolKind.Enum, "enum domain"),
        ("Slot", lsp.SymbolKind.Class, "domain subsetof Integer"),
        ("stock", lsp.SymbolKind.Function, "controlled: Slot -> Integer"),
        ("light", lsp.SymbolKind.Function, "controlled: Color"),
        ("r_fill", lsp.SymbolKind.Method, "rule($s in Slot, $n in Integer)"),
        ("inv_nonneg", lsp.SymbolKind.Property, "invariant"),
        ("r_main", lsp.SymbolKind.Method, "main rule"),
    ]
    assert [c.name for c in syms[0].children] == ["RED", "GREEN"]
    hov = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri),
                                                                 _at(12, "stock(")))
    assert "controlled stock: Slot -> Integer" in hov.contents.value
    assert "how many items are on each slot" in hov.contents.value
    hov = await client.text_document_hover_async(lsp.HoverParams(lsp.TextDocumentIdentifier(uri),
                                                                 _at(18, "r_fill")))
    assert "rule r_fill($s in Slot, $n in Integer)" in hov.contents.value
    # $old used on line 13 is bound on line 12
    [loc] = await client.text_document_definition_async(lsp.DefinitionParams(
        lsp.TextDocumentIdentifier(uri), _at(12, "$old")))
    assert loc.range.start == _at(11, "$old")
    refs = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=lsp.TextDocumentIdentifier(uri), position=_at(6, "stock"),
        context=lsp.ReferenceContext(include_declaration=True)))
    assert [r.range.start for r in refs] == [_at(6, "stock"), _at(11, "stock"), _at(12, "stock"),
                                             _at(14, "stock"), _at(14, "stock", 1), _at(22, "stock")]


@pytest.mark.asyncio
async def test_definition_of_a_library_function_opens_the_builtin_library(client: LanguageClient, tmp_path):
    path = tmp_path / "Shop.asm"
    uri = await _open(client, path, SPEC)
    locs = await client.text_document_definition_async(lsp.DefinitionParams(
        lsp.TextDocumentIdentifier(uri), _at(4, "Integer")))
    [loc] = locs
    assert loc.uri == "asmcheck:/library/StandardLibrary.asm"
    res = await client.protocol.send_request_async("asmcheck/textDocumentContent", {"uri": loc.uri})
    text = res["text"] if isinstance(res, dict) else res.text
    line = text.split("\n")[loc.range.start.line]
    assert line[loc.range.start.character:loc.range.end.character] == "Integer"
    assert line.strip() == "basic domain Integer"


def _need_rtpattern():
    if not (RTP / "Application" / "VisualServoing.asm").exists():
        pytest.skip(f"RTPatternLibrary is not at {RTP} (set ASMCHECK_SHARED to the shared folder)")


@pytest.mark.asyncio
async def test_definition_and_references_across_imports(client: LanguageClient):
    _need_rtpattern()
    vs = RTP / "Application" / "VisualServoing.asm"
    uri = await _open(client, vs)
    assert list(client.diagnostics[uri]) == []
    # line 85: r_SwingingBuffer_init [cam2Vs_SB , ...] -- a pattern rule of Pattern/SwingingBuffer.asm
    text = decode_source(vs.read_bytes()).split("\n")
    col = text[84].index("r_SwingingBuffer_init")
    [loc] = await client.text_document_definition_async(lsp.DefinitionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(84, col + 3)))
    sb = RTP / "Pattern" / "SwingingBuffer.asm"
    assert loc.uri == from_fs_path(str(sb))
    assert (loc.range.start.line, loc.range.start.character, loc.range.end.character) == (37, 7, 28)
    assert decode_source(sb.read_bytes()).split("\n")[37][7:28] == "r_SwingingBuffer_init"
    refs = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=lsp.TextDocumentIdentifier(uri), position=lsp.Position(84, col + 3),
        context=lsp.ReferenceContext(include_declaration=True)))
    got = [(Path(r.uri).name, r.range.start.line + 1) for r in refs]
    assert got == [("VisualServoing.asm", 85), ("VisualServoing.asm", 86), ("SwingingBuffer.asm", 38)]
    # on an import clause, definition opens the module it reads
    [loc] = await client.text_document_definition_async(lsp.DefinitionParams(
        lsp.TextDocumentIdentifier(uri), lsp.Position(5, 12)))
    assert loc.uri == from_fs_path(str(RTP / "CommonBehaviour" / "Scheduler.asm"))


def _cli_trace(spec: Path, prop: str) -> str:
    """The counterexample block `asmcheck explore` prints for ``prop``."""
    out = subprocess.run([sys.executable, "-m", "asmcheck", "explore", str(spec)], capture_output=True, text=True,
                         cwd=ROOT).stdout
    blocks = out.split("\n\n")
    [block] = [b for b in blocks if b.startswith(prop + " ")]
    lines = block.split("\n")
    return "\n".join(ln for ln in lines if not ln.startswith("verdict: ")).rstrip("\n") + "\n"


async def _lenses(client: LanguageClient, uri: str) -> list[lsp.CodeLens]:
    return await client.text_document_code_lens_async(lsp.CodeLensParams(lsp.TextDocumentIdentifier(uri)))


@pytest.mark.asyncio
async def test_explore_lens_and_counterexample_document(client: LanguageClient):
    spec = ROOT / "specs" / "buggy" / "sb_async_master_no_release.asm"
    uri = await _open(client, spec)
    assert list(client.diagnostics[uri]) == []
    lenses = await _lenses(client, uri)
    main_line = next(i for i, ln in enumerate(spec.read_text().split("\n")) if "main rule r_main" in ln)
    titles = [(ln.range.start.line, ln.command.title) for ln in lenses]
    assert (main_line, "Explore") in titles and (main_line, "Simulate 10 steps") in titles
    explore = next(ln.command for ln in lenses if ln.command.title == "Explore" and ln.range.start.line == main_line)
    result = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command=explore.command, arguments=explore.arguments))
    assert result["verdict"] == "violated"
    verdicts = {p["name"]: p["verdict"] for p in result["properties"]}
    assert verdicts["stp_lock_release_on_exit"] == "violated"
    assert sum(v == "violated" for v in verdicts.values()) == 1 and len(verdicts) == 9
    # the verdict is a diagnostic at the property's span (swinging_buffer.prop:37:6)
    prop_uri = from_fs_path(str(ROOT / "properties" / "swinging_buffer.prop"))
    bad = [d for d in client.diagnostics[prop_uri] if d.severity == lsp.DiagnosticSeverity.Error]
    assert [(d.range.start.line + 1, d.range.start.character + 1) for d in bad] == [(37, 6)]
    assert bad[0].message.startswith("stp_lock_release_on_exit: violated (207 states")
    # the spec's own properties hold, at their own lines
    own = {d.message.split(":")[0]: d.range.start.line + 1 for d in client.diagnostics[uri]}
    assert own == {"inv_indexes_distinct": 328, "inv_arrays_current": 331, "ltlSpec_master_leaves": 340,
                   "ltlSpec_slave_leaves": 343}
    # the run reported $/progress from begin to end
    kinds = [[v.kind for v in reports] for reports in client.progress_reports.values()]
    assert ["begin", "end"] == [k for k in kinds[-1] if k != "report"]
    # Show counterexample opens an asmcheck: document whose text is the CLI's trace
    lenses = await _lenses(client, uri)
    show = next(ln.command for ln in lenses if ln.command.title == "Show counterexample: stp_lock_release_on_exit")
    doc_uri = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command=show.command, arguments=show.arguments))
    assert doc_uri.startswith("asmcheck:/counterexample/sb_async_master_no_release/stp_lock_release_on_exit")
    assert client.shown_documents[-1].uri == doc_uri
    res = await client.protocol.send_request_async("asmcheck/textDocumentContent", {"uri": doc_uri})
    text = res["text"] if isinstance(res, dict) else res.text
    assert text == _cli_trace(spec, "stp_lock_release_on_exit")
    assert text.startswith("stp_lock_release_on_exit (swinging_buffer.prop:37:6) is violated -- shortest "
                           "counterexample, 4 steps (the last step breaks it):\n  formula: ")


@pytest.mark.asyncio
async def test_simulate_lens_shows_what_the_cli_prints(client: LanguageClient):
    spec = ROOT / "specs" / "sb_async_master.asm"
    uri = await _open(client, spec)
    lenses = await _lenses(client, uri)
    sim = next(ln.command for ln in lenses if ln.command.title == "Simulate 10 steps")
    doc_uri = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command=sim.command, arguments=sim.arguments))
    res = await client.protocol.send_request_async("asmcheck/textDocumentContent", {"uri": doc_uri})
    text = res["text"] if isinstance(res, dict) else res.text
    cli = subprocess.run([sys.executable, "-m", "asmcheck", "simulate", str(spec), "-n", "10"], capture_output=True,
                         text=True, cwd=ROOT).stdout
    assert text == cli
    assert text.count("\nstep ") == 10


@pytest.mark.asyncio
async def test_a_long_exploration_can_be_cancelled(client: LanguageClient, tmp_path):
    spec = tmp_path / "Count.asm"
    spec.write_text("asm Count\nimport StandardLibrary\nsignature:\n\tcontrolled n: Integer\ndefinitions:\n"
                    "\tmain rule r_main = n := n + 1\ndefault init s0:\n\tfunction n = 0\n", encoding="utf-8")
    uri = await _open(client, spec)
    task = asyncio.ensure_future(client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command="asmcheck.explore", arguments=[uri])))
    for _ in range(200):        # wait for the first progress report, then press Cancel
        reports = [t for t, r in client.progress_reports.items() if any(v.kind == "report" for v in r)]
        if reports:
            break
        await asyncio.sleep(0.05)
    assert reports, "no $/progress report arrived"
    client.window_work_done_progress_cancel(lsp.WorkDoneProgressCancelParams(token=reports[0]))
    result = await asyncio.wait_for(task, 20)
    assert result == {"cancelled": True}
    assert client.progress_reports[reports[0]][-1].kind == "end"
    assert client.progress_reports[reports[0]][-1].message == "cancelled"


@pytest.mark.asyncio
async def test_settings_import_path_and_monitored_bounds(client: LanguageClient, tmp_path):
    lib_dir = tmp_path / "libs"
    lib_dir.mkdir()
    (lib_dir / "Lib.asm").write_text("module Lib\nimport StandardLibrary\nexport *\nsignature:\n"
                                     "\tmonitored speed: Integer\ndefinitions:\n", encoding="utf-8")
    spec = tmp_path / "Car.asm"
    spec.write_text("asm Car\nimport StandardLibrary\nimport Lib\nsignature:\n\tcontrolled fast: Boolean\n"
                    "definitions:\n\tmain rule r_main = fast := speed > 2\ndefault init s0:\n"
                    "\tfunction fast = false\n", encoding="utf-8")
    uri = await _open(client, spec)
    [d] = client.diagnostics[uri]
    assert d.message.startswith("import not found") and d.range.start.line == 2
    # -I libs, as a workspace setting: the import is found, the spec is clean
    client.diagnostics.pop(uri)
    client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(
        settings={"asmetal": {"importPath": [str(lib_dir)], "exploreTimeLimit": 60}}))
    await _diagnostics(client, uri)
    assert list(client.diagnostics[uri]) == []
    # exploring needs the monitored Integer bounded: without a bound it says so
    result = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command="asmcheck.explore", arguments=[uri]))
    assert "speed" in result["error"]
    client.diagnostics.pop(uri)
    client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(
        settings={"asmetal": {"importPath": [str(lib_dir)], "monitored": ["speed=0..4"]}}))
    await _diagnostics(client, uri)
    result = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command="asmcheck.explore", arguments=[uri]))
    assert result["verdict"] == "holds"
    assert result["summary"].startswith("Car: 2 states, 4 transitions, depth 1")  # as the CLI with -I and --monitored


@pytest.mark.asyncio
async def test_cancelling_the_request_stops_the_run(client: LanguageClient, tmp_path):
    spec = tmp_path / "Count.asm"
    spec.write_text("asm Count\nimport StandardLibrary\nsignature:\n\tcontrolled n: Integer\ndefinitions:\n"
                    "\tmain rule r_main = n := n + 1\ndefault init s0:\n\tfunction n = 0\n", encoding="utf-8")
    uri = await _open(client, spec)
    before = set(client.progress_reports)
    task = asyncio.ensure_future(client.protocol.send_request_async(
        lsp.WORKSPACE_EXECUTE_COMMAND, lsp.ExecuteCommandParams(command="asmcheck.explore", arguments=[uri]),
        msg_id="explore-1"))
    for _ in range(200):        # wait until the run reports progress, then cancel the request itself
        tokens = [t for t in client.progress_reports if t not in before]
        if tokens and any(v.kind == "report" for v in client.progress_reports[tokens[0]]):
            break
        await asyncio.sleep(0.05)
    assert tokens, "no $/progress arrived"
    client.protocol.notify(lsp.CANCEL_REQUEST, lsp.CancelParams(id="explore-1"))
    with pytest.raises(Exception, match="cancel"):
        await asyncio.wait_for(task, 20)
    for _ in range(200):        # the exploration stops: its progress ends as cancelled
        if client.progress_reports[tokens[0]][-1].kind == "end":
            break
        await asyncio.sleep(0.05)
    assert client.progress_reports[tokens[0]][-1].kind == "end"
    assert client.progress_reports[tokens[0]][-1].message == "cancelled"
