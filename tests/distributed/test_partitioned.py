"""Partitioned refinement on a local Dask cluster: equal to the serial mesh, readable everywhere."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import blockmesh
from blockmesh import ResourceError
from blockmesh.distributed.files import pieces_dir
from blockmesh.distributed.partition import partition
from blockmesh.distributed.pieces import build_piece, piece_nodes

distributed = pytest.importorskip(
    "dask.distributed",
    reason="dask[distributed] is not installed (pip install 'blockmesh[distributed]')",
)
import blockmesh.distributed as bd  # noqa: E402

FIELDS = ("points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch", "region")


@pytest.fixture(scope="module")
def client():
    with bd.dask_client(workers=2) as c:
        yield c


def _same(a: blockmesh.Mesh, b: blockmesh.Mesh) -> None:
    for field in FIELDS:
        assert np.array_equal(getattr(a, field), getattr(b, field)), field
    assert a.patch_names == b.patch_names and a.region_names == b.region_names
    assert a.level == b.level and a.name == b.name


@pytest.mark.parametrize(
    ("name", "level", "partitions", "suffix"),
    [
        ("sp", 2, 3, ".pvtu"),
        ("joined-8", 3, 3, ".xdmf"),
        ("l-shape", 4, 5, ".pvtu"),
        ("ring", 2, 6, ".xdmf"),
        ("triangle", 3, 2, ".pvtu"),
        ("dodecagon", 5, 2, ".xdmf"),
    ],
)
def test_gathered_pieces_equal_the_serial_mesh(
    client, catalogue, tmp_path, name, level, partitions, suffix
):
    domain = catalogue[name]
    index = tmp_path / f"{name}{suffix}"
    made = bd.refine_to(domain, level, index, partitions=partitions, client=client)
    serial = blockmesh.refine(domain, level)
    _same(bd.gather(index), serial)
    assert (made.cells, made.nodes) == (serial.n_cells, serial.n_points)
    assert made.boundary_edges == serial.boundary_edges.shape[0]
    assert made.quality == serial.quality()
    assert made.bandwidth == serial.bandwidth()
    assert made.area == pytest.approx(serial.area, rel=1e-14)
    assert len(made.pieces) == partitions and all(p.exists() for p in made.pieces)
    # Every node is owned by exactly one piece; the owned coordinates add up to the serial ones.
    owned = sum(s["owned_nodes"] for s in made.summaries)
    assert owned == serial.n_points
    total = np.sum([s["owned_sum"] for s in made.summaries], axis=0)
    assert total == pytest.approx(serial.points.sum(axis=0), rel=1e-12, abs=1e-9)


def test_pieces_own_every_node_once(catalogue):
    domain = catalogue["l-shape"]
    parts = partition(domain, 3, 4)
    serial = blockmesh.refine(domain, 3)
    owners = np.zeros(serial.n_points, dtype=int)
    for p in range(parts.n_partitions):
        piece = build_piece(parts, p)
        ids, ghost = piece_nodes(parts, p)
        assert np.array_equal(ids, piece.global_node_ids) and np.all(np.diff(ids) > 0)
        assert np.array_equal(piece.mesh.points, serial.points[ids])  # bit for bit per global id
        first = piece.first_cell
        assert np.array_equal(ids[piece.mesh.cells], serial.cells[first : first + parts.cells(p)])
        owners[ids[~ghost]] += 1
    assert np.all(owners == 1)


def test_partitions_are_balanced_groups_of_whole_units(catalogue):
    parts = partition(catalogue["joined-8"], 4, 3)
    sizes = [parts.cells(p) for p in range(3)]
    assert sum(sizes) == 8 * 6**4 and max(sizes) <= 1.25 * min(sizes)
    assert parts.split_level == 1  # 8 blocks do not split well in 3; their 48 children do
    with pytest.raises(blockmesh.ArgumentError, match="at most 6 at level 2"):
        partition(catalogue["sp"], 2, 7)


def test_pieces_read_back_with_meshio_h5py_and_vtk(client, catalogue, tmp_path):
    meshio = pytest.importorskip("meshio")
    h5py = pytest.importorskip("h5py")
    domain = catalogue["joined-8"]
    serial = blockmesh.refine(domain, 2)
    vtu = bd.refine_to(domain, 2, tmp_path / "j8.pvtu", partitions=3, client=client)
    xdmf = bd.refine_to(domain, 2, tmp_path / "j8.xdmf", partitions=3, client=client)
    for path, summary in zip(vtu.pieces, vtu.summaries, strict=True):
        m = meshio.read(path)
        gids = np.asarray(m.point_data["GlobalNodeIds"])
        assert np.array_equal(m.points[:, :2], serial.points[gids])
        polygons = next(c.data for c in m.cells if c.type == "polygon")
        assert len(polygons) == summary["cells"]
        assert np.array_equal(
            gids[polygons], serial.cells[summary["first_cell"] :][: len(polygons)]
        )
        ghosts = np.asarray(m.point_data["vtkGhostType"])
        assert int((ghosts == 0).sum()) == summary["owned_nodes"]
    for path in xdmf.pieces:
        with h5py.File(path, "r") as f:
            gids = f["mesh/global_node_ids"][()]
            assert np.array_equal(f["mesh/points"][()], serial.points[gids])
    vtk = pytest.importorskip("vtk", reason="VTK is not installed (its XML reader is optional)")
    reader = vtk.vtkXMLPUnstructuredGridReader()
    reader.SetFileName(str(vtu.path))
    reader.Update()
    grid = reader.GetOutput()
    ghosts = sum(s["nodes"] - s["owned_nodes"] for s in vtu.summaries)
    assert grid.GetNumberOfPoints() == serial.n_points + ghosts
    assert grid.GetNumberOfCells() == serial.n_cells + serial.boundary_edges.shape[0]
    assert grid.GetPointData().GetGlobalIds().GetName() == "GlobalNodeIds"
    assert grid.GetPointGhostArray() is not None


@pytest.mark.parametrize(("function", "rule"), [("x^3*y + 1", "paper"), ("sin(x)*exp(y)", "fan")])
def test_partition_integrals_sum_to_the_serial_value(client, catalogue, function, rule):
    domain = catalogue["ring"]
    serial = blockmesh.integrate(domain, function, order=4, level=3, rule=rule)
    parts = bd.integrate(domain, function, level=3, order=4, rule=rule, partitions=4, client=client)
    assert parts == pytest.approx(serial, rel=1e-13, abs=1e-13)


def test_a_partition_too_big_for_its_worker_is_refused_before_anything_is_written(tmp_path):
    small = distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=False,
        memory_limit="300MB",
        dashboard_address=None,
    )
    with (
        small,
        distributed.Client(small) as client,
        pytest.raises(ResourceError, match=r"partition 0 of 1 needs about .* use at least"),
    ):
        bd.refine_to(
            blockmesh.load_domain("joined-8"), 7, tmp_path / "big.pvtu", partitions=1, client=client
        )
    assert list(tmp_path.iterdir()) == []


def test_existing_output_is_replaced_only_when_complete(client, catalogue, tmp_path):
    index = tmp_path / "m.pvtu"
    bd.refine_to(catalogue["sp"], 2, index, partitions=2, client=client)
    (first,) = pieces_dir(index).iterdir()
    names = sorted(p.name for p in first.iterdir())
    bd.refine_to(catalogue["sp"], 3, index, partitions=3, client=client)
    (second,) = pieces_dir(index).iterdir()  # the first write's folder is gone
    assert second != first
    assert sorted(p.name for p in second.iterdir()) == [*names, "m_0002.vtu"]
    assert bd.gather(index).level == 3
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.pvtu", "m.pvtu.pieces"]


def test_bad_index_names_and_missing_dask(tmp_path, monkeypatch):
    with pytest.raises(blockmesh.ExportError, match=r"must be a \.pvtu .* or an \.xdmf"):
        bd.refine_to(blockmesh.load_domain("sp"), 2, tmp_path / "m.vtu", partitions=2)
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    with pytest.raises(ResourceError, match=r"pip install 'blockmesh\[distributed\]'"):
        bd.refine_to(blockmesh.load_domain("sp"), 2, tmp_path / "m.pvtu", partitions=2)


@pytest.mark.parametrize(
    ("name", "level", "partitions", "suffix"),
    [("annulus", 3, 2, ".pvtu"), ("disc", 3, 40, ".xdmf"), ("cylinder-channel", 2, 5, ".pvtu")],
)
def test_curved_domains_partition_onto_their_curves(
    client, tmp_path, name, level, partitions, suffix
):
    """Pieces place curved units by the curve-aware rule: the serial mesh, bit for bit."""
    domain = blockmesh.load_domain(name)
    index = tmp_path / f"{name}{suffix}"
    bd.refine_to(domain, level, index, partitions=partitions, client=client)
    serial = blockmesh.refine(domain, level)
    _same(bd.gather(index), serial)
    parts = partition(domain, level, partitions)
    pieces = [build_piece(parts, p) for p in range(partitions)]
    assert sum(len(p.mesh.curves) for p in pieces) == len(serial.curves)
    for piece in pieces:
        assert piece.mesh.curves.distances(piece.mesh.points).max(initial=0.0) == 0.0


def test_a_shared_curve_gives_both_pieces_the_same_nodes(client):
    vertices = [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)]
    edges = {(1, 2): blockmesh.curves.Arc(through=(2.4, 0.4))}
    domain = blockmesh.Domain.from_blocks(vertices, [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)], edges=edges)
    parts = partition(domain, 3, 2)
    serial = blockmesh.refine(domain, 3)
    points = np.full_like(serial.points, np.nan)
    for p in range(2):
        piece = build_piece(parts, p)
        points[piece.global_node_ids] = piece.mesh.points
    assert np.array_equal(points, serial.points)


@pytest.mark.parametrize("name", ["plate-hole", "annulus"])
def test_partitioned_exact_geometry_integral_is_the_serial_one(client, name):
    domain = blockmesh.load_domain(name)
    for exact_geometry in (False, True):
        serial = blockmesh.integrate(
            domain, "x^4*y^2 + 1", order=5, level=2, exact_geometry=exact_geometry
        )
        parts = bd.integrate(domain, "x^4*y^2 + 1", order=5, level=2, partitions=3,
                             client=client, exact_geometry=exact_geometry)  # fmt: skip
        assert parts == pytest.approx(serial, rel=1e-14)
    with pytest.raises(blockmesh.errors.ArgumentTypeError, match="exact_geometry must be"):
        bd.integrate(domain, "1", order=1, level=1, client=client, exact_geometry="yes")


def test_distributed_integrate_takes_f_as_blockmesh_integrate_does(client):
    """blockmesh.integrate(target, f=...) but blockmesh.distributed.integrate(target,
    function=...): the same call with f= raised TypeError (issue 22)."""
    domain = blockmesh.load_domain("sp")
    serial = blockmesh.integrate(domain, f="x*x + 1", order=2, level=2)
    value = bd.integrate(domain, f="x*x + 1", order=2, level=2, partitions=2, client=client)
    assert value == pytest.approx(serial, rel=1e-14)
    with pytest.warns(DeprecationWarning, match="f="):
        old = bd.integrate(domain, function="x*x + 1", order=2, level=2, client=client)
    assert old == pytest.approx(serial, rel=1e-14)
    with pytest.raises(blockmesh.ArgumentError, match="got both f and its earlier name function"):
        bd.integrate_with_estimate(domain, "1", function="1", order=2, client=client)
