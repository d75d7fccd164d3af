"""``blockmesh mesh``'s report of one mesh, printed: counts, quality, sizes, bandwidth, files."""

from __future__ import annotations

from typing import Any

from blockmesh.commands.common import printable


def print_report(report: dict[str, Any], done: str = "refined") -> None:
    """Print ``report`` (:func:`~blockmesh.commands.mesh.single.mesh_one`'s) for a reader."""
    q = report["quality"]
    print(
        f"{printable(report['domain'])}: level {report['level']}, {report['cells']:,} cells, "
        f"{report['nodes']:,} nodes, {report['edges']:,} edges "
        f"({report['boundary_edges']:,} on the boundary), area {report['area']:.12g}"
    )
    print(
        f"  angles {q['min_angle']:.2f}° .. {q['max_angle']:.2f}°, max aspect ratio "
        f"{q['max_aspect_ratio']:.3g}, area ratio {q['area_ratio']:.3g}, "
        f"not strictly convex: {q['not_strictly_convex']}"
    )
    for line in _size_lines(report):
        print(line)
    local = report.get("local_refinement")
    if local:
        counts = ", ".join(f"{m:,}" for m in local["marked"])
        print(
            f"  local refinement: {local['rounds']} round(s) marking {counts} cells "
            f"({printable(local['marking'])}); "
            f"{local['hanging_nodes']:,} hanging nodes, cells of up to {local['max_vertices']} "
            "vertices"
        )
    bandwidth = report["bandwidth"]
    line = f"  bandwidth {bandwidth['nested']:,} (nested)"
    if bandwidth["rcm"] is not None:
        line += f" -> {bandwidth['rcm']:,} (reverse Cuthill-McKee)"
    print(line + f"; {done} in {report['seconds']:.3f} s")
    for key, label in (
        ("plot", "plot"),
        ("quality_plot", "quality plot"),
        ("size_plot", "size plot"),
        ("output", "mesh"),
    ):
        if report.get(key):
            print(f"  wrote {label} {printable(report[key])}")


def _size_lines(report: dict[str, Any]) -> list[str]:
    """The size report: diameters and neighbours; size got against size asked when sized."""
    s = report.get("sizes")
    if not s:
        return []
    a, b = s["neighbour_cells"]
    lines = [
        f"  cell diameters {s['min_diameter']:.4g} .. {s['max_diameter']:.4g}; largest "
        f"neighbour size ratio {s['neighbour_ratio']:.3g} (cells {a} and {b})"
    ]
    if s["worst_ratio"] is not None:
        x, y = s["worst_point"]
        lines.append(
            f"  size got / size asked: worst {s['worst_ratio']:.3g} (cell {s['worst_cell']} near "
            f"({x:.6g}, {y:.6g})), mean {s['mean_ratio']:.3g}; {report['cells']:,} cells = "
            f"{s['count_ratio']:.3g} x the ideal {s['ideal_cells']:,.0f}"
        )
    return lines
