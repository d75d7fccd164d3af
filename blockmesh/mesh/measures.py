"""Cell measures of a pentagon mesh in one chunked pass: areas, angles, aspect, convexity.

:meth:`Mesh.quality <blockmesh.mesh.Mesh.quality>`, :attr:`Mesh.area <blockmesh.mesh.Mesh.area>`
and :meth:`Mesh.check_geometry <blockmesh.mesh.Mesh.check_geometry>` all read the same
:class:`CellMeasures`, computed once per mesh by :func:`measure_cells`.

How it is fast: cells are visited in chunks small enough for every temporary to stay in the CPU
caches, corner-major (one contiguous row per corner), and only differences of nearby points are
used (edge vectors and diagonals), so results do not depend on where the mesh lies. Three identities
avoid most of the per-corner work:

- the sine of a corner's turn satisfies ``sin^2 = cross^2 / (cross^2 + dot^2)`` (Lagrange's
  identity ``|a|^2 |b|^2 = (a.b)^2 + (a x b)^2``), so "every corner turns left by more than the
  tolerance" is ``cross > 0`` and ``|dot / cross| < K`` for all corners, without square roots;
- for left turns, ``dot / cross = cot(turn)`` decreases with the turn, so the smallest interior
  angle sits at the smallest ``dot / cross`` and the largest at the largest: ``arctan2`` runs
  for two corners per chunk, not for all of them;
- the shoelace area is ``2A = sum_k (x_k - x_0)(y_(k+1) - y_(k-1))``, whose second factors are
  the diagonals already needed for the diameter.

A chunk where any corner fails the fast test (a straight, reflex or degenerate corner, or
non-finite values) is measured again with the plain formulas of :mod:`blockmesh.geometry`, so
the counts of bad cells are exactly those formulas' counts.

Examples
--------
>>> import blockmesh
>>> m = measure_cells(blockmesh.load_domain("sp").mesh(1))
>>> round(m.min_angle, 1), round(m.max_angle, 1), m.not_strictly_convex, round(m.area, 12)
(56.3, 150.3, 0, 5.0)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from blockmesh._system.threads import run_parallel
from blockmesh.errors import ArgumentError
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    corner_sines,
    interior_angles,
    signed_area,
)

if TYPE_CHECKING:
    from blockmesh.mesh.mesh import Mesh

__all__ = [
    "CHUNK",
    "CellMeasures",
    "cell_shapes",
    "measure_cells",
    "signed_areas",
    "widest_id_spread",
]

#: Cells measured at once, with each thread's working arrays (about 480 bytes a cell) reused from
#: chunk to chunk (8192 was 1.2-1.4x faster than 2048 or 4096 here, and scales with threads).
CHUNK = 8192

#: ``|cot(turn)| < _COT_LIMIT`` means ``sin(turn) > COLLINEAR_SIN_TOL`` with a safety margin: a
#: corner closer to the tolerance than that is measured by the plain formula.
_COT_LIMIT = math.sqrt(1.0 / COLLINEAR_SIN_TOL**2 - 1.0) * (1.0 - 1e-6)


@dataclass(frozen=True)
class CellMeasures:
    """What one pass over the cells finds (angles in degrees).

    Attributes
    ----------
    area : float
        Sum of the cell areas.
    min_area, max_area : float
    min_angle, max_angle : float
        Smallest and largest interior angle over all corners.
    max_aspect_ratio : float
        Largest diameter**2 / area (``inf`` when a cell has no positive area).
    not_strictly_convex : int
        Cells with a corner whose turn has sine at most ``COLLINEAR_SIN_TOL``.
    invalid : int
        Cells that are not strictly convex or have no positive area (what
        :meth:`~blockmesh.mesh.Mesh.check_geometry` refuses).
    first_invalid : int
        The first such cell, or -1.
    bandwidth : int
        Largest difference between two node ids of one cell (see
        :meth:`~blockmesh.mesh.Mesh.bandwidth`), read in the same pass.
    """

    area: float
    min_area: float
    max_area: float
    min_angle: float
    max_angle: float
    max_aspect_ratio: float
    not_strictly_convex: int
    invalid: int
    first_invalid: int
    bandwidth: int


class _Accumulator:
    """Running extremes and sums over the chunks."""

    def __init__(self) -> None:
        self.area_sums: list[float] = []
        self.min_area, self.max_area = math.inf, -math.inf
        self.min_angle, self.max_angle = math.inf, -math.inf
        self.max_aspect = 0.0
        self.not_strictly_convex = 0
        self.invalid, self.first_invalid = 0, -1
        self.bandwidth = 0

    def add(self, start: int, areas, diam2, min_angle: float, max_angle: float, sharp) -> None:
        """Fold in one chunk; ``sharp`` None means every corner of it turns left enough.

        Extremes are read with ``argmin``/``argmax``, which let other threads run (NumPy's
        ``min``/``max`` reductions hold the interpreter lock here); NaN wins as in ``min``.
        """
        smallest = float(areas[np.argmin(areas)])
        self.area_sums.append(float(areas.sum()))
        self.min_area = min(self.min_area, smallest)
        self.max_area = max(self.max_area, float(areas[np.argmax(areas)]))
        self.min_angle = min(self.min_angle, min_angle)
        self.max_angle = max(self.max_angle, max_angle)
        if sharp is None and smallest > 0:  # the common case: no cell of the chunk is invalid
            aspect = np.divide(diam2, areas, out=diam2)
            self.max_aspect = max(self.max_aspect, float(aspect[np.argmax(aspect)]))
            return
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
        self.max_aspect = max(self.max_aspect, float(aspect.max()))
        if sharp is None:
            bad = ~(areas > 0)
        else:
            self.not_strictly_convex += int(np.count_nonzero(~sharp))
            bad = ~(sharp & (areas > 0))
        if np.any(bad):
            if self.first_invalid < 0:
                self.first_invalid = start + int(np.flatnonzero(bad)[0])
            self.invalid += int(np.count_nonzero(bad))

    @classmethod
    def merged(cls, parts: list[_Accumulator]) -> _Accumulator:
        """One accumulator for consecutive pieces measured apart, in order."""
        whole = cls()
        for part in parts:
            whole.area_sums += part.area_sums
            whole.min_area = min(whole.min_area, part.min_area)
            whole.max_area = max(whole.max_area, part.max_area)
            whole.min_angle = min(whole.min_angle, part.min_angle)
            whole.max_angle = max(whole.max_angle, part.max_angle)
            whole.max_aspect = max(whole.max_aspect, part.max_aspect)
            whole.not_strictly_convex += part.not_strictly_convex
            if whole.first_invalid < 0:
                whole.first_invalid = part.first_invalid
            whole.invalid += part.invalid
            whole.bandwidth = max(whole.bandwidth, part.bandwidth)
        return whole

    def result(self) -> CellMeasures:
        """The measures of every cell folded in."""
        return CellMeasures(
            area=math.fsum(self.area_sums),
            min_area=self.min_area,
            max_area=self.max_area,
            min_angle=self.min_angle,
            max_angle=self.max_angle,
            max_aspect_ratio=self.max_aspect,
            not_strictly_convex=self.not_strictly_convex,
            invalid=self.invalid,
            first_invalid=self.first_invalid,
            bandwidth=self.bandwidth,
        )


def _plain_chunk(points: np.ndarray, cells: np.ndarray, start: int, acc: _Accumulator) -> None:
    """The chunk measured with the plain formulas (corners relative to each cell's first)."""
    xy = points[cells]
    xy -= xy[:, :1]
    angles = interior_angles(xy)
    areas = signed_area(xy)
    diff = xy[:, :, None, :] - xy[:, None, :, :]
    diam2 = np.max(np.einsum("mijk,mijk->mij", diff, diff), axis=(1, 2))
    sines = np.nan_to_num(corner_sines(xy), nan=-1.0)
    sharp = np.all(sines > COLLINEAR_SIN_TOL, axis=1)
    acc.add(start, areas, diam2, float(angles.min()), float(angles.max()), sharp)


#: Chunks measured by one worker thread at a time.
_CHUNKS_PER_PIECE = 32


def measure_cells(
    mesh: Mesh,
    *,
    chunk: int = CHUNK,
    progress: Callable[[int, int], None] | None = None,
    threads: int | None = None,
) -> CellMeasures:
    """Areas, angles, aspect ratios and convexity of every cell, in one pass of ``chunk`` cells.

    O(M) time; memory O(chunk) per thread besides the mesh. Pieces of 32 chunks are shared by
    ``threads`` worker threads (default :func:`blockmesh._system.threads.default_threads`), each
    with its own working arrays (nothing is allocated per chunk, which is what lets threads help);
    the result does not depend on their number. ``progress(done, total)`` is called with the cells
    measured so far as pieces finish.

    Examples
    --------
    >>> import blockmesh
    >>> m = measure_cells(blockmesh.load_domain("square-cut").mesh(3))
    >>> m.invalid, m.first_invalid, round(m.area, 12)
    (0, -1, 0.875)
    """
    n_cells = mesh.n_cells
    if n_cells == 0:
        return CellMeasures(0.0, math.inf, -math.inf, math.inf, -math.inf, 0.0, 0, 0, -1, 0)
    chunk = min(chunk, n_cells)
    step = chunk * _CHUNKS_PER_PIECE
    pieces = [(start, min(start + step, n_cells)) for start in range(0, n_cells, step)]
    done = [0]

    def finished(k: int, _: _Accumulator) -> None:
        if progress is not None:
            done[0] += pieces[k][1] - pieces[k][0]
            progress(done[0], n_cells)

    parts = run_parallel(
        lambda piece, work: _measure_piece(mesh, piece, work),
        pieces,
        threads=threads,
        workspace=lambda: _Workspace(chunk),
        finished=finished,
    )
    return _Accumulator.merged(parts).result()


class _Workspace:
    """One thread's working arrays for chunks of up to ``chunk`` cells.

    Flat, and reshaped for each chunk, so that every view is contiguous.
    """

    def __init__(self, chunk: int) -> None:
        self.chunk = chunk
        self.z = np.empty(5 * chunk, dtype=np.complex128)
        self.b = np.empty(14 * chunk)
        self.edges = np.empty(12 * chunk)
        self.diagonals = np.empty(10 * chunk)
        self.cross = np.empty(5 * chunk)
        self.dot = np.empty(5 * chunk)
        self.scratch = np.empty(5 * chunk)
        self.areas = np.empty(chunk)
        self.diam2 = np.empty(chunk)
        self.ids = np.empty(2 * chunk, dtype=np.int64)
        self.corner_ids = np.empty(5 * chunk, dtype=np.int64)


def widest_id_spread(columns: np.ndarray, out: np.ndarray | None = None) -> int:
    """The largest difference between two ids of one cell; ``columns`` (5, m): corner k's ids.

    The bandwidth of a numbering over these cells (:meth:`blockmesh.mesh.Mesh.bandwidth`).
    ``out`` (2, m) int64, when given, holds the temporaries (nothing is allocated).

    Examples
    --------
    >>> widest_id_spread(np.array([[0, 7], [1, 9], [2, 8], [3, 3], [4, 5]]))
    6
    """
    m = columns.shape[1]
    if m == 0:
        return 0
    high, low = np.empty((2, m), dtype=np.int64) if out is None else out
    np.maximum(columns[0], columns[1], out=high)
    np.minimum(columns[0], columns[1], out=low)
    for k in range(2, 5):
        np.maximum(high, columns[k], out=high)
        np.minimum(low, columns[k], out=low)
    high -= low
    return int(high[np.argmax(high)])


def signed_areas(
    points: np.ndarray, cells: np.ndarray, out: np.ndarray | None = None
) -> np.ndarray:
    """Signed area of every pentagon (positive when counter-clockwise), shape (m,).

    The numbers of :func:`blockmesh.geometry.signed_area` bit for bit (the shoelace formula
    relative to each cell's first corner, the same operations in the same order), computed
    corner-major in chunks of :data:`CHUNK` cells, so that the temporaries stay in the caches
    (about 12x faster than the (m, 5, 2) formulation on a million cells). ``cells`` (m, 5) must
    hold valid ids of ``points``; ``out`` (m,) float64, when given, receives the areas.

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 0.5], [1, 1], [0, 1]], dtype=float) + 1e9
    >>> signed_areas(square, np.array([[0, 1, 2, 3, 4], [4, 3, 2, 1, 0]])).tolist()
    [1.0, -1.0]
    """
    if cells.ndim != 2 or cells.shape[1] != 5:
        raise ArgumentError(
            f"signed_areas needs pentagons, cells of shape (m, 5); got shape {cells.shape}"
        )
    m_all = cells.shape[0]
    areas = np.empty(m_all) if out is None else out
    z_points = np.ascontiguousarray(points, dtype=np.float64).view(np.complex128).reshape(-1)
    chunk = max(1, min(CHUNK, m_all))
    columns = np.empty((5, chunk), dtype=np.int64)
    z = np.empty((5, chunk), dtype=np.complex128)
    local = np.empty((2, 5, chunk))
    terms = np.empty((2, 3, chunk))
    for start in range(0, m_all, chunk):
        m = min(chunk, m_all - start)
        ids = columns[:, :m]
        np.copyto(ids, cells[start : start + m].T)
        corners = np.take(z_points, ids, mode="clip", out=z[:, :m])
        x, y = local[:, :, :m]
        np.subtract(corners.real, corners.real[:1], out=x)
        np.subtract(corners.imag, corners.imag[:1], out=y)
        # Twice the area: sum over k = 1..3 of x_k y_(k+1) - x_(k+1) y_k (corner 0 is the origin).
        cross = np.multiply(x[1:4], y[2:5], out=terms[0, :, :m])
        cross -= np.multiply(x[2:5], y[1:4], out=terms[1, :, :m])
        part = np.add(cross[0], cross[1], out=areas[start : start + m])
        part += cross[2]
        part *= 0.5
    return areas


def _measure_piece(mesh: Mesh, piece: tuple[int, int], work: _Workspace) -> _Accumulator:
    """The measures of cells ``piece[0] .. piece[1]-1``, chunk by chunk, in ``work``'s arrays.

    The fast formulas (see the module's docstring); a chunk where a corner fails their test is
    measured with the plain ones.
    """
    acc = _Accumulator()
    z_points = mesh.points.view(np.complex128).reshape(-1)
    with np.errstate(all="ignore"):  # overflow and 0/0 fail the fast test: plain formulas
        for start in range(piece[0], piece[1], work.chunk):
            cells = mesh.cells[start : min(start + work.chunk, piece[1])]
            m = cells.shape[0]
            # Corner-major, contiguous: np.take would copy a strided index array every time.
            columns = work.corner_ids[: 5 * m].reshape(5, m)
            np.copyto(columns, cells.T)
            spread = widest_id_spread(columns, work.ids[: 2 * m].reshape(2, m))
            acc.bandwidth = max(acc.bandwidth, spread)
            # (5, m); the ids were checked by the Mesh.
            z = np.take(z_points, columns, mode="clip", out=work.z[: 5 * m].reshape(5, m))
            # b[:, j] = corner j mod 5 (x then y), so that every edge and diagonal is one slice.
            b = work.b[: 14 * m].reshape(2, 7, m)
            b[0, :5] = z.real
            b[1, :5] = z.imag
            b[:, 5:] = b[:, :2]
            # (2, 6, m): corner j to j+1, edge 5 is edge 0 again; (2, 5, m): corner j to j+2.
            edges = np.subtract(b[:, 1:], b[:, :-1], out=work.edges[: 12 * m].reshape(2, 6, m))
            diagonals = np.subtract(
                b[:, 2:], b[:, :-2], out=work.diagonals[: 10 * m].reshape(2, 5, m)
            )
            ex, ey = edges
            scratch = work.scratch[: 5 * m].reshape(5, m)
            # Corners 1..4, 0: incoming edge j, outgoing edge j+1.
            cross = np.multiply(ex[:-1], ey[1:], out=work.cross[: 5 * m].reshape(5, m))
            cross -= np.multiply(ey[:-1], ex[1:], out=scratch)
            if not cross.flat[np.argmin(cross)] > 0:  # argmin: NaN is found, as by min
                _plain_chunk(mesh.points, cells, start, acc)
                continue
            dot = np.multiply(ex[:-1], ex[1:], out=work.dot[: 5 * m].reshape(5, m))
            dot += np.multiply(ey[:-1], ey[1:], out=scratch)
            cot = np.divide(dot, cross, out=scratch)
            low, high = int(np.argmin(cot)), int(np.argmax(cot))
            if not (cot.flat[low] > -_COT_LIMIT and cot.flat[high] < _COT_LIMIT):
                _plain_chunk(mesh.points, cells, start, acc)
                continue
            # 2A = sum_k (x_k - x_0)(y_(k+1) - y_(k-1)), k = 1..4.
            terms = np.subtract(b[0, 1:5], b[0, :1], out=scratch[:4])
            terms *= diagonals[1, :4]
            areas = np.add(terms[0], terms[1], out=work.areas[:m])
            areas += terms[2]
            areas += terms[3]
            areas *= 0.5
            # The diameter: the longest edge or diagonal. (Element-wise ufuncs rather than
            # reductions along an axis, which hold the interpreter lock.)
            edges *= edges
            diagonals *= diagonals
            lengths = np.add(edges[0, 1:], edges[1, 1:], out=scratch)
            diam2 = np.maximum(lengths[0], lengths[1], out=work.diam2[:m])
            for k in range(2, 5):
                np.maximum(diam2, lengths[k], out=diam2)
            lengths = np.add(diagonals[0], diagonals[1], out=scratch)
            for k in range(5):
                np.maximum(diam2, lengths[k], out=diam2)
            # The largest cot is the smallest turn: the largest interior angle; and vice versa.
            turn = np.arctan2(cross.flat[[low, high]], dot.flat[[low, high]])
            min_angle, max_angle = (180.0 - np.degrees(turn)).tolist()
            acc.add(start, areas, diam2, min_angle, max_angle, None)
    return acc


def cell_shapes(mesh: Mesh, *, chunk: int = 1 << 16) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Interior angles (5, m) in degrees and aspect ratios (m,) of the cells, chunk by chunk.

    For histograms of the whole mesh in bounded memory (``plot_quality``). Aspect ratio is
    diameter**2 / area, ``inf`` where a cell has no positive area.

    Examples
    --------
    >>> import blockmesh
    >>> angles, aspect = next(cell_shapes(blockmesh.load_domain("sp").mesh(0)))
    >>> angles.round(1).ravel().tolist(), aspect.round(3).tolist()
    ([135.0, 135.0, 71.6, 126.9, 71.6], [3.2])
    """
    z_points = mesh.points.view(np.complex128).reshape(-1)
    for start in range(0, mesh.n_cells, chunk):
        z = np.take(z_points, mesh.cells[start : start + chunk].T, mode="clip")  # (5, m)
        edges = np.roll(z, -1, axis=0) - z  # edge k from corner k to k + 1
        turn = edges * np.roll(edges, 1, axis=0).conj()  # at corner k: incoming edge k - 1
        angles = 180.0 - np.degrees(np.angle(turn))
        local = z[1:] - z[0]
        areas = 0.5 * (local[:-1].conj() * local[1:]).imag.sum(axis=0)
        diam2 = np.max(np.abs(z[:, None, :] - z[None, :, :]) ** 2, axis=(0, 1))
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
        yield angles, aspect
