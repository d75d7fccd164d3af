"""Coordinates checked: finite numbers in range; points closer than the same-point tolerance.

Examples
--------
>>> parse_points([[0, 0], [1, "a"]], "vertex")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
blockmesh.errors.DomainFormatError: vertex 1 has a y coordinate that is not a number ('a'); ...
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable

import numpy as np

from blockmesh.domain.validate.problems import raise_problems, shortened
from blockmesh.domain.validate.tolerances import MIN_EXTENT, same_point_tol
from blockmesh.errors import DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.polygons import MAX_COORDINATE, local_frame

__all__ = ["close_pairs", "coincident_pairs", "parse_points"]


def _is_number(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def parse_points(raw: object, what: str = "vertex") -> np.ndarray:
    """Validate a list of ``[x, y]`` pairs; returns a new (K, 2) float64 array.

    Raises DomainFormatError for wrong shapes or non-numbers and DomainError for non-finite values.

    Examples
    --------
    >>> parse_points([[0, 0], [1, 2.5]]).tolist()
    [[0.0, 0.0], [1.0, 2.5]]
    """
    if isinstance(raw, np.ndarray):
        if raw.ndim != 2 or raw.shape[1] != 2:
            raise DomainFormatError(f"{what} coordinates must have shape (n, 2), got {raw.shape}")
        if not (np.issubdtype(raw.dtype, np.number) and not np.issubdtype(raw.dtype, np.bool_)):
            raise DomainFormatError(f"{what} coordinates must be numbers, got dtype {raw.dtype}")
        if np.issubdtype(raw.dtype, np.floating) or np.issubdtype(raw.dtype, np.integer):
            return _checked_values(np.array(raw, dtype=np.float64), what)
        items = raw.tolist()
    elif isinstance(raw, str | bytes) or not isinstance(raw, Iterable):
        raise DomainFormatError(
            f"expected a list of [x, y] pairs for the {what} coordinates, got {type(raw).__name__}"
        )
    else:
        items = list(raw)
    problems = []
    for i, item in enumerate(items):
        if isinstance(item, str | bytes) or not isinstance(item, Iterable):
            problems.append(f"{what} {i} is {item!r}: each {what} must be a pair [x, y]")
            continue
        pair = list(item)
        if len(pair) != 2:
            problems.append(f"{what} {i} is {pair!r}: each {what} must be a pair [x, y]")
            continue
        for axis, value in zip("xy", pair, strict=True):
            if not _is_number(value):
                problems.append(
                    f"{what} {i} has a{'n' if axis == 'x' else ''} {axis} coordinate that is not "
                    f"a number ({value!r}); coordinates must be numbers"
                )
    raise_problems(DomainFormatError, problems)
    try:
        points = np.array(items, dtype=np.float64).reshape(-1, 2)
    except OverflowError:
        big = next(i for i, item in enumerate(items) if not _fits(item))
        raise DomainError(
            f"{what} {big} has a coordinate too large for a double ({shortened(items[big])}); "
            f"coordinates must be at most {MAX_COORDINATE:g} in magnitude"
        ) from None
    return _checked_values(points, what)


def _checked_values(points: np.ndarray, what: str) -> np.ndarray:
    bad = np.flatnonzero(~np.all(np.isfinite(points), axis=1))
    raise_problems(
        DomainError,
        [
            f"{what} {i} ({float(points[i, 0])!r}, {float(points[i, 1])!r}) is not finite: "
            "coordinates must be finite numbers"
            for i in bad
        ],
    )
    huge = np.flatnonzero(np.any(np.abs(points) > MAX_COORDINATE, axis=1))
    raise_problems(
        DomainError,
        [
            f"{what} {i} {fmt_point(points[i])} is too far out: coordinates must be at most "
            f"{MAX_COORDINATE:g} in magnitude (move the domain nearer the origin, or change units)"
            for i in huge
        ],
    )
    if points.shape[0] >= 3:
        span = float(np.max(np.ptp(points, axis=0)))
        if 0 < span < MIN_EXTENT:
            raise DomainError(
                f"the {what} coordinates span only {span:.3g}: below {MIN_EXTENT:g} areas and "
                "angles underflow in double precision (to 0); scale the domain up (change units)"
            )
    return points


def _fits(item: Iterable) -> bool:
    try:
        np.array(list(item), dtype=np.float64)
    except OverflowError:
        return False
    return True


#: Close pairs are found by a sweep along x (O(n log n): 0.08 ms for 2,000 points, where
#: comparing all pairs took 120 ms), unless the sweep would compare more than
#: :data:`_SWEEP_PAIRS` pairs per point (many points within ``r`` of one another in x); then up to
#: this many points by comparing all pairs (chunked numpy), so that loading a domain does not
#: import ``scipy.spatial`` (0.3-0.5 s in a fresh process), and above it with a k-d tree.
_BRUTE_FORCE_POINTS = 2048
_SWEEP_PAIRS = 32


def close_pairs(points: np.ndarray, r: float) -> np.ndarray:
    """Pairs ``(i, j)``, ``i < j``, of points at most ``r`` apart, as an ``(n, 2)`` array.

    The same pairs as :meth:`scipy.spatial.cKDTree.query_pairs` (in another order).

    Examples
    --------
    >>> close_pairs(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1e-13]]), 1e-12).tolist()
    [[0, 2]]
    """
    points = np.asarray(points, dtype=np.float64)
    n = points.shape[0]
    swept = _swept_pairs(points, r)
    if swept is not None:
        return swept
    if n > _BRUTE_FORCE_POINTS:
        from scipy.spatial import cKDTree

        return cKDTree(points).query_pairs(r=r, output_type="ndarray")
    found = [np.empty((0, 2), dtype=np.intp)]
    for start in range(0, n, 256):
        block = points[start : start + 256]
        gap = block[:, None, :] - points[None, :, :]
        i, j = np.nonzero(np.hypot(gap[..., 0], gap[..., 1]) <= r)
        i += start
        keep = i < j
        found.append(np.stack([i[keep], j[keep]], axis=1))
    return np.concatenate(found)


def _swept_pairs(points: np.ndarray, r: float) -> np.ndarray | None:
    """The pairs of :func:`close_pairs` by a sweep along x; None when it would compare too many.

    Every point is compared with the points after it in x order that are at most ``r`` further
    in x: O(n log n) plus the pairs compared.
    """
    n = points.shape[0]
    order = np.argsort(points[:, 0], kind="stable")
    xs = points[order, 0]
    counts = np.searchsorted(xs, xs + r, side="right") - np.arange(n) - 1
    total = int(counts.sum())
    if total > _SWEEP_PAIRS * n:
        return None
    first = np.repeat(np.arange(n), counts)
    step = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    i, j = order[first], order[first + 1 + step]
    gap = points[i] - points[j]
    keep = np.hypot(gap[:, 0], gap[:, 1]) <= r
    pairs = np.stack([i[keep], j[keep]], axis=1).astype(np.intp)
    return np.sort(pairs, axis=1)


def coincident_pairs(points: np.ndarray) -> list[tuple[int, int]]:
    """Pairs ``(i, j)``, ``i < j``, of points closer than the same-point tolerance, sorted."""
    frame = local_frame(points)
    pairs = close_pairs(frame.to_local(points), same_point_tol(frame))
    return sorted((int(a), int(b)) for a, b in np.sort(pairs, axis=1))
