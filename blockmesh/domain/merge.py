"""Vertices closer than a tolerance merged into one, and everything that names them renumbered.

:meth:`blockmesh.Domain.from_blocks` with ``merge_tol`` glues pieces made separately along their
common edges: :func:`merge_vertices` keeps the lowest-numbered vertex of each close group,
renumbers the vertices in order and maps the blocks and the vertex pairs of patches and
interfaces; :func:`merged_edges` maps the keys of curves and grading.

Examples
--------
>>> import numpy as np
>>> points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0 + 1e-12, 0.0], [2.0, 0.0]])
>>> merged, blocks, (patches,) = merge_vertices(points, np.array([[0, 1], [2, 3]]),
...                                            ({"wall": [(2, 3)]},), 1e-9)
>>> merged.shape, blocks.tolist(), patches
((3, 2), [[0, 1], [1, 2]], {'wall': [(1, 2)]})
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from blockmesh.errors import DomainFormatError

__all__ = ["merge_vertices", "merged_edges"]


def merge_vertices(
    points: np.ndarray, blocks: np.ndarray, named: tuple[Any, ...], tol: float
) -> tuple[np.ndarray, np.ndarray, tuple[Any, ...]]:
    """Merge vertices closer than ``tol``; renumber; map blocks and ``named``'s vertex pairs.

    ``named`` holds mappings of name to vertex pairs (the patches, the interfaces).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    if not isinstance(tol, numbers.Real) or isinstance(tol, bool) or not tol >= 0:
        raise DomainFormatError(f"merge_tol must be a distance >= 0, got {tol!r}")
    n = points.shape[0]
    pairs = cKDTree(points).query_pairs(r=float(tol), output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    representative = np.full(label.max() + 1, n, dtype=np.int64)
    np.minimum.at(representative, label, np.arange(n))
    target = representative[label]
    kept = np.unique(target)
    new_id = np.full(n, -1, dtype=np.int64)
    new_id[kept] = np.arange(kept.size)
    mapping = new_id[target]
    return points[kept], mapping[blocks], tuple(_mapped_pairs(p, mapping, n) for p in named)


def _mapped_pairs(patches: Any, mapping: np.ndarray, n: int) -> Any:
    """A mapping of name to vertex pairs with every pair's ids mapped (others left as given)."""
    mapped_patches = patches
    if patches:
        mapped_patches = {}
        for patch_name, edges in dict(patches).items():
            mapped = []
            for edge in edges if isinstance(edges, Iterable) else [edges]:
                pair = (
                    list(edge) if isinstance(edge, Iterable) and not isinstance(edge, str) else None
                )
                if (
                    pair is not None
                    and len(pair) == 2
                    and all(isinstance(v, numbers.Integral) and 0 <= int(v) < n for v in pair)
                ):
                    mapped.append((int(mapping[pair[0]]), int(mapping[pair[1]])))
                else:
                    mapped.append(edge)
            mapped_patches[patch_name] = mapped
    return mapped_patches


def merged_edges(edges: Any, given: np.ndarray, merged: np.ndarray) -> Any:
    """``edges`` keyed by the vertex ids after a merge (each vertex finds its merged point)."""
    if not edges or not isinstance(edges, Mapping):
        return edges
    from scipy.spatial import cKDTree

    _, new_id = cKDTree(merged).query(given)
    out = {}
    for key, curve in edges.items():
        try:
            a, b = (int(new_id[int(v)]) for v in key)
        except (TypeError, ValueError, IndexError):
            out[key] = curve  # resolve_curves names the bad key
            continue
        out[(a, b)] = curve
    return out
