"""``clutchsim uq``: an uncertainty study of a scenario (distributions in, probabilities,
quantiles and sensitivity indices out)."""

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
  # how often does a launch on a 0-8 % grade stall the engine? (2000 random runs)
  clutchsim uq --vary 'vehicle.grade=uniform(0,8)' --vary 'vehicle.mass=normal(1500,50)' \\
      --samples 2000 --seed 1 --out grade_mc/ --json
  # which input drives the lock-up time? Sobol' indices, 32 * (4 + 2) runs (512 or more
  # base samples for tight intervals)
  clutchsim uq --method sobol --samples 32 --seed 1 --out sobol/ \\
      --vary 'vehicle.grade=uniform(0,1.5)' --vary 'vehicle.mass=tol(1300±100,cpk=1.33)' \\
      --vary 'inertia[0].J=tnormal(0.15,0.01,0.12,0.18)' \\
      --vary 'coupling[0].friction.overrides.phi0=lognormal(0.001,0.1)'
  # correlated inputs (rank correlation, Gaussian copula), Latin hypercube
  clutchsim uq --method lhs --samples 500 --seed 2 --vary 'vehicle.mass=uniform(1200,1600)' \\
      --vary 'vehicle.grade=uniform(0,4)' --corr vehicle.mass,vehicle.grade=0.5 --out lhs/

DIST: uniform(A,B), normal(MU,SIGMA), tnormal(MU,SIGMA,LO,HI), lognormal(MEDIAN,S),
triangular(LO,MODE,HI), discrete(V1,V2,...) or discrete(V1:W1,V2:W2,...), tol(±T,cpk=C)
(normal about the scenario's value of KEY, sigma = T/(3 C)) or tol(NOM±T,cpk=C).  KEY is a
scenario key as in --set.  --samples: runs (mc, lhs), base samples, a power of 2 (sobol:
N*(d+2) runs for d inputs) or trajectories (morris: N*(d+1) runs).

outputs in DIR: the sweep's files (results.parquet: one row per run, sweep.json, chunks/;
an interrupted study resumes when the same command is repeated), uq.json (the --json
document and the convergence of every estimate), probabilities.csv, quantiles.csv,
sensitivity.csv (sobol, morris), uq_*.png, command.txt and report.html (all of it on one
page).
--json prints {"method", "samples" (runs), "base_samples", "seed", "inputs", "correlation",
"thresholds", "probabilities" {event: {"p", "ci95", "count"}}, "quantiles" {metric: {"p05",
"p50", "p95", "mean", "std", "n"}}, "sobol" {metric: {key: {"S1", "S1_ci95", "ST",
"ST_ci95"}}} (sobol) or "morris" {metric: {key: {"mu_star", "mu_star_ci95", "mu",
"sigma"}}} (morris), "skipped", "path", "wall_s", ...}.  Events: every run outcome
(completed, stalled, chatter, invariant_violated, ...), no_lockup, judder
(judder_amplitude_Nm > --judder-threshold) and over_temperature (> --temperature-limit).
exit status: 0 (also when runs failed: that is what the probabilities count), 2 bad input
(checked before anything runs), 130/143 interrupted (finished chunks are kept).
"""


def register(sub, common):
    p = command_parser(sub, common, "uq", help="uncertainty study: failure "
                       "probabilities, quantiles, sensitivity indices",
                       description="Sample scenario keys from distributions, run them as one "
                       "sweep and estimate the probability of each outcome, the quantiles "
                       "of every metric and (sobol, morris) the sensitivity to each input.",
                       epilog=HELP, scenario=True)
    p.add_argument("--vary", action="append", default=[], metavar="KEY=DIST", required=True,
                   help="an uncertain input (repeatable)")
    p.add_argument("--corr", action="append", default=[], metavar="KEY_A,KEY_B=RHO",
                   help="rank correlation of two inputs (repeatable; mc and lhs)")
    p.add_argument("--method", default="mc", choices=("mc", "lhs", "sobol", "morris"),
                   help="Monte Carlo (default), Latin hypercube, Sobol' indices, Morris")
    p.add_argument("--samples", type=int, metavar="N", help="samples (default: 1000 for "
                   "mc and lhs, 1024 for sobol, 20 for morris; see below)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="seed (default 0)")
    add_study_flags(p)
    p.add_argument("--judder-threshold", type=float, default=5.0, metavar="NM",
                   help="judder event: judder_amplitude_Nm above this [N·m] (default 5)")
    p.add_argument("--temperature-limit", type=float, default=300.0, metavar="C",
                   help="over_temperature event: the friction-surface temperature (else "
                   "the heat node's) above this [°C] (default 300)")
    add_output_flags(p, force=False, json_help="print the study on stdout")
    add_sweep_flags(p, "--address")
    add_limit_flags(p, runs=True)


def run(args) -> int:
    return run_study(args, "uq", _run)


def _run(args, out) -> int:
    from ..progress import progress_for
    from ..report import build_report
    from ..studies.uq import uq
    metrics = metric_names(args.metrics)
    res = uq(args.scenario, args.vary, method=args.method, samples=args.samples,
             seed=args.seed, correlation=args.corr, metrics=metrics, model=args.model,
             overrides=args.set, options=solver_option_items(args.option), out=out,
             backend="dask" if args.address else "threads", workers=args.workers,
             address=args.address or "local", connect_timeout=args.connect_timeout,
             chunk_size=args.chunk_size, judder_threshold_Nm=args.judder_threshold,
             temperature_limit_C=args.temperature_limit, plots=not args.no_plots,
             progress=progress_for(args, "runs"), max_runs=args.max_runs,
             max_output_rows=args.max_output_rows)
    write_command(res.path, args.argv)
    build_report(res.path, title=f"clutchsim uq report: {res.method}, {res.samples} runs "
                 f"over {', '.join(res.inputs)}")
    happened = {k: f"{v['p']:.3g} [{v['ci95'][0]:.3g}, {v['ci95'][1]:.3g}]"
                for k, v in res.probabilities.items() if v["count"]}
    log.info("uq: %s, %d runs in %.1f s (%.0f runs/s) -> %s; P: %s", res.method, res.samples,
             res.run_wall_s, res.samples / res.run_wall_s if res.run_wall_s else 0.0,
             res.path, happened)
    if args.json:
        emit_json(res.to_dict())
    return 0


__all__ = ["register", "run"]
