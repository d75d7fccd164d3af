"""The paper's Tables 1-11 as data: pentagons, integrands, references, printed entries, errata.

Everything comes from ``paper_tables.json`` in this package (read once): the paper's two
pentagons, the integrand of each table, per (table, pentagon) a high-precision reference value
(>= 34 significant digits; the exact rational for the polynomials of Tables 3-6) with ``∫|f|``,
the entries the paper prints (rows 1, 2, 5, 10 of Tables 1-6 and 5, 10, 20 of Tables 7-11 at
NPMR = 6..6^4; the corrected value of each misprint beside it) and the errata (also in
``docs/mathematics.md`` §7). A
double-precision result is as good as it gets when ``|value - reference| <= TOLERANCE * ∫|f|``.

Examples
--------
>>> case = paper_case(3, "SP")
>>> case.integrand, case.exact
('(0.2*x + 0.3*y)^19', Fraction(-389834752439, 7000000000000000000))
>>> table_orders(7)
(5, 10, 15, 20, 25, 30, 35, 40, 45)
>>> [e.expected for e in case.entries if e.corrected][:1]
['-3.247407437070756e-08']
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from fractions import Fraction
from importlib import resources
from typing import Any

from blockmesh.checks import whole_number
from blockmesh.errors import ArgumentError, ArgumentTypeError, UnknownNameError

__all__ = [
    "CASES",
    "ERRATA",
    "INTEGRANDS",
    "PENTAGONS",
    "TABLES",
    "TOLERANCE",
    "Erratum",
    "PaperCase",
    "PrintedEntry",
    "paper_case",
    "pentagon_title",
    "table_orders",
]


def _load() -> dict[str, Any]:
    text = resources.files(__package__).joinpath("paper_tables.json").read_text("utf-8")
    data: dict[str, Any] = json.loads(text)
    return data


_DATA = _load()

#: |value - reference| <= TOLERANCE * ∫|f| is round-off (summation order) for these tables.
TOLERANCE: float = _DATA["tolerance"]["relative_to_abs_integral"]

#: The paper's two pentagons, counter-clockwise.
PENTAGONS: dict[str, tuple[tuple[int, int], ...]] = {
    name: tuple((int(x), int(y)) for x, y in entry["corners"])
    for name, entry in _DATA["pentagons"].items()
}

#: Table -> (the paper's function number in ``fnxy``, the integrand as an expression).
#: Table 11's last term is used as printed, with y twice: -0.2 exp(-(9y-4)^2 - (9y-7)^2).
INTEGRANDS: dict[int, tuple[int, str]] = {
    entry["table"]: (entry["function"], entry["integrand"]) for entry in _DATA["tables"]
}

_ORDERS: dict[int, tuple[int, ...]] = {
    entry["table"]: tuple(entry["orders"]) for entry in _DATA["tables"]
}

#: The table numbers.
TABLES = tuple(INTEGRANDS)


@dataclass(frozen=True)
class PrintedEntry:
    """One entry the paper prints: table row ``order`` (OGLR), column ``level`` (NPMR = 6**level).

    ``corrected`` is the right value where the printed one is a misprint (see :data:`ERRATA`).
    """

    order: int
    level: int
    printed: str
    corrected: str | None = None

    @property
    def expected(self) -> str:
        """What the paper's rule gives: the corrected value of a misprint, else the printed one."""
        return self.corrected or self.printed


@dataclass(frozen=True)
class PaperCase:
    """One (table, pentagon) pair: integrand, reference value, ``∫|f|`` and the printed entries."""

    table: int
    pentagon: str
    reference: str
    abs_integral: float
    exact_fraction: str | None = None
    entries: tuple[PrintedEntry, ...] = field(default=(), repr=False)

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
CASES: tuple[PaperCase, ...] = tuple(
    PaperCase(
        case["table"],
        case["pentagon"],
        case["reference"],
        case["abs_integral"],
        case["exact_fraction"],
        tuple(PrintedEntry(**entry) for entry in case["entries"]),
    )
    for case in _DATA["cases"]
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
ERRATA: tuple[Erratum, ...] = tuple(Erratum(**erratum) for erratum in _DATA["errata"])


def _check_table(table: object) -> int:
    number = whole_number(table, "table", minimum=1)
    if number not in INTEGRANDS:
        raise ArgumentError(f"no table {number}; the paper's tables are 1..{max(TABLES)}")
    return number


def _check_pentagon(pentagon: object) -> str:
    if not isinstance(pentagon, str):
        raise ArgumentTypeError(f"pentagon must be a name (SP or USP), got {pentagon!r}")
    key = pentagon.upper()
    if key not in PENTAGONS:
        raise UnknownNameError(
            f"unknown pentagon {pentagon!r}; choose one of: {', '.join(PENTAGONS)}"
        )
    return key


def pentagon_title(pentagon: str) -> tuple[str, str]:
    """The paper's tag and name of a pentagon.

    Examples
    --------
    >>> pentagon_title("usp")
    ('[II]', 'unsymmetrical pentagon')
    """
    entry = _DATA["pentagons"][_check_pentagon(pentagon)]
    return entry["tag"], entry["title"]


def table_orders(table: int) -> tuple[int, ...]:
    """The orders (OGLR) a table lists: 1..10 for Tables 1-6, 5, 10, ..., 45 for Tables 7-11.

    Examples
    --------
    >>> table_orders(1)
    (1, 2, 3, 4, 5, 6, 7, 8, 9, 10)
    """
    return _ORDERS[_check_table(table)]


def paper_case(table: int, pentagon: str) -> PaperCase:
    """The case of ``table`` (1..11) on ``pentagon`` ("SP" or "USP", any case).

    Examples
    --------
    >>> paper_case(9, "usp").reference
    '1.798096146581152670802198439191585'
    """
    key = (_check_table(table), _check_pentagon(pentagon))
    return next(c for c in CASES if (c.table, c.pentagon) == key)
