"""
A first mesh, level by level
============================

The catalogue domain ``square-cut`` is four pentagonal blocks. Each level of refinement splits every
pentagon into six: the vertex mean, the edge midpoints and five inner points make five corner
pentagons and one in the middle. The counts follow closed forms (B·6^L cells).
"""

import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection

import blockmesh

domain = blockmesh.load_domain("square-cut")
print(f"{domain.name}: {domain.n_blocks} blocks, patches {domain.patch_names}")

# %%
# Refine to levels 0 to 3 and draw each mesh, every cell shaded by the block it comes from.

fig, axes = plt.subplots(1, 4, figsize=(14, 3.8))
for level, ax in enumerate(axes):
    mesh = blockmesh.refine(domain, level)
    cells = PolyCollection(
        mesh.points[mesh.cells],
        array=mesh.block_id,
        cmap="Pastel1",
        edgecolors="0.25",
        linewidths=0.6,
    )
    ax.add_collection(cells)
    ax.set_title(f"level {level}: {mesh.n_cells} cells, {mesh.n_points} nodes")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_axis_off()
    print(f"level {level}: {mesh.n_cells} cells = 4 x 6^{level}")

# %%
# The report of ``blockmesh mesh square-cut --level 3``, in Python: the worst angles, aspect
# ratio and area ratio, and the bandwidth of the paper's nested numbering.

mesh = blockmesh.refine(domain, 3)
quality = mesh.quality()
print(f"angles {quality.min_angle:.2f} .. {quality.max_angle:.2f} degrees")
print(f"max aspect ratio {quality.max_aspect_ratio:.2f}, bandwidth {mesh.bandwidth():,}")
