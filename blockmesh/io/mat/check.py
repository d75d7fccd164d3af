"""A structural check of MATLAB v5 files, before :func:`scipy.io.loadmat` reads them.

scipy's reader trusts the sizes a file states: a damaged ``.mat`` file can crash the interpreter
(a segmentation fault in its compiled reader) rather than raise. :func:`check_mat` walks the
data elements (tags, array flags, dimensions, names, and the sizes of the data, which are
skipped, not read) and raises :class:`~blockmesh.errors.ExportError` at the first one that does
not fit: a size beyond its parent, a data size that disagrees with the dimensions, a cell or
struct with a wrong number of elements. O(number of data elements); compressed variables are
decompressed (one at a time) to be walked, never past the size they announce, which must be
within what the file may expand to (:mod:`blockmesh._system.bounded`).

Examples
--------
>>> import io, tempfile, pathlib
>>> import numpy as np
>>> import scipy.io
>>> path = pathlib.Path(tempfile.mkdtemp()) / "a.mat"
>>> scipy.io.savemat(path, {"Node": np.zeros((3, 2)), "Names": np.array(["a", "bc"], dtype=object)})
>>> check_mat(path)
>>> data = bytearray(path.read_bytes())
>>> data[-30] ^= 0x40  # damage the last variable
>>> _ = path.write_bytes(bytes(data))
>>> check_mat(path)
Traceback (most recent call last):
...
blockmesh.errors.ExportError: ...a.mat is damaged: ...
"""

from __future__ import annotations

import io
import zlib
from pathlib import Path
from typing import BinaryIO

import numpy as np

from blockmesh._system.bounded import current_guard, open_regular
from blockmesh.errors import ExportError

__all__ = ["check_mat"]

_INT8, _INT32, _UINT32, _MATRIX, _COMPRESSED, _UTF8 = 1, 5, 6, 14, 15, 16
#: Bytes per value of the numeric data types.
_ITEM = {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 9: 8, 12: 8, 13: 8, 16: 1, 17: 2, 18: 4}
_CELL, _STRUCT, _CHAR = 1, 2, 4
_NUMERIC = {4, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}
_COMPLEX = 0x0800
_LARGEST = 1 << 40


class _DamageError(Exception):
    """What is wrong, for the ExportError."""


def _tag(f: BinaryIO, end: int) -> tuple[int, int, bytes | None]:
    """The type and size of the next data element; its bytes if small (packed in the tag)."""
    raw = f.read(8)
    if len(raw) < 8:
        raise _DamageError(f"a data element is cut off at byte {f.tell()}")
    first, second = (int(v) for v in np.frombuffer(raw, dtype="<u4"))
    if first >> 16:  # small data element: size, type and up to 4 bytes in the tag
        size, kind = first >> 16, first & 0xFFFF
        if size > 4:
            raise _DamageError(f"a small data element of {size} bytes at byte {f.tell() - 8}")
        return kind, size, raw[4 : 4 + size]
    if f.tell() + second > end:
        raise _DamageError(f"the data element at byte {f.tell() - 8} is larger than its container")
    return first, second, None


def _skip(f: BinaryIO, size: int, small: bytes | None) -> None:
    if small is None:
        f.seek(size + (-size % 8), 1)


def _data(f: BinaryIO, kind: int, want: int, end: int, what: str) -> bytes:
    """The bytes of the next element, which must be of type ``kind`` (read, small sizes only)."""
    got, size, small = _tag(f, end)
    if got != kind:
        raise _DamageError(f"{what}: a data element of type {got} where type {kind} belongs")
    if small is not None:
        return small
    if size > want:
        raise _DamageError(f"{what} of {size} bytes")
    raw = f.read(size)
    f.seek(-size % 8, 1)
    return raw


