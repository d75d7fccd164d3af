"""blockmesh._system.atomic: one-rename commits, stale temporaries, OS errors as ExportError."""

from __future__ import annotations

import errno
import os
import socket
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from helpers_io import listing, patch_atomic_os, sp_mesh

import blockmesh._system.atomic as atomic
import blockmesh.io as bio
from blockmesh.errors import ExportError


def dead_pid() -> int:
    """The id of a process that has finished."""
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def host() -> str:
    return "".join(c for c in socket.gethostname() if c.isalnum())[:24] or "host"


def test_atomic_file_commits_on_success_only(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic.atomic_file(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("stop")
    assert target.read_text() == "old" and listing(tmp_path) == ["out.txt"]
    with atomic.atomic_file(target) as tmp:
        assert tmp.name.startswith(".out.txt.") and tmp.name.endswith(".tmp")
        tmp.write_text("new")
    assert target.read_text() == "new" and listing(tmp_path) == ["out.txt"]


def test_new_files_get_normal_permissions(tmp_path: Path) -> None:
    umask = os.umask(0)
    os.umask(umask)
    path = bio.write(sp_mesh(1), tmp_path / "m.npz")
    assert path.stat().st_mode & 0o777 == 0o666 & ~umask
    path.chmod(0o600)
    bio.write(sp_mesh(2), path)
    assert path.stat().st_mode & 0o777 == 0o600  # an existing file keeps its bits


def test_stale_temporaries_are_recognised(tmp_path: Path) -> None:
    target = tmp_path / "m.vtu"
    dead, alive = dead_pid(), os.getppid()
    names = {
        "killed": f".m.vtu.{host()}-{dead}-abcdef.tmp",
        "running": f".m.vtu.{host()}-{alive}-abcdef.tmp",
        "elsewhere": f".m.vtu.otherhost-{dead}-abcdef.tmp",
        "another target": f".m.vtu.x.{host()}-{dead}-abcdef.tmp",
        "old untagged": ".m.vtu.abcd1234.tmp",
        "new untagged": ".m.vtu.wxyz9876.tmp",
    }
    for name in names.values():
        (tmp_path / name).write_text("x")
    hour_ago = time.time() - 2 * 3600
    os.utime(tmp_path / names["old untagged"], (hour_ago, hour_ago))
    (tmp_path / f".m.vtu.{host()}-{dead}-123456.tmp").mkdir()  # a folder of a killed write
    removed = {p.name for p in atomic.clean_stale(target)}
    assert removed == {names["killed"], names["old untagged"], f".m.vtu.{host()}-{dead}-123456.tmp"}
    assert set(listing(tmp_path)) == set(names.values()) - {names["killed"], names["old untagged"]}


def test_the_next_write_removes_what_a_kill_left(tmp_path: Path) -> None:
    leftover = tmp_path / f".m.vtu.{host()}-{dead_pid()}-abcdef.tmp"
    leftover.write_bytes(b"\0" * 1000)
    bio.write(sp_mesh(1), tmp_path / "m.vtu")
    assert listing(tmp_path) == ["m.vtu"]


def test_an_old_folder_moved_aside_is_put_back(tmp_path: Path) -> None:
    """A kill between "old aside" and "new in" left no target and a .old folder: restored."""
    aside = tmp_path / f".polyMesh.{host()}-{dead_pid()}-abcdef.old"
    aside.mkdir()
    (aside / "points").write_text("old mesh")
    atomic.clean_stale(tmp_path / "polyMesh")
    assert listing(tmp_path) == ["polyMesh"]
    assert (tmp_path / "polyMesh" / "points").read_text() == "old mesh"


@pytest.mark.parametrize("exchange", [True, False])
def test_atomic_dir_replaces_the_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, exchange: bool
) -> None:
    if not exchange:
        monkeypatch.setattr(atomic, "_exchange", lambda a, b: False)
    target = tmp_path / "poly"
    target.mkdir()
    (target / "old").write_text("1")
    with atomic.atomic_dir(target) as tmp:
        (tmp / "new").write_text("2")
    assert listing(target) == ["new"] and listing(tmp_path) == ["poly"]


def test_exchange_swaps_in_one_step(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    (a / "x").write_text("a")
    if not atomic._exchange(a, b):
        pytest.skip("this system cannot swap two paths in one step (renameat2 RENAME_EXCHANGE)")
    assert listing(b) == ["x"] and listing(a) == []


def test_data_files_of_earlier_writes_are_removed(tmp_path: Path) -> None:
    light = tmp_path / "m.xdmf"
    for name in ("m.h5", "m.0123abcd.h5", "m.x.h5", "other.h5"):
        (tmp_path / name).write_text("data")
    owned = {"m.h5", "m.0123abcd.h5"}
    with atomic.atomic_with_data(light, ".h5", owned=lambda p: p.name in owned) as (lt, dt, data):
        lt.write_text(f"light naming {data.name}")
        dt.write_text("new data")
    assert set(listing(tmp_path)) == {"m.xdmf", data.name, "m.x.h5", "other.h5"}
    assert light.read_text() == f"light naming {data.name}"


def test_check_target_messages(tmp_path: Path) -> None:
    (tmp_path / "f").write_text("")
    with pytest.raises(ExportError, match="is a file, not a directory"):
        atomic.check_target(tmp_path / "f" / "x" / "m.vtu")
    with pytest.raises(ExportError, match="the directory .* does not exist; create it first"):
        atomic.check_target(tmp_path / "no" / "m.vtu")
    with pytest.raises(ExportError, match="it is a directory"):
        atomic.check_target(tmp_path)
    with pytest.raises(ExportError, match="a file of that name exists"):
        atomic.check_target(tmp_path / "f", directory=True)


@pytest.mark.parametrize(
    ("code", "text"),
    [
        (errno.ENOSPC, "No space left on device (ENOSPC); free some space or write elsewhere"),
        (errno.EROFS, "Read-only file system (EROFS); write to a folder on a writable file system"),
        (errno.EACCES, "Permission denied (EACCES); check the folder's permissions, or write"),
        (errno.ENOTDIR, "Not a directory (ENOTDIR); a part of the path is a file, not a folder"),
        (errno.EIO, "Input/output error (EIO)"),
    ],
)
def test_export_error_names_path_and_cause(code: int, text: str) -> None:
    error = atomic.export_error(OSError(code, "library wording"), Path("/data/m.vtu"))
    assert str(error).startswith(f"cannot write /data/m.vtu: {text}")


def test_errors_inside_the_block_are_translated(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    with (
        pytest.raises(ExportError, match="No space left on device") as info,
        atomic.atomic_file(tmp_path / "x") as tmp,
    ):
        tmp.write_text("a")
        raise OSError(errno.ENOSPC, "full")
    assert isinstance(info.value.__cause__, OSError) and listing(tmp_path) == []

    def refuse(*args: object, **kw: object) -> int:
        raise PermissionError(errno.EACCES, "denied")

    patch_atomic_os(monkeypatch, open=refuse)
    with (
        pytest.raises(ExportError, match=r"cannot write .*x: Permission denied \(EACCES\)"),
        atomic.atomic_file(tmp_path / "x"),
    ):
        pass


CONCURRENT = """
import sys
sys.path.insert(0, {tests!r})
import blockmesh.io as bio
from helpers_io import sp_mesh
mesh = sp_mesh({level})
for _ in range(15):
    bio.write(mesh, {path!r})
"""


@pytest.mark.slow
def test_concurrent_writers_leave_one_whole_pair(tmp_path: Path) -> None:
    """Two processes writing the same .xdmf target: the pair read at the end is whole."""
    path = tmp_path / "m.xdmf"
    tests = str(Path(__file__).parents[1])
    runs = [
        subprocess.Popen(
            [
                sys.executable,
                "-c",
                textwrap.dedent(CONCURRENT.format(tests=tests, level=level, path=str(path))),
            ]
        )
        for level in (1, 2)
    ]
    assert [r.wait(timeout=300) for r in runs] == [0, 0]
    assert bio.read(path).n_cells in (6, 36)
    assert len(listing(tmp_path)) == 2 and not list(tmp_path.glob(".*"))


def test_atomic_files_puts_the_old_files_back_when_a_rename_fails(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The older several-file commit (kept for its users): all renamed, or all put back."""
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text("old a")
    b.write_text("old b")
    calls: list[object] = []

    def flaky(src: object, dst: object) -> None:
        calls.append(dst)
        if dst == b:
            raise OSError(errno.EIO, "rename failed")
        os.replace(src, dst)

    patch_atomic_os(monkeypatch, replace=flaky)
    with pytest.raises(ExportError), atomic.atomic_files(a, b) as (ta, tb):
        ta.write_text("new a")
        tb.write_text("new b")
    monkeypatch.undo()
    assert (a.read_text(), b.read_text()) == ("old a", "old b")
    assert listing(tmp_path) == ["a.txt", "b.txt"]
    with atomic.atomic_files(a, b) as (ta, tb):
        ta.write_text("new a")
        tb.write_text("new b")
    assert (a.read_text(), b.read_text()) == ("new a", "new b")
    assert listing(tmp_path) == ["a.txt", "b.txt"]
