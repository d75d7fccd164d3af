"""The package's layers hold: imports go down the pipeline, never up, never round in a cycle.

The layer order (lowest first) is written in :data:`LAYERS` and in docs/architecture.md. A module
may import modules of its own unit or of a lower layer; within a layer, units are peers. Imports
made inside functions (deferred) count like any other, unless they are listed in
:data:`DEFERRED` with the reason they are deferred; imports made only for type checkers count for
the order but not for cycles. No module imports a private name (``_name``) from another package.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from imports import PACKAGE, Import, imports, modules

#: The units of the package, layer by layer from the bottom (a unit is a package or module).
LAYERS: list[tuple[str, ...]] = [
    ("blockmesh.errors", "blockmesh.checks", "blockmesh._system", "blockmesh._moved"),
    ("blockmesh.numerics",),
    ("blockmesh.geometry",),
    ("blockmesh.curves",),
    ("blockmesh.sizing",),
    ("blockmesh.mesh",),
    ("blockmesh.io",),
    ("blockmesh.refinement",),
    ("blockmesh.decompose",),
    ("blockmesh.domain",),
    ("blockmesh.plot",),
    ("blockmesh.quadrature",),
    ("blockmesh.vem",),
    ("blockmesh.distributed",),
    ("blockmesh.tables",),
    ("blockmesh.commands",),
    ("blockmesh.cli", "blockmesh.__main__", "blockmesh"),
]

#: Imports kept inside functions, (importing module, imported module): why.
DEFERRED: dict[tuple[str, str], str] = {
    ("blockmesh.cli", "blockmesh.commands.common"): (
        "start-up: `blockmesh --help` and `--version` import no numerical library"
    ),
    ("blockmesh.commands._partitions", "blockmesh.distributed"): (
        "optional extra: Dask is imported only for --partitions / --scheduler"
    ),
    ("blockmesh.commands.integrate", "blockmesh.distributed"): (
        "optional extra: Dask is imported only for --partitions / --scheduler"
    ),
    ("blockmesh.commands.mesh.partitioned", "blockmesh.distributed"): (
        "optional extra: Dask is imported only for --partitions / --scheduler"
    ),
    ("blockmesh.commands.mesh.partitioned", "blockmesh.distributed.files"): (
        "optional extra: Dask is imported only for --partitions / --scheduler"
    ),
    ("blockmesh.commands.mesh.single", "blockmesh.plot"): (
        "start-up: matplotlib (about 0.3 s) is imported only when a picture is asked for"
    ),
    ("blockmesh.commands.solve", "blockmesh.vem.plot"): (
        "start-up: matplotlib (about 0.3 s) is imported only when a picture is asked for"
    ),
    ("blockmesh.commands.solve_adaptive", "blockmesh.vem.plot"): (
        "start-up: matplotlib (about 0.3 s) is imported only when a picture is asked for"
    ),
    ("blockmesh.domain.domain", "blockmesh.domain.blockgraph"): (
        "start-up: networkx (about 0.2 s) is imported only when the block graph is asked for"
    ),
}


def unit_of(module: str) -> tuple[int, str]:
    """The layer and unit of a module (the longest unit name that contains it)."""
    matches = [
        (layer, unit)
        for layer, units in enumerate(LAYERS)
        for unit in units
        if module == unit or module.startswith(unit + ".")
    ]
    if not matches:
        raise AssertionError(f"{module} belongs to no unit of LAYERS: add it")
    return max(matches, key=lambda match: len(match[1]))


def upward(found: list[Import]) -> list[str]:
    out = []
    for imp in found:
        (low, _), (high, _) = unit_of(imp.source), unit_of(imp.target)
        if high > low:
            out.append(f"{imp.source}:{imp.line} imports {imp.target} (a higher layer)")
    return out


def cycles(found: list[Import]) -> list[list[str]]:
    """Cycles among modules through imports that run (typing-only ones left out)."""
    graph: dict[str, set[str]] = {}
    for imp in found:
        if not imp.typing_only and imp.target != imp.source:
            graph.setdefault(imp.source, set()).add(imp.target)
    # Tarjan's strongly connected components, iteratively.
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []
    counter = 0
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.get(root, ()))))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is None:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        out.append(sorted(component))
            elif child not in index:
                index[child] = low[child] = counter
                counter += 1
                stack.append(child)
                on_stack.add(child)
                work.append((child, iter(sorted(graph.get(child, ())))))
            elif child in on_stack:
                low[node] = min(low[node], index[child])
    return out


def package_of(module: str) -> str:
    """The top-level unit a module belongs to (``blockmesh.io.vtu.format`` -> ``blockmesh.io``)."""
    parts = module.split(".")
    return ".".join(parts[:2])


@pytest.fixture(scope="module")
def found() -> list[Import]:
    return imports()


def test_every_module_has_a_unit():
    homeless = []
    for module in modules():
        try:
            unit_of(module)
        except AssertionError:
            homeless.append(module)
    assert homeless == [], "add their packages to LAYERS"


def test_no_import_goes_up_a_layer(found):
    assert upward(found) == []


def test_no_cycle_among_modules(found):
    assert cycles(found) == []


def test_deferred_imports_are_the_listed_ones(found):
    deferred = {
        (imp.source, imp.target)
        for imp in found
        if imp.deferred and not imp.typing_only and imp.target != imp.source
    }
    assert deferred == set(DEFERRED)


def test_no_private_name_crosses_a_package(found):
    crossing = [
        f"{imp.source}:{imp.line} imports {name} from {imp.target}"
        for imp in found
        for name in imp.names
        if name.startswith("_")
        and not name.startswith("__")
        and package_of(imp.source) != package_of(imp.target)
    ]
    private_modules = [
        f"{imp.source}:{imp.line} imports {imp.target}"
        for imp in found
        if any(part.startswith("_") and not part.startswith("__") for part in imp.target.split("."))
        and package_of(imp.source) != package_of(imp.target)
        and not imp.target.startswith("blockmesh._system")
        and imp.target != "blockmesh._moved"
    ]
    assert crossing + private_modules == []


def test_the_checks_find_what_they_look_for():
    """Each check fails on an import that breaks it (the tests above can fail)."""
    up = Import("blockmesh.mesh.mesh", "blockmesh.domain.domain", ("Domain",), 1, False, False)
    assert upward([up]) == [
        "blockmesh.mesh.mesh:1 imports blockmesh.domain.domain (a higher layer)"
    ]
    down = Import("blockmesh.domain.domain", "blockmesh.mesh.mesh", ("Mesh",), 1, False, False)
    assert upward([down]) == []
    assert cycles([up, down]) == [["blockmesh.domain.domain", "blockmesh.mesh.mesh"]]
    typing_only = Import("blockmesh.mesh.mesh", "blockmesh.domain.domain", (), 1, False, True)
    assert cycles([typing_only, down]) == []


def test_the_packages_shipped_are_the_packages_on_disk():
    """pyproject.toml lists every package folder (a missing one is missing from the wheel)."""
    config = tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text(encoding="utf-8"))
    listed = set(config["tool"]["setuptools"]["packages"]) - {"blockmesh.domains"}
    on_disk = {
        ".".join(path.parent.relative_to(PACKAGE.parent).parts)
        for path in Path(PACKAGE).rglob("__init__.py")
    }
    assert listed == on_disk
