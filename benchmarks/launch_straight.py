"""The default launch on a straight-line plant with an exact Jacobian (a prototype of the
generated network plant, ``_launch_straight.py``) against today's chain plant, in one run.

Rows: the chain plant at the scenario's settings (ROS34PW2, rtol 1e-6), and the prototype
with ROS34PW2 (differenced Jacobian, as the CEO's measurement in numerics-notes), RODAS4 and
RODAS5P (exact Jacobian) on a tolerance ladder.  Error: the largest engine, disc and wheel
speed difference [rpm] on the shared 2 ms output grid against the chain plant at rtol 1e-10.
Time: the integrator's own wall time, median of ``--repeats`` runs after a warm-up.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np
from _common import emit
from _launch_plain import SPEEDS, launch_params
from _launch_straight import build

from clutchsim.core import SolverOptions, simulate

MODEL = "mykhailevych2020"


def _err_rpm(res, ref, names):
    out = 0.0
    for ours, theirs in zip(names, SPEEDS):
        i = np.clip(np.searchsorted(ref.t, res.t), 0, ref.t.size - 1)
        same = np.abs(ref.t[i] - res.t) <= 1e-9
        out = max(out, float(np.max(np.abs(res[ours][same] - ref[theirs][i[same]]))))
    return out * 30.0 / np.pi


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=15)
    a = ap.parse_args(argv)
    from clutchsim.driveline.run import run_scenario
    from clutchsim.scenario import load_scenario
    sc = load_scenario(None, overrides=["solver.wall_time=1000"])
    ref = run_scenario(load_scenario(None, overrides=["solver.rtol=1e-10", "solver.atol=1e-12",
                                                      "solver.wall_time=1000"]), MODEL).result
    chain = sc.chain(MODEL)
    names = {"omega_engine": f"omega_{chain.inertias[0].name}",
             "omega_disc": f"omega_{chain.inertias[1].name}",
             "omega_wheels": f"omega_{chain.inertias[4].name}"}
    par = launch_params(sc, MODEL)
    inputs = {"throttle": sc.inputs[chain.engine.throttle],
              "command": sc.inputs[chain.couplings[0].command]}
    rows = []

    def timed(label, run, speed_names):
        run()
        walls = []
        for _ in range(a.repeats):
            res = run()
            walls.append(res.stats.wall_s)
        st = res.stats
        rows.append({"case": label, "outcome": str(res.outcome),
                     "integrator_ms": round(statistics.median(walls) * 1e3, 3),
                     "steps": st.steps, "rhs_evals": st.rhs_evals, "jacobians": st.jacobians,
                     "event_evals": st.event_evals,
                     "speed_error_rpm": round(_err_rpm(res, ref, speed_names), 4)})
        print(rows[-1])

    chain_names = [names[s] for s in SPEEDS]
    timed(f"chain plant, {sc.solver}, rtol 1e-6", lambda: run_scenario(sc, MODEL).result,
          chain_names)
    for method, exact, ladder in (("ros34pw2", False, (1e-6,)),
                                  ("rodas4", True, (1e-6, 3e-6, 1e-5)),
                                  ("rodas5p", True, (1e-6, 3e-6, 1e-5))):
        system = build(par, exact=exact)
        for rtol in ladder:
            opts = SolverOptions(rtol=rtol, atol=rtol / 100, dt_out=0.002, wall_time=1000.0)
            timed(f"straight-line, {method}, {'exact' if exact else 'differenced'} Jacobian, "
                  f"rtol {rtol:g}",
                  lambda system=system, opts=opts, method=method: simulate(
                      system, (0.0, par.t_end), inputs, solver=method, options=opts),
                  list(SPEEDS))
    emit({"rows": rows})


if __name__ == "__main__":
    main()
