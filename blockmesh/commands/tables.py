"""``blockmesh tables``: regenerate the paper's Tables 1-11 and their errors."""

from __future__ import annotations

import argparse
from pathlib import Path

from blockmesh._system.atomic import atomic_file
from blockmesh.commands import Option, Options, registration
from blockmesh.commands.common import check_folders, print_json, printable
from blockmesh.commands.options import JSON_OPTION, plot_option
from blockmesh.quadrature import RULES
from blockmesh.tables import PENTAGONS, TABLES, PaperTable, compute_table, format_table, write_csv
from blockmesh.tables.plot import plot_convergence

__all__ = ["OPTIONS", "register", "run"]


#: Most numbers a list option may name (a range like 1-1000000000 is refused, not expanded).
_MAX_LIST = 1000


def _int_list(text: str) -> tuple[int, ...]:
    """``"3"``, ``"1,2,7"`` or ``"7-11"`` (and mixtures) to a tuple of ints."""
    values: list[int] = []
    try:
        for part in text.split(","):
            if "-" in part.strip()[1:]:
                low, high = part.split("-", 1)
                span = range(int(low), int(high) + 1)
                if len(values) + len(span) > _MAX_LIST:
                    raise argparse.ArgumentTypeError(
                        f"{text!r} names more than {_MAX_LIST} numbers"
                    )
                values.extend(span)
            else:
                values.append(int(part))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a list of whole numbers (e.g. 3, 1,2,7 or 1-4)"
        ) from None
    if not values:
        raise argparse.ArgumentTypeError(f"{text!r} names no numbers")
    return tuple(values)


#: The options of ``blockmesh tables``, in the order of its ``--help``.
OPTIONS: Options = (
    Option(
        "--table",
        type=_int_list,
        metavar="K",
        default=TABLES,
        help="table number(s): 3, 1,2,7 or 7-11 (default all)",
    ),
    Option(
        "--levels",
        type=_int_list,
        metavar="L",
        default=(1, 2, 3, 4),
        help="refinement levels (columns NPMR = 6^L): 1-4 (default), 2, 1,3",
    ),
    Option(
        "--orders",
        type=_int_list,
        metavar="N",
        help="orders (rows) instead of the paper's (1-10 for Tables 1-6, 5,10,...,45 for 7-11)",
    ),
    Option(
        "--pentagon",
        choices=("SP", "USP", "both"),
        default="both",
        help="which pentagon (default both)",
    ),
    Option("--rule", choices=tuple(RULES), default="paper", help="quadrature rule (default paper)"),
    Option("--csv", metavar="FILE", help="write every entry to a CSV file"),
    plot_option("the error against the level, one line per order"),
    JSON_OPTION,
)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh tables`` with the parsed ``args``; returns the exit code."""
    check_folders(args.csv, args.plot)
    pentagons = tuple(PENTAGONS) if args.pentagon == "both" else (args.pentagon,)
    results = []
    for table in args.table:
        for pentagon in pentagons:
            result = compute_table(
                table, pentagon, levels=args.levels, orders=args.orders, rule=args.rule
            )
            results.append(result)
            if not args.json:
                print(format_table(result))
                print()
    best = [(float(r.scaled_errors.min()), r) for r in results]
    worst, result = max(best, key=lambda item: item[0])
    entries = sum(r.values.size for r in results)
    written = []
    if args.csv:
        with (
            atomic_file(Path(args.csv)) as temporary,
            open(temporary, "w", encoding="utf-8", newline="") as handle,
        ):
            rows = write_csv(results, handle)
        written.append(f"wrote {rows} rows to {printable(args.csv)}")
    if args.plot:
        plot_convergence(results, args.plot)
        written.append(f"wrote {printable(args.plot)}")
    if args.json:
        print_json(
            {
                "entries": entries,
                "worst_best_scaled_error": worst,
                "tables": [_table_json(r) for r in results],
                "csv": args.csv,
                "plot": args.plot,
            }
        )
        return 0
    print(
        f"{entries} entries; the most accurate entry of each table is within {worst:.1e} x ∫|f| "
        f"of the reference (worst: Table {result.case.table} {result.case.pentagon}; round-off "
        "floor 1e-13)"
    )
    for line in written:
        print(line)
    return 0


register = registration("tables", OPTIONS, run)


def _table_json(result: PaperTable) -> dict[str, object]:
    """One regenerated table as plain lists: rows are the orders, columns the levels."""
    return {
        "table": result.case.table,
        "pentagon": result.case.pentagon,
        "rule": result.rule,
        "orders": list(result.orders),
        "levels": list(result.levels),
        "values": result.values.tolist(),
        "errors": result.errors.tolist(),
        "scaled_errors": result.scaled_errors.tolist(),
    }
