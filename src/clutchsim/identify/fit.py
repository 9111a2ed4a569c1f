"""Output-error identification of friction (and plant) parameters from measured records.

The plant is driven by the measured input, and the residual is the simulated output minus
the measured output on the measurement grid.  ``scipy.optimize.least_squares`` (trust-region
reflective, bounds) minimises it from one or more starts, with finite-difference Jacobians.
Every simulation reuses one compiled system (:meth:`System.with_params`) and runs at a tight
tolerance (:data:`FIT_SOLVER_DEFAULTS`), because finite differences of a loosely integrated
trajectory are dominated by the integrator's error.

Error measures: ``NRMSE = ||y_sim − y|| / ||y − mean(y)||`` and ``R² = 1 − NRMSE²``.  For
the EMPS plant the denominator is the measured tracking error ``q − q_ref`` (minus its mean),
because the position itself follows the reference to 1e-4 and any simulation would look
perfect against it; the benchmark's own measure ``100·||q_sim − q||/||q||`` [%] is reported
as ``metrics["position_error_pct"]``.

Several records at once: ``data`` may be a list of records (each already windowed).  The
residual is the concatenation of the records' normalised residuals, each times
``sqrt(w_k/Σw)`` (``weights``, default equal), so the cost is ``½·Σ (w_k/Σw)·NRMSE_k²`` and a
record at a low load counts as much as one at a high load.  The pooled NRMSE is
``sqrt(Σ (w_k/Σw)·NRMSE_k²)``.  Plant parameters named in ``per_record`` (e.g. an offset)
are fitted once per record, as ``name@1``, ``name@2``, ...; validation records use their mean.
All records of one fit must share the sampling interval (within 1 %): they are refused
otherwise (resample them first), because the solver's output step is the sampling interval.

Standard errors come from the Jacobian at the optimum, ``(JᵀJ)⁻¹·s²`` with
``s² = ||r||²/(m − n)``.  They assume independent residuals; measured residuals are strongly
correlated in time, so read them as a lower bound and as a conditioning diagnostic.
"""

from __future__ import annotations

import dataclasses
import math
import os
import threading
import time
from collections.abc import Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import lru_cache
from types import MappingProxyType

import numpy as np
from scipy.optimize import least_squares

from ..core import SolverOptions, simulate
from ..core.options import DEFAULT_METHOD
from ..core.system import closest
from ..data import Measurement, read_measurements
from ..friction import make_model
from ..friction.base import FrictionModel
from .parameters import ParameterSpace, apply_to_model, model_parameter_names, model_value
from .plants import POST, PlantSpec, Setup, absent_input, build_setup

__all__ = ["FIT_SOLVER_DEFAULTS", "INITIAL_STATES", "FitOptions", "FitProblem", "FitResult",
           "Trace", "evaluate", "fit", "nrmse", "simulate_setup", "solver_options"]

#: solver options of every simulation of a fit or an evaluation where ``options`` does not
#: set them (the one place they are written); ``atol`` is then set for each record from its
#: output scale, ``ATOL_FRACTION · rtol · max|output|``
FIT_SOLVER_DEFAULTS = MappingProxyType({"rtol": 1e-8, "wall_time": 30.0,
                                        "max_steps": 5_000_000})
ATOL_FRACTION = 1e-2
#: how a validation record starts: the plant's default, or the whole state at the end of the fit
INITIAL_STATES = ("rest", "fit-end")


def nrmse(residual: np.ndarray, normaliser: np.ndarray) -> float:
    """``||residual|| / ||normaliser||`` (normaliser: measured minus its mean)."""
    return float(np.linalg.norm(residual) / np.linalg.norm(normaliser))


@dataclass(frozen=True, eq=False)
class Trace:
    """Measured and simulated output of one record, with its error measures."""

    source: str
    t: np.ndarray
    measured: np.ndarray
    simulated: np.ndarray
    nrmse: float
    r2: float
    metrics: Mapping[str, float] = field(default_factory=dict)
    reference: np.ndarray | None = None

    @property
    def residual(self) -> np.ndarray:
        return self.simulated - self.measured

    def as_dict(self) -> dict:
        return {"source": self.source, "nrmse": self.nrmse, "r2": self.r2,
                "samples": int(self.t.size), **dict(self.metrics)}


