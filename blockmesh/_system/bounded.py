"""Reading files nobody vouches for, within bounds: the guards every reader shares.

A mesh or domain file may come from anywhere, so every reader of blockmesh treats it as hostile:

- **only ordinary files** are opened (:func:`open_regular`, :func:`check_regular`): a FIFO, a
  device, a socket or a directory is refused *before* it is opened (opening a FIFO blocks;
  reading ``/dev/zero`` never ends), and the file opened is checked again (``fstat``), so a
  file swapped for a FIFO in between is refused too;
- **declared sizes are checked before anything is allocated** (:class:`ReadGuard`): data stored
  as it is must be in the file (:meth:`ReadGuard.stored`); compressed data may expand at most
  :data:`MAX_EXPANSION` times the size of the files read (:meth:`ReadGuard.expanded`: a mesh's
  coordinates do not compress that well, a decompression bomb does); and what a read allocates
  must fit in its memory limit (:meth:`ReadGuard.allocate`: ``max_memory`` given to
  :func:`reading`, by default the memory available now);
- **decompression stops at the declared size** (:func:`inflate`, :class:`Inflater`): data is
  inflated in bounded pieces, and one byte more than declared is an error, never a bigger buffer;
- **XML is parsed by expat**, linear in its size, with entity declarations refused
  (:func:`parse_xml`);
- **a file named by a file stays in its folder** (:func:`confined`): an XDMF's HDF5 file, an
  index's pieces; absolute paths, ``..`` and links that lead out are refused, with one message
  that does not tell whether the file exists.

Every refusal is one :class:`~blockmesh.errors.BlockMeshError` naming the file, the part of it
and the value (an :class:`~blockmesh.errors.ExportError` for a mesh file, a
:class:`~blockmesh.errors.ResourceError` for a memory limit).

Examples
--------
>>> check_regular("/dev/null", what="mesh file")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
blockmesh.errors.ExportError: cannot read /dev/null: it is a character device, not a regular file...
>>> with reading("m.vtu", max_memory=1000) as guard:  # doctest: +ELLIPSIS
...     guard.allocate(800, "the points")
...     guard.allocate(400, "the cells")
Traceback (most recent call last):
...
blockmesh.errors.ResourceError: m.vtu: reading the cells needs 400 B more (1.2 KB in all), beyond...
"""

from __future__ import annotations

import contextlib
import contextvars
import lzma
import os
import stat
import zlib
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import BinaryIO

from blockmesh._system.memory import available_memory, format_bytes
from blockmesh.errors import BlockMeshError, ExportError, ResourceError

__all__ = [
    "CHILD_LIMITS",
    "EXPANSION_SLACK",
    "MAX_EXPANSION",
    "Inflater",
    "ReadGuard",
    "check_regular",
    "confined",
    "current_guard",
    "file_kind",
    "inflate",
    "open_regular",
    "parse_xml",
    "reading",
]

#: Most bytes of decompressed data per byte of the files read. A mesh's arrays compress about
#: 1.5-4x (the coordinates hardly at all); a decompression bomb expands about 1000x (zlib) or more.
MAX_EXPANSION = 64
#: Decompressed bytes allowed on top of :data:`MAX_EXPANSION` times the files' size, so that a
#: small file of constant data (a one-cell mesh) is never refused.
EXPANSION_SLACK = 16 * 2**20
#: Bytes inflated at a time.
_PIECE = 1 << 22

_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def file_kind(mode: int) -> str:
    """What a file of mode ``mode`` is, for messages: ``"a FIFO (named pipe)"``, ...

    Examples
    --------
    >>> import os
    >>> file_kind(os.stat("/").st_mode), file_kind(os.stat("/dev/null").st_mode)
    ('a directory', 'a character device')
    """
    if stat.S_ISREG(mode):
        return "a regular file"
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def _refuse(
    path: Path, kind: str, what: str, error: type[BlockMeshError], verb: str = "read"
) -> BlockMeshError:
    return error(
        f"cannot {verb} {path}: it is {kind}, not a regular file; a {what} must be an ordinary file"
    )


