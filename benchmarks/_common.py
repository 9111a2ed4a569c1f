"""Shared timing helpers for the benchmark scripts (not part of the test suite)."""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time


def median_ms(fn, repeats: int = 5, warmup: int = 1) -> tuple[float, object]:
    """Median wall time of ``fn()`` in milliseconds over ``repeats`` runs after warm-up."""
    out = None
    for _ in range(warmup):
        out = fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times), out


def fresh_process_seconds(code: str) -> float:
    """Run ``code`` in a new interpreter; it must print the seconds it measured last."""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    return float(done.stdout.strip().splitlines()[-1])


def cpu_model() -> str:
    """The processor's model name as ``lscpu`` gives it (ratios against Python move with
    the CPU, so every result names it)."""
    try:
        text = subprocess.run(["lscpu"], capture_output=True, text=True, check=False).stdout
    except OSError:
        return "unknown (no lscpu)"
    for line in text.splitlines():
        if line.startswith("Model name:"):
            return line.split(":", 1)[1].strip()
    return "unknown"


def emit(result: dict) -> None:
    """The machine-readable result: one JSON object on the last line of stdout, with the
    CPU model (``cpu``) and the load averages at the end (``load_end``)."""
    import os
    result = {**result, "cpu": result.get("cpu") or cpu_model(),
              "load_end": list(os.getloadavg())}
    print(json.dumps(result))


def c_function_values(system) -> dict:
    """``{name: function value}`` of the plant's rhs, events, outputs, jac, factor and solve
    (those the run calls) at their C addresses, as the engine calls them
    (:func:`clutchsim.core._cfunctions.c_functions`), for timing loops compiled by numba.
    Every pointer argument is a 64-bit integer (``np.int64(a.ctypes.data)``): on x86-64 and
    AArch64 a pointer and a 64-bit integer travel in the same register (engine.c's
    signatures, pointers spelled int64)."""
    from numba import types

    from clutchsim.core._cfunctions import c_functions
    from clutchsim.core.cengine import _Address

    i64, f64 = types.int64, types.float64
    sigs = {"rhs": types.void(f64, i64, i64, i64, i64),
            "events": types.void(f64, i64, i64, i64, i64),
            "outputs": types.void(f64, i64, i64, i64, i64),
            "jac": types.void(f64, i64, i64, i64, i64, i64),
            "factor": types.intc(f64, i64, i64, i64),
            "solve": types.void(i64, i64, i64, i64, i64)}
    addresses = dict(zip(("rhs", "events", "reset", "outputs", "jac", "factor", "solve"),
                         c_functions(system)))
    return {n: _Address(addresses[n], sig, system) for n, sig in sigs.items() if addresses[n]}
