"""Compiling and loading the native explorer's generated C.

* **Compiler.**  ``$CC`` if set, else ``gcc``, ``cc`` or ``clang`` on the PATH, else the Zig
  toolchain shipped as the Python package ``ziglang`` (``pip install 'asmcheck[native]'``),
  run as ``python -m ziglang cc``.
* **Flags.**  GCC gets :data:`GCC_FLAGS` (-O1 with -O2's inlining: as fast a search, about 40 %
  less compile time); any other compiler :data:`FLAGS` (-O2).  ``$ASMCHECK_CFLAGS``, when set,
  replaces the optimisation flags of either (``-O0`` compiles about three times faster and searches
  slower: the test suite's setting); it is part of the cache key.
* **Cache.**  A compiled library is kept under the hash of its source, the compiler (its
  resolved path, size and modification time) and the flags, in asmcheck's private cache folder (:mod:`asmcheck.cache`: ``$ASMCHECK_CACHE``, else
  ``$XDG_CACHE_HOME/asmcheck``, else ``~/.cache/asmcheck``, mode 0700), so a second run of the
  same spec compiles nothing.  A library there that is a link, belongs to another user or that
  others may write is never loaded (someone else could have put code there): it is removed
  and built again.  Compilation writes to a temporary name in that folder and renames.
* **Timing.**  :data:`last_compile_seconds` is the time the last :func:`build` spent in the
  compiler (0.0 on a cache hit).
"""
from __future__ import annotations

import atexit
import ctypes
import hashlib
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ..cache import private_cache_dir, usable_cache_file

FLAGS = ["-O2", "-shared", "-fPIC"]
# GCC: -O1 with -O2's inlining and strict aliasing.  The search loop runs as fast as with -O2
# (the hot code is small functions inlined into the expansion of a state), and the compiler
# takes about 40 % less time: the rest of -O2 (partial redundancy elimination, value range
# propagation, scheduling, ...) costs time on the whole file, run-once set-up code included,
# and gains nothing measurable on the search.  Other compilers (clang, zig cc) keep -O2.
GCC_FLAGS = ["-O1", "-finline-small-functions", "-finline-functions", "-fstrict-aliasing", "-shared", "-fPIC"]
LIBS = ["-lm"]          # the generated code calls floor, sqrt, pow (Reals)
INSTALL_HINT = "pip install 'asmcheck[native]'"
NO_COMPILER = f"no C compiler found (gcc, cc, clang or $CC); for native speed: {INSTALL_HINT}"

last_compile_seconds: float = 0.0
"""Seconds the last :func:`build` spent compiling (0.0 when the library came from the cache)."""

last_cache_hit: bool = False

_private_dirs: list[str] = []
_loaded: dict = {}


def _cleanup_private() -> None:
    for d in _private_dirs:
        shutil.rmtree(d, ignore_errors=True)
    _private_dirs.clear()


atexit.register(_cleanup_private)


# ----------------------------------------------------------------- the compiler
def _ziglang_available() -> bool:
    try:
        import importlib.util
        return importlib.util.find_spec("ziglang") is not None
    except (ImportError, ValueError):
        return False


def compiler_command() -> list[str] | None:
    """The command that runs the C compiler (a list of arguments), or None."""
    env_cc = os.environ.get("CC")
    if env_cc:
        parts = shlex.split(env_cc)
        if parts and shutil.which(parts[0]):
            return [shutil.which(parts[0]), *parts[1:]]
    for cc in ("gcc", "cc", "clang"):
        path = shutil.which(cc)
        if path:
            return [path]
    if _ziglang_available():
        return [sys.executable, "-m", "ziglang", "cc"]
    return None


def compiler() -> str | None:
    """The C compiler as one printable command, or None when there is none."""
    cmd = compiler_command()
    return None if cmd is None else shlex.join(cmd)


_identity: dict = {}


def compiler_identity(cmd: list[str]) -> str:
    """What identifies the compiler ``cmd`` in the cache key, without running it: the program's
    resolved path, size and modification time (a compiler upgraded in place gives other
    libraries), or the ``ziglang`` package's version."""
    key = tuple(cmd)
    if key not in _identity:
        parts = []
        if cmd[1:3] == ["-m", "ziglang"]:
            try:
                from importlib.metadata import version
                parts.append(f"ziglang {version('ziglang')}")
            except Exception:
                parts.append("ziglang")
        try:
            real = os.path.realpath(cmd[0])
            st = os.stat(real)
            parts.append(f"{real} {st.st_size} {st.st_mtime_ns}")
        except OSError:
            parts.append(os.path.basename(cmd[0]))
        parts += cmd[1:]
        _identity[key] = " ".join(parts)
    return _identity[key]


