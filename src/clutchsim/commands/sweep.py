"""``clutchsim sweep``: a scenario over a grid or seeded samples of its parameters."""

from __future__ import annotations

import logging

from ._common import (
    add_limit_flags,
    add_output_flags,
    add_study_flags,
    add_sweep_flags,
    command_parser,
    emit_json,
    metric_names,
    run_study,
    solver_option_items,
    write_command,
)

log = logging.getLogger("clutchsim")

HELP = """\
examples:
  clutchsim sweep examples/launch.toml --vary vehicle.mass=1100:1700:4 \\
      --vary vehicle.grade=0:6:4 --out mass_grade/
  # Monte Carlo: phi0 about its value (1 mrad, 10 %), 2000 seeded samples; all lock up
  clutchsim sweep examples/launch.toml --vary vehicle.mass='uniform(1100,1700)' \\
      --vary 'coupling[0].friction.overrides.phi0=normal(0.001,0.0001)' --samples 2000 \\
      --seed 1 --metrics lockup_time_s,slip_energy_J --out mc/
  # on a Dask cluster; exit 2 when no scheduler answers at that address
  clutchsim sweep examples/launch.toml --vary vehicle.mass=1100:1700:50 --out big/ \\
      --dask tcp://scheduler:8786

KEY is a scenario key as in --set (clutchsim run); SPEC is LO:HI:N (grid, N >= 1),
V1,V2,... (values), uniform(A,B), loguniform(A,B) or normal(MU,SIGMA) (random, needs
--samples and --seed).  Grid keys form the full product.  The scenario is built once; a key
that sets one component value (vehicle.mass, a friction parameter, ...) only changes the
parameter vector per run, other keys rebuild the scenario for the run (docs/sweeps.md).
--option KEY=VALUE sets a solver option of every run (rtol, max_steps, wall_time, ...).

outputs in DIR: results.parquet (one row per run: run, the varied keys, status, outcome,
warnings, message, metrics; units in the Parquet field metadata), sweep.json, chunks/
(finished chunks; an interrupted sweep (Ctrl-C, SIGTERM) keeps them: re-run the same
command to resume), figures (heat maps for a 2-D grid, histograms and scatter otherwise),
traces/ with --keep-traces, command.txt and report.html.  A sweep that fails before its
first chunk (e.g. no Dask scheduler answers) leaves no directory behind.

The number of runs (--max-runs) and the output rows of a run at the extremes of every
varied key (--max-output-rows) are checked before anything runs.
--json prints {"results", "runs", "chunks", "chunks_resumed", "wall_s", "status_counts",
"outcome_counts", "runs_with_warnings", "batched_runs", "sweep_id"} (batched_runs: the
runs of this call that ran in compiled batches, see docs/sweeps.md).
exit status: 0 (also when some runs failed: they are rows with their status and outcome),
2 bad input.
"""


def register(sub, common):
    p = command_parser(sub, common, "sweep", help="run a scenario over many parameter "
                       "values", description="Run a scenario over a grid or seeded random "
                       "samples of its parameters; one row of metrics per run.", epilog=HELP,
                       scenario=True)
    p.add_argument("--vary", action="append", default=[], metavar="KEY=SPEC", required=True,
                   help="a key to vary (repeatable)")
    p.add_argument("--samples", type=int, metavar="N", help="random samples")
    p.add_argument("--seed", type=int, metavar="S", help="seed of the random samples")
    add_study_flags(p)
    p.add_argument("--keep-traces", action="store_true", help="also write every run's time "
                   "series (traces/)")
    add_output_flags(p, force=False, json_help="print a summary on stdout")
    add_sweep_flags(p, "--dask")
    add_limit_flags(p, runs=True)


def run(args) -> int:
    return run_study(args, "sweep", _run)


def _run(args, out) -> int:
    from ..progress import progress_for
    from ..report import build_report
    from ..studies.sweeps import SweepOptions, SweepSpec, sweep
    metrics = metric_names(args.metrics)
    spec = SweepSpec(vary=args.vary or (), samples=args.samples, seed=args.seed,
                     metrics=metrics, model=args.model, overrides=args.set or (),
                     solver_options=solver_option_items(args.option),
                     keep_traces=args.keep_traces)
    options = SweepOptions(backend="dask" if args.address else "threads",
                           workers=args.workers, address=args.address or "local",
                           connect_timeout=args.connect_timeout,
                           chunk_size=args.chunk_size, max_runs=args.max_runs,
                           max_output_rows=args.max_output_rows)
    res = sweep(args.scenario, spec, options, out=out, plots=not args.no_plots,
                load=not args.no_plots, progress=progress_for(args, "runs"))
    write_command(res.path, args.argv)
    build_report(res.path)
    bad = {k: v for k, v in res.outcome_counts.items() if k != "completed"}
    log.info("sweep: %d runs (%d chunks, %d resumed) in %.1f s -> %s%s%s", res.runs,
             res.chunks, res.chunks_skipped, res.wall_s, res.path / "results.parquet",
             f"; did not complete: {bad}" if bad else "",
             f"; {res.runs_with_warnings} runs with warnings (see the warnings column)"
             if res.runs_with_warnings else "")
    if args.json:
        emit_json({"results": str(res.path / "results.parquet"), "runs": res.runs,
                   "chunks": res.chunks, "chunks_resumed": res.chunks_skipped,
                   "wall_s": res.wall_s, "status_counts": res.status_counts,
                   "outcome_counts": res.outcome_counts,
                   "runs_with_warnings": res.runs_with_warnings,
                   "batched_runs": res.batched_runs,
                   "sweep_id": res.manifest["sweep_id"]})
    return 0


__all__ = ["register", "run"]