@dataclass(frozen=True, eq=False)
class FitResult:
    """Outcome of :func:`fit` (immutable).

    Attributes
    ----------
    model : FrictionModel
        The friction model with the fitted (and fixed) values.
    model_name : str
        Registry name of the model.
    parameters, stderr : mapping of str to float
        Fitted values and their standard errors (physical units; see the module notes).
        A standard error is None when the data do not determine the parameter.
    bounds : mapping of str to (float, float)
        Bounds used.
    at_bound : tuple of str
        Fitted parameters that ended at a bound: within 0.1 % of it
        (:data:`AT_BOUND_REL`; of the bound's value, or of the range for a bound of 0).
        Such a value is the bound, not an estimate.
    unidentified : tuple of str
        Fitted parameters the data cannot determine: a direction of zero sensitivity (their
        standard error is None), or a term that the fit switched off (a Stribeck drop
        F_s = F_c leaves v_s and delta without effect; a Stribeck speed at its lower bound
        hides F_s).
    warnings : tuple of str
        One sentence per parameter at a bound or unidentified: why and what to do.
    fixed : mapping of str to float
        Values held fixed (given by ``fixed=``).
    plant : str
        Plant kind; ``plant_parameters`` all plant parameter values used.
    fit_trace, validation : Trace, tuple of Trace
        Fitting record and validation records.
    nrmse_fit, r2_fit : float
        Error measures on the fitting record.
    nrmse_validation : float or None
        Mean NRMSE over the validation records (None without ``validate=``).
    records : tuple of Trace
        Every fitting record (``fit_trace`` is the first); ``nrmse_pooled`` their pooled NRMSE.
    notes : tuple of str
        Declared inputs that a record lacks (taken as zero), and how validation started.
    cost_history : ndarray
        Lowest cost (½·NRMSE²) reached after each simulation, over all starts.
    starts : tuple of dict
        Per start: start values, final cost, evaluations, optimiser message.
    evaluations : int
        Simulations run; ``failed_evaluations`` those that did not complete.
    wall_time : float
        Wall time of the whole fit [s] (validation included).
    signal, input, output : str
        Simulated signal and measured columns.
    """

    model: FrictionModel
    model_name: str
    parameters: Mapping[str, float]
    stderr: Mapping[str, float]
    bounds: Mapping[str, tuple[float, float]]
    at_bound: tuple[str, ...]
    unidentified: tuple[str, ...]
    warnings: tuple[str, ...]
    fixed: Mapping[str, float]
    plant: str
    plant_parameters: Mapping[str, float]
    fit_trace: Trace
    validation: tuple[Trace, ...]
    cost_history: np.ndarray
    starts: tuple[dict, ...]
    evaluations: int
    failed_evaluations: int
    wall_time: float
    signal: str
    input: str
    output: str
    message: str
    records: tuple[Trace, ...] = ()
    nrmse_pooled: float | None = None
    notes: tuple[str, ...] = ()

    @property
    def nrmse_fit(self) -> float:
        return self.fit_trace.nrmse

    @property
    def r2_fit(self) -> float:
        return self.fit_trace.r2

    @property
    def nrmse_validation(self) -> float | None:
        if not self.validation:
            return None
        return float(np.mean([v.nrmse for v in self.validation]))

    @property
    def residuals(self) -> np.ndarray:
        return self.fit_trace.residual

    def summary(self) -> dict:
        """The short document ``clutchsim fit --json`` prints."""
        return {"model": self.model_name, "parameters": dict(self.parameters),
                "stderr": dict(self.stderr), "nrmse_fit": self.nrmse_fit,
                "nrmse_validation": self.nrmse_validation, "nrmse_pooled": self.nrmse_pooled,
                "records": [{"source": r.source, "nrmse": r.nrmse} for r in self.records],
                "validation": [{"source": v.source, "nrmse": v.nrmse} for v in self.validation],
                "at_bound": list(self.at_bound), "unidentified": list(self.unidentified),
                "warnings": list(self.warnings), "notes": list(self.notes)}

    def as_dict(self) -> dict:
        """Everything but the traces, JSON-ready (fit.json)."""
        return {
            **self.summary(),
            "r2_fit": self.r2_fit,
            "plant": self.plant, "plant_parameters": dict(self.plant_parameters),
            "input": self.input, "output": self.output, "signal": self.signal,
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "fixed": dict(self.fixed),
            "model_values": {n: model_value(self.model, n)
                             for n in model_parameter_names(self.model)},
            "fit": self.fit_trace.as_dict(),
            "records": [r.as_dict() for r in self.records],
            "validation": [v.as_dict() for v in self.validation],
            "starts": list(self.starts), "evaluations": self.evaluations,
            "failed_evaluations": self.failed_evaluations,
            "wall_time_s": self.wall_time, "message": self.message,
        }


# ---------------------------------------------------------------- simulation
def solver_options(options: SolverOptions | Mapping | None = None
                   ) -> tuple[SolverOptions, bool]:
    """The solver options every simulation of a fit starts from, and whether their atol is
    to be set from each record's output scale.

    ``options``: a :class:`SolverOptions`, used as it is; or a mapping of the keys of a
    scenario's ``[solver]`` table (``SolverOptions.from_mapping``, which names a bad key and
    lists the valid ones) over :data:`FIT_SOLVER_DEFAULTS`, with atol from the output scale
    unless the mapping sets it; ``None`` is the empty mapping.
    """
    if isinstance(options, SolverOptions):
        return options, False
    if options is not None and not isinstance(options, Mapping):
        raise TypeError(f"options must be a SolverOptions or a mapping of solver options, "
                        f"got {type(options).__name__}")
    mapping = dict(options or {})
    auto_atol = "atol" not in mapping
    # atol 1.0 is a placeholder: replaced per record (see _options)
    return SolverOptions.from_mapping(mapping, **FIT_SOLVER_DEFAULTS, atol=1.0), auto_atol


def _options(setup: Setup, base: SolverOptions, auto_atol: bool) -> SolverOptions:
    """``base`` with the record's output grid (and, if asked, an atol from its scale)."""
    dt = float(np.min(np.diff(setup.t)))
    span = float(setup.t[-1] - setup.t[0])
    n_out = int(span / dt) + 10
    atol = ATOL_FRACTION * base.rtol * max(float(np.max(np.abs(setup.measured))), 1e-300) \
        if auto_atol else base.atol
    # room for the extra rows stored at located events
    return dataclasses.replace(base, atol=atol, dt_out=dt, max_output=2 * n_out + 10_000)


def _run(setup: Setup, p, solver, options, load_fraction):
    system = setup.system.with_params(p)
    res = simulate(system, (float(setup.t[0]), float(setup.t[-1])),
                   setup.signals(load_fraction), y0=setup.y0, solver=solver, options=options)
    if res.status != "completed" or res.t[-1] < setup.t[-1] - 1e-9 * max(1.0, abs(setup.t[-1])):
        return None
    return res


