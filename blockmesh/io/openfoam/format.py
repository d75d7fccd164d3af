"""OpenFOAM ``polyMesh``: the 2-D mesh extruded one layer into pentagonal prisms (ASCII).

Layout. Given a case directory ``CASE`` the mesh goes to ``CASE/constant/polyMesh`` and, only
where they are missing, ``system/controlDict``, ``fvSchemes`` and ``fvSolution`` are added, with
solver settings and schemes that let the common solvers run once the fields are added
(``laplacianFoam``, ``potentialFoam``, ``icoFoam``, ``simpleFoam``, ``pimpleFoam``: solvers for
``T``, ``p``, ``p_rgh``, ``Phi``, ``U``, ``k``, ``epsilon``, ``omega``, ``nuTilda``; ``Euler`` in
time, second order in space). Given a path ending in ``polyMesh`` only that folder is written.

Mesh. Nodes ``0..N-1`` are the mesh's points at ``z = 0`` and ``N..2N-1`` the same at ``z = dz``
(default: the mean edge length). Cell ``k`` is the prism over pentagon ``k``. Faces, as OpenFOAM
requires: the internal faces first, in upper-triangular order (owner < neighbour, sorted by owner
then neighbour), then one patch per mesh patch (type ``wall`` if its name contains "wall", else
``patch``; faces sorted by owner), then the patch ``frontAndBack`` of type ``empty`` (the ``z = 0``
faces, then the ``z = dz`` ones). Every face's normal points out of its owner: a side face over
the cell edge ``a -> b`` (counter-clockwise in the owner) is ``(a, b, b+N, a+N)``; the back face of
cell ``(v0..v4)`` is ``(v4..v0)``. The regions are written as ``cellZones`` and the interfaces of
a composite domain as ``faceZones`` (the internal faces over their edges, with a ``flipMap`` that
points each face from the interface's first region into its second; ``checkMesh`` lists both).
Patch and zone names are made valid OpenFOAM words (:data:`blockmesh.io.names.FOAM_WORD`).

Atomic. A new case is built whole in a hidden folder and renamed in; in an existing case the
``polyMesh`` folder is swapped in one step (:func:`blockmesh._system.atomic.atomic_dir`), so a kill
leaves the old mesh or the new one. :func:`read_openfoam` checks that the files belong together
(the counts in ``owner``'s note).

Everything is built with whole-array operations and printed with :mod:`blockmesh.io.text`, so
1.7 M cells take seconds (:mod:`blockmesh.io.openfoam.writer`). :func:`read_openfoam`
(:mod:`blockmesh.io.openfoam.reader`) rebuilds the pentagons from the ``z = 0`` faces of the
``empty`` patch, the boundary patches from the side faces, the regions from the cell zones, the
interfaces from the face zones (block ids and the refinement parent are not kept by this
format).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 1)
>>> case = pathlib.Path(tempfile.mkdtemp()) / "case"
>>> poly = write_openfoam(mesh, case)
>>> sorted(p.name for p in poly.iterdir())
['boundary', 'cellZones', 'faces', 'neighbour', 'owner', 'points']
>>> sorted(p.name for p in (case / "system").iterdir())
['controlDict', 'fvSchemes', 'fvSolution']
>>> back = read_openfoam(case)
>>> bool(np.array_equal(back.cells, mesh.cells)), back.patch_names
(True, ('boundary',))
"""

from __future__ import annotations

from blockmesh.io.common import Format
from blockmesh.io.names import FOAM_WORD
from blockmesh.io.openfoam.polygons import read_openfoam
from blockmesh.io.openfoam.writer import EMPTY_PATCH, polymesh_dir, write_openfoam

__all__ = ["EMPTY_PATCH", "FORMAT", "foam_word", "polymesh_dir", "read_openfoam", "write_openfoam"]


def foam_word(name: str) -> str:
    """``name`` made a valid OpenFOAM word (letters, digits, ``_``, ``-``, ``.`` and ``:`` only).

    Examples
    --------
    >>> foam_word("outer wall"), foam_word("2nd"), foam_word("inlet")
    ('outer_wall', 'p_2nd', 'inlet')
    """
    return FOAM_WORD.clean(name)


FORMAT = Format.of(
    write_openfoam,
    read_openfoam,
    "OpenFOAM case / polyMesh directory: one extruded layer of pentagonal prisms",
    extensions=(),
    directory=True,
    options=("dz",),
)
