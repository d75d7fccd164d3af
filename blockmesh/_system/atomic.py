"""Atomic outputs: build every output beside its target under a hidden name, commit by one rename.

Used by every writer (:mod:`blockmesh.io`), the pictures, the tables' CSV and the domain files. A
reader of the target sees the old output or the new one, never a truncated file or a mix, even if
the writing process is killed. Three shapes of output:

one file (:func:`atomic_file`)
    written to a temporary file, then renamed onto the target.
a folder (:func:`atomic_dir`, an OpenFOAM ``polyMesh`` or case)
    built as a temporary folder, then swapped with the old one in one step (Linux
    ``renameat2(RENAME_EXCHANGE)``). Where the system cannot swap, the old folder is first
    renamed aside; a kill between the two renames is repaired by the next write to the target,
    which puts the old folder back.
a light file naming a data file (:func:`atomic_with_data`, an ``.xdmf`` and its ``.h5``)
    the data file gets a new name of its own (``STEM.<8 hex digits>.h5``) and is renamed in first;
    renaming the light file, which names it, is the commit. Data files of earlier writes are
    removed after it.

Temporary names are ``.NAME.HOST-PID-RANDOM.tmp`` (and ``.old`` for a folder moved aside). A later
write to the same target removes those whose process no longer runs on this machine: what a
killed run left behind (see :func:`clean_stale`).

A Ctrl-C (or SIGTERM, SIGHUP) that arrived during the write stops it before the commit even if
a finaliser swallowed its exception (:func:`blockmesh._system.interrupts.raise_pending`).

Operating-system failures (no space left, read-only file system, permission denied, a path
component that is not a folder) become one :class:`~blockmesh.errors.ExportError` naming the
target and the cause (:mod:`blockmesh._system.targets`, whose names are re-exported here).

Examples
--------
>>> import pathlib, tempfile
>>> target = pathlib.Path(tempfile.mkdtemp()) / "out.txt"
>>> with atomic_file(target) as tmp:
...     _ = tmp.write_text("done")
>>> target.read_text(), sorted(p.name for p in target.parent.iterdir())
('done', ['out.txt'])
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import os
import re
import shutil
import stat
import time
from collections.abc import Callable, Iterator
from pathlib import Path

from blockmesh._system.bounded import file_kind
from blockmesh._system.interrupts import raise_pending
from blockmesh._system.libc import libc_function
from blockmesh._system.procfs import umask
from blockmesh._system.targets import as_path, check_target, export_error, export_errors
from blockmesh.errors import ExportError

__all__ = [
    "as_path",
    "atomic_dir",
    "atomic_file",
    "atomic_files",
    "atomic_with_data",
    "check_target",
    "clean_stale",
    "data_files",
    "export_error",
    "export_errors",
    "remove_pending",
    "scratch_file",
]


def _host_name() -> str:
    """The machine's name (without importing ``socket``, whose import costs start-up time)."""
    try:
        return os.uname().nodename
    except AttributeError:  # Windows
        import socket

        return socket.gethostname()


def _token(n_bytes: int) -> str:
    """``2 n_bytes`` random hex digits (as ``secrets.token_hex``, without its imports)."""
    return os.urandom(n_bytes).hex()


_HOST = re.sub(r"[^A-Za-z0-9]", "", _host_name())[:24] or "host"
_TAG = re.compile(r"(?P<host>[A-Za-z0-9]+)-(?P<pid>\d+)-[0-9a-f]{6}")
#: Names ``tempfile.mkstemp`` gave temporaries before the tags: stale once an hour old.
_UNTAGGED = re.compile(r"[a-z0-9_]{8}")
_UNTAGGED_AGE = 3600.0
_DATA_TOKEN = r"[0-9a-f]{8}"


# --------------------------------------------------------------------------- temporaries
def _mode_for(target: Path, default: int) -> int:
    try:
        return stat.S_IMODE(target.stat().st_mode)
    except OSError:
        return default & ~umask()


