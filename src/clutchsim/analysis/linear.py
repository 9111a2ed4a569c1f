"""Linearisation of a plant about an operating point, and its modes.

Everything here uses only the :class:`~clutchsim.core.System` interface: state, input and
output names and units, ``call_rhs``/``call_outputs`` (and ``call_jac`` where the plant
registered an exact Jacobian).  The conventions it relies on:

* the trailing ``system.quadratures`` states are pure integrals (energy accounts) and are
  left out;
* states named ``<element>.locked`` or ``<element>.mode`` are discrete mode flags: frozen at
  their operating-point value, not linearised;
* a switching element ``E`` reports its slip speed as the output ``w_slip_E`` [rad/s] and
  its friction torque as ``T_friction_E`` (a coupling), ``T_E`` (a brake) or ``T_loss_E``
  (a lossy gear) [N·m], and its capacity as ``capacity_E``.  An element whose flag
  ``E.locked`` is set is a constraint of the plant (its slip is held at zero): the
  linearisation eliminates one speed per locked element through the linear relation
  ``w_slip_E = 0`` (the cluster is merged), so no spurious zero mode appears.

A slipping element enters through its friction slope ``dT/d(slip)`` [N·m·s/rad], which the
plant's right-hand side contains; it is also reported per element (the output torque
differenced with respect to the slip speed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.system import System, call_jac, call_outputs, call_rhs, closest, has_jacobian

__all__ = [
    "DISCRETE_SUFFIXES",
    "ElementPoint",
    "LinearModel",
    "Mode",
    "OperatingPoint",
    "OperatingPointError",
    "element_points",
    "linearise",
    "modes",
    "operating_point",
]

#: state-name suffixes of discrete mode flags (frozen, not linearised)
DISCRETE_SUFFIXES = (".locked", ".mode")
#: capacity below which an unlocked element counts as free (open) [N·m]
FREE_CAPACITY = 1e-9
#: relative finite-difference step (central differences with Richardson extrapolation:
#: truncation error O(h^4), round-off ~eps/h)
FD_STEP = 1e-4


class OperatingPointError(RuntimeError):
    """The simulation to the operating time did not complete (``outcome``, ``message``)."""

    def __init__(self, message: str, outcome: str = "", t_reached: float | None = None):
        super().__init__(message)
        self.outcome = outcome
        self.t_reached = t_reached


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class ElementPoint:
    """A switching element at the operating point.

    ``state``: ``"locked"`` (a constraint of the plant), ``"free"`` (no capacity) or
    ``"slipping"``; ``slip_rad_s`` its slip speed [rad/s]; ``friction_slope_Nms`` the slope
    ``dT/d(slip)`` of its friction torque [N·m·s/rad] (None when locked: the constraint
    carries the torque); ``torque_Nm`` its friction torque [N·m]; ``capacity_Nm``.
    """

    name: str
    state: str
    slip_rad_s: float
    friction_slope_Nms: float | None
    torque_Nm: float
    capacity_Nm: float

    def as_dict(self) -> dict:
        return {"slip_rad_s": self.slip_rad_s, "friction_slope_Nms": self.friction_slope_Nms,
                "state": self.state}


@dataclass(frozen=True)
class LinearModel:
    """``dx/dt = A·x`` about an operating point, over the linearised states.

    ``A`` [1/s in the units of the states] is read-only; ``state_names``/``state_units``
    label its rows and columns; ``frozen`` are the states left out (discrete flags,
    quadratures); ``locked`` the elements whose constraint merged a speed (``merged``: the
    speed states eliminated); ``method`` ``"exact"`` (the plant's Jacobian) or
    ``"finite-difference"``.
    """

    A: np.ndarray
    state_names: tuple[str, ...]
    state_units: tuple[str, ...]
    t_s: float
    frozen: tuple[str, ...]
    locked: tuple[str, ...]
    merged: tuple[str, ...]
    method: str
    #: indices (into the plant's state vector) of the continuous states, and the basis
    #: ``x_continuous = basis·x`` of the linearised states in them (identity without
    #: merged constraints)
    continuous: tuple[int, ...] = ()
    basis: np.ndarray | None = None

    @property
    def n(self) -> int:
        return len(self.state_names)


@dataclass(frozen=True)
class Mode:
    """One mode of a :class:`LinearModel` (a complex pair counts once).

    ``eigenvalue`` [1/s]; ``frequency_hz`` the natural frequency ``|λ|/2π`` of an
    oscillatory mode, 0 for a real eigenvalue (rigid-body or first-order mode);
    ``damping_ratio`` ``-Re λ/|λ|`` [-] (±1 for a real eigenvalue, 0 at λ = 0);
    ``growth_rate_1_s`` ``Re λ`` [1/s]; ``stable``; ``dominant_states`` the states with the
    largest participation factors, largest first; ``participation`` their factors [-]
    (normalised to sum 1 over all states).
    """

    eigenvalue: complex
    frequency_hz: float
    damping_ratio: float
    growth_rate_1_s: float
    stable: bool
    dominant_states: tuple[str, ...]
    participation: tuple[float, ...]

    def as_dict(self) -> dict:
        return {"frequency_hz": self.frequency_hz, "damping_ratio": self.damping_ratio,
                "growth_rate_1_s": self.growth_rate_1_s, "stable": self.stable,
                "dominant_states": list(self.dominant_states)}


@dataclass(frozen=True)
class OperatingPoint:
    """State ``y`` and inputs ``u`` of ``system`` at ``t_s`` [s], and its elements."""

    system: System
    t_s: float
    y: np.ndarray
    u: np.ndarray
    elements: tuple[ElementPoint, ...]
    steps: int = 0

    def element(self, name: str) -> ElementPoint:
        for e in self.elements:
            if e.name == name:
                return e
        names = [e.name for e in self.elements]
        raise ValueError(f"element {name!r} does not exist{closest(name, names)} (switching "
                         f"elements: {', '.join(names) or 'none'})")


# ------------------------------------------------------------------ helpers
def _arr(x) -> np.ndarray:
    return np.ascontiguousarray(x, dtype=np.float64)


def _discrete(name: str) -> bool:
    return name.endswith(DISCRETE_SUFFIXES)


def _rhs(system: System, t, y, u) -> np.ndarray:
    dy = np.zeros(system.n_states)
    call_rhs(system.tag, float(t), _arr(y), _arr(u), system.params, dy)
    return dy


def _outputs(system: System, t, y, u) -> np.ndarray:
    out = np.zeros(len(system.output_names))
    call_outputs(system.tag, float(t), _arr(y), _arr(u), system.params, out)
    return out


def _steps(y: np.ndarray, idx) -> np.ndarray:
    """Finite-difference steps of the states ``idx``: relative to their size, with a
    floor that keeps a state at 0 (a twist, a slip) well inside its nonlinearity."""
    return np.array([FD_STEP * max(abs(float(y[j])), 1e-2) for j in idx])


def _jacobian_fd(f, y: np.ndarray, idx, steps) -> np.ndarray:
    """Columns ``d f/d y_j`` for ``j`` in ``idx``: central differences at steps h and h/2,
    Richardson-extrapolated (error O(h^4))."""
    cols = []
    for j, h in zip(idx, steps):
        def d(hh, j=j):
            yp, ym = y.copy(), y.copy()
            yp[j] += hh
            ym[j] -= hh
            return (f(yp) - f(ym)) / (2.0 * hh)
        cols.append((4.0 * d(0.5 * h) - d(h)) / 3.0)
    return np.array(cols).T


def _element_names(system: System) -> tuple[str, ...]:
    return tuple(n[len("w_slip_"):] for n in system.output_names if n.startswith("w_slip_"))


def _torque_output(system: System, name: str) -> str:
    for cand in (f"T_friction_{name}", f"T_{name}", f"T_loss_{name}"):
        if cand in system.output_names:
            return cand
    raise ValueError(f"element {name!r}: the plant has no friction-torque output")


def _locked(system: System, y: np.ndarray, name: str) -> bool:
    flag = f"{name}.locked"
    return flag in system.state_names and y[system.state_names.index(flag)] > 0.5


def _continuous(system: System) -> list[int]:
    n = system.n_states - system.quadratures
    return [j for j in range(n) if not _discrete(system.state_names[j])]


# ------------------------------------------------------------------ public API
def element_points(system: System, t: float, y, u, elements=None) -> tuple[ElementPoint, ...]:
    """Every switching element of ``system`` at ``(t, y, u)`` (or the ``elements`` named):
    locked / free / slipping, slip speed and friction slope (see :class:`ElementPoint`)."""
    y, u = _arr(y).copy(), _arr(u)
    names = _element_names(system)
    if elements is not None:
        for e in elements:
            if e not in names:
                raise ValueError(f"element {e!r} does not exist{closest(e, names)} "
                                 f"(switching elements of {system.name}: "
                                 f"{', '.join(names) or 'none'})")
        names = tuple(e for e in names if e in set(elements))
    out0 = _outputs(system, t, y, u)
    onames = system.output_names
    cont = _continuous(system)
    res = []
    for name in names:
        iw = onames.index(f"w_slip_{name}")
        it = onames.index(_torque_output(system, name))
        cap_name = f"capacity_{name}"
        cap = float(out0[onames.index(cap_name)]) if cap_name in onames else math.inf
        w, torque = float(out0[iw]), float(out0[it])
        if _locked(system, y, name):
            res.append(ElementPoint(name, "locked", w, None, torque, cap))
            continue
        # perturb the speed the slip depends on most (its own side), difference T over w
        steps = _steps(y, cont)
        pick = [iw, it]
        grad_w = _jacobian_fd(lambda yy, pick=pick: _outputs(system, t, yy, u)[pick], y,
                              cont, steps)
        speeds = [k for k, j in enumerate(cont) if system.state_units[j] == "rad/s"]
        k = max(speeds, key=lambda k: abs(grad_w[0, k])) if speeds else None
        if k is None or grad_w[0, k] == 0.0:
            raise ValueError(f"element {name!r}: its slip speed depends on no speed state")
        slope = float(grad_w[1, k] / grad_w[0, k])
        state = "free" if abs(cap) <= FREE_CAPACITY else "slipping"
        res.append(ElementPoint(name, state, w, slope, torque, cap))
    return tuple(res)


def linearise(system: System, t: float, y, u, *, constraints=()) -> LinearModel:
    """The linear model ``dx/dt = A·x`` of ``system`` about ``(t, y, u)`` with the inputs
    frozen at ``u``.

    Quadrature states and discrete flags are left out (frozen); the speed of each locked
    element is eliminated through its constraint ``w_slip = 0``, and so is one state per
    entry of ``constraints`` (mappings state name -> coefficient of a linear relation
    ``sum c_j·x_j = 0`` the plant keeps, e.g. a rigid gear ``omega_b - omega_a/r = 0``).  ``A`` is the plant's
    exact Jacobian where it registered one, else central differences of its right-hand
    side (Richardson-extrapolated, steps ``1e-4·max(|y_j|, 0.01)``).
    """
    y, u = _arr(y).copy(), _arr(u)
    if y.shape != (system.n_states,):
        raise ValueError(f"{system.name}: y has shape {y.shape}, expected "
                         f"({system.n_states},)")
    if u.shape != (len(system.input_names),):
        raise ValueError(f"{system.name}: u has shape {u.shape}, expected "
                         f"({len(system.input_names)},)")
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(u))):
        raise ValueError(f"{system.name}: the operating point is not finite")
    cont = _continuous(system)
    names = system.state_names
    if has_jacobian(system.tag):
        J = np.zeros((system.n_states, system.n_states))
        call_jac(system.tag, float(t), y, u, system.params, J)
        A = J[np.ix_(cont, cont)]
        method = "exact"
    else:
        A = _jacobian_fd(lambda yy: _rhs(system, t, yy, u), y, cont, _steps(y, cont))[cont, :]
        method = "finite-difference"
    # a dimensionless state that nothing drives (a gear ratio, a held mode value) is a
    # discrete value between events: frozen as the flags are
    dy = _rhs(system, t, y, u)
    held = [k for k, j in enumerate(cont) if system.state_units[j] == "-" and
            not np.any(A[k]) and dy[j] == 0.0]
    if held:
        live = [k for k in range(len(cont)) if k not in held]
        A = A[np.ix_(live, live)]
        cont = [cont[k] for k in live]
    frozen = tuple(names[j] for j in range(system.n_states) if j not in set(cont))
    # constraints of the locked elements: rows d w_slip / d x (linear in the speeds)
    locked = tuple(e for e in _element_names(system) if _locked(system, y, e))
    merged: list[str] = []
    keep = list(range(len(cont)))
    T = np.eye(len(cont))
    rows = []
    for c in constraints:
        row = np.zeros(len(cont))
        for name, coef in c.items():
            if name not in names or names.index(name) not in cont:
                raise ValueError(f"constraint {c!r}: {name!r} is not a linearised state")
            row[cont.index(names.index(name))] = float(coef)
        rows.append(row)
    if locked:
        iw = [system.output_names.index(f"w_slip_{e}") for e in locked]
        rows.extend(_jacobian_fd(lambda yy: _outputs(system, t, yy, u)[iw], y, cont,
                                 _steps(y, cont)))
    if rows:
        C = np.array(rows)
        C[np.abs(C) < 1e-9 * np.max(np.abs(C))] = 0.0
        pivots = []
        R = C.copy()
        for r in range(R.shape[0]):       # eliminate the downstream-most speed per row
            row = R[r]
            nz = [k for k in np.flatnonzero(row) if k not in pivots]
            if not nz:
                continue                  # a redundant constraint (already implied)
            k = nz[-1]
            pivots.append(k)
            R[r] = row / row[k]
            for s in range(R.shape[0]):
                if s != r and R[s, k] != 0.0:
                    R[s] -= R[s, k] * R[r]
        keep = [k for k in range(len(cont)) if k not in pivots]
        # x_pivot = -C_p^+ C_f x_free (least squares: a redundant row is consistent)
        T = np.zeros((len(cont), len(keep)))
        T[keep, np.arange(len(keep))] = 1.0
        T[pivots, :] = -np.linalg.lstsq(C[:, pivots], C[:, keep], rcond=None)[0]
        merged = [names[cont[k]] for k in pivots]
        A = A[keep, :] @ T
    idx = [cont[k] for k in keep]
    return LinearModel(_readonly(A), tuple(names[j] for j in idx),
                       tuple(system.state_units[j] for j in idx), float(t), frozen, locked,
                       tuple(merged), method, tuple(cont), _readonly(T))


def modes(lin: LinearModel, *, n_dominant: int = 3, share: float = 0.2) -> tuple[Mode, ...]:
    """The modes of ``lin``, sorted by frequency (then growth rate).

    A complex pair is one mode; a real eigenvalue is a mode of frequency 0.  The
    dominant states are those whose participation factor ``|v_k·w_k|`` (right and left
    eigenvectors) is at least ``share`` of the largest, at most ``n_dominant`` of them.
    An eigenvalue counts as stable when ``Re λ <= 1e-11·max(1, ||A||)`` (a rigid-body mode
    is marginally stable).
    """
    A = lin.A
    if A.size == 0:
        return ()
    lam, V = np.linalg.eig(A)
    try:
        W = np.linalg.inv(V)              # rows: left eigenvectors, W·V = I
    except np.linalg.LinAlgError:
        W = np.linalg.pinv(V)
    norm = max(1.0, float(np.max(np.abs(A).sum(axis=1))))
    tol = 1e-11 * norm
    out = []
    for i, lam_i in enumerate(lam):
        if lam_i.imag < -tol:             # the conjugate of a listed pair
            continue
        mag = abs(lam_i)
        if abs(lam_i.imag) <= tol:
            re = float(lam_i.real)
            freq, zeta = 0.0, (0.0 if abs(re) <= tol else (-1.0 if re > 0 else 1.0))
            lam_i = complex(re, 0.0)
        else:
            freq, zeta = mag / (2.0 * math.pi), float(-lam_i.real / mag)
        p = np.abs(V[:, i] * W[i, :])
        p = p / p.sum() if p.sum() > 0 else p
        order = np.argsort(-p, kind="stable")
        dom = [int(k) for k in order[:n_dominant] if p[k] >= share * p[order[0]]]
        out.append(Mode(complex(lam_i), float(freq), zeta, float(lam_i.real),
                        bool(lam_i.real <= tol), tuple(lin.state_names[k] for k in dom),
                        tuple(float(p[k]) for k in dom)))
    out.sort(key=lambda m: (m.frequency_hz, m.growth_rate_1_s))
    return tuple(out)


def _inputs_at(scenario, system: System, t: float) -> np.ndarray:
    return np.array([float(np.asarray(scenario.inputs[n](t)).ravel()[0])
                     for n in system.input_names])


def operating_point(scenario, model: str | None = None, t: float = 0.0, *,
                    elements=None, check=None) -> OperatingPoint:
    """Simulate ``scenario`` with ``model`` on its clutch from 0 to ``t`` [s] and return
    the state, the inputs at ``t`` and every switching element there.  ``check``, when
    given, is called with the built system before the run (to refuse a bad name before a
    simulation).

    Raises ``ValueError`` for ``t`` outside ``[0, t_end]`` or an unknown element, and
    :class:`OperatingPointError` when the run ends (fails or stops) before ``t``.
    """
    from ..core import simulate
    t = float(t)
    if not math.isfinite(t) or t < 0.0:
        raise ValueError(f"operating time t = {t:g} s must be >= 0 (the scenario starts at 0)")
    if t > scenario.t_end:
        raise ValueError(f"operating time t = {t:g} s is past the scenario's end t_end = "
                         f"{scenario.t_end:g} s ({scenario.file}, [scenario] t_end); choose "
                         f"t <= {scenario.t_end:g} or raise t_end")
    if model is None and scenario.models:
        model = scenario.models[0]
    u0 = {n: float(np.asarray(s(0.0)).ravel()[0]) for n, s in scenario.inputs.items()}
    system = scenario.network(model).build(u0)
    if check is not None:
        check(system)
    steps = 0
    if t == 0.0:
        y = system.y0.copy()
    else:
        inputs = {n: scenario.inputs[n] for n in system.input_names}
        res = simulate(system, (0.0, t), inputs, solver=scenario.solver,
                       options=scenario.options)
        t_last = float(res.t[-1]) if res.t.size else 0.0
        if res.status == "failed" or t_last < t * (1.0 - 1e-12):
            raise OperatingPointError(f"the run to the operating time t = {t:g} s ended at "
                                      f"{t_last:g} s ({res.outcome}): {res.message}",
                                      str(res.outcome), t_last)
        y = np.array([float(res[n][-1]) for n in system.state_names])
        steps = res.stats.steps
    u = _inputs_at(scenario, system, t)
    elems = element_points(system, t, y, u, elements)
    return OperatingPoint(system, t, _readonly(y), _readonly(u), elems, steps)
