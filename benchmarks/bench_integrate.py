"""Benchmark of blockmesh.integrate (a script, not a test).

1. Throughput: quadrature points per second of ``integrate`` against evaluating f alone on the
   same points (goal: >= 0.8x at order >= 5, level 6), and what the error estimate costs
   (``integrate`` with its default estimate against ``warn_rtol=None``).
2. Error against evaluations for the three rules (paper, jacobi, fan) on the tables' integrands.
3. Time to reach 1e-12: ``integrate_to_tolerance`` against ``scipy.integrate.dblquad`` on SP and
   USP for the smooth integrands of the tables.

Run: ``PYTHONPATH=. python benchmarks/bench_integrate.py [--quick]``.
"""

from __future__ import annotations

import argparse
import itertools
import math
import time
from fractions import Fraction

import numpy as np
from _page import Page, add_arguments
from scipy import integrate as scipy_integrate

from blockmesh.numerics.expr import parse_expression
from blockmesh.quadrature import DEFAULT_CHUNK, RULES, integrate, integrate_to_tolerance, rule_info
from blockmesh.quadrature.kernel import chunks
from blockmesh.tables import PENTAGONS, paper_case, pentagon_mesh

#: Scalar versions of the tables' smooth integrands, for scipy's dblquad.
SCALAR = {
    1: lambda y, x: (x**4 + y**3) / (1 + x**2),
    2: lambda y, x: (1 - x) * math.sin(10 * x * y),
    3: lambda y, x: (0.2 * x + 0.3 * y) ** 19,
    5: lambda y, x: (x + y) ** 19 / 1e10,
    7: lambda y, x: math.cos(30 * (x + y)),
    9: lambda y, x: math.exp(-((x - 0.5) ** 2 + (y - 0.5) ** 2)),
    10: lambda y, x: math.exp(-100 * ((x - 0.5) ** 2 + (y - 0.5) ** 2)),
    11: lambda y, x: (
        0.75 * math.exp(-0.25 * (9 * x - 2) ** 2 - 0.25 * (9 * y - 2) ** 2)
        + 0.75 * math.exp((-1 / 49) * (9 * x + 1) ** 2 - 0.1 * (9 * y + 1))
        + 0.5 * math.exp(-0.25 * (9 * x - 7) ** 2 - 0.25 * (9 * y - 3) ** 2)
        - 0.2 * math.exp(-((9 * y - 4) ** 2) - (9 * y - 7) ** 2)
    ),
}


def _best(fn, repeat: int = 3) -> float:
    fn()  # warm up (first touch of memory, caches of rules)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


# --------------------------------------------------------------------------- 1. throughput
def throughput(page: Page, level: int, orders: tuple[int, ...], tables: tuple[int, ...]) -> None:
    mesh = pentagon_mesh("SP", level)
    out = page.table(
        f"1. Throughput on SP level {level} ({mesh.n_cells:,} cells), rule paper",
        [
            "integrand",
            "order",
            "points",
            "integrate",
            "f alone",
            "M points/s",
            "f alone / integrate",
            "no estimate",
            "estimate",
        ],
    )
    for table in tables:
        text = paper_case(table, "SP").integrand
        f = parse_expression(text)
        for n in orders:
            points = mesh.n_cells * rule_info("paper", n).points_per_cell

            def run_integrate(f=f, n=n):
                integrate(mesh, f, order=n)

            def run_without_estimate(f=f, n=n):
                integrate(mesh, f, order=n, warn_rtol=None)

            def run_f_alone(f=f, n=n):
                spent = 0.0
                for _, xs, ys, _ in chunks(mesh, RULES["paper"], n, DEFAULT_CHUNK):
                    start = time.perf_counter()
                    with np.errstate(all="ignore"):
                        f(xs, ys)
                    spent += time.perf_counter() - start
                return spent

            t_int = _best(run_integrate)
            t_plain = _best(run_without_estimate)
            run_f_alone()
            t_f = min(run_f_alone() for _ in range(3))
            label = text if len(text) <= 32 else text[:29] + "..."
            out.row(
                f"`{label}`",
                n,
                f"{points:,}",
                f"{t_int * 1e3:.0f} ms",
                f"{t_f * 1e3:.0f} ms",
                f"{points / t_int / 1e6:.0f}",
                f"{t_f / t_int:.2f}",
                f"{t_plain * 1e3:.0f} ms",
                f"{(t_int / t_plain - 1) * 100:+.0f}%",
            )
    out.note(
        f'Points in chunks of {DEFAULT_CHUNK:,}. "no estimate": `warn_rtol=None`; "estimate": '
        "what the default error estimate adds."
    )


