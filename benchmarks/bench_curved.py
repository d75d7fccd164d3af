"""Curved domains: convergence of area and integrals with and without exact geometry, and cost.

Run: ``python benchmarks/bench_curved.py``. Prints, level by level, the error of the straight
cells' area and of an integral (the straight cells converge at second order: each level
quarters the error) against the exact-geometry results (at round-off from level 0), then the time
of the curve-aware refinement against the straight refinement of the same blocks, and of
exact-geometry integration against plain integration. Not a test: timings on shared machines are
noisy; each figure is the best of several runs after a warm-up.
"""

from __future__ import annotations

import argparse
import math
import time

from _page import Page, add_arguments

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


def convergence(page: Page) -> None:
    areas = page.table(
        "Area of the straight cells against the true area",
        ["domain", "level", "error, straight", "ratio to level before", "error, exact geometry"],
    )
    for name, true in AREAS.items():
        domain = blockmesh.load_domain(name)
        previous = None
        for level in range(6):
            mesh = domain.mesh(level)
            error = abs(mesh.area - true) / true
            ratio = f"{previous / error:.2f}" if previous else "-"
            exact = abs(mesh.curved_area - true) / true
            areas.row(name, level, f"{error:.2e}", ratio, f"{exact:.2e}")
            previous = error
    areas.note("Relative errors: |area - true| / true.")
    integral = page.table(
        "∫∫ e^x cos y over plate-hole, order 8",
        ["level", "error, straight", "ratio to level before", "error, exact geometry"],
    )
    domain = blockmesh.load_domain("plate-hole")
    previous = None
    for level in range(6):
        straight = blockmesh.integrate(domain, "exp(x) * cos(y)", order=8, level=level)
        exact = blockmesh.integrate(
            domain, "exp(x) * cos(y)", order=8, level=level, exact_geometry=True
        )
        error = abs(straight - PLATE) / PLATE
        ratio = f"{previous / error:.2f}" if previous else "-"
        integral.row(level, f"{error:.2e}", ratio, f"{abs(exact - PLATE) / PLATE:.2e}")
        previous = error
    integral.note(
        "Relative errors against (e^2 - e^-2) 2 sin 2 - π/4 (the hole's part by the mean "
        "value of a harmonic function)."
    )


def cost(page: Page) -> None:
    refine = page.table(
        "Refinement: curve-aware against straight (the same blocks without their curves)",
        ["domain", "level", "cells", "curved", "straight", "ratio"],
    )
    for name in ("disc", "annulus", "plate-hole", "cylinder-channel"):
        curved = blockmesh.load_domain(name)
        straight = blockmesh.Domain.from_blocks(
            curved.vertices, curved.blocks, dict(curved.patches), name=name
        )
        for level in (5, 6):
            t_curved = best_of(lambda c=curved, lv=level: c.mesh(lv), 3)
            t_straight = best_of(lambda s=straight, lv=level: s.mesh(lv), 3)
            cells = curved.n_blocks * 6**level
            refine.row(
                name,
                level,
                f"{cells:,}",
                f"{t_curved * 1e3:.1f} ms",
                f"{t_straight * 1e3:.1f} ms",
                f"{t_curved / t_straight:.2f}",
            )
    refine.note("Best of 3 after a warm-up.")
    integrate = page.table(
        "Integration, order 8: exact geometry against the straight cells",
        ["domain", "level", "cells", "exact geometry", "straight", "ratio"],
    )
    for name in ("disc", "plate-hole"):
        mesh = blockmesh.load_domain(name).mesh(4)
        plain = best_of(lambda m=mesh: blockmesh.integrate(m, "exp(x)*cos(y)", order=8))
        exact = best_of(
            lambda m=mesh: blockmesh.integrate(m, "exp(x)*cos(y)", order=8, exact_geometry=True)
        )
        integrate.row(
            name,
            4,
            f"{mesh.n_cells:,}",
            f"{exact * 1e3:.1f} ms",
            f"{plain * 1e3:.1f} ms",
            f"{exact / plain:.2f}",
        )
    integrate.note("Best of 5 after a warm-up.")
    start = time.perf_counter()
    blockmesh.load_domain("cylinder-channel")
    page.text(
        "Loading `cylinder-channel` (which runs the curve checks to level 5): "
        f"{time.perf_counter() - start:.3f} s."
    )


ABOUT = """\
The catalogue's curved domains: how the straight cells' area and integrals converge with the level
(second order: each level quarters the error) against the exact-geometry results (at round-off from
level 0), then what the curves cost: the curve-aware refinement against the same blocks without
their curves, and exact-geometry integration against plain integration. Timings on a shared
machine are noisy; each is the best of several runs after a warm-up."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("curved", "Curved domains: convergence and cost", ABOUT)
    convergence(page)
    cost(page)
    page.write(args)


if __name__ == "__main__":
    main()
