"""The result of an integration with its error estimate."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["IntegrationResult"]


@dataclass(frozen=True)
class IntegrationResult:
    """A value, its error estimate and what it cost.

    Returned by :func:`~blockmesh.quadrature.integrate_with_estimate` (a fixed rule, order and
    level) and :func:`~blockmesh.quadrature.integrate_to_tolerance` (order and level chosen).

    Attributes
    ----------
    value : float
        The result (for :func:`integrate_to_tolerance`, the last and most accurate one).
    error_estimate : float
        An estimate of ``|value - exact|``: see the function that made it.
    order, level : int
        Where ``value`` was computed.
    rule : str
    cells : int
        Cells of the mesh at ``level``.
    points : int
        Evaluations of f, over every pass.
    converged : bool
        Whether ``error_estimate`` met the tolerance (for a fixed rule: the warning level).
    message : str
        A one-line account: how the estimate was made, and why it is large when it is.
    history : tuple of (level, order, value)
        Every pass, in order.
    worst_cell : int or None
        The cell where the estimate is largest (for a fixed rule), else None.
    """

    value: float
    error_estimate: float
    order: int
    level: int
    rule: str
    cells: int
    points: int
    converged: bool
    message: str
    history: tuple[tuple[int, int, float], ...]
    worst_cell: int | None = None

    def __float__(self) -> float:
        return self.value
