"""Stabilisation of the virtual element matrices: which one, and how it is scaled.

The consistency part of a cell matrix, ``a(Π∇u, Π∇v)``, vanishes on the functions with
``Π∇v = 0``; it is completed by ``s(u, v) = ((I - Π) u)ᵀ T ((I - Π) v)`` on the vertex values,
with a positive diagonal T of the same scale as the consistency matrix K. The recipes:

``"identity"``
    ``T = κ̄ I`` with κ̄ the cell mean of the coefficient (diffusion for the stiffness, reaction
    times ``|E| / n`` for the mass): the "dofi-dofi" stabilisation of Sutton's 50-line VEM.
``"trace"``
    ``T = (trace K / d) I`` for a cell matrix of size d: scaled by the consistency matrix itself,
    so it follows the material and the cell's shape (the choice of Gain, Talischi and Paulino for
    elasticity).
``"diagonal"``
    ``T = diag(max(K_ii, floor))``: the "D-recipe" of Beirão da Veiga, Dassi and Russo, robust on
    badly shaped cells; the floor is the identity recipe's κ̄ where there is one.

Every recipe is multiplied by ``scale`` (default 1). On a triangle ``I - Π = 0``: no recipe
changes anything there. ``"trace"`` is the default of both solvers: on the paper's pentagons it
gave a 20 % smaller L2 error than ``"identity"`` at scale 1 on a smooth Poisson problem, and the
same H1 error (which no recipe or scale changes by more than a few per cent); a smaller scale
makes the lowest-order elements less stiff (Cook's membrane converges faster with 0.3 than with
1). The measurements are in the documentation (``docs/solving.md``, "Stabilisation") and
``benchmarks/bench_accuracy.py``.

Examples
--------
>>> import numpy as np
>>> k = np.array([[[2.0, -2.0], [-2.0, 2.0]]])
>>> r = np.array([[[0.5, -0.5], [-0.5, 0.5]]])
>>> stabilize(k, r, "trace", coefficient=None, scale=1.0)[0].tolist()
[[1.0, -1.0], [-1.0, 1.0]]
"""

from __future__ import annotations

import numpy as np

from blockmesh.checks import choice
from blockmesh.errors import ArgumentError

__all__ = ["STABILIZATIONS", "check_scale", "check_stabilization", "stabilize"]

#: The recipes, by name, with a line each.
STABILIZATIONS: dict[str, str] = {
    "trace": "trace of the consistency matrix over its size, times the identity",
    "identity": "dofi-dofi: the cell mean of the coefficient times the identity (Sutton)",
    "diagonal": "the diagonal of the consistency matrix (the D-recipe), floored by the identity's",
}


def check_stabilization(name: object, allowed: tuple[str, ...] = tuple(STABILIZATIONS)) -> str:
    """``name`` if it is one of ``allowed`` (ArgumentError listing them otherwise)."""
    return str(choice(name, allowed, "stabilization"))


def check_scale(scale: object) -> float:
    """``scale`` as a float > 0 (ArgumentError otherwise)."""
    if isinstance(scale, bool) or not isinstance(scale, int | float | np.floating | np.integer):
        raise ArgumentError(f"stabilization_scale must be a number > 0, got {scale!r}")
    value = float(scale)
    if not np.isfinite(value) or value <= 0:
        raise ArgumentError(f"stabilization_scale must be a number > 0, got {scale!r}")
    return value


def stabilize(
    consistency: np.ndarray,
    residual: np.ndarray,
    recipe: str,
    *,
    coefficient: np.ndarray | None,
    scale: float,
) -> np.ndarray:
    """The stabilisation matrices ``Rᵀ T R`` (M, d, d) of a group of cells.

    Parameters
    ----------
    consistency : ndarray (M, d, d)
        The consistency matrices K of the cells.
    residual : ndarray (M, d, d)
        ``I - Π`` in the cell's degrees of freedom.
    recipe : {"identity", "trace", "diagonal"}
    coefficient : ndarray (M,) or None
        κ̄ per cell for ``"identity"`` (required there) and the floor of ``"diagonal"``.
    scale : float
    """
    d = consistency.shape[1]
    if recipe == "identity":
        if coefficient is None:
            raise ArgumentError("the identity stabilization needs a coefficient scale")
        tau = np.broadcast_to(coefficient[:, None], (consistency.shape[0], d))
    elif recipe == "trace":
        trace = np.einsum("mii->m", consistency)
        tau = np.broadcast_to((trace / d)[:, None], (consistency.shape[0], d))
    else:
        tau = np.einsum("mii->mi", consistency)
        if coefficient is not None:
            tau = np.maximum(tau, coefficient[:, None])
    return scale * np.matmul(residual.transpose(0, 2, 1), tau[:, :, None] * residual)
