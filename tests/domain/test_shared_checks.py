"""The checks that several inputs share give each input its own located message.

The arrays of tables of a domain file (``[[arcs]]``, ``[[grading]]``, ``[[edges]]``) share one
check that they are tables, and one that an edge is ``[a, b]``; the ``*_source`` fields of a
Domain share one shape check; patches and regions share how unnamed edges and blocks are named.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from blockmesh import Domain, DomainError, DomainFormatError

BLOCKS = "vertices = [[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]]\nblocks = [[0, 1, 2, 3, 4]]\n"
POLYGON = "polygon = [[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]]\n"


@pytest.mark.parametrize(
    ("text", "key", "what"),
    [
        (POLYGON + "arcs = 3", "arcs", "one per curved polygon edge"),
        (BLOCKS + "grading = [1, 2]", "grading", "edge = [a, b], ratio = r"),
        (BLOCKS + 'edges = "arc"', "edges", "one per curved edge"),
    ],
)
def test_an_array_of_tables_that_is_not_one_is_named_with_its_key(text, key, what):
    with pytest.raises(DomainFormatError) as error:
        Domain.from_toml_text(text)
    assert f"<text>: '{key}' must be [[{key}]] tables ({what}), got " in str(error.value)


@pytest.mark.parametrize("pair", ["[0]", "[0, 1, 2]", "[0, true]", '["a", 1]', "3"])
def test_an_edge_that_is_not_two_vertex_ids_is_named_in_each_table(pair):
    with pytest.raises(DomainFormatError, match=r"\[\[grading\]\] entry 1: an edge is \[a, b\]"):
        Domain.from_toml_text(BLOCKS + f"[[grading]]\nedge = {pair}\nratio = 2")
    with pytest.raises(DomainFormatError, match=r"\[\[edges\]\] entry 1: arc must be \[a, b\]"):
        Domain.from_toml_text(BLOCKS + f"[[edges]]\narc = {pair}\nthrough = [1, -0.2]")


def test_the_source_fields_are_checked_against_their_own_counts():
    d = Domain.from_toml_text(POLYGON)
    n = d.boundary_edges.shape[0]
    with pytest.raises(
        DomainError, match=rf"one \(ring, edge\) row per boundary edge, shape \({n}, 2\)"
    ):
        dataclasses.replace(d, boundary_source=np.zeros((n + 1, 2), dtype=np.int64))
    with pytest.raises(DomainError, match=r"one entry per block, shape \(1,\), got \(2,\)"):
        dataclasses.replace(d, block_source=np.zeros(2, dtype=np.int64))
    kept = dataclasses.replace(d, block_source=np.array([7]))
    assert kept.block_source.tolist() == [7]
    assert kept.boundary_source.tolist() == d.boundary_source.tolist()


@pytest.mark.parametrize("listed", [[], ["boundary"], ["wall", "boundary"], ["wall"]])
def test_unnamed_edges_and_blocks_join_the_default_patch_and_region(listed):
    names = {"wall": [[0, 1]], "boundary": [[1, 2]]}
    regions = {"domain": [0]} if "boundary" in listed else {}
    d = Domain.from_toml_text(
        BLOCKS
        + "[patches]\n"
        + "".join(f"{k} = {names[k]}\n" for k in listed)
        + "[regions]\n"
        + "".join(f"{k} = {v}\n" for k, v in regions.items())
    )
    assert d.patch_names[: len(listed)] == tuple(listed)
    assert d.patch_names.count("boundary") == 1
    assert sum(len(e) for e in d.patches.values()) == 5
    assert d.region_names == ("domain",)
