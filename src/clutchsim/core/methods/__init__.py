"""The integration methods of clutchsim, each one tableau of coefficients (data, not code).

Two families run on the one step loop of the C engine (:mod:`clutchsim.core.cengine`):

* :class:`RosenbrockTableau`: linearly implicit (Rosenbrock and Rosenbrock-W) methods in
  the transformed form of Hairer & Wanner (*Solving ODEs II*, §IV.7, eq. 7.25)::

      (I/(γh) − J) U_i = f(t + c_i h, y + Σ_{j<i} a_ij U_j) + Σ_{j<i} (C_ij/h) U_j
                         + d_i h ∂f/∂t
      y_1 = y + Σ m_i U_i,      err = Σ e_i U_i

  built from the published ``(α, Γ, b, b̂)`` by ``a = α Γ⁻¹``, ``C = diag(1/γ) − Γ⁻¹``,
  ``m = b Γ⁻¹``, ``e = (b − b̂) Γ⁻¹``, ``c_i = Σ_j α_ij``, ``d_i = Σ_j Γ_ij``.
* :class:`ExplicitTableau`: explicit Runge–Kutta pairs (Butcher ``A, b, b̂, c``).

Adding a method is one module in this package that builds a tableau from its published
coefficients and calls :func:`register_method`; registration recomputes the order
conditions (:mod:`._order`) of the method and of its embedded solution and refuses a
tableau that fails them.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

import numpy as np

from ..system import closest
from ._order import order_residuals

__all__ = ["METHODS", "ExplicitTableau", "RosenbrockTableau", "get_method", "register_method"]

#: dense-output forms (see ``dense_eval`` in ``core/engine.c``)
DENSE_HERMITE = 0      # cubic Hermite through both step ends and their slopes
DENSE_STAGES = 1       # Rosenbrock continuous extension from the stages (rows of H)
DENSE_POLY = 2         # explicit RK: y0 + Σ_k θ^(k+1) h Σ_i P[i, k] K_i

#: method families (``kind`` in the packed options)
ROSENBROCK = 0
EXPLICIT = 1

#: tolerance on the order-condition residuals of a published tableau (coefficients are
#: printed with 15–17 digits)
ORDER_TOL = 1e-10


def _as_matrix(x, s, name):
    a = np.zeros((s, s))
    rows = list(x)
    if len(rows) not in (s - 1, s):
        raise ValueError(f"{name} must have {s} (or {s - 1}) rows, got {len(rows)}")
    start = s - len(rows)
    for i, row in enumerate(rows):
        vals = list(row)
        a[i + start, :len(vals)] = vals
    return a


@dataclass(frozen=True)
class RosenbrockTableau:
    """A Rosenbrock(-W) method from its published ``(α, Γ, b, b̂)`` coefficients.

    Parameters
    ----------
    name, description, source : str
        Registry name, one line for listings, and the publication the numbers come from.
    gamma : float
        The diagonal ``γ`` of ``Γ``.
    alpha, Gamma_lower : sequences of rows
        Strictly lower parts of ``α`` and ``Γ`` (row ``i`` holds the entries ``j < i``;
        the first, empty row may be left out).
    b, b_hat : sequences
        Weights of the solution and of the embedded solution.
    order, embedded_order : int
        Orders the coefficients are checked for on registration.
    dense : int
        ``DENSE_HERMITE`` or ``DENSE_STAGES``; with ``DENSE_STAGES``, ``H`` holds 2 or 3
        rows of stage weights of the continuous extension (Hairer & Wanner's ``rodas.f``
        form ``y(θ) = (1−θ)y0 + θ(y1 + (1−θ)(k1 + θ(k2 + θ k3)))``).
    w_method : bool
        The method keeps its order with an approximate Jacobian (a W-method): the
        integrator may then reuse one Jacobian, and one inverted iteration matrix while the step changes
        little.
    stages_at_end : tuple of int
        Extra stages written directly in transformed form, for methods published that way
        (RODAS-type stiffly accurate tails); see :meth:`transformed`.
    """

    name: str
    description: str
    source: str
    gamma: float
    order: int
    embedded_order: int
    alpha: tuple = ()
    Gamma_lower: tuple = ()
    b: tuple = ()
    b_hat: tuple = ()
    dense: int = DENSE_HERMITE
    H: tuple = ()
    w_method: bool = False
    #: the transformed coefficients directly (a, C, c, d, m, e), for methods published in
    #: that form; then alpha/Gamma/b/b_hat are derived from them
    transformed_form: dict = field(default_factory=dict)
    family: int = ROSENBROCK

    @property
    def stages(self) -> int:
        if self.transformed_form:
            return len(self.transformed_form["c"])
        return len(self.b)

    def published(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(α, Γ, b, b̂)`` as full arrays (derived from the transformed form if that is
        what was given)."""
        s = self.stages
        if self.transformed_form:
            a, C, _, _, m, e = self.transformed()
            Gi = np.diag(np.full(s, 1.0 / self.gamma)) - C
            G = np.linalg.inv(Gi)
            return a @ G, G, m @ G, (m - e) @ G
        A = _as_matrix(self.alpha, s, "alpha")
        G = _as_matrix(self.Gamma_lower, s, "Gamma") + np.diag(np.full(s, self.gamma))
        return A, G, np.asarray(self.b, float), np.asarray(self.b_hat, float)

    def transformed(self):
        """``(a, C, c, d, m, e)`` of the transformed form (see the module docstring)."""
        s = self.stages
        if self.transformed_form:
            tf = self.transformed_form
            return (_as_matrix(tf["a"], s, "a"), _as_matrix(tf["C"], s, "C"),
                    np.asarray(tf["c"], float), np.asarray(tf["d"], float),
                    np.asarray(tf["m"], float), np.asarray(tf["e"], float))
        A, G, b, bh = self.published()
        Gi = np.linalg.inv(G)
        a = A @ Gi
        C = np.diag(1.0 / np.diag(G)) - Gi
        return a, C, A.sum(1), G.sum(1), b @ Gi, (b - bh) @ Gi

    def check(self) -> None:
        """Raise ValueError unless the method and its embedded solution satisfy their
        order conditions (with the exact Jacobian) to ``ORDER_TOL``."""
        A, G, b, bh = self.published()
        s = self.stages
        if np.any(np.triu(A) != 0.0) and np.abs(np.triu(A)).max() > ORDER_TOL:
            raise ValueError(f"method {self.name!r}: alpha must be strictly lower triangular")
        if np.abs(np.diag(G) - self.gamma).max() > ORDER_TOL:
            raise ValueError(f"method {self.name!r}: the diagonal of Gamma must be gamma")
        if self.transformed_form:
            _, _, c, d, _, _ = self.transformed()
            if np.abs(c - A.sum(1)).max() > ORDER_TOL or np.abs(d - G.sum(1)).max() > 1e-9:
                raise ValueError(f"method {self.name!r}: the stage times c and weights d "
                                 "must be the row sums of alpha and Gamma")
        for weights, order, what in ((b, self.order, "solution"),
                                     (bh, self.embedded_order, "embedded solution")):
            _require_order(self.name, what, order_residuals(weights, A, order, G), order)
        if self.dense == DENSE_STAGES and len(self.H) not in (2, 3):
            raise ValueError(f"method {self.name!r}: H needs 2 or 3 rows of {s} stage weights")

    def packed(self):
        a, C, c, d, m, e = self.transformed()
        s = self.stages
        H = np.zeros((3, s))
        for i, row in enumerate(self.H):
            H[i, :len(row)] = row
        return a, C, c, d, m, e, H


