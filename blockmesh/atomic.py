"""Atomic writes: build the output next to its target under a temporary name, then rename it.

Used by every writer (:mod:`blockmesh.io`), the pictures and the domain files.

An exception (or Ctrl-C) while the output is being written removes the temporary file and leaves
any existing file untouched; a reader never sees a half-written file. Several files that belong
together (an ``.xdmf`` and its ``.h5``) are renamed one after the other and put back as they were
if a rename fails. A directory (an OpenFOAM ``polyMesh``) is swapped in by two renames.

Examples
--------
>>> import pathlib, tempfile
>>> target = pathlib.Path(tempfile.mkdtemp()) / "out.txt"
>>> with atomic_file(target) as tmp:
...     _ = tmp.write_text("done")
>>> target.read_text()
'done'
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

from .errors import ExportError

__all__ = ["atomic_dir", "atomic_file", "atomic_files", "check_target", "scratch_file"]


def _umask() -> int:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except OSError:
        pass
    return 0o022


def _mode_for(target: Path, default: int) -> int:
    try:
        return stat.S_IMODE(target.stat().st_mode)
    except OSError:
        return default & ~_umask()


def check_target(path: Path, *, directory: bool = False) -> Path:
    """The absolute target path, after checking its parent directory exists.

    Raises :class:`ExportError` naming the missing directory, or when a file target is an
    existing directory (or a directory target an existing file).

    Examples
    --------
    >>> check_target(Path("/no/dir/m.vtu"))
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: cannot write /no/dir/m.vtu: the directory /no/dir does not ...
    """
    path = Path(path).absolute()
    parent = path.parent
    if not parent.is_dir():
        raise ExportError(
            f"cannot write {path}: the directory {parent} does not exist; "
            f"create it first (mkdir -p {parent})"
        )
    if not directory and path.is_dir():
        raise ExportError(f"cannot write {path}: it is a directory; give a file name")
    if directory and path.exists() and not path.is_dir():
        raise ExportError(f"cannot write the directory {path}: a file of that name exists")
    return path


def _temp_file(target: Path) -> Path:
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    return Path(name)


def _unlink(path: Path) -> None:
    with contextlib.suppress(OSError):
        path.unlink()


@contextlib.contextmanager
def atomic_files(*targets: Path) -> Iterator[tuple[Path, ...]]:
    """Temporary paths for ``targets``, renamed onto them when the block ends without error.

    The targets' parent directories must exist (see :func:`check_target`). Existing targets keep
    their permission bits; new ones get ``0o666`` less the umask.
    """
    targets = tuple(check_target(t) for t in targets)
    temps: list[Path] = []
    try:
        for t in targets:
            temps.append(_temp_file(t))
        yield tuple(temps)
        for tmp, target in zip(temps, targets, strict=True):
            os.chmod(tmp, _mode_for(target, 0o666))
        _commit(temps, list(targets))
    finally:
        for tmp in temps:
            _unlink(tmp)


def _keep_copy(target: Path) -> Path:
    """A hard link (or, where links are not supported, a copy) of ``target`` beside it."""
    backup = _temp_file(target)
    _unlink(backup)
    try:
        os.link(target, backup)
    except OSError:
        shutil.copy2(target, backup)
    return backup


def _commit(temps: list[Path], targets: list[Path]) -> None:
    """Rename every temp onto its target; if one rename fails, put the old targets back."""
    if len(targets) == 1:
        os.replace(temps[0], targets[0])
        return
    done: list[tuple[Path, Path | None]] = []
    try:
        for tmp, target in zip(temps, targets, strict=True):
            backup = _keep_copy(target) if target.exists() else None
            done.append((target, backup))
            os.replace(tmp, target)
    except BaseException:
        for target, backup in reversed(done):
            if backup is not None:
                os.replace(backup, target)
                _unlink(backup)  # still there when it was a link to the unreplaced target
            else:
                _unlink(target)
        raise
    for _, backup in done:
        if backup is not None:
            _unlink(backup)


@contextlib.contextmanager
def atomic_file(target: Path) -> Iterator[Path]:
    """A temporary path renamed onto ``target`` when the block ends without error."""
    with atomic_files(target) as (tmp,):
        yield tmp


@contextlib.contextmanager
def scratch_file(target: Path) -> Iterator[Path]:
    """A temporary file beside ``target``, deleted when the block ends (for intermediate output)."""
    tmp = _temp_file(Path(target).absolute())
    try:
        yield tmp
    finally:
        _unlink(tmp)


@contextlib.contextmanager
def atomic_dir(target: Path) -> Iterator[Path]:
    """A temporary directory that replaces the directory ``target`` when the block succeeds.

    An existing ``target`` is moved aside, the new one renamed in, and the old one deleted; if the
    block raises, the temporary directory is deleted and ``target`` is left as it was.
    """
    target = check_target(target, directory=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent))
    try:
        yield tmp
        os.chmod(tmp, _mode_for(target, 0o777))
        old = None
        if target.exists():
            old = Path(
                tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".old", dir=target.parent)
            )
            os.rmdir(old)
            os.rename(target, old)
        try:
            os.rename(tmp, target)
        except BaseException:
            if old is not None:
                os.rename(old, target)
            raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
