"""The paper's Tables 1-11, regenerated: integrands, reference values, errata and layout.

Each table integrates one function over the paper's two pentagons, SP ``<(-1,-1), (1,-1), (2,0),
(0,1), (-2,0)>`` and USP ``<(0,0), (2,0), (3,1), (1,3), (0,2)>``, refined to NPMR = 6**L cells
(L = 1..4), with the paper's rule (:func:`blockmesh.quadrature.integrate`, ``rule="paper"``) at
orders (OGLR) 1..10 (Tables 1-6) or 5, 10, ..., 45 (Tables 7-11).

The reference values are high-precision (>= 30 digits; exact rationals for the polynomials of
Tables 3-6), copied from the project's ``paper-reference.json`` together with ``∫|f|`` per case,
the scale of the round-off floor: a double-precision result is as good as it gets when
``|value - reference| <= 1e-13 * ∫|f|``.

Examples
--------
>>> case = paper_case(3, "SP")
>>> case.integrand, case.exact
('(0.2*x + 0.3*y)^19', Fraction(-389834752439, 7000000000000000000))
>>> table_orders(7)
(5, 10, 15, 20, 25, 30, 35, 40, 45)
>>> result = compute_table(1, "USP", levels=(1, 2), orders=(10,))
>>> bool(result.errors.max() < 1e-13 * result.case.abs_integral)
True
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

import numpy as np

from .errors import BlockMeshError
from .mesh import Mesh
from .quadrature import DEFAULT_CHUNK, integrate
from .refinement import refine

__all__ = [
    "CASES",
    "ERRATA",
    "INTEGRANDS",
    "PENTAGONS",
    "TABLES",
    "Erratum",
    "PaperCase",
    "PaperTable",
    "compute_table",
    "format_table",
    "paper_case",
    "pentagon_mesh",
    "plot_convergence",
    "table_orders",
    "write_csv",
]

#: The paper's two pentagons, counter-clockwise.
PENTAGONS: dict[str, tuple[tuple[int, int], ...]] = {
    "SP": ((-1, -1), (1, -1), (2, 0), (0, 1), (-2, 0)),
    "USP": ((0, 0), (2, 0), (3, 1), (1, 3), (0, 2)),
}

_PENTAGON_TITLES = {"SP": "symmetrical pentagon", "USP": "unsymmetrical pentagon"}

#: Table -> (the paper's function number in ``fnxy``, the integrand as an expression).
#: Table 11's last term is used as printed, with y twice: -0.2 exp(-(9y-4)^2 - (9y-7)^2).
INTEGRANDS: dict[int, tuple[int, str]] = {
    1: (100, "(x^4 + y^3) / (1 + x^2)"),
    2: (101, "(1 - x) * sin(10*x*y)"),
    3: (102, "(0.2*x + 0.3*y)^19"),
    4: (103, "(0.17*x + 0.25*y)^25"),
    5: (104, "(x + y)^19 / 10^10"),
    6: (105, "(x - y)^20 / 10^5"),
    7: (106, "cos(30*(x + y))"),
    8: (107, "sqrt((x - 0.5)^2 + (y - 0.5)^2)"),
    9: (108, "exp(-((x - 1/2)^2 + (y - 1/2)^2))"),
    10: (109, "exp(-100*((x - 1/2)^2 + (y - 1/2)^2))"),
    11: (
        110,
        "0.75*exp(-0.25*(9*x - 2)^2 - 0.25*(9*y - 2)^2)"
        " + 0.75*exp((-1/49)*(9*x + 1)^2 - 0.1*(9*y + 1))"
        " + 0.5*exp(-0.25*(9*x - 7)^2 - 0.25*(9*y - 3)^2)"
        " + -0.2*exp(-(9*y - 4)^2 - (9*y - 7)^2)",
    ),
}

#: The table numbers.
TABLES = tuple(INTEGRANDS)


@dataclass(frozen=True)
class PaperCase:
    """One (table, pentagon) pair: integrand, reference value and ``∫|f|``."""

    table: int
    pentagon: str
    reference: str
    abs_integral: float
    exact_fraction: str | None = None

    @property
    def fid(self) -> int:
        """The paper's function number (``fnxy`` case)."""
        return INTEGRANDS[self.table][0]

    @property
    def integrand(self) -> str:
        """The integrand as an expression string."""
        return INTEGRANDS[self.table][1]

    @property
    def exact(self) -> Fraction:
        """The reference value as an exact Fraction (the true value for Tables 3-6)."""
        return Fraction(self.exact_fraction or self.reference)


