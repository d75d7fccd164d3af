"""``blockmesh mesh`` of several domains (names, files or globs) on up to two processes.

``-o`` (and each picture) must then name each output with ``{name}``. A domain that fails is
reported and does not stop the others; the exit code is then 1.
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
from typing import Any

from blockmesh.commands.common import ProgressBar, load_target, print_json, printable
from blockmesh.commands.mesh.single import mesh_one
from blockmesh.errors import BlockMeshError


def expand_globs(names: list[str]) -> list[str]:
    """``names`` with each glob pattern replaced by the files it matches (sorted)."""
    expanded = []
    for name in names:
        if any(c in name for c in "*?["):
            matches = sorted(glob.glob(name))
            if not matches:
                raise BlockMeshError(f"no file matches {name!r}")
            expanded += matches
        else:
            expanded.append(name)
    return expanded


def _batch_worker(name: str, options: dict[str, Any], output: str | None) -> dict[str, Any]:
    try:
        target = load_target(name, max_memory=options["max_memory"])
        return {"ok": True, **mesh_one(target, options, output)}
    except BlockMeshError as error:
        return {"ok": False, "domain": name, "error": str(error)}


def run_batch(names: list[str], options: dict[str, Any], args: argparse.Namespace) -> int:
    """Mesh every domain of ``names`` on up to two processes; the exit code (1 if any failed)."""
    output = args.output
    for key in ("output", "plot", "quality_plot", "size_plot"):
        value = getattr(args, key)
        if value and "{name}" not in value:
            raise BlockMeshError(
                f"with several domains, --{key.replace('_', '-')} must contain {{name}} so that "
                f"each domain gets its own file, e.g. 'out/{{name}}.vtu'"
            )
    bar = ProgressBar(f"meshing {len(names)} domains", enabled=ProgressBar.wanted(args))
    results: list[dict[str, Any]] = []
    from concurrent.futures import ProcessPoolExecutor, as_completed

    workers = min(2, len(names), os.cpu_count() or 1)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(_batch_worker, name, options, output): name for name in names}
        for done, future in enumerate(as_completed(futures), start=1):
            results.append(future.result())
            bar(done, len(names))
    order = {name: k for k, name in enumerate(names)}
    results.sort(key=lambda r: order.get(r["domain"], len(names)))
    failures = [r for r in results if not r["ok"]]
    if args.json:
        print_json({"domains": results, "failed": len(failures)})
    else:
        print(
            f"{'domain':<16} {'cells':>12} {'nodes':>12} {'min°':>7} {'max°':>7} {'s':>7}  output"
        )
        for r in results:
            if r["ok"]:
                q = r["quality"]
                written = [r[k] for k in ("output", "plot", "quality_plot", "size_plot") if r[k]]
                print(
                    f"{printable(r['domain']):<16} {r['cells']:>12,} {r['nodes']:>12,} "
                    f"{q['min_angle']:>7.2f} {q['max_angle']:>7.2f} {r['seconds']:>7.3f}  "
                    f"{printable(', '.join(written)) or '-'}"
                )
            else:
                print(f"{printable(r['domain']):<16} FAILED: {printable(r['error'])}")
        print(f"{len(results) - len(failures)} of {len(results)} domains meshed")
    for r in failures:
        print(
            f"blockmesh mesh: {printable(r['domain'])}: error: {printable(r['error'])}",
            file=sys.stderr,
        )
    return 1 if failures else 0
