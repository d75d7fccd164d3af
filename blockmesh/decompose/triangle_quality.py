"""Free points of a triangulation moved (and crowded pairs merged) so that its worst angles rise.

The size-driven decomposition (:mod:`blockmesh.decompose.sized`) turns every triangle into nine
pentagons, and a pentagon at a triangle's corner keeps that corner's angle until the optimiser
moves it: the worst angles of the blocks are, to first order, the worst angles of the triangles.
The relaxation that places the points (DistMesh's springs) makes the triangles' *sides* right;
this module makes their *angles* right, in two steps:

1. **Crowded fans merged** (on request). At a fixed point (a corner of the outline, a point on a
   boundary or an interface), the ``k`` triangles around it share its angle ``theta`` (90 degrees
   at a square corner, 180 along a straight boundary); when ``theta / k`` is below
   :data:`MERGE_BELOW` no placement of the free points can give them good angles, so two free
   neighbours of the fixed point, consecutive around it, are merged into their midpoint (a square
   corner with three triangles gets two, 45 degrees each).
2. **Angle-based smoothing.** Each free point tries a few positions: towards the mean of the
   apexes of the equilateral triangles over the far sides of the triangles around it (the
   optimal-Delaunay fixed point for angles), towards the apex over its worst triangle's far side,
   and small steps in eight directions; it takes the one that most raises the smallest angle of
   the triangles around it, never folding one and never leaving the domain. Points are moved in
   independent sets (no two in one triangle), worst first, and the Delaunay triangulation is
   made again between rounds, so a move is judged on the triangles it really changes.

The fixed points never move. The result feeds the same conforming triangulation as before; only
the free points have changed.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> free = np.array([[0.3, 0.2], [0.75, 0.7]])
>>> inside = lambda xy: np.all((xy > 0) & (xy < 1), axis=1)
>>> before = worst_triangle_angle(np.vstack([square, free]), inside)
>>> after = worst_triangle_angle(np.vstack([square, raise_triangle_angles(square, free, inside)]),
...                              inside)
>>> bool(after > before + 5)
True
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["MERGE_BELOW", "SIDE_CAP", "WORK_BELOW", "raise_triangle_angles", "worst_triangle_angle"]

#: A fixed point whose angle shared by its triangles gives each less than this (degrees) has two
#: of its free neighbours merged (see the module notes).
MERGE_BELOW = 40.0
#: Rounds of smoothing (each with a new Delaunay triangulation) and steps per round.
_ROUNDS, _STEPS = 6, 4
#: Rounds of merging at most.
_MERGE_ROUNDS = 3
_SQRT3_2 = 0.8660254037844386
#: The directions of the small steps, and their length as a fraction of the longest far side.
_DIRECTIONS = np.column_stack([np.cos(np.arange(8) * np.pi / 4), np.sin(np.arange(8) * np.pi / 4)])
_SMALL_STEP = 0.05
#: Free points whose triangles all have angles of at least this (degrees) stay where they are.
WORK_BELOW = 50.0
#: With the side wanted known, no move makes a triangle's longest side longer than this times the
#: smallest side wanted at its corners (the smallest: where the field is steep, the mean would let
#: the small end's cells grow).
SIDE_CAP = 1.5

Inside = Callable[[np.ndarray], np.ndarray]
Length = Callable[[np.ndarray], np.ndarray]


def _triangles(points: np.ndarray, inside: Inside) -> np.ndarray:
    """Counter-clockwise Delaunay triangles (not flat) whose centroid is inside."""
    from scipy.spatial import Delaunay

    tri = Delaunay(points).simplices.astype(np.int64)
    p = points[tri]
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    tri[cross < 0] = tri[cross < 0][:, [0, 2, 1]]
    longest = np.max(np.sum((p - np.roll(p, 1, axis=1)) ** 2, axis=2), axis=1)
    tri = tri[np.abs(cross) > 1e-12 * longest]
    return tri[inside(points[tri].mean(axis=1))]


def _angles(xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Angles (degrees) of triangles (..., 3, 2) at their corners, and whether counter-clockwise."""
    a = np.roll(xy, -1, axis=-2) - xy
    b = np.roll(xy, 1, axis=-2) - xy
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]
    return np.degrees(np.arctan2(np.abs(cross), dot)), cross[..., 0] > 0


def _min_angles(xy: np.ndarray) -> np.ndarray:
    """Smallest angle of triangles (..., 3, 2); ``-inf`` where one is not counter-clockwise."""
    angles, ccw = _angles(xy)
    return np.where(ccw, angles.min(axis=-1), -np.inf)


def worst_triangle_angle(points: np.ndarray, inside: Inside) -> float:
    """The smallest angle (degrees) of the Delaunay triangles of ``points`` inside the domain.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    >>> round(worst_triangle_angle(square, lambda xy: np.ones(len(xy), dtype=bool)), 6)
    45.0
    """
    tri = _triangles(np.asarray(points, dtype=np.float64), inside)
    return float(_min_angles(points[tri]).min()) if len(tri) else 180.0


