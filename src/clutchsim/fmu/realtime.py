"""A scenario's driveline as a fixed-step C library for hardware-in-the-loop rigs
(:func:`export_realtime`, behind ``clutchsim rt``), and that library run from Python
(:class:`RealtimeKernel`, :func:`run_realtime`, :func:`compare_realtime`) to check it
against clutchsim's variable-step run.

The directory also holds an FMI 2.0 co-simulation FMU that takes the same fixed steps
(:func:`~clutchsim.fmu.export.export_fmu` with ``fixed_step``).

The library is the printed plant (``plant.c``, :mod:`clutchsim.cgen.cprint`, the same C as
the FMUs), its layout (``model.h``) and the kernel (``clutchsim_rt.h``, ``rt_kernel.c``,
``ros2.c``): one ROS2 step per call (one Jacobian, one LU factorisation, two right-hand
sides and two triangular solves: a fixed amount of work), then the plant's events at the
step's end, with a bounded event iteration.  No allocation, no I/O, no recursion in the
step.

The clutch's law is the scenario's (model (6) with its default ``clamp`` reset in the
packaged launch): its slip reversals are events, found at the end of the step in which they
happen, and the reset clamps the pre-sliding state there.  Not the event-free ``stop``
policy: a fixed step carries its state past the stop's bound by up to ``h·|v|`` (0.08 rad
against a bound of 2 mrad in the default launch at 1 ms), the state stays there while the
clutch slides, and after the next reversal the spring pushes against the slip until the
state is back inside: friction that feeds energy in.  Measured on the default launch at
1 ms: ``stop`` misses the engine speed by 41 rpm and the peak jerk by 13 %; ``clamp`` by
1.4 rpm and 0.05 % (docs/realtime.md).  ``reset="stop"`` is still accepted.

The step size.  ROS2 is L-stable and takes the exact Jacobian at every step, so no linear
mode makes it unstable, however stiff.  What the step limits is how well a mode is
followed: per step ROS2 multiplies an undamped oscillation of angular frequency ``ω`` by
``|R(iωh)|`` (:func:`ros2_damping`), which adds a numerical damping ratio of 0.4 % at
``ωh = 0.1``, 2.6 % at 0.2, 18 % at 0.5 and 41 % at 1.  :func:`step_limit` takes the
oscillatory modes of the plant linearised at its initial state and at the variable-step
run's state at lock-up (or its end), and requires ``ωh <= OMEGA_H_MAX`` (0.5) for every one
with a frequency up to ``follow_hz`` (default 200 Hz: shuffle, judder and the damper modes);
faster modes (a friction law's presliding stiffness) are damped by the step, as an
L-stable method must, and listed as such.  A step beyond the limit is refused
(:class:`RealtimeError`, the CLI's exit status 2) naming the mode and the largest step.
"""

from __future__ import annotations

import ctypes
import json
import math
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._util import claim_output_dir
from ..cgen.compiler import compile_shared, find_compiler
from .export import FmuError, _parameters, export_fmu, model_h, printed_plant

__all__ = ["AGREEMENT", "OMEGA_H_MAX", "RT_MODEL", "RealtimeError", "RealtimeExport", "RealtimeKernel",
           "compare_realtime", "export_realtime", "ros2_damping", "run_realtime",
           "sampled_inputs", "step_limit"]

_HERE = Path(__file__).parent
#: the kernel's C files (copied next to the printed plant)
RT_SOURCES = ("clutchsim_rt.h", "rt_kernel.c", "ros2.c")
#: the clutch law of the real-time library when the scenario lists it: model (6), with the
#: scenario's reset policy
RT_MODEL = "mykhailevych2020"
#: the largest ω·h of a followed mode (ROS2's numerical damping ratio 0.18 there)
OMEGA_H_MAX = 0.5
#: modes up to this frequency [Hz] must be followed by default
FOLLOW_HZ = 200.0
#: how far the kernel's launch may be from the variable-step run without a warning: relative
#: errors of the lock-up time and the peak jerk, and the engine speed's largest error [rpm]
AGREEMENT = {"lockup_time_s": 0.01, "jerk_peak_mps3": 0.05, "engine_speed_max_error_rpm": 5.0}
#: an oscillatory mode of the linearisation: damping ratio below this
_OSCILLATORY_ZETA = 0.9
_LIB = "libclutchsim_rt.so"
#: the co-simulation FMU (FMI 2.0) with the kernel's fixed step, beside the library
FMU_NAME = "clutchsim_rt.fmu"


class RealtimeError(FmuError):
    """An option, a scenario or a step that the real-time library cannot take (exit 2)."""


