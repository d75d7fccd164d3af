r"""Numbers as ASCII text, fast and exact both ways (for the text formats: Gmsh, OpenFOAM).

Writing: :func:`write_rows` prints tables of numbers; reading: :func:`parse_numbers` parses them.

Python's ``repr`` costs about 0.6 µs a number, which makes a 1.7 M cell OpenFOAM mesh take many
seconds to write. Here numbers become fixed-width ``uint8`` digit matrices with whole-array
operations; padding bytes are NUL and are squeezed out when a chunk of rows is written.

Floats are written with 17 significant digits, correctly rounded (so they read back bit for bit):
``x * 10**k`` is formed exactly as a double-double (Dekker's two-product, ``10**k`` being exact for
``k <= 22``) and rounded to a 17-digit integer. Values outside ``[1e-5, 1e15)`` in magnitude (rare
in meshes) fall back to ``repr``.

Examples
--------
>>> import io
>>> buf = io.BytesIO()
>>> write_rows(buf, [np.array([1, 20]), b" ", np.array([0.5, -1 / 3]), b"\\n"])
>>> buf.getvalue()
b'1 5e-1\\n20 -3.3333333333333331e-1\\n'
"""

from __future__ import annotations

import contextlib
import io
import os
import warnings
from collections.abc import Sequence
from typing import BinaryIO, Protocol

import numpy as np

from blockmesh._system.bounded import current_guard
from blockmesh.errors import ExportError
from blockmesh.numerics.doubledouble import two_prod

__all__ = ["ChunkedBytes", "TextReader", "float_bytes", "int_bytes", "parse_numbers", "write_rows"]

#: Width of a formatted float: sign, 17 digits, point, 'e', exponent sign, 3 exponent digits.
FLOAT_WIDTH = 24
_FAST_MIN, _FAST_MAX = 1e-5, 1e15
_POW10 = 10.0 ** np.arange(23)

Part = bytes | np.ndarray


def _word(text: str) -> int:
    """Four bytes (NUL-padded on the left when right-aligned is wanted by the caller) as uint32."""
    return int(np.frombuffer(text.encode().ljust(4, b"\0")[:4], dtype=np.uint32)[0])


def _tables() -> dict[str, np.ndarray]:
    """uint32 words of the 4-character texts of 0..9999.

    Zero-padded, without leading zeros (right-aligned), and without trailing zeros (left-aligned).
    """
    codes = np.arange(10_000)
    full = np.empty((10_000, 4), dtype=np.uint8)
    q = codes.copy()
    for col in range(3, -1, -1):
        full[:, col] = q % 10 + 48
        q //= 10
    n_lead = np.zeros(10_000, dtype=np.int64)
    n_trail = np.zeros(10_000, dtype=np.int64)
    for j in (1, 2, 3):
        n_lead += codes < 10 ** (4 - j)
        n_trail += codes % 10**j == 0
    n_lead[0] = n_trail[0] = 4
    cols = np.arange(4)
    lead = np.where(cols < n_lead[:, None], 0, full).astype(np.uint8)
    trail = np.where(cols >= 4 - n_trail[:, None], 0, full).astype(np.uint8)
    last = lead.copy()
    last[0] = [0, 0, 0, 48]  # a lone zero is written "0"
    words = {
        # index g + 10000 * (all groups before are zero)
        "int": np.concatenate([full, lead]),
        "int_last": np.concatenate([full, last]),
        # index g + 10000 * (all groups after are zero)
        "frac": np.concatenate([full, trail]),
    }
    return {key: np.ascontiguousarray(a).view(np.uint32).ravel() for key, a in words.items()}


_WORDS = _tables()
# float head word: sign, leading digit, point; index = 20 * negative + 10 * has_fraction + digit
_HEAD = np.array(
    [
        _word(("-" if neg else "\0") + str(digit) + ("." if frac else "\0") + "\0")
        for neg in (0, 1)
        for frac in (0, 1)
        for digit in range(10)
    ],
    dtype=np.uint32,
)
# float tail word: the decimal exponent -9..99 as 'e', sign and two digits (NUL for exponent 0)
_EXPONENTS = np.arange(-9, 100)
_TAIL = np.array(
    [_word(f"e{e:d}".rjust(4, "\0") if e else "") for e in _EXPONENTS], dtype=np.uint32
)


