"""Speed of the compiled core on LuGre stick-slip, against scipy in the same run.

Problem: LuGre (Canudas de Wit et al. 1995, Table I), m = 1 kg on the friction contact,
spring k = 2 N/m whose free end moves at 0.1 m/s, 0–30 s, from rest.  Compared:

* clutchsim: the rig plant with the compiled RODAS4 integrator;
* scipy ``solve_ivp`` RK45 and LSODA with a plain-Python right-hand side of the same
  equations (what a user would write);

scipy at rtol = 1e-6, atol = 1e-8; clutchsim at rtol = 1e-6, atol = 1e-9 (the bristle state
z is of order 1e-5 m, so atol = 1e-8 would leave it loosely controlled); medians of 5 runs
after a warm-up.  Accuracy: the maximum deviation of the spring force from a tight reference
(scipy Radau, rtol = 1e-11) on a 10 ms grid; the comparison is only fair if clutchsim's error
is not larger than scipy's, which the output shows.  Cold start: a second fresh process (numba's on-disk cache warm) timed from interpreter
start to the first result.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from _common import emit, fresh_process_seconds, median_ms

M, K, V = 1.0, 2.0, 0.1
S0, S1, S2, FC, FS, VS = 1e5, math.sqrt(1e5), 0.4, 1.0, 1.5, 1e-3
T_END, RTOL, ATOL = 30.0, 1e-6, 1e-8
CS_ATOL = 1e-9
GRID = np.linspace(0.0, T_END, 3001)


def lugre_rhs(t, y):
    x, v, z = y
    g = FC + (FS - FC) * math.exp(-(v / VS) ** 2)
    dz = v - S0 * abs(v) * z / g
    f = S0 * z + S1 * dz + S2 * v
    return [v, (K * (V * t - x) - f) / M, dz]


def scipy_run(method, rtol=RTOL, atol=ATOL):
    sol = solve_ivp(lugre_rhs, (0.0, T_END), [0.0, 0.0, 0.0], method=method, rtol=rtol,
                    atol=atol, dense_output=True)
    x = sol.sol(GRID)[0]
    return K * (V * GRID - x)


def clutchsim_run():
    from clutchsim.core import SolverOptions
    from clutchsim.friction import make_model
    from clutchsim.rig import run_rig
    res = run_rig(make_model("lugre"), T_END, force=0.0, spring=K, pull_speed=V, mass=M,
                  options=SolverOptions(rtol=RTOL, atol=CS_ATOL, dt_out=0.01))
    assert res.status == "completed", res.message
    return res


COLD = """
import time
t0 = time.perf_counter()
from clutchsim.core import SolverOptions
from clutchsim.friction import make_model
from clutchsim.rig import run_rig
res = run_rig(make_model("lugre"), 30.0, force=0.0, spring=2.0, pull_speed=0.1,
              options=SolverOptions(rtol=1e-6, atol=1e-9, dt_out=0.01))
assert res.status == "completed"
print(time.perf_counter() - t0)
"""


def main():
    first_process_s = fresh_process_seconds(COLD)      # may compile (cold numba cache)
    cold_start_s = fresh_process_seconds(COLD)         # cache warm: what users see
    ref = scipy_run("Radau", rtol=1e-11, atol=1e-13)
    cs_ms, res = median_ms(clutchsim_run)
    cs_force = np.interp(GRID, res.t, res["F_spring"])
    rk_ms, rk_force = median_ms(lambda: scipy_run("RK45"), repeats=5, warmup=1)
    ls_ms, ls_force = median_ms(lambda: scipy_run("LSODA"), repeats=5, warmup=1)
    err = {name: float(np.abs(f - ref).max()) for name, f in
           (("clutchsim", cs_force), ("scipy_rk45", rk_force), ("scipy_lsoda", ls_force))}
    emit({
        "problem": "LuGre stick-slip, Table I, m=1 kg, k=2 N/m, 0.1 m/s, 0-30 s",
        "clutchsim_ms": round(cs_ms, 3), "scipy_rk45_ms": round(rk_ms, 1),
        "scipy_lsoda_ms": round(ls_ms, 1), "ratio_vs_rk45": round(rk_ms / cs_ms, 1),
        "ratio_vs_lsoda": round(ls_ms / cs_ms, 1), "cold_start_s": round(cold_start_s, 3),
        "first_process_s": round(first_process_s, 3),
        "max_force_error_N": err, "steps": res.stats.steps, "rhs_evals": res.stats.rhs_evals,
    })


if __name__ == "__main__":
    main()
