"""Module paths of release 0.1 that moved into the stage packages, kept importable for a while.

``import blockmesh.template`` still works and gives the names ``blockmesh.template`` had, found
in their new homes (``blockmesh.refinement.template``), with a :class:`DeprecationWarning` that
names the new path. Paths whose package kept the old name (``blockmesh.mesh``,
``blockmesh.curves``, ``blockmesh.domain``, ``blockmesh.geometry``, ``blockmesh.refinement``,
``blockmesh.io.vtu`` ...) need nothing: the package re-exports the old names.

Examples
--------
>>> import importlib, warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     old = importlib.reload(importlib.import_module("blockmesh.template"))
>>> old.pentagon_template.__module__
'blockmesh.refinement.template'
>>> str(caught[-1].message)
'blockmesh.template moved to blockmesh.refinement.template; import it from there'
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import operator
import sys
import warnings
from collections.abc import Callable
from types import ModuleType
from typing import Any

__all__ = ["MOVED", "RENAMED", "install", "removed_names"]

#: Old module -> its new home, then the other modules that received some of its names.
MOVED: dict[str, tuple[str, ...]] = {
    "blockmesh.atomic": ("blockmesh._system.atomic",),
    "blockmesh.libc": ("blockmesh._system.libc",),
    "blockmesh.prefault": ("blockmesh._system.prefault",),
    "blockmesh.threads": ("blockmesh._system.threads",),
    "blockmesh.memory": ("blockmesh.refinement.sizes", "blockmesh._system.memory"),
    "blockmesh.gauss": ("blockmesh.numerics.gauss",),
    "blockmesh.doubledouble": ("blockmesh.numerics.doubledouble",),
    "blockmesh.expr": ("blockmesh.numerics.expr",),
    "blockmesh.polynomial": ("blockmesh.numerics.polynomial",),
    "blockmesh.topology": ("blockmesh.geometry.topology",),
    "blockmesh.measures": ("blockmesh.mesh.measures",),
    "blockmesh.template": ("blockmesh.refinement.template",),
    "blockmesh.blockplan": ("blockmesh.refinement.plan",),
    "blockmesh.grouped_refinement": ("blockmesh.refinement.grouped",),
    "blockmesh.smooth": ("blockmesh.refinement.smoothing",),
    "blockmesh.improve": ("blockmesh.refinement.improve",),
    "blockmesh.curved_refinement": ("blockmesh.refinement.curved", "blockmesh.curves.edges"),
    "blockmesh.curve_checks": ("blockmesh.domain.curve_checks",),
    "blockmesh.curved_polygons": ("blockmesh.domain.curved_polygons",),
    "blockmesh.curved_quadrature": ("blockmesh.quadrature.curved", "blockmesh.curves.edges"),
    "blockmesh.curved_exact": ("blockmesh.quadrature.exact_curved",),
    "blockmesh.exact": ("blockmesh.quadrature.exact",),
    "blockmesh.blockgraph": ("blockmesh.domain.blockgraph",),
    "blockmesh.validate": ("blockmesh.domain.validate",),
    "blockmesh.tomlio": ("blockmesh.domain.tomlio",),
    "blockmesh.loading": ("blockmesh.domain.loading",),
    "blockmesh.catalogue": ("blockmesh.domain.catalogue",),
    "blockmesh.plot_tables": ("blockmesh.tables.plot",),
    "blockmesh.io._common": ("blockmesh.io.common",),
    "blockmesh.commands._common": ("blockmesh.commands.common",),
    "blockmesh.io.vtu_stream": ("blockmesh.io.vtu.stream",),
    "blockmesh.io.legacy_vtk": ("blockmesh.io.vtk.format",),
    "blockmesh.io.vtk_stream": ("blockmesh.io.vtk.stream",),
    "blockmesh.io.msh_reader": ("blockmesh.io.msh.reader",),
    "blockmesh.io.msh_writer": ("blockmesh.io.msh.writer",),
    "blockmesh.io.mat_check": ("blockmesh.io.mat.check",),
    "blockmesh.io.openfoam_reader": ("blockmesh.io.openfoam.reader",),
    "blockmesh.io.openfoam_writer": ("blockmesh.io.openfoam.writer",),
}

#: Old names that became something else: the dotted path of what replaces them.
RENAMED: dict[tuple[str, str], str] = {
    ("blockmesh.curved_quadrature", "cell_areas"): "blockmesh.mesh.mesh:Mesh.curved_cell_areas",
    ("blockmesh.polynomial", "as_polynomial"): "blockmesh.numerics.expr:as_polynomial",
    ("blockmesh.decompose.conversion", "convert_mesh"): "blockmesh.domain.loading:convert_mesh",
}


def _resolve(target: str) -> Any:
    module, _, attribute = target.partition(":")
    return operator.attrgetter(attribute)(importlib.import_module(module))


def removed_names(module: str) -> Callable[[str], Any]:
    """A module ``__getattr__`` that finds the names :data:`RENAMED` moves out of ``module``.

    Examples
    --------
    >>> import warnings
    >>> lookup = removed_names("blockmesh.polynomial")
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     lookup("as_polynomial").__module__
    'blockmesh.numerics.expr'
    """

    def lookup(name: str) -> Any:
        target = RENAMED.get((module, name))
        if target is None:
            raise AttributeError(f"module {module!r} has no attribute {name!r}")
        warnings.warn(
            f"{module}.{name} moved to {target.replace(':', '.')}; import it from there",
            DeprecationWarning,
            stacklevel=2,
        )
        return _resolve(target)

    return lookup


class _MovedModule(ModuleType):
    """An old module path: every attribute is looked up in the modules that received its names."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        renamed = RENAMED.get((self.__name__, name))
        if renamed is not None:
            return _resolve(renamed)
        for home in MOVED[self.__name__]:
            module = importlib.import_module(home)
            if hasattr(module, name):
                return getattr(module, name)
        raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")


class _MovedFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds the old paths of :data:`MOVED` and loads each as a :class:`_MovedModule`."""

    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Any:  # noqa: ARG002
        if fullname not in MOVED:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec: Any) -> ModuleType:
        return _MovedModule(spec.name)

    def exec_module(self, module: ModuleType) -> None:
        home = MOVED[module.__name__][0]
        warnings.warn(
            f"{module.__name__} moved to {home}; import it from there",
            DeprecationWarning,
            stacklevel=2,
        )


def install() -> None:
    """Put the finder of old paths at the end of :data:`sys.meta_path` (once)."""
    if not any(isinstance(finder, _MovedFinder) for finder in sys.meta_path):
        sys.meta_path.append(_MovedFinder())