def _temp_path(target: Path, kind: str = "tmp") -> Path:
    tag = f"{_HOST}-{os.getpid()}-{_token(3)}"
    return target.with_name(f".{target.name}.{tag}.{kind}")


#: Temporaries this process created and has not yet renamed or removed. A signal that arrives
#: after a temporary is created but before the ``try`` that removes it (a window of a few
#: bytecodes) would leave it behind; :func:`remove_pending` removes what is listed here.
_PENDING: set[Path] = set()


def _new_temp(target: Path, create: Callable[[Path], None]) -> Path:
    while True:
        tmp = _temp_path(target)
        _PENDING.add(tmp)  # listed before it exists: no moment where it exists unlisted
        try:
            create(tmp)
        except FileExistsError:
            _PENDING.discard(tmp)
            continue
        return tmp


def _create_file(tmp: Path) -> None:
    os.close(os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))


def _new_temp_file(target: Path) -> Path:
    return _new_temp(target, _create_file)


def _new_temp_dir(target: Path) -> Path:
    return _new_temp(target, lambda tmp: os.mkdir(tmp, 0o700))


def _unlink(path: Path) -> None:
    with contextlib.suppress(OSError):
        path.unlink()
    _PENDING.discard(path)


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        _unlink(path)
    _PENDING.discard(path)