_families: dict = {}


def compile_flags(cmd: list[str]) -> list[str]:
    """The flags for the compiler ``cmd``: :data:`GCC_FLAGS` for GCC (asked once a process, by
    ``--version``), :data:`FLAGS` for any other."""
    key = tuple(cmd)
    if key not in _families:
        family = "other"
        if cmd[1:3] != ["-m", "ziglang"]:
            try:
                out = subprocess.run([*cmd, "--version"], capture_output=True, text=True, timeout=30).stdout
            except (OSError, subprocess.SubprocessError):
                out = ""
            if "Free Software Foundation" in out and "clang" not in out.lower():
                family = "gcc"
        _families[key] = family
    flags = GCC_FLAGS if _families[key] == "gcc" else FLAGS
    chosen = optimisation_override()
    return flags if chosen is None else [*chosen, "-shared", "-fPIC"]


def optimisation_override() -> list[str] | None:
    """The words of ``$ASMCHECK_CFLAGS`` (they replace the optimisation flags), or None when unset."""
    env = os.environ.get("ASMCHECK_CFLAGS")
    return shlex.split(env) if env and env.strip() else None


# ----------------------------------------------------------------- the cache folder
def cache_dir() -> Path:
    """The folder where compiled engines are kept: asmcheck's private cache folder
    (:func:`asmcheck.cache.private_cache_dir`: mode 0700, never another user's or a shared one)."""
    return private_cache_dir()


# ----------------------------------------------------------------- compile and load
class Unsupported(Exception):
    """The spec (or a property) uses something the native explorer does not translate, or
    no engine can be built here; the one-line reason says which."""


def _unsupported(reason: str):
    return Unsupported(reason)


def _compile(cmd: list[str], src: str, folder: Path, lib: Path) -> None:
    fd, c_name = tempfile.mkstemp(prefix=lib.stem + ".", suffix=".c", dir=folder)
    with os.fdopen(fd, "w") as f:
        f.write(src)
    fd, tmp_name = tempfile.mkstemp(prefix=lib.stem + ".", suffix=".so.tmp", dir=folder)
    os.close(fd)
    try:
        try:
            proc = subprocess.run([*cmd, *compile_flags(cmd), "-o", tmp_name, c_name, *LIBS], capture_output=True,
                                  text=True)
        except OSError as e:
            raise _unsupported(f"the C compiler {shlex.join(cmd)} cannot be run: {e.strerror}") from None
        if proc.returncode != 0:
            raise _unsupported(compile_error_line(proc.stderr))
        os.chmod(tmp_name, 0o700)
        os.replace(tmp_name, lib)     # atomic: a concurrent build of the same source is harmless
    finally:
        for f in (c_name, tmp_name):
            try:
                os.unlink(f)
            except OSError:
                pass


def compile_error_line(stderr: str) -> str:
    """The compiler's first error as one line, without the temporary file's name."""
    for ln in stderr.splitlines():
        m = re.match(r"^.*?\.c:(\d+):(?:\d+:)? (?:fatal )?error: (.*)$", ln)
        if m:
            return f"the C compiler failed on line {m.group(1)} of the generated code: {' '.join(m.group(2).split())[:300]}"
    first = next((ln for ln in stderr.splitlines() if ln.strip()), "no message")
    return f"the C compiler failed: {' '.join(first.split())[:300]}"


def library_path(src: str, cmd: list[str] | None = None) -> tuple[Path, str]:
    """(folder, file name) under which the library for ``src`` is cached: the hash of the
    source, both sets of flags (which one a compiler gets is decided only when it compiles) and
    the compiler's identity (:func:`compiler_identity`)."""
    cmd = cmd or compiler_command() or []
    h = hashlib.sha256()
    for part in (src, "\0", " ".join(FLAGS + LIBS), "\0", " ".join(GCC_FLAGS), "\0",
                 compiler_identity(cmd) if cmd else ""):
        h.update(part.encode())
    override = optimisation_override()
    if override is not None:
        h.update(("\0ASMCHECK_CFLAGS\0" + " ".join(override)).encode())
    return cache_dir(), f"model-{h.hexdigest()[:32]}.so"


