"""
A polygon with a hole, an arc and a circle
==========================================

Any simple polygon with holes is decomposed into strictly convex pentagonal blocks; a polygon
edge may be a circular arc and a hole may be a circle. The nodes that refinement puts on a
curved edge lie on the curve.
"""

import matplotlib.pyplot as plt
from matplotlib.collections import LineCollection, PolyCollection

from blockmesh import Domain
from blockmesh.curves import Arc

domain = Domain.from_polygon(
    [(0, 0), (4, 0), (4, 2), (0, 2)],
    holes=[[(2.6, 0.6), (3.4, 0.6), (3.4, 1.4), (2.6, 1.4)]],
    patches={"inlet": [3], "outlet": [1], "walls": [0, 2], "square": ["hole 0"]},
    arcs={2: Arc(through=(2, 2.4))},
    circles=[{"center": (1.2, 1.0), "radius": 0.4, "patch": "cylinder"}],
    name="channel",
)
print(f"{domain.n_blocks} blocks, {len(domain.curves)} curved block edges")
print("patches:", ", ".join(domain.patch_names))

# %%
# The blocks, and the mesh one level down with its boundary coloured by patch.

mesh = domain.mesh(1)
fig, (left, right) = plt.subplots(1, 2, figsize=(14, 4.2))
left.add_collection(
    PolyCollection(
        domain.vertices[domain.blocks], facecolors="0.93", edgecolors="0.2", linewidths=0.8
    )
)
left.set_title(f"{domain.n_blocks} blocks (straight outlines of the curved ones)")
right.add_collection(
    PolyCollection(mesh.points[mesh.cells], facecolors="0.97", edgecolors="0.4", linewidths=0.3)
)
for k, name in enumerate(mesh.patch_names):
    edges = mesh.points[mesh.boundary_edges[mesh.boundary_patch == k]]
    right.add_collection(LineCollection(edges, colors=f"C{k}", linewidths=2, label=name))
right.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
right.set_title(f"level 1: {mesh.n_cells:,} cells")
for ax in (left, right):
    ax.set_aspect("equal")
    ax.autoscale_view()

# %%
# The straight cells approach the curves as the level rises; their area converges at second
# order, while ``curved_area`` (the cells with their curved edges) is exact at every level.

for level in range(4):
    m = domain.mesh(level)
    print(f"level {level}: straight cells {m.area:.8f}, curved cells {m.curved_area:.8f}")