def raise_triangle_angles(
    fixed: np.ndarray,
    free: np.ndarray,
    inside: Inside,
    *,
    length: Length | None = None,
    merge: bool = False,
    movable: np.ndarray | None = None,
) -> np.ndarray:
    """New free points whose Delaunay triangles have better worst angles (see the module notes).

    Parameters
    ----------
    fixed : ndarray (F, 2)
        Points that stay (the outline's samples).
    free : ndarray (M, 2)
        Points that may move.
    inside : callable
        ``inside(xy) -> bool array``: which points are inside the domain (a triangle is kept
        when its centroid is; a free point never moves out).
    length : callable, optional
        ``length(xy) -> array``: the triangle side wanted at points. With it, no move makes a
        triangle's longest side pass :data:`SIDE_CAP` times the smallest side wanted at its corners
        (or its longest side before, if longer): the cells made from the triangles keep their
        sizes, and a graded field costs no more cells.
    merge : bool
        Merge crowded pairs of free points around fixed points first (the result then has
        fewer free points).
    movable : ndarray (M,) bool, optional
        Which free points may move (all by default; without ``merge``): after a local change,
        only the points near it need smoothing again.

    Returns
    -------
    ndarray (M', 2)
        The free points (``M' <= M``; ``M' = M`` without ``merge``).

    Notes
    -----
    O((F + M) log(F + M)) per round (a Delaunay triangulation and whole-array steps); the
    steps cost O(k) for the k triangles around the points that try to move.
    """
    fixed = np.asarray(fixed, dtype=np.float64)
    free = np.array(free, dtype=np.float64)
    if not len(free):
        return free
    mobile = np.ones(len(fixed) + len(free), dtype=bool)
    mobile[: len(fixed)] = False
    if movable is not None:
        if merge:
            raise ValueError("merge needs every free point movable")
        mobile[len(fixed) :] = np.asarray(movable, dtype=bool)
        if not mobile.any():
            return free
    if merge:
        for _ in range(_MERGE_ROUNDS):
            merged = _merge_crowded(fixed, free, inside)
            if len(merged) == len(free):
                break
            free = merged
        mobile = np.r_[mobile[: len(fixed)], np.ones(len(free), dtype=bool)]
    for _ in range(_ROUNDS):
        points = np.vstack([fixed, free])
        wanted = None if length is None else np.asarray(length(points), dtype=np.float64)
        moved = _smooth(points, mobile, _triangles(points, inside), inside, wanted)
        free = points[len(fixed) :]
        if not moved:
            break
    return free


def _merge_crowded(fixed: np.ndarray, free: np.ndarray, inside: Inside) -> np.ndarray:
    """Free points with one crowded pair merged per fixed point whose fan is too crowded."""
    points = np.vstack([fixed, free])
    n_fixed, n = len(fixed), len(fixed) + len(free)
    tri = _triangles(points, inside)
    angles, _ = _angles(points[tri])
    corner = tri.ravel()
    share = np.bincount(corner, weights=angles.ravel(), minlength=n)
    count = np.bincount(corner, minlength=n)
    crowded = (np.arange(n) < n_fixed) & (count >= 2)
    crowded &= share < MERGE_BELOW * np.maximum(count, 1)
    if not crowded.any():
        return free
    # Triangles (c, a, b) with c crowded and fixed, a and b free: one per c, sharpest at c first.
    t, k = np.nonzero(crowded[tri])
    a, b = tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]
    ok = (a >= n_fixed) & (b >= n_fixed)
    t, k, a, b = t[ok], k[ok], a[ok], b[ok]
    if not t.size:
        return free
    order = np.lexsort((angles[t, k], tri[t, k]))
    c = tri[t, k][order]
    first = np.r_[True, c[1:] != c[:-1]]
    a, b = a[order][first], b[order][first]
    # A point merged once per round.
    used = np.zeros(n, dtype=bool)
    keep_pairs = []
    for i, j in zip(a.tolist(), b.tolist(), strict=True):
        if not (used[i] or used[j]):
            used[i] = used[j] = True
            keep_pairs.append((i, j))
    if not keep_pairs:
        return free
    pairs = np.array(keep_pairs, dtype=np.int64)
    points[pairs[:, 0]] = 0.5 * (points[pairs[:, 0]] + points[pairs[:, 1]])
    alive = np.ones(n, dtype=bool)
    alive[pairs[:, 1]] = False
    return points[n_fixed:][alive[n_fixed:]]


def _longest(xy: np.ndarray) -> np.ndarray:
    """The longest side of triangles (..., 3, 2)."""
    d = np.roll(xy, -1, axis=-2) - xy
    return np.sqrt(np.max(d[..., 0] ** 2 + d[..., 1] ** 2, axis=-1))