def remove_pending() -> list[Path]:
    """Remove the temporaries this process left, e.g. when a signal interrupted a write.

    The writers remove their temporaries themselves when an exception unwinds them; this is
    for the few bytecodes between creating one and entering the ``try`` that would remove it.
    The command line calls it when it stops on Ctrl-C, SIGTERM or SIGHUP.

    Returns
    -------
    list of pathlib.Path
        The temporaries that still existed and were removed.

    Examples
    --------
    >>> remove_pending()
    []
    """
    removed = []
    for path in list(_PENDING):
        if path.exists() or path.is_symlink():
            removed.append(path)
        _remove(path)
    return removed


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs on this machine (True when that cannot be known)."""
    if pid == os.getpid() or os.name != "posix":
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def _is_stale(path: Path, middle: str) -> bool:
    tag = _TAG.fullmatch(middle)
    if tag is not None:
        return tag["host"] == _HOST and not _alive(int(tag["pid"]))
    if _UNTAGGED.fullmatch(middle):
        try:
            return time.time() - path.lstat().st_mtime > _UNTAGGED_AGE
        except OSError:
            return False
    return False


def _mtime(path: Path) -> float:
    try:
        return path.lstat().st_mtime
    except OSError:  # removed meanwhile (by another writer's clean-up)
        return 0.0


def clean_stale(target: Path) -> list[Path]:
    """Remove the temporaries a killed write to ``target`` left; returns the paths handled.

    A temporary ``.NAME.HOST-PID-RANDOM.tmp`` (file or folder) or ``.old`` (a folder moved aside)
    is stale when it was made on this machine by a process that no longer runs; temporaries of
    running writers and of other machines are left alone. If the target itself is missing and a
    stale ``.old`` folder exists, the write was killed between its two renames: the ``.old``
    folder (the previous output, whole) is put back instead of being removed.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / f".m.vtu.{_HOST}-999999999-abcdef.tmp").write_text("left by a kill")
    >>> [p.name.endswith(".tmp") for p in clean_stale(folder / "m.vtu")], list(folder.iterdir())
    ([True], [])
    """
    target = Path(target).absolute()
    prefix = f".{target.name}."
    try:
        entries = [
            Path(e.path)
            for e in os.scandir(target.parent)
            if e.name.startswith(prefix) and e.name.endswith((".tmp", ".old"))
        ]
    except OSError:
        return []
    stale = [p for p in entries if _is_stale(p, p.name[len(prefix) : -4])]
    stale.sort(key=_mtime, reverse=True)
    for path in stale:
        if path.name.endswith(".old") and path.is_dir() and not os.path.lexists(target):
            with contextlib.suppress(OSError):
                os.rename(path, target)
                continue
        _remove(path)
    return stale


# ---------------------------------------------------------------- one file or one folder
@contextlib.contextmanager
def _committed(target: Path, *, directory: bool) -> Iterator[Path]:
    """A temporary file (or folder) put in place of ``target`` when the block ends without error.

    A file is renamed onto the target, a folder swapped in (:func:`_swap_in`); the temporary is
    removed whatever happens, and an :class:`OSError` becomes an :class:`ExportError`.
    """
    target = check_target(Path(target), directory=directory)
    with export_errors(target):
        clean_stale(target)
        tmp = _new_temp_dir(target) if directory else _new_temp_file(target)
        try:
            yield tmp
            os.chmod(tmp, _mode_for(target, 0o777 if directory else 0o666))
            raise_pending()  # Ctrl-C swallowed by a finaliser during the write: no commit
            if directory:
                _swap_in(tmp, target)
            else:
                os.replace(tmp, target)
        finally:
            if directory:
                _remove(tmp)
            else:
                _unlink(tmp)


# ------------------------------------------------------------------------------ one file
@contextlib.contextmanager
def atomic_file(target: Path) -> Iterator[Path]:
    """A temporary path renamed onto ``target`` when the block ends without error.

    The target's parent folder must exist (see :func:`check_target`). An existing target keeps its
    permission bits; a new one gets ``0o666`` less the umask. An exception (or Ctrl-C) in the
    block removes the temporary file and leaves the target as it was; an :class:`OSError` becomes
    an :class:`ExportError` (see :func:`export_error`).
    """
    with _committed(target, directory=False) as tmp:
        yield tmp


@contextlib.contextmanager
def atomic_files(*targets: Path) -> Iterator[tuple[Path, ...]]:
    """Temporary paths for several ``targets``, renamed onto them one after the other.

    Each file is whole, and if a rename fails the targets already renamed are put back; but a
    process killed between two renames leaves new and old files side by side. For a light file
    that names a data file use :func:`atomic_with_data`, which has no such window.
    """
    targets = tuple(check_target(Path(t)) for t in targets)
    with export_errors(targets[0]):
        temps: list[Path] = []
        try:
            for t in targets:
                clean_stale(t)
                temps.append(_new_temp_file(t))
            yield tuple(temps)
            for tmp, t in zip(temps, targets, strict=True):
                os.chmod(tmp, _mode_for(t, 0o666))
            raise_pending()
            _replace_all(temps, list(targets))
        finally:
            for tmp in temps:
                _unlink(tmp)


def _replace_all(temps: list[Path], targets: list[Path]) -> None:
    """Rename every temporary onto its target; if one rename fails, put the old targets back."""
    done: list[tuple[Path, Path | None]] = []
    try:
        for tmp, target in zip(temps, targets, strict=True):
            backup = None
            if os.path.lexists(target):
                backup = _temp_path(target)
                try:
                    os.link(target, backup)
                except OSError:  # no hard links on this file system
                    shutil.copy2(target, backup)
            try:
                os.replace(tmp, target)
            except BaseException:
                if backup is not None:
                    _unlink(backup)
                raise
            done.append((target, backup))
    except BaseException:
        for target, backup in reversed(done):  # each put back, whatever the others do
            with contextlib.suppress(OSError):
                if backup is not None:
                    os.replace(backup, target)
                else:
                    target.unlink()
        raise
    for _, backup in done:
        if backup is not None:
            _unlink(backup)


@contextlib.contextmanager
def scratch_file(target: Path) -> Iterator[Path]:
    """A temporary file beside ``target``, deleted when the block ends (for intermediate output)."""
    target = Path(target).absolute()
    with export_errors(target):
        tmp = _new_temp_file(target)
        try:
            yield tmp
        finally:
            _unlink(tmp)


# -------------------------------------------------------------------------------- folders
def _renameat2() -> Callable[..., int] | None:
    arguments = (ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint)
    return libc_function("renameat2", arguments, ctypes.c_int)


_AT_FDCWD, _RENAME_EXCHANGE = -100, 2
_CANNOT_EXCHANGE = {errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EXDEV}


def _exchange(a: Path, b: Path) -> bool:
    """Swap the paths ``a`` and ``b`` in one step; False where the system cannot."""
    func = _renameat2()
    if func is None:
        return False
    if func(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in _CANNOT_EXCHANGE:
        return False
    raise OSError(code, os.strerror(code), os.fspath(b))


def _swap_in(new: Path, target: Path) -> None:
    """Put the folder ``new`` at ``target``; afterwards ``new`` holds the old folder, if any."""
    if not os.path.lexists(target):
        os.rename(new, target)
        return
    if _exchange(new, target):
        return
    old = _temp_path(target, "old")
    os.rename(target, old)
    try:
        os.rename(new, target)
    except BaseException:
        os.rename(old, target)
        raise
    os.rename(old, new)


@contextlib.contextmanager
def atomic_dir(target: Path) -> Iterator[Path]:
    """A temporary folder that replaces the folder ``target`` when the block succeeds.

    The new folder is swapped with the old one in one step where the system can (Linux); else the
    old one is renamed aside first (a kill then is repaired by the next write, see
    :func:`clean_stale`). The old folder is deleted afterwards. If the block raises, the
    temporary folder is deleted and ``target`` is left as it was.
    """
    with _committed(target, directory=True) as tmp:
        yield tmp


# -------------------------------------------------------------- light file + data file
@contextlib.contextmanager
def _folder_lock(folder: Path) -> Iterator[None]:
    """An exclusive lock on ``folder`` (flock) for the block, where the system offers one."""
    try:
        import fcntl
    except ImportError:  # not POSIX
        yield
        return
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        yield
        return
    try:
        with contextlib.suppress(OSError):
            fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def data_files(light: Path, suffix: str) -> list[Path]:
    """The files beside ``light`` named like its data files.

    That is ``STEM.<8 hex digits>SUFFIX`` and ``STEMSUFFIX`` (the name before the digits); only
    regular files (not links, FIFOs or devices, which no write made and which are never opened).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> for name in ("m.xdmf", "m.h5", "m.0123abcd.h5", "m.x.h5", "other.h5"):
    ...     _ = (folder / name).write_text("")
    >>> [p.name for p in data_files(folder / "m.xdmf", ".h5")]
    ['m.0123abcd.h5', 'm.h5']
    """
    light = Path(light).absolute()
    pattern = re.compile(re.escape(light.stem) + rf"(\.{_DATA_TOKEN})?" + re.escape(suffix))
    try:
        names = [
            e.name
            for e in os.scandir(light.parent)
            if pattern.fullmatch(e.name) and e.is_file(follow_symlinks=False)
        ]
    except OSError:
        return []
    return sorted(light.parent / name for name in names)


@contextlib.contextmanager
def atomic_with_data(
    light: Path, suffix: str, *, owned: Callable[[Path], bool]
) -> Iterator[tuple[Path, Path, Path]]:
    """Temporary paths for a light file and its data file, committed together.

    Yields ``(light_tmp, data_tmp, data)``: write the data to ``data_tmp`` and, to ``light_tmp``,
    a light file that names the data file ``data.name`` (``STEM.<8 hex digits>SUFFIX``, a name no
    file has). When the block succeeds, ``data_tmp`` is renamed to ``data`` and then ``light_tmp``
    onto ``light``: that last rename is the commit, so a reader finds the old pair or the new one.
    Then the data files of earlier writes (:func:`data_files` for which ``owned(path)`` is true)
    are removed. Commits of concurrent writers to the same folder are serialised (flock).
    """
    light = check_target(Path(light))
    with export_errors(light):
        clean_stale(light)
        while True:
            data = light.with_name(f"{light.stem}.{_token(4)}{suffix}")
            if not os.path.lexists(data):
                break
        light_tmp, data_tmp = _new_temp_file(light), _new_temp_file(light)
        try:
            yield light_tmp, data_tmp, data
            mode = _mode_for(light, 0o666)
            os.chmod(light_tmp, mode)
            os.chmod(data_tmp, mode)
            with _folder_lock(light.parent):
                raise_pending()
                os.replace(data_tmp, data)
                try:
                    os.replace(light_tmp, light)
                except BaseException:
                    _unlink(data)
                    raise
                for old in data_files(light, suffix):
                    if old != data and owned(old):
                        _unlink(old)
        finally:
            _unlink(light_tmp)
            _unlink(data_tmp)


# ------------------------------------------------------------ light file + data folder
_GENERATION = re.compile(_DATA_TOKEN)


@contextlib.contextmanager
def atomic_with_folder(light: Path, folder: Path) -> Iterator[tuple[Path, Path, str]]:
    """Temporary paths for a light file and a folder of data files it names, committed together.

    The data of each write goes to a folder of its own, ``folder/<8 hex digits>`` (a
    *generation*). Yields ``(light_tmp, data_tmp, generation)``: fill the temporary folder
    ``data_tmp`` (inside ``folder``) and write to ``light_tmp`` a light file naming its data as
    ``FOLDER/GENERATION/NAME``. When the block succeeds, ``data_tmp`` is renamed to
    ``folder/generation`` and then ``light_tmp`` onto ``light``: that last rename is the commit,
    so a reader (and a process killed at any step) finds the old light file with its data or the
    new one with its own. The other generations are removed afterwards, and so are the
    temporaries killed writes left (:func:`clean_stale`). If the block raises, the temporaries
    go, and ``folder`` too when this write made it and it is empty. Commits of concurrent writers
    are serialised (flock on ``folder``).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> out = pathlib.Path(tempfile.mkdtemp())
    >>> for text in ("first", "second"):
    ...     with atomic_with_folder(out / "m.idx", out / "m.idx.pieces") as (light, data, gen):
    ...         _ = (data / "p0").write_text(text)
    ...         _ = light.write_text(f"m.idx.pieces/{gen}/p0")
    >>> named = (out / "m.idx").read_text()
    >>> (out / named).read_text(), len(list((out / "m.idx.pieces").iterdir()))
    ('second', 1)
    """
    light = check_target(Path(light))
    folder = Path(folder).absolute()
    with export_errors(light):
        clean_stale(folder)  # what killed writes of the earlier layout left beside the index
        made = False
        try:
            mode = os.stat(folder).st_mode
        except FileNotFoundError:
            os.mkdir(folder, 0o777)  # the umask applies, as to any new folder
            made = True
        else:
            if not stat.S_ISDIR(mode):
                raise ExportError(
                    f"cannot write {light}: its data folder {folder} is {file_kind(mode)}, not a "
                    "directory (move it away)"
                )
        clean_stale(light)
        while True:
            generation = _token(4)
            if not os.path.lexists(folder / generation):
                break
        light_tmp = _new_temp_file(light)
        data_tmp = _new_temp_dir(folder / generation)
        committed = False
        try:
            yield light_tmp, data_tmp, generation
            os.chmod(light_tmp, _mode_for(light, 0o666))
            os.chmod(data_tmp, 0o777 & ~umask())
            with _folder_lock(folder):
                raise_pending()  # Ctrl-C swallowed by a finaliser during the write: no commit
                os.rename(data_tmp, folder / generation)
                _PENDING.add(folder / generation)  # removed again if the commit fails
                os.replace(light_tmp, light)
                committed = True
                _PENDING.discard(folder / generation)
                _clean_generations(folder, keep=generation)
        finally:
            _unlink(light_tmp)
            _remove(data_tmp)
            if not committed:
                _remove(folder / generation)
                if made:
                    with contextlib.suppress(OSError):
                        os.rmdir(folder)


def _clean_generations(folder: Path, keep: str) -> None:
    """Remove the generations in ``folder`` other than ``keep``, and stale temporaries."""
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return
    for entry in entries:
        if entry.name == keep:
            continue
        if _GENERATION.fullmatch(entry.name):
            _remove(Path(entry.path))
        elif entry.name.startswith(".") and entry.name.endswith(".tmp"):
            generation = entry.name[1:].split(".", 1)[0]
            clean_stale(folder / generation)
