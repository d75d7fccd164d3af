"""The regenerated tables as text in the paper's layout, and as CSV rows.

Examples
--------
>>> from blockmesh.tables import compute_table
>>> buffer = io.StringIO()
>>> write_csv([compute_table(1, "SP", levels=(1,), orders=(1,))], buffer)
1
>>> buffer.getvalue().splitlines()[0].split(",")[:4]
['table', 'pentagon', 'integrand', 'rule']
"""

from __future__ import annotations

import csv
import io

from blockmesh.tables.compute import PaperTable
from blockmesh.tables.data import ERRATA, PENTAGONS, TOLERANCE, pentagon_title

__all__ = ["format_table", "write_csv"]


def _npmr(level: int) -> str:
    return "NPMR=6" if level == 1 else f"NPMR=6^{level}"


def format_table(result: PaperTable) -> str:
    """The table in the paper's layout (OGLR rows x NPMR columns), then the errors.

    Examples
    --------
    >>> from blockmesh.tables import compute_table
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
    tag, title = pentagon_title(case.pentagon)
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
    floor = TOLERANCE * case.abs_integral
    lines.append(f"|value - reference|   (round-off floor {TOLERANCE:g} x ∫|f| = {floor:.2g})")
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
    """Write every entry of ``results`` as CSV rows to an open text file; returns the row count."""
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
