"""Building the native engine: compiler discovery, the content-hash cache and its permissions,
the fallback when no compiler exists.  Engine pinned: native (the fallback cases: python)."""
import json
import os
import stat

import pytest

from asmcheck.cli import main
from asmcheck.explore import native_build
from asmcheck.explore.native import NativeExplorer, Unsupported

from helpers import machine, spec, write

pytestmark = pytest.mark.engines("native")

COUNTER = spec("\tenum domain Phase = {PH0 | PH1 | PH2 | PH3 | PH4 | PH5}\n\tcontrolled x: Phase",
               "\tmain rule r_main = switch x\n\t\tcase PH0: x := PH1\n\t\tcase PH1: x := PH2\n\t\t"
               "case PH2: x := PH3\n\t\tcase PH3: x := PH4\n\t\tcase PH4: x := PH5\n\t\totherwise skip\n\tendswitch",
               "\tfunction x = PH0")
# a tiny C source in the shape the engine loads (one exported function)
SRC = "long asm_probe(long x) { return x + %d; }\n"


def need_compiler():
    if native_build.compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")


@pytest.fixture(autouse=True)
def real_flags(monkeypatch):
    """This module builds with the compiler's own flags (GCC_FLAGS, FLAGS): the suite's quicker
    optimisation flags ($ASMCHECK_CFLAGS, see conftest.py) are not used here."""
    monkeypatch.delenv("ASMCHECK_CFLAGS", raising=False)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    d = tmp_path / "cache"
    monkeypatch.setenv("ASMCHECK_CACHE", str(d))
    return d


def replace(lib, data, mode):
    # a new file under the old name (writing into the loaded library would change this process's code)
    lib.unlink()
    lib.write_bytes(data)
    os.chmod(lib, mode)


def probe(src):
    import ctypes
    return native_build.build(src, {"asm_probe": (ctypes.c_long, [ctypes.c_long])})


def test_cache_folder_is_created_private(cache):
    d = native_build.cache_dir()
    assert d == cache
    assert stat.S_IMODE(os.stat(d).st_mode) == 0o700


