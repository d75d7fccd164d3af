"""The block-by-block refinement (plan, groups, threads) against a plain transcription of the paper.

The reference walks every cell level by level with Python loops (numbering: the paper's
``nodaladdressesforpentagon``; coordinates: the paper's arithmetic on whole arrays), independently
of :mod:`blockmesh.refinement.template`, :mod:`blockmesh.refinement.plan` and
:mod:`blockmesh.refinement.grouped`. The fast path is compared with it bit for bit under every way
of cutting the work: blocks refined one by one or in groups, the base refined first and its cells
used as blocks, one or more threads.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import CATALOGUE
from paper_numbering import paper_cells

import blockmesh
import blockmesh.refinement.grouped as grouped
import blockmesh.refinement.template as template
from blockmesh.geometry.topology import cell_neighbours
from blockmesh.refinement.plan import (
    block_node_ids,
    edge_id_table,
    edge_node_ids,
    group_node_ids,
    node_pattern,
    plan_refinement,
)

STRAIGHT = [
    name for name in CATALOGUE if not len(blockmesh.load_domain(name).block_mesh().curves or ())
]


def reference_points(base, levels: int) -> np.ndarray:
    """Coordinates by the paper's arithmetic, level by level over all cells, stored by node id."""
    xy = base.points.copy()
    cells = base.cells.tolist()
    for level in range(1, levels + 1):
        finer = paper_cells(base.cells.tolist(), level)
        points = np.empty((1 + max(max(c) for c in finer), 2))
        points[: len(xy)] = xy
        v = xy[np.array(cells)]  # (C, 5, 2)
        p = (((v[:, 0] + v[:, 1]) + v[:, 2]) + v[:, 3]) + v[:, 4]
        p /= 5
        u = (v + np.roll(v, -1, axis=1)) * 0.5
        w = (u + p[:, None, :]) * 0.5
        children = np.array(finer).reshape(-1, 6, 5)
        points[children[:, :5, 1]] = u  # child k = <v_k, u_k, w_k, w_k-1, u_k-1>
        points[children[:, 5, :]] = w
        xy, cells = points, finer
    return xy


@pytest.mark.parametrize("name", STRAIGHT)
def test_refinement_equals_the_papers_walk(catalogue, name):
    base = catalogue[name].block_mesh()
    for level in (1, 2):
        mesh = blockmesh.refine(base, level)
        assert mesh.cells.tolist() == paper_cells(base.cells.tolist(), level)
        assert mesh.points.tobytes() == reference_points(base, level).tobytes()


@pytest.mark.parametrize("name", ["sp", "joined-3", "l-shape", "star", "triangle"])
@pytest.mark.parametrize(
    ("block_level", "group_nodes", "threads"),
    [(1, 1, 1), (1, 1, 3), (2, 200, 2), (3, 10**6, 2), (6, 1 << 18, 1)],
)
def test_every_way_of_cutting_the_work_gives_the_same_mesh(
    catalogue, name, block_level, group_nodes, threads, monkeypatch
):
    # block_level 1..3 refines the base first and uses its cells as blocks; group_nodes 1 makes
    # every block its own group, 200 and 10^6 put several or all blocks in one group.
    want = catalogue[name].mesh(3)
    monkeypatch.setattr(grouped, "BLOCK_LEVEL", block_level)
    monkeypatch.setattr(grouped, "GROUP_NODES", group_nodes)
    got = blockmesh.refine(catalogue[name], 3, threads=threads)
    fields = ("points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch", "region")
    for field in fields:
        assert getattr(got, field).tobytes() == getattr(want, field).tobytes(), field
    assert got.level == want.level == 3


def test_smoothing_is_the_same_for_any_number_of_threads(catalogue):
    one = blockmesh.refine(catalogue["joined-3"], 2, smooth=2, threads=1)
    two = blockmesh.refine(catalogue["joined-3"], 2, smooth=2, threads=2)
    assert one.points.tobytes() == two.points.tobytes()


