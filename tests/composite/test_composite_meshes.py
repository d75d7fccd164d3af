"""The composite catalogue domains: tiling, conformity across interfaces, regions, at levels 0-3.

And what carries the interfaces: refinement (the plan's edge ids), the block graph, the check
certificate, every exporter and its reader, and the domain file's round trip.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from composite_checks import assert_composite, catalogue_shapes
from helpers import COMPOSITE_CATALOGUE, run_cli

import blockmesh
import blockmesh.io as bio
import blockmesh.refinement.grouped
from blockmesh import Domain


@pytest.fixture(scope="module")
def composites() -> dict[str, Domain]:
    return {name: blockmesh.load_domain(name) for name in COMPOSITE_CATALOGUE}


def test_the_catalogue_has_four_composites(composites):
    assert set(composites) >= {"fibre-cell", "layered-plate", "heat-sink", "inclusion"}
    cell = composites["fibre-cell"]
    assert cell.region_names == ("matrix", "fibre") and cell.interface_names == ("matrix|fibre",)
    assert len(cell.block_mesh().interface_cells()) == 4 * 48  # four fibres, 16 chords of 3
    assert composites["layered-plate"].interface_names == ("bottom|core", "core|top")


@pytest.mark.parametrize("name", COMPOSITE_CATALOGUE)
@pytest.mark.parametrize("level", [0, 1, 2])
def test_catalogue_composites_tile_conform_and_carry_regions(composites, name, level):
    assert_composite(composites[name].mesh(level), catalogue_shapes(name))


@pytest.mark.slow
@pytest.mark.parametrize("name", COMPOSITE_CATALOGUE)
def test_catalogue_composites_at_level_3(composites, name):
    assert_composite(composites[name].mesh(3), catalogue_shapes(name))


def test_refined_interfaces_are_the_coarse_ones_split(composites, monkeypatch):
    """Every interface edge at level L lies on an interface edge of the blocks, 2^L of them."""
    domain = composites["heat-sink"]
    base = domain.block_mesh()
    for level in (1, 2, 3):
        mesh = domain.mesh(level)
        assert mesh.interface_edges.shape[0] == base.interface_edges.shape[0] * 2**level
        cells = mesh.interface_cells()
        coarse = {tuple(sorted(pair)) for pair in base.interface_cells().tolist()}
        blocks = {tuple(sorted(pair)) for pair in mesh.block_id[cells].tolist()}
        assert blocks <= coarse
    # Refining a refined mesh carries them the same way: refine(refine(d, 1), 1) == refine(d, 2).
    again = blockmesh.refine(domain.mesh(1), 1)
    assert np.array_equal(again.interface_edges, domain.mesh(2).interface_edges)
    # Deep refinements go in two stages (the base refined first, its cells then as blocks):
    # forced here at level 3, they give the same interfaces.
    one_stage = domain.mesh(3)
    monkeypatch.setattr(blockmesh.refinement.grouped, "BLOCK_LEVEL", 1)
    two_stages = domain.mesh(3)
    assert np.array_equal(two_stages.cells, one_stage.cells)
    assert np.array_equal(two_stages.interface_edges, one_stage.interface_edges)


def test_curved_interfaces_keep_a_true_circle(composites):
    domain = composites["inclusion"]
    for level in (0, 2, 4):
        mesh = domain.mesh(level)
        ring = mesh.points[np.unique(mesh.interface_edges)]
        assert np.abs(np.hypot(*ring.T) - 0.5).max() < 2e-16 * 4
        left, right = mesh.interface_cells().T  # both regions use the very same node ids
        for cell in (left, right):
            assert np.all(np.any(mesh.cells[cell] == mesh.interface_edges[:, :1], axis=1))


def test_domain_file_round_trip(composites, tmp_path):
    for name in ("layered-plate", "inclusion"):
        domain = composites[name]
        again = Domain.from_toml(domain.write_toml(tmp_path / f"{name}.toml"))
        assert np.array_equal(again.interface_edges, domain.interface_edges)
        assert again.interface_names == domain.interface_names
        assert again.region_names == domain.region_names
    apart = Domain.from_shapely(
        __import__("shapely").MultiPolygon(
            [__import__("shapely").box(0, 0, 1, 1), __import__("shapely").box(2, 0, 3, 1)]
        )
    )
    assert apart.components == 2
    assert Domain.from_toml_text(apart.to_toml()).components == 2


def labelled(mesh) -> list:
    """The interface edges with their interfaces, sorted (formats may reorder them)."""
    edges, patch = mesh.interface_edges.tolist(), mesh.interface_patch.tolist()
    return sorted(zip(map(tuple, edges), patch, strict=True))


@pytest.mark.parametrize("fmt", sorted(bio.FORMATS))
def test_every_format_carries_the_interfaces(composites, tmp_path, fmt):
    mesh = composites["heat-sink"].mesh(1)
    target = tmp_path / (
        "case" if bio.FORMATS[fmt].directory else f"mesh{bio.FORMATS[fmt].extensions[0]}"
    )
    back = bio.read(bio.write(mesh, target, format=fmt), format=fmt)
    assert np.array_equal(back.region, mesh.region)
    assert labelled(back) == labelled(mesh)
    if fmt == "openfoam":  # OpenFOAM words: '|' is not one of their characters
        assert back.interface_names == ("sink_chip",)
    else:
        assert back.interface_names == mesh.interface_names


def test_check_lists_interfaces_and_pieces(capsys, tmp_path):
    code, stdout, _ = run_cli(capsys, "check", "layered-plate", "--json")
    assert code == 0
    report = json.loads(stdout)
    assert report["interfaces"] == {
        "bottom|core": {"edges": 12, "between": ["bottom", "core"]},
        "core|top": {"edges": 12, "between": ["core", "top"]},
    }
    assert report["region_areas"] == pytest.approx({"bottom": 4.0, "core": 4.0, "top": 4.0})
    code, stdout, _ = run_cli(capsys, "check", "layered-plate")
    assert "interface bottom|core: 12 edges between bottom and core (internal)" in stdout
    path = tmp_path / "apart.wkt"
    path.write_text("MULTIPOLYGON (((0 0, 1 0, 1 1, 0 1, 0 0)), ((2 0, 3 0, 3 1, 2 1, 2 0)))")
    code, stdout, _ = run_cli(capsys, "check", str(path))
    assert code == 0 and "2 pieces" in stdout and "the mesh is not connected" in stdout
    # A mesh file with interfaces checks too (its interfaces listed).
    mesh_path = bio.write(blockmesh.load_domain("layered-plate").mesh(1), tmp_path / "m.npz")
    code, stdout, _ = run_cli(capsys, "check", str(mesh_path), "--json")
    assert json.loads(stdout)["interfaces"]["core|top"]["edges"] == 24


def test_block_graph_marks_interfaces(composites):
    graph = composites["layered-plate"].block_graph()
    marked = [d["interface"] for _, _, d in graph.edges(data=True) if d["interface"]]
    assert sorted(set(marked)) == ["bottom|core", "core|top"] and len(marked) == 24


def test_pictures(composites, tmp_path):
    from blockmesh.plot import plot_domain, plot_mesh

    assert plot_domain(composites["fibre-cell"], tmp_path / "d.png").stat().st_size > 0
    assert plot_mesh(composites["inclusion"].mesh(1), tmp_path / "m.png").stat().st_size > 0
