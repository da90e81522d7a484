"""The native search loop's shortcuts, each checked on small specs written for the test: exact
counts, equality with the Python engine, and what the engine does (how many times its C is
generated)."""
from pathlib import Path

import pytest

from asmcheck.explore import native_build
from asmcheck.explore.native import Generator, NativeExplorer

from helpers import write

pytestmark = pytest.mark.engines("native")


def need_compiler():
    if native_build.compiler_command() is None:
        pytest.skip("no C compiler on this machine")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    d = tmp_path / "cache"
    monkeypatch.setenv("ASMCHECK_CACHE", str(d))
    return d


def test_a_spec_that_needs_more_element_slots_is_generated_once_on_the_next_run(tmp_path, cache, monkeypatch):
    need_compiler()
    from test_native_build import stack20
    from asmcheck.semantics.machine import Machine
    from asmcheck.semantics.resolve import check_file
    path = write(tmp_path, stack20())
    made = []
    orig = Generator.generate

    def counted(self):
        made.append(self.cn_k)
        return orig(self)
    monkeypatch.setattr(Generator, "generate", counted)

    def search():
        made.clear()
        ex = NativeExplorer(Machine(check_file(path), {}))
        try:
            r = ex.run()
            return list(made), ex.gen.cn_k, (r.verdict, r.states, r.transitions, r.depth)
        finally:
            ex.close()

    # the first search: 16 slots, stopped, generated again with 32
    assert search() == ([16, 32], 32, ("holds", 21, 21, 20))
    # the next: generated once, with 32 (the note is found before the C is generated)
    assert search() == ([32], 32, ("holds", 21, 21, 20))
    assert native_build.last_compile_seconds == 0.0
    # the note is keyed by the spec's content: an edited spec starts from 16 again
    Path(path).write_text(Path(path).read_text() + "// edited\n")
    assert search() == ([16, 32], 32, ("holds", 21, 21, 20))
    assert search() == ([32], 32, ("holds", 21, 21, 20))