def _groups(q: np.ndarray, n_groups: int) -> list[np.ndarray]:
    """Base-10000 digits of non-negative ints, most significant first."""
    out = []
    for _ in range(n_groups):
        q, r = np.divmod(q, 10_000)
        out.append(r)
    return out[::-1]


def int_bytes(values: np.ndarray) -> np.ndarray:
    """Decimal digits of integers as an (n, W) ``uint8`` matrix, right-aligned, NUL-padded.

    Examples
    --------
    >>> [bytes(row[row != 0]) for row in int_bytes(np.array([7, -42, 0]))]
    [b'7', b'-42', b'0']
    """
    v = np.asarray(values, dtype=np.int64).ravel()
    q = np.abs(v)
    top = int(q.max()) if q.size else 0
    n_groups = -(-len(str(top)) // 4)
    if top < 2**31:
        q = q.astype(np.int32)
    negative = bool(np.any(v < 0))
    columns = []
    if negative:
        columns.append(np.where(v < 0, np.uint32(_word("\0\0\0-")), np.uint32(0)))
    for j, g in enumerate(_groups(q, n_groups)):
        # q below 10**(4 * (n_groups - j)): every group before this one is zero
        leading = q < 10 ** (4 * (n_groups - j)) if j else np.ones(q.shape, dtype=bool)
        table = _WORDS["int_last"] if j == n_groups - 1 else _WORDS["int"]
        columns.append(table[g + 10_000 * leading])
    words = np.stack(columns, axis=1)
    return words.view(np.uint8)


def _digits17(x: np.ndarray, k: np.ndarray) -> np.ndarray:
    """``round(|x| * 10**k)`` exactly, as int64 (needs ``|x| * 10**k >= 2**53``)."""
    p, err = two_prod(np.abs(x), _POW10[k])
    return p.astype(np.int64) + np.rint(err).astype(np.int64)


def float_bytes(values: np.ndarray) -> np.ndarray:
    """Floats as an (n, 24) ``uint8`` matrix of exact 17-significant-digit text, NUL-padded.

    Trailing zeros of the mantissa are dropped; the exponent is omitted when it is 0.

    Examples
    --------
    >>> m = float_bytes(np.array([0.0, 1.0, -2.5, 0.1, 1e300]))
    >>> [bytes(r[r != 0]).decode() for r in m]
    ['0', '1', '-2.5', '1.0000000000000001e-1', '1e+300']
    """
    x = np.asarray(values, dtype=np.float64).ravel()
    n = x.size
    out = np.zeros((n, FLOAT_WIDTH), dtype=np.uint8)
    ax = np.abs(x)
    fast = (ax >= _FAST_MIN) & (ax < _FAST_MAX)
    idx = np.flatnonzero(fast)
    xf = x[idx]
    with np.errstate(divide="ignore"):
        e = np.floor(np.log10(np.abs(xf))).astype(np.int64)
    k = np.clip(16 - e, 0, 22)
    d = _digits17(xf, k)
    for _ in range(2):  # log10 may be off by one next to a power of ten
        low, high = d < 10**16, d >= 10**17
        if not (low.any() or high.any()):
            break
        k = np.clip(k + low - high, 0, 22)
        fix = low | high
        d[fix] = _digits17(xf[fix], k[fix])
    ok = (d >= 10**16) & (d < 10**17)
    idx, xf, d, k = idx[ok], xf[ok], d[ok], k[ok]
    fast[:] = False
    fast[idx] = True

    # words: head (sign, leading digit, point), four groups of fraction digits, exponent
    lead, rest = np.divmod(d, 10**16)
    groups = _groups(rest, 4)
    columns = [np.empty(0)] * 6
    later_zero = np.ones(idx.size, dtype=bool)
    for j in range(3, -1, -1):
        g = groups[j]
        columns[1 + j] = _WORDS["frac"][g + 10_000 * later_zero]
        later_zero &= g == 0
    columns[0] = _HEAD[20 * (xf < 0) + 10 * ~later_zero + lead]
    columns[5] = _TAIL[16 - k - _EXPONENTS[0]]
    words = np.stack(columns, axis=1)
    block = words.view(np.uint8)
    out[idx] = block

    zero = x == 0
    out[zero, 0] = ord("0")
    for i in np.flatnonzero(~fast & ~zero):  # rare: outside the fast range, or not finite
        text = repr(float(x[i])).encode()
        out[i, : len(text)] = np.frombuffer(text, dtype=np.uint8)
    return out


def _as_matrix(part: np.ndarray) -> np.ndarray:
    if part.dtype == np.uint8 and part.ndim == 2:
        return part  # already formatted
    if part.ndim == 2:  # columns separated by single spaces
        n, k = part.shape
        cols = _as_matrix(part.ravel())
        width = cols.shape[1]
        out = np.empty((n, k, width + 1), dtype=np.uint8)
        out[:, :, :width] = cols.reshape(n, k, width)
        out[:, :, width] = ord(" ")
        out[:, -1, width] = 0
        return out.reshape(n, k * (width + 1))
    if np.issubdtype(part.dtype, np.integer):
        return int_bytes(part)
    return float_bytes(part)


def write_rows(f: BinaryIO, parts: Sequence[Part], *, chunk: int = 1 << 16) -> None:
    """Write rows made of literal byte strings and numeric columns, chunk by chunk.

    Each part is either ``bytes`` (the same in every row), a 1-D numeric array (one value a row,
    ints or floats), a 2-D numeric array (its columns separated by single spaces), or a ``uint8``
    matrix from :func:`int_bytes`/:func:`float_bytes`. All arrays have the same number of rows.
    O(rows) time, O(chunk) extra memory.
    """
    arrays = [p for p in parts if not isinstance(p, bytes)]
    if not arrays:
        raise ValueError("write_rows needs at least one array part")
    n = arrays[0].shape[0]
    literals = {p: np.frombuffer(p, dtype=np.uint8) for p in parts if isinstance(p, bytes)}
    for start in range(0, n, chunk):
        stop = min(n, start + chunk)
        mats = [
            np.broadcast_to(literals[p], (stop - start, len(p)))
            if isinstance(p, bytes)
            else _as_matrix(p[start:stop])
            for p in parts
        ]
        table = np.concatenate(mats, axis=1)
        f.write(table.tobytes().translate(None, b"\0"))


def parse_numbers(text: bytes, dtype: type, where: str) -> np.ndarray:
    r"""The whitespace-separated numbers of ``text`` as a 1-D array of ``dtype``.

    Integers parse at about 300 MB/s, floats (shortest round-trip or 17-digit text) exactly.
    Raises :class:`ExportError` naming ``where`` when a token is not a number of that type.

    Examples
    --------
    >>> parse_numbers(b"1 -2\n 30", np.int64, "f").tolist()
    [1, -2, 30]
    >>> parse_numbers(b"1 2.5", np.int64, "the $Elements section of m.msh")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: the $Elements section of m.msh: malformed numbers ...
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return np.fromstring(text, dtype=dtype, sep=" ")
        except (DeprecationWarning, ValueError) as exc:
            kind = "integers" if np.issubdtype(dtype, np.integer) else "numbers"
            raise ExportError(f"{where}: malformed numbers (expected {kind}: {exc})") from None


class _Readable(Protocol):
    def read(self, size: int = -1, /) -> bytes: ...


class ChunkedBytes:
    """The bytes of a binary file, read a chunk at a time into a buffer that is parsed in place.

    The base of the chunked readers (:class:`TextReader`, the VTU reader's scanner): they parse
    ``_buf`` from ``_pos`` on and call :meth:`_more` when they need more of the file; ``_read``
    counts the bytes read from it. ``chunk`` is the least that one call reads.
    """

    def __init__(self, file: _Readable, chunk: int) -> None:
        self.file = file
        self.chunk = chunk
        self._buf = b""
        self._pos = 0
        self._read = 0  # bytes read from the file so far

    def _more(self) -> bool:
        """Append the next chunk of the file to the buffer; False at the end of the file.

        The chunk is at least as long as what is buffered, so a long line is read in O(its
        length), not O(length^2).
        """
        data = self.file.read(max(self.chunk, len(self._buf) - self._pos))
        if not data:
            return False
        self._read += len(data)
        self._buf = self._buf[self._pos :] + data
        self._pos = 0
        return True


class TextReader(ChunkedBytes):
    r"""Lines and tables of numbers from a binary file, read in chunks of bounded size.

    For the text formats' readers: a section header is read with :meth:`line`, a block of ``n``
    lines of numbers with :meth:`table`, which parses them chunk by chunk into one array, so the
    file is never held in memory whole. O(bytes read); memory O(chunk + the table).

    Examples
    --------
    >>> import io
    >>> r = TextReader(io.BytesIO(b"$Nodes\n2\n1 0.5\n2 1.5\n$EndNodes\n"), "f", chunk=4)
    >>> r.line(), r.line()
    (b'$Nodes', b'2')
    >>> r.table(2, 2, np.float64).tolist(), r.line()
    ([[1.0, 0.5], [2.0, 1.5]], b'$EndNodes')
    """

    def __init__(
        self, file: _Readable, where: str, *, chunk: int = 1 << 22, size: int | None = None
    ) -> None:
        super().__init__(file, chunk)
        self.where = where
        self.line_number = 0
        # the bytes the stream can give at most: the file's size, or given (for a gzip stream,
        # what it may expand to); None: unknown, no size checks
        self._size: int | None = size
        if size is None and isinstance(file, io.BufferedReader | io.FileIO):
            with contextlib.suppress(OSError, ValueError):
                self._size = os.fstat(file.fileno()).st_size

    @property
    def left(self) -> int | None:
        """Bytes not parsed yet (buffered or not read), or None when the size is unknown."""
        if self._size is None:
            return None
        return self._size - self._read + len(self._buf) - self._pos

    def check_count(self, count: int, what: str, per_item: int = 2) -> int:
        """``count`` if ``count`` items of at least ``per_item`` bytes fit in what is left.

        ExportError naming the line for a negative count or one the file cannot hold (an
        announced count is never looped over or allocated before this).
        """
        left = self.left
        if count < 0 or (left is not None and count * per_item > left):
            room = f"the file has only {left:,} bytes left" if left is not None else "negative"
            raise ExportError(
                f"{self.where}, line {self.line_number}: {count:,} {what} are announced, but "
                f"{room} (damaged?)"
            )
        return count

    @property
    def at_end(self) -> bool:
        """Whether every byte of the file has been read."""
        return self._pos >= len(self._buf) and not self._more()

    def line(self) -> bytes:
        """The next line, without its end; ``b""`` at the end of the file (see :attr:`at_end`)."""
        while True:
            end = self._buf.find(b"\n", self._pos)
            if end >= 0:
                text = self._buf[self._pos : end]
                self._pos = end + 1
                self.line_number += 1
                return text.rstrip(b"\r")
            if not self._more():
                text = self._buf[self._pos :]
                self._pos = len(self._buf)
                if text:
                    self.line_number += 1
                return text

    def rest(self) -> bytes:
        """Everything not read yet (for small files)."""
        while self._more():
            pass
        text, self._pos = self._buf[self._pos :], len(self._buf)
        return text

    def lines_until(self, end: bytes) -> list[bytes]:
        """The lines up to the line ``end`` (which is consumed); ExportError if it never comes."""
        out: list[bytes] = []
        start = self.line_number
        while True:
            text = self.line()
            if text.strip() == end:
                return out
            if not text and self.at_end:
                raise ExportError(
                    f"{self.where}: no {end.decode(errors='replace')} after line {start}"
                )
            out.append(text)

    def _take(self, n_lines: int) -> bytes:
        """Up to ``n_lines`` whole lines from the buffer (at least one unless at the end)."""
        guess = 64
        while True:
            stop = min(len(self._buf), self._pos + guess * n_lines)
            window = np.frombuffer(
                self._buf, dtype=np.uint8, count=stop - self._pos, offset=self._pos
            )
            ends = np.flatnonzero(window == 10)
            if ends.size >= n_lines or stop == len(self._buf):
                if ends.size == 0:
                    if self._more():
                        continue
                    text, self._pos = self._buf[self._pos :], len(self._buf)
                    return text
                k = min(n_lines, ends.size)
                end = self._pos + int(ends[k - 1]) + 1
                text, self._pos = self._buf[self._pos : end], end
                return text
            guess *= 4

    def table(
        self,
        rows: int,
        cols: int,
        dtype: type,
        out_dtype: type | None = None,
        *,
        blank: bytes = b"",
        keep: int | None = None,
    ) -> np.ndarray:
        """The next ``rows`` lines of ``cols`` numbers each, as a ``(rows, cols)`` array.

        Parsed as ``dtype`` and stored as ``out_dtype`` (default ``dtype``), e.g. int64 values
        kept as int32; only the first ``keep`` columns are stored if given (``(x, y)`` of
        ``x y z``); the characters in ``blank`` are read as spaces (``b"()"`` for OpenFOAM's
        ``(x y z)`` and ``4(a b c d)``). Raises :class:`ExportError` naming the lines when they do
        not hold ``cols`` numbers each.
        """
        return self._table(rows, cols, dtype, out_dtype, blank, keep, tagged=False)[1]

    def tagged_table(
        self, rows: int, cols: int, dtype: type, out_dtype: type | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        r""":meth:`table`, its first column (tags) apart: ``(rows,)`` and ``(rows, cols - 1)``.

        Both are contiguous: the tags can be dropped without a copy of the rest.

        Examples
        --------
        >>> import io
        >>> r = TextReader(io.BytesIO(b"7 1 2\n8 3 4\n"), "x")
        >>> [a.tolist() for a in r.tagged_table(2, 3, np.int64)]
        [[7, 8], [[1, 2], [3, 4]]]
        """
        tags, table = self._table(rows, cols, dtype, out_dtype, b"", None, tagged=True)
        assert tags is not None
        return tags, table

    def _table(
        self,
        rows: int,
        cols: int,
        dtype: type,
        out_dtype: type | None,
        blank: bytes,
        keep: int | None,
        *,
        tagged: bool,
    ) -> tuple[np.ndarray | None, np.ndarray]:
        spaces = bytes.maketrans(blank, b" " * len(blank)) if blank else None
        width = cols if keep is None else keep
        lead = int(tagged)
        left = self.left
        if rows < 0 or cols < 1 or (left is not None and rows * cols * 2 > left + 1):
            raise ExportError(
                f"{self.where}, line {self.line_number}: a table of {rows} lines of {cols} "
                f"numbers is announced, but the file has only {left} bytes left (damaged?)"
            )

        itemsize = np.dtype(out_dtype or dtype).itemsize
        current_guard(self.where).allocate(rows * width * itemsize, f"a table of {rows:,} lines")
        try:
            out: np.ndarray = np.empty((rows, width - lead), dtype=out_dtype or dtype)
            lead_column = np.empty(rows, dtype=out.dtype) if tagged else None
        except (MemoryError, ValueError):
            raise ExportError(
                f"{self.where}, line {self.line_number}: a table of {rows} lines is too large"
            ) from None
        done = 0
        first = self.line_number + 1
        while done < rows:
            text = self._take(rows - done)
            if not text:
                raise ExportError(
                    f"{self.where}: the file ends at line {self.line_number}, inside a table of "
                    f"{rows} lines that starts at line {first}"
                )
            parsed = text.translate(spaces) if spaces else text
            values = parse_numbers(
                parsed, dtype, f"{self.where}, lines {first}..{first + rows - 1}"
            )
            k = text.count(b"\n") + (not text.endswith(b"\n"))
            if values.size != k * cols:
                raise ExportError(
                    f"{self.where}, lines {self.line_number + 1}..{self.line_number + k}: "
                    f"expected {cols} numbers on each line, found {values.size} on {k} lines"
                )
            if values.dtype != out.dtype and values.size and out.dtype.kind in "iu":
                limits = np.iinfo(out.dtype)
                if values.min() < limits.min or values.max() > limits.max:
                    raise ExportError(
                        f"{self.where}, lines {self.line_number + 1}..{self.line_number + k}: "
                        f"numbers beyond {out.dtype} ({values.min()}..{values.max()})"
                    )
            table = values.reshape(k, cols)
            out[done : done + k] = table[:, lead:width]
            if lead_column is not None:
                lead_column[done : done + k] = table[:, 0]
            done += k
            self.line_number += k
            if self._pos >= len(self._buf):
                self._more()
        return lead_column, out

    def skip(self, n_lines: int) -> None:
        """Skip the next ``n_lines`` lines without parsing them."""
        self.check_count(n_lines, "lines to skip", 1)
        left = n_lines
        while left:
            text = self._take(left)
            if not text:
                raise ExportError(f"{self.where}: the file ends at line {self.line_number}")
            k = text.count(b"\n")
            left -= k
            self.line_number += k
            if self._pos >= len(self._buf):
                self._more()
