"""The C engine against the numba loop: the same run, the same bits, their times.

``clutchsim.core.cengine`` runs plants printed as C through ``core/engine.c``, a
line-by-line C port of the numba loop (``core/_driver.py``); plants of numba functions take
the numba loop.  This script prepares a scenario's run as ``simulate`` does, checks that
both loops give the same output rows, events, counters and end, bit for bit (it stops
otherwise), and times them in the same process, interleaved, in thread CPU time: the
numba loop called from Python as ``simulate`` calls it (with the unboxing of its
arguments), and the engine through ``ctypes``.  Reported: the fastest call and the median
of ``--calls`` calls of each, their ratio, the run's counts, the CPU model.

Prints one JSON object on the last stdout line.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from _common import emit

from clutchsim.core import _driver as drv
from clutchsim.core import cengine
from clutchsim.core.simulate import _integrate, prepare_runs
from clutchsim.scenario import load_scenario

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "launch.toml"


def differences(ref, got) -> str:
    """'' when ``got`` (the engine's result) has the bits of ``ref`` (the numba loop's)."""
    names = ("status", "t_end", "info_k", "info_i", "t", "y", "u", "outputs", "ev_t", "ev_k",
             "ev_a", "stats", "h_smallest")
    out = []
    for name, r, g in zip(names, ref[:13], got[:13]):
        same = (r.shape == g.shape and np.array_equal(r, g, equal_nan=True)
                if isinstance(r, np.ndarray) else r == g)
        if not same:
            out.append(name)
    return ", ".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--calls", type=int, default=300, help="timed calls of each loop")
    ap.add_argument("--scenario", default=str(EXAMPLE))
    ap.add_argument("--model", default=None, help="friction model (default: the scenario's first)")
    args = ap.parse_args(argv)

    sc = load_scenario(args.scenario)
    model = args.model or (sc.models[0] if sc.models else None)
    system = sc.system(model)
    inputs = {n: sc.inputs[n] for n in system.input_names}
    prep = prepare_runs(system, (0.0, sc.t_end), inputs, solver=sc.solver, options=sc.options)
    engine = cengine.engine_for(prep.args)
    if engine is None:
        print("the C engine is not available for this plant or on this machine",
              file=sys.stderr)
        return 1
    p0 = system.params.copy()
    run_args = list(prep.args)
    run_args[6] = np.ascontiguousarray(system.y0, dtype=float)
    run_args[7] = p0.copy()
    run_args[13] = prep.args[13].copy()
    run_args = tuple(run_args)

    def numba_loop():
        run_args[7][:] = p0
        return _integrate(run_args, prep.fixed_key)

    def c_engine():
        run_args[7][:] = p0
        return engine(run_args)

    ref = numba_loop()
    diff = differences(ref, c_engine())
    if diff:
        print(f"the C engine's run differs from the numba loop's in: {diff}", file=sys.stderr)
        return 1
    runs = {"numba": numba_loop, "c_engine": c_engine}
    times = {k: [] for k in runs}
    for _ in range(args.calls):
        for key, call in runs.items():
            t_a = time.thread_time_ns()
            call()
            times[key].append(time.thread_time_ns() - t_a)
    ms = {k: np.asarray(v) / 1e6 for k, v in times.items()}
    st = ref[11]
    emit({
        "benchmark": "engine_compare",
        "scenario": Path(args.scenario).name, "model": model, "solver": sc.solver,
        "calls": args.calls, "bit_identical": True,
        "steps": int(st[drv.S_STEPS]), "rejected": int(st[drv.S_REJECTED]),
        "rhs": int(st[drv.S_RHS]), "lu": int(st[drv.S_LU]), "events": int(st[drv.S_EVENTS]),
        "rows": int(st[drv.S_OUTPUT]),
        **{f"{k}_ms_min": round(float(v.min()), 4) for k, v in ms.items()},
        **{f"{k}_ms_median": round(float(np.median(v)), 4) for k, v in ms.items()},
        "c_over_numba_min": round(float(ms["c_engine"].min() / ms["numba"].min()), 3),
        "c_over_numba_median": round(float(np.median(ms["c_engine"]) / np.median(ms["numba"])), 3),
    })
    return 0


if __name__ == "__main__":
    sys.exit(main())
