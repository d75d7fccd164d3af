"""Pictures of big meshes: cell density with block outlines instead of every polygon."""

from __future__ import annotations

import numpy as np
import pytest

import blockmesh.plot as plot
from blockmesh.geometry.topology import cell_neighbours, edge_keys


@pytest.mark.parametrize("name", ["joined-8", "l-shape", "ring", "triangle", "square-cut"])
def test_block_interfaces_are_the_edges_between_blocks(catalogue, name):
    mesh = catalogue[name].mesh(3)
    neighbour = cell_neighbours(mesh.cells, mesh.n_points)
    cell, edge = np.nonzero(neighbour >= 0)
    across = neighbour[cell, edge] // 5
    differ = mesh.block_id[cell] != mesh.block_id[across]
    start = mesh.cells[cell[differ], edge[differ]]
    stop = mesh.cells[cell[differ], (edge[differ] + 1) % 5]
    expected = set(edge_keys(start, stop, mesh.n_points).tolist())
    found = plot._block_interfaces(mesh)
    assert set(edge_keys(found[:, 0], found[:, 1], mesh.n_points).tolist()) == expected


def test_density_counts_every_cell_and_its_area(catalogue):
    mesh = catalogue["l-shape"].mesh(3)
    extent = mesh.points.max(axis=0) - mesh.points.min(axis=0)
    pixel = float(extent.max()) / 7
    shape = np.ceil(extent / pixel).astype(np.int64)
    density = plot._density_picture(mesh, pixel, shape)
    assert density.shape == (shape[1], shape[0])
    # Every unmasked pixel holds cells, and the densities are those of the cells' sizes.
    areas = mesh.cell_areas()
    assert density.min() >= 1 / areas.max() * (1 - 1e-12)
    assert density.max() <= 1 / areas.min() * (1 + 1e-12)


def test_big_mesh_is_drawn_as_a_density_picture(catalogue, tmp_path, monkeypatch):
    monkeypatch.setattr(plot, "DRAW_LIMIT", 1000)
    drawn = []
    real = plot._density_figure
    monkeypatch.setattr(plot, "_density_figure", lambda mesh: drawn.append(mesh) or real(mesh))
    small = catalogue["joined-8"].mesh(1)
    plot.plot_mesh(small, tmp_path / "small.png")
    assert drawn == [] and (tmp_path / "small.png").stat().st_size > 0
    big = catalogue["joined-8"].mesh(3)
    plot.plot_mesh(big, tmp_path / "big.png")
    assert drawn == [big] and (tmp_path / "big.png").stat().st_size > 0


def test_density_picture_is_written(catalogue, tmp_path, monkeypatch):
    monkeypatch.setattr(plot, "DRAW_LIMIT", 1000)
    path = plot.plot_mesh(catalogue["ring"].mesh(3), tmp_path / "ring.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    quality = plot.plot_quality(catalogue["ring"].mesh(3), tmp_path / "quality.png", chunk=100)
    assert quality.stat().st_size > 0
