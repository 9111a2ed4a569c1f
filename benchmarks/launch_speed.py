"""Speed of one default launch (model (6), mykhailevych2020) against scipy and CasADi.

Problem: the packaged passenger-car launch (examples/launch.toml: 5 inertias, two-stage
damper, gearbox, driveshaft, engine with idle governor, thermal nodes; 0–4 s) with friction
model (6) on the clutch, at the scenario's solver settings (RODAS5P, rtol = 3e-6,
atol = 1e-8, outputs every 2 ms).  Compared:

* clutchsim: ``run_scenario`` (the scenario's compiled method, with located events and resets);
* scipy ``solve_ivp`` RK45 and LSODA at the same rtol and atol on a hand-written
  plain-Python model of the same equations (``_launch_plain.py``: what a user without
  clutchsim would write; ``math`` only, no numba, no call into clutchsim while
  integrating).  Its clutch slip zero crossings are terminal scipy events; the reset of
  model (6) is applied between two ``solve_ivp`` calls and the integration restarts.
  ``--scipy-rhs compiled`` instead runs the baselines through clutchsim's scipy backend,
  which calls the plant's compiled right-hand side (scipy's per-step overhead only);
* CasADi CVODES and IDAS (``casadi.integrator``) at the same rtol and atol on the same
  equations in CasADi SX symbols (``_launch_casadi.py``: numbers from the same
  ``launch_params``), outputs on the 2 ms grid; the slip zero crossings are found by a
  sign change between grid points, located to 1e-10 s on sub-integrations, model (6)'s
  reset is applied and the integration restarts (CasADi's own event support is
  experimental).  Each with SUNDIALS' defaults and with the BDF order capped at 2 (keys
  ``casadi_<solver>_bdf2_*``: orders 3-5 keep the locked clutch ringing at rtol 1e-6).  Optional: without casadi (>= 3.6, extra ``bench``) its keys are ``null``
  and ``casadi_note`` says why.

Validation (skipped with ``--no-check``; ``--check`` runs only this and exits 1 on failure):
the plain model and clutchsim both run at rtol = atol = 1e-8 (plain model: LSODA); the
engine, disc and wheel speeds must agree within 1 rpm on the 2 ms grid and the lock-up
times within 1 ms.  Keys ``check_*``.

Accuracy: ``max_abs_speed_diff_rpm`` is the largest difference of the engine, disc and
wheel speeds between clutchsim and the scipy baselines on the common 2 ms grid (all at the
benchmark tolerances); ``*_err_rpm`` is each run's largest speed error against the tight
clutchsim run of the validation, so the ratios can be read at known accuracy.

Matched accuracy: clutchsim also runs on a fixed tolerance ladder (``LADDER``: rtol, with
atol = rtol/100 as in the scenario), with the scenario's method and with the methods of
``LADDER_METHODS`` (method, step-size controller or None for the method's own, rtols).
For each baseline ``ratio_vs_<method>_matched`` uses the fastest rung whose speed error is
no larger than that baseline's error (all rungs are printed under ``ladder``;
``clutchsim_matched_<key>_method``/``_controller``/``_rtol`` name it), which is how the
targets "at matching results" are read.

``ratio_vs_casadi`` is the fastest CasADi run's time (``casadi_cvodes_ms``,
``casadi_idas_ms`` or their ``_bdf2`` variants; ``ratio_vs_casadi_solver`` names its key)
over clutchsim's at matched accuracy by the same rule (``ratio_vs_<key>_matched``).

``clutchsim_best_ms``: the rung matched to RK45 timed as the scenario's setting is, as
``run_scenario`` (median of ``BEST_REPEATS`` runs, alternated with the ``simulate`` runs
below so that both meet the same load), and ``ratio_vs_rk45_best``;
``clutchsim_best_simulate_ms`` and ``ratio_vs_rk45_best_simulate``: the same setting timed
as ``simulate`` alone, the work the baselines do (integration, events, output grid; plus
clutchsim's output signals and energy accounts), without the launch metrics
(``run_scenario`` adds their compiled kernel, ~0.23 ms, and the Python around it).

Timing: clutchsim in this process, median of ``--repeats`` runs after a warm-up (the
ladder's rungs: interleaved rounds, each rung timed warm once per round, median and minimum
of ``--repeats`` rounds, so that every rung meets the same load; see ``ladder_rows``); each
scipy and CasADi baseline in a child process, median of ``--scipy-repeats`` runs after a warm-up
run.  Every baseline run has a time limit of ``--scipy-timeout`` seconds; a baseline whose
first run does not finish is reported as ``null`` with ``scipy_<method>_lower_bound_ms``
(``casadi_<solver>_lower_bound_ms``; the limit) and ``ratio_vs_<method>_lower_bound``.
The CasADi symbols and integrators are built once per child before the runs and not
timed (``casadi_<solver>_build_ms``), as clutchsim's compiled code is cached.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from _common import emit, median_ms
from _launch_plain import SPEEDS, check, launch_params, simulate_plain, speed_diff_rpm

#: child name, key, method: keys ``scipy_<key>_*`` and ``ratio_vs_<key>*``
BASELINES = (("scipy-rk45", "rk45", "RK45"), ("scipy-lsoda", "lsoda", "LSODA"))
#: child name, key, CasADi integrator, its largest BDF order (None: SUNDIALS' 5): keys
#: ``<key>_*`` and ``ratio_vs_<key>*``.  Orders 3-5 are not A-stable and make the locked
#: clutch ring at rtol 1e-6 (~3-10x the slip crossings); order 2 is the tuned peer.
CASADI = (("casadi-cvodes", "casadi_cvodes", "cvodes", None),
          ("casadi-idas", "casadi_idas", "idas", None),
          ("casadi-cvodes-bdf2", "casadi_cvodes_bdf2", "cvodes", 2),
          ("casadi-idas-bdf2", "casadi_idas_bdf2", "idas", 2))
CASADI_MIN = (3, 6)
#: relative tolerances of the matched-accuracy ladder (atol = rtol/100)
LADDER = (1e-5, 5e-6, 3e-6, 1e-6, 5e-7, 3e-7, 1e-7)
#: further rungs on another method (the scenario's own is RODAS5P, which with the network
#: plant's exact Jacobian needs the fewest steps at a given accuracy)
LADDER_METHODS = (("ros34pw2", None, (1e-5, 3e-6, 1e-6, 3e-7)),
                  ("rodas5p", "I", (1e-5, 5e-6, 4e-6, 3e-6, 1e-6)))
MODEL = "mykhailevych2020"
#: runs of a rung per interleaved round of the ladder, the last one timed
BLOCK = 3


class _TimeLimit(Exception):
    """Raised in a child process when one baseline run exceeds its time limit."""


def _scenario(t_end: float, rtol: float | None = None, method: str | None = None,
              controller: str | None = None):
    from clutchsim.scenario import load_scenario
    tol = [] if rtol is None else [f"solver.rtol={rtol!r}", f"solver.atol={rtol * 1e-2!r}"]
    if method is not None:
        tol.append(f"solver.method={method!r}")
    if controller is not None:
        tol.append(f"solver.controller={controller!r}")
    return load_scenario(None, overrides=[f"scenario.t_end={t_end!r}",
                                          "solver.wall_time=100000", *tol])


def child(a) -> None:
    """One baseline: warm-up + ``scipy_repeats`` timed runs, one JSON line per run.

    Lines: ``{"build_ms": ..., "version": ...}`` first for a CasADi baseline (its symbols
    and integrators, built once and not timed), ``{"ms": ..., "warmup": bool}`` per
    finished run, ``{"timeout": s}`` when a run hits the limit, and a last
    ``{"done": true, ...}``; the speeds of the last run go to ``a.out`` (npz).
    """
    sc = _scenario(a.t_end)
    opts = sc.options
    if a.child in {c[0] for c in CASADI}:
        import casadi
        from _launch_casadi import build, simulate_casadi
        _, _, solver, order = next(c for c in CASADI if c[0] == a.child)
        m = build(launch_params(sc, MODEL), solver, opts.rtol, opts.atol, opts.dt_out,
                  max_order=order)
        print(json.dumps({"build_ms": m.build_s * 1e3, "version": casadi.__version__}),
              flush=True)

        def run():
            r = simulate_casadi(m)
            return r, r.t, {n: r[n] for n in SPEEDS}, r.status, r.nfev, len(r.events)
    elif a.scipy_rhs == "plain":
        method = {s: m for s, _, m in BASELINES}[a.child]
        par = launch_params(sc, MODEL)

        def run():
            r = simulate_plain(par, method, opts.rtol, opts.atol, opts.dt_out)
            return r, r.t, {n: r[n] for n in SPEEDS}, r.status, r.nfev, len(r.events)
    else:
        from clutchsim.scenario import run_scenario

        def run():
            res = run_scenario(sc, MODEL, solver=a.child).result
            return (res, res.t, {n: res[n] for n in SPEEDS}, res.status, res.stats.rhs_evals,
                    res.stats.events)

    def alarm(signum, frame):
        raise _TimeLimit

    signal.signal(signal.SIGALRM, alarm)
    out = None
    for i in range(a.scipy_repeats + 1):
        signal.setitimer(signal.ITIMER_REAL, a.scipy_timeout)
        t0 = time.perf_counter()
        try:
            out = run()
        except _TimeLimit:
            print(json.dumps({"timeout": a.scipy_timeout, "run": i}), flush=True)
            return
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0.0)
        print(json.dumps({"ms": (time.perf_counter() - t0) * 1e3, "warmup": i == 0}),
              flush=True)
    _, t, speeds, status, nfev, events = out
    np.savez(a.out, t=t, **speeds)
    print(json.dumps({"done": True, "status": status, "rhs_evals": int(nfev),
                      "events": int(events)}), flush=True)


def run_baseline(a, name: str):
    """Run baseline ``name`` in a child process; parse its lines.

    Returns
    -------
    info : dict
        ``times_ms`` (timed runs), ``timeout`` (limit hit, or None), ``done`` line, ``note``,
        ``build`` line (CasADi only).
    speeds : dict or None
        ``t`` and the speeds of the last run.
    """
    # the per-run limit is enforced in the child; this is only a backstop (+ set-up time)
    backstop = a.scipy_timeout * (a.scipy_repeats + 1) + 600.0
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "speeds.npz")
        cmd = [sys.executable, os.path.abspath(__file__), "--child", name,
               "--scipy-rhs", a.scipy_rhs, "--scipy-repeats", str(a.scipy_repeats),
               "--t-end", repr(a.t_end), "--scipy-timeout", repr(a.scipy_timeout),
               "--out", out]
        note = ""
        try:
            done = subprocess.run(cmd, capture_output=True, text=True, timeout=backstop,
                                  check=False)
            text, err, rc = done.stdout, done.stderr, done.returncode
        except subprocess.TimeoutExpired as exc:
            text = exc.stdout or ""
            text = text.decode() if isinstance(text, bytes) else text
            err, rc = "", 0
            note = f"child killed after {backstop:g} s"
        info = {"times_ms": [], "timeout": None, "done": None, "note": note, "build": None}
        for line in text.splitlines():
            try:
                rec = json.loads(line)
            except json.JSONDecodeError:
                continue
            if "ms" in rec and not rec["warmup"]:
                info["times_ms"].append(rec["ms"])
            elif "timeout" in rec:
                info["timeout"] = rec["timeout"]
                info["note"] = (f"run {rec['run'] + 1} did not finish within "
                                f"{rec['timeout']:g} s")
            elif rec.get("done"):
                info["done"] = rec
            elif "build_ms" in rec:
                info["build"] = rec
        if rc != 0 and not info["note"]:
            last = err.strip().splitlines()[-1] if err.strip() else f"exit code {rc}"
            info["note"] = "failed: " + last
        speeds = dict(np.load(out)) if info["done"] else None
    return info, speeds


def baseline_row(a, out: dict, name: str, prefix: str, key: str, ctx: dict) -> float | None:
    """Run baseline ``name`` in a child and write its keys into ``out``.

    Keys ``<prefix>_ms`` (median), ``_runs``, ``_status``, ``_rhs_evals``, ``_events``,
    ``_note``, ``_lower_bound_ms`` (time limit hit), ``_err_rpm`` (against the tight run),
    ``_build_ms`` (CasADi), ``ratio_vs_<key>`` (its time over clutchsim's at the benchmark
    tolerances), ``ratio_vs_<key>_matched`` and ``clutchsim_matched_<key>_rtol`` (the fastest
    ladder rung with a speed error no larger than the baseline's), ``ratio_vs_<key>_lower_bound``
    and ``max_abs_speed_diff_rpm_<key>``.

    Parameters
    ----------
    ctx : dict
        ``ms`` (clutchsim's time), ``ref`` (its result), ``dt`` (output interval [s]),
        ``err`` (``err(t, speeds)`` -> error against the tight run [rpm], or None).

    Returns
    -------
    float or None
        The baseline's largest speed difference from clutchsim [rpm] (None: no speeds).
    """
    info, sp = run_baseline(a, name)
    times, ms = info["times_ms"], ctx["ms"]
    if info["build"]:
        out[f"{prefix}_build_ms"] = info["build"]["build_ms"]
    if info["note"]:
        out[f"{prefix}_note"] = info["note"]
        print(f"{name}: {info['note']}", file=sys.stderr)
    if not times:
        out[f"{prefix}_ms"] = None
        out[f"ratio_vs_{key}"] = None
        if info["timeout"] is not None:
            out[f"{prefix}_lower_bound_ms"] = info["timeout"] * 1e3
            out[f"ratio_vs_{key}_lower_bound"] = info["timeout"] * 1e3 / ms
        return None
    out[f"{prefix}_ms"] = statistics.median(times)
    out[f"{prefix}_runs"] = len(times)
    out[f"ratio_vs_{key}"] = out[f"{prefix}_ms"] / ms
    if sp is None:
        return None
    done = info["done"]
    out[f"{prefix}_status"] = done["status"]
    out[f"{prefix}_rhs_evals"] = done["rhs_evals"]
    out[f"{prefix}_events"] = done["events"]
    d = speed_diff_rpm(ctx["ref"].t, ctx["ref"], sp["t"], sp, ctx["dt"])
    out[f"max_abs_speed_diff_rpm_{key}"] = max(d[n] for n in SPEEDS)
    if ctx["err"] is not None:
        out[f"{prefix}_err_rpm"] = e_b = ctx["err"](sp["t"], sp)
        ok = [r for r in out["ladder"] if r["err_rpm"] <= e_b]
        if ok:
            best = min(ok, key=lambda r: r["ms"])
            out[f"ratio_vs_{key}_matched"] = out[f"{prefix}_ms"] / best["ms"]
            out[f"clutchsim_matched_{key}_rtol"] = best["rtol"]
            out[f"clutchsim_matched_{key}_method"] = best["method"]
            out[f"clutchsim_matched_{key}_controller"] = best["controller"]
        else:
            out[f"ratio_vs_{key}_matched"] = None
    return out[f"max_abs_speed_diff_rpm_{key}"]


def casadi_missing() -> str | None:
    """Why the CasADi baselines cannot run (None: casadi >= 3.6 is installed)."""
    try:
        version = importlib.metadata.version("casadi")
    except importlib.metadata.PackageNotFoundError:
        return "casadi is not installed (optional extra 'bench': pip install -e '.[bench]')"
    parts = tuple(int(p) for p in version.split(".")[:2] if p.isdigit())
    if parts < CASADI_MIN:
        return (f"casadi {version} is installed; the baselines need "
                f"{'.'.join(map(str, CASADI_MIN))} or newer (integrator with t0 and a grid)")
    return None


def casadi_rows(a, out: dict, ctx: dict) -> None:
    """The CasADi CVODES and IDAS baselines (:data:`CASADI`) and ``ratio_vs_casadi``.

    ``ratio_vs_casadi`` is the fastest CasADi run's time over clutchsim's at matched
    accuracy (``ratio_vs_<key>_matched`` of that run; ``ratio_vs_casadi_solver`` names its
    key).  Without casadi every CasADi key is ``null`` and ``casadi_note`` says why.
    """
    why = casadi_missing()
    if why is not None:
        for _, key, _, _ in CASADI:
            out[f"{key}_ms"] = out[f"ratio_vs_{key}"] = None
        out.update(casadi_note=why, casadi_version=None, ratio_vs_casadi=None,
                   ratio_vs_casadi_solver=None)
        print(f"casadi baselines skipped: {why}", file=sys.stderr)
        return
    out["casadi_version"] = importlib.metadata.version("casadi")
    for name, key, _, _ in CASADI:
        baseline_row(a, out, name, key, key, ctx)
    timed = [(out[f"{key}_ms"], key) for _, key, _, _ in CASADI if out[f"{key}_ms"] is not None]
    out["ratio_vs_casadi"] = out["ratio_vs_casadi_solver"] = None
    if not timed:
        out["casadi_note"] = "no CasADi run finished"
    elif ctx["err"] is None:
        out["casadi_note"] = "no matched ratio without the validation run (--no-check)"
    else:
        _, key = min(timed)
        out["ratio_vs_casadi_solver"] = key
        out["ratio_vs_casadi"] = out.get(f"ratio_vs_{key}_matched")
        if out["ratio_vs_casadi"] is None:
            out["casadi_note"] = (f"no clutchsim ladder rung is as accurate as {key} "
                                  f"({out[f'{key}_err_rpm']:.3g} rpm)")


def ladder_rows(rungs, t_end: float, repeats: int, err) -> list[dict]:
    """Time the ladder's rungs (``(method or None, controller or None, rtol)``) interleaved:
    a warm-up run of each, then ``repeats`` rounds; in a round each rung runs ``BLOCK``
    times back to back and the last run is timed (a rung's first run after another rung's
    was slower: a loop median of 3.43 against 2.57 ms alone, in one measurement).  A
    rung's ``ms`` is its median over the rounds (what the baselines report), ``ms_min`` its
    minimum.  Rungs a few per cent apart, timed one after another, were ordered by the load
    of the moment, which picked the matched rung by chance; interleaved, every rung meets
    the same load."""
    from clutchsim.scenario import run_scenario
    scs = [_scenario(t_end, rtol, method, ctrl) for method, ctrl, rtol in rungs]
    last = [run_scenario(sc_r, MODEL) for sc_r in scs]
    times = [[] for _ in rungs]
    for _ in range(repeats):
        for k, sc_r in enumerate(scs):
            for _ in range(BLOCK - 1):
                run_scenario(sc_r, MODEL)
            t0 = time.perf_counter()
            last[k] = run_scenario(sc_r, MODEL)
            times[k].append((time.perf_counter() - t0) * 1e3)
    return [{"method": sc_r.solver, "controller": ctrl or "default", "rtol": rtol,
             "ms": statistics.median(ms_r), "ms_min": min(ms_r),
             "err_rpm": err(lr_r.result.t, lr_r.result), "steps": lr_r.result.stats.steps}
            for (_, ctrl, rtol), sc_r, ms_r, lr_r in zip(rungs, scs, times, last, strict=True)]


#: runs behind each median of the best rung (they take milliseconds; a median of 5 moved by
#: up to 1.5x between processes on the project machine)
BEST_REPEATS = 21


def best_row(a, out: dict) -> None:
    """The rung matched to RK45, timed as the scenario's own setting is (median of
    ``BEST_REPEATS`` runs after a warm-up): ``clutchsim_best_ms`` and
    ``ratio_vs_rk45_best`` (RK45's median over it).  The ladder's interleaved rounds are
    fair between rungs but not how a user runs one setting.  Also
    ``clutchsim_best_simulate_ms``: the same setting timed as ``simulate``, alternated with
    the ``run_scenario`` runs (the integration, events and output grid the baselines also
    compute, with clutchsim's output signals and energy accounts, without the launch
    metrics), and its ``ratio_vs_rk45_best_simulate``."""
    from clutchsim.scenario import run_scenario
    if out.get("clutchsim_matched_rk45_rtol") is None or not out.get("scipy_rk45_ms"):
        return
    ctrl = out["clutchsim_matched_rk45_controller"]
    sc = _scenario(a.t_end, out["clutchsim_matched_rk45_rtol"],
                   out["clutchsim_matched_rk45_method"], None if ctrl == "default" else ctrl)
    repeats = max(a.repeats, BEST_REPEATS)
    # the work the baselines do: the integration with its events and output grid (and
    # clutchsim's output signals and energy accounts), without the launch metrics
    from clutchsim.core import simulate
    system = sc.system(MODEL)
    inputs = {n: sc.inputs[n] for n in system.input_names}

    def sim():
        return simulate(system, (0.0, sc.t_end), inputs, solver=sc.solver, options=sc.options)
    # alternated, so that both meet the same load (timed one after the other, one run had
    # run_scenario at 3.42 ms and simulate at 2.04 ms: 1.4 ms apart, where the metrics
    # take ~0.45 ms)
    times: dict = {"run": [], "sim": []}
    for fn in (lambda: run_scenario(sc, MODEL), sim):
        fn()
    for _ in range(repeats):
        for key, fn in (("run", lambda: run_scenario(sc, MODEL)), ("sim", sim)):
            t0 = time.perf_counter()
            fn()
            times[key].append((time.perf_counter() - t0) * 1e3)
    ms, ms_sim = statistics.median(times["run"]), statistics.median(times["sim"])
    out["clutchsim_best_ms"] = ms
    out["ratio_vs_rk45_best"] = out["scipy_rk45_ms"] / ms
    out["clutchsim_best_simulate_ms"] = ms_sim
    out["ratio_vs_rk45_best_simulate"] = out["scipy_rk45_ms"] / ms_sim
    out["clutchsim_best_repeats"] = repeats


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="clutchsim runs (after a warm-up)")
    ap.add_argument("--scipy-repeats", type=int, default=5,
                    help="runs of each scipy and CasADi baseline (after a warm-up run)")
    ap.add_argument("--t-end", type=float, default=4.0, help="end time [s]")
    ap.add_argument("--scipy-rhs", choices=("plain", "compiled"), default="plain",
                    help="plain: hand-written Python model (default); compiled: clutchsim's "
                         "scipy backend on the plant's compiled right-hand side")
    ap.add_argument("--scipy-timeout", type=float, default=600.0,
                    help="time limit of each scipy and CasADi run [s]")
    ap.add_argument("--check", action="store_true",
                    help="only validate the plain model against clutchsim (exit 1 on failure)")
    ap.add_argument("--no-check", action="store_true", help="skip the validation")
    ap.add_argument("--child", choices=[b[0] for b in BASELINES + CASADI],
                    help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        child(a)
        return
    if a.check:
        rep = check("LSODA", 1e-8, 1e-8, t_end=a.t_end)
        emit(rep)
        sys.exit(0 if rep["ok"] else 1)
    from clutchsim.scenario import run_scenario
    sc = _scenario(a.t_end)
    ms, lr = median_ms(lambda: run_scenario(sc, MODEL), repeats=a.repeats)
    ref = lr.result
    dt = sc.options.dt_out
    out = {"problem": f"default launch, model (6), 0-{a.t_end:g} s, rtol={sc.options.rtol:g}, "
                      f"atol={sc.options.atol:g}",
           "clutchsim_ms": ms, "clutchsim_runs": a.repeats, "clutchsim_status": ref.status,
           "clutchsim_rhs_evals": ref.stats.rhs_evals, "clutchsim_events": ref.stats.events,
           "scipy_rhs": a.scipy_rhs, "scipy_timeout_s": a.scipy_timeout}
    tight = None
    if not a.no_check:
        rep, tight, _ = check("LSODA", 1e-8, 1e-8, t_end=a.t_end, return_runs=True)
        out.update(check_ok=rep["ok"], check_method="LSODA rtol=atol=1e-8",
                   check_max_abs_speed_diff_rpm=rep["max_abs_speed_diff_rpm"],
                   check_lockup_time_s=rep["lockup_time_s"],
                   check_lockup_diff_s=rep["lockup_diff_s"],
                   check_first_slip_zero_diff_s=rep["first_slip_zero_diff_s"],
                   check_rhs_rel_mismatch=rep["rhs_rel_mismatch"])
        if not rep["ok"]:
            print("validation of the plain model FAILED: " + json.dumps(rep), file=sys.stderr)

    def err(t, sp):
        d = speed_diff_rpm(tight.t, tight, t, sp, dt)
        return max(d[n] for n in SPEEDS)
    if tight is not None:
        out["clutchsim_err_rpm"] = err(ref.t, ref)
        rungs = ([(None, None, r) for r in LADDER]
                 + [(m, c, r) for m, c, rs in LADDER_METHODS for r in rs])
        out["ladder"] = ladder_rows(rungs, a.t_end, a.repeats, err)
    ctx = {"ms": ms, "ref": ref, "dt": dt, "err": err if tight is not None else None}
    diffs = [baseline_row(a, out, name, f"scipy_{key}", key, ctx) for name, key, _ in BASELINES]
    diffs = [d for d in diffs if d is not None]
    out["max_abs_speed_diff_rpm"] = max(diffs) if diffs else None
    casadi_rows(a, out, ctx)
    best_row(a, out)
    emit(out)


if __name__ == "__main__":
    main()
