"""Checks and repairs of domain input, each failure a typed error with a located message.

The functions here take raw user input (lists from TOML or Python, numpy arrays) and return clean
arrays, or raise :class:`~blockmesh.errors.DomainError` (geometry),
:class:`~blockmesh.errors.DomainFormatError` (types and shapes) or
:class:`~blockmesh.errors.TopologyError` (how blocks fit together). Every message names the vertex,
edge or block with its coordinates and says how to fix it. Where a stage finds several problems,
all of them are reported at once (one per line: :mod:`~blockmesh.domain.validate.problems`).
Harmless repairs (clockwise order, a closing vertex that repeats the first, straight corners of a
polygon) are made with a :class:`~blockmesh.errors.BlockMeshWarning`.

One module per stage of the input:

- :mod:`~blockmesh.domain.validate.points`: coordinates, and points that are one;
- :mod:`~blockmesh.domain.validate.rings`: a polygon and its holes;
- :mod:`~blockmesh.domain.validate.blocks`: blocks, each a strictly convex pentagon;
- :mod:`~blockmesh.domain.validate.topology`: how the blocks fit together;
- :mod:`~blockmesh.domain.validate.names`: patches and regions;
- :mod:`~blockmesh.domain.validate.tolerances`: when two points are one, when rings touch.

Examples
--------
>>> parse_points([[0, 0], [1, "a"]], "vertex")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
blockmesh.errors.DomainFormatError: vertex 1 has a y coordinate that is not a number ('a'); ...
"""

from __future__ import annotations

from blockmesh.domain.validate.blocks import check_block_shapes, parse_blocks
from blockmesh.domain.validate.names import (
    DEFAULT_PATCH,
    DEFAULT_REGION,
    edge_pair,
    resolve_patches,
    resolve_regions,
)
from blockmesh.domain.validate.points import parse_points
from blockmesh.domain.validate.rings import Ring, check_rings, ring_label
from blockmesh.domain.validate.tolerances import GAP_TOL, MIN_EXTENT, NEAR_TOL
from blockmesh.domain.validate.topology import check_topology
from blockmesh.errors import fmt_point
from blockmesh.geometry.polygons import MAX_COORDINATE

__all__ = [
    "DEFAULT_PATCH",
    "DEFAULT_REGION",
    "GAP_TOL",
    "MAX_COORDINATE",
    "MIN_EXTENT",
    "NEAR_TOL",
    "Ring",
    "check_block_shapes",
    "check_rings",
    "check_topology",
    "edge_pair",
    "fmt_point",
    "parse_blocks",
    "parse_points",
    "resolve_patches",
    "resolve_regions",
    "ring_label",
]
