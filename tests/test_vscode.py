"""The VS Code extension (editors/vscode): it builds into a .vsix, its grammar tokenises the specs
as AsmetaL reads them, and its snippets expand to AsmetaL that parses."""
from __future__ import annotations

import json
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

from asmcheck.lsp.analysis import TOKEN_RE
from asmcheck.syntax.parser import RESERVED, decode_source, parse_text

from conftest import ROOT

pytestmark = pytest.mark.engines("none")

EXT = ROOT / "editors" / "vscode"
SPECS = sorted((ROOT / "specs").glob("*.asm")) + sorted((ROOT / "specs" / "buggy").glob("*.asm"))
OPERATOR_WORDS = {"and", "or", "not", "xor", "implies", "iff", "mod"}
NETWORK = ("ENOTFOUND", "EAI_AGAIN", "ETIMEDOUT", "ECONNREFUSED", "ECONNRESET", "network")


def _need_node():
    for tool in ("node", "npm", "npx"):
        if shutil.which(tool) is None:
            pytest.skip(f"{tool} is not installed: the VS Code extension is not built")


def _run(cmd, **kw):
    return subprocess.run(cmd, cwd=EXT, capture_output=True, text=True, timeout=600, **kw)


@pytest.fixture(scope="module")
def node_modules():
    """The extension's npm dependencies, installed as package-lock.json pins them."""
    _need_node()
    if not (EXT / "node_modules" / "vscode-textmate").exists() or not (
            EXT / "node_modules" / "vscode-languageclient").exists():
        r = _run(["npm", "ci", "--no-audit", "--no-fund"])
        if r.returncode != 0:
            if any(n in r.stderr for n in NETWORK):
                pytest.skip(f"npm cannot reach its registry: {r.stderr.strip().splitlines()[-1]}")
            raise AssertionError(f"npm ci failed:\n{r.stdout}\n{r.stderr}")
    return EXT / "node_modules"


def test_extension_builds_into_a_vsix(node_modules, tmp_path):
    r = _run(["npx", "tsc", "-p", "./"])
    assert r.returncode == 0, r.stdout + r.stderr
    out = tmp_path / "asmetal.vsix"
    r = _run(["npx", "vsce", "package", "--no-rewrite-relative-links", "--out", str(out)])
    assert r.returncode == 0, r.stdout + r.stderr
    with zipfile.ZipFile(out) as z:
        names = set(z.namelist())
        manifest = json.loads(z.read("extension/package.json"))
    for must in ("extension/package.json", "extension/out/extension.js", "extension/readme.md",
                 "extension/syntaxes/asmetal.tmLanguage.json", "extension/snippets/asmetal.json",
                 "extension/language-configuration.json", "extension/media/screenshot.png",
                 "extension/node_modules/vscode-languageclient/package.json"):
        assert must in names, must
    assert not any(n.startswith("extension/src/") or n.endswith(".ts") for n in names)
    assert not any("node_modules/typescript/" in n or "node_modules/vscode-textmate/" in n for n in names)
    [lang] = manifest["contributes"]["languages"]
    assert lang["id"] == "asmetal" and lang["extensions"] == [".asm"]
    js = (EXT / "out" / "extension.js").read_text()
    assert '"-m", "asmcheck", "lsp"' in js


def test_first_line_pattern_tells_asmetal_from_assembly():
    manifest = json.loads((EXT / "package.json").read_text())
    [lang] = manifest["contributes"]["languages"]
    first = re.compile(lang["firstLine"])
    for line in ("asm sb_async_master", "module CommonDefinitions", "asyncr asm Philosophers", "  asm T  "):
        assert first.match(line), line
    for line in ("mov ax, 1", "; asm startup code", "section .text", "asm", "module", "global _start"):
        assert not first.match(line), line
    for spec in SPECS:
        heads = [ln for ln in decode_source(spec.read_bytes()).split("\n") if re.match(r"\s*(asm|module)\b", ln)]
        assert first.match(heads[0]), spec