def _matrix(f: BinaryIO, end: int, skip: frozenset[bytes]) -> bytes:
    """Walk the miMATRIX element ending at ``end``; returns its name."""
    if f.tell() == end:
        return b""  # an empty matrix
    flags = np.frombuffer(_data(f, _UINT32, 8, end, "array flags"), dtype="<u4")
    if flags.size < 2:
        raise _DamageError("array flags of fewer than 8 bytes")
    cls, complex_ = int(flags[0]) & 0xFF, bool(int(flags[0]) & _COMPLEX)
    dims = np.frombuffer(_data(f, _INT32, 4 * 32, end, "dimensions"), dtype="<i4")
    if dims.size < 2 or np.any(dims < 0) or np.prod(dims.astype(float)) > _LARGEST:
        raise _DamageError(f"dimensions {dims.tolist()}")
    count = int(np.prod(dims.astype(np.int64)))
    name = _data(f, _INT8, 64, end, "a variable name")
    if name in skip:
        f.seek(end)
        return name
    if cls == _CELL:
        for _ in range(count):
            _sub_matrix(f, end, skip)
    elif cls == _STRUCT:
        length = np.frombuffer(_data(f, _INT32, 4, end, "field name length"), dtype="<i4")
        names = _data(f, _INT8, 1 << 20, end, "field names")
        width = int(length[0]) if length.size else 0
        if width <= 0 or len(names) % width:
            raise _DamageError(f"struct field names of {len(names)} bytes in fields of {width}")
        for _ in range(count * (len(names) // width)):
            _sub_matrix(f, end, skip)
    elif cls in _NUMERIC:
        for _ in range(2 if complex_ else 1):
            kind, size, small = _tag(f, end)
            if kind not in _ITEM:
                raise _DamageError(f"data of unknown type {kind}")
            if not (cls == _CHAR and kind == _UTF8) and size != count * _ITEM[kind]:
                raise _DamageError(f"{size} bytes of data for {count} values of {_ITEM[kind]}")
            _skip(f, size, small)
    else:
        raise _DamageError(
            f"an array of class {cls} (blockmesh reads numbers, text, cells, structs)"
        )
    if f.tell() > end + 7:
        raise _DamageError("an array runs past its end")
    f.seek(end)
    return name


def _sub_matrix(f: BinaryIO, end: int, skip: frozenset[bytes]) -> None:
    kind, size, small = _tag(f, end)
    if kind != _MATRIX or small is not None:
        raise _DamageError(f"a data element of type {kind} where an array belongs")
    stop = f.tell() + size
    _matrix(f, stop, skip)
    f.seek(stop + (-size % 8))


def _compressed(f: BinaryIO, size: int, skip: frozenset[bytes]) -> None:
    """Walk a compressed variable: its header first, the rest only if it is not skipped."""
    unpack = zlib.decompressobj()
    packed = f.read(size)
    try:
        head = unpack.decompress(packed, 256)
        inner = io.BytesIO(head)
        kind, length, _ = _tag(inner, 8 + len(head) + (1 << 62))
        if kind != _MATRIX:
            raise _DamageError(f"a compressed element of type {kind}")
        inner.seek(8)
        try:  # the name, from the header alone
            _data(inner, _UINT32, 8, len(head), "array flags")
            _data(inner, _INT32, 128, len(head), "dimensions")
            if _data(inner, _INT8, 64, len(head), "a variable name") in skip:
                return
        except _DamageError:
            pass  # the header did not fit in the first bytes: walk it whole below
        announced = 8 + length
        guard = current_guard()
        if announced > guard.expansion_allowed - guard.expanded_bytes:
            raise _DamageError(
                f"a compressed variable announces {announced:,} bytes, more than the file may "
                f"expand to ({guard.expansion_allowed:,} bytes: a decompression bomb?)"
            )
        rest = unpack.decompress(unpack.unconsumed_tail, max(announced - len(head), 1))
        body = head + rest
        guard.expanded(len(body), "a compressed variable")
    except zlib.error as exc:
        raise _DamageError(f"a compressed variable does not decompress ({exc})") from None
    whole = io.BytesIO(body)
    whole.seek(8)
    if 8 + length > len(body):
        raise _DamageError("a compressed variable is shorter than it says")
    _matrix(whole, 8 + length, skip)


def check_mat(path: Path, *, skip: tuple[str, ...] = ()) -> None:
    """Raise :class:`ExportError` if the MAT v5 file ``path`` is damaged (see the module notes).

    Variables named in ``skip`` are not walked past their names (they are checked elsewhere).
    """
    where = str(path)
    names = frozenset(n.encode() for n in skip)
    try:
        with open_regular(path) as f:
            f.seek(0, 2)
            size = f.tell()
            f.seek(128)
            while f.tell() < size:
                kind, length, small = _tag(f, size)
                start = f.tell()
                if kind == _MATRIX and small is None:
                    _matrix(f, start + length, names)
                elif kind == _COMPRESSED and small is None:
                    _compressed(f, length, names)
                else:
                    raise _DamageError(f"a top-level data element of type {kind}")
                f.seek(start + length + (-length % 8 if kind == _MATRIX else 0))
    except _DamageError as damage:
        raise ExportError(f"{where} is damaged: {damage}") from None
    except OSError as exc:
        raise ExportError(f"cannot read {where}: {exc}") from None