def simulate_setup(setup: Setup, p: np.ndarray, *, solver: str, options: SolverOptions,
                   post_offset: float = 0.0, extra: Sequence[str] = (),
                   load_fraction: float | None = None):
    """Simulated signal on the error grid (after any warm-up), or None if the run did not
    complete.

    With ``extra`` signal names, returns ``(y, {name: values on the grid})``.
    """
    res = _run(setup, p, solver, options, load_fraction)
    if res is None:
        return None
    grid = setup.grid
    y = np.interp(grid, res.t, res[setup.signal]) + post_offset
    if setup.output_add is not None:
        y = y + setup.output_add[setup.skip:]
    if not np.all(np.isfinite(y)):
        return None
    if extra:
        return y, {n: np.interp(grid, res.t, res[n]) for n in extra}
    return y


class _Problem:
    """Maps fitted values to parameter vectors and runs the simulations of one record."""

    def __init__(self, model, setup: Setup, names, fixed_plant, solver, tolerances,
                 record: int = 1):
        self.record = record        # 1-based record of name@k values; 0: their mean
        self.model = model
        self.setup = setup
        self.names = tuple(names)
        self.fixed_plant = dict(fixed_plant)
        self.solver = solver
        self.tolerances = tolerances        # (base SolverOptions, atol from the output?)
        self.options = _options(setup, *tolerances)

    def split(self, values: np.ndarray):
        model_vals, plant_vals = {}, dict(self.setup.plant_values)
        per: dict = {}
        for name, value in list(self.fixed_plant.items()) + list(zip(self.names, values)):
            base, at, k = name.partition("@")
            if at:
                per.setdefault(base, {})[int(k)] = float(value)
            elif name in self.setup.plant_index:
                plant_vals[name] = float(value)
            else:
                model_vals[name] = float(value)
        for base, by_record in per.items():
            plant_vals[base] = (float(np.mean(list(by_record.values()))) if self.record == 0
                                else by_record.get(self.record, plant_vals[base]))
        return apply_to_model(self.model, model_vals), plant_vals

    def vector(self, model: FrictionModel, plant_vals) -> tuple[np.ndarray, float]:
        s = self.setup
        p = s.system.params.copy()
        post = 0.0
        for name, value in plant_vals.items():
            idx = s.plant_index[name]
            if idx == POST:
                post = value
            elif idx >= 0:
                p[idx] = value
        p = np.concatenate([p[:s.header], model.pack()])
        return p, post

    def parameters(self, values: np.ndarray, setup: Setup | None = None):
        """Parameter vector, output offset and load fraction of ``setup`` at ``values``."""
        model, plant_vals = self.split(values)
        p, post = self.vector(model, plant_vals)
        setup = setup or self.setup
        if setup is not self.setup:
            p = np.concatenate([setup.system.params[:setup.header], p[self.setup.header:]])
            for name, value in plant_vals.items():
                if setup.plant_index[name] >= 0:
                    p[setup.plant_index[name]] = value
        return p, post, plant_vals.get("load_fraction")

    def _opts(self, setup):
        # output grid and atol follow the record simulated (validation records differ)
        return self.options if setup is self.setup else _options(setup, *self.tolerances)

    def run(self, values: np.ndarray, setup: Setup | None = None, extra: Sequence[str] = ()):
        setup = setup or self.setup
        p, post, lam = self.parameters(values, setup)
        return simulate_setup(setup, p, solver=self.solver, options=self._opts(setup),
                              post_offset=post, extra=extra, load_fraction=lam)

    def final_state(self, values: np.ndarray) -> np.ndarray | None:
        """The whole state (plant, then friction) at the end of this record, simulated at
        ``values``."""
        s = self.setup
        p, _, lam = self.parameters(values, s)
        res = _run(s, p, self.solver, self.options, lam)
        if res is None:
            return None
        return np.array([res.final(n) for n in s.system.state_names])

    def evaluate(self, values: np.ndarray, setup: Setup, source: str, plant: str) -> Trace:
        """Simulate ``setup`` at ``values`` and measure the errors."""
        extra = ("F_motor",) if "voltage" in setup.extras else ()
        out = self.run(values, setup, extra)
        if out is None:
            raise RuntimeError(f"{source}: the simulation at the fitted parameters did not "
                               "complete")
        y, sig = out if extra else (out, {})
        trace = _trace(setup, y, source, plant)
        if extra:
            f_meas = setup.system.params[1] * setup.extras["voltage"]
            err = np.linalg.norm(sig["F_motor"] - f_meas) / np.linalg.norm(f_meas)
            trace = Trace(trace.source, trace.t, trace.measured, trace.simulated, trace.nrmse,
                          trace.r2, MappingProxyType({**trace.metrics,
                                                      "force_error_pct": float(100 * err)}),
                          trace.reference)
        return trace


def _trace(setup: Setup, y: np.ndarray, source: str, plant: str) -> Trace:
    res = y - setup.measured
    e = nrmse(res, setup.normaliser)
    metrics = {}
    if plant == "emps":
        metrics["position_error_pct"] = float(100.0 * np.linalg.norm(res)
                                              / np.linalg.norm(setup.measured))
    metrics["rmse"] = float(np.sqrt(np.mean(res ** 2)))
    return Trace(source, setup.grid, setup.measured, y, e, 1.0 - e * e,
                 MappingProxyType(metrics), setup.extras.get("q_ref"))


@lru_cache(maxsize=4)
def _pool(n: int) -> ThreadPoolExecutor:
    return ThreadPoolExecutor(max_workers=min(n, os.cpu_count() or 1),
                              thread_name_prefix="clutchsim-fit")


