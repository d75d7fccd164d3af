"""Pictures of domains and meshes (matplotlib, Agg backend, imported only when drawing).

Examples
--------
>>> import tempfile, pathlib, blockmesh
>>> with tempfile.TemporaryDirectory() as tmp:
...     path = plot_domain(blockmesh.load_domain("square-cut"), pathlib.Path(tmp) / "d.png")
...     path.stat().st_size > 0
True
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.atomic import atomic_file
from blockmesh.checks import choice
from blockmesh.errors import ExportError
from blockmesh.geometry.polygons import signed_area
from blockmesh.geometry.topology import cell_neighbours
from blockmesh.mesh.measures import cell_shapes
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.sizes import DRAW_LIMIT

__all__ = [
    "DRAW_LIMIT",
    "LABELS",
    "LABEL_LIMIT",
    "domain_figure",
    "mesh_figure",
    "plot_domain",
    "plot_mesh",
    "plot_quality",
    "pyplot",
    "save_figure",
]

#: Meshes with at most this many cells get node and cell numbers (like the paper's Figs. 2-4).
LABEL_LIMIT = 400
#: Which blocks :func:`plot_domain` numbers: those whose number fits inside them (``"auto"``),
#: every block, or none.
LABELS = ("auto", "all", "none")
#: Pixels across the longer side of the cell-density picture (fewer when the largest cells
#: are bigger than such a pixel).
DENSITY_PIXELS = 800
_PATCH_COLOURS = ("#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2")
_REGION_SHADES = ("#f2f2f2", "#fde9c9", "#dff0d8", "#dbe9f6", "#f4dcec", "#e8e1f3")


def pyplot():
    """matplotlib.pyplot on the Agg backend (no screen needed), imported on first use."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path: str | Path, *, dpi: int = 150) -> Path:
    """Write ``fig`` to a .png, .pdf or .svg file atomically, then close it."""
    path = Path(path)
    kind = path.suffix.lower()[1:]
    try:
        if kind not in {"png", "pdf", "svg"}:
            raise ExportError(f"cannot draw {path}: pictures are .png, .pdf or .svg files")
        with atomic_file(path) as temporary:
            fig.savefig(temporary, format=kind, dpi=dpi, bbox_inches="tight")
    finally:
        pyplot().close(fig)
    return path


def _draw_patches(ax, points, edges, patch, names, curves=None) -> None:
    from matplotlib.collections import LineCollection

    for k, name in enumerate(names):
        mine = edges[patch == k]
        segments = (
            points[mine] if not curves else [_edge_path(points, a, b, curves) for a, b in mine]
        )
        if len(segments):
            colour = _PATCH_COLOURS[k % len(_PATCH_COLOURS)]
            ax.add_collection(LineCollection(segments, colors=colour, linewidths=2.5, label=name))


def _draw_interfaces(ax, points, edges, curves=None) -> None:
    """The interfaces of a composite domain: dark lines, one legend entry."""
    from matplotlib.collections import LineCollection

    if len(edges) == 0:
        return
    segments = points[edges] if not curves else [_edge_path(points, a, b, curves) for a, b in edges]
    ax.add_collection(LineCollection(segments, colors="k", linewidths=1.8, label="interfaces"))


