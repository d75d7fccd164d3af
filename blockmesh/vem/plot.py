"""Pictures of solutions (matplotlib, imported only when drawing).

A diffusion-reaction solution is drawn as the nodal values, interpolated linearly on a fan of
triangles in every cell (no new nodes), with the cell edges; an elasticity solution as the
deformed mesh (displacements magnified so that the largest is a tenth of the domain's size)
coloured by the von Mises stress of every cell. The interfaces of a composite domain are drawn
as white lines (on the deformed mesh, black).

Examples
--------
>>> import pathlib, tempfile
>>> import blockmesh
>>> from blockmesh.vem import solve_poisson
>>> mesh = blockmesh.load_domain("square").mesh(1)
>>> sol = solve_poisson(mesh, 1.0, dirichlet={"left": 0})
>>> plot_solution(sol, pathlib.Path(tempfile.mkdtemp()) / "u.png").stat().st_size > 0
True
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from blockmesh.plot import pyplot, save_figure
from blockmesh.vem.adaptive import AdaptiveStep
from blockmesh.vem.elasticity import ElasticitySolution
from blockmesh.vem.poisson import PoissonSolution
from blockmesh.vem.polygons import PolygonMesh

__all__ = ["plot_convergence", "plot_solution"]


def _fan(mesh: PolygonMesh) -> np.ndarray:
    """Triangles (T, 3) fanned from corner 0 of every cell."""
    triangles = []
    for group in mesh.groups:
        for k in range(1, group.size - 1):
            triangles.append(group.cells[:, [0, k, k + 1]])
    return np.concatenate(triangles)


def _draw_interfaces(ax, solution: PoissonSolution | ElasticitySolution, colour: str) -> None:
    """The interfaces of the solution's mesh (a composite domain's), where they are now."""
    from matplotlib.collections import LineCollection

    mesh = solution.mesh
    if not mesh.interface_names:
        return
    points = mesh.points
    if isinstance(solution, ElasticitySolution):
        size = float(np.ptp(points, axis=0).max())
        largest = float(np.hypot(*solution.displacement.T).max())
        points = points + (0.1 * size / largest if largest > 0 else 0.0) * solution.displacement
    ax.add_collection(LineCollection(points[mesh.interface_edges], colors=colour, linewidths=1.2))


def _edges_width(n_cells: int) -> float:
    return 0.5 if n_cells <= 2000 else 0.2 if n_cells <= 20000 else 0.0


def plot_solution(
    solution: PoissonSolution | ElasticitySolution, path: str | Path, *, title: str = ""
) -> Path:
    """Draw ``solution`` to a .png, .pdf or .svg file (atomically); returns the path."""
    from matplotlib.collections import PolyCollection
    from matplotlib.tri import Triangulation

    plt = pyplot()
    mesh = solution.mesh
    fig, ax = plt.subplots(figsize=(8, 7))
    polygons = [mesh.points[c] for g in mesh.groups for c in g.cells]
    width = _edges_width(mesh.n_cells)
    if isinstance(solution, PoissonSolution):
        tri = Triangulation(mesh.points[:, 0], mesh.points[:, 1], _fan(mesh))
        shaded = ax.tripcolor(tri, solution.values, shading="gouraud", cmap="viridis")
        fig.colorbar(shaded, ax=ax, label="u")
        if width:
            ax.add_collection(
                PolyCollection(
                    polygons, facecolors="none", edgecolors="k", linewidths=width, alpha=0.35
                )
            )
        heading = "u_h"
    else:
        size = float(np.ptp(mesh.points, axis=0).max())
        largest = float(np.hypot(*solution.displacement.T).max())
        factor = 0.1 * size / largest if largest > 0 else 0.0
        moved = mesh.points + factor * solution.displacement
        order = np.concatenate([g.index for g in mesh.groups])
        deformed = [moved[c] for g in mesh.groups for c in g.cells]
        ax.add_collection(
            PolyCollection(polygons, facecolors="none", edgecolors="0.7", linewidths=0.3)
        )
        cells = PolyCollection(deformed, cmap="inferno", edgecolors="k", linewidths=width * 0.6)
        cells.set_array(solution.von_mises[order])
        ax.add_collection(cells)
        fig.colorbar(cells, ax=ax, label="von Mises stress")
        heading = f"deformed x {factor:.3g}, von Mises stress"
    _draw_interfaces(ax, solution, "w" if isinstance(solution, PoissonSolution) else "k")
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_title(title or f"{heading}: {mesh.n_cells:,} cells, {solution.info.dof:,} unknowns")
    return save_figure(fig, path)


def plot_convergence(
    history: Sequence[AdaptiveStep],
    path: str | Path,
    *,
    title: str = "",
    references: Sequence[tuple[str, Sequence[int], Sequence[float]]] = (),
) -> Path:
    """Error and estimator against unknowns (log-log) of an adaptive run, with a slope-1/2 line.

    ``references`` adds other curves: ``(label, unknowns, errors)`` each (e.g. uniform
    refinement).
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 5))
    n = np.array([s.unknowns for s in history], dtype=float)
    ax.loglog(n, [s.estimator for s in history], "o-", label="estimator")
    if all(s.h1_error is not None for s in history):
        ax.loglog(n, [s.h1_error for s in history], "s-", label="H1 error")
        if all(s.l2_error is not None for s in history):
            ax.loglog(n, [s.l2_error for s in history], "^-", label="L2 error")
    for label, unknowns, errors in references:
        ax.loglog(unknowns, errors, "--", label=label)
    if n.size > 1:
        anchor = history[-1].estimator
        ax.loglog(n, anchor * (n / n[-1]) ** -0.5, "k:", label="N^(-1/2)")
    ax.set_xlabel("unknowns N")
    ax.set_ylabel("error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    ax.set_title(title or f"adaptive refinement: {len(history)} steps")
    return save_figure(fig, path)
