"""The private cache folder (grammar table, compiled models): mode 0700, only the user's files."""
import os
import stat
import tempfile
from pathlib import Path

import pytest

from asmcheck import cache
from asmcheck.syntax import parser

pytestmark = pytest.mark.engines("none")

ROOT = os.geteuid() == 0 if hasattr(os, "geteuid") else False


def _mode(p):
    return stat.S_IMODE(os.stat(p).st_mode)


def test_cache_folder_is_created_private(tmp_path, monkeypatch):
    target = tmp_path / "deep" / "cache"
    monkeypatch.setenv("ASMCHECK_CACHE", str(target))
    assert cache.private_cache_dir() == target
    assert _mode(target) == 0o700
    # the grammar table goes there
    assert parser._cache_file() == str(target / Path(parser._cache_file()).name)
    assert Path(parser._cache_file()).name.startswith("grammar-")


def test_cache_folder_open_to_others_is_made_private(tmp_path, monkeypatch):
    target = tmp_path / "c"
    target.mkdir()
    os.chmod(target, 0o777)
    monkeypatch.setenv("ASMCHECK_CACHE", str(target))
    assert cache.private_cache_dir() == target
    assert _mode(target) == 0o700


@pytest.mark.parametrize("kind", ["group-writable", "world-writable", "symlink"])
def test_untrusted_cache_file_is_removed_and_rebuilt(tmp_path, monkeypatch, kind):
    target = tmp_path / "c"
    monkeypatch.setenv("ASMCHECK_CACHE", str(target))
    name = Path(parser._cache_file()).name
    f = target / name
    if kind == "symlink":
        (tmp_path / "elsewhere").write_bytes(b"not a grammar")
        f.symlink_to(tmp_path / "elsewhere")
    else:
        f.write_bytes(b"not a grammar")
        os.chmod(f, 0o664 if kind == "group-writable" else 0o646)
    assert parser._cache_file() == str(f)
    assert not os.path.lexists(f)                       # refused: removed, to be rebuilt
    assert (tmp_path / "elsewhere").exists() or kind != "symlink"
    # lark builds the table again and writes it in the private folder
    from lark import Lark
    Lark(parser._GRAMMAR_PATH.read_text(encoding="utf-8"), parser="lalr", lexer="contextual",
         propagate_positions=True, maybe_placeholders=False, cache=parser._cache_file())
    st = os.lstat(f)
    assert stat.S_ISREG(st.st_mode) and not (st.st_mode & 0o022)


@pytest.mark.skipif(not ROOT, reason="changing a file's owner needs root")
def test_cache_file_of_another_user_is_refused(tmp_path, monkeypatch):
    target = tmp_path / "c"
    monkeypatch.setenv("ASMCHECK_CACHE", str(target))
    f = Path(parser._cache_file())
    f.write_bytes(b"planted")
    os.chmod(f, 0o644)
    os.chown(f, 4242, 4242)
    assert parser._cache_file() == str(f) and not f.exists()


@pytest.mark.skipif(not ROOT, reason="changing a folder's owner needs root")
def test_cache_folder_of_another_user_is_not_used(tmp_path, monkeypatch):
    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o777)
    os.chown(shared, 4242, 4242)
    monkeypatch.setenv("ASMCHECK_CACHE", str(shared))
    got = cache.private_cache_dir()
    assert got != shared and shared not in got.parents
    assert _mode(got) == 0o700 and os.stat(got).st_uid == os.geteuid()
    assert got.name.startswith("asmcheck-cache-") and got.name != "asmcheck-cache-"
    assert _mode(shared) == 0o777                       # someone else's folder is left alone


def test_no_shared_temporary_name_when_no_cache_folder_can_be_made(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    monkeypatch.setenv("ASMCHECK_CACHE", str(blocker / "cache"))   # under a file: cannot be created
    got = cache.private_cache_dir()
    assert Path(tempfile.gettempdir()) in got.parents
    assert got.name.startswith("asmcheck-cache-") and len(got.name) > len("asmcheck-cache-") + 4
    assert _mode(got) == 0o700
    assert cache.private_cache_dir() == got             # the same folder for the rest of the run


def test_plain_names_only():
    with pytest.raises(ValueError):
        cache.private_cache_file("../x")
