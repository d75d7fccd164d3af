"""Composite domains: decomposition time and blocks, against the same outline as one polygon.

Run: ``python benchmarks/bench_composite.py [--repeat 3] [--output docs/benchmarks/composite.md]``.

For every composite catalogue domain (several parts, a later part cut out of the earlier ones),
prints and writes a Markdown table of

- the composite: its regions and interfaces, its blocks, the time of the fragmenting (shapely:
  parts cut, noded, faces found and checked), of the decomposition of all faces at once
  (``decompose_faces``: triangulation with the interfaces as segments, templates, node moves),
  and of the whole construction (the two, plus the arcs put on the circles and the Domain's own
  checks, the curve checks included);
- the same outline as one polygon of one material (the union of the parts: no interface, no
  fibre boundary inside), made with ``Domain.from_shapely``: its blocks and time.

The ratio of blocks says what the interfaces cost; the split of the time where it goes. Each
time is the best of ``--repeat`` runs after a warm-up. Not a test: timings on shared machines
are noisy.
"""

from __future__ import annotations

import argparse
import time
import tomllib
import warnings
from pathlib import Path

import shapely

import blockmesh
import blockmesh.domain.compose as compose
from blockmesh import Domain
from blockmesh.domain.catalogue import catalogue_names, catalogue_path


def composites() -> list[str]:
    return [n for n in catalogue_names() if "[[parts]]" in catalogue_path(n).read_text()]


def union_outline(name: str) -> shapely.Geometry:
    """The union of a composite catalogue domain's parts (circles followed finely)."""
    raw = tomllib.loads(catalogue_path(name).read_text())
    shapes = []
    for table in raw["parts"]:
        discs = [
            shapely.Point(*c["center"]).buffer(c["radius"], quad_segs=16)
            for c in table.get("circles", [])
        ]
        if "polygon" in table:
            shape = shapely.Polygon(table["polygon"], table.get("holes", []))
            shapes.append(shape.difference(shapely.union_all(discs)) if discs else shape)
        else:
            shapes += discs
    return shapely.union_all(shapes)


class Timed:
    """Wraps a function of :mod:`blockmesh.domain.compose` and adds up its time."""

    def __init__(self, name: str) -> None:
        self.name, self.original, self.seconds = name, getattr(compose, name), 0.0

    def __call__(self, *args, **kwargs):
        start = time.perf_counter()
        try:
            return self.original(*args, **kwargs)
        finally:
            self.seconds += time.perf_counter() - start


def measure(name: str, repeat: int) -> dict[str, object]:
    best: dict[str, float] = {}
    domain = None
    for _ in range(repeat + 1):  # the first run warms up
        timers = {key: Timed(key) for key in ("_fragments", "decompose_faces")}
        for key, timer in timers.items():
            setattr(compose, key, timer)
        original_of = compose._Arrangement.of
        spent = [0.0]

        def timed_of(*args, _of=original_of, _spent=spent, **kwargs):
            start = time.perf_counter()
            try:
                return _of(*args, **kwargs)
            finally:
                _spent[0] += time.perf_counter() - start

        compose._Arrangement.of = timed_of  # type: ignore[method-assign]
        try:
            start = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                domain = blockmesh.load_domain(name)
            total = time.perf_counter() - start
        finally:
            for key, timer in timers.items():
                setattr(compose, key, timer.original)
            compose._Arrangement.of = original_of  # type: ignore[method-assign]
        figures = {
            "fragment": timers["_fragments"].seconds + spent[0],
            "decompose": timers["decompose_faces"].seconds,
            "total": total,
        }
        for key, value in figures.items():
            best[key] = min(best.get(key, float("inf")), value)
    assert domain is not None
    outline = union_outline(name)
    one_best = float("inf")
    single = None
    for _ in range(repeat + 1):
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            single = Domain.from_shapely(outline, name=f"{name} as one polygon")
        one_best = min(one_best, time.perf_counter() - start)
    assert single is not None
    return {
        "name": name,
        "regions": len(domain.region_names),
        "interfaces": len(domain.interface_names),
        "interface edges": int(domain.interface_edges.shape[0]),
        "blocks": domain.n_blocks,
        **best,
        "one blocks": single.n_blocks,
        "one seconds": one_best,
    }


def table(rows: list[dict[str, object]]) -> str:
    head = (
        "| domain | regions | interfaces (block edges) | blocks | fragment s | decompose s | "
        "whole construction s | one polygon: blocks | one polygon: s | blocks ratio |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    )
    lines = [
        f"| {r['name']} | {r['regions']} | {r['interfaces']} ({r['interface edges']}) | "
        f"{r['blocks']:,} | {r['fragment']:.3f} | {r['decompose']:.3f} | {r['total']:.2f} | "
        f"{r['one blocks']:,} | {r['one seconds']:.3f} | "
        f"{int(r['blocks']) / int(r['one blocks']):.1f} |"  # type: ignore[call-overload]
        for r in rows
    ]
    return head + "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--output", type=Path, default=Path("docs/benchmarks/composite.md"))
    args = parser.parse_args()
    rows = [measure(name, args.repeat) for name in composites()]
    text = table(rows)
    print(text)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(
        "# Composite domains: decomposition time and blocks\n\n"
        "Written by `python benchmarks/bench_composite.py` (best of "
        f"{args.repeat} runs after a warm-up, on a shared 2-core machine: times are noisy). "
        "Each composite catalogue domain against the same outline as one polygon of one "
        "material (the union of its parts, `Domain.from_shapely`). *fragment*: the parts cut "
        "(a later part cut out of the earlier ones), noded and checked (shapely); *decompose*: "
        "all faces triangulated at once with the interfaces as segments, templates and node "
        "moves; *whole construction*: everything `blockmesh.load_domain` does, the arcs put on "
        "the circles and the Domain's own checks (the curve checks to level 5) included.\n\n" + text
    )
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