def _expected(text: str):
    """Keywords (line, start, end, word) and comment pieces (line, start, end), 0-based, by asmcheck's lexer."""
    keywords, comments = [], []
    starts = [0] + [m.end() for m in re.finditer("\n", text)]

    def pos(off):
        import bisect
        ln = bisect.bisect_right(starts, off) - 1
        return ln, off - starts[ln]

    for m in TOKEN_RE.finditer(text):
        if m.lastgroup == "name" and (m.group() in RESERVED or m.group() in OPERATOR_WORDS):
            ln, col = pos(m.start())
            keywords.append((ln, col, col + len(m.group()), m.group()))
        elif m.lastgroup == "comment":
            ln, col = pos(m.start())
            for i, piece in enumerate(m.group().split("\n")):
                c0 = col if i == 0 else 0
                if piece.rstrip("\r"):
                    comments.append((ln + i, c0, c0 + len(piece.rstrip("\r"))))
    return keywords, comments


def test_grammar_tokenises_every_keyword_and_comment(node_modules):
    r = _run(["node", "test/grammar.js", *map(str, SPECS)])
    assert r.returncode == 0, r.stderr
    tokens = json.loads(r.stdout)
    checked_kw = checked_comments = 0
    for spec in SPECS:
        keywords, comments = _expected(decode_source(spec.read_bytes()))
        by_line: dict[int, list] = {}
        for ln, s, e, scopes in tokens[str(spec)]:
            by_line.setdefault(ln, []).append((s, e, scopes))
        for ln, s, e, word in keywords:
            hit = [sc for (a, b, sc) in by_line.get(ln, []) if (a, b) == (s, e)]
            assert hit, f"{spec.name}:{ln + 1}:{s + 1}: {word!r} is not one token"
            inner = hit[0][-1]
            want = "constant.language." if word in ("true", "false", "undef", "i") else ("keyword.", "storage.")
            assert inner.startswith(want), f"{spec.name}:{ln + 1}:{s + 1}: {word!r} is {inner}"
            checked_kw += 1
        for ln, s, e in comments:
            for (a, b, sc) in by_line.get(ln, []):
                if a < e and b > s:
                    assert any(x.startswith("comment.") for x in sc), \
                        f"{spec.name}:{ln + 1}:{a + 1}: inside a comment but scoped {sc}"
            covered = sum(min(b, e) - max(a, s) for (a, b, sc) in by_line.get(ln, []) if a < e and b > s)
            assert covered == e - s, f"{spec.name}:{ln + 1}: comment not covered"
            checked_comments += 1
    assert checked_kw > 3000 and checked_comments > 500, (checked_kw, checked_comments)


def _expand(body: list[str]) -> str:
    """A snippet's text with every placeholder at its default (mirrors take the same value)."""
    text = "\n".join(body).replace("\\$", "\x00")
    text = text.replace("${TM_FILENAME_BASE}", "S")
    defaults: dict[str, str] = {}
    while True:
        m = re.search(r"\$\{(\d+):([^${}]*)\}", text)
        if not m:
            break
        defaults.setdefault(m.group(1), m.group(2))
        text = text[:m.start()] + m.group(2) + text[m.end():]
    text = re.sub(r"\$(\d+)", lambda m: defaults.get(m.group(1), ""), text)
    return text.replace("\x00", "$")


RULE_SNIPPETS = {"par", "seq", "if", "if-else", "choose", "forall", "let", "switch"}
DECL_SNIPPETS = {"rule", "control-state machine"}


def test_snippets_expand_to_asmetal_that_parses(tmp_path):
    snippets = json.loads((EXT / "snippets" / "asmetal.json").read_text())
    assert {"par", "if", "choose", "forall", "control-state machine"} <= set(snippets)
    head = "asm S\nimport StandardLibrary\nsignature:\ndefinitions:\n"
    for name, sn in snippets.items():
        text = _expand(sn["body"])
        if name in RULE_SNIPPETS:
            spec = head + "\tmain rule r_main =\n" + text + "\n"
        elif name in DECL_SNIPPETS:
            spec = head + text + "\n\tmain rule r_main = skip\n"
        elif name == "invariant":
            spec = head + text + "\n\tmain rule r_main = skip\n"
        elif name == "main rule":
            spec = head + text + "\n"
        elif name == "asm":
            spec = text + "\n"
        else:
            raise AssertionError(f"snippet {name!r} has no test")
        parsed = parse_text(spec, str(tmp_path / "S.asm"))
        assert parsed is not None and parsed.name == "S", name
        if name == "control-state machine":
            assert [r.name for r in parsed.rules] == ["r_machine", "r_main"]
