"""The scipy Radau reference solution of the van der Pol problem shared by the stiff tests."""

from scipy.integrate import solve_ivp


def radau_van_der_pol(mu: float, t_end: float):
    """Dense Radau solution (rtol = atol = 1e-10) of x'' = mu (1 - x²) x' - x from
    (x, x') = (2, 0), the initial state of :func:`clutchsim.core.reference_problems.van_der_pol`."""
    return solve_ivp(lambda t, y: [y[1], mu * (1 - y[0] ** 2) * y[1] - y[0]], (0, t_end),
                     [2.0, 0.0], method="Radau", rtol=1e-10, atol=1e-10, dense_output=True)
