"""The one-pass cell measures against the plain formulas of blockmesh.geometry."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh import DomainError, Mesh
from blockmesh.geometry import COLLINEAR_SIN_TOL, corner_sines, interior_angles, signed_area
from blockmesh.mesh.measures import CHUNK, measure_cells, signed_areas


def _plain(mesh: Mesh) -> dict[str, float]:
    xy = mesh.points[mesh.cells]
    xy -= xy[:, :1]
    areas = signed_area(xy)
    angles = interior_angles(xy)
    diff = xy[:, :, None, :] - xy[:, None, :, :]
    diam2 = np.max(np.einsum("mijk,mijk->mij", diff, diff), axis=(1, 2))
    sharp = np.all(np.nan_to_num(corner_sines(xy), nan=-1.0) > COLLINEAR_SIN_TOL, axis=1)
    bad = ~(sharp & (areas > 0))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
    return {
        "area": float(np.sum(areas)),
        "abs_area": float(np.sum(np.abs(areas))),
        "min_area": float(areas.min()),
        "max_area": float(areas.max()),
        "min_angle": float(angles.min()),
        "max_angle": float(angles.max()),
        "max_aspect_ratio": float(aspect.max()),
        "not_strictly_convex": int(np.count_nonzero(~sharp)),
        "invalid": int(np.count_nonzero(bad)),
        "first_invalid": int(np.flatnonzero(bad)[0]) if bad.any() else -1,
        "bandwidth": int(np.max(mesh.cells.max(axis=1) - mesh.cells.min(axis=1))),
    }


def _agree(mesh: Mesh, chunk: int) -> None:
    fast, plain = measure_cells(mesh, chunk=chunk), _plain(mesh)
    scale = plain.pop("abs_area")
    assert fast.area == pytest.approx(plain.pop("area"), rel=1e-13, abs=1e-13 * scale)
    for key, expected in plain.items():
        got = getattr(fast, key)
        if isinstance(expected, int):
            assert got == expected, key
        else:
            assert got == pytest.approx(expected, rel=1e-13, abs=1e-300), key


@pytest.mark.parametrize("name", ["sp", "l-shape", "ring", "triangle", "dodecagon"])
@pytest.mark.parametrize("chunk", [7, 4096])
def test_refined_catalogue_meshes(catalogue, name, chunk):
    for level, smooth in ((0, 0), (3, 0), (3, 2)):
        _agree(catalogue[name].mesh(level, smooth=smooth), chunk)


def _trusted(points, cells) -> Mesh:
    n = len(cells)
    return Mesh._trusted(
        points=np.asarray(points, dtype=float),
        cells=np.asarray(cells),
        block_id=np.zeros(n, dtype=np.int64),
        parent=np.full(n, -1),
        boundary_edges=np.zeros((0, 2), dtype=np.int64),
        boundary_patch=np.zeros(0, dtype=np.int64),
        patch_names=("boundary",),
        region=np.zeros(n, dtype=np.int64),
        region_names=("domain",),
    )


@settings(max_examples=examples(60))
@given(
    st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), min_size=5, max_size=40).filter(
        lambda p: len(set(p)) == len(p)
    ),
    st.integers(0, 2**32 - 1),
    st.sampled_from([1, 3, 8]),
)
def test_random_cells_bad_ones_included(points, seed, chunk):
    """Random pentagons over random points: non-convex, clockwise, repeated corners."""
    rng = np.random.default_rng(seed)
    cells = rng.integers(0, len(points), size=(int(rng.integers(1, 20)), 5))
    _agree(_trusted(points, cells), chunk)


def test_straight_and_far_away_cells():
    square = [(0, 0), (1, 0), (2, 0), (2, 1), (0, 1)]  # a straight corner at (1, 0)
    mesh = _trusted(square, [[0, 1, 2, 3, 4]])
    assert measure_cells(mesh).not_strictly_convex == 1
    with pytest.raises(DomainError, match="1 of the 1 cells are not strictly convex"):
        mesh.check_geometry()
    near = blockmesh.refine(blockmesh.load_domain("sp"), 2)
    far = _trusted(near.points + 1e9, near.cells)
    assert far.quality().min_angle == pytest.approx(near.quality().min_angle, rel=1e-6)
    assert far.area == pytest.approx(5.0, rel=1e-9)


def test_quality_area_and_check_share_one_pass(catalogue):
    mesh = catalogue["joined-8"].mesh(2)
    mesh.quality()
    first = mesh._cache["measures"]
    mesh.check_geometry()
    assert mesh._cache["measures"] is first
    assert mesh.area == first.area
    assert mesh.quality(chunk=5) == mesh.quality()


def test_bandwidth_matches_the_plain_formula(catalogue):
    """Its own pass, and read from the cell measures once they are made (the same value)."""
    for name in ("sp", "l-shape", "ring"):
        for mesh in (catalogue[name].mesh(3), catalogue[name].mesh(3).with_rcm_numbering()):
            plain = int(np.max(mesh.cells.max(axis=1) - mesh.cells.min(axis=1)))
            assert mesh.bandwidth() == plain
            mesh.quality()
            assert "measures" in mesh._cache and mesh.bandwidth() == plain


def _same_bits(points, cells) -> None:
    xy = np.asarray(points, dtype=float)[cells]
    expected = signed_area(xy)
    got = signed_areas(np.asarray(points, dtype=float), np.asarray(cells))
    assert got.dtype == np.float64 and got.shape == expected.shape
    assert np.array_equal(got.view(np.int64), expected.view(np.int64))  # every bit, signs of zero


@settings(max_examples=examples(60))
@given(
    st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), min_size=5, max_size=40),
    st.integers(0, 2**32 - 1),
    st.sampled_from([0.0, 1e9, -7.5e5]),
)
def test_signed_areas_are_the_shoelace_formula_bit_for_bit(points, seed, offset):
    """Random pentagons (clockwise, repeated and collinear corners), near and far from 0."""
    rng = np.random.default_rng(seed)
    cells = rng.integers(0, len(points), size=(int(rng.integers(0, 30)), 5))
    _same_bits(np.asarray(points) + offset, cells)


def test_signed_areas_over_chunks_of_catalogue_meshes():
    """Meshes longer than one chunk, curved ones included; Mesh.cell_areas is the same."""
    for name in ("joined-8", "annulus", "lake-island"):
        mesh = blockmesh.load_domain(name).mesh(4)
        assert mesh.n_cells > CHUNK
        _same_bits(mesh.points, mesh.cells)
        assert np.array_equal(mesh.cell_areas(), signed_area(mesh.points[mesh.cells]))


def test_signed_areas_refuse_other_polygons():
    with pytest.raises(
        blockmesh.ArgumentError, match=r"cells of shape \(m, 5\); got shape \(1, 4\)"
    ):
        signed_areas(np.zeros((4, 2)), np.array([[0, 1, 2, 3]]))


def test_a_clockwise_cell_is_named_by_the_check():
    """The first cell without positive area, found beyond the first chunk of the check."""
    mesh = blockmesh.refine(blockmesh.load_domain("sp"), 7)  # 279,936 cells: two chunks
    cells = mesh.cells.copy()
    bad = mesh.n_cells - 3
    cells[bad] = cells[bad, ::-1]
    with pytest.raises(blockmesh.ArgumentError, match=f"cell {bad} .* is clockwise or has no area"):
        Mesh(
            points=mesh.points,
            cells=cells,
            block_id=mesh.block_id,
            parent=mesh.parent,
            boundary_edges=mesh.boundary_edges,
            boundary_patch=mesh.boundary_patch,
            patch_names=mesh.patch_names,
            region=mesh.region,
            region_names=mesh.region_names,
        )
