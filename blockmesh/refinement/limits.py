"""What :func:`~blockmesh.refinement.refine` checks before it builds: memory and precision.

:func:`check_memory` refuses a level whose predicted size does not fit the memory (naming the
largest level that does); :func:`check_precision` a level whose cells double precision cannot
resolve where the mesh lies.
"""

from __future__ import annotations

import numpy as np

from blockmesh._system.memory import available_memory, format_bytes, format_count
from blockmesh.errors import ResourceError
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.sizes import MeshSize, largest_fitting_level, predict_size

__all__ = ["check_memory", "check_precision"]


def check_memory(base: Mesh, n_shared: int, level: int, max_memory: int | None) -> None:
    """ResourceError when refining ``base`` ``level`` times is predicted not to fit.

    ``n_shared`` is the number of edges two cells of ``base`` share; the limit is
    ``max_memory``, or the memory available now.
    """
    n_boundary = 5 * base.n_cells - 2 * n_shared
    limit = available_memory() if max_memory is None else int(max_memory)

    def size(steps: int) -> MeshSize:
        return predict_size(
            base.n_cells, base.n_points, n_shared, n_boundary, steps, base.level + steps
        )

    wanted = size(level)
    if wanted.peak_bytes <= limit:
        return

    fits = largest_fitting_level(size, level, limit)  # type: ignore[arg-type]
    source = "the limit given" if max_memory is not None else "the memory available now"
    advice = (
        f"the largest level that fits is {base.level + fits}"
        if fits >= 0
        else "not even the unrefined mesh fits"
    )
    name = f" of {base.name!r}" if base.name else ""
    raise ResourceError(
        f"level {base.level + level}{name} needs about {format_bytes(wanted.peak_bytes)} "
        f"({format_count(wanted.cells)} cells, {format_count(wanted.nodes)} nodes), more than "
        f"{source} ({format_bytes(limit)}); {advice}"
    )


#: Each level shrinks the shortest cell edge by at most this factor (half the length, and the
#: inner cells' worsening shape; measured 0.43..0.5 per level on the catalogue).
_EDGE_SHRINK = 0.4
#: Shortest edge allowed, in units of the coordinates' spacing (ulp) where the mesh lies.
_MIN_EDGE_ULPS = 64


def check_precision(base: Mesh, level: int) -> None:
    """Refuse a level whose cells double precision cannot resolve where the mesh lies.

    Far from the origin the spacing of float64 numbers (their ulp) grows: at 1e15 it is 0.125, so
    a unit square there cannot hold cells a tenth across. The shortest edge at ``level`` is
    estimated from the base's shortest edge and compared with the ulp of the largest coordinate.
    """
    if level == 0 or base.n_cells == 0:
        return
    xy = base.points[base.cells]
    edges = np.hypot(*(np.roll(xy, -1, axis=1) - xy).transpose(2, 0, 1))
    shortest = float(edges.min())
    spacing = float(np.spacing(np.max(np.abs(base.points))))
    finest = next(
        (k for k in range(level + 1) if shortest * _EDGE_SHRINK**k < _MIN_EDGE_ULPS * spacing),
        None,
    )
    if finest is None:
        return
    where = float(np.max(np.abs(base.points)))
    usable = (
        f"the highest level it resolves is {base.level + finest - 1}"
        if finest > 0
        else "not even the unrefined mesh is resolved"
    )
    raise ResourceError(
        f"level {base.level + level} would need cells about "
        f"{shortest * _EDGE_SHRINK**level:.2g} across at coordinates near {where:.3g}, where "
        f"double precision only resolves steps of {spacing:.2g}; {usable}. Move the domain "
        "near the origin (subtract a point inside it from every vertex) to refine further"
    )