# ---------------------------------------------------------------- data and names
def _as_measurement(data, what: str) -> Measurement:
    if isinstance(data, Measurement):
        return data
    if isinstance(data, Mapping):
        if "t" not in data:
            raise ValueError(f"{what}: a mapping of arrays needs a time column 't'; "
                             f"columns: {', '.join(data)}")
        return Measurement.from_arrays(data["t"], source=what,
                                       **{k: v for k, v in data.items() if k != "t"})
    if isinstance(data, (str, bytes)) or hasattr(data, "__fspath__"):
        return read_measurements(data)
    raise TypeError(f"{what} must be a Measurement, a mapping of arrays or a file path, got "
                    f"{type(data).__name__}")


def _check_names(names, model, plant: PlantSpec, what: str):
    valid_model = model_parameter_names(model)
    valid = valid_model + tuple(plant.parameters)
    for name in names:
        if not isinstance(name, str) or name not in valid:
            raise ValueError(
                f"{what}: {model.name} has no parameter {name!r}{closest(str(name), valid)}; "
                f"model parameters: {', '.join(valid_model)}; plant {plant.kind!r} "
                f"parameters: {', '.join(plant.parameters) or '(none)'}")


def _record_of(name: str, setups) -> tuple[str, Setup]:
    base, at, k = name.partition("@")
    return base, setups[int(k) - 1] if at else setups[0]


def _start_values(model, setups, names, fixed_plant) -> dict:
    out = {}
    for name in names:
        base, setup = _record_of(name, setups)
        if base in setup.plant_index:
            out[name] = fixed_plant.get(name, fixed_plant.get(base, setup.plant_values[base]))
        else:
            out[name] = model_value(model, name)
    return out


def _default_bounds(plant: PlantSpec, setups, names) -> dict:
    out = {}
    for name in names:
        base, setup = _record_of(name, setups)
        if base in plant.parameters:
            b = plant.parameters[base]
            if b is None and base == "offset":
                amp = float(np.max(np.abs(setup.measured)))
                b = (-amp, amp)
            out[name] = b
    return out


def _check_rates(records: Sequence[Measurement]) -> None:
    """Records of one joint fit must share the sampling interval (refused otherwise)."""
    dts = [float(np.median(np.diff(m.t))) for m in records]
    for m, dt in zip(records[1:], dts[1:]):
        if abs(dt - dts[0]) > 0.01 * dts[0]:
            raise ValueError(
                f"records of one fit have different sampling intervals: {records[0].source} "
                f"{dts[0]:.6g} s, {m.source} {dt:.6g} s; resample them to one rate first "
                "(a joint fit refuses mixed rates rather than resampling silently)")


#: a fitted value within this fraction of a bound is reported as at the bound [-]
AT_BOUND_REL = 1e-3


def _at_bound(value: float, lo: float, hi: float) -> str | None:
    """``"lower"``/``"upper"`` when ``value`` is within AT_BOUND_REL of that bound."""
    for side, b in (("lower", lo), ("upper", hi)):
        scale = abs(b) if b != 0 else abs(hi - lo)
        if abs(value - b) <= AT_BOUND_REL * scale:
            return side
    return None


def _identifiability(params, values: Mapping[str, float], bounds, stderr, model
                     ) -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """``(at_bound, unidentified, warnings)`` of a fit (see :class:`FitResult`)."""
    at, warn = {}, []
    for name in params:
        side = _at_bound(values[name], *bounds[name])
        if side:
            at[name] = side
            warn.append(f"{name} = {values[name]:.6g} is at its {side} bound "
                        f"{bounds[name][0 if side == 'lower' else 1]:.6g} (within "
                        f"{AT_BOUND_REL:.1%}): the data push it there, so this is the bound, "
                        "not an estimate; widen the bound or fix the parameter")
    why: dict[str, str] = {}
    for name in params:
        if name in stderr and stderr[name] is None:
            why[name] = "the data do not constrain it (a direction of zero sensitivity)"

    def value(n):
        if n in values:
            return values[n]
        return model_value(model, n) if n in model_parameter_names(model) else None
    f_c, f_s, v_s = value("F_c"), value("F_s"), value("v_s")
    if f_c is not None and f_s is not None and abs(f_s - f_c) <= AT_BOUND_REL * abs(f_c):
        for n in ("v_s", "delta"):
            if n in params:
                why.setdefault(n, f"the Stribeck drop vanished (F_s = {f_s:.6g} = F_c), so "
                                  f"{n} has no effect")
    if v_s is not None and "F_s" in params and at.get("v_s") == "lower":
        why.setdefault("F_s", f"the Stribeck speed v_s is at its lower bound {v_s:.3g}: the "
                              "drop from F_s happens below the speeds in the data")
    unidentified = tuple(n for n in params if n in why)
    for n in unidentified:
        warn.append(f"{n} cannot be identified: {why[n]}; fix it (fixed=) or give data that "
                    "excite it")
    return tuple(n for n in params if n in at), unidentified, tuple(warn)


def _standard_errors(jac, den, residual, space: ParameterSpace, x, params) -> dict:
    """Standard errors of the physical parameters; None where the data do not determine one.

    The covariance is formed in the scaled coordinates (well conditioned) from the SVD of the
    Jacobian and then mapped to physical units.  A parameter with a component along a
    direction of (numerically) zero singular value, e.g. a Stribeck level repaired onto the
    Coulomb level, is undetermined.
    """
    m, n = residual.size, len(params)
    if jac is None or m <= n:
        return {}
    J = np.asarray(jac) * den                      # data units per scaled unit
    s2 = float(np.sum(residual ** 2)) / (m - n)
    _, sv, vt = np.linalg.svd(J, full_matrices=False)
    keep = sv > 1e-8 * sv[0] if sv.size and sv[0] > 0 else np.zeros(sv.size, dtype=bool)
    cov = (vt[keep].T / sv[keep] ** 2) @ vt[keep] * s2
    null = vt[~keep]
    deriv = space.derivative(x)
    out = {}
    for j, name in enumerate(params):
        if null.size and np.max(np.abs(null[:, j])) > 1e-3:
            out[name] = None
        else:
            out[name] = float(abs(deriv[j]) * math.sqrt(max(cov[j, j], 0.0)))
    return out


