"""
A mesh made in partitions on Dask
=================================

``blockmesh.distributed`` makes a mesh piece by piece on the workers of a Dask cluster
(``pip install -e '.[distributed]'``): each partition is a group of whole blocks, each worker
numbers its nodes from closed-form counts without talking to the others and writes its piece, and
the pieces together are the serial mesh, array for array. Here two workers of a cluster inside
this process (threads: ``Client(processes=False)``) make the ``l-shape`` at level 3 in four
partitions. ``refine_to(..., workers=2)`` starts two worker processes instead (in a script, under
``if __name__ == "__main__":``, since the workers import the script again), and
``client=Client("tcp://host:8786")`` uses a running cluster.
"""

import shutil
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from dask.distributed import Client
from matplotlib.collections import PolyCollection

import blockmesh
import blockmesh.distributed as bd

domain = blockmesh.load_domain("l-shape")
out = Path(tempfile.mkdtemp()) / "l-shape.pvtu"
with Client(processes=False, n_workers=2, threads_per_worker=1, dashboard_address=":0") as client:
    made = bd.refine_to(domain, 3, out, partitions=4, client=client)
print(f"{made.cells:,} cells, {made.nodes:,} nodes in {len(made.pieces)} pieces:")
for piece in made.pieces:
    print(" ", piece.relative_to(out.parent))

# %%
# Read back and put together (for a mesh that fits), it equals the serial refinement bit for
# bit; the cells of partition p are a contiguous range of the whole mesh's cells.

mesh = bd.gather(out)
serial = blockmesh.refine(domain, 3)
print("same as the serial mesh:", np.array_equal(mesh.points, serial.points),
      np.array_equal(mesh.cells, serial.cells))  # fmt: skip
partition = np.empty(mesh.n_cells, dtype=int)
for summary in made.summaries:
    first = summary["first_cell"]
    partition[first : first + summary["cells"]] = summary["piece"]

fig, ax = plt.subplots(figsize=(6, 6))
ax.add_collection(
    PolyCollection(
        mesh.points[mesh.cells], array=partition, cmap="Set2", edgecolors="0.3", linewidths=0.3
    )
)
ax.set_aspect("equal")
ax.autoscale_view()
ax.set_title("l-shape, level 3: the cells of each of 4 partitions")

shutil.rmtree(out.parent)  # the files were for this example only
