"""Composite domains: decomposition time and blocks, against the same outline as one polygon.

Run: ``python benchmarks/bench_composite.py [--repeat 3]`` (writes docs/benchmarks/composite.md).

For every composite catalogue domain (several parts, a later part cut out of the earlier ones),
prints and writes to its page a table of

- the composite: its regions and interfaces, its blocks, the time of the fragmenting (shapely:
  parts cut, noded, faces found and checked), of the decomposition of all faces at once
  (``decompose_faces``: triangulation with the interfaces as segments, templates, node moves),
  and of the whole construction (the two, plus the arcs put on the circles and the Domain's own
  checks, the curve checks included);
- the same outline as one polygon of one material (the union of the parts: no interface, no
  fibre boundary inside), made with ``Domain.from_shapely``: its blocks and time;
- the first part alone with the later ones cut out as holes (what the one-polygon route could
  do before: a matrix with circular holes, ``Domain.from_polygon(..., circles=...)``).

The blocks say what the interfaces cost; the split of the time where it goes. Each
time is the best of ``--repeat`` runs after a warm-up. Not a test: timings on shared machines
are noisy.
"""

from __future__ import annotations

import argparse
import time
import tomllib
import warnings

import shapely
from _page import Page, add_arguments

import blockmesh
from blockmesh import Domain
from blockmesh.decompose.fragments import decompose_faces
from blockmesh.domain.catalogue import catalogue_names, catalogue_path
from blockmesh.domain.compose import MIN_ANGLE, arrange, extent
from blockmesh.domain.parts import part_from_table


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


def parts_of(name: str) -> list:
    raw = tomllib.loads(catalogue_path(name).read_text())
    return [part_from_table(table, k) for k, table in enumerate(raw["parts"])]


def stages(parts: list) -> tuple[float, float]:
    """Seconds of the fragmenting (up to the checked arrangement) and of the decomposition."""
    start = time.perf_counter()
    _, _, arrangement = arrange(parts, extent(parts))
    middle = time.perf_counter()
    decompose_faces(arrangement.points, arrangement.faces, min_angle=MIN_ANGLE)
    return middle - start, time.perf_counter() - middle


def first_with_holes(name: str) -> Domain:
    """The first part alone, the later parts cut out of it as holes: one material."""
    raw = tomllib.loads(catalogue_path(name).read_text())
    first, later = raw["parts"][0], raw["parts"][1:]
    if all("polygon" not in table for table in later):  # discs: the polygon form's circles
        circles = [c for table in later for c in table.get("circles", [])]
        return Domain.from_polygon(first["polygon"], first.get("holes"), circles=circles)
    shape = shapely.Polygon(first["polygon"], first.get("holes", []))
    for table in later:
        shape = shape.difference(shapely.Polygon(table["polygon"]))
    return Domain.from_shapely(shape)


def best(function, repeat: int):
    """The result of ``function()`` and the best time of ``repeat`` runs after a warm-up."""
    out, fastest = None, float("inf")
    for _ in range(repeat + 1):
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = function()
        fastest = min(fastest, time.perf_counter() - start)
    return out, fastest


def measure(name: str, repeat: int) -> dict[str, object]:
    parts = parts_of(name)
    times = [stages(parts) for _ in range(repeat + 1)]
    domain, total = best(lambda: blockmesh.load_domain(name), repeat)
    outline, outline_s = best(
        lambda: Domain.from_shapely(union_outline(name), name=f"{name} outline"), repeat
    )
    holes, holes_s = best(lambda: first_with_holes(name), repeat)
    return {
        "name": name,
        "regions": len(domain.region_names),
        "interfaces": len(domain.interface_names),
        "interface edges": int(domain.interface_edges.shape[0]),
        "blocks": domain.n_blocks,
        "fragment": min(t[0] for t in times),
        "decompose": min(t[1] for t in times),
        "total": total,
        "outline blocks": outline.n_blocks,
        "outline seconds": outline_s,
        "holes blocks": holes.n_blocks,
        "holes seconds": holes_s,
    }


ABOUT = """Each composite catalogue domain against the same outline as one polygon of one
material (the union of its parts, `Domain.from_shapely`) and against its first part with the
later parts cut out as holes (one material, the circles as circular holes of the polygon form).
*fragment*: the parts cut (a later part cut out of the earlier ones), noded and checked
(shapely); *decompose*: all faces triangulated at once with the interfaces as segments,
templates and node moves; *whole construction*: everything `blockmesh.load_domain` does, the
arcs put on the circles and the Domain's own checks (its curve checks) included.
Each time is the best of `--repeat` runs after a warm-up."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("composite", "Composite domains: decomposition time and blocks", ABOUT)
    table = page.table(
        "The catalogue composites against the same geometry as one polygon",
        [
            "domain",
            "regions",
            "interfaces (block edges)",
            "blocks",
            "fragment s",
            "decompose s",
            "whole construction s",
            "outline as one polygon: blocks, s",
            "first part with holes: blocks, s",
        ],
    )
    for name in composites():
        r = measure(name, args.repeat)
        table.row(
            r["name"],
            r["regions"],
            f"{r['interfaces']} ({r['interface edges']})",
            f"{r['blocks']:,}",
            f"{r['fragment']:.3f}",
            f"{r['decompose']:.3f}",
            f"{r['total']:.2f}",
            f"{r['outline blocks']:,}, {r['outline seconds']:.3f}",
            f"{r['holes blocks']:,}, {r['holes seconds']:.2f}",
        )
    table.note(
        "The blocks say what the interfaces cost (a circle followed on both sides, the parts "
        "decomposed together); the split of the time says where it goes."
    )
    page.write(args)


if __name__ == "__main__":
    main()