# ---------------------------------------------------------------- evaluate
def evaluate(model: FrictionModel | str, data, *, input: str, output: str,
             plant: str | PlantSpec = "rig-force", plant_options: Mapping | None = None,
             signal: str | None = None, solver: str = DEFAULT_METHOD,
             options: SolverOptions | Mapping | None = None, inputs=(), z0=None,
             warmup: float = 0.0) -> Trace:
    """Simulate a plant with given parameters against a record (no fitting).

    Same arguments as :func:`fit` (``z0``: initial friction states; ``warmup`` [s]: leading
    part simulated but not compared); returns the :class:`Trace` with its error measures.
    Raises RuntimeError if the simulation does not complete.
    """
    tolerances = solver_options(options)
    model = make_model(model) if isinstance(model, str) else model
    spec = plant if isinstance(plant, PlantSpec) else PlantSpec(plant, dict(plant_options or {}))
    meas = _as_measurement(data, "data")
    setup = build_setup(spec, model, meas, input=input, output=output, signal=signal,
                        inputs=inputs, z0=z0, warmup=warmup)
    problem = _Problem(model, setup, (), {}, solver, tolerances)
    return problem.evaluate(np.empty(0), setup, meas.source, spec.kind)


def _initial_state(initial, model: FrictionModel):
    """``None`` (rest), ``"fit-end"`` or an array of the model's states (checked)."""
    if initial is None or (isinstance(initial, str) and initial == "rest"):
        return None
    if isinstance(initial, str):
        if initial != "fit-end":
            raise ValueError(f"validate_initial = {initial!r} must be one of "
                             f"{', '.join(INITIAL_STATES)} or an array of {model.name}'s "
                             f"{model.n_states} state(s)")
        return initial
    z = np.asarray(initial, dtype=float).ravel()
    if z.size != model.n_states or not np.all(np.isfinite(z)):
        raise ValueError(f"validate_initial has {z.size} entries; {model.name} has "
                         f"{model.n_states} state(s) ({', '.join(model.state_names()) or 'none'})"
                         ", all finite")
    return z


# ---------------------------------------------------------------- fit
@dataclass(frozen=True)
class FitProblem:
    """What :func:`fit` fits: the measured columns, the parameters and the plant.

    Attributes
    ----------
    input, output : str
        Measured columns: the plant's driving input and the compared output.
    params : sequence of str
        Parameters to fit: model fields (``"k[0]"`` for tuple elements) or plant parameters
        (shared by all records).
    bounds : mapping of str to (lo, hi), optional
        Per fitted parameter; default ``start/100 ... start·100`` (plant parameters have
        their own defaults).  ``lo < hi`` is required.  A bound of a ``per_record`` name
        applies to each record's copy.
    fixed : mapping of str to float, optional
        Values set before fitting and held (model fields or plant parameters).
    plant : str or PlantSpec
        ``"rig-force"``, ``"rig-velocity"`` or ``"emps"`` (see :mod:`.plants`).
    plant_options : mapping, optional
        Plant options when ``plant`` is a string.
    signal : str, optional
        Simulated signal compared with ``output`` (default per plant: x, F, q).
    inputs : sequence of InputSpec
        Measured inputs beyond the drive signal, and where they enter (:mod:`.plants`).
    per_record : sequence of str
        Plant parameters fitted separately for each record (``name@1``, ``name@2``, ...).
    weights : sequence of float, optional
        Weight of each record in the cost (default equal).
    t_span : (float or None, float or None), optional
        Window of the data used [s] (validation records are used whole).
    """

    input: str
    output: str
    params: Sequence[str]
    bounds: Mapping[str, tuple[float, float]] | None = None
    fixed: Mapping[str, float] | None = None
    plant: str | PlantSpec = "rig-force"
    plant_options: Mapping | None = None
    signal: str | None = None
    inputs: Sequence = ()
    per_record: Sequence[str] = ()
    weights: Sequence[float] | None = None
    t_span: tuple[float | None, float | None] | None = None

    def __post_init__(self):
        params = (self.params,) if isinstance(self.params, str) else tuple(self.params)
        object.__setattr__(self, "params", params)
        object.__setattr__(self, "per_record", tuple(self.per_record))
        object.__setattr__(self, "inputs", tuple(self.inputs))
        for name in ("bounds", "fixed", "plant_options"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name) or {})))
        if self.input == self.output:
            raise ValueError(f"input = output = {self.input!r}: the fit drives the plant with "
                             "the input column and compares its response with the output "
                             "column; name two different columns (e.g. --input v --output F)")
        if not params and not self.per_record:
            raise ValueError("params: give at least one parameter to fit")
        if len(set(params)) != len(params):
            raise ValueError(f"params: repeated names in {list(params)}")
        both = [n for n in self.per_record if n in params]
        if both:
            raise ValueError(f"{both[0]!r} is in both params and per_record: list it once")

    def plant_spec(self) -> PlantSpec:
        """The plant, a :class:`PlantSpec` as given or built from the name and options."""
        return self.plant if isinstance(self.plant, PlantSpec) else \
            PlantSpec(self.plant, dict(self.plant_options))


