"""asmcheck's private cache folder (the parser's grammar table, compiled models).

The folder is ``$ASMCHECK_CACHE`` when set, else ``$XDG_CACHE_HOME/asmcheck``, else
``~/.cache/asmcheck``.  It is created with mode 0700.  It is used only when it is a folder
owned by the user that no one else may write to (a folder of the user's that others may
write to is made private first); otherwise asmcheck uses a fresh private folder with an
unpredictable name for the rest of the run, removed at exit.  A file in the cache is used
only when it is a regular file (not a link) owned by the user that no one else may write
to; any other file there is removed, so that it is rebuilt privately.
"""
from __future__ import annotations

import atexit
import os
import shutil
import stat
import tempfile
import threading
from pathlib import Path

_lock = threading.Lock()
_scratch: Path | None = None        # this run's private folder, when the configured one is refused
_scratch_pid = 0


def configured_cache_dir() -> Path:
    """Where the cache lives when it is usable (ASMCHECK_CACHE, XDG_CACHE_HOME, ~/.cache)."""
    env = os.environ.get("ASMCHECK_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "asmcheck"


def _uid() -> int | None:
    return os.geteuid() if hasattr(os, "geteuid") else None


def _private_folder(path: Path) -> bool:
    """Is ``path`` a folder of the user's that no one else may write to (made so if it is the user's)?"""
    try:
        st = os.stat(path)
    except OSError:
        return False
    if not stat.S_ISDIR(st.st_mode):
        return False
    uid = _uid()
    if uid is None:
        return True
    if st.st_uid != uid:
        return False
    if st.st_mode & 0o077:
        try:
            os.chmod(path, 0o700)
        except OSError:
            return False
        try:
            return not (os.stat(path).st_mode & 0o077)
        except OSError:
            return False
    return True


def _scratch_dir() -> Path:
    """A private folder for this process only (mkdtemp: mode 0700, unpredictable name)."""
    global _scratch, _scratch_pid
    if _scratch is None or _scratch_pid != os.getpid():
        _scratch = Path(tempfile.mkdtemp(prefix="asmcheck-cache-"))
        _scratch_pid = os.getpid()
        atexit.register(shutil.rmtree, str(_scratch), True)
    return _scratch


def private_cache_dir() -> Path:
    """The cache folder, created with mode 0700 and checked (see the module's text).

    Never a shared folder: when the configured folder cannot be made private, a fresh
    private folder of this run is returned instead."""
    with _lock:
        path = configured_cache_dir()
        try:
            if not path.exists():
                os.makedirs(path, mode=0o700, exist_ok=True)
        except OSError:
            return _scratch_dir()
        if _private_folder(path):
            return path
        return _scratch_dir()


def usable_cache_file(path: Path) -> bool:
    """May the cache file at ``path`` be read?  A file that may not is removed (to be rebuilt).

    Usable: absent (it will be written), or a regular file, not a link, owned by the user
    and writable by no one else."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return True
    except OSError:
        return False
    uid = _uid()
    ok = stat.S_ISREG(st.st_mode) and not (st.st_mode & 0o022) and (uid is None or st.st_uid == uid)
    if ok:
        return True
    try:
        if stat.S_ISDIR(st.st_mode):
            shutil.rmtree(path)
        else:
            os.unlink(path)
    except OSError:
        return False
    return True


def private_cache_file(name: str) -> Path | None:
    """``name`` in the private cache folder, checked by :func:`usable_cache_file`; None when
    the file there can be neither trusted nor removed (then do not cache)."""
    if os.sep in name or (os.altsep and os.altsep in name) or name in ("", ".", ".."):
        raise ValueError(f"not a plain file name: {name!r}")
    path = private_cache_dir() / name
    return path if usable_cache_file(path) else None
