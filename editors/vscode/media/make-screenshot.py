#!/usr/bin/env python3
"""Draw media/screenshot.png from what the extension really receives.

    python editors/vscode/media/make-screenshot.py      (needs node, the extension's npm packages, chromium)

It starts the language server (``python -m asmcheck lsp``) over stdio with pygls' client, opens
specs/buggy/sb_async_master_no_release.asm, asks for its code lenses, runs the Explore lens, and
opens the counterexample (``asmcheck:`` document) as the Show counterexample lens does.  The
texts are coloured by the extension's own TextMate grammar (test/grammar.js, vscode-textmate).
These real answers are laid out as an editor window in HTML and rendered by headless Chromium.
It is a drawing of the extension's data, not a capture of a VS Code window.
"""
from __future__ import annotations

import asyncio
import html
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXT = HERE.parent
ROOT = EXT.parent.parent
sys.path.insert(0, str(ROOT))
SPEC = ROOT / "specs" / "buggy" / "sb_async_master_no_release.asm"
PROP = ROOT / "properties" / "swinging_buffer.prop"

COLOURS = [("comment.", "#6a9955"), ("keyword.operator", "#d4d4d4"), ("keyword.", "#569cd6"),
           ("storage.", "#569cd6"), ("constant.language", "#569cd6"), ("constant.numeric", "#b5cea8"),
           ("constant.other.enum", "#4fc1ff"), ("string.", "#ce9178"), ("variable.", "#9cdcfe"),
           ("entity.name.function.rule", "#dcdcaa"), ("entity.name.function", "#dcdcaa"),
           ("entity.name.section", "#c586c0"), ("support.type", "#4ec9b0"), ("entity.name.type", "#4ec9b0")]


async def server_answers():
    from lsprotocol import types as lsp
    from pygls.lsp.client import LanguageClient
    from pygls.uris import from_fs_path

    client = LanguageClient("screenshot", "1")
    diags: dict[str, list] = {}
    shown: list[str] = []

    @client.feature(lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    def on_diags(params):
        diags[params.uri] = params.diagnostics

    @client.feature(lsp.WINDOW_SHOW_DOCUMENT)
    def on_show(params):
        shown.append(params.uri)
        return lsp.ShowDocumentResult(success=True)

    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    await client.start_io(sys.executable, "-m", "asmcheck", "lsp", env=env)
    caps = lsp.ClientCapabilities(window=lsp.WindowClientCapabilities(
        show_document=lsp.ShowDocumentClientCapabilities(support=True)))
    await client.initialize_async(lsp.InitializeParams(capabilities=caps, root_uri=from_fs_path(str(ROOT))))
    client.initialized(lsp.InitializedParams())
    uri = from_fs_path(str(SPEC))
    client.text_document_did_open(lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(
        uri, "asmetal", 1, SPEC.read_text(encoding="utf-8"))))
    lenses = await client.text_document_code_lens_async(lsp.CodeLensParams(lsp.TextDocumentIdentifier(uri)))
    explore = next(ln.command for ln in lenses if ln.command.title == "Explore")
    result = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command=explore.command, arguments=explore.arguments))
    lenses = await client.text_document_code_lens_async(lsp.CodeLensParams(lsp.TextDocumentIdentifier(uri)))
    show = next(ln.command for ln in lenses if ln.command.title.startswith("Show counterexample"))
    doc_uri = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command=show.command, arguments=show.arguments))
    res = await client.protocol.send_request_async("asmcheck/textDocumentContent", {"uri": doc_uri})
    trace = res["text"] if isinstance(res, dict) else res.text
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return lenses, result, diags, doc_uri, trace


def colour_lines(path: Path) -> list[str]:
    out = subprocess.run(["node", str(EXT / "test" / "grammar.js"), str(path)], capture_output=True, text=True,
                         check=True).stdout
    tokens = json.loads(out)[str(path)]
    lines = path.read_text(encoding="utf-8").split("\n")
    html_lines = [""] * len(lines)
    for ln, s, e, scopes in tokens:
        text = lines[ln][s:e]
        colour = "#d4d4d4"
        for scope in reversed(scopes):
            hit = next((c for p, c in COLOURS if scope.startswith(p)), None)
            if hit:
                colour = hit
                break
        html_lines[ln] += f'<span style="color:{colour}">{html.escape(text)}</span>'
    return html_lines


def squiggle(line_html: str, plain: str, start: int, end: int) -> str:
    """Put a red wavy underline under characters start..end of a line (plain text, no colours there)."""
    return (html.escape(plain[:start]) + f'<span class="err">{html.escape(plain[start:end])}</span>'
            + html.escape(plain[end:]))