def ros2_damping(omega_h: float) -> tuple[float, float]:
    """``(|R|, ζ)``: ROS2's amplification of an undamped mode of ``ω·h`` per step and the
    damping ratio that adds (``R(z) = (1 + (1 − 2γ)z + (γ² − 2γ + ½)z²)/(1 − γz)²``,
    ``γ = 1 + 1/√2``)."""
    g = 1.0 + 1.0 / math.sqrt(2.0)
    z = 1j * omega_h
    r = (1.0 + (1.0 - 2.0 * g) * z + (g * g - 2.0 * g + 0.5) * z * z) / (1.0 - g * z) ** 2
    a, ph = abs(r), math.atan2(r.imag, r.real)
    if a >= 1.0 or omega_h == 0.0:
        return a, 0.0
    return a, -math.log(a) / math.hypot(ph, math.log(a))


@dataclass(frozen=True)
class Mode:
    """An oscillatory mode of the linearised plant at ``where``: frequency [Hz], damping
    ratio, the states that take part most, ``ω·h`` at the step, and whether the step must
    follow it."""

    where: str
    hz: float
    zeta: float
    states: tuple[str, ...]
    omega_h: float
    followed: bool

    def to_dict(self) -> dict:
        _, zn = ros2_damping(self.omega_h)
        return {"where": self.where, "frequency_hz": self.hz, "damping_ratio": self.zeta,
                "states": list(self.states), "omega_h": self.omega_h,
                "numerical_damping_ratio": zn, "followed": self.followed}


def _modes(system, t, y, u, where, step, follow_hz) -> list[Mode]:
    """The oscillatory modes (:func:`clutchsim.analysis.linear.modes`) of ``system``
    linearised about ``(t, y, u)``."""
    from ..analysis.linear import linearise, modes
    out = []
    for m in modes(linearise(system, float(t), y, u)):
        if m.frequency_hz > 0.0 and m.damping_ratio < _OSCILLATORY_ZETA:
            w = 2.0 * math.pi * m.frequency_hz
            out.append(Mode(where, m.frequency_hz, m.damping_ratio, m.dominant_states,
                            float(w * step), bool(m.frequency_hz <= follow_hz)))
    return out


def step_limit(sc, system, step: float, follow_hz: float = FOLLOW_HZ, reference=None
               ) -> tuple[float, list[Mode]]:
    """``(h_max, modes)``: the largest step that follows every mode up to ``follow_hz``
    (``ω·h <= OMEGA_H_MAX``) and the oscillatory modes of the plant linearised at its
    initial state and 50 ms after the lock-up (else at the end) of ``reference`` (a
    :class:`~clutchsim.scenario.run.LaunchResult` of ``system``; None: the initial state
    only)."""
    def inputs_at(t):
        return sampled_inputs(sc, system.input_names, np.array([float(t)]))[0]

    modes = _modes(system, 0.0, system.y0, inputs_at(0.0), "initial state", step, follow_hz)
    res = None if reference is None else reference.result
    if res is not None and res.t.size:
        t_lock = reference.metrics.get("lockup_time_s")
        locked = t_lock is not None and math.isfinite(t_lock)
        i = min(int(np.searchsorted(res.t, t_lock + 0.05 if locked else res.t[-1])),
                res.t.size - 1)
        y = np.array([res[s][i] for s in system.state_names])
        where = "after lock-up" if locked else "end"
        modes += _modes(system, res.t[i], y, inputs_at(res.t[i]),
                        f"{where} (t = {res.t[i]:.3g} s)", step, follow_hz)
    fastest = max((m.hz for m in modes if m.followed), default=0.0)
    h_max = OMEGA_H_MAX / (2.0 * math.pi * fastest) if fastest > 0 else math.inf
    return h_max, modes


@dataclass(frozen=True)
class RealtimeExport:
    """What :func:`export_realtime` wrote: the directory, the library built from its
    sources, the step [s], the clutch law, the layout and the modes of the step check."""

    out: Path
    library: Path
    step: float
    model: str
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    events: tuple[str, ...]
    step_max: float
    modes: tuple[Mode, ...]
    check: dict

    def to_dict(self) -> dict:
        return {"out": str(self.out), "library": str(self.library), "step_s": self.step,
                "model": self.model, "states": list(self.states), "inputs": list(self.inputs),
                "outputs": list(self.outputs), "events": list(self.events),
                "step_max_s": self.step_max if math.isfinite(self.step_max) else None,
                "omega_h_max": OMEGA_H_MAX, "modes": [m.to_dict() for m in self.modes],
                "check": self.check}