def _bounds(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lowest and highest x and y (column by column: ``min(axis=0)`` on (N, 2) is far slower)."""
    lo = np.array([points[:, 0].min(initial=np.inf), points[:, 1].min(initial=np.inf)])
    hi = np.array([points[:, 0].max(initial=-np.inf), points[:, 1].max(initial=-np.inf)])
    return lo, hi


def _frame(ax, points, title: str) -> None:
    lo, hi = _bounds(points)
    pad = 0.04 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_title(title)


#: Points per curved edge when a domain's curves are drawn.
_CURVE_SAMPLES = 24


def _edge_path(points, a: int, b: int, curves) -> np.ndarray:
    """The edge from vertex ``a`` to ``b`` as a polyline: its curve sampled, or the segment."""
    t = np.linspace(0.0, 1.0, _CURVE_SAMPLES + 1)
    if (a, b) in curves:
        return curves[(a, b)].point(t)
    if (b, a) in curves:
        return curves[(b, a)].point(1 - t)
    return points[[a, b]]


def _block_outlines(domain) -> list[np.ndarray]:
    """Every block's outline, its curved edges sampled."""
    outlines = []
    for block in domain.blocks.tolist():
        pieces = [
            _edge_path(domain.vertices, block[k], block[(k + 1) % 5], domain.curves)[:-1]
            for k in range(5)
        ]
        outlines.append(np.vstack(pieces))
    return outlines


def plot_domain(domain, path: str | Path, *, labels: str = "auto") -> Path:
    """Draw the blocks (numbered), vertices (numbered) and patches (coloured, with a legend).

    Regions are shaded (with a legend of their names) and interfaces drawn dark. ``labels`` says
    which blocks are numbered (:data:`LABELS`): by default those whose number fits inside the
    block as drawn, so that no two numbers overlap (at 2,000 blocks most would); vertices are
    numbered up to 150 of them. Returns the path written.
    """
    return save_figure(domain_figure(domain, labels=labels), path)


def domain_figure(domain, *, labels: str = "auto"):
    """The matplotlib Figure :func:`plot_domain` saves (close it with ``pyplot().close``)."""
    from matplotlib.collections import PolyCollection

    choice(labels, LABELS, "labels")
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 7))
    xy = domain.vertices[domain.blocks]
    shades = [_REGION_SHADES[r % len(_REGION_SHADES)] for r in domain.region]
    outlines = _block_outlines(domain) if domain.curves else xy
    ax.add_collection(
        PolyCollection(outlines, facecolors=shades, edgecolors="0.35", linewidths=1.0)
    )
    _draw_patches(
        ax,
        domain.vertices,
        domain.boundary_edges,
        domain.boundary_patch,
        domain.patch_names,
        domain.curves,
    )
    _draw_interfaces(ax, domain.vertices, domain.interface_edges, domain.curves)
    dot = 3 if domain.n_vertices <= 500 else 1  # many vertices: dots that do not merge
    ax.plot(domain.vertices[:, 0], domain.vertices[:, 1], "o", ms=dot, color="k")
    if domain.n_vertices <= 150:
        for v, (x, y) in enumerate(domain.vertices):
            ax.annotate(
                str(v), (x, y), xytext=(3, 3), textcoords="offset points", fontsize=7, color="b"
            )
    ax.legend(title="patches", loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    if len(domain.region_names) > 1:
        from matplotlib.patches import Patch

        handles = [
            Patch(facecolor=_REGION_SHADES[k % len(_REGION_SHADES)], edgecolor="0.35", label=n)
            for k, n in enumerate(domain.region_names)
        ]
        fig.legend(handles=handles, title="regions", loc="lower left", bbox_to_anchor=(0.91, 0.1))
    _frame(ax, domain.vertices, "")
    size = 11 if domain.n_blocks <= 30 else 7
    centres = xy.mean(axis=1)
    numbered = np.full(domain.n_blocks, labels == "all")
    if labels == "auto":
        numbered = _labels_fit(ax, xy, centres, size)
    for b in np.flatnonzero(numbered).tolist():
        x, y = centres[b]
        ax.text(x, y, str(b), ha="center", va="center", fontsize=size, weight="bold", color="0.2")
    shown = int(np.count_nonzero(numbered))
    which = (
        "blocks bold"
        if shown == domain.n_blocks
        else f"numbers where they fit: {shown:,} of {domain.n_blocks:,} blocks"
        if labels == "auto"
        else "block numbers off"
    )
    ax.set_title(
        f"{domain.name}: {domain.n_blocks:,} blocks, {domain.n_vertices:,} vertices "
        f"({which}{', vertices blue' if domain.n_vertices <= 150 else ''})"
    )
    return fig


def _labels_fit(ax, polygons: np.ndarray, centres: np.ndarray, size: float) -> np.ndarray:
    """Which polygons (B, 5, 2), drawn in ``ax``, hold their number's box around their centre.

    The box of a bold number is about 0.7 em wide per digit and 1.2 em high (DejaVu Sans); it
    fits when its four corners are inside the convex polygon on the screen, so numbers that fit
    never overlap one another.
    """
    ax.apply_aspect()
    to_screen = ax.transData.transform
    corners = to_screen(polygons.reshape(-1, 2)).reshape(polygons.shape)
    middle = to_screen(centres)
    em = size * ax.figure.dpi / 72.0
    digits = np.char.str_len(np.arange(polygons.shape[0]).astype(str))
    half = np.stack([0.35 * em * digits, np.full(digits.shape, 0.6 * em)], axis=1)
    signs = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    box = middle[:, None, :] + signs[None] * half[:, None, :]  # (B, 4, 2)
    start = corners[:, None, :, :]  # (B, 1, 5, 2) against every box corner
    edge = np.roll(corners, -1, axis=1)[:, None] - start
    to_box = box[:, :, None, :] - start
    turn = edge[..., 0] * to_box[..., 1] - edge[..., 1] * to_box[..., 0]
    return np.all(turn > 0, axis=(1, 2))


def plot_mesh(mesh, path: str | Path, *, labels: bool | None = None) -> Path:
    """Draw the cells (shaded by block or region), the patches, and numbers when few enough.

    ``labels=None`` numbers nodes (blue) and cells (black) when there are at most
    ``LABEL_LIMIT`` cells. A mesh with more than one region colours each region, outlines the
    blocks, draws its interfaces dark and lists the regions in a legend. A mesh of more than
    ``DRAW_LIMIT`` cells is drawn as its cell density (cells per unit area, a colour picture of
    ``DENSITY_PIXELS`` across) with the block outlines, the patches and the interfaces, and the
    title says so; that takes about a second per few million cells.
    """
    return save_figure(mesh_figure(mesh, labels=labels), path)


def mesh_figure(mesh, *, labels: bool | None = None):
    """The matplotlib Figure :func:`plot_mesh` saves (close it with ``pyplot().close``)."""
    if mesh.n_cells > DRAW_LIMIT:
        return _density_figure(mesh)
    from matplotlib.collections import LineCollection, PolyCollection

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 8))
    polygons = isinstance(mesh, PolygonMesh)
    if polygons:
        xy: Any = [mesh.points[c] for c in mesh.cell_lists()]
        centres = mesh.vertex_means()
    else:
        xy = mesh.points[mesh.cells]
        centres = xy.mean(axis=1)
    regions = np.unique(mesh.region)
    if regions.size > 1:
        palette = plt.get_cmap("Set3")
        faces = palette(mesh.region % palette.N)
    else:
        n_blocks = int(mesh.block_id.max()) + 1 if mesh.n_cells else 1
        palette = plt.get_cmap("Pastel1" if n_blocks <= 9 else "tab20")
        faces = palette((mesh.block_id % palette.N) / max(palette.N - 1, 1))
    width = 0.8 if mesh.n_cells <= 5000 else 0.3 if mesh.n_cells <= 50000 else 0.1
    ax.add_collection(PolyCollection(xy, facecolors=faces, edgecolors="0.25", linewidths=width))
    if regions.size > 1:
        from matplotlib.patches import Patch

        if int(mesh.block_id.max(initial=0)) > int(mesh.block_id.min(initial=0)):
            outline = mesh.points[_block_interfaces(mesh)]
            dark = mesh.interface_edges.shape[0] == 0  # else the interfaces are the dark lines
            ax.add_collection(
                LineCollection(outline, colors="0.1" if dark else "0.45", linewidths=1.2)
            )
        handles = [
            Patch(facecolor=palette(k % palette.N), edgecolor="0.25", label=mesh.region_names[k])
            for k in regions.tolist()
        ]
        fig.legend(handles=handles, title="regions", loc="lower left", bbox_to_anchor=(0.91, 0.1))
    _draw_patches(ax, mesh.points, mesh.boundary_edges, mesh.boundary_patch, mesh.patch_names)
    _draw_interfaces(ax, mesh.points, mesh.interface_edges)
    if polygons and mesh.n_cells <= 20000:
        hanging = mesh.points[mesh.hanging_nodes()]
        if hanging.size:
            ax.plot(*hanging.T, "o", ms=2.0 if mesh.n_cells <= 2000 else 1.0, color="#c44e52",
                    label="hanging nodes")  # fmt: skip
    if labels is None:
        labels = mesh.n_cells <= LABEL_LIMIT
    if labels:
        size = 8 if mesh.n_cells <= 40 else 5 if mesh.n_cells <= 250 else 3.5
        for c, (x, y) in enumerate(centres):
            ax.text(x, y, str(c), ha="center", va="center", fontsize=size, color="k")
        for v, (x, y) in enumerate(mesh.points):
            ax.text(x, y, str(v), ha="left", va="bottom", fontsize=size * 0.85, color="b")
    ax.legend(title="patches", loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    _frame(
        ax,
        mesh.points,
        f"{mesh.name or 'mesh'}, level {mesh.level}: {mesh.n_cells:,} cells, "
        f"{mesh.n_points:,} nodes",
    )
    return fig


def _block_interfaces(mesh) -> np.ndarray:
    """Cell edges (E, 2) between cells of different blocks, each listed once or twice.

    A node is on an interface when cells of two blocks use it; an edge is drawn when both its
    ends are (refinement never joins two such nodes across a block's inside). O(M + B N) with a
    mask per block for up to 64 blocks (each a contiguous run of cells after refinement), O(M)
    scattered minima and maxima otherwise.
    """
    block_id = mesh.block_id
    if isinstance(mesh, PolygonMesh):  # the edges whose two cells lie in different blocks
        cells = mesh.polygon_cells()
        across = cell_neighbours(cells, mesh.n_points)
        owner = cells.slot_cell()
        apart = (across >= 0) & (block_id[owner] != block_id[owner[np.maximum(across, 0)]])
        return np.stack([mesh.nodes[apart], cells.following()[apart]], axis=1)
    ordered = bool(np.all(block_id[1:] >= block_id[:-1]))
    blocks = np.unique(
        block_id[np.r_[True, block_id[1:] != block_id[:-1]]] if ordered else block_id
    )
    if blocks.size <= 64:
        used = np.zeros(mesh.n_points, dtype=bool)
        shared = np.zeros(mesh.n_points, dtype=bool)
        mine = np.zeros(mesh.n_points, dtype=bool)
        edges = np.asarray(np.searchsorted(block_id, np.r_[blocks, blocks[-1] + 1]))
        bounds = [int(b) for b in edges.ravel()]
        for k, block in enumerate(blocks):
            mine[:] = False
            if ordered:
                mine[mesh.cells[bounds[k] : bounds[k + 1]]] = True
            else:
                mine[mesh.cells[block_id == block]] = True
            shared |= mine & used
            used |= mine
    else:
        lowest = np.full(mesh.n_points, np.iinfo(np.int64).max)
        highest = np.full(mesh.n_points, -1)
        np.minimum.at(lowest, mesh.cells, block_id[:, None])
        np.maximum.at(highest, mesh.cells, block_id[:, None])
        shared = lowest != highest
    # Only cells with an interface node can have an interface edge.
    near = np.flatnonzero(np.any(shared[mesh.cells], axis=1))
    start = mesh.cells[near]
    stop = start[:, [1, 2, 3, 4, 0]]
    both = shared[start] & shared[stop]
    return np.stack([start[both], stop[both]], axis=1)


def _largest_area(mesh) -> float:
    """The largest cell area: measured if the mesh has been, else from a sample of cells."""
    if isinstance(mesh, PolygonMesh):
        return float(mesh.cell_areas().max(initial=0.0))
    measured = mesh._cache.get("measures")
    if measured is not None:
        return float(measured.max_area)
    step = max(1, mesh.n_cells // 65536)
    xy = mesh.points[mesh.cells[::step]]
    xy -= xy[:, :1]

    return 2.0 * float(signed_area(xy).max(initial=0.0))  # a sample can miss the largest


def _density_picture(mesh, pixel: float, shape: np.ndarray) -> np.ndarray:
    """Cells per unit area in each pixel: cells whose vertex mean falls there over their area."""
    lo = _bounds(mesh.points)[0]
    counts = np.zeros(int(shape[0] * shape[1]))
    areas = np.zeros_like(counts)
    z_points = mesh.points.view(np.complex128).reshape(-1)
    chunk = 1 << 16
    for start in range(0, mesh.n_cells, chunk):
        if isinstance(mesh, PolygonMesh):
            pieces = slice(start, start + chunk)
            xy_centres = mesh.vertex_means()[pieces]
            centres = xy_centres[:, 0] + 1j * xy_centres[:, 1]
            area = mesh.cell_areas()[pieces]
        else:
            z = np.take(z_points, mesh.cells[start : start + chunk].T, mode="clip")
            centres = z.sum(axis=0) / 5
            local = z[1:] - z[0]
            area = 0.5 * (local[:-1].conj() * local[1:]).imag.sum(axis=0)
        i = np.minimum(((centres.real - lo[0]) / pixel).astype(np.int64), shape[0] - 1)
        j = np.minimum(((centres.imag - lo[1]) / pixel).astype(np.int64), shape[1] - 1)
        where = j * shape[0] + i
        counts += np.bincount(where, minlength=counts.size)
        areas += np.bincount(where, weights=area, minlength=counts.size)
    with np.errstate(divide="ignore", invalid="ignore"):
        density = counts / areas
    return np.ma.masked_invalid(np.where(counts > 0, density, np.nan)).reshape(shape[1], shape[0])


def _density_figure(mesh):
    """The cell density (cells per unit area) as a picture, with block outlines and patches."""
    from matplotlib.collections import LineCollection
    from matplotlib.colors import LogNorm

    plt = pyplot()
    lo, hi = _bounds(mesh.points)
    extent = np.maximum(hi - lo, np.finfo(float).tiny)
    # Pixels no smaller than the largest cells, so that every pixel inside holds a cell centre.
    largest = max(_largest_area(mesh), 0.0)
    pixel = max(float(extent.max()) / DENSITY_PIXELS, 1.5 * largest**0.5)
    shape = np.maximum(np.ceil(extent / pixel).astype(np.int64), 1)  # (nx, ny)
    fig, ax = plt.subplots(figsize=(8, 8))
    image = ax.imshow(
        _density_picture(mesh, pixel, shape),
        origin="lower",
        extent=(lo[0], lo[0] + shape[0] * pixel, lo[1], lo[1] + shape[1] * pixel),
        cmap="viridis",
        norm=LogNorm(),
        interpolation="nearest",
    )
    fig.colorbar(image, ax=ax, shrink=0.7, label="cells per unit area")
    if int(mesh.block_id.max(initial=0)) > int(mesh.block_id.min(initial=0)):
        outline = mesh.points[_block_interfaces(mesh)]
        ax.add_collection(LineCollection(outline, colors="w", linewidths=0.8))
    _draw_patches(ax, mesh.points, mesh.boundary_edges, mesh.boundary_patch, mesh.patch_names)
    _draw_interfaces(ax, mesh.points, mesh.interface_edges)
    ax.legend(title="patches", loc="upper left", bbox_to_anchor=(1.25, 1.0), fontsize=8)
    _frame(
        ax,
        mesh.points,
        f"{mesh.name or 'mesh'}, level {mesh.level}: {mesh.n_cells:,} cells, "
        f"{mesh.n_points:,} nodes\ntoo many to draw one by one: cell density and block outlines",
    )
    return fig


def plot_quality(mesh, path: str | Path, *, chunk: int = 1 << 16) -> Path:
    """Histograms of the cells' interior angles and aspect ratios (diameter**2 / area).

    O(M) in chunks; the aspect ratios of all cells are kept (8 bytes per cell) for their bins.
    """
    plt = pyplot()
    angle_bins = np.linspace(0.0, 180.0, 91)
    angle_counts = np.zeros(angle_bins.size - 1)
    aspects = []
    shapes = (
        [_polygon_shapes(mesh)] if isinstance(mesh, PolygonMesh) else cell_shapes(mesh, chunk=chunk)
    )
    for angles, aspect in shapes:
        angle_counts += np.histogram(angles, bins=angle_bins)[0]
        aspects.append(aspect)
    aspect = np.concatenate(aspects) if aspects else np.zeros(0)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    left.stairs(angle_counts, angle_bins, fill=True, color="#4c72b0")
    left.axvline(108.0, color="k", lw=0.8, ls="--", label="regular pentagon (108°)")
    left.set_xlabel("interior angle (degrees)")
    left.set_ylabel("corners")
    left.legend(fontsize=8)
    finite = aspect[np.isfinite(aspect)]
    counts, bins = np.histogram(finite, bins=60) if finite.size else (np.zeros(1), [1.0, 2.0])
    right.stairs(counts, bins, fill=True, color="#dd8452")
    right.axvline(1.52, color="k", lw=0.8, ls="--", label="regular pentagon (1.52)")
    right.set_xlabel("aspect ratio: diameter² / area")
    right.set_ylabel("cells")
    right.legend(fontsize=8)
    fig.suptitle(f"{mesh.name or 'mesh'}, level {mesh.level}: quality of {mesh.n_cells:,} cells")
    return save_figure(fig, path)


def _polygon_shapes(mesh: PolygonMesh) -> tuple[np.ndarray, np.ndarray]:
    """The angles at the corners (straight vertices are not corners) and the aspect ratios."""
    incoming, outgoing = mesh._slot_vectors()
    cross = incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0]
    dot = np.einsum("sd,sd->s", incoming, outgoing)
    angles = (180.0 - np.degrees(np.arctan2(cross, dot)))[~mesh.straight_vertices()]
    areas = mesh.cell_areas()
    with np.errstate(divide="ignore", invalid="ignore"):
        aspect = np.where(areas > 0, mesh.cell_diameters() ** 2 / areas, np.inf)
    return angles, aspect