@pytest.mark.parametrize("name", ["joined-8", "l-shape", "ring", "square", "lake-island"])
def test_plan_ids_agree_with_the_refined_mesh(catalogue, name):
    base = catalogue[name].block_mesh()
    neighbour = cell_neighbours(base.cells, base.n_points)
    level = 3
    mesh = blockmesh.refine(base, level)
    plan = plan_refinement(base.cells, neighbour, base.n_points, level)
    assert plan.n_nodes == mesh.n_points
    pentagon_cells = template.pentagon_template(level).cells
    per_block = 6**level
    table = edge_id_table(plan)
    ids = group_node_ids(plan, 0, base.n_cells, table)
    along = template.pentagon_template(level).edge_nodes
    for block in range(base.n_cells):
        # The block's cells are its ids through the template's cells.
        block_cells = mesh.cells[block * per_block : (block + 1) * per_block]
        assert np.array_equal(ids[block][pentagon_cells], block_cells)
        got, numbered = block_node_ids(plan, block)
        assert np.array_equal(got, ids[block])
        # The nodes a block numbers are exactly its ids from its offsets on, per level.
        assert int(numbered.sum()) == plan.nodes_of_block(block)
        pattern = node_pattern(level, tuple(plan.taken[block].tolist()))
        assert np.array_equal(pattern.own, numbered)
        for edge in range(5):
            assert np.array_equal(edge_node_ids(plan, block, edge), ids[block, along[edge]])
            assert np.array_equal(table[block, edge], ids[block, along[edge]])


def test_a_failing_worker_stops_the_others_and_reaches_the_caller(catalogue, monkeypatch):
    import threading

    calls = []

    def failing(local, level, *args):
        calls.append(threading.current_thread().name)
        raise ValueError("boom")

    monkeypatch.setattr(grouped, "_place_finest_level", failing)
    monkeypatch.setattr(grouped, "GROUP_NODES", 1)
    with pytest.raises(ValueError, match="boom"):
        blockmesh.refine(catalogue["lake-island"], 2, threads=2)
    # Each worker stops at its first failure: at most one group per thread was started.
    assert 1 <= len(calls) <= 2
    assert not [t for t in threading.enumerate() if t.name.startswith("blockmesh-")]


def test_progress_is_reported_in_the_calling_thread(catalogue, monkeypatch):
    import threading

    monkeypatch.setattr(grouped, "GROUP_NODES", 1)
    seen = []
    blockmesh.refine(
        catalogue["joined-8"],
        2,
        threads=2,
        progress=lambda done, total: seen.append((done, total, threading.current_thread())),
    )
    assert [(d, t) for d, t, _ in seen] == [(k, 8) for k in range(1, 9)]
    assert {thread for *_, thread in seen} == {threading.current_thread()}


def test_threads_must_be_a_whole_number_of_at_least_one(catalogue):
    with pytest.raises(blockmesh.BlockMeshError, match="threads must be a whole number >= 1"):
        blockmesh.refine(catalogue["sp"], 1, threads=0)


def test_default_threads_follow_the_environment(monkeypatch):
    from blockmesh._system.threads import MAX_THREADS, default_threads

    monkeypatch.setenv("BLOCKMESH_THREADS", "3")
    assert default_threads() == 3
    monkeypatch.setenv("BLOCKMESH_THREADS", "none")
    assert 1 <= default_threads() <= MAX_THREADS


def test_template_cache_is_bounded(monkeypatch):
    monkeypatch.setattr(template, "TEMPLATE_CACHE_BYTES", template.pentagon_template(4).nbytes)
    monkeypatch.setattr(template, "_CACHE", template._TemplateCache())
    big = template.pentagon_template(5)
    assert template.cached_template_bytes() == 0  # over the budget: only weakly held
    assert template.pentagon_template(5) is big  # found again while alive
    small = template.pentagon_template(4)
    assert template.cached_template_bytes() == small.nbytes
    template.pentagon_template(3)
    assert template.cached_template_bytes() <= template.TEMPLATE_CACHE_BYTES
    del big
    import gc

    gc.collect()
    assert template._CACHE.get(5) is None