@dataclass(frozen=True)
class ExplicitTableau:
    """An explicit Runge–Kutta pair ``(A, b, b̂, c)`` with a polynomial dense output.

    ``P``: rows of stage weights of the continuous extension, ``y(θ) = y0 + h Σ_i
    K_i Σ_k P[i][k] θ^(k+1)`` (up to 4 powers).  ``fsal``: the last stage is ``f`` at the
    new point (first same as last), so a step costs ``s − 1`` right-hand sides.
    """

    name: str
    description: str
    source: str
    order: int
    embedded_order: int
    A: tuple
    b: tuple
    b_hat: tuple
    P: tuple
    fsal: bool = True
    family: int = EXPLICIT
    dense: int = DENSE_POLY
    w_method: bool = False

    @property
    def stages(self) -> int:
        return len(self.b)

    def check(self) -> None:
        s = self.stages
        A = _as_matrix(self.A, s, "A")
        for weights, order, what in ((self.b, self.order, "solution"),
                                     (self.b_hat, self.embedded_order, "embedded solution")):
            _require_order(self.name, what, order_residuals(weights, A, order), order)

    def packed(self):
        s = self.stages
        A = _as_matrix(self.A, s, "A")
        P = np.zeros((4, s))
        for i, row in enumerate(self.P):
            P[:len(row), i] = row
        b = np.asarray(self.b, float)
        return A, np.zeros((s, s)), A.sum(1), np.zeros(s), b, b - np.asarray(self.b_hat), P


def _require_order(name, what, residuals, order):
    bad = [(tree, r) for tree, r in residuals if abs(r) > ORDER_TOL]
    if bad:
        tree, r = max(bad, key=lambda x: abs(x[1]))
        raise ValueError(f"method {name!r}: the {what} does not have order {order}: "
                         f"{len(bad)} order condition(s) fail, the worst by {r:.3g} "
                         f"(tree {tree!r})")


#: registered methods by name
METHODS: dict[str, RosenbrockTableau | ExplicitTableau] = {}


def register_method(tableau: RosenbrockTableau | ExplicitTableau):
    """Check the tableau's order conditions and register it under its name."""
    if not isinstance(tableau, (RosenbrockTableau, ExplicitTableau)):
        raise TypeError(f"a method must be a RosenbrockTableau or ExplicitTableau, got "
                        f"{type(tableau).__name__}")
    tableau.check()
    METHODS[tableau.name] = tableau
    return tableau


def get_method(name: str):
    """The registered method ``name`` (ValueError listing the valid ones otherwise)."""
    try:
        return METHODS[name]
    except (KeyError, TypeError):
        raise ValueError(f"method {name!r} is not known{closest(str(name), METHODS)}; "
                         f"valid methods: {', '.join(METHODS)}") from None


for _module in ("rodas4", "ros34pw2", "rodas5p", "dopri5"):
    importlib.import_module(f"{__name__}.{_module}")
