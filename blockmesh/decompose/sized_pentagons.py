"""Pentagons on the triangles of the sized decomposition: templates, bent onto curves, placed.

Step 6 of :mod:`blockmesh.decompose.sized`: every triangle becomes nine pentagons by the balanced
template (:data:`~blockmesh.decompose.templates.BALANCED_SECTOR_WEIGHTS`), graded where the
field varies, side nodes shared bit for bit; triangles with a side on a curve are bent with it
(a transfinite map); and the nodes on chains are put at their exact places, those on straight
chains free to slide along them.
"""

from __future__ import annotations

import numpy as np

from blockmesh.decompose.outline import Outline, _chain_points, _Chains
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.templates import BALANCED_SECTOR_WEIGHTS, EDGE_FRACTIONS
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL, corner_sines

__all__: list[str] = []


def _pentagons(chains: _Chains, points: np.ndarray, triangles: np.ndarray, weight: np.ndarray):
    """Balanced templates on the triangles, graded; the node chains and their parameters.

    The template's nodes are placed by barycentric weights on the triangle's corners; each
    weight is scaled by the corner's ``weight`` (``L^(-1/2)``, ``L`` the triangle side wanted
    there) and the three renormalised, so the cells near a corner asking smaller cells come out
    smaller: to first order, cells proportional to a linearly varying ``L``. A node on a side
    depends only on that side's two corners, so neighbours still share it.
    """
    pieces = pentagons_from_pieces(points, [triangles], BALANCED_SECTOR_WEIGHTS)
    nodes = np.array(pieces.nodes)
    count = len(triangles)
    first_new = len(points) + 2 * len(pieces.side_keys)
    sides = pieces.side_chains(triangles.ravel(), np.roll(triangles, -1, axis=1).ravel())
    ids = np.concatenate(
        [
            sides[:, 1:3].reshape(count, 6),
            first_new + 10 * np.arange(count)[:, None] + np.arange(10),
        ],
        axis=1,
    )
    corner = points[triangles]  # (T, 3, 2)
    matrix = np.stack([corner[:, 0] - corner[:, 2], corner[:, 1] - corner[:, 2]], axis=2)
    lam = np.linalg.solve(matrix[:, None], (nodes[ids] - corner[:, None, 2])[..., None])[..., 0]
    lam = np.concatenate([lam, 1.0 - lam.sum(axis=2, keepdims=True)], axis=2)
    mu = lam * weight[triangles][:, None, :]
    mu /= mu.sum(axis=2, keepdims=True)
    nodes[ids] = np.einsum("tnk,tkd->tnd", mu, corner)
    n_chains = len(chains.outline.chains)
    along = pieces.side_chains(chains.a, chains.b)  # (S, 4): a, two side nodes, b
    wa, wb = weight[chains.a], weight[chains.b]
    f1, f2 = EDGE_FRACTIONS
    g1 = f1 * wb / ((1 - f1) * wa + f1 * wb)
    g2 = f2 * wb / ((1 - f2) * wa + f2 * wb)
    span = chains.t1 - chains.t0
    t_side = np.column_stack([chains.t0, chains.t0 + g1 * span, chains.t0 + g2 * span, chains.t1])
    order = np.lexsort((chains.t0, chains.chain))
    bounds = np.searchsorted(chains.chain[order], np.arange(n_chains + 1))
    chain_nodes, chain_params = [], []
    for c in range(n_chains):
        run = order[bounds[c] : bounds[c + 1]]
        chain_nodes.append(np.concatenate([along[run, :3].ravel(), along[run[-1:], 3]]))
        chain_params.append(np.concatenate([t_side[run, :3].ravel(), t_side[run[-1:], 3]]))
    return pieces, nodes, chain_nodes, chain_params


