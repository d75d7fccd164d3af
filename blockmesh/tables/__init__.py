"""The paper's Tables 1-11, regenerated: integrands, reference values, errata and layout.

Each table integrates one function over the paper's two pentagons, SP ``<(-1,-1), (1,-1), (2,0),
(0,1), (-2,0)>`` and USP ``<(0,0), (2,0), (3,1), (1,3), (0,2)>``, refined to NPMR = 6**L cells
(L = 1..4), with the paper's rule (:mod:`blockmesh.quadrature.paper`) at orders (OGLR) 1..10
(Tables 1-6) or 5, 10, ..., 45 (Tables 7-11).

The package: :mod:`.data` (the paper's data, read from ``paper_tables.json`` here: pentagons,
integrands, reference values with ``∫|f|``, the printed entries, the errata), :mod:`.compute`
(the tables regenerated), :mod:`.report` (text in the paper's layout, CSV); the convergence
picture is :func:`blockmesh.tables.plot.plot_convergence`.

Examples
--------
>>> case = paper_case(3, "SP")
>>> case.integrand, case.exact
('(0.2*x + 0.3*y)^19', Fraction(-389834752439, 7000000000000000000))
>>> result = compute_table(1, "USP", levels=(1, 2), orders=(10,))
>>> bool(result.errors.max() < TOLERANCE * result.case.abs_integral)
True
"""

# The public names are the modules' own __all__ (below), imported one by one for the analysers.
from blockmesh.tables import compute, data, report
from blockmesh.tables.compute import PaperTable, compute_table, pentagon_mesh  # noqa: F401
from blockmesh.tables.data import (  # noqa: F401
    CASES,
    ERRATA,
    INTEGRANDS,
    PENTAGONS,
    TABLES,
    TOLERANCE,
    Erratum,
    PaperCase,
    PrintedEntry,
    paper_case,
    pentagon_title,
    table_orders,
)
from blockmesh.tables.plot import plot_convergence
from blockmesh.tables.report import format_table, write_csv  # noqa: F401

__all__ = [*data.__all__, *compute.__all__, *report.__all__]


def __getattr__(name: str) -> object:
    """``plot_convergence`` from :mod:`blockmesh.tables.plot` (kept here for old imports)."""
    if name == "plot_convergence":
        return plot_convergence
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
