"""Frequency response of a linearised plant: forced judder in the linear range.

About an operating point the plant is ``dx/dt = A·x + B·u``, ``out = C·x + D·u`` (the
deviations from the point).  ``A`` is :func:`~clutchsim.analysis.linear.linearise`'s;
:func:`state_space` adds ``B = d f/d u``, ``C = d out/d x`` and ``D = d out/d u`` by the
differentiation that gives ``A`` for a plant without an exact Jacobian (the driveline
today): central differences at the steps ``h = 1e-4·max(|v|, 0.01)`` and ``h/2``,
Richardson-extrapolated (error O(h⁴)).  The interface has no exact input or output
Jacobian, so ``B``, ``C``, ``D`` are differenced even where ``A`` is exact.  ``C`` of a
state is its row of the basis of the linearised states (exact).

:func:`frequency_response` evaluates ``H(jω) = C·(jω·I − A)⁻¹·B + D`` from one input
channel (a load torque on an inertia [N·m], a clutch command [-] i.e. a clamp-load
oscillation, the throttle [-]) to one output (``a_vehicle``, a torque ``T_<name>``, a
speed ``omega_<inertia>``, any output or linearised state) over a frequency grid;
:func:`clutchsim.studies.frf.frf_analysis` does it for a scenario at an operating time
(docs/judder.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..core.system import System, closest
from .linear import (
    FD_STEP,
    LinearModel,
    _jacobian_fd,
    _outputs,
    _readonly,
    _rhs,
    _steps,
    modes,
)

__all__ = ["DEFAULT_BAND_HZ", "DEFAULT_POINTS", "FrequencyResponse", "Peak", "StateSpace",
           "frequency_grid", "frequency_response", "ratio_unit", "state_space"]

#: default frequency grid [Hz]: below the shuffle mode (~3 Hz) to above model (6)'s contact
#: mode (~650 Hz) of a passenger-car driveline
DEFAULT_BAND_HZ = (0.1, 1000.0)
#: default number of grid points (log-spaced)
DEFAULT_POINTS = 400
#: most grid points (the response is one complex solve per point)
MAX_POINTS = 100_000
#: one-sided derivatives of an input that differ by more than this (relative) mark a kink
#: (a saturation, a table breakpoint, a command at 0): a smooth plant differs by O(h)
KINK_TOL = 1e-2


@dataclass(frozen=True)
class StateSpace:
    """``dx/dt = A·x + B·u``, ``out = C·x + D·u`` about the operating point of ``linear``.

    ``A`` [1/s] (``linear.A``), ``B`` [state unit/s per input unit], ``C`` [output unit per
    state unit], ``D`` [output unit per input unit], all read-only; rows and columns named
    by ``linear.state_names``, ``input_names`` and ``output_names`` (the plant's outputs,
    then its linearised states, merged ones included).  ``kinks``: the inputs whose
    one-sided derivatives differ (the plant is not differentiable in them at the point;
    ``B`` and ``D`` hold the mean of both sides there).
    """

    linear: LinearModel
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    input_names: tuple[str, ...]
    input_units: tuple[str, ...]
    output_names: tuple[str, ...]
    output_units: tuple[str, ...]
    kinks: tuple[str, ...] = ()

    @property
    def A(self) -> np.ndarray:
        return self.linear.A

    @property
    def method(self) -> str:
        """How each matrix was obtained."""
        return f"A {self.linear.method}, B/C/D finite-difference"


@dataclass(frozen=True)
class Peak:
    """A local maximum of ``|H|``: ``frequency_hz`` [Hz], ``magnitude`` [the ratio's unit]."""

    frequency_hz: float
    magnitude: float

    def as_dict(self) -> dict:
        return {"frequency_hz": self.frequency_hz, "magnitude": self.magnitude}


@dataclass(frozen=True)
class FrequencyResponse:
    """``H(f) = output/input`` of the linear model at ``frequency_hz`` [Hz].

    ``response`` the complex ``H`` [``unit``]; ``magnitude`` ``|H|`` [``unit``];
    ``phase_deg`` its angle in (−180, 180] [deg] (the output lags the input where it is
    negative); ``unit`` the ratio ``output_unit/input_unit``; ``peaks`` the local maxima of
    ``|H|`` inside the grid, each refined between its neighbours (``|H|`` is evaluated
    exactly there), by frequency; ``t_s`` the operating time [s]; ``warnings`` what limits
    the result (an unstable mode: no steady state; an input at a kink).
    """

    input: str
    output: str
    input_unit: str
    output_unit: str
    frequency_hz: np.ndarray
    response: np.ndarray
    peaks: tuple[Peak, ...]
    t_s: float
    model: str = ""
    method: str = ""
    warnings: tuple[str, ...] = ()

    @property
    def unit(self) -> str:
        return ratio_unit(self.output_unit, self.input_unit)

    @property
    def magnitude(self) -> np.ndarray:
        return np.abs(self.response)

    @property
    def phase_deg(self) -> np.ndarray:
        return np.degrees(np.angle(self.response))

    def with_model(self, model: str) -> FrequencyResponse:
        return replace(self, model=model)

    def rows(self) -> list[dict]:
        """One dict per frequency (the CSV table), units in the keys."""
        u = self.unit
        return [{"frequency_hz": float(f), f"magnitude [{u}]": float(m), "phase_deg": float(p)}
                for f, m, p in zip(self.frequency_hz, self.magnitude, self.phase_deg)]

    def as_dict(self) -> dict:
        """The JSON document of ``clutchsim judder --frf ... --json``."""
        return {"kind": "frf", "model": self.model, "t_s": self.t_s, "input": self.input,
                "output": self.output, "unit": self.unit,
                "input_unit": self.input_unit, "output_unit": self.output_unit,
                "frequency_hz": [float(f) for f in self.frequency_hz],
                "magnitude": [float(m) for m in self.magnitude],
                "phase_deg": [float(p) for p in self.phase_deg],
                "peaks": [p.as_dict() for p in self.peaks],
                "warnings": list(self.warnings)}


def ratio_unit(output_unit: str, input_unit: str) -> str:
    """The unit of ``output/input``: ``"m/s²/(N·m)"``, ``"N·m"`` per a dimensionless input,
    ``"-"`` for equal units."""
    if input_unit in ("-", ""):
        return output_unit or "-"
    if output_unit == input_unit:
        return "-"
    den = f"({input_unit})" if any(c in input_unit for c in "/· ") else input_unit
    return f"1/{den}" if output_unit in ("-", "") else f"{output_unit}/{den}"


def frequency_grid(f_min: float = DEFAULT_BAND_HZ[0], f_max: float = DEFAULT_BAND_HZ[1],
                   points: int = DEFAULT_POINTS) -> np.ndarray:
    """``points`` frequencies [Hz] log-spaced from ``f_min`` to ``f_max`` (both included).

    Raises ``ValueError`` unless ``0 < f_min < f_max`` (finite) and
    ``2 <= points <= MAX_POINTS``.
    """
    f_min, f_max = float(f_min), float(f_max)
    if not (math.isfinite(f_min) and f_min > 0.0):
        raise ValueError(f"f_min = {f_min:g} Hz must be a finite frequency > 0 (the grid is "
                         "log-spaced)")
    if not (math.isfinite(f_max) and f_max > f_min):
        raise ValueError(f"f_max = {f_max:g} Hz must be finite and above f_min = {f_min:g} Hz")
    if isinstance(points, bool) or int(points) != points or not 2 <= points <= MAX_POINTS:
        raise ValueError(f"points = {points!r} must be an integer from 2 to {MAX_POINTS:,}")
    return np.geomspace(f_min, f_max, int(points))


def _frequencies(freqs_hz) -> np.ndarray:
    f = np.asarray(freqs_hz, dtype=float).ravel()
    if f.size == 0 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise ValueError(f"freqs_hz = {freqs_hz!r} must be finite frequencies >= 0 Hz")
    return f


def _one_sided(f, v: np.ndarray, k: int, h: float):
    """Forward and backward differences of ``f`` in ``v[k]`` at step ``h``."""
    vp, vm = v.copy(), v.copy()
    vp[k] += h
    vm[k] -= h
    f0 = f(v)
    return (f(vp) - f0) / h, (f0 - f(vm)) / h


def _differs(a: np.ndarray, b: np.ndarray) -> bool:
    scale = max(float(np.max(np.abs(a))), float(np.max(np.abs(b))))
    return scale > 0.0 and float(np.max(np.abs(a - b))) > KINK_TOL * scale


def state_space(system: System, lin: LinearModel, y, u) -> StateSpace:
    """``B``, ``C``, ``D`` of ``system`` about ``(lin.t_s, y, u)`` for every input and every
    output (plant outputs, then the linearised states), in the coordinates of ``lin``.

    Rows of ``B`` are those the reduced ``A`` keeps (a merged speed follows its cluster
    through the constraint); ``C`` is differenced over the continuous states and mapped
    through ``lin.basis``.  See the module docstring for the differencing.
    """
    y = np.ascontiguousarray(y, dtype=np.float64).copy()
    u = np.ascontiguousarray(u, dtype=np.float64).copy()
    t = lin.t_s
    cont = list(lin.continuous)
    keep = [cont.index(system.state_names.index(n)) for n in lin.state_names]
    n_out = len(system.output_names)

    def rhs_out(uu):
        return np.concatenate([_rhs(system, t, y, uu)[cont], _outputs(system, t, y, uu)])

    m = len(system.input_names)
    h_u = [FD_STEP * max(abs(float(u[k])), 1e-2) for k in range(m)]
    G = _jacobian_fd(rhs_out, u, range(m), h_u) if m else np.zeros((len(cont) + n_out, 0))
    kinks = []
    for k in range(m):
        fwd, bwd = _one_sided(rhs_out, u, k, h_u[k])
        if _differs(fwd, bwd):
            kinks.append(system.input_names[k])
    B = G[:len(cont)][keep, :]
    D_out = G[len(cont):, :]
    C_out = _jacobian_fd(lambda yy: _outputs(system, t, yy, u), y, cont, _steps(y, cont)) \
        @ lin.basis
    C_state = np.asarray(lin.basis)                  # x_continuous = basis·x
    state_names = tuple(system.state_names[j] for j in cont)
    state_units = tuple(system.state_units[j] for j in cont)
    C = np.vstack([C_out.reshape(n_out, lin.n), C_state])
    D = np.vstack([D_out.reshape(n_out, m), np.zeros((len(cont), m))])
    return StateSpace(lin, _readonly(B), _readonly(C), _readonly(D), tuple(system.input_names),
                      tuple(system.input_units), (*system.output_names, *state_names),
                      (*system.output_units, *state_units), tuple(kinks))


def _check_names(input: str, output: str, inputs, outputs, where: str) -> None:
    if input not in inputs:
        raise ValueError(f"input {input!r} is not an input of {where}{closest(input, inputs)}"
                         f" (inputs: {', '.join(inputs) or 'none'})")
    if output not in outputs:
        raise ValueError(f"output {output!r} is not an output or linearised state of "
                         f"{where}{closest(output, outputs)} (outputs: {', '.join(outputs)})")


def frequency_response(ss: StateSpace, input: str, output: str, freqs_hz) -> FrequencyResponse:
    """``H(jω) = C·(jω·I − A)⁻¹·B + D`` from ``input`` to ``output`` of ``ss`` at
    ``freqs_hz`` [Hz] (finite, >= 0; 0 only where ``A`` is regular).

    Unknown names are a ``ValueError`` that lists the valid ones.  The result warns when
    the linear model has an unstable mode (``H`` is then no steady state a simulation
    reaches) and when the plant has a kink in ``input`` at the point.
    """
    _check_names(input, output, ss.input_names, ss.output_names, "the plant")
    f = _frequencies(freqs_hz)
    k = ss.input_names.index(input)
    i = ss.output_names.index(output)
    A, b, c, d = ss.A, ss.B[:, k], ss.C[i], float(ss.D[i, k])
    eye = np.eye(A.shape[0])

    def H(fk):
        s = 2j * math.pi * np.atleast_1d(fk)
        if A.shape[0] == 0:
            return np.full(s.shape, d, dtype=complex)
        x = np.linalg.solve(s[:, None, None] * eye - A, np.broadcast_to(b, (s.size, b.size))
                            [..., None])[..., 0]
        return x @ c + d

    try:
        resp = np.concatenate([H(f[j:j + 2000]) for j in range(0, f.size, 2000)])
    except np.linalg.LinAlgError:
        resp = np.full(f.shape, np.nan, dtype=complex)
    if not np.all(np.isfinite(resp)):
        bad = f[~np.isfinite(resp)]
        raise ValueError(f"the response is not finite at {bad[0]:g} Hz ({bad.size} of "
                         f"{f.size} frequencies): jω·I − A is singular there (a rigid-body "
                         "eigenvalue at 0 Hz or an undamped mode on the grid) or the plant "
                         "is not finite at the point; leave that frequency out of the grid")
    warn = []
    bad = [m for m in modes(ss.linear) if not m.stable]
    if bad:
        worst = max(bad, key=lambda m: m.growth_rate_1_s)
        warn.append(f"the linear model has {len(bad)} unstable mode(s) (largest growth rate "
                    f"{worst.growth_rate_1_s:.4g} 1/s, at {worst.frequency_hz:.4g} Hz, "
                    f"dominated by {', '.join(worst.dominant_states)}): H is not a steady "
                    "state that a simulation reaches; it is the response of the frozen "
                    "linear model")
    if input in ss.kinks:
        warn.append(f"the plant is not differentiable in {input!r} at "
                    "the operating point (its one-sided derivatives differ by more than "
                    f"{KINK_TOL:g} relative: a saturation, a table breakpoint or a "
                    "command at 0): H uses their mean and holds only for one side")
    return FrequencyResponse(input, output, ss.input_units[k], ss.output_units[i],
                             _readonly(f), _readonly(resp), _peaks(f, resp, H),
                             ss.linear.t_s, method=ss.method, warnings=tuple(warn))


def _peaks(f: np.ndarray, resp: np.ndarray, H) -> tuple[Peak, ...]:
    """Local maxima of ``|resp|`` over the grid (a plateau counts once), each refined by a
    bounded scalar search of ``|H|`` between its neighbours."""
    from scipy.optimize import minimize_scalar
    mag = np.abs(resp)
    out = []
    j = 1
    while j < f.size - 1:
        k = j
        while k + 1 < f.size - 1 and mag[k + 1] == mag[j]:
            k += 1                                  # a plateau j..k
        if mag[j] > mag[j - 1] and mag[k] > mag[k + 1]:
            lo, hi = float(f[j - 1]), float(f[k + 1])
            r = minimize_scalar(lambda x: -abs(H(x)[0]), bounds=(lo, hi), method="bounded",
                                options={"xatol": 1e-10 * hi})
            fk, mk = (float(r.x), float(-r.fun)) if -r.fun >= mag[j] else \
                (float(f[j]), float(mag[j]))
            out.append(Peak(fk, mk))
        j = k + 1
    return tuple(out)
