"""The examples of docs/api.md and of the README run, in order, from the repository's root."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parents[1]


def python_blocks(path: Path) -> list[tuple[int, str]]:
    """(line, code) of every ```python block of a Markdown file."""
    text = path.read_text(encoding="utf-8")
    out = []
    for m in re.finditer(r"^```python\n(.*?)^```", text, flags=re.S | re.M):
        out.append((text.count("\n", 0, m.start()) + 2, m.group(1)))
    return out


DOCS = [ROOT / "docs" / "api.md", ROOT / "README.md"]


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.name)
def test_the_examples_run(doc, monkeypatch):
    blocks = python_blocks(doc)
    assert blocks, f"{doc.name} has no python example"
    monkeypatch.chdir(ROOT)
    scope: dict = {"__name__": "__doc_example__"}
    for line, code in blocks:
        exec(compile(code, f"{doc}:{line}", "exec"), scope)


def test_a_failing_example_fails(tmp_path):
    """The reader of examples sees a block that does not hold."""
    md = tmp_path / "x.md"
    md.write_text("text\n\n```python\nassert 1 == 2\n```\n", encoding="utf-8")
    [(line, code)] = python_blocks(md)
    assert line == 4
    with pytest.raises(AssertionError):
        exec(compile(code, f"{md}:{line}", "exec"), {})