#: The 22 cases (reference values to >= 34 significant digits).
CASES: tuple[PaperCase, ...] = (
    PaperCase(1, "SP", "1.924030542632650121575145369629934", 2.5071499943129734),
    PaperCase(1, "USP", "20.48256361468692452827984674976528", 20.482563614686924),
    PaperCase(2, "SP", "-0.01310371966995714406601960433308732", 3.331978820005585),
    PaperCase(2, "USP", "0.2330293242715160874726379671562929", 2.299651515115417),
    PaperCase(
        3,
        "SP",
        "-5.569067891985714285714285714285714e-8",
        5.694441728270238e-08,
        "-389834752439/7000000000000000000",
    ),
    PaperCase(
        3,
        "USP",
        "0.6943645045589234334523809523809524",
        0.6943645045589235,
        "5832661838294956841/8400000000000000000",
    ),
    PaperCase(
        4,
        "SP",
        "-6.999009126799835395369416881177761e-12",
        7.049609166611502e-12,
        "-4913304407013484447549330650586788391339/"
        "702000000000000000000000000000000000000000000000000",
    ),
    PaperCase(
        4,
        "USP",
        "0.008874019492738579967319291621209903",
        0.008874019492738588,
        "1547128380314132356906469344618258852140137/174343585968017578125000000000000000000000000",
    ),
    PaperCase(
        5,
        "SP",
        "-4.660338095238095238095238095238095e-6",
        6.158303174603175e-06,
        "-978671/210000000000",
    ),
    PaperCase(
        5, "USP", "10.99511577843809523809523809523810", 10.995115778438096, "2254857728/205078125"
    ),
    PaperCase(6, "SP", "1.165084415584415584415584415584416", 1.165084415584416, "179423/154000"),
    PaperCase(6, "USP", "2.088073419913419913419913419913420", 2.08807341991342, "1507328/721875"),
    PaperCase(7, "SP", "-0.007436177299024373219858448899496427", 3.1864112740440698),
    PaperCase(7, "USP", "0.03653806452480411229361177887938740", 3.8321785830332282),
    PaperCase(8, "SP", "5.809534594898993711537644374406389", 5.809534588569726),
    PaperCase(8, "USP", "7.800618298021123954289758058444030", 7.800618295026695),
    PaperCase(9, "SP", "1.729175291842216445410886742214897", 1.7291752918422165),
    PaperCase(9, "USP", "1.798096146581152670802198439191585", 1.7980961465811527),
    PaperCase(10, "SP", "0.03139133725472966396367968598186081", 0.03139133725472966),
    PaperCase(10, "USP", "0.03141592653584963166067280451776289", 0.03141592653584963),
    PaperCase(11, "SP", "2.190018384318485748596900210234507", 2.1900183843184857),
    PaperCase(11, "USP", "0.5580351276015039284914693665917746", 0.5584815257717798),
)


@dataclass(frozen=True)
class Erratum:
    """A misprint in the paper (the program and this module compute the corrected value)."""

    table: int
    pentagon: str
    order: int | None
    level: int | None
    note: str