@dataclass(frozen=True)
class FitOptions:
    """How :func:`fit` searches and simulates (as :class:`~clutchsim.core.SolverOptions` is
    to :func:`~clutchsim.core.simulate`).

    Attributes
    ----------
    starts : int or sequence of mappings
        Number of starts (the first is the model's values, the others uniform in the scaled
        box from ``seed``), or explicit start points (partial mappings name -> value).
    seed : int
        Seed of the random starts (the fit is deterministic for a seed).
    solver : str
        Integrator of every simulation (a method of :mod:`clutchsim.core.methods`).
    solver_options : SolverOptions or mapping, optional
        Tolerances and budgets of every simulation (its ``dt_out`` and ``max_output`` are
        set per record): a :class:`SolverOptions` as it is, or a mapping of solver options
        (``{"rtol": 1e-9, "wall_time": 60}``, the keys of a scenario's ``[solver]`` table)
        over :data:`FIT_SOLVER_DEFAULTS`, with atol from each record's output scale unless
        it is given.  See :func:`solver_options`.
    diff_step : float
        Finite-difference step in scaled coordinates [-].
    max_nfev : int
        Most residual evaluations per start (Jacobian columns not counted).
    max_workers : int
        Threads that simulate Jacobian columns in parallel (1: serial).
    tol : float
        ``ftol`` and ``xtol`` of ``least_squares`` (relative change of cost and of the
        scaled parameters that ends a start).
    """

    starts: int | Sequence[Mapping] = 1
    seed: int = 0
    solver: str = DEFAULT_METHOD
    solver_options: SolverOptions | Mapping | None = None
    diff_step: float = 1e-5
    max_nfev: int = 200
    max_workers: int = 2
    tol: float = 1e-8

    def __post_init__(self):
        if isinstance(self.starts, (int, np.integer)) and not isinstance(self.starts, bool):
            if self.starts < 1:
                raise ValueError(f"starts = {self.starts} must be >= 1")
        else:
            object.__setattr__(self, "starts", tuple(dict(pt) for pt in self.starts))
            if not self.starts:
                raise ValueError("starts: give at least one start point")
        for name in ("max_nfev", "max_workers"):
            if int(getattr(self, name)) < 1:
                raise ValueError(f"{name} = {getattr(self, name)} must be >= 1")
        for name in ("diff_step", "tol"):
            if not float(getattr(self, name)) > 0.0:
                raise ValueError(f"{name} = {getattr(self, name)} must be > 0")


def fit(model: FrictionModel | str, data, problem: FitProblem,
        options: FitOptions | None = None, *, validate=None, validate_initial=None,
        validate_warmup: float = 0.0, progress=None) -> FitResult:
    """Fit friction (and plant) parameters to one or several measured records by output error.

    Parameters
    ----------
    model : FrictionModel or str
        Model with the start values (a name uses its default parameter set).
    data : Measurement, mapping of arrays (with ``"t"``) or path, or a list of them
        Fitting record(s); a list is fitted jointly (see the module notes).
    problem : FitProblem
        The columns, the parameters fitted and held, their bounds, the plant.
    options : FitOptions, optional
        Starts, seed, solver and its options, the least-squares settings.
    validate : data or sequence of data, optional
        Records simulated with the fitted values (not used for fitting).
    validate_initial : "rest", "fit-end" or array, optional
        State the validation records start from: the plant's default (``"rest"``, None);
        the whole state (plant and friction: position, velocity, a controller's state, the
        friction states) at the end of the (last) fitting record at the fitted values
        (``"fit-end"``, for a record that continues it: it goes on moving as the simulation
        did, and an event at the split, such as a reversal, still happens); or the given
        friction states (the plant starts as by default).
    validate_warmup : float
        Leading part of each validation record [s] simulated and left out of its error.
    progress : callable, optional
        Called as ``progress(done, total)`` after each simulation (``total`` is an upper
        bound: the evaluation budget); see :mod:`clutchsim.progress`.

    Returns
    -------
    FitResult

    Examples
    --------
    >>> problem = FitProblem(input="v", output="F", params=["F_c", "F_s"])  # doctest: +SKIP
    >>> res = fit("stribeck", "rig.csv", problem, FitOptions(starts=3))     # doctest: +SKIP
    """
    wall0 = time.perf_counter()
    options = FitOptions() if options is None else options
    tolerances = solver_options(options.solver_options)
    model = make_model(model) if isinstance(model, str) else model
    if not isinstance(model, FrictionModel):
        raise TypeError(f"model must be a friction model or a model name, got "
                        f"{type(model).__name__}")
    spec = problem.plant_spec()
    meas_list, val_list = _records(data, validate, problem)
    w = _record_weights(problem.weights, len(meas_list))
    model, fixed_plant = _check_problem(problem, model, spec)
    initial = _initial_state(validate_initial, model)
    setups = [build_setup(spec, model, m, input=problem.input, output=problem.output,
                          signal=problem.signal, inputs=problem.inputs) for m in meas_list]
    names = [*problem.params,
             *(f"{n}@{k + 1}" for n in problem.per_record for k in range(len(meas_list)))]
    start = _start_values(model, setups, names, fixed_plant)
    space, start_notes = _search_space(problem, spec, setups, names, start)
    problems = [_Problem(model, s, names, fixed_plant, options.solver, tolerances, record=k + 1)
                for k, s in enumerate(setups)]
    points = _start_points(options, space, names, start, model, spec)
    objective = _Objective(problems, setups, w, space, options, progress,
                           budget=max(1, len(points) * options.max_nfev * (len(names) + 1)
                                      * len(meas_list)))
    best, starts = objective.solve(points, names)
    values = space.to_physical(best.x)
    fitted_model, plant_vals = problems[0].split(values)
    reported = _reported_values(names, values, setups, problems, fitted_model)
    traces = [prob.evaluate(values, s, m.source, spec.kind)
              for prob, s, m in zip(problems, setups, meas_list)]
    r_all = np.concatenate([tr.residual * f for tr, f in zip(traces, objective.factors)])
    stderr = _standard_errors(best.jac, 1.0, r_all, space, best.x, names)
    phys_bounds = {n: (float(a), float(b)) for n, a, b in
                   zip(names, space.lower, space.upper)}
    at_bound, unidentified, fit_warnings = _identifiability(
        names, {n: float(v) for n, v in reported.items()}, phys_bounds, stderr, fitted_model)
    notes = start_notes + [note for s in setups for note in s.notes]
    val_traces = _validation_traces(val_list, problems, meas_list, values, fitted_model,
                                    setups[0], names, fixed_plant, options, tolerances, spec,
                                    problem, initial, validate_warmup, notes)
    pooled = float(math.sqrt(sum(wk * tr.nrmse ** 2 for wk, tr in zip(w, traces))))
    return FitResult(
        model=fitted_model, model_name=fitted_model.name,
        parameters=MappingProxyType(reported), stderr=MappingProxyType(stderr),
        bounds=MappingProxyType(phys_bounds), at_bound=at_bound,
        unidentified=unidentified, warnings=fit_warnings,
        fixed=MappingProxyType(dict(problem.fixed)), plant=spec.kind,
        plant_parameters=MappingProxyType(plant_vals), fit_trace=traces[0],
        validation=tuple(val_traces), cost_history=np.array(objective.history),
        starts=tuple(starts), evaluations=objective.n, failed_evaluations=objective.failed,
        wall_time=time.perf_counter() - wall0, signal=setups[0].signal, input=problem.input,
        output=problem.output, message=str(best.message), records=tuple(traces),
        nrmse_pooled=pooled, notes=tuple(notes))