def _clutch_override(sc, reset: str) -> list[str]:
    """The override that puts model (6)'s reset policy ``reset`` on the scenario's clutch."""
    from ..friction.mykhailevych2020 import RESET_POLICIES
    if reset not in RESET_POLICIES:
        # checked here, not by the model: its message would name the override below, a
        # key the user never typed
        raise RealtimeError(f"--reset {reset}: model (6)'s reset policy is one of "
                            f"{', '.join(RESET_POLICIES)}")
    for kind in ("coupling", "component"):
        for i, t in enumerate(sc.data.get(kind, [])):
            if t.get("name") == sc.clutch and isinstance(t.get("friction"), dict):
                return [f'{kind}[{i}].friction.overrides.reset="{reset}"']
    raise RealtimeError(f"--reset {reset}: the scenario's clutch {sc.clutch!r} has no "
                        "friction model to set it on")


def _c_name(name: str) -> str:
    return re.sub(r"\W", "_", name, flags=re.ASCII)


def _c_names(array: str, names) -> str:
    body = ", ".join(json.dumps(n, ensure_ascii=True) for n in names) or "0"
    return f"static const char *{array}[{max(len(names), 1)}] = {{{body}}};"


def export_realtime(scenario, out, model: str | None = None, *, step: float = 1e-3,
                    overrides=None, follow_hz: float = FOLLOW_HZ, reset: str | None = None,
                    force: bool = False) -> RealtimeExport:
    """Write the real-time C library of ``scenario`` into the directory ``out``.

    Parameters
    ----------
    scenario : Scenario, str, Path or None
        A loaded scenario or a path (None: the default launch).
    out : str or Path
        The output directory (claimed as clutchsim's output directories are: an existing one
        only if it is empty or an earlier ``clutchsim rt`` output; written atomically).
    model : str, optional
        The clutch's friction model (default: model (6) when the scenario lists it, else
        the scenario's first).
    reset : str, optional
        Model (6)'s reset policy on the clutch (default: the scenario's).
    step : float
        The fixed step [s] (default 1 ms: 1 kHz).
    follow_hz : float
        Modes up to this frequency [Hz] must be followed (``ω·h <= OMEGA_H_MAX``).

    Raises :class:`RealtimeError` for a step the plant cannot take or a bad option, and
    :class:`~clutchsim.cgen.compiler.CompilerError` without a C compiler.
    """
    from ..scenario import resolve_scenario
    from ..scenario.run import run_system
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not (
            math.isfinite(step) and 0.0 < step <= 0.1):
        raise RealtimeError(f"--step {step!r}: the fixed step must be a number of seconds in "
                            "(0, 0.1]")
    if not (isinstance(follow_hz, (int, float)) and math.isfinite(follow_hz) and follow_hz > 0):
        raise RealtimeError(f"--follow {follow_hz!r}: a frequency [Hz] > 0")
    find_compiler()             # no compiler: NoCompilerError now, before any work
    overrides = list(overrides or ())
    sc = resolve_scenario(scenario, overrides)
    if reset is not None:
        sc = resolve_scenario(scenario, overrides + _clutch_override(sc, reset))
    if model is None and sc.models:
        model = sc.models[0] if RT_MODEL not in sc.models else RT_MODEL
    plan, comps, system, u0, program = printed_plant(sc, model)
    reference = run_system(sc, system, model)
    h_max, modes = step_limit(sc, system, step, follow_hz, reference)
    if step > h_max * (1.0 + 1e-12):
        worst = max((m for m in modes if m.followed), key=lambda m: m.hz)
        raise RealtimeError(
            f"--step {step:g} s: too long for the mode at {worst.hz:.4g} Hz of "
            f"{', '.join(worst.states)} ({worst.where}, damping ratio {worst.zeta:.3g}): "
            f"ω·h = {worst.omega_h:.3g} > {OMEGA_H_MAX} (ROS2 would damp it by a numerical damping ratio of "
            f"{ros2_damping(worst.omega_h)[1]:.2g}); the largest step is {h_max:.3g} s "
            f"(or follow modes only up to a lower --follow than {follow_hz:g} Hz)")
    p = np.asarray(system.params, dtype=float)
    defines = {"CS_RT_STEP": repr(float(step))}
    for prefix, names in (("CS_RT_X_", system.state_names), ("CS_RT_U_", system.input_names),
                          ("CS_RT_Y_", system.output_names)):
        for i, n in enumerate(names):
            defines[prefix + _c_name(n)] = i
    header = model_h(f"the real-time kernel of {sc.name!r}", system,
                     [u0[n] for n in system.input_names], p, np.zeros(len(p), dtype=int),
                     defines)
    header += "\n".join([_c_names("cs_state_names", system.state_names),
                         _c_names("cs_input_names", system.input_names),
                         _c_names("cs_output_names", system.output_names), ""])
    law = system.metadata.get("models", {}).get(sc.clutch, model or "")
    layout = {"scenario": sc.name, "step_s": float(step), "model": law,
              "states": list(system.state_names), "state_units": list(system.state_units),
              "inputs": list(system.input_names), "input_units": list(system.input_units),
              "outputs": list(system.output_names),
              "output_units": list(system.output_units),
              "events": list(system.event_names), "n_parameters": int(p.size),
              "parameters": {q["name"]: q["slot"] for q in _parameters(plan, comps)}}
    out = Path(out)
    with claim_output_dir(out, "rt", force=force) as claimed, claimed.build() as part:
        (part / "plant.c").write_text(program.source)
        (part / "model.h").write_text(header)
        for f in RT_SOURCES:
            shutil.copyfile(_HERE / f, part / f)
        compile_shared([part / "rt_kernel.c", part / "plant.c"], part / _LIB, include=[part])
        (part / "rt.json").write_text(json.dumps(layout, indent=2, allow_nan=False))
        check = compare_realtime(RealtimeKernel(part), sc, reference=reference)
        info = RealtimeExport(out, out / _LIB, float(step), law, tuple(system.state_names),
                              tuple(system.input_names), tuple(system.output_names),
                              tuple(system.event_names), h_max, tuple(modes), check)
        about = {k: v for k, v in info.to_dict().items() if k not in ("out", "library")}
        (part / "rt.json").write_text(json.dumps({**layout, **about, "library": _LIB},
                                                 indent=2, allow_nan=False, default=float))
        export_fmu(sc, part / FMU_NAME, model, fmi="2", kind="cs", fixed_step=step)
        (part / "README.md").write_text(_readme(sc.name, law, step, system))
    return info