def _bend(
    chains: _Chains,
    frame,
    pieces,
    nodes: np.ndarray,
    points: np.ndarray,
    triangles: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Template nodes of triangles with a side on a curve, moved with the curve.

    A triangle ``(A, B, C)`` whose side ``AB`` is a chord of curve ``γ`` is mapped by the
    transfinite (Gordon-Hall) map ``x + (λA + λB) (γ(t) - ((1 - t) A + t B))``,
    ``t = λB / (λA + λB)``, with ``λ`` the barycentric coordinates of the straight node: the
    nodes on ``AB`` land on the curve, those on the other sides stay (their neighbours across
    share them), and the inner nodes follow, so the cells keep their shapes. Triangles with two
    curved sides take both displacements. Where the full displacement of the inner nodes would
    fold a cell (a flat triangle on a strongly curved piece), they move less; the triangles
    that fold even so are returned, for their chain segment to be split.
    """
    curved = np.array([c is not None for c in chains.outline.curves], dtype=bool)
    segments = np.flatnonzero(curved[chains.chain])
    if not segments.size:
        return nodes, np.zeros(0, dtype=np.int64)
    n = len(points)
    # The triangles on either side of each curved segment, and which corner is off it.
    keys = np.minimum(triangles, np.roll(triangles, -1, axis=1)) * n + np.maximum(
        triangles, np.roll(triangles, -1, axis=1)
    )
    seg_keys = np.minimum(chains.a[segments], chains.b[segments]) * n + np.maximum(
        chains.a[segments], chains.b[segments]
    )
    tri, side = np.nonzero(np.isin(keys, seg_keys))
    which = segments[np.argsort(seg_keys)][np.searchsorted(np.sort(seg_keys), keys[tri, side])]
    per_piece = 10  # the hub and nine inner nodes of a triangle's template
    first_new = len(points) + 2 * len(pieces.side_keys)
    # Each bent triangle's nodes, their displacement, and whether they are on its curved side.
    bent: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
    for t, k, c in zip(tri.tolist(), side.tolist(), which.tolist(), strict=True):
        corners = triangles[t]
        a_id, b_id = corners[k], corners[(k + 1) % 3]
        ends = {int(chains.a[c]): 0.0, int(chains.b[c]): 1.0}
        own = np.concatenate(
            [
                pieces.side_chains(corners, np.roll(corners, -1))[:, 1:3].ravel(),
                first_new + per_piece * t + np.arange(per_piece),
            ]
        )
        A, B, C = points[a_id], points[b_id], points[corners[(k + 2) % 3]]
        matrix = np.column_stack([A - C, B - C])
        lam = np.linalg.solve(matrix, (nodes[own] - C).T).T
        on = lam[:, 0] + lam[:, 1]
        t_side = np.where(on > 1e-12, lam[:, 1] / np.maximum(on, 1e-300), 0.0)
        # Chain parameter along the segment from a_id to b_id.
        s0, s1 = ends[int(a_id)], ends[int(b_id)]
        param = chains.t0[c] + (s0 + t_side * (s1 - s0)) * (chains.t1[c] - chains.t0[c])
        curve = _chain_points(
            chains.outline, int(chains.chain[c]), np.concatenate([[0.0], param, [1.0]])
        )[1:-1]
        chord = (1 - t_side)[:, None] * A + t_side[:, None] * B
        shift = on[:, None] * (frame.to_local(curve) - chord)
        if t in bent:
            ids, before, side_of = bent[t]
            bent[t] = (ids, before + shift, side_of | (on > 1 - 1e-9))
        else:
            bent[t] = (own, shift, on > 1 - 1e-9)
    # Inner nodes move by the full displacement, or less where that would fold a cell.
    moved = nodes.copy()
    folded = []
    for t, (ids, shift, side_of) in bent.items():
        rows = pieces.blocks[9 * t : 9 * t + 9]
        for factor in (1.0, 0.6, 0.3, 0.0):
            moved[ids] = nodes[ids] + np.where(side_of[:, None], shift, factor * shift)
            if np.all(corner_sines(moved[rows]) > 1e3 * COLLINEAR_SIN_TOL):
                break
        else:
            folded.append(t)
    return moved, np.array(folded, dtype=np.int64)


def _place_on_outline(
    outline: Outline,
    frame,
    nodes: np.ndarray,
    chain_nodes: list[np.ndarray],
    chain_params: list[np.ndarray],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes on chains at their exact places; which nodes are fixed and which slide."""
    fixed = np.zeros(len(nodes), dtype=bool)
    slide = np.zeros((len(nodes), 2))
    fixed[: len(outline.corners)] = True
    exact = np.zeros((len(nodes), 2))
    has_exact = np.zeros(len(nodes), dtype=bool)
    for c, (ids, params) in enumerate(zip(chain_nodes, chain_params, strict=True)):
        xy = _chain_points(outline, c, params)
        exact[ids] = xy
        has_exact[ids] = True
        inner = ids[1:-1]
        if outline.curves[c] is not None:
            fixed[inner] = True
        else:
            d = nodes[ids[-1]] - nodes[ids[0]]
            slide[inner] = d / np.hypot(*d)
    nodes[has_exact] = frame.to_local(exact[has_exact])
    return nodes, fixed, slide
