"""Helpers of the FMU tests: the tubes an FMU run is compared in, FMPy runs (Model Exchange
and co-simulation), switch times, the energy balance, and the printed C against the
compiled plant on random states."""

import contextlib

import numpy as np

from clutchsim.fmu import CPlant, input_table

#: the tube every FMU run is compared in: max |FMU - clutchsim| / max(|clutchsim|, 1)
TUBE = 2e-3
#: switch times [s], FMU under FMPy against clutchsim.  FMPy's simulate_fmu sets the inputs
#: in CVode's root function only (not in its right-hand side), so within each internal step
#: the FMU sees the inputs of the step's start: CoupledClutches' 5 Hz torque input then
#: shifts clutch1's second stop by 1.1e-4 s (driven by scipy with the inputs set in the
#: right-hand side, the same FMU follows clutchsim to 3e-10, docs/fmu.md)
SWITCH_TOL = 3e-4
ENERGY = ("W_in", "W_friction", "W_damping", "W_road", "E_grade", "W_sync")


def fmpy():
    import fmpy as _fmpy
    return _fmpy


def tube(f, res, name, mask=None):
    ref = np.interp(f["time"], res.t, res[name])
    err = np.abs(f[name] - ref) / max(float(np.max(np.abs(res[name]))), 1.0)
    return float(np.max(err if mask is None else err[mask]))


def tube_tv(f, res, name, dt):
    """The tube with a width in time as well (as CSV-compare's): how far each FMU sample
    lies outside clutchsim's values within ``dt`` of its time, over the signal's range.
    For a signal that rings or jumps, where a shift by a fraction of a step is a large
    difference in value."""
    t, y = res.t, res[name]
    worst = 0.0
    for ti, xi in zip(f["time"], f[name]):
        lo_i, hi_i = np.searchsorted(t, ti - dt), np.searchsorted(t, ti + dt, side="right")
        vals = np.r_[y[lo_i:hi_i], np.interp([ti - dt, ti + dt], t, y)]
        worst = max(worst, float(vals.min()) - xi, xi - float(vals.max()))
    return worst / max(float(np.max(np.abs(y))), 1.0)


def energy_balance(f):
    resid = f["W_in"] - sum(f[k] for k in ENERGY[1:]) - (f["E_kinetic"] - f["E_kinetic"][0]) \
        - (f["E_spring"] - f["E_spring"][0])
    return abs(resid[-1]) / max(abs(f["W_in"][-1]), float(np.max(f["E_kinetic"])))


def _inputs(path):
    md = fmpy().read_model_description(str(path))
    return [v.name for v in md.modelVariables if v.causality == "input"]


@contextlib.contextmanager
def _inputs_in_rhs():
    """FMPy's CVode with the inputs set at every right-hand-side evaluation, as FMI's Model
    Exchange expects of an importer.  FMPy's own sets them only in CVode's root function
    (after each internal step and at the output points), so over a step the FMU sees the
    inputs of the step's start: a lag of one internal step, the largest error of a ramped
    input's run once CVode's steps grow (rtol 1e-6).  Only ``CVodeSolver.f`` changes;
    FMPy's ``simulate_fmu`` builds its solver from ``fmpy.sundials`` at each call."""
    from fmpy import sundials
    base = sundials.CVodeSolver

    class Solver(base):
        def f(self, t, y, ydot, user_data):
            self.input.apply(t)
            return base.f(self, t, y, ydot, user_data)

    sundials.CVodeSolver = Solver
    try:
        yield
    finally:
        sundials.CVodeSolver = base


def simulate(path, scenario, names, rtol, dt_out, record_events=False, inputs_in_rhs=False):
    """The FMU as Model Exchange under FMPy's CVode, fed the scenario's inputs (named:
    FMPy runs a file with both interfaces as co-simulation unless told); with
    ``inputs_in_rhs``, set at every right-hand-side evaluation (:func:`_inputs_in_rhs`)."""
    with _inputs_in_rhs() if inputs_in_rhs else contextlib.nullcontext():
        return fmpy().simulate_fmu(str(path), fmi_type="ModelExchange", solver="CVode",
                                   relative_tolerance=rtol, output_interval=dt_out,
                                   output=names, record_events=record_events,
                                   input=input_table(scenario, dt=dt_out / 2,
                                                     names=_inputs(path)))


def simulate_cs(path, scenario, names, rtol, dt_out):
    """The FMU as co-simulation under FMPy, a communication step every ``dt_out``."""
    return fmpy().simulate_fmu(str(path), fmi_type="CoSimulation", relative_tolerance=rtol,
                               output_interval=dt_out, output=names,
                               input=input_table(scenario, dt=dt_out, names=_inputs(path)))


def switches(f, element):
    """Times at which the FMU run switched ``element`` (its mode or lock flag changed
    between the two rows FMPy records at an event)."""
    t = f["time"]
    changed = (np.diff(f[f"{element}.mode"]) != 0) | (np.diff(f[f"{element}.locked"]) != 0)
    return t[1:][changed & (np.diff(t) == 0)]


