"""NumPy .npz: every array of the Mesh, lossless (dtypes and boundary order included)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers_io import assert_same, tagged

import blockmesh.io as bio
from blockmesh.errors import ExportError
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


@pytest.mark.parametrize("compression", [None, "zlib"])
def test_npz_is_lossless(mesh: Mesh, tmp_path: Path, compression: str | None) -> None:
    path = bio.write(mesh, tmp_path / "m.npz", compression=compression)
    with np.load(path, allow_pickle=False) as data:
        for key in ("points", "cells", "block_id", "parent", "boundary_edges", "region"):
            np.testing.assert_array_equal(data[key], getattr(mesh, key))
            assert data[key].dtype == getattr(mesh, key).dtype
        assert tuple(data["patch_names"].tolist()) == mesh.patch_names
    back = bio.read(path)
    assert_same(back, mesh)
    np.testing.assert_array_equal(back.boundary_edges, mesh.boundary_edges)
    assert (back.level, back.name) == (mesh.level, mesh.name)


def test_npz_of_something_else(tmp_path: Path) -> None:
    np.savez(tmp_path / "x.npz", a=np.arange(3))
    with pytest.raises(ExportError, match="not a blockmesh .npz: it lacks points"):
        bio.read(tmp_path / "x.npz")