def _readme(name, law, step, system) -> str:
    return f"""# Real-time kernel of {name!r} (clutchsim)

Fixed step {step:g} s, clutch law {law}.  Build with any C99 compiler:

    cc -O2 -std=c99 -c rt_kernel.c plant.c

and call it as `clutchsim_rt.h` shows.  `{FMU_NAME}`: the same steps as an FMI 2.0
co-simulation FMU (communication steps: multiples of {step:g} s).
Inputs (`s.u[CS_RT_U_<name>]`): {", ".join(system.input_names)}.
States: {len(system.state_names)}; outputs: {len(system.output_names)} (names and units in
rt.json and model.h).
"""


class RealtimeKernel:
    """The library of :func:`export_realtime` loaded with ctypes (a test and benchmark
    driver: a rig links the C sources itself)."""

    def __init__(self, directory):
        directory = Path(directory)
        self.info = json.loads((directory / "rt.json").read_text())
        self.lib = ctypes.CDLL(str(directory / _LIB))
        self._nu = len(self.info["inputs"])
        # cs_rt_instance starts with t, y[max(NX, 1)], u[max(NU, 1)], p (all doubles)
        self._p_offset = 8 * (1 + max(len(self.info["states"]), 1) + max(self._nu, 1))
        self.lib.cs_rt_size.restype = ctypes.c_size_t
        self._buf = ctypes.create_string_buffer(self.lib.cs_rt_size())
        self.lib.cs_rt_init.argtypes = [ctypes.c_void_p]
        self.lib.cs_rt_run.argtypes = [ctypes.c_void_p, ctypes.c_long, ctypes.c_void_p,
                                       ctypes.c_void_p, ctypes.c_int, ctypes.c_void_p]
        self.lib.cs_rt_run.restype = ctypes.c_int
        self.names = tuple(self.info["states"]) + tuple(self.info["outputs"])
        self.units = tuple(self.info["state_units"]) + tuple(self.info["output_units"])

    def run(self, inputs: np.ndarray, record=None, parameters=None
            ) -> tuple[np.ndarray, int]:
        """Reset to the start, take ``len(inputs)`` steps with ``inputs[k]`` held over step
        ``k``; ``(rec, status)``: after each step the signals ``record`` (names of states
        and outputs; all of them by default) as the rows of ``rec`` (NaN after the run
        ended), and the status (0 ran through, 1 stopped by an event of the plant, 2 the
        step failed, 3 an event of the plant ended it as a failure: an engine stall).
        ``parameters``: ``{name: value}`` of the plant's parameter vector (``rt.json``'s
        ``parameters``) set after the reset."""
        names = self.names if record is None else tuple(record)
        idx = np.array([self.names.index(n) for n in names], dtype=np.int32)
        u = np.ascontiguousarray(inputs, dtype=float).reshape(-1, max(self._nu, 1))
        rec = np.full((u.shape[0], idx.size), np.nan)
        self.lib.cs_rt_init(self._buf)
        if parameters:
            slots = self.info["parameters"]
            for name, value in parameters.items():
                if name not in slots:
                    raise KeyError(f"no parameter {name!r} in the real-time plant")
                ctypes.c_double.from_buffer(self._buf, self._p_offset + 8 * slots[name]
                                            ).value = float(value)
        st = self.lib.cs_rt_run(self._buf, u.shape[0], u.ctypes.data, idx.ctypes.data,
                                idx.size, rec.ctypes.data)
        return rec, int(st)