def _records(data, validate, problem: FitProblem):
    """The fitting records (windowed to ``problem.t_span``) and the validation records, as
    measurements, checked: at least one, equal sampling, every measured input present."""
    items = list(data) if isinstance(data, (list, tuple)) else [data]
    if not items:
        raise ValueError("data: give at least one record")
    multi = len(items) > 1
    meas_list = [_as_measurement(d, f"data[{k}]" if multi else "data")
                 for k, d in enumerate(items)]
    if problem.t_span is not None:
        meas_list = [m.window(*problem.t_span) for m in meas_list]
    _check_rates(meas_list)
    vitems = [] if validate is None else \
        list(validate) if isinstance(validate, (list, tuple)) else [validate]
    val_list = [_as_measurement(item, f"validate[{k}]") for k, item in enumerate(vitems)]
    absent = absent_input(problem.inputs, meas_list, val_list)
    if absent:
        raise ValueError(f"inputs: {absent[1]}")
    return meas_list, val_list


def _record_weights(weights, n_rec: int) -> np.ndarray:
    """Each record's weight in the cost, normalised to sum 1."""
    w = np.ones(n_rec) if weights is None else np.asarray(weights, dtype=float).ravel()
    if w.size != n_rec or not np.all(np.isfinite(w)) or np.any(w < 0) or not w.sum() > 0:
        raise ValueError(f"weights = {list(np.ravel(weights))}: give one finite weight >= 0 "
                         f"per record ({n_rec}), not all zero")
    return w / w.sum()


def _check_problem(problem: FitProblem, model: FrictionModel, spec: PlantSpec):
    """The names of ``problem`` checked against the model and plant; returns the model with
    its fixed fields set and the fixed plant parameters."""
    for name in problem.per_record:
        if name not in spec.parameters:
            raise ValueError(f"per_record: {name!r} is not a plant parameter of "
                             f"{spec.kind!r}{closest(name, spec.parameters)}; plant parameters: "
                             f"{', '.join(spec.parameters)}")
    _check_names(problem.params, model, spec, "params")
    fixed = problem.fixed
    _check_names([n.partition("@")[0] for n in fixed], model, spec, "fixed")
    both = [n for n in fixed if n in problem.params or n.partition("@")[0] in problem.per_record]
    if both:
        raise ValueError(f"parameter(s) {', '.join(both)} are both fitted and fixed")
    fixed_plant = {n: float(v) for n, v in fixed.items()
                   if n.partition("@")[0] in spec.parameters}
    model = apply_to_model(model, {n: v for n, v in fixed.items()
                                   if n.partition("@")[0] not in spec.parameters})
    return model, fixed_plant


def _search_space(problem: FitProblem, spec: PlantSpec, setups, names, start):
    """The bounded, scaled space of the fitted names (a ``per_record`` name's bound applies
    to each copy) and the notes on start values outside their bounds."""
    bounds = dict(problem.bounds)
    for n in problem.per_record:
        if n in bounds:
            b = bounds.pop(n)
            for k in range(len(setups)):
                bounds.setdefault(f"{n}@{k + 1}", b)
    space = ParameterSpace.build(names, start, bounds, _default_bounds(spec, setups, names))
    notes = [f"start value {n} = {start[n]:.6g} lies outside its bounds "
             f"[{lo:.6g}, {hi:.6g}]: the fit starts from the nearest bound"
             for n, lo, hi in zip(names, space.lower, space.upper)
             if not lo <= start[n] <= hi]
    return space, notes