#: The paper's misprints in Tables 1-11 (entries and header values).
ERRATA: tuple[Erratum, ...] = (
    Erratum(
        3,
        "SP",
        1,
        1,
        "printed +3.247407437070757e-008: the sign is lost; correct -3.247407437070756e-08",
    ),
    Erratum(
        8, "USP", 5, 3, "printed 7.80061806668203e+000 drops a digit 6; correct 7.800618066668207"
    ),
    Erratum(
        8, "USP", 45, 1, "printed 7.80061835888679e+000 drops a digit 8; correct 7.800618358888683"
    ),
    Erratum(
        4,
        "SP",
        None,
        None,
        "the printed EXACT VALUE -6.999...e-11 is 10x too large; correct -6.999009126799835395e-12",
    ),
    Erratum(2, "USP", None, None, "no EXACT VALUE printed; reference 0.23302932427151608747"),
    Erratum(
        1,
        "SP",
        None,
        None,
        "the printed EXACT VALUE is wrong after ~17 digits "
        "(the MATLAB program's 1.9240305426326501215751453696299 is right)",
    ),
    Erratum(
        11,
        "SP",
        None,
        None,
        "f4 is printed -0.2 exp(-(9y-4)^2 - (9y-7)^2) (y twice); the tables use it as printed",
    ),
    Erratum(
        11,
        "USP",
        None,
        None,
        "f4 is printed -0.2 exp(-(9y-4)^2 - (9y-7)^2) (y twice); the tables use it as printed",
    ),
)


def _check_table(table: int) -> int:
    if isinstance(table, bool) or table not in INTEGRANDS:
        raise BlockMeshError(f"no table {table!r}; the paper's tables are 1..{max(TABLES)}")
    return int(table)


def _check_pentagon(pentagon: str) -> str:
    key = str(pentagon).upper()
    if key not in PENTAGONS:
        raise BlockMeshError(f"unknown pentagon {pentagon!r}; choose SP or USP")
    return key


def table_orders(table: int) -> tuple[int, ...]:
    """The orders (OGLR) a table lists: 1..10 for Tables 1-6, 5, 10, ..., 45 for Tables 7-11.

    Examples
    --------
    >>> table_orders(1)
    (1, 2, 3, 4, 5, 6, 7, 8, 9, 10)
    """
    return tuple(range(1, 11)) if _check_table(table) <= 6 else tuple(range(5, 50, 5))


def paper_case(table: int, pentagon: str) -> PaperCase:
    """The case of ``table`` (1..11) on ``pentagon`` ("SP" or "USP").

    Examples
    --------
    >>> paper_case(9, "usp").reference
    '1.798096146581152670802198439191585'
    """
    key = (_check_table(table), _check_pentagon(pentagon))
    return next(c for c in CASES if (c.table, c.pentagon) == key)


@lru_cache(maxsize=16)
def pentagon_mesh(pentagon: str, level: int) -> Mesh:
    """The paper's pentagon refined ``level`` times (6**level cells), cached.

    Examples
    --------
    >>> pentagon_mesh("SP", 2).n_cells
    36
    """
    key = _check_pentagon(pentagon)
    base = Mesh.from_cells(np.array(PENTAGONS[key], dtype=np.float64), [[0, 1, 2, 3, 4]], name=key)
    return refine(base, level)


@dataclass(frozen=True, eq=False)
class PaperTable:
    """One regenerated table for one pentagon.

    Attributes
    ----------
    case : PaperCase
    orders, levels : tuple of int
        Rows (OGLR) and columns (NPMR = 6**level).
    values : ndarray (len(orders), len(levels))
    rule : str
    """

    case: PaperCase
    orders: tuple[int, ...]
    levels: tuple[int, ...]
    values: np.ndarray
    rule: str = "paper"

    @property
    def errors(self) -> np.ndarray:
        """``|value - reference|`` of every entry (the reference subtracted exactly)."""
        ref = self.case.exact
        return np.array(
            [[float(abs(Fraction(float(v)) - ref)) for v in row] for row in self.values]
        ).reshape(self.values.shape)

    @property
    def scaled_errors(self) -> np.ndarray:
        """``|value - reference| / ∫|f|``, comparable with the round-off floor 1e-13."""
        return self.errors / self.case.abs_integral


