"""ASCII numbers (blockmesh.io.text): exact formatting, parsing, and the chunked reader."""

from __future__ import annotations

import io

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh.io.text as text
from blockmesh.errors import ExportError


@settings(max_examples=examples(60))
@given(st.lists(st.integers(-(2**62), 2**62), min_size=1, max_size=40))
def test_int_bytes_matches_str(values: list[int]) -> None:
    rows = text.int_bytes(np.array(values, dtype=np.int64))
    assert [bytes(r[r != 0]).decode() for r in rows] == [str(v) for v in values]


@settings(max_examples=examples(60))
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=40))
def test_float_bytes_round_trips_exactly(values: list[float]) -> None:
    x = np.array(values, dtype=np.float64)
    texts = [bytes(r[r != 0]).decode() for r in text.float_bytes(x)]
    back = np.array([float(t) for t in texts])
    np.testing.assert_array_equal(back.view(np.int64), (x + 0.0).view(np.int64))
    assert all(len(t) <= 24 and " " not in t for t in texts)


def test_write_rows_layout() -> None:
    buf = io.BytesIO()
    text.write_rows(buf, [b"4(", np.array([[1, 22, 333, 0]]), b") ", np.array([0.5]), b"\n"])
    assert buf.getvalue() == b"4(1 22 333 0) 5e-1\n"


@settings(max_examples=examples(40))
@given(
    st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=60),
    st.integers(1, 64),
)
def test_written_rows_parse_back_in_any_chunking(values: list[float], chunk: int) -> None:
    """write_rows then TextReader.table, with chunks as small as one byte: the same numbers."""
    x = np.array(values).reshape(-1, 1)
    buf = io.BytesIO()
    text.write_rows(buf, [np.arange(x.shape[0]), b" ", x[:, 0], b"\n"])
    buf.write(b"end\n")
    r = text.TextReader(io.BytesIO(buf.getvalue()), "f", chunk=chunk)
    table = r.table(x.shape[0], 2, np.float64)
    np.testing.assert_array_equal(table[:, 1], x[:, 0])
    np.testing.assert_array_equal(table[:, 0], np.arange(x.shape[0]))
    assert r.line() == b"end" and r.at_end


def test_table_errors_name_the_lines() -> None:
    r = text.TextReader(io.BytesIO(b"head\n1 2\n3\n"), "f.txt")
    assert r.line() == b"head"
    with pytest.raises(ExportError, match=r"f.txt, lines 2..3: expected 2 numbers on each line"):
        r.table(2, 2, np.int64)
    r = text.TextReader(io.BytesIO(b"1 2\n"), "f.txt")
    with pytest.raises(ExportError, match="the file ends at line 1, inside a table of 3 lines"):
        r.table(3, 2, np.int64)
    with pytest.raises(ExportError, match="f.txt: malformed numbers"):
        text.parse_numbers(b"1 x 2", np.int64, "f.txt")


def test_skip_and_blanks() -> None:
    r = text.TextReader(io.BytesIO(b"3\n(\n4(0 1 2 3)\n4(1 2 3 4)\n4(5 6 7 8)\n)\n"), "faces")
    assert r.line() == b"3" and r.line() == b"("
    r.skip(1)
    np.testing.assert_array_equal(
        r.table(2, 5, np.int64, blank=b"()")[:, 1:], [[1, 2, 3, 4], [5, 6, 7, 8]]
    )
    assert r.line() == b")"
