"""The block graph: blocks as nodes, shared block edges as graph edges (networkx).

The graph is for users who want to walk a domain's blocks with networkx (neighbours, paths,
colourings, partitions). The conformity certificate of ``blockmesh check`` is computed with the
same topology primitives as validation and refinement (:mod:`blockmesh.geometry.topology`).

Examples
--------
>>> import blockmesh
>>> g = blockmesh.load_domain("square-cut").block_graph()
>>> g.number_of_nodes(), g.number_of_edges()
(4, 4)
>>> g.edges[0, 1]["vertices"]
(4, 0)
"""

from __future__ import annotations

from typing import Any

import networkx as nx
import numpy as np

from blockmesh.geometry.topology import connected_pieces, count_loops
from blockmesh.mesh.labels import interface_summary

__all__ = ["block_graph", "certificate"]


def block_graph(domain) -> nx.Graph:
    """Graph of a domain's blocks.

    Nodes are block ids with attributes ``vertices`` (the 5 vertex ids), ``area`` and ``region``;
    an edge joins two blocks sharing a block edge and carries ``vertices`` (the two vertex ids, as
    the lower-numbered block runs along it) and ``interface`` (the interface's name, or None).
    ``graph["boundary"]`` lists the boundary edges as ``(block, (a, b), patch)``. O(B).
    """
    graph = nx.Graph(name=domain.name)
    areas = domain.block_areas()
    for b, block in enumerate(domain.blocks.tolist()):
        graph.add_node(
            b,
            vertices=tuple(block),
            area=float(areas[b]),
            region=domain.region_names[domain.region[b]],
        )
    neighbour = domain._neighbour
    boundary_owner = {}
    interface_of = {
        (min(int(a), int(c)), max(int(a), int(c))): domain.interface_names[int(k)]
        for (a, c), k in zip(domain.interface_edges, domain.interface_patch, strict=True)
    }
    for b, e in zip(*np.nonzero(neighbour >= 0), strict=True):
        other = int(neighbour[b, e]) // 5
        if b < other:
            a, c = int(domain.blocks[b, e]), int(domain.blocks[b, (e + 1) % 5])
            name = interface_of.get((min(a, c), max(a, c)))
            graph.add_edge(int(b), other, vertices=(a, c), interface=name)
    for b, e in zip(*np.nonzero(neighbour < 0), strict=True):
        a, c = int(domain.blocks[b, e]), int(domain.blocks[b, (e + 1) % 5])
        boundary_owner[(a, c)] = int(b)
    graph.graph["boundary"] = [
        (boundary_owner[(int(a), int(c))], (int(a), int(c)), domain.patch_names[p])
        for (a, c), p in zip(domain.boundary_edges, domain.boundary_patch, strict=True)
    ]
    return graph


def certificate(domain) -> dict[str, Any]:
    """The conformity certificate of a domain, as a JSON-ready dictionary.

    Counts (blocks, vertices, shared and boundary edges per patch), the regions (their blocks
    and areas) and interfaces (their edges and the two regions each lies between), the Euler
    characteristic V - E + F (c - h for c connected components and h holes; a composite domain
    of disjoint parts has several components), and per block its orientation, strict convexity
    and angles.

    Examples
    --------
    >>> import blockmesh
    >>> c = certificate(blockmesh.load_domain("ring"))
    >>> c["euler_characteristic"], c["holes"], c["valid"]
    (0, 1, True)
    """
    angles = domain.block_angles()
    areas = domain.block_areas()
    n_edges = domain.n_shared_edges + domain.boundary_edges.shape[0]
    euler = domain.n_vertices - n_edges + domain.n_blocks
    components, _ = connected_pieces(domain._neighbour)
    loops = count_loops(domain.boundary_edges)
    blocks = [
        {
            "block": b,
            "vertices": [int(v) for v in domain.blocks[b]],
            "region": domain.region_names[domain.region[b]],
            "area": float(areas[b]),
            "counter_clockwise": bool(areas[b] > 0),
            "strictly_convex": bool(np.all(angles[b] < 180.0)),
            "min_angle": float(angles[b].min()),
            "max_angle": float(angles[b].max()),
        }
        for b in range(domain.n_blocks)
    ]
    return {
        "domain": domain.name,
        "valid": True,
        "layout": domain.layout,
        "blocks": domain.n_blocks,
        "vertices": domain.n_vertices,
        "shared_edges": domain.n_shared_edges,
        "boundary_edges": int(domain.boundary_edges.shape[0]),
        "patches": {
            name: int(np.count_nonzero(domain.boundary_patch == k))
            for k, name in enumerate(domain.patch_names)
        },
        "regions": {name: [int(b) for b in ids] for name, ids in domain.regions.items()},
        "region_areas": {
            name: float(np.sum(areas[domain.region == k]))
            for k, name in enumerate(domain.region_names)
        },
        "interfaces": _interfaces(domain),
        "area": domain.area,
        "euler_characteristic": int(euler),
        "connected_components": int(components),
        "boundary_loops": loops,
        "holes": loops - components,
        "min_angle": float(angles.min()),
        "max_angle": float(angles.max()),
        "block_details": blocks,
    }


def _interfaces(domain) -> dict[str, dict[str, Any]]:
    """Each interface's edge count and the regions on its two sides (first side first)."""
    if not domain.interface_names:
        return {}
    return interface_summary(domain.block_mesh())