def compute_table(
    table: int,
    pentagon: str,
    *,
    levels: tuple[int, ...] = (1, 2, 3, 4),
    orders: tuple[int, ...] | None = None,
    rule: str = "paper",
    chunk: int = DEFAULT_CHUNK,
) -> PaperTable:
    """Regenerate ``table`` for ``pentagon`` at the given levels and orders.

    Parameters
    ----------
    table : int
        1..11.
    pentagon : {"SP", "USP"}
    levels : tuple of int
        Refinement levels (columns NPMR = 6**level), default the paper's 1..4.
    orders : tuple of int, optional
        Rows; default :func:`table_orders`.
    rule : str
        Quadrature rule, default the paper's.
    chunk : int
        As in :func:`blockmesh.quadrature.integrate`.

    Examples
    --------
    >>> t = compute_table(6, "SP", levels=(1,), orders=(10, 11))
    >>> t.values.shape, bool(t.errors[1, 0] < 1e-14)  # degree 20 is exact from order 11 on
    ((2, 1), True)
    """
    case = paper_case(table, pentagon)
    rows = table_orders(table) if orders is None else tuple(int(n) for n in orders)
    columns = tuple(int(level) for level in levels)
    for level in columns:
        if level < 0:
            raise BlockMeshError(f"levels must be >= 0, got {level}")
    values = np.empty((len(rows), len(columns)))
    for j, level in enumerate(columns):
        mesh = pentagon_mesh(case.pentagon, level)
        for i, n in enumerate(rows):
            values[i, j] = integrate(mesh, case.integrand, order=n, rule=rule, chunk=chunk)
    values.setflags(write=False)
    return PaperTable(case, rows, columns, values, rule)


def _npmr(level: int) -> str:
    return "NPMR=6" if level == 1 else f"NPMR=6^{level}"


def format_table(result: PaperTable) -> str:
    """The table in the paper's layout (OGLR rows x NPMR columns), then the errors.

    Examples
    --------
    >>> print(format_table(compute_table(5, "USP", levels=(1, 2), orders=(10,))))
    ... # doctest: +NORMALIZE_WHITESPACE, +ELLIPSIS
    Table 5, [II] P = USP, unsymmetrical pentagon <1(0,0), 2(2,0), 3(3,1), 4(1,3), 5(0,2)>
      integrand  (x + y)^19 / 10^10
      reference  10.99511577843809523809523809523810
    OGLR  NPMR=6                  NPMR=6^2
      10  1.0995115778438...e+01   1.0995115778438...e+01
    |value - reference|   (round-off floor 1e-13 x ∫|f| = 1.1e-12)
    OGLR  NPMR=6    NPMR=6^2
      10  ...e-15   ...e-15
    """
    case = result.case
    corners = ", ".join(f"{k + 1}({x},{y})" for k, (x, y) in enumerate(PENTAGONS[case.pentagon]))
    tag = "[I]" if case.pentagon == "SP" else "[II]"
    title = _PENTAGON_TITLES[case.pentagon]
    lines = [
        f"Table {case.table}, {tag} P = {case.pentagon}, {title} <{corners}>",
        f"  integrand  {case.integrand}",
        f"  reference  {case.reference}",
    ]
    if result.rule != "paper":
        lines.append(f"  rule       {result.rule}")
    lines.append("OGLR  " + "".join(f"{_npmr(level):<24}" for level in result.levels).rstrip())
    for n, row in zip(result.orders, result.values, strict=True):
        lines.append(f"{n:>4} " + "".join(f"{v:< 24.15e}" for v in row).rstrip())
    floor = 1e-13 * case.abs_integral
    lines.append(f"|value - reference|   (round-off floor 1e-13 x ∫|f| = {floor:.2g})")
    lines.append("OGLR  " + "".join(f"{_npmr(level):<10}" for level in result.levels).rstrip())
    for n, row in zip(result.orders, result.errors, strict=True):
        lines.append(f"{n:>4}  " + "".join(f"{e:<10.1e}" for e in row).rstrip())
    for erratum in ERRATA:
        if (erratum.table, erratum.pentagon) == (case.table, case.pentagon):
            where = (
                f"OGLR {erratum.order}, NPMR=6^{erratum.level}: "
                if erratum.order is not None
                else ""
            )
            lines.append(f"  paper erratum: {where}{erratum.note}")
    return "\n".join(lines)


