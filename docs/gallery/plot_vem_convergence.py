"""
A virtual element solve and its convergence
===========================================

``blockmesh.vem`` solves -Δu = f on the pentagon meshes as they are, with lowest-order virtual
elements (one unknown per node). With the exact solution u = sin(πx) sin(πy) on the unit square
(the catalogue's ``square``, 8 blocks), the errors fall with the level: against the number of
unknowns N, the L2 error nearly as N^-1 and the H1 error nearly as N^-1/2 (second and first
order in h).
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection

import blockmesh
from blockmesh.vem import solve_poisson

domain = blockmesh.load_domain("square")
exact = "sin(pi*x)*sin(pi*y)"
gradient = ("pi*cos(pi*x)*sin(pi*y)", "pi*sin(pi*x)*cos(pi*y)")
dirichlet = dict.fromkeys(domain.patch_names, 0)
unknowns, l2, h1 = [], [], []
for level in range(1, 5):
    mesh = domain.mesh(level)
    sol = solve_poisson(mesh, "2*pi^2*sin(pi*x)*sin(pi*y)", dirichlet=dirichlet)
    errors = sol.errors(exact, gradient)
    unknowns.append(sol.info.dof)
    l2.append(errors.l2)
    h1.append(errors.h1)
    print(f"level {level}: {sol.info.dof:6,} unknowns, L2 {errors.l2:.3e}, H1 {errors.h1:.3e}")

# %%
# The errors against the unknowns, with the slopes the theory predicts.

fig, ax = plt.subplots(figsize=(7, 5))
n = np.array(unknowns, dtype=float)
ax.loglog(n, l2, "o-", label="L2 error")
ax.loglog(n, h1, "s-", label="H1 error")
ax.loglog(n, l2[0] * (n / n[0]) ** -1.0, "k:", lw=0.8, label="N^-1")
ax.loglog(n, h1[0] * (n / n[0]) ** -0.5, "k--", lw=0.8, label="N^-1/2")
ax.set_xlabel("unknowns N")
ax.legend()
ax.set_title("errors against unknowns")
print("rates:", np.round(np.diff(np.log(l2)) / np.diff(np.log(n)), 2), "(L2),",
      np.round(np.diff(np.log(h1)) / np.diff(np.log(n)), 2), "(H1)")  # fmt: skip

# %%
# The solution on the level-2 mesh, each cell shaded by the mean of its nodal values.

mesh = domain.mesh(2)
sol = solve_poisson(mesh, "2*pi^2*sin(pi*x)*sin(pi*y)", dirichlet=dirichlet)
fig, right = plt.subplots(figsize=(6.5, 5.5))
cells = PolyCollection(mesh.points[mesh.cells], array=sol.values[mesh.cells].mean(axis=1))
cells.set_edgecolor("0.3")
cells.set_linewidth(0.3)
right.add_collection(cells)
right.set_aspect("equal")
right.autoscale_view()
fig.colorbar(cells, ax=right, label="u")
right.set_title(f"u on level 2 ({mesh.n_cells} pentagons)")
