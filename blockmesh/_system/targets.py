"""Output targets checked before writing, and operating-system failures as one located error.

Every writer checks its target first (:func:`check_target`: the folder exists, nothing of
another kind is in the way) and turns an :class:`OSError` while writing (no space left,
read-only file system, permission denied, a path component that is not a folder) into one
:class:`~blockmesh.errors.ExportError` naming the target, the cause and what to do
(:func:`export_error`, :func:`export_errors`); :func:`as_path` checks a path argument's type.
The atomic writers (:mod:`blockmesh._system.atomic`) use them for every output.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import stat
from collections.abc import Iterator
from pathlib import Path

from blockmesh._system.bounded import file_kind
from blockmesh.errors import ArgumentTypeError, ExportError

__all__ = ["as_path", "check_target", "export_error", "export_errors"]

_HINTS = {
    errno.ENOSPC: "free some space or write elsewhere",
    errno.EDQUOT: "free some space or write elsewhere",
    errno.EROFS: "write to a folder on a writable file system",
    errno.EACCES: "check the folder's permissions, or write elsewhere",
    errno.EPERM: "check the folder's permissions, or write elsewhere",
    errno.ENOTDIR: "a part of the path is a file, not a folder",
    errno.ENAMETOOLONG: "choose a shorter name",
}


#: numpy's message for a short write (``ndarray.tofile``), which carries no error number.
_SHORT_WRITE = re.compile(r"(?P<requested>\d+) requested and (?P<written>\d+) written")


def export_error(error: OSError, target: Path) -> ExportError:
    """The :class:`ExportError` for an OS failure while writing ``target``: path and cause.

    Examples
    --------
    >>> import errno
    >>> print(export_error(OSError(errno.ENOSPC, "No space left on device"), Path("/d/m.vtu")))
    cannot write /d/m.vtu: No space left on device (ENOSPC); free some space or write elsewhere

    A short write without an error number (numpy's ``tofile``: "5345 requested and 2011
    written") is a full disk too:

    >>> short = export_error(OSError("5345 requested and 2011 written"), Path("/d/m.vtk"))
    >>> str(short).split(": ", 1)[1].split(";")[:2]
    ['No space left on device (ENOSPC', ' only 2011 of 5345 bytes were written)']
    """
    short = _SHORT_WRITE.fullmatch(str(error)) if not error.errno else None
    if short:
        return ExportError(
            f"cannot write {target}: {os.strerror(errno.ENOSPC)} (ENOSPC; only "
            f"{short['written']} of {short['requested']} bytes were written); "
            f"{_HINTS[errno.ENOSPC]}"
        )
    number = error.errno or 0
    code = errno.errorcode.get(number)
    reason = os.strerror(number) if code else (error.strerror or str(error))
    reason = reason or type(error).__name__
    text = f"cannot write {target}: {reason}"
    if code:
        text += f" ({code})"
    hint = _HINTS.get(error.errno or 0)
    return ExportError(f"{text}; {hint}" if hint else text)


@contextlib.contextmanager
def export_errors(target: Path) -> Iterator[None]:
    """Turn an :class:`OSError` raised in the block into :func:`export_error` for ``target``."""
    try:
        yield
    except OSError as error:
        raise export_error(error, Path(target)) from error


def as_path(value: object, what: str = "path") -> Path:
    """``value`` (a ``str`` or ``os.PathLike``) as a :class:`~pathlib.Path`.

    Raises
    ------
    ArgumentTypeError
        For anything else (``None``, a number, a list), naming ``what`` and the type given.

    Examples
    --------
    >>> as_path("out/m.vtu")
    PosixPath('out/m.vtu')
    >>> as_path(3.5)
    Traceback (most recent call last):
    ...
    blockmesh.errors.ArgumentTypeError: path must be a str or os.PathLike, got float 3.5
    """
    if isinstance(value, str | os.PathLike):
        path = os.fspath(value)
        if isinstance(path, str):
            return Path(path)
    raise ArgumentTypeError(
        f"{what} must be a str or os.PathLike, got {type(value).__name__} {value!r:.60}"
    )


def check_target(path: Path, *, directory: bool = False) -> Path:
    """The absolute target path, after checking its parent folder exists.

    Raises :class:`ExportError` naming the missing folder (or the file in the way), or when a file
    target is an existing folder (or a folder target an existing file).

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
        blocker = next((p for p in (parent, *parent.parents) if os.path.lexists(p)), None)
        if blocker is not None and not blocker.is_dir():
            raise ExportError(
                f"cannot write {path}: {blocker} is a file, not a directory; choose another folder"
            )
        raise ExportError(
            f"cannot write {path}: the directory {parent} does not exist; "
            f"create it first (mkdir -p {parent})"
        )
    try:
        mode: int | None = os.stat(path).st_mode  # symbolic links followed: where it would go
    except OSError:
        mode = None  # nothing there (or a dangling link, which the rename replaces)
    if mode is None:
        return path
    if not directory and stat.S_ISDIR(mode):
        raise ExportError(f"cannot write {path}: it is a directory; give a file name")
    if not directory and not stat.S_ISREG(mode):
        raise ExportError(
            f"cannot write {path}: it is {file_kind(mode)}, not a regular file; blockmesh writes "
            "only where a regular file may go (give another name)"
        )
    if directory and stat.S_ISREG(mode):
        raise ExportError(f"cannot write the directory {path}: a file of that name exists")
    if directory and not stat.S_ISDIR(mode):
        raise ExportError(
            f"cannot write the directory {path}: it is {file_kind(mode)} (give another name)"
        )
    return path
