"""
Export to OpenFOAM
==================

A mesh written as an OpenFOAM case is one layer of pentagonal prisms, faces in OpenFOAM's order,
the patches as boundary patches (``wall`` when the name contains "wall") and the regions as
``cellZones``; ``system/`` files with solver settings are added when missing. Reading the case back
gives the same mesh (OpenFOAM keeps no block ids or parents).
"""

import shutil
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection

import blockmesh

mesh = blockmesh.load_domain("l-shape").mesh(3)
case = Path(tempfile.mkdtemp()) / "l-shape-case"
polymesh = blockmesh.write(mesh, case, format="openfoam")  # the case's constant/polyMesh
for path in sorted(case.rglob("*")):
    if path.is_file():
        print(path.relative_to(case), f"{path.stat().st_size:,} bytes")

# %%
# The boundary file lists the patches: the mesh's own, and ``frontAndBack`` (the two faces of the
# layer), of type ``empty`` so that the case is 2-D.

print((polymesh / "boundary").read_text()[-900:])

# %%
# Read back: the same points, cells, patches and regions.

again = blockmesh.read(case)
print(again.n_cells == mesh.n_cells, np.array_equal(again.region, mesh.region))
print("patches:", again.patch_names, "regions:", again.region_names)

fig, ax = plt.subplots(figsize=(6, 6))
for k, name in enumerate(again.patch_names):
    edges = again.points[again.boundary_edges[again.boundary_patch == k]]
    ax.add_collection(LineCollection(edges, colors=f"C{k}", linewidths=2.5, label=name))
ax.scatter(*again.points[again.cells].mean(axis=1).T, c=again.region, s=2, cmap="Set2")
ax.set_aspect("equal")
ax.legend(title="patches")
ax.set_title("the case read back: patches, and cells by cellZone")

shutil.rmtree(case.parent)  # the files were for this example only