def _moved_min_angles(
    corner: np.ndarray, p1: np.ndarray, p2: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Smallest angle (degrees) of triangles ``(corner, p1, p2)`` and their longest side squared.

    ``-inf`` where a triangle is not counter-clockwise. The smallest angle is opposite the
    shortest side and acute, so it is ``arcsin(2 area / (b c))`` with ``b, c`` the other two
    sides: one arcsine per triangle, no angle at the other corners.
    """
    u, v = p1 - corner, p2 - corner
    w = p2 - p1
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    lu = u[:, 0] ** 2 + u[:, 1] ** 2
    lv = v[:, 0] ** 2 + v[:, 1] ** 2
    lw = w[:, 0] ** 2 + w[:, 1] ** 2
    shortest = np.minimum(np.minimum(lu, lv), lw)
    with np.errstate(invalid="ignore", divide="ignore"):
        sine = cross / np.sqrt(lu * lv * lw / shortest)
    angle = np.degrees(np.arcsin(np.clip(np.nan_to_num(sine, nan=-1.0), -1.0, 1.0)))
    return np.where(cross > 0, angle, -np.inf), np.maximum(np.maximum(lu, lv), lw)


def _smooth(
    points: np.ndarray,
    mobile: np.ndarray,
    tri: np.ndarray,
    inside: Inside,
    wanted: np.ndarray | None = None,
) -> bool:
    """Steps of angle-based smoothing on a fixed triangulation, in place; whether any moved.

    Only ``mobile`` points whose worst angle is below :data:`WORK_BELOW` try to move, and
    only the triangles around them are measured. With ``wanted`` (the triangle side wanted at
    each point), no move makes a triangle's longest side pass :data:`SIDE_CAP` times the
    smallest wanted at its corners (or its longest side before, if longer).
    """
    n = len(points)
    corner = tri.ravel()
    # The triangles around every mobile point, grouped by point (rows sorted by owner).
    order = np.argsort(corner, kind="stable")
    owner_all = corner[order]
    sel = mobile[owner_all]
    star_all, at_all, owner_all = order[sel] // 3, order[sel] % 3, owner_all[sel]
    if not owner_all.size:
        return False
    tie = ((np.arange(n, dtype=np.uint64) * np.uint64(2654435761)) % np.uint64(2**32)).astype(
        np.float64
    ) / 2**32
    cap2 = None if wanted is None else (SIDE_CAP * wanted[tri].min(axis=1)) ** 2
    moved = False
    for _ in range(_STEPS):
        p1 = points[tri[star_all, (at_all + 1) % 3]]
        p2 = points[tri[star_all, (at_all + 2) % 3]]
        q_all, longest_all = _moved_min_angles(points[owner_all], p1, p2)
        starts = np.flatnonzero(np.r_[True, owner_all[1:] != owner_all[:-1]])
        node_q = np.full(n, np.inf)
        node_q[owner_all[starts]] = np.minimum.reduceat(q_all, starts)
        active = mobile & (node_q < WORK_BELOW)
        rows_of = active[owner_all]
        if not rows_of.any():
            break
        star, owner = star_all[rows_of], owner_all[rows_of]
        p1, p2, q = p1[rows_of], p2[rows_of], q_all[rows_of]
        group = np.flatnonzero(np.r_[True, owner[1:] != owner[:-1]])
        movers = owner[group]
        # The apex of the equilateral triangle over each star triangle's far side.
        d = p2 - p1
        apex = 0.5 * (p1 + p2) + _SQRT3_2 * np.column_stack([-d[:, 1], d[:, 0]])
        size = np.diff(np.r_[group, len(owner)])
        mean = np.add.reduceat(apex, group, axis=0) / size[:, None]
        here = points[movers]
        # The apex over the far side of the mover's worst triangle (its first, in a tie).
        worst_row = np.flatnonzero(q <= node_q[owner])
        worst_row = worst_row[np.r_[True, owner[worst_row[1:]] != owner[worst_row[:-1]]]]
        worst_apex = apex[worst_row]
        reach = np.sqrt(np.maximum.reduceat(d[:, 0] ** 2 + d[:, 1] ** 2, group))
        limit2 = None if cap2 is None else np.maximum(cap2[star], longest_all[rows_of])
        candidates = [here + f * (mean - here) for f in (1.0, 0.5, 0.25)]
        candidates += [here + f * (worst_apex - here) for f in (0.5, 0.25, 0.1)]
        candidates += [here + _SMALL_STEP * reach[:, None] * u for u in _DIRECTIONS]
        slot = np.repeat(np.arange(len(movers)), size)
        before = node_q[movers]
        gain = np.zeros(len(movers))
        best = here.copy()
        for candidate in candidates:
            score, longest2 = _moved_min_angles(candidate[slot], p1, p2)
            if limit2 is not None:
                score[longest2 > limit2] = -np.inf
            after = np.minimum.reduceat(score, group)
            with np.errstate(invalid="ignore"):
                better = np.flatnonzero(after - before > gain + 1e-9)
            better = better[inside(candidate[better])]
            gain[better] = after[better] - before[better]
            best[better] = candidate[better]
        want = gain > 1e-6
        if not want.any():
            break
        # An independent set: in every triangle, only its worst point that wants to move.
        priority = np.full(n, -np.inf)
        priority[movers[want]] = -before[want] + 1e-3 * tie[movers[want]]
        top = np.full(n, -np.inf)
        np.maximum.at(top, corner, np.repeat(priority[tri].max(axis=1), 3))
        go = want & (priority[movers] >= top[movers])
        points[movers[go]] = best[go]
        moved = True
    return moved