def test_xdg_cache_home_is_the_default_base(tmp_path, monkeypatch):
    monkeypatch.delenv("ASMCHECK_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert native_build.cache_dir() == tmp_path / "xdg" / "asmcheck"
    assert stat.S_IMODE(os.stat(tmp_path / "xdg" / "asmcheck").st_mode) == 0o700


def test_second_build_is_a_cache_hit_that_compiles_nothing(cache):
    need_compiler()
    lib = probe(SRC % 7)
    assert lib.asm_probe(1) == 8
    assert native_build.last_compile_seconds > 0 and not native_build.last_cache_hit
    libs = sorted(p.name for p in cache.iterdir())
    assert len(libs) == 1 and libs[0].endswith(".so")      # no leftover .c or temporary file
    assert stat.S_IMODE(os.stat(cache / libs[0]).st_mode) == 0o700
    lib = probe(SRC % 7)
    assert lib.asm_probe(1) == 8
    assert native_build.last_compile_seconds == 0.0 and native_build.last_cache_hit
    assert sorted(p.name for p in cache.iterdir()) == libs
    # another source is another library
    assert probe(SRC % 9).asm_probe(1) == 10
    assert native_build.last_compile_seconds > 0
    assert len(list(cache.iterdir())) == 2


def test_second_run_of_a_spec_compiles_nothing(tmp_path, cache):
    need_compiler()
    m = machine(tmp_path, COUNTER)
    ex = NativeExplorer(m)
    assert ex.compile_seconds > 0
    assert ex.run().states == 6
    ex.close()
    ex = NativeExplorer(machine(tmp_path, COUNTER))
    assert ex.compile_seconds == 0.0
    assert ex.run().states == 6
    ex.close()


def test_world_writable_cache_folder_is_made_private_and_what_others_put_there_is_not_loaded(cache):
    need_compiler()
    probe(SRC % 3)
    (lib,) = cache.iterdir()
    os.chmod(cache, 0o777)
    # someone replaces the library while the folder is open, and leaves it writable by others
    replace(lib, b"not a library", 0o666)
    assert probe(SRC % 3).asm_probe(0) == 3          # rebuilt, not loaded
    assert native_build.last_compile_seconds > 0
    assert stat.S_IMODE(os.stat(cache).st_mode) == 0o700
    assert stat.S_IMODE(os.stat(lib).st_mode) == 0o700


def test_group_writable_cached_library_is_rebuilt(cache):
    need_compiler()
    probe(SRC % 4)
    (lib,) = cache.iterdir()
    replace(lib, b"not a library", 0o770)
    assert probe(SRC % 4).asm_probe(1) == 5
    assert native_build.last_compile_seconds > 0
    assert stat.S_IMODE(os.stat(lib).st_mode) == 0o700


def test_a_link_in_the_cache_is_not_loaded(cache, tmp_path):
    need_compiler()
    probe(SRC % 6)
    (lib,) = cache.iterdir()
    other = tmp_path / "elsewhere.so"
    lib.rename(other)
    lib.symlink_to(other)
    assert probe(SRC % 6).asm_probe(0) == 6
    assert native_build.last_compile_seconds > 0 and not lib.is_symlink()


def test_foreign_owned_cache_folder_is_refused(cache, monkeypatch):
    need_compiler()
    cache.mkdir(mode=0o700)
    me = os.geteuid()
    if me == 0:
        os.chown(cache, 12345, -1)          # as root: really give it away
    else:
        monkeypatch.setattr(native_build.os, "geteuid", lambda: me + 1)
    d = native_build.cache_dir()
    assert d != cache and stat.S_IMODE(os.stat(d).st_mode) == 0o700
    if me != 0:
        monkeypatch.setattr(native_build.os, "geteuid", lambda: me)
    assert probe(SRC % 5).asm_probe(0) == 5
    assert list(cache.iterdir()) == []          # nothing written to (or loaded from) someone else's folder


def test_compiler_discovery_order(monkeypatch, tmp_path):
    bindir = tmp_path / "bin"
    bindir.mkdir()
    for name in ("mycc", "clang"):
        exe = bindir / name
        exe.write_text("#!/bin/sh\nexit 0\n")
        exe.chmod(0o755)
    monkeypatch.setenv("PATH", str(bindir))
    monkeypatch.setenv("CC", "mycc -m64")
    assert native_build.compiler_command() == [str(bindir / "mycc"), "-m64"]
    monkeypatch.delenv("CC")
    assert native_build.compiler_command() == [str(bindir / "clang")]
    (bindir / "clang").unlink()
    monkeypatch.setattr(native_build, "_ziglang_available", lambda: True)
    cmd = native_build.compiler_command()
    assert cmd[1:] == ["-m", "ziglang", "cc"]


def test_no_compiler_falls_back_to_python_with_one_line(tmp_path, cache, monkeypatch, capsys):
    monkeypatch.setenv("PATH", str(tmp_path / "nothing"))
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.setattr(native_build, "_ziglang_available", lambda: False)
    assert native_build.compiler() is None
    path = write(tmp_path, COUNTER.replace("function x = PH0", "function x = PH1"))   # not in the cache
    with pytest.raises(Unsupported) as e:
        NativeExplorer(machine(tmp_path, open(path).read()))
    assert str(e.value) == native_build.NO_COMPILER
    assert "\n" not in str(e.value) and "pip install 'asmcheck[native]'" in str(e.value)
    # auto: the Python engine runs
    assert main(["explore", path, "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["engine"], out["states"]) == ("python", 5)
    # native asked for: the one line says why and how
    assert main(["explore", path, "--engine", "native"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "pip install 'asmcheck[native]'" in err[0]


def test_compile_error_is_one_line(cache):
    need_compiler()
    with pytest.raises(Unsupported) as e:
        native_build.build("int f( {\n")
    msg = str(e.value)
    assert msg.startswith("the C compiler failed on line 1 of the generated code: ") and "\n" not in msg
    assert str(cache) not in msg        # no temporary file name: the same error gives the same line
    assert list(cache.iterdir()) == []


def test_fallback_note_is_one_line():
    assert native_build.fallback_note(native_build.NO_COMPILER) == (
        "engine: python (native engine not used: no C compiler found (gcc, cc, clang or $CC); "
        "for native speed: pip install 'asmcheck[native]')")
    assert native_build.fallback_note("the infinite domain\nInteger") == \
        "engine: python (native engine not used: the infinite domain Integer)"


def test_a_damaged_cached_library_is_built_again(cache):
    need_compiler()
    folder, name = native_build.library_path(SRC % 11)
    assert folder == cache
    (cache / name).write_bytes(b"\x7fELF truncated")
    os.chmod(cache / name, 0o700)
    assert probe(SRC % 11).asm_probe(0) == 11
    assert native_build.last_compile_seconds > 0


def fake_compiler(bindir, name, version_text):
    exe = bindir / name
    exe.write_text("#!/bin/sh\ncat <<'END'\n" + version_text + "\nEND\n")
    exe.chmod(0o755)
    return [str(exe)]


def test_gcc_gets_its_own_flags_and_any_other_compiler_o2(tmp_path):
    bindir = tmp_path / "bin"
    bindir.mkdir()
    gcc = fake_compiler(bindir, "gcc", "gcc (Debian 12.2.0-14) 12.2.0\nCopyright (C) 2022 Free Software Foundation, Inc.")
    clang = fake_compiler(bindir, "clang", "Debian clang version 14.0.6\nTarget: x86_64-pc-linux-gnu")
    cc = fake_compiler(bindir, "cc", "some other compiler 1.0")
    assert native_build.compile_flags(gcc) == native_build.GCC_FLAGS
    assert native_build.GCC_FLAGS[:2] == ["-O1", "-finline-small-functions"]
    assert native_build.compile_flags(clang) == native_build.FLAGS == ["-O2", "-shared", "-fPIC"]
    assert native_build.compile_flags(cc) == native_build.FLAGS
    # zig cc (clang inside) is not even asked
    assert native_build.compile_flags([str(bindir / "python"), "-m", "ziglang", "cc"]) == native_build.FLAGS


def test_asmcheck_cflags_replaces_the_optimisation_flags_and_keys_the_cache(tmp_path, cache, monkeypatch):
    bindir = tmp_path / "bin"
    bindir.mkdir()
    gcc = fake_compiler(bindir, "gcc", "gcc (Debian 12.2.0-14) 12.2.0\nCopyright (C) 2022 Free Software Foundation, Inc.")
    clang = fake_compiler(bindir, "clang", "Debian clang version 14.0.6\nTarget: x86_64-pc-linux-gnu")
    real = native_build.library_path(SRC % 1, gcc)[1]
    monkeypatch.setenv("ASMCHECK_CFLAGS", "-O0  -g")
    assert native_build.compile_flags(gcc) == native_build.compile_flags(clang) == ["-O0", "-g", "-shared", "-fPIC"]
    quick = native_build.library_path(SRC % 1, gcc)[1]
    assert quick != real
    monkeypatch.setenv("ASMCHECK_CFLAGS", "-Og")
    assert native_build.compile_flags(gcc) == ["-Og", "-shared", "-fPIC"]
    assert native_build.library_path(SRC % 1, gcc)[1] not in (real, quick)
    monkeypatch.setenv("ASMCHECK_CFLAGS", " ")          # empty: the compiler's own flags
    assert native_build.compile_flags(gcc) == native_build.GCC_FLAGS
    assert native_build.library_path(SRC % 1, gcc)[1] == real


def test_a_spec_built_with_the_real_and_the_quick_flags_gives_the_same_report(tmp_path, cache, monkeypatch, capsys):
    need_compiler()
    path = write(tmp_path, COUNTER)
    reports = []
    for flags in (None, "-O0"):
        if flags:
            monkeypatch.setenv("ASMCHECK_CFLAGS", flags)
        assert main(["explore", path, "--engine", "native", "--format", "json", "--deadlock"]) == 1
        report = json.loads(capsys.readouterr().out)
        assert report["engine"] == "native" and report["compile_seconds"] > 0
        reports.append({k: v for k, v in report.items() if k not in ("seconds", "compile_seconds")})
    assert len([p for p in cache.iterdir() if p.suffix == ".so"]) == 2
    assert reports[0] == reports[1]
    assert (reports[0]["states"], reports[0]["transitions"]) == (6, 6)


def test_the_cache_key_names_the_compiler_itself_not_only_its_name(tmp_path, cache):
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    gcc_a = fake_compiler(a, "gcc", "gcc 12.2.0\nFree Software Foundation")
    gcc_b = fake_compiler(b, "gcc", "gcc 13.1.0\nFree Software Foundation")
    src = SRC % 1
    assert native_build.library_path(src, gcc_a) == native_build.library_path(src, list(gcc_a))
    assert native_build.library_path(src, gcc_a)[1] != native_build.library_path(src, gcc_b)[1]
    assert native_build.library_path(src, gcc_a)[1] != native_build.library_path(SRC % 2, gcc_a)[1]
    assert native_build.compiler_identity(gcc_a).startswith(os.path.realpath(gcc_a[0]) + " ")


def test_a_kept_note_is_read_back_only_when_it_is_ours(cache):
    assert native_build.recall("key one") is None
    native_build.remember("key one", "32")
    assert native_build.recall("key one") == "32" and native_build.recall("key two") is None
    (note,) = [p for p in cache.iterdir() if p.name.startswith("note-")]
    assert stat.S_IMODE(os.stat(note).st_mode) == 0o600
    os.chmod(note, 0o666)                   # others may write it: not read, removed
    assert native_build.recall("key one") is None and not note.exists()


def stack20():
    # 20 cells at once: more than the first 16 element slots (test_native_extend's stack, bounded)
    from test_native_extend import STACK
    return STACK.replace("asm Stack", "asm Stack20").replace(
        "\t\textend Cell with $c do", "\t\tif size < 20 then extend Cell with $c do").replace(
        "\t\t\tendpar\n", "\t\t\tendpar\n\t\tendif\n").replace(
        "\tcontrolled below: Cell -> Cell\n", "\tcontrolled below: Cell -> Cell\n\tcontrolled size: Integer\n").replace(
        "\t\t\t\ttop := $c\n", "\t\t\t\ttop := $c\n\t\t\t\tsize := size + 1\n") + "default init s0:\n\tfunction size = 0\n"


def test_the_element_slots_a_search_needed_are_where_the_next_one_starts(tmp_path, cache):
    need_compiler()
    from asmcheck.semantics.machine import Machine
    from asmcheck.semantics.resolve import check_file
    spec = check_file(write(tmp_path, stack20()))

    def search():
        ex = NativeExplorer(Machine(spec, {}))
        first = ex.gen.cn_k
        try:
            r = ex.run()
            return first, ex.gen.cn_k, (r.verdict, r.states, r.transitions, r.depth)
        finally:
            ex.close()

    # the first search runs with 16 slots, stops, and runs again with 32
    assert search() == (16, 32, ("holds", 21, 21, 20))
    notes = [p for p in cache.iterdir() if p.name.startswith("note-")]
    assert len(notes) == 1 and notes[0].read_text() == "32"
    # the next one starts with 32, from the cached engine, with the same result
    assert search() == (32, 32, ("holds", 21, 21, 20))
    assert native_build.last_compile_seconds == 0.0
    # a number the retry could not have reached is not believed
    for bad in ("48", "512", "8", "x32", ""):
        notes[0].write_text(bad)
        assert search() == (16, 32, ("holds", 21, 21, 20)), bad
        assert notes[0].read_text() == "32"