def check_regular(
    path: str | os.PathLike[str],
    *,
    what: str = "mesh file",
    error: type[BlockMeshError] = ExportError,
) -> os.stat_result:
    """The ``stat`` of ``path`` if it is a regular file (symbolic links followed), else ``error``.

    Nothing is opened: a FIFO, a device, a socket or a directory is refused by its type.
    A missing or unreadable path is refused too, naming the cause.
    """
    path = Path(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise error(f"cannot read {path}: it does not exist") from None
    except OSError as exc:
        raise error(f"cannot read {path}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(info.st_mode):
        raise _refuse(path, file_kind(info.st_mode), what, error)
    return info


def open_regular(
    path: str | os.PathLike[str],
    *,
    what: str = "mesh file",
    error: type[BlockMeshError] = ExportError,
    max_bytes: int | None = None,
) -> BinaryIO:
    """``path`` opened for reading (binary, buffered) if it is a regular file.

    Refused before opening when it is not (:func:`check_regular`); opened without blocking and
    checked again, so a FIFO put in its place meanwhile is refused too. With ``max_bytes``, a
    larger file is refused. When a :func:`reading` guard is active, the file's size is added to
    what it may expand to (:meth:`ReadGuard.opened`).

    Examples
    --------
    >>> open_regular("/dev/zero")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: cannot read /dev/zero: it is a character device, not a regular...
    """
    path = Path(path)
    check_regular(path, what=what, error=error)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        raise error(f"cannot read {path}: {exc.strerror or exc}") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise _refuse(path, file_kind(info.st_mode), what, error)
        if max_bytes is not None and info.st_size > max_bytes:
            raise error(
                f"cannot read {path}: it has {info.st_size:,} bytes, more than the "
                f"{max_bytes:,} a {what} may have"
            )
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        handle = os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
    guard = _GUARD.get()
    if guard is not None:
        guard.opened(info.st_size)
    return handle


#: Two helpers for the script of a child process that reads a file nobody vouches for (meshio
#: in :mod:`blockmesh.io.sandbox`, h5py in :mod:`blockmesh.io.xdmf.hdf5_probe`): ``_vm()``, the
#: child's address space in bytes, and ``_lower(kind, want)``, which lowers a resource limit
#: (never above the hard limit the parent had). The script imports ``resource`` first.
CHILD_LIMITS = """
def _vm():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0

def _lower(kind, want):
    soft, hard = resource.getrlimit(kind)
    if hard != resource.RLIM_INFINITY:
        want = min(want, hard)
    resource.setrlimit(kind, (want, want if hard == resource.RLIM_INFINITY else hard))
"""


# ------------------------------------------------------------------------------ the guard
class ReadGuard:
    """The bounds of one read: its memory limit and how much its files may expand.

    Made by :func:`reading`; the readers find it with :func:`current_guard`.

    Parameters
    ----------
    where : str
        The file being read (for messages).
    limit : int
        Bytes the read may allocate.
    source : str
        Where the limit comes from, for messages (``"--max-memory"``).
    """

    def __init__(self, where: str, limit: int, source: str) -> None:
        self.where = where
        self.limit = int(limit)
        self.source = source
        self.allocated = 0
        self.file_bytes = 0
        self.expanded_bytes = 0

    def opened(self, nbytes: int) -> None:
        """Count a file of ``nbytes`` bytes among those read (what may expand)."""
        self.file_bytes += max(int(nbytes), 0)

    @property
    def expansion_allowed(self) -> int:
        """Decompressed bytes the files read so far may expand to."""
        return MAX_EXPANSION * self.file_bytes + EXPANSION_SLACK

    def allocate(self, nbytes: int, what: str) -> None:
        """Count ``nbytes`` about to be allocated for ``what``; ResourceError beyond the limit."""
        nbytes = max(int(nbytes), 0)
        self.allocated += nbytes
        if self.allocated > self.limit:
            raise ResourceError(
                f"{self.where}: reading {what} needs {format_bytes(nbytes)} more "
                f"({format_bytes(self.allocated)} in all), beyond the "
                f"{format_bytes(self.limit)} allowed ({self.source}); a damaged file, or a mesh "
                "too big for this machine"
            )

    def stored(self, nbytes: int, left: int, what: str) -> None:
        """ExportError unless ``nbytes`` of data stored as they are fit in the ``left`` bytes."""
        if nbytes < 0 or nbytes > left:
            raise ExportError(
                f"{self.where}: {what} announces {nbytes:,} bytes of data, but only {left:,} "
                "bytes of the file are left (damaged or truncated)"
            )

    def expanded(self, nbytes: int, what: str) -> None:
        """Count ``nbytes`` of data decompressed for ``what``; ExportError beyond the allowance."""
        self.expanded_bytes += max(int(nbytes), 0)
        if self.expanded_bytes > self.expansion_allowed:
            raise ExportError(
                f"{self.where}: {what} expands to more than {MAX_EXPANSION} times the size of "
                f"the file ({format_bytes(self.expanded_bytes)} from "
                f"{format_bytes(self.file_bytes)}); a decompression bomb or a damaged file"
            )


_GUARD: contextvars.ContextVar[ReadGuard | None] = contextvars.ContextVar(
    "blockmesh_read_guard", default=None
)


def _default_limit() -> int:
    return available_memory()


@contextlib.contextmanager
def reading(where: str | os.PathLike[str], *, max_memory: int | None = None) -> Iterator[ReadGuard]:
    """The :class:`ReadGuard` of a read of ``where``, active in the block.

    Inside another read's block (an XDMF reading its HDF5 file) the outer guard is used, so one
    limit covers the whole read. ``max_memory`` is the memory limit in bytes; default: the memory
    available now.
    """
    outer = _GUARD.get()
    if outer is not None:
        yield outer
        return
    if max_memory is None:
        guard = ReadGuard(str(where), _default_limit(), "the memory available now")
    else:
        guard = ReadGuard(str(where), max_memory, "the memory limit, --max-memory")
    token = _GUARD.set(guard)
    try:
        yield guard
    finally:
        _GUARD.reset(token)


def current_guard(where: str | os.PathLike[str] = "the file") -> ReadGuard:
    """The active :class:`ReadGuard`, or a new one with the default limit if none is active."""
    guard = _GUARD.get()
    return (
        guard
        if guard is not None
        else ReadGuard(str(where), _default_limit(), "the memory available now")
    )


# ------------------------------------------------------------------------ decompression
_DECOMPRESSORS: dict[str, Callable[[], object]] = {
    "zlib": zlib.decompressobj,
    "gzip": lambda: zlib.decompressobj(16 + zlib.MAX_WBITS),
    "lzma": lzma.LZMADecompressor,
}
_ERRORS = (zlib.error, lzma.LZMAError, EOFError, ValueError)


class Inflater:
    """Decompress a stream fed in pieces, never past ``limit`` bytes of output.

    ``feed(data)`` returns the output so far (at most ``limit`` bytes in all); one byte more is
    an :class:`ExportError` naming ``what``. Output is made in pieces of a few megabytes, so a
    compressed input of a few bytes never becomes a big buffer at once.

    Examples
    --------
    >>> import zlib
    >>> inflater = Inflater("zlib", 10, "block 0 of the points", "m.vtu")
    >>> inflater.feed(zlib.compress(b"0123456789"))
    b'0123456789'
    >>> Inflater("zlib", 4, "block 0", "m.vtu").feed(zlib.compress(b"0123456789"))
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: m.vtu: block 0 decompresses to more than the 4 bytes declared
    """

    def __init__(self, method: str, limit: int, what: str, where: str) -> None:
        self.method, self.limit, self.what, self.where = method, int(limit), what, where
        self.decompressor: object = _DECOMPRESSORS[method]()
        self.produced = 0

    def _too_big(self) -> ExportError:
        return ExportError(
            f"{self.where}: {self.what} decompresses to more than the {self.limit:,} bytes declared"
        )

    def feed(self, data: bytes | memoryview) -> bytes:
        """Decompress ``data``; the output (bytes), at most the declared size in all."""
        pieces = []
        d = self.decompressor
        pending: bytes | memoryview = data
        try:
            while True:
                room = self.limit - self.produced
                ask = min(_PIECE, room + 1)
                if isinstance(d, lzma.LZMADecompressor):
                    if d.eof:
                        break
                    out = d.decompress(pending, max_length=ask)
                    pending = b""
                    more = not d.needs_input and not d.eof
                else:
                    out = d.decompress(pending, ask)  # type: ignore[attr-defined]
                    pending = d.unconsumed_tail  # type: ignore[attr-defined]
                    more = bool(pending) or (len(out) == ask and not d.eof)  # type: ignore[attr-defined]
                self.produced += len(out)
                if self.produced > self.limit:
                    raise self._too_big()
                if out:
                    pieces.append(out)
                if not more:
                    break
        except _ERRORS as exc:
            raise ExportError(f"{self.where}: {self.what} does not decompress ({exc})") from None
        guard = _GUARD.get()
        if guard is not None:
            guard.expanded(sum(len(p) for p in pieces), self.what)
        return b"".join(pieces)

    @property
    def finished(self) -> bool:
        """Whether the compressed stream has ended."""
        return bool(getattr(self.decompressor, "eof", False))

    def close(self, exact: bool = True) -> None:
        """Check the stream ended (and, with ``exact``, gave exactly the declared size)."""
        if not self.finished:
            raise ExportError(
                f"{self.where}: {self.what} is cut off (its compressed data ends early)"
            )
        if exact and self.produced != self.limit:
            raise ExportError(
                f"{self.where}: {self.what} decompresses to {self.produced:,} bytes, not the "
                f"{self.limit:,} declared"
            )


def inflate(data: bytes | memoryview, method: str, size: int, what: str, where: str) -> bytes:
    """``data`` decompressed, which must give exactly ``size`` bytes (never more are made).

    Examples
    --------
    >>> import lzma
    >>> inflate(lzma.compress(b"abc"), "lzma", 3, "a block", "m.vtu")
    b'abc'
    >>> inflate(lzma.compress(b"abc" * 1000), "lzma", 3, "a block", "m.vtu")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: m.vtu: a block decompresses to more than the 3 bytes declared
    """
    inflater = Inflater(method, size, what, where)
    out = inflater.feed(data)
    inflater.close()
    return out


# ------------------------------------------------------------------------------------ XML
def parse_xml(data: bytes, where: str, *, error: type[BlockMeshError] = ExportError):
    """The root element of the XML document ``data``, parsed by expat (linear time).

    Entity declarations (internal or external) and external references are refused: a file
    blockmesh reads never needs them, and they are how an XML file expands to gigabytes or reads
    other files.

    Examples
    --------
    >>> parse_xml(b'<a x="1"><b/></a>', "f.xdmf").find("b").tag
    'b'
    >>> parse_xml(b'<!DOCTYPE a [<!ENTITY e "x">]><a>&e;</a>', "f.xdmf")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: cannot read f.xdmf as XML: it declares the entity 'e'; ...
    """
    import xml.etree.ElementTree as ET
    from xml.parsers import expat

    class _RefusedError(Exception):
        pass

    def entity(name: str, *_rest: object) -> None:
        raise _RefusedError(f"it declares the entity {name!r}")

    def external(*_rest: object) -> int:
        raise _RefusedError("it refers to an external entity")

    builder = ET.TreeBuilder()
    parser = expat.ParserCreate()
    parser.buffer_text = True
    parser.StartElementHandler = builder.start
    parser.EndElementHandler = builder.end
    parser.CharacterDataHandler = builder.data
    parser.EntityDeclHandler = entity
    parser.UnparsedEntityDeclHandler = entity
    parser.ExternalEntityRefHandler = external
    try:
        parser.Parse(bytes(data), True)
        return builder.close()
    except _RefusedError as exc:
        raise error(
            f"cannot read {where} as XML: {exc}; blockmesh reads XML without entities"
        ) from None
    except (expat.ExpatError, AssertionError) as exc:
        raise error(f"cannot read {where} as XML: {exc}") from None
    except (LookupError, ValueError) as exc:  # an encoding Python does not know, or multi-byte
        raise error(f"cannot read {where} as XML: its declared encoding fails ({exc})") from None
    except RecursionError:
        raise error(f"cannot read {where} as XML: it nests too deeply") from None


# ------------------------------------------------------------------------------ references
def confined(folder: Path, reference: str, where: str, what: str = "data file") -> Path:
    """The regular file ``reference`` names inside ``folder`` (the folder of ``where``).

    ``reference`` must be a relative path that stays in ``folder`` once symbolic links are
    followed, and name a regular file. Every failure is the same :class:`ExportError`, which does
    not tell whether a file of that name exists elsewhere.

    Examples
    --------
    >>> confined(Path("/tmp"), "/etc/passwd", "/tmp/m.xdmf")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: /tmp/m.xdmf refers to the data file '/etc/passwd', which is ...
    """
    shown = reference if len(reference) <= 200 else reference[:197] + "..."
    refused = ExportError(
        f"{where} refers to the {what} {shown!r}, which is not a regular file in the folder of "
        f"{Path(where).name} (a {what} must sit beside the file that names it: copy them "
        "together, or write the mesh again)"
    )
    if not reference or "\0" in reference or os.path.isabs(reference):
        raise refused
    try:
        base = folder.resolve()
        target = (base / reference).resolve()
    except (OSError, RuntimeError, ValueError):
        raise refused from None
    if not target.is_relative_to(base) or target == base:
        raise refused
    try:
        info = os.stat(target)
    except (OSError, ValueError):
        raise refused from None
    if not stat.S_ISREG(info.st_mode):
        raise refused
    return target
