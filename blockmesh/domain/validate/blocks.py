"""Blocks checked: five distinct vertex ids each, strictly convex and counter-clockwise.

Examples
--------
>>> parse_blocks([[0, 1, 2, 3]], 5)
Traceback (most recent call last):
...
blockmesh.errors.DomainFormatError: block 0 is [0, 1, 2, 3]: a block is a pentagon, 5 vertex ids
"""

from __future__ import annotations

import numbers
import warnings
from collections.abc import Iterable

import numpy as np

from blockmesh.domain.validate.points import coincident_pairs
from blockmesh.domain.validate.problems import raise_problems, shortened
from blockmesh.errors import BlockMeshWarning, DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    corner_sines,
    interior_angles,
    local_frame,
    signed_area,
)

__all__ = ["block_label", "check_block_shapes", "parse_blocks"]


def parse_blocks(raw: object, n_vertices: int) -> np.ndarray:
    """Validate a list of 5-tuples of vertex ids; returns a new (B, 5) int64 array.

    Examples
    --------
    >>> parse_blocks([[0, 1, 2, 3, 4]], 5).tolist()
    [[0, 1, 2, 3, 4]]
    >>> parse_blocks([[0, 1, 2, 3]], 5)
    Traceback (most recent call last):
    ...
    blockmesh.errors.DomainFormatError: block 0 is [0, 1, 2, 3]: a block is a pentagon, 5 vertex ids
    """
    if (
        isinstance(raw, np.ndarray)
        and np.issubdtype(raw.dtype, np.integer)
        and raw.ndim == 2
        and raw.shape[1] == 5
        and raw.shape[0] > 0
    ):
        ids = raw.astype(np.int64)
        ordered = np.sort(ids, axis=1)
        if (
            ids.min() >= 0
            and ids.max() < n_vertices
            and not np.any(ordered[:, 1:] == ordered[:, :-1])
        ):
            return ids
        items = raw.tolist()
    elif isinstance(raw, np.ndarray):
        items = raw.tolist()
    elif isinstance(raw, str | bytes) or not isinstance(raw, Iterable):
        raise DomainFormatError(
            f"expected a list of blocks (5 vertex ids each), got {type(raw).__name__}"
        )
    else:
        items = [list(b) if isinstance(b, Iterable) and not isinstance(b, str) else b for b in raw]
    if not items:
        raise DomainFormatError("a domain needs at least one block")
    problems = []
    for i, block in enumerate(items):
        if not isinstance(block, list) or len(block) != 5:
            problems.append(f"block {i} is {block!r}: a block is a pentagon, 5 vertex ids")
            continue
        for v in block:
            if not isinstance(v, numbers.Integral) or isinstance(v, bool):
                problems.append(
                    f"block {i} has vertex id {shortened(v)}, which is not a whole number"
                )
            elif not 0 <= int(v) < n_vertices:
                problems.append(
                    f"block {i} refers to vertex {shortened(v)}, but the vertices are numbered "
                    f"0..{n_vertices - 1}"
                )
        whole = all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in block)
        if whole and len(set(block)) != len(block):
            twice = sorted({v for v in block if block.count(v) > 1})
            problems.append(
                f"block {i} ({', '.join(map(str, block))}) uses vertex "
                f"{', '.join(map(str, twice))} twice; a block has five different corners"
            )
    raise_problems(DomainFormatError, problems)
    return np.array(items, dtype=np.int64).reshape(-1, 5)


def block_label(blocks: np.ndarray, b: int) -> str:
    """How messages name a block: ``block 3 (vertices 4, 7, 9, 2, 5)``."""
    return f"block {b} (vertices {', '.join(map(str, blocks[b]))})"


def check_block_shapes(vertices: np.ndarray, blocks: np.ndarray, *, repair: bool) -> np.ndarray:
    """Check every block is a strictly convex pentagon; reverse clockwise ones when ``repair``.

    Returns the (possibly repaired) blocks as a new array. Also rejects vertices at the same
    coordinates and vertices no block uses. Works in the domain's local frame, so the verdict does
    not depend on where the domain sits. O(B) plus O(K log K) for the repeated points.

    Examples
    --------
    >>> v = np.array([[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]], dtype=float)
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     check_block_shapes(v, np.array([[0, 4, 3, 2, 1]]), repair=True).tolist()
    [[0, 1, 2, 3, 4]]
    >>> str(caught[0].message)[:25]
    '1 block was clockwise and'
    """
    blocks = np.array(blocks, dtype=np.int64)
    same = coincident_pairs(vertices)
    raise_problems(
        DomainError,
        [
            f"vertices {a} and {b} are the same point {fmt_point(vertices[a])}: list each point "
            f"once and use vertex {a} in every block that has this corner"
            for a, b in same
        ],
    )
    used = np.zeros(vertices.shape[0], dtype=bool)
    used[blocks.ravel()] = True
    unused = np.flatnonzero(~used)
    raise_problems(
        DomainError,
        [
            f"vertex {v} {fmt_point(vertices[v])} is not used by any block; remove it or make it "
            "a corner of a block"
            for v in unused
        ],
    )
    local = local_frame(vertices).to_local(vertices)
    xy = local[blocks]
    areas = signed_area(xy)
    extent = np.ptp(xy, axis=1).max(axis=1)
    flat = np.flatnonzero(np.abs(areas) <= 1e-12 * extent**2)
    raise_problems(
        DomainError,
        [f"{block_label(blocks, int(b))} has zero area: its corners lie on one line" for b in flat],
    )
    clockwise = np.flatnonzero(areas < 0)
    if clockwise.size:
        if not repair:
            raise_problems(
                DomainError,
                [
                    f"{block_label(blocks, int(b))} runs clockwise; list its corners "
                    "counter-clockwise"
                    for b in clockwise
                ],
            )
        reversed_order = [0, 4, 3, 2, 1]
        blocks[clockwise] = blocks[clockwise][:, reversed_order]
        xy = local[blocks]
        shown = "; ".join(
            f"block {b} is now {', '.join(map(str, blocks[b]))}" for b in clockwise[:4]
        )
        warnings.warn(
            f"{clockwise.size} block{'s were' if clockwise.size > 1 else ' was'} clockwise and "
            f"reversed to counter-clockwise order (first vertex kept): {shown}",
            BlockMeshWarning,
            stacklevel=4,
        )
    sines = corner_sines(xy)
    angles = interior_angles(xy)
    straight = (np.abs(sines) <= COLLINEAR_SIN_TOL) & (angles > 90)
    wrong = sines < -COLLINEAR_SIN_TOL
    turning = np.sum(180.0 - angles, axis=1)
    crossing = ~np.isclose(turning, 360.0, atol=1e-6)
    problems = []
    for b in np.flatnonzero(np.any(straight | wrong, axis=1) | crossing).tolist():
        label = block_label(blocks, int(b))
        for k in range(5):
            v = blocks[b, k]
            if straight[b, k]:
                problems.append(
                    f"{label} is not strictly convex: the corner at vertex {v} "
                    f"{fmt_point(vertices[v])} is straight (180°); move vertex {v} off the line "
                    "through its neighbours, or use a block with that corner removed"
                )
                break
            if wrong[b, k]:
                problems.append(
                    f"{label} is not convex: the corner at vertex {v} {fmt_point(vertices[v])} "
                    f"turns the wrong way ({angles[b, k]:.1f}°); split the block or move the vertex"
                )
                break
        else:
            problems.append(
                f"{label} crosses itself (its corners go around {turning[b] / 360:.0f} times); "
                "list its corners in order around it"
            )
    raise_problems(DomainError, problems)
    return blocks
