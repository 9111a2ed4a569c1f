"""The main job: what ``make demo`` runs.

The default passenger-car launch with the seed paper's model (6), the robust switching
model and the naive switching model side by side (the seed's Figs. 9–10), plus the drift
test on every applicable friction model (its Figs. 3–5), written into one directory with
an HTML report.
"""

from __future__ import annotations

import json
import logging
import time
from pathlib import Path

from ._util import atomic_write, claim_output_dir

__all__ = ["DEMO_MODELS", "format_summary", "run_demo"]

log = logging.getLogger("clutchsim")

#: the clutch models compared on the default launch
DEMO_MODELS = ("mykhailevych2020", "coulomb-robust", "coulomb-naive")


def run_demo(out: str | Path = "clutchsim-out/demo", *, plots: bool = True,
             force: bool = False) -> dict:
    """Run the demo into ``out`` (built atomically) and return its summary.

    ``out`` is checked before anything runs (:func:`clutchsim._util.claim_output_dir`: an
    existing directory only if it is empty or an earlier demo; ``force``: beside files
    clutchsim did not write, which are kept).

    Layout: ``launch/`` (time series, summary.json, figures of the three launches),
    ``drift/`` (drift benchmark figure, traces, bench.json), ``demo.json`` and
    ``report.html``.
    """
    with claim_output_dir(out, "demo", force=force) as claimed:
        return _run_demo(Path(out), claimed, plots)


def _run_demo(out: Path, claimed, plots: bool) -> dict:
    from .scenario.warmup import metrics_compiled_beside
    t0 = time.perf_counter()
    # the drift test first: from an empty cache the launch metrics compile meanwhile, in a
    # second process, and the first launch's analysis waits for them (measured, session 31:
    # a fresh demo 55 s -> 44 s).  That compilation is the demo's longest path: it starts
    # before the other imports (~2 s from a fresh install).
    with claimed.build() as part, metrics_compiled_beside(work_first=True):
        from .benchmarks import run_benchmark, write_outputs
        from .scenario import load_scenario
        from .scenario.outputs import write_runs
        log.info("drift test on all applicable models ...")
        drift = run_benchmark("drift")
        write_outputs(drift, part / "drift")
        scenario = load_scenario(None)
        # the launches' plants compile while the metrics' child runs; write_runs then
        # simulates, draws the figures, and only then analyses (the first analysis waits
        # for the child)
        for model in DEMO_MODELS:
            scenario.system(model)
        launch = write_runs(scenario, DEMO_MODELS, part / "launch", plots=plots)
        summary = {
            "kind": "demo",
            "scenario": launch["scenario"],
            "launch": launch["models"],
            "drift": drift.metrics_json()["results"],
            # every value of the launches' equations, the clutch once per model
            "parameters": launch["parameters"],
            "wall_s": time.perf_counter() - t0,
        }
        atomic_write(part / "demo.json", lambda p: Path(p).write_text(
            json.dumps(summary, indent=2, allow_nan=False, default=float)))
        if plots:
            from .report import build_report
            for sub in ("launch", "drift"):
                build_report(part / sub)
            build_report(part, title="clutchsim demo: launch through lock-up and drift test")
    summary["out"] = str(out)
    summary["report"] = str(out / "report.html")
    return summary


def _fmt(value, spec: str, none: str = "–") -> str:
    return none if value is None else format(value, spec)


def format_summary(summary: dict) -> str:
    """A short plain-text table of the demo for the terminal."""
    rows = [("model", "completed", "lock-up [s]", "slip energy [kJ]", "heat node peak [°C]",
             "steps", "wall [s]")]
    for name, m in summary["launch"].items():
        rows.append((name, "yes" if m["completed"] else "NO",
                     _fmt(m.get("lockup_time_s"), ".3f"),
                     _fmt(None if m.get("slip_energy_J") is None
                          else m["slip_energy_J"] / 1e3, ".2f"),
                     _fmt(m.get("peak_heat_node_temp_C"), ".1f"),
                     str(m.get("steps", "")), _fmt(m.get("wall_s"), ".3f")))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = [f"Launch: {summary['scenario']}"]
    for i, r in enumerate(rows):
        lines.append("  " + "  ".join(c.ljust(w) for c, w in zip(r, widths)))
        if i == 0:
            lines.append("  " + "  ".join("-" * w for w in widths))
    for name, m in summary["launch"].items():
        if not m["completed"]:
            lines.append(f"  {name} did not complete: {m['message']}")
    lines.append("")
    lines.append("Drift test (drift per load cycle of the sub-break-away sine):")
    for name, m in summary["drift"].items():
        d1 = m.get("D1", {}).get("drift_per_cycle_m")
        d2 = m.get("D2", {}).get("drift_per_cycle_m")
        lines.append(f"  {name:<28} D1 {_fmt(None if d1 is None else d1 * 1e6, '10.4f')} µm"
                     f"   D2 {_fmt(None if d2 is None else d2 * 1e6, '10.4f')} µm")
    lines.append("")
    lines.append(f"report: {summary['report']}")
    return "\n".join(lines)
