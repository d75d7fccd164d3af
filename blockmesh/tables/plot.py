"""The convergence picture of the regenerated tables (matplotlib, imported on first use).

Examples
--------
>>> import pathlib, tempfile
>>> from blockmesh.tables import compute_table
>>> path = pathlib.Path(tempfile.mkdtemp()) / "t9.png"
>>> plot_convergence([compute_table(9, "SP", levels=(1, 2), orders=(5, 10))], path).name
't9.png'
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from blockmesh.plot import pyplot, save_figure
from blockmesh.tables.compute import PaperTable
from blockmesh.tables.data import PENTAGONS, TOLERANCE, PaperCase

__all__ = ["plot_convergence"]


def plot_convergence(results: list[PaperTable], path: str | Path) -> Path:
    """Draw error / ∫|f| against level, one line per order, one panel per table and pentagon.

    Uses matplotlib's Agg backend (imported here, not at import time). Entries at or below
    ``1e-17`` are drawn at ``1e-17``; the dashed line is the round-off floor ``1e-13``. The file
    is written atomically (:func:`blockmesh.plot.save_figure`).
    """
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
        ax.axhline(TOLERANCE, color="0.4", ls="--", lw=0.9, label=f"floor {TOLERANCE:g}")
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
    return save_figure(fig, path, dpi=110)


def _short(case: PaperCase) -> str:
    text = case.integrand
    return text if len(text) <= 38 else "Franke-like sum of 4 exponentials"
