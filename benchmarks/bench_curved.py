"""Curved domains: convergence of area and integrals with and without exact geometry, and cost.

Run: ``python benchmarks/bench_curved.py``. Prints, level by level, the error of the straight
cells' area and of an integral (the straight cells converge at second order: each level
quarters the error) against the exact-geometry results (at round-off from level 0), then the time
of the curve-aware refinement against the straight refinement of the same blocks, and of
exact-geometry integration against plain integration. Not a test: timings on shared machines are
noisy; each figure is the best of several runs after a warm-up.
"""

from __future__ import annotations

import math
import time

import blockmesh

#: ∫ e^x cos y over the plate with a hole: the square's closed form minus the hole's, which is
#: π r^2 (the value at its centre: e^x cos y is harmonic).
PLATE = (math.e**2 - math.e**-2) * 2 * math.sin(2) - math.pi * 0.25
AREAS = {"plate-hole": 16 - math.pi / 4, "disc": math.pi, "annulus": 0.75 * math.pi}


def best_of(function, repeat: int = 5) -> float:
    function()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def convergence() -> None:
    print("area: |straight - true| / true (ratio to the previous level), exact geometry")
    for name, true in AREAS.items():
        domain = blockmesh.load_domain(name)
        previous = None
        for level in range(6):
            mesh = domain.mesh(level)
            error = abs(mesh.area - true) / true
            ratio = f"{previous / error:5.2f}" if previous else "    -"
            exact = abs(mesh.curved_area - true) / true
            print(f"  {name:11} L{level}  {error:9.2e}  {ratio}   {exact:9.2e}")
            previous = error
    print("∫∫ e^x cos y over plate-hole, order 8: |error| / |exact|, straight vs exact geometry")
    domain = blockmesh.load_domain("plate-hole")
    previous = None
    for level in range(6):
        straight = blockmesh.integrate(domain, "exp(x) * cos(y)", order=8, level=level)
        exact = blockmesh.integrate(
            domain, "exp(x) * cos(y)", order=8, level=level, exact_geometry=True
        )
        error = abs(straight - PLATE) / PLATE
        ratio = f"{previous / error:5.2f}" if previous else "    -"
        print(f"  L{level}  {error:9.2e}  {ratio}   {abs(exact - PLATE) / PLATE:9.2e}")
        previous = error


def cost() -> None:
    print("refinement: curve-aware against straight (same blocks, no curves)")
    for name in ("disc", "annulus", "plate-hole", "cylinder-channel"):
        curved = blockmesh.load_domain(name)
        straight = blockmesh.Domain.from_blocks(
            curved.vertices, curved.blocks, dict(curved.patches), name=name
        )
        for level in (5, 6):
            t_curved = best_of(lambda c=curved, lv=level: c.mesh(lv), 3)
            t_straight = best_of(lambda s=straight, lv=level: s.mesh(lv), 3)
            cells = curved.n_blocks * 6**level
            print(
                f"  {name:16} L{level} {cells:>10,} cells  curved {t_curved * 1e3:7.1f} ms  "
                f"straight {t_straight * 1e3:7.1f} ms  ratio {t_curved / t_straight:4.2f}"
            )
    print("integration, order 8: exact geometry against straight cells")
    for name in ("disc", "plate-hole"):
        mesh = blockmesh.load_domain(name).mesh(4)
        plain = best_of(lambda m=mesh: blockmesh.integrate(m, "exp(x)*cos(y)", order=8))
        exact = best_of(
            lambda m=mesh: blockmesh.integrate(m, "exp(x)*cos(y)", order=8, exact_geometry=True)
        )
        print(
            f"  {name:11} L4 {mesh.n_cells:>7,} cells  exact geometry {exact * 1e3:6.1f} ms  "
            f"straight {plain * 1e3:6.1f} ms  ratio {exact / plain:4.2f}"
        )
    start = time.perf_counter()
    blockmesh.load_domain("cylinder-channel")
    print(
        f"loading cylinder-channel (curve checks to level 5): {time.perf_counter() - start:.3f} s"
    )


if __name__ == "__main__":
    convergence()
    cost()
