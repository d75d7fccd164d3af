"""Populating output memory ahead of the writers: correct data, no thread left behind."""

from __future__ import annotations

import sys
import threading

import numpy as np
import pytest

from blockmesh._system.prefault import Prefault, populate


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="MADV_POPULATE_WRITE is Linux")
def test_populate_makes_pages_resident_without_changing_them():
    array = np.empty(1 << 22, dtype=np.uint8)
    array[:] = 7
    assert populate(array)
    assert populate(array, 4096 * 3 + 5, 4096 * 9)  # a range not on page boundaries
    assert np.all(array == 7)


def test_populate_refuses_what_it_cannot_do():
    assert populate(np.empty((64, 64))[:, ::2]) is False  # not contiguous: nothing done


def test_prefault_thread_never_outlives_its_block():
    arrays = [np.empty(3 << 20), np.empty((1 << 20, 5), dtype=np.int64)]
    with Prefault(arrays):
        for array in arrays:
            array[...] = 1
    assert not [t for t in threading.enumerate() if t.name == "blockmesh-prefault"]
    assert all(np.all(array == 1) for array in arrays)


def test_an_error_inside_stops_the_thread():
    with pytest.raises(RuntimeError), Prefault([np.empty(64 << 20, dtype=np.uint8)]):
        raise RuntimeError("stop")
    assert not [t for t in threading.enumerate() if t.name == "blockmesh-prefault"]