def sampled_inputs(sc, names, t) -> np.ndarray:
    """The scenario's input signals ``names`` at the times ``t``: one row per time (a
    column of zeros without inputs: the kernel's input array is never empty)."""
    return np.column_stack([np.broadcast_to(np.asarray(sc.inputs[n](t), dtype=float),
                                            t.shape) for n in names]) if names else \
        np.zeros((t.size, 1))


def run_realtime(kernel: RealtimeKernel, sc, t_end: float | None = None):
    """The scenario's launch on the real-time kernel, each input sampled at the start of
    its step and held (as a rig's controller sets it): a :class:`~clutchsim.core.Result`
    of every state and output at the step ends."""
    from ..core.result import Result, Stats
    h = float(kernel.info["step_s"])
    t_end = sc.t_end if t_end is None else float(t_end)
    n = round(t_end / h)
    starts = np.arange(n) * h
    u = sampled_inputs(sc, kernel.info["inputs"], starts)
    rec, status = kernel.run(u)
    t = np.arange(1, n + 1) * h
    done = ~np.isnan(rec[:, 0])
    cols = [(name, unit, rec[done, j]) for j, (name, unit) in
            enumerate(zip(kernel.names, kernel.units))]
    outcome = ("completed", "stopped", "solver_error", "event_failed")[status]
    return Result.build(t[done], cols, outcome=outcome,
                        message=f"fixed-step kernel, {n} steps of {h:g} s",
                        stats=Stats(int(done.sum()), 0, 2 * int(done.sum()), int(done.sum()),
                                    int(done.sum()), 0, h, 0.0), solver="ros2-fixed")


def compare_realtime(kernel: RealtimeKernel, sc, model: str | None = None, *,
                     reference=None) -> dict:
    """The kernel's launch against clutchsim's variable-step run of the same plant
    (``reference``, a :class:`~clutchsim.scenario.run.LaunchResult`; None: run it): the
    lock-up time, the peak jerk and the slip energy (launch metrics of both) and the
    largest engine-speed difference [rpm] on the kernel's steps."""
    from ..analysis.launch_metrics import analyse_run
    from ..scenario.run import run_system
    if reference is None:
        model = model if model is not None else kernel.info["model"]
        reference = run_system(sc, sc.system(model), model)
    ref, m_ref = reference.result, reference.metrics
    rt = run_realtime(kernel, sc)
    _, m_rt = analyse_run(rt, sc.clutch)
    out = {"status": rt.status, "steps": int(rt.t.size)}
    for key in ("lockup_time_s", "jerk_peak_mps3", "slip_energy_J"):
        a, b = m_rt.get(key), m_ref.get(key)
        out[key] = {"realtime": a, "reference": b,
                    "relative_error": (None if a is None or b in (None, 0) else
                                       abs(a - b) / abs(b))}
    if "omega_engine" in rt.signals:
        w_ref = np.interp(rt.t, ref.t, ref["omega_engine"])
        out["engine_speed_max_error_rpm"] = float(np.max(np.abs(rt["omega_engine"] - w_ref))
                                                  * 30.0 / math.pi)
    warnings = []
    if rt.status != ref.status:
        warnings.append(f"the kernel's run {rt.status}, the variable-step run {ref.status}")
    for key, limit in AGREEMENT.items():
        v = out.get(key)
        err = v.get("relative_error") if isinstance(v, dict) else v
        if isinstance(v, dict) and (v["realtime"] is None) != (v["reference"] is None):
            warnings.append(f"{key}: {v['realtime']} in the kernel's run, {v['reference']} "
                            "in the variable-step run")
        elif err is not None and err > limit:
            warnings.append(f"{key}: {'relative error' if isinstance(v, dict) else 'error'} "
                            f"{err:.3g} against the variable-step run exceeds {limit:g} (a "
                            "shorter --step follows it closer)")
    out["warnings"] = warnings
    return out
