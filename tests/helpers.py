"""Small helpers shared by the tests: write a spec, load it, run steps."""
from __future__ import annotations

import re
from pathlib import Path

from asmcheck.semantics.machine import Chooser, Machine
from asmcheck.semantics.printer import location_text
from asmcheck.semantics.resolve import check_file
from asmcheck.semantics.values import show


def write(tmp_path: Path, text: str) -> str:
    name = re.search(r"\b(?:asm|module)\s+([A-Za-z_][A-Za-z0-9_]*)", text).group(1)
    p = tmp_path / f"{name}.asm"
    p.write_text(text, encoding="utf-8")
    return str(p)


def machine(tmp_path: Path, text: str, **options) -> Machine:
    spec = check_file(write(tmp_path, text))
    return Machine(spec, options)


def view(m: Machine, state: dict) -> dict:
    """location text -> printed value, for assertions."""
    out = {}
    for k, v in state.items():
        if type(k) is tuple and k[0] == "#dom":
            out[k[1]] = "{" + ", ".join(e.name for e in v) + "}"
        else:
            out[location_text(m, k)] = show(v)
    return out


def run(m: Machine, steps: int = 1, chooser_factory=Chooser) -> dict:
    st = m.initial_state()
    for _ in range(steps):
        _, st, _ = m.step(st, chooser_factory())
    return view(m, st)


def successor_views(m: Machine, state=None) -> list[dict]:
    st = m.initial_state() if state is None else state
    out = []
    for log, ups, nxt, mon in m.successors(st):
        v = view(m, nxt)
        if v not in out:
            out.append(v)
    return out


def spec(sig: str, defs: str, init: str = "") -> str:
    """A one-file asm named S with the given signature, definitions and default init lines."""
    return ("asm S\nimport StandardLibrary\nsignature:\n" + sig + "\ndefinitions:\n" + defs +
            ("\ndefault init s0:\n" + init + "\n" if init else "\n"))


def engine_free(report: dict, engine: str | None = None) -> dict:
    """``report`` (``explore --format json``) without what differs from one engine's run to the
    other's: the engine (checked to be ``engine`` when given), the times and the engine's notes;
    changed in place, and returned."""
    got = report.pop("engine")
    if engine is not None:
        assert got == engine
    for key in ("seconds", "compile_seconds", "engine_note", "engine_reason"):
        report.pop(key, None)
    return report


def both(tmp_path, capsys, text, *extra):
    """``explore --format json`` of the spec ``text`` on the native engine and on the Python engine:
    the two reports must be equal but for the engine and the times; returns (exit code, report)."""
    import json
    import pytest
    from asmcheck.cli import main
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, text)
    outs = []
    for engine in ("native", "python"):
        code = main(["explore", path, "--format", "json", "--engine", engine, *extra])
        outs.append((code, engine_free(json.loads(capsys.readouterr().out), engine)))
    assert outs[0] == outs[1]
    return outs[0]


def native_search(path, workers=1, packed=None, **kw):
    """Run the native search on ``path`` with the spec's properties: (result, explorer, the parent
    of every state, the words of every state).  ``packed`` (True/False) asks for the packed store
    or the plain one; ``kw`` goes to NativeExplorer."""
    import ctypes
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.props import spec_properties
    from asmcheck.props.load import load_machine
    spec, m = load_machine(str(path), {})
    sp, stp = spec_properties(m)
    ex = NativeExplorer(m, state_props=sp, step_props=stp, workers=workers, **kw)
    if packed is not None:
        ex.packed = packed
    r = ex.run()
    parents = (ctypes.c_int64 * r.states)()
    ex.dll.asm_parents(parents)
    words = (ctypes.c_uint64 * ex.gen.nwords)()
    states = []
    for i in range(r.states):
        ex.dll.asm_state(i, words)
        states.append(tuple(words))
    return r, ex, list(parents), states


def warm_native(path: str, *args: str) -> None:
    """Compiles (and caches) the native engine ``explore path *args`` uses, searching no state: a
    timed run that follows spends its time limit searching, not compiling (the compile of a cache
    miss comes out of --max-seconds).  ``args``: the run's other options, without --engine,
    --max-seconds and --max-depth.  (--max-depth 0: no step runs; with --max-states 1 the initial
    state's steps are still enumerated, some 9 s for a state with 1,000,000 sequences of inputs.)"""
    import contextlib
    import io

    from asmcheck.cli import main
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        main(["explore", path, *args, "--engine", "native", "--max-depth", "0"])
