"""Bounded input: every parser limit of the domain reader gives one located error (issue 14, 4).

Numbers too large, nesting too deep, files too big, special files (FIFOs, devices, directories),
malformed values; and a fuzz test over the reader: only BlockMeshErrors escape.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import threading

import numpy as np
import pytest
from helpers import examples
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import blockmesh
import blockmesh.decompose.polygon as polygon_route
import blockmesh.domain.tomlio as tomlio
from blockmesh import BlockMeshError, Domain, DomainError, DomainFormatError, ResourceError


@pytest.mark.parametrize(
    ("text", "kind", "message"),
    [
        ("polygon = [[1e400, 0], [1, 0], [0, 1]]", DomainError,
         r"vertex 0 \(inf, 0.0\) is not finite"),
        ("polygon = [[0, 0], [1, 0], [0, " + "1" * 4300 + "]]", DomainFormatError,
         "the integer at line 1, column 32 has 4300 digits; numbers in a domain file have at most"),
        ("polygon = [[0, 0], [1, 0], [0, " + "9" * 401 + "]]", DomainFormatError, "has 401 digits"),
        ("polygon = " + "[" * 50_000 + "]" * 50_000, DomainFormatError,
         "arrays or tables nest more than 16 deep at line 1, column 27"),
        ("vertices = [[0,0],[1,0],[1,1],[0,1],[0.5,2]]\nblocks = [[0, [1], 2, 3, 4]]",
         DomainFormatError, r"block 0 has vertex id \[1\], which is not a whole number"),
        ("polygon = [[1e308, 0], [-1e308, 0], [0, 1e308]]", DomainError,
         r"polygon vertex 0 \(1e\+308, 0\) is too far out: coordinates must be at most 1e\+150"),
        ("vertices = [[0,0],[1,0],[1,1],[0,1],[0.5,2]]\nblocks = [[0, 1, 2, 3, 99999999999]]",
         DomainFormatError, "refers to vertex 99999999999, but the vertices are numbered 0..4"),
        ("polygon = [[0, 0], [1, 0], [0, 1]]\n[patches]\na = [{x = 1}]", DomainFormatError,
         r"patch 'a' has \{'x': 1\}"),
        ("polygon = [[0, 0], [1, 0], [0, 1]]\nholes = [[[0.1, 0.1], [0.2, 0.1]]]", DomainError,
         "hole 0 needs at least 3 vertices, got 2"),
        ('description = """a\n' + "[" * 100 + '"""\n# [[[[[[[[[[[[[[[[[[[[[\n'
         'polygon = [[0, 0], [1, 0], [0, 1]]', None, None),
    ],
)  # fmt: skip
def test_limits_and_bad_values_are_located(text, kind, message):
    if kind is None:  # brackets inside a string are not nesting
        assert Domain.from_toml_text(text).n_blocks == 9
        return
    with pytest.raises(kind, match=message):
        Domain.from_toml_text(text)


def _finishes(function, seconds: float = 10.0):
    """Run ``function`` in a thread; its outcome, or a failure if it does not end in time."""
    outcome: dict[str, object] = {}

    def run():
        try:
            outcome["value"] = function()
        except BaseException as error:
            outcome["error"] = error

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(seconds)
    assert not thread.is_alive(), "reading did not end (it would hang the command line)"
    return outcome


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    outcome = _finishes(lambda: blockmesh.load_domain(fifo))
    error = outcome.get("error")
    assert isinstance(error, DomainFormatError)
    assert "pipe.toml: it is a FIFO (named pipe), not a regular file" in str(error)


@pytest.mark.skipif(sys.platform == "win32", reason="no /dev on Windows")
@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom", "/dev/null"])
def test_devices_are_refused(device):
    if not os.path.exists(device):
        pytest.skip(f"{device} does not exist here")
    outcome = _finishes(lambda: blockmesh.load_domain(device))
    error = outcome.get("error")
    assert isinstance(error, DomainFormatError)
    assert f"{device}: it is a character device, not a regular file" in str(error)


def test_directories_and_oversized_and_binary_files(tmp_path, monkeypatch):
    folder = tmp_path / "folder.toml"
    folder.mkdir()
    with pytest.raises(DomainFormatError, match="it is a directory, not a regular file"):
        Domain.from_toml(folder)
    big = tmp_path / "big.toml"
    big.write_text("polygon = [[0, 0], [1, 0], [0, 1]]\n" + "# padding\n" * 100)
    monkeypatch.setattr(tomlio.bounds, "MAX_FILE_BYTES", 256)
    with pytest.raises(DomainFormatError, match="larger than 0 MiB, the most a domain file may be"):
        Domain.from_toml(big)
    monkeypatch.undo()
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"polygon = [[0, 0]]\n\xa7\xff")
    with pytest.raises(DomainFormatError, match=r"not UTF-8 text \(byte 19, line 2\)"):
        Domain.from_toml(binary)


@pytest.mark.slow
def test_the_thousand_corner_polygon_is_decomposed_in_bounded_memory():
    # A 2,000-corner --polygon once tried to allocate 477 GiB (the chord programme); now it
    # takes the triangulation, in time and memory near-linear in the corners (and 1,000 corners
    # is the most accepted: MAX_CORNERS).
    import tracemalloc

    t = 2 * np.pi * np.arange(1000) / 1000
    corners = np.column_stack([np.cos(t), np.sin(t)])
    tracemalloc.start()
    try:
        domain = Domain.from_polygon(corners)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert domain.layout == "triangulation"
    assert peak < 2e9
    assert domain.area == pytest.approx(500 * math.sin(2 * math.pi / 1000), rel=1e-12)


def test_too_many_corners_are_refused_before_any_work(monkeypatch):
    monkeypatch.setattr(polygon_route, "MAX_CORNERS", 100)
    t = 2 * np.pi * np.arange(101) / 101
    with pytest.raises(ResourceError, match="the polygon has 101 corners; at most 100"):
        Domain.from_polygon(np.column_stack([np.cos(t), np.sin(t)]))


# ----------------------------------------------------------------------------- fuzz
_KEYS = [*tomlio.ALLOWED_KEYS, "polygn", "hole", "patch"]
_SCALARS = st.one_of(
    st.integers(-(10**40), 10**40),
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.sampled_from(["hole 0", "hole 1:2", "hole", "0", "x", "inlet", "hole -1", ""]),
    st.booleans(),
)
_VALUES = st.recursive(
    _SCALARS,
    lambda inner: st.one_of(
        st.lists(inner, max_size=6),
        st.dictionaries(st.sampled_from(["a", "b", "inlet", "hole 0"]), inner, max_size=3),
    ),
    max_leaves=24,
)


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return "{" + ", ".join(f'"{k}" = {_toml(v)}' for k, v in value.items()) + "}"


@st.composite
def documents(draw):
    if draw(st.booleans()):
        return draw(st.text(max_size=200))
    keys = draw(st.lists(st.sampled_from(_KEYS), max_size=5, unique=True))
    lines = [f"{key} = {_toml(draw(_VALUES))}" for key in keys]
    if draw(st.booleans()):
        lines.append("[patches]")
        for name in draw(st.lists(st.sampled_from(["inlet", "wall", "bad name"]), max_size=3)):
            lines.append(f'"{name}" = {_toml(draw(_VALUES))}')
    return "\n".join(lines)


@settings(max_examples=examples(300), suppress_health_check=[HealthCheck.too_slow])
@given(documents())
def test_fuzzed_domain_text_raises_only_blockmesh_errors(text):
    with contextlib.suppress(BlockMeshError):
        Domain.from_toml_text(text)
