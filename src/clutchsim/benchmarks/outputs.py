"""Write a benchmark's outputs: its figure, the traces as CSV, and bench.json."""

from __future__ import annotations

import json
from pathlib import Path

__all__ = ["traces_frame", "write_outputs"]


#: rows kept per run in the written traces (the plots and metrics use the full results)
MAX_ROWS_PER_RUN = 5000


def traces_frame(result, max_rows: int = MAX_ROWS_PER_RUN):
    """All runs in one long table: model, run, then the signals with units.

    Runs longer than ``max_rows`` are decimated uniformly (first and last rows kept), so
    that a benchmark's CSV stays a few MB; the full-resolution results are in
    ``result.runs``.
    """
    import numpy as np
    import pandas as pd
    frames = []
    for label, runs in result.runs.items():
        for run_name, res in runs.items():
            frame = res.to_frame()
            if len(frame) > max_rows:
                keep = np.unique(np.linspace(0, len(frame) - 1, max_rows).round().astype(int))
                frame = frame.iloc[keep]
            frame.insert(0, "run", run_name)
            frame.insert(0, "model", label)
            frames.append(frame)
    return pd.concat(frames, ignore_index=True, sort=False)


def write_outputs(result, directory) -> None:
    """Write ``<name>.png``, ``<name>_traces.csv`` and ``bench.json`` into ``directory``.

    The caller makes the directory atomic (:meth:`clutchsim._util.OutputDir.build`).
    """
    from ..plot._style import save_png
    from ..plot.benchmarks import plot_benchmark
    partial = Path(directory)
    partial.mkdir(parents=True, exist_ok=True)
    fig, _ = plot_benchmark(result)
    save_png(fig, partial / f"{result.benchmark}.png")
    traces_frame(result).to_csv(partial / f"{result.benchmark}_traces.csv", index=False,
                                float_format="%.12g")
    doc = {"kind": "bench", **result.metrics_json(), "protocol": result.protocol,
           "models": dict(result.models)}
    (partial / "bench.json").write_text(json.dumps(doc, indent=2, allow_nan=False))