def _start_points(options: FitOptions, space: ParameterSpace, names, start, model, spec):
    """The scaled start points: the model's values, then random ones from the seed, or the
    explicit points of ``options.starts`` (names checked)."""
    x_first = space.clip_inside(space.to_scaled(np.array([start[n] for n in names])))
    if not isinstance(options.starts, tuple):
        rng = np.random.default_rng(options.seed)
        return [x_first] + [space.clip_inside(space.random(rng))
                            for _ in range(options.starts - 1)]
    points = []
    for k, pt in enumerate(options.starts):
        _check_names([n.partition("@")[0] for n in pt], model, spec, f"starts[{k}]")
        bad = [n for n in pt if n not in names]
        if bad:
            raise ValueError(f"starts[{k}]: {', '.join(bad)} not fitted")
        vals = np.array([float(pt.get(n, start[n])) for n in names])
        points.append(space.clip_inside(space.to_scaled(vals)))
    return points


class _Objective:
    """The weighted residual of all records over the scaled parameters, its forward-difference
    Jacobian (columns in parallel threads: the integrator releases the GIL), and the counts
    and best cost so far."""

    def __init__(self, problems, setups, w, space: ParameterSpace, options: FitOptions,
                 progress, budget: int):
        self.problems, self.setups, self.space = problems, setups, space
        self.options, self.progress, self.budget = options, progress, budget
        dens = [float(np.linalg.norm(s.normaliser)) for s in setups]
        self.factors = [math.sqrt(wk) / d for wk, d in zip(w, dens)]
        # a failed run counts as NRMSE = 3 for its record
        self.penalties = [3.0 * math.sqrt(wk) * s.normaliser / d
                          for wk, s, d in zip(w, setups, dens)]
        self.n = self.failed = 0
        self.best = math.inf
        self.history: list[float] = []
        self._lock = threading.Lock()
        self._last: dict = {}
        self.workers = max(1, min(len(problems[0].names), os.cpu_count() or 1,
                                  options.max_workers))

    def evaluate(self, x) -> np.ndarray:
        values = self.space.to_physical(x)
        parts = []
        for prob, s, f, pen in zip(self.problems, self.setups, self.factors, self.penalties):
            try:
                y = prob.run(values)
            except ValueError:      # a model constraint the repairs do not cover
                y = None
            with self._lock:
                self.n += 1
                self.failed += y is None
                if self.progress is not None:
                    self.progress(min(self.n, self.budget), self.budget)
            parts.append(pen if y is None else (y - s.measured) * f)
        return np.concatenate(parts)

    def residual(self, x) -> np.ndarray:
        r = self.evaluate(x)
        self._last["x"], self._last["r"] = x.copy(), r
        self.best = min(self.best, 0.5 * float(r @ r))
        self.history.append(self.best)
        return r

    def jacobian(self, x) -> np.ndarray:
        last = self._last
        r0 = last["r"] if "x" in last and np.array_equal(last["x"], x) else self.residual(x)
        _, hi_s = self.space.scaled_bounds
        steps = self.options.diff_step * np.maximum(1.0, np.abs(x))
        steps = np.where(x + steps > hi_s, -steps, steps)

        def column(j):
            xj = x.copy()
            xj[j] += steps[j]
            return (self.evaluate(xj) - r0) / steps[j]

        cols = list(_pool(len(x)).map(column, range(len(x)))) if self.workers > 1 \
            else [column(j) for j in range(len(x))]
        return np.column_stack(cols)

    def solve(self, points, names):
        """``least_squares`` from every start: the best solution and a record per start."""
        best, records = None, []
        tol = self.options.tol
        for x0 in points:
            n0 = self.n
            sol = least_squares(self.residual, x0, jac=self.jacobian,
                                bounds=self.space.scaled_bounds, method="trf",
                                max_nfev=self.options.max_nfev, x_scale=1.0, ftol=tol,
                                xtol=tol)
            records.append({"start": dict(zip(names, self.space.to_physical(x0).tolist())),
                            "cost": float(sol.cost), "evaluations": self.n - n0,
                            "message": str(sol.message)})
            if best is None or sol.cost < best.cost:
                best = sol
        if self.progress is not None:
            self.progress(self.budget, self.budget)
        return best, records


def _reported_values(names, values, setups, problems, fitted_model) -> dict:
    """The values actually simulated (after order-constraint repairs), by name."""
    reported = {}
    for n in names:
        base, setup = _record_of(n, setups)
        if base in setup.plant_index:
            reported[n] = problems[int(n.partition("@")[2] or 1) - 1].split(values)[1][base]
        else:
            reported[n] = model_value(fitted_model, n)
    return reported


def _validation_traces(val_list, problems, meas_list, values, fitted_model, setup0, names,
                       fixed_plant, options: FitOptions, tolerances, spec, problem: FitProblem,
                       initial, warmup: float, notes: list) -> list:
    """The validation records simulated at the fitted values (``notes`` gets theirs)."""
    if not val_list:
        return []
    y_start = None
    if isinstance(initial, str):     # "fit-end": the whole state, so that a record that
        # continues the fitting one also continues its motion and its event states
        last = problems[-1]
        y_start = last.final_state(values)
        if y_start is None:
            raise RuntimeError(f"{meas_list[-1].source}: the simulation at the fitted "
                               "parameters did not complete (for the final state)")
        initial = None
        names_ = last.setup.system.state_names
        notes.append(f"validation starts from the state at the end of "
                     f"{meas_list[-1].source}: " + ", ".join(
                         f"{n} = {z:.6g}" for n, z in zip(names_, y_start)))
    val_problem = _Problem(fitted_model, setup0, names, fixed_plant, options.solver,
                           tolerances, record=0 if len(meas_list) > 1 else 1)
    traces = []
    for vm in val_list:
        vs = build_setup(spec, fitted_model, vm, input=problem.input, output=problem.output,
                         signal=problem.signal, inputs=problem.inputs, z0=initial, y0=y_start,
                         warmup=warmup)
        notes.extend(vs.notes)
        traces.append(val_problem.evaluate(values, vs, vm.source, spec.kind))
    return traces