def reset_times(res, element):
    """clutchsim's switches of ``element`` (its resets; a gear shift's excepted)."""
    return [e.t for e in res.events if e.name.startswith(f"{element}:") and e.t > 0.0
            and e.action == "reset" and "shift to gear" not in e.name]


def assert_same_switches(f, res, elements, tol=SWITCH_TOL, skip=()):
    """The FMU's switches of each element at clutchsim's times; ``skip``: windows
    ``(t0, t1)`` [s] left out on both sides."""
    def kept(ts):
        return [t for t in ts if not any(a <= t <= b for a, b in skip)]
    for el in elements:
        ours = kept(reset_times(res, el))
        theirs = kept(list(switches(f, el)))
        assert len(theirs) == len(ours), (el, theirs, ours)
        assert np.max(np.abs(np.array(theirs) - np.array(ours)), initial=0.0) <= tol, el


def random_states(system, rng, k=100):
    n = len(system.y0)
    for _ in range(k):
        y = system.y0 * (1.0 + 0.5 * rng.standard_normal(n)) + 3.0 * rng.standard_normal(n)
        yield y, rng.uniform(-0.2, 1.2, len(system.input_names)), rng.uniform(0.0, 4.0)


def rel(a, b):
    return float(np.max(np.abs(a - b) / (1.0 + np.abs(a)))) if np.size(a) else 0.0


def c_plant_difference(plan, system, k=100):
    """The worst relative difference between the printed C (:class:`CPlant`) and the
    compiled plant on ``k`` random states, times and inputs: right-hand side, outputs,
    event functions, the exact Jacobian and every reset map, both modes of each switching
    element.  Returns (the difference, the C plant, whether a locked state was seen)."""
    c = CPlant(plan)
    mod, p = plan.module, system.params
    n, no, ne = len(system.y0), len(system.output_names), len(system.event_names)
    rng = np.random.default_rng(7)
    worst = 0.0
    checked_lock = False
    locks = [s[:-len(".locked")] for s in system.state_names if s.endswith(".locked")]
    for y, u, t in random_states(system, rng, k):
        for el in locks:                        # both modes of each switching element
            ilk = system.state_names.index(f"{el}.locked")
            y[ilk] = float(rng.integers(0, 2))
            y[system.state_names.index(f"{el}.mode")] = 0.0 if y[ilk] else float(
                rng.choice([-1.0, 1.0]))
            checked_lock |= y[ilk] > 0.5
        for name, size in (("rhs", n), ("outputs", no), ("events", ne)):
            a, b = np.zeros(size), np.zeros(size)
            getattr(mod, name)(t, y, u, p, a)
            getattr(c, name)(t, y, u, p, b)
            assert np.all(np.isfinite(a))
            worst = max(worst, rel(a, b))
        A, B = np.zeros((n, n)), np.zeros((n, n))
        mod.jac(t, y, u, p, A)
        c.jac(t, y, u, p, B)
        worst = max(worst, rel(A, B))
        for k_ev in range(ne):
            ya, yb = y.copy(), y.copy()
            ra, rb = mod.reset(t, ya, u, p, k_ev), c.reset(t, yb, u, p, k_ev)
            assert ra == rb, (k_ev, ra, rb)
            worst = max(worst, rel(ya, yb))
    return worst, c, checked_lock or not locks


def simulate_cs_slopes(path, scenario, names, rtol, dt):
    """The FMI 2 co-simulation FMU driven by a master of our own that gives, with each
    communication step's inputs, their slopes over the step (``fmi2SetRealInputDerivatives``:
    the chord of the scenario's signal from ``t`` to just before ``t + dt``, exact for the
    piecewise-linear commands between breakpoints).  FMPy's ``simulate_fmu`` has the
    option (``set_input_derivatives``) but its buffer holds 9 derivatives whatever the FMU
    (FMPy 0.3.x, simulation.py: ``(value_type * 9)()``), so a 2-input FMU fails there."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    from clutchsim.scenario import resolve_scenario
    sc = resolve_scenario(scenario, None)
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    ins = [v.name for v in md.modelVariables if v.causality == "input"]
    sigs = [sc.inputs[n] for n in ins]
    u_vr = [vr[n] for n in ins]
    out_vr = [vr[n] for n in names]
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="m")
    fmu.instantiate()
    fmu.setupExperiment(tolerance=rtol, startTime=0.0)
    fmu.enterInitializationMode()

    def at(t):
        return [float(np.asarray(s(t)).ravel()[0]) for s in sigs]
    fmu.setReal(u_vr, at(0.0))
    fmu.exitInitializationMode()
    n = round(sc.t_end / dt)
    rows = [[0.0, *fmu.getReal(out_vr)]]
    for k in range(n):
        t, t1 = k * dt, (k + 1) * dt
        u0, u1 = at(t), at(np.nextafter(t1, -np.inf))
        fmu.setReal(u_vr, u0)
        fmu.setRealInputDerivatives(u_vr, [1] * len(u_vr),
                                    [(b - a) / dt for a, b in zip(u0, u1)])
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
        rows.append([t1, *fmu.getReal(out_vr)])
    fmu.terminate()
    fmu.freeInstance()
    data = np.array(rows)
    return {"time": data[:, 0], **{n: data[:, i + 1] for i, n in enumerate(names)}}
