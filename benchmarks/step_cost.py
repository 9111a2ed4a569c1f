"""Where one integrator step's time goes, for the LuGre rig and the default launch.

For each plant the integrator runs the problem (medians of ``--repeats`` runs after a
warm-up); then each piece of work a step does is timed alone in a compiled loop at a state
of the run: a right-hand side, the event functions, the plant's exact Jacobian (or the
finite-difference one it replaces), one inversion of ``I/(γh) − J`` (its leading block, at
the plant's Jacobian at that state, γh = 1 ms; counted as ``lu_decompositions``) and one
stage solve (a matrix–vector product with that inverse).  A plant with its own factors of
``I/(γh) − J`` (the network plants' straight-line elimination,
:mod:`clutchsim.network.elimination`) has those timed as well (``factor_ns``,
``factor_solve_ns``), and the breakdown counts them instead of the dense inverse.  The counts of the run
(right-hand sides, event evaluations, Jacobians, inversions, stage solves) times these costs
give the real work; the rest of the integrator's time is the step loop's own bookkeeping
(controller, error norm, stage combinations, dense output, output rows, event brackets).

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numba
import numpy as np
from _common import c_function_values, emit

from clutchsim.core.cengine import dense_linalg
from clutchsim.core.methods import get_method
from clutchsim.core.system import call_jac, has_jacobian, plant_functions


@numba.njit(inline="always")
def _a(x):
    return np.int64(x.ctypes.data)


@numba.njit
def _loop_rhs(f, n, t, y, u, p, out):
    s = 0.0
    for _ in range(n):
        y[0] += 1e-14
        f(t, _a(y), _a(u), _a(p), _a(out))
        s += out[0] if out.size else 0.0
    return s


@numba.njit
def _loop_factor(f, n, c, J, F):
    s = 0
    for _ in range(n):
        J[0, 0] += 1e-14
        s += f(c, _a(J), J.shape[1], _a(F))
    return s


@numba.njit
def _loop_factor_solve(f, n, F, b, X):
    for _ in range(n):
        b[0] += 1e-14
        f(_a(F), _a(b), _a(X), X.shape[1], 0)
    return X[0, 0]


@numba.njit
def _loop_jac(f, n, t, y, u, p, J):
    for _ in range(n):
        y[0] += 1e-14
        f(t, _a(y), _a(u), _a(p), _a(J), J.shape[1])
    return J[0, 0]


@numba.njit
def _loop_inverse(invert, J, n, M, piv, nd):
    # the engine's own inverse (engine.c), called through its address as the step calls it
    s = 0.0
    m = J.shape[0]
    for _ in range(n):
        J[0, 0] += 1e-14
        invert(np.int64(J.ctypes.data), 1.0e3, np.int64(M.ctypes.data),
               np.int64(piv.ctypes.data), m, nd)
        s += M[0, 0]
    return s


@numba.njit
def _loop_solve(solve, M, b, X, n, nd):
    m = M.shape[0]
    for _ in range(n):
        b[0] += 1e-14
        solve(np.int64(M.ctypes.data), np.int64(b.ctypes.data), np.int64(X.ctypes.data), 0,
              m, nd)
    return X[0, 0]


def _best_ns(fn, args, n):
    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        fn(*args)
        best = min(best, time.perf_counter() - t0)
    return best / n * 1e9


def _costs(system, y, u, n=100_000):
    tag, p = system.tag, system.params
    fns = plant_functions(tag)
    cf = c_function_values(system)     # the C functions, as the engine calls them
    ns = system.n_states
    nd = ns - system.quadratures
    out = {}
    dy = np.empty(ns)
    _loop_rhs(cf["rhs"], 10, 0.5, y.copy(), u, p, dy)
    out["rhs_ns"] = _best_ns(_loop_rhs, (cf["rhs"], n, 0.5, y.copy(), u, p, dy), n)
    g = np.empty(system.n_events)
    if system.n_events:
        _loop_rhs(cf["events"], 10, 0.5, y.copy(), u, p, g)
        out["events_ns"] = _best_ns(_loop_rhs, (cf["events"], n, 0.5, y.copy(), u, p, g), n)
    else:
        out["events_ns"] = 0.0
    J = np.zeros((ns, ns))
    if has_jacobian(tag):
        _loop_jac(cf["jac"], 10, 0.5, y.copy(), u, p, J)
        out["jacobian_ns"] = _best_ns(_loop_jac, (cf["jac"], n, 0.5, y.copy(), u, p, J), n)
    else:   # forward differences: nd right-hand sides
        out["jacobian_ns"] = nd * out["rhs_ns"]
    out["jacobian_kind"] = "exact" if has_jacobian(tag) else "finite differences"
    # the inverse at the plant's own Jacobian (the elimination skips zero multipliers, so
    # a random dense matrix would overstate it), for a step with gamma*h = 1 ms
    if has_jacobian(tag):
        call_jac(tag, 0.5, y, u, p, J)
    else:
        J = np.random.default_rng(1).normal(size=(ns, ns))
        J[:, nd:] = 0.0
    M = np.empty((ns, ns))
    piv = np.empty(ns, dtype=np.int64)
    b = np.ones(ns)
    X = np.empty((1, ns))
    invert, solve = dense_linalg()
    _loop_inverse(invert, J, 10, M, piv, nd)
    out["inverse_ns"] = _best_ns(_loop_inverse, (invert, J, n, M, piv, nd), n)
    _loop_solve(solve, M, b, X, 10, nd)
    out["solve_ns"] = _best_ns(_loop_solve, (solve, M, b, X, n, nd), n)
    out["linear_solver"] = "dense inverse"
    if fns.factor_size:
        F = np.empty(fns.factor_size)
        if _loop_factor(cf["factor"], 10, 1e3, J, F) == 10:
            out["factor_ns"] = _best_ns(_loop_factor, (cf["factor"], n, 1e3, J, F), n)
            _loop_factor_solve(cf["solve"], 10, F, b, X)
            out["factor_solve_ns"] = _best_ns(_loop_factor_solve, (cf["solve"], n, F, b, X),
                                              n)
            out["linear_solver"] = "plant's factors"
    return out


def _breakdown(name, run, system, y, u, method, repeats):
    run()
    walls = []
    for _ in range(repeats):
        res = run()
        walls.append(res.stats.wall_s)
    st = res.stats
    c = _costs(system, y, u)
    stages = get_method(method).stages
    attempts = st.steps + st.rejected
    work = {"rhs": st.rhs_evals * c["rhs_ns"], "events": st.event_evals * c["events_ns"],
            # a finite-difference Jacobian's right-hand sides are counted in rhs_evals
            "jacobian": st.jacobians * c["jacobian_ns"] if c["jacobian_kind"] == "exact"
            else 0.0,
            "inverse": st.lu_decompositions * c.get("factor_ns", c["inverse_ns"]),
            "solves": attempts * stages * c.get("factor_solve_ns", c["solve_ns"])}
    total_ns = statistics.median(walls) * 1e9
    per_step = {k: v / st.steps for k, v in work.items()}
    per_step["bookkeeping"] = (total_ns - sum(work.values())) / st.steps
    return {**accounts(st, stages, system, c["jacobian_kind"]), "case": name, "method": method, "integrator_ms": total_ns / 1e6, "steps": st.steps,
            "rejected": st.rejected, "rhs_evals": st.rhs_evals,
            "rhs_per_step": st.rhs_evals / st.steps, "event_evals": st.event_evals,
            "event_evals_per_step": st.event_evals / st.steps, "jacobians": st.jacobians,
            "lu": st.lu_decompositions, **c, "ns_per_step": total_ns / st.steps,
            "ns_per_step_by_part": per_step}


def accounts(st, stages, system, jacobian_kind):
    """Where the right-hand sides and event evaluations of a Rosenbrock run come from.

    Every attempted step evaluates ``stages - 1`` stages (the first stage is the f at the
    step's start); every Jacobian brings the time derivative df/dt by one forward
    difference (and, differenced, one right-hand side per implicit state); every accepted
    step evaluates f at its end (the next step's first stage and the Hermite slope).  The
    rest are the f at the start, the initial-step probe and the restarts after breakpoints
    and state-changing events.  Events (if the plant has any): every accepted step ends with
    one evaluation and every located event with one at its root; the rest are samples inside steps (3 per
    sampled step) and the regula-falsi probes of event location."""
    nd = system.n_states - system.quadratures
    per_jac = 1 + (nd if jacobian_kind != "exact" else 0)
    rhs = {"stages": (st.steps + st.rejected) * (stages - 1),
           "time_derivative_and_jacobian": st.jacobians * per_jac,
           "step_ends": st.steps}
    rhs["start_and_restarts"] = st.rhs_evals - sum(rhs.values())
    ev = {"step_ends": st.steps if system.n_events else 0, "at_located_events": st.events}
    ev["samples_and_location"] = st.event_evals - sum(ev.values())
    return {"rhs_by_source": rhs, "event_evals_by_source": ev}


def rig_case(repeats):
    from clutchsim.core import SolverOptions
    from clutchsim.friction import make_model
    from clutchsim.rig import make_rig, run_rig
    model = make_model("lugre")
    opts = SolverOptions(rtol=1e-6, atol=1e-9, dt_out=0.01)

    def run():
        return run_rig(model, 30.0, force=0.0, spring=2.0, pull_speed=0.1, options=opts)
    res = run()
    system = make_rig(model, spring=2.0, pull_speed=0.1)
    i = res.t.size // 2
    y = np.array([res[s][i] for s in system.state_names])
    u = np.array([res[s][i] for s in system.input_names])
    return _breakdown("LuGre stick-slip (core_speed), rtol 1e-6", run, system, y, u, "rodas4",
                      repeats)


def launch_case(repeats):
    from clutchsim.scenario import load_scenario, run_scenario
    sc = load_scenario(None, overrides=["solver.wall_time=1000"])
    model = "mykhailevych2020"

    def run():
        return run_scenario(sc, model).result
    res = run()
    u0 = {name: float(np.asarray(sig(0.0)).ravel()[0]) for name, sig in sc.inputs.items()}
    system = sc.network(model).build(u0)
    i = int(np.searchsorted(res.t, 0.9))
    y = np.array([res[s][i] for s in system.state_names])
    u = np.array([res[s][i] for s in system.input_names])
    return _breakdown("default launch, model (6)", run, system, y, u, sc.solver, repeats)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=15)
    a = ap.parse_args(argv)
    rows = [rig_case(a.repeats), launch_case(a.repeats)]
    for r in rows:
        parts = ", ".join(f"{k} {v:.0f}" for k, v in r["ns_per_step_by_part"].items())
        print(f"{r['case']} ({r['method']}): {r['integrator_ms']:.2f} ms, {r['steps']} steps, "
              f"{r['ns_per_step']:.0f} ns/step = {parts}; {r['rhs_per_step']:.2f} RHS and "
              f"{r['event_evals_per_step']:.2f} event evaluations per step")
    emit({"rows": rows})


if __name__ == "__main__":
    main()
