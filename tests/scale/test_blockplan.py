"""The block-by-block numbering plan against the all-blocks-at-once refinement."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import CATALOGUE

import blockmesh.refinement as refinement
import blockmesh.template as template
from blockmesh.blockplan import block_node_ids, edge_node_ids, plan_refinement
from blockmesh.topology import cell_neighbours

FIELDS = ("points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch", "region")


@pytest.mark.parametrize("name", CATALOGUE)
def test_block_by_block_equals_all_blocks_bit_for_bit(catalogue, name):
    base = catalogue[name].block_mesh()
    neighbour = cell_neighbours(base.cells, base.n_points)
    for level in (1, 3):
        whole = refinement._build_all_blocks(base, neighbour, level, 0, None)
        by_block = refinement._build_block_by_block(base, neighbour, level, None)
        for field in FIELDS:
            assert np.array_equal(getattr(whole, field), getattr(by_block, field)), field


@pytest.mark.parametrize("name", ["joined-8", "l-shape", "ring", "square"])
def test_plan_ids_match_the_global_ids(catalogue, name):
    base = catalogue[name].block_mesh()
    neighbour = cell_neighbours(base.cells, base.n_points)
    level = 3
    ids, n_nodes = refinement._global_ids(base.cells, neighbour, base.n_points, level)
    plan = plan_refinement(base.cells, neighbour, base.n_points, level)
    assert plan.n_nodes == n_nodes
    along = template.pentagon_template(level).edge_nodes
    for block in range(base.n_cells):
        got, numbered = block_node_ids(plan, block)
        assert np.array_equal(got, ids[block])
        # The nodes a block numbers are exactly its ids from its offsets on, per level.
        assert int(numbered.sum()) == plan.nodes_of_block(block)
        for edge in range(5):
            assert np.array_equal(edge_node_ids(plan, block, edge), ids[block, along[edge]])


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