def build(src: str, symbols: dict | None = None) -> ctypes.CDLL:
    """Compile ``src`` (or take it from the cache) and load it; ``symbols`` maps a function
    name to ``(restype, argtypes)``, set on the loaded library.  Raises
    ``native.Unsupported`` (one line) when there is no compiler or it fails."""
    global last_compile_seconds, last_cache_hit
    last_compile_seconds = 0.0
    last_cache_hit = False
    cmd = compiler_command()
    folder, name = library_path(src, cmd)
    lib = folder / name
    if not usable_cache_file(lib):     # not ours, or open to others, and it cannot be removed
        folder = Path(tempfile.mkdtemp(prefix="asmcheck-build-"))
        _private_dirs.append(str(folder))
        lib = folder / name
    dll = _loaded.get(str(lib)) if os.path.lexists(lib) else None
    if dll is None:
        for attempt in (1, 2):
            if os.path.lexists(lib):
                last_cache_hit = True
            else:
                if cmd is None:
                    raise _unsupported(NO_COMPILER)
                t0 = time.perf_counter()
                _compile(cmd, src, folder, lib)
                last_compile_seconds = time.perf_counter() - t0
            try:
                dll = ctypes.CDLL(str(lib))
                break
            except OSError as e:
                # a damaged cache entry (a run killed while writing, a full disk): build it again once
                try:
                    os.unlink(lib)
                except OSError:
                    pass
                last_cache_hit = False
                if attempt == 2 or cmd is None:
                    raise _unsupported(f"the compiled engine cannot be loaded: {' '.join(str(e).split())[:200]}") \
                        from None
        _loaded[str(lib)] = dll
    else:
        last_cache_hit = True
    for fname, (restype, argtypes) in (symbols or {}).items():
        fn = getattr(dll, fname)
        fn.restype = restype
        fn.argtypes = argtypes
    return dll


def forget(dll: ctypes.CDLL) -> None:
    """Drop the library ``dll`` from this process's table of loaded libraries (the engine of a
    search run again on another one), so that it is not kept alive by it, and give the C heap's
    free memory back to the system.  (The library itself stays mapped: ctypes never unloads one,
    and nothing tells for sure that no function of it is still held.)"""
    for k, v in list(_loaded.items()):
        if v is dll:
            del _loaded[k]
    trim_heap()


def trim_heap() -> None:
    """Return the C heap's free pages to the system (glibc's malloc_trim; nothing elsewhere)."""
    try:
        libc = ctypes.CDLL(None)
        trim = libc.malloc_trim
    except (OSError, AttributeError):
        return
    trim.argtypes = [ctypes.c_size_t]
    trim.restype = ctypes.c_int
    trim(0)


def _note_path(key: str) -> Path:
    return cache_dir() / f"note-{hashlib.sha256(key.encode()).hexdigest()[:32]}"


def recall(key: str) -> str | None:
    """What :func:`remember` kept for ``key`` (a generated source, say) in the private cache
    folder, or None (nothing kept, or a file there that is not safely ours: removed)."""
    try:
        path = _note_path(key)
        if not os.path.lexists(path) or not usable_cache_file(path):
            return None
        with open(path, encoding="ascii") as f:
            return f.read(200).strip() or None
    except (OSError, UnicodeError):
        return None


def remember(key: str, value: str) -> None:
    """Keep the short text ``value`` for ``key`` in the private cache folder (written under a
    temporary name and renamed; nothing happens where the folder cannot be written)."""
    try:
        path = _note_path(key)
        if not usable_cache_file(path):
            return
        fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "w", encoding="ascii") as f:
            f.write(value)
        os.chmod(tmp, 0o600)
        os.replace(tmp, path)
    except OSError:
        pass


def fallback_note(reason: str) -> str:
    """The one line a report prints when ``--engine auto`` runs the Python engine because the
    native one cannot (``reason``: the ``Unsupported`` message, itself one line)."""
    reason = " ".join(str(reason).split())
    return f"engine: python (native engine not used: {reason})"