# --------------------------------------------------------------------------- 2. error vs cost
def error_vs_cost(page: Page, tables: tuple[int, ...], targets=(1e-6, 1e-10, 1e-13)) -> None:
    out = page.table(
        "2. Fewest evaluations reaching |error| <= target x ∫|f| (levels 0-3, orders 1-30)",
        ["table", "pentagon", "target", *RULES],
    )
    for table in tables:
        for pentagon in PENTAGONS:
            case = paper_case(table, pentagon)
            exact = case.exact
            results = {}
            for rule in RULES:
                found = dict.fromkeys(targets)
                for level in range(0, 4):
                    mesh = pentagon_mesh(pentagon, level)
                    for n in range(1, 31):
                        value = integrate(mesh, case.integrand, order=n, rule=rule, warn_rtol=None)
                        err = float(abs(Fraction(value) - exact)) / case.abs_integral
                        cost = mesh.n_cells * rule_info(rule, n).points_per_cell
                        for target in targets:
                            if err <= target and (found[target] is None or cost < found[target]):
                                found[target] = cost
                results[rule] = found
            for target in targets:
                cells = [
                    f"{results[rule][target]:,}" if results[rule][target] else "-" for rule in RULES
                ]
                out.row(table, pentagon, f"{target:.0e}", *cells)
    out.note("Every rule of order n is exact to degree 2n - 1.")


# --------------------------------------------------------------------------- 3. vs dblquad
def _strips(corners):
    """The convex polygon as vertical strips: (x0, x1, lower(x), upper(x)) per strip."""
    pts = [tuple(map(float, p)) for p in corners]
    xs = sorted({p[0] for p in pts})
    edges = list(zip(pts, pts[1:] + pts[:1], strict=True))

    def bounds(x):
        ys = []
        for (xa, ya), (xb, yb) in edges:
            if min(xa, xb) <= x <= max(xa, xb) and xa != xb:
                ys.append(ya + (yb - ya) * (x - xa) / (xb - xa))
        return min(ys), max(ys)

    strips = []
    for x0, x1 in itertools.pairwise(xs):

        def lower(x, x0=x0, x1=x1):
            return bounds(min(max(x, x0), x1))[0]

        def upper(x, x0=x0, x1=x1):
            return bounds(min(max(x, x0), x1))[1]

        strips.append((x0, x1, lower, upper))
    return strips


def versus_dblquad(page: Page, tables: tuple[int, ...], tol: float = 1e-12) -> None:
    out = page.table(
        f"3. Time to |error| <= {tol:g}: `integrate_to_tolerance` against scipy's `dblquad`",
        [
            "table",
            "pentagon",
            "blockmesh",
            "error",
            "points",
            "level/order",
            "dblquad",
            "error",
            "evaluations",
            "speed-up",
        ],
    )
    for table in tables:
        for pentagon in PENTAGONS:
            case = paper_case(table, pentagon)
            reference = float(case.exact)
            base = pentagon_mesh(pentagon, 0)

            def ours(case=case, base=base):
                return integrate_to_tolerance(base, case.integrand, tol)

            t_ours = _best(ours, repeat=3)
            result = ours()
            scalar = SCALAR[table]
            calls = [0]

            def counted(y, x, scalar=scalar, calls=calls):
                calls[0] += 1
                return scalar(y, x)

            def theirs(pentagon=pentagon, counted=counted, calls=calls):
                calls[0] = 0
                total = 0.0
                for x0, x1, lower, upper in _strips(PENTAGONS[pentagon]):
                    total += scipy_integrate.dblquad(
                        counted, x0, x1, lower, upper, epsabs=tol, epsrel=tol
                    )[0]
                return total

            start = time.perf_counter()
            value = theirs()
            t_theirs = time.perf_counter() - start
            flag = "" if result.converged else " (not converged)"
            out.row(
                table,
                pentagon,
                f"{t_ours * 1e3:.1f} ms",
                f"{abs(result.value - reference):.1e}",
                f"{result.points:,}",
                f"{result.level}/{result.order}",
                f"{t_theirs * 1e3:.0f} ms",
                f"{abs(value - reference):.1e}",
                f"{calls[0]:,}",
                f"{t_theirs / t_ours:.0f}x{flag}",
            )
    out.note(
        "blockmesh: `integrate_to_tolerance` from the single pentagon; dblquad: "
        f"epsabs = epsrel = {tol:g}, the pentagon split into vertical strips."
    )


ABOUT = """\
`blockmesh.integrate` on the paper's pentagons: quadrature points per second against evaluating f
alone on the same points (and what the default error estimate costs); the fewest evaluations of f
each rule needs to reach a relative error on the tables' integrands; and the time to reach 1e-12
with `integrate_to_tolerance` against `scipy.integrate.dblquad`."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes, fewer cases")
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("integrate", "Integration", ABOUT)
    if args.quick:
        throughput(page, 5, (5,), (1, 9))
        error_vs_cost(page, (9,))
        versus_dblquad(page, (9,))
    else:
        throughput(page, 6, (5, 10), (1, 3, 7, 9, 11))
        error_vs_cost(page, (1, 2, 7, 9, 11))
        versus_dblquad(page, (1, 2, 3, 5, 7, 9, 10, 11))
    page.write(args)


if __name__ == "__main__":
    main()