def page(lenses, result, diags, doc_uri, trace) -> str:
    spec_lines = colour_lines(SPEC)
    prop_lines = colour_lines(PROP)
    plain_prop = PROP.read_text(encoding="utf-8").split("\n")
    spec_plain = SPEC.read_text(encoding="utf-8").split("\n")
    main_line = next(i for i, ln in enumerate(spec_plain) if "main rule r_main" in ln)
    lens_titles = " | ".join(ln.command.title for ln in lenses if ln.range.start.line == main_line)
    prop_uri = next(u for u in diags if u.endswith("swinging_buffer.prop"))
    bad = next(d for d in diags[prop_uri] if d.severity == 1)
    bl = bad.range.start.line

    def numbered(lines, first, last, special=None):
        rows = []
        for i in range(first, last):
            body = special(i) if special else None
            rows.append(f'<div class="row"><span class="ln">{i + 1}</span><span class="code">'
                        f'{body if body is not None else lines[i]}</span></div>')
        return "\n".join(rows)

    left_top = (f'<div class="lens">{html.escape(lens_titles)}</div>' +
                numbered(spec_lines, main_line, main_line + 16))
    left_bottom = numbered(prop_lines, bl - 1, bl + 5, special=lambda i: squiggle(
        prop_lines[i], plain_prop[i], bad.range.start.character, bad.range.end.character) if i == bl else None)
    hover = f'<div class="hover">{html.escape(bad.message)}<div class="src">{html.escape(bad.source)}</div></div>'
    problems = []
    for u in sorted(diags):
        for d in diags[u]:
            icon = {1: "&#10006;", 2: "&#9888;", 3: "&#8505;"}.get(d.severity, "&#8505;")
            cls = {1: "perr", 2: "pwarn"}.get(d.severity, "pinfo")
            problems.append(f'<div class="prob"><span class="{cls}">{icon}</span> {html.escape(d.message)} '
                            f'<span class="dim">{html.escape(Path(u).name)} [Ln {d.range.start.line + 1}, '
                            f'Col {d.range.start.character + 1}]</span></div>')
    trace_html = "\n".join(f'<div class="row"><span class="ln">{i + 1}</span><span class="code">'
                           f'{html.escape(t)}</span></div>' for i, t in enumerate(trace.rstrip("\n").split("\n")))
    return f"""<!doctype html><html><head><meta charset="utf-8"><style>
body {{ margin:0; background:#1e1e1e; color:#d4d4d4; font: 13px 'DejaVu Sans Mono', monospace; }}
.bar {{ background:#323233; color:#ccc; padding:6px 12px; font-family:'DejaVu Sans',sans-serif; font-size:12px; }}
.tabs {{ background:#252526; display:flex; font-family:'DejaVu Sans',sans-serif; font-size:12px; }}
.tab {{ padding:7px 14px; color:#969696; border-right:1px solid #1e1e1e; }}
.tab.on {{ background:#1e1e1e; color:#fff; }}
.cols {{ display:flex; }} .col {{ flex:1; border-right:1px solid #333; overflow:hidden; }}
.row {{ white-space:pre; line-height:19px; tab-size:4; }} .ln {{ display:inline-block; width:44px; color:#858585;
 text-align:right; padding-right:14px; }}
.lens {{ color:#999; font-family:'DejaVu Sans',sans-serif; font-size:11.5px; padding:2px 0 1px 58px; }}
.err {{ text-decoration: underline wavy #f14c4c; text-underline-offset:3px; color:#d4d4d4; }}
.hover {{ margin:4px 0 6px 120px; background:#252526; border:1px solid #454545; padding:6px 10px; width:560px;
 white-space:normal; font-family:'DejaVu Sans',sans-serif; font-size:12px; }}
.hover .src {{ color:#888; margin-top:3px; }}
.panel {{ border-top:1px solid #444; background:#1e1e1e; padding:4px 0; font-family:'DejaVu Sans',sans-serif;
 font-size:12px; }}
.ptitle {{ padding:3px 12px; color:#e7e7e7; text-transform:uppercase; font-size:11px; border-bottom:1px solid #333; }}
.prob {{ padding:2px 20px; white-space:nowrap; }} .perr {{ color:#f14c4c; }} .pinfo {{ color:#3794ff; }}
.pwarn {{ color:#cca700; }} .dim {{ color:#888; }}
</style></head><body>
<div class="bar">asmcheck &mdash; AsmetaL (asmcheck) extension &middot; {html.escape(result["summary"])}</div>
<div class="cols">
<div class="col"><div class="tabs"><div class="tab on">sb_async_master_no_release.asm</div></div>
{left_top}
<div class="tabs"><div class="tab on">swinging_buffer.prop</div></div>
{left_bottom}
{hover}
</div>
<div class="col"><div class="tabs"><div class="tab on">{html.escape(doc_uri.split("?")[0])}</div></div>
{trace_html}
</div></div>
<div class="panel"><div class="ptitle">Problems</div>
{"".join(problems)}
</div></body></html>"""


def main() -> int:
    browser = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
    if browser is None:
        print("no chromium: cannot render the picture", file=sys.stderr)
        return 2
    answers = asyncio.run(server_answers())
    with tempfile.TemporaryDirectory() as tmp:
        page_path = Path(tmp) / "screenshot.html"
        page_path.write_text(page(*answers), encoding="utf-8")
        out = HERE / "screenshot.png"
        subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                        f"--screenshot={out}", "--window-size=1500,900", page_path.as_uri()],
                       check=True, capture_output=True)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