_CSV_FIELDS = (
    "table",
    "pentagon",
    "integrand",
    "rule",
    "order",
    "level",
    "npmr",
    "value",
    "reference",
    "abs_error",
    "error_over_abs_integral",
)


def write_csv(results: list[PaperTable], handle: io.TextIOBase) -> int:
    """Write every entry of ``results`` as CSV rows to an open text file; returns the row count.

    Examples
    --------
    >>> buffer = io.StringIO()
    >>> write_csv([compute_table(1, "SP", levels=(1,), orders=(1,))], buffer)
    1
    >>> buffer.getvalue().splitlines()[0].split(",")[:4]
    ['table', 'pentagon', 'integrand', 'rule']
    """
    writer = csv.writer(handle, lineterminator="\n")
    writer.writerow(_CSV_FIELDS)
    rows = 0
    for result in results:
        case = result.case
        errors, scaled = result.errors, result.scaled_errors
        for i, n in enumerate(result.orders):
            for j, level in enumerate(result.levels):
                writer.writerow(
                    (
                        case.table,
                        case.pentagon,
                        case.integrand,
                        result.rule,
                        n,
                        level,
                        6**level,
                        repr(float(result.values[i, j])),
                        case.reference,
                        f"{errors[i, j]:.6e}",
                        f"{scaled[i, j]:.6e}",
                    )
                )
                rows += 1
    return rows


def plot_convergence(results: list[PaperTable], path: str) -> None:
    """Draw error / ∫|f| against level, one line per order, one panel per table and pentagon.

    Uses matplotlib's Agg backend (imported here, not at import time). Entries at or below
    ``1e-17`` are drawn at ``1e-17``; the dashed line is the round-off floor ``1e-13``. The file
    is written atomically (:func:`blockmesh.plot.save_figure`).
    """
    from .plot import pyplot, save_figure

    plt = pyplot()

    tables = sorted({r.case.table for r in results})
    pentagons = [p for p in PENTAGONS if any(r.case.pentagon == p for r in results)]
    fig, axes = plt.subplots(
        len(tables),
        len(pentagons),
        figsize=(5.2 * len(pentagons) + 1.6, 3.4 * len(tables)),
        squeeze=False,
        constrained_layout=True,
    )
    cmap = plt.get_cmap("viridis")
    for result in results:
        row, col = tables.index(result.case.table), pentagons.index(result.case.pentagon)
        ax = axes[row][col]
        scaled = np.maximum(result.scaled_errors, 1e-17)
        for i, n in enumerate(result.orders):
            colour = cmap(i / max(1, len(result.orders) - 1))
            ax.semilogy(
                result.levels, scaled[i], "o-", color=colour, ms=3.5, lw=1.3, label=f"n={n}"
            )
        ax.axhline(1e-13, color="0.4", ls="--", lw=0.9, label="floor 1e-13")
        ax.set_xticks(result.levels, [f"$6^{level}$" for level in result.levels])
        ax.set_ylim(5e-18, 2.0)
        ax.grid(True, which="major", color="0.9")
        ax.set_title(
            f"Table {result.case.table}, {result.case.pentagon}: {_short(result.case)}", fontsize=9
        )
        ax.set_xlabel("NPMR (cells)", fontsize=8)
        ax.set_ylabel("|error| / ∫|f|", fontsize=8)
        ax.tick_params(labelsize=8)
        if col == len(pentagons) - 1:
            ax.legend(
                title="OGLR",
                fontsize=7,
                title_fontsize=7,
                loc="center left",
                bbox_to_anchor=(1.02, 0.5),
            )
    rule = results[0].rule if results else "paper"
    fig.suptitle(f"|value - reference| / ∫|f| against mesh level, one line per order ({rule} rule)")
    save_figure(fig, path, dpi=110)


def _short(case: PaperCase) -> str:
    text = case.integrand
    return text if len(text) <= 38 else "Franke-like sum of 4 exponentials"
