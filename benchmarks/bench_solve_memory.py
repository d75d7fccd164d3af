"""The memory guard of ``blockmesh solve`` against measured peak resident memory.

Run: ``python benchmarks/bench_solve_memory.py`` (square, l-shape and lake-island, Poisson and
elasticity, direct solver), or with ``--domains``, ``--levels``, ``--equations``.

Each case runs ``blockmesh solve DOMAIN --level L --equation E ... --json`` in a fresh process,
reads the command's own prediction (``predicted_peak_bytes``, from
:func:`blockmesh.refinement.sizes.predict_solve_command`) and the process's measured peak
resident set (``ru_maxrss`` of the child), and prints their ratio and, from SuperLU, the non-zeros
of L + U against :func:`blockmesh.refinement.sizes.lu_nonzeros`. These runs set the constants
``SOLVE_COSTS``, ``LU_BYTES_PER_NONZERO`` and the fill of ``lu_nonzeros``. Not a test: figures
depend on the machine and its libraries.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time

from _page import Page, add_arguments

RUNNER = """
import json, resource, sys
from scipy.sparse import linalg
from blockmesh.cli import main
splu, found = linalg.splu, {}
def counting(matrix, **options):
    lu = splu(matrix, **options)
    found["lu"] = int(lu.L.nnz + lu.U.nnz)
    return lu
linalg.splu = counting
code = main(sys.argv[1:])
print("PEAK", resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, found.get("lu", 0),
      file=sys.stderr)
sys.exit(code)
"""

#: Boundary conditions per domain and equation (every boundary patch clamped).
CLAMPED = {"poisson": "*=0", "elasticity": "*=0, 0"}
LOADS = {"poisson": "1", "elasticity": "0, -1"}


def measure(domain: str, level: int, equation: str) -> tuple[dict, int, int, float]:
    """(report, measured peak bytes, non-zeros of L + U, seconds) of one solve."""
    argv = ["solve", domain, "--level", str(level), "--equation", equation,
            "--source", LOADS[equation], "--dirichlet", CLAMPED[equation], "--json"]  # fmt: skip
    start = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", RUNNER, *argv], capture_output=True, text=True, check=False
    )
    seconds = time.perf_counter() - start
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed: {out.stderr.strip()[-500:]}")
    peak, lu = (int(v) for v in out.stderr.split("PEAK")[-1].split()[:2])
    return json.loads(out.stdout), peak, lu, seconds


def main() -> None:
    from blockmesh.refinement.sizes import lu_nonzeros

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--domains", nargs="+", default=["square", "l-shape", "lake-island"])
    parser.add_argument("--levels", nargs="+", type=int, default=[3, 4, 5])
    parser.add_argument("--equations", nargs="+", default=["poisson", "elasticity"])
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("solve-memory", "The solve command's memory guard", __doc__)
    table = page.table(
        "blockmesh solve DOMAIN --level L: predicted peak against the measured peak",
        ["domain", "L", "equation", "unknowns", "LU non-zeros", "predicted / LU", "predicted MB",
         "measured MB", "ratio", "seconds"],
    )  # fmt: skip
    worst = 0.0
    for domain in args.domains:
        for equation in args.equations:
            for level in args.levels:
                try:
                    report, peak, lu, seconds = measure(domain, level, equation)
                except RuntimeError as error:
                    table.row(domain, level, equation, str(error), "", "", "", "", "", "")
                    continue
                components = 2 if equation == "elasticity" else 1
                lu_predicted = lu_nonzeros(report["nodes"], components)
                ratio = report["predicted_peak_bytes"] / peak
                worst = max(worst, abs(ratio - 1))
                table.row(
                    domain, level, equation, f"{report['dof']:,}", f"{lu:,}",
                    f"{lu_predicted / lu:.2f}x", f"{report['predicted_peak_bytes'] / 1e6:.0f}",
                    f"{peak / 1e6:.0f}", f"{ratio:.2f}", f"{seconds:.1f}",
                )  # fmt: skip
    page.text(f"Largest deviation of the predicted peak from the measured: {worst:.0%}.")
    page.write(args)


if __name__ == "__main__":
    main()
