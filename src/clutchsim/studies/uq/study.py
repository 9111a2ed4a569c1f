"""Uncertainty studies: sample the inputs, run them as one sweep, estimate what comes out.

:func:`study` is the engine (sampling and estimation, independent of what evaluates a
design); :func:`uq` is it on a scenario, evaluated by :func:`clutchsim.studies.sweeps.sweep` (the
chunks, the resume, the backends).  The estimators of Sobol' and Morris are SALib's.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from ..._util import DEFAULT_MAX_OUTPUT_ROWS, DEFAULT_MAX_RUNS
from ..sweeps.design import Design
from .inputs import UQInputError, correlation_matrix, parse_correlation, parse_inputs

__all__ = ["DEFAULT_SAMPLES", "METHODS", "OUTCOMES", "UQResult", "clopper_pearson",
           "make_samples", "read_columns", "study", "study_runs", "uq", "write_study"]

log = logging.getLogger("clutchsim")

METHODS = ("mc", "lhs", "sobol", "morris")
#: ``samples`` of each method when none is given: runs (mc, lhs), base samples (sobol),
#: trajectories (morris)
DEFAULT_SAMPLES = {"mc": 1000, "lhs": 1000, "sobol": 1024, "morris": 20}
#: the runs' ``outcome`` names (:class:`clutchsim.core.Outcome`, ``stalled`` for an engine
#: stall, ``error`` for parameters the run refused), each given a probability
OUTCOMES = ("completed", "stopped", "stalled", "event_failed", "budget", "wall_time",
            "step_collapse", "chatter", "nan", "solver_error", "invariant_violated", "error")
#: metrics that are the solver's effort, not the launch: quantiles but no sensitivities
SOLVER_METRICS = ("steps", "rhs_evals", "events", "min_step_s", "wall_s")
#: Morris levels (the level j of L is the probability (j + 1/2) / L of the input)
MORRIS_LEVELS = 4
#: bootstrap resamples of SALib's confidence intervals
RESAMPLES = 100


def _freeze(obj):
    if isinstance(obj, dict):
        return MappingProxyType({k: _freeze(v) for k, v in obj.items()})
    if isinstance(obj, (list, tuple)):
        return tuple(_freeze(v) for v in obj)
    return obj


def _thaw(obj):
    if isinstance(obj, MappingProxyType | dict):
        return {k: _thaw(v) for k, v in obj.items()}
    if isinstance(obj, tuple):
        return [_thaw(v) for v in obj]
    return obj


@dataclass(frozen=True)
class UQResult:
    """What an uncertainty study found (read-only mappings; :meth:`to_dict` for JSON).

    ``probabilities``: ``{event: {"p", "ci95": [lo, hi], "count"}}`` (Clopper–Pearson);
    ``quantiles``: ``{metric: {"p05", "p50", "p95", "mean", "std", "n"}}`` over the runs
    where the metric has a value; ``sobol``: ``{metric: {key: {"S1", "S1_ci95", "ST",
    "ST_ci95"}}}`` (method ``sobol``); ``morris``: ``{metric: {key: {"mu_star",
    "mu_star_ci95", "mu", "sigma"}}}`` (method ``morris``); ``convergence``: ``{estimate:
    {"n": [...], "value": [...], "lo": [...], "hi": [...]}}`` over growing prefixes of the
    runs."""

    method: str
    inputs: MappingProxyType
    samples: int
    base_samples: int
    seed: int
    probabilities: MappingProxyType
    quantiles: MappingProxyType
    sobol: MappingProxyType | None
    morris: MappingProxyType | None
    convergence: MappingProxyType = field(repr=False)
    correlation: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    thresholds: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    skipped: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    units: MappingProxyType = field(default_factory=lambda: MappingProxyType({}), repr=False)
    path: Path | None = None
    wall_s: float = 0.0
    run_wall_s: float = 0.0
    chunks_resumed: int = 0
    batched_runs: int = 0
    #: the wall time of the compiled batches (integrator and metrics kernel), summed over
    #: the workers [s]
    batch_loop_wall_s: float = 0.0

    def to_dict(self) -> dict:
        """The study as plain JSON types (the ``--json`` document)."""
        doc = {"method": self.method, "samples": self.samples,
               "base_samples": self.base_samples, "seed": self.seed,
               "inputs": _thaw(self.inputs),
               "correlation": {f"{a},{b}": r for (a, b), r in self.correlation.items()},
               "thresholds": _thaw(self.thresholds),
               "probabilities": _thaw(self.probabilities),
               "quantiles": _thaw(self.quantiles)}
        if self.sobol is not None:
            doc["sobol"] = _thaw(self.sobol)
        if self.morris is not None:
            doc["morris"] = _thaw(self.morris)
        doc["skipped"] = _thaw(self.skipped)
        doc.update(path=str(self.path) if self.path else None, wall_s=self.wall_s,
                   run_wall_s=self.run_wall_s, chunks_resumed=self.chunks_resumed,
                   batched_runs=self.batched_runs,
                   batch_loop_wall_s=self.batch_loop_wall_s)
        return doc


# --------------------------------------------------------------------------- sampling
def study_runs(method: str, samples: int, n_inputs: int) -> int:
    """The runs of a study: ``samples`` (mc, lhs), ``samples * (d + 2)`` (sobol, first
    and total indices), ``samples * (d + 1)`` (morris, ``samples`` trajectories)."""
    return {"mc": samples, "lhs": samples, "sobol": samples * (n_inputs + 2),
            "morris": samples * (n_inputs + 1)}[method]


def _check_method(method, samples, seed, n_inputs, corr) -> None:
    if method not in METHODS:
        from ...scenario.schema import suggest
        raise UQInputError(f"--method {method!r}: not one of {', '.join(METHODS)}"
                           f"{suggest(method, METHODS)}")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
        raise UQInputError(f"--samples {samples!r}: must be an integer >= 1")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise UQInputError(f"--seed {seed!r}: must be an integer >= 0 (the same seed gives "
                           "the same samples)")
    if method == "sobol" and (samples < 8 or samples & (samples - 1)):
        lo = 1 << max(3, int(samples).bit_length() - 1)
        raise UQInputError(f"--samples {samples}: Sobol' needs a power of 2 >= 8 (the "
                           f"base samples of Saltelli's scheme; e.g. {lo} or {2 * lo})")
    if method == "morris" and samples < 2:
        raise UQInputError(f"--samples {samples}: Morris needs >= 2 trajectories")
    if method in ("sobol", "morris") and corr is not None:
        raise UQInputError(f"--corr with --method {method}: its indices assume independent "
                           "inputs; use --method mc or lhs for correlated inputs")


def make_samples(method: str, samples: int, seed: int, n_inputs: int,
                 corr: np.ndarray | None = None) -> np.ndarray:
    """The probabilities ``u`` (runs x inputs, in (0, 1)) of a study's runs; the inputs'
    values are their distributions' inverse CDFs at ``u``.  Correlations (mc, lhs) act
    through a Gaussian copula with the normals' correlation matrix ``corr``."""
    from scipy import stats
    problem = {"num_vars": n_inputs, "names": [f"x{i}" for i in range(n_inputs)],
               "bounds": [[0.0, 1.0]] * n_inputs}
    if method == "mc":
        u = np.random.default_rng(seed).random((samples, n_inputs))
    elif method == "lhs":
        from scipy.stats import qmc
        u = qmc.LatinHypercube(d=n_inputs, rng=np.random.default_rng(seed)).random(samples)
    elif method == "sobol":
        from SALib.sample import sobol
        u = sobol.sample(problem, samples, calc_second_order=False, seed=seed)
    else:
        from SALib.sample import morris
        u = morris.sample(problem, samples, num_levels=MORRIS_LEVELS, seed=seed)
        u = (np.rint(u * (MORRIS_LEVELS - 1)) + 0.5) / MORRIS_LEVELS
    if corr is not None:
        z = stats.norm.ppf(np.clip(u, 1e-12, 1 - 1e-12)) @ np.linalg.cholesky(corr).T
        u = stats.norm.cdf(z)
    return np.clip(u, 1e-12, 1 - 1e-12)


# --------------------------------------------------------------------------- estimators
def clopper_pearson(k, n, level: float = 0.95):
    """The exact (Clopper–Pearson) interval of a probability from ``k`` of ``n``:
    ``(lo, hi)``, arrays when ``k`` is one (coverage >= ``level`` for every p)."""
    from scipy import stats
    k = np.asarray(k, dtype=float)
    n = np.asarray(n, dtype=float)
    a = (1.0 - level) / 2.0
    with np.errstate(invalid="ignore", divide="ignore"):
        lo = np.where(k > 0, stats.beta.ppf(a, k, n - k + 1), 0.0)
        hi = np.where(k < n, stats.beta.isf(a, k + 1, n - k), 1.0)
    return lo, hi


def _prefixes(n: int, first: int = 20, points: int = 12) -> list[int]:
    if n <= first:
        return [n]
    grid = np.unique(np.rint(np.geomspace(first, n, points)).astype(int))
    return [int(v) for v in grid]


def _events(cols: dict, thresholds: dict) -> dict:
    """``{event: bool per run}``: each outcome, and the derived events."""
    codes, names = cols["outcome"]
    ev = {}
    for name in list(OUTCOMES) + [n for n in names if n not in OUTCOMES]:
        i = names.index(name) if name in names else -1
        ev[name] = codes == i
    if "lockup_time_s" in cols:
        ev["no_lockup"] = ~np.isfinite(cols["lockup_time_s"])
    if "judder_amplitude_Nm" in cols:
        with np.errstate(invalid="ignore"):
            ev["judder"] = cols["judder_amplitude_Nm"] > thresholds["judder_amplitude_Nm"]
    temp = "peak_surface_temp_C" if np.isfinite(cols.get("peak_surface_temp_C",
                                                          np.array([np.nan]))).any() \
        else "peak_heat_node_temp_C"
    if temp in cols:
        with np.errstate(invalid="ignore"):
            ev["over_temperature"] = cols[temp] > thresholds["temperature_C"]
    return ev


def _probabilities(events: dict, n: int) -> tuple[dict, dict]:
    probs, conv = {}, {}
    steps = _prefixes(n)
    for name, hit in events.items():
        k = int(hit.sum())
        lo, hi = clopper_pearson(k, n)
        probs[name] = {"p": k / n if n else None, "ci95": [float(lo), float(hi)],
                       "count": k}
        if k:
            ks = np.cumsum(hit)[np.asarray(steps) - 1]
            los, his = clopper_pearson(ks, np.asarray(steps))
            conv[f"P({name})"] = {"n": steps, "value": (ks / np.asarray(steps)).tolist(),
                                  "lo": los.tolist(), "hi": his.tolist()}
    return probs, conv


def _quantiles(cols: dict, metrics) -> tuple[dict, dict]:
    q, conv = {}, {}
    for m in metrics:
        v = cols[m]
        ok = np.isfinite(v)
        if not ok.any():
            q[m] = {"p05": None, "p50": None, "p95": None, "mean": None, "std": None, "n": 0}
            continue
        p05, p50, p95 = np.quantile(v[ok], [0.05, 0.5, 0.95])
        q[m] = {"p05": float(p05), "p50": float(p50), "p95": float(p95),
                "mean": float(v[ok].mean()), "std": float(v[ok].std(ddof=1)) if ok.sum() > 1
                else 0.0, "n": int(ok.sum())}
        steps = [s for s in _prefixes(v.size) if ok[:s].any()]
        qs = [np.quantile(v[:s][ok[:s]], [0.05, 0.5, 0.95]) for s in steps]
        conv[f"p50({m})"] = {"n": steps, "value": [float(x[1]) for x in qs],
                             "lo": [float(x[0]) for x in qs], "hi": [float(x[2]) for x in qs]}
    return q, conv


def _sensitivity_outputs(cols: dict, metrics, events: dict, skipped: dict) -> dict:
    """``{name: values}`` the sensitivities are computed for: the launch metrics with a
    value in every run and some spread, and the indicator of every event that happened in
    some runs but not all (``P(stalled)``, ...); the others go to ``skipped`` with why."""
    out = {}
    for m in metrics:
        if m in SOLVER_METRICS:
            continue
        v = cols[m]
        if not np.isfinite(v).all():
            skipped[m] = (f"no value in {int((~np.isfinite(v)).sum())} runs (e.g. runs "
                          "that did not lock up); see the P(...) entries")
        elif np.ptp(v) == 0:
            skipped[m] = "the same value in every run"
        else:
            out[m] = v
    for name, hit in events.items():
        if 0 < hit.sum() < hit.size:
            out[f"P({name})"] = hit.astype(float)
    return out


def _sobol(keys, ys: dict, seed: int, base: int) -> tuple[dict, dict]:
    from SALib.analyze import sobol
    d = len(keys)
    problem = {"num_vars": d, "names": list(keys), "bounds": [[0.0, 1.0]] * d}
    res, conv = {}, {}
    steps = [s for s in (2 ** np.arange(3, int(math.log2(base)) + 1)) if s >= 16] or [base]
    for name, y in ys.items():
        si = sobol.analyze(problem, y, calc_second_order=False, num_resamples=RESAMPLES,
                           conf_level=0.95, seed=seed)
        res[name] = {k: {"S1": float(si["S1"][i]),
                         "S1_ci95": [float(si["S1"][i] - si["S1_conf"][i]),
                                     float(si["S1"][i] + si["S1_conf"][i])],
                         "ST": float(si["ST"][i]),
                         "ST_ci95": [float(si["ST"][i] - si["ST_conf"][i]),
                                     float(si["ST"][i] + si["ST_conf"][i])]}
                     for i, k in enumerate(keys)}
        parts = [sobol.analyze(problem, y[: int(s) * (d + 2)], calc_second_order=False,
                               num_resamples=RESAMPLES, conf_level=0.95, seed=seed)
                 for s in steps[:-1]] + [si]
        for i, k in enumerate(keys):
            for idx in ("S1", "ST"):
                conv[f"{idx}({name}; {k})"] = {
                    "n": [int(s) * (d + 2) for s in steps],
                    "value": [float(p[idx][i]) for p in parts],
                    "lo": [float(p[idx][i] - p[f"{idx}_conf"][i]) for p in parts],
                    "hi": [float(p[idx][i] + p[f"{idx}_conf"][i]) for p in parts]}
    return res, conv


def _morris(keys, u: np.ndarray, ys: dict, seed: int) -> dict:
    from SALib.analyze import morris
    d = len(keys)
    problem = {"num_vars": d, "names": list(keys), "bounds": [[0.0, 1.0]] * d}
    x = (u * MORRIS_LEVELS - 0.5) / (MORRIS_LEVELS - 1)      # back to SALib's levels
    res = {}
    for name, y in ys.items():
        mi = morris.analyze(problem, x, y, num_resamples=RESAMPLES, conf_level=0.95,
                            num_levels=MORRIS_LEVELS, seed=seed)
        res[name] = {k: {"mu_star": float(mi["mu_star"][i]),
                         "mu_star_ci95": [float(mi["mu_star"][i] - mi["mu_star_conf"][i]),
                                          float(mi["mu_star"][i] + mi["mu_star_conf"][i])],
                         "mu": float(mi["mu"][i]), "sigma": float(mi["sigma"][i])}
                     for i, k in enumerate(keys)}
    return res


def _clean(obj):
    """NaN and infinities as None (JSON has neither)."""
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_clean(v) for v in obj]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


# --------------------------------------------------------------------------- the study
def study(inputs, evaluate, *, method: str = "mc", samples: int, seed: int,
          correlation=None, judder_threshold_Nm: float = 5.0,
          temperature_limit_C: float = 300.0, max_runs: int | None = DEFAULT_MAX_RUNS,
          nominal=None) -> tuple[UQResult, dict]:
    """Sample ``inputs`` (``{key: Dist or DIST text}``), evaluate the runs and estimate.

    ``evaluate(design) -> (columns, info)``: ``columns`` maps ``"outcome"`` to ``(codes,
    names)`` (an int array and the names it indexes) and every metric to a float array
    (NaN: no value), one entry per run of ``design`` in its order; ``info`` may hold
    ``path``, ``wall_s``, ``chunks_resumed``, ``batched_runs``, ``batch_loop_wall_s`` and
    ``units``.  Everything is
    checked before ``evaluate`` is called.  Returns the result and the columns (for the
    figures)."""
    from ..._util import check_run_count
    t0 = time.perf_counter()
    dists = parse_inputs(inputs, nominal)
    keys = tuple(dists)
    pairs = parse_correlation(correlation or {})
    corr = correlation_matrix(keys, pairs)
    _check_method(method, samples, seed, len(keys), corr)
    for name, v in (("--judder-threshold", judder_threshold_Nm),
                    ("--temperature-limit", temperature_limit_C)):
        if not (isinstance(v, (int, float)) and math.isfinite(v)):
            raise UQInputError(f"{name} {v!r}: must be a finite number")
    n = study_runs(method, int(samples), len(keys))
    if max_runs is not None:
        check_run_count(n, max_runs, what=f"{method} study of {samples} samples over "
                        f"{len(keys)} inputs")
    u = make_samples(method, int(samples), int(seed), len(keys), corr)
    design = Design(keys, {k: dists[k].ppf(u[:, j]) for j, k in enumerate(keys)}, (), keys,
                    int(u.shape[0]))
    cols, info = evaluate(design)
    thresholds = {"judder_amplitude_Nm": float(judder_threshold_Nm),
                  "temperature_C": float(temperature_limit_C)}
    events = _events(cols, thresholds)
    metrics = [m for m in cols if m != "outcome" and m not in keys]
    probs, conv = _probabilities(events, n)
    quant, qconv = _quantiles(cols, metrics)
    conv.update(qconv)
    skipped: dict = {}
    sob = mor = None
    if method in ("sobol", "morris"):
        ys = _sensitivity_outputs(cols, metrics, events, skipped)
        if method == "sobol":
            sob, sconv = _sobol(keys, ys, int(seed), int(samples))
            conv.update(sconv)
        else:
            mor = _morris(keys, u, ys, int(seed))
    result = UQResult(
        method=method, inputs=_freeze({k: d.text() for k, d in dists.items()}), samples=n,
        base_samples=int(samples), seed=int(seed),
        probabilities=_freeze(_clean(probs)), quantiles=_freeze(_clean(quant)),
        sobol=_freeze(_clean(sob)) if sob is not None else None,
        morris=_freeze(_clean(mor)) if mor is not None else None,
        convergence=_freeze(_clean(conv)), correlation=MappingProxyType(dict(pairs)),
        thresholds=_freeze(thresholds), skipped=_freeze(skipped),
        units=_freeze(info.get("units", {})), path=info.get("path"),
        wall_s=time.perf_counter() - t0, run_wall_s=float(info.get("wall_s", 0.0)),
        chunks_resumed=int(info.get("chunks_resumed", 0)),
        batched_runs=int(info.get("batched_runs", 0)),
        batch_loop_wall_s=float(info.get("batch_loop_wall_s", 0.0)))
    return result, cols


def read_columns(path, metrics) -> dict:
    """The study's columns from a sweep's results.parquet: the outcome dictionary-encoded
    (codes and names: no Python string per run), the metrics as float arrays (NaN: no
    value).  Read one column at a time, so that only one column is held twice (Arrow and
    numpy) at any moment."""
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.parquet as pq
    f = pq.ParquetFile(Path(path) / "results.parquet")
    enc = pc.dictionary_encode(f.read(columns=["outcome"])["outcome"]).combine_chunks()
    cols = {"outcome": (enc.indices.to_numpy(zero_copy_only=False).astype(np.int32),
                        enc.dictionary.to_pylist())}
    del enc
    for m in metrics:
        c = pc.fill_null(f.read(columns=[m])[m].cast(pa.float64()), float("nan"))
        cols[m] = c.to_numpy()
    return cols


def _frame_columns(table, metrics) -> dict:
    """:func:`read_columns` from a results DataFrame (a sweep in a temporary directory)."""
    import pandas as pd
    codes, names = pd.factorize(table["outcome"])
    cols = {"outcome": (codes.astype(np.int32), [str(v) for v in names])}
    for m in metrics:
        cols[m] = table[m].to_numpy(dtype=float, na_value=np.nan)
    return cols


def write_study(path, result: UQResult) -> list[Path]:
    """The study's files in ``path`` (atomically): uq.json (the ``--json`` document and
    the convergence), probabilities.csv, quantiles.csv and, for Sobol'/Morris,
    sensitivity.csv."""
    import json

    import pandas as pd

    from ..._util import atomic_write
    path = Path(path)
    doc = result.to_dict()
    doc["convergence"] = _thaw(result.convergence)
    files = [atomic_write(path / "uq.json", lambda t: Path(t).write_text(
        json.dumps(doc, indent=2, allow_nan=False, default=str), encoding="utf-8"))]
    prob = pd.DataFrame([{"event": k, "p": v["p"], "ci95_lo": v["ci95"][0],
                          "ci95_hi": v["ci95"][1], "count": v["count"]}
                         for k, v in result.probabilities.items()])
    quant = pd.DataFrame([{"metric": k, "unit": result.units.get(k, ""), **v}
                          for k, v in result.quantiles.items()])
    tables = {"probabilities.csv": prob, "quantiles.csv": quant}
    sens = result.sobol if result.sobol is not None else result.morris
    if sens is not None:
        rows = []
        for metric, by_key in sens.items():
            for key, v in by_key.items():
                row = {"output": metric, "input": key}
                for name, x in v.items():
                    if isinstance(x, tuple):
                        row[f"{name}_lo"], row[f"{name}_hi"] = x
                    else:
                        row[name] = x
                rows.append(row)
        tables["sensitivity.csv"] = pd.DataFrame(rows)
    for name, frame in tables.items():
        files.append(atomic_write(path / name, lambda t, f=frame: f.to_csv(t, index=False)))
    return files


def uq(scenario=None, vary=None, *, method: str = "mc", samples: int | None = None,
       seed: int = 0, correlation=None, metrics=None, model: str | None = None,
       overrides=None, options=None, out=None, backend="threads",
       workers: int | None = None, address: str = "local", connect_timeout: float = 10.0,
       chunk_size: int | None = None, judder_threshold_Nm: float = 5.0,
       temperature_limit_C: float = 300.0, plots: bool = False, progress=None,
       max_runs: int | None = DEFAULT_MAX_RUNS,
       max_output_rows: int | None = DEFAULT_MAX_OUTPUT_ROWS) -> UQResult:
    """An uncertainty study of ``scenario`` (None: the packaged default launch).

    Parameters
    ----------
    vary : mapping or sequence of str
        ``{"vehicle.grade": "uniform(0,1.5)", "vehicle.mass": "normal(1500,50)"}`` or the
        CLI form ``["vehicle.mass=normal(1500,50)", ...]``: the DIST syntax of
        :mod:`clutchsim.studies.uq.inputs`; keys as in ``--set``.
    method : "mc", "lhs", "sobol" or "morris"
        Monte Carlo, Latin hypercube, Sobol' first-order and total indices (Saltelli's
        scheme, ``samples`` base samples, a power of 2: ``samples * (d + 2)`` runs) or
        Morris screening (``samples`` trajectories: ``samples * (d + 1)`` runs).
    samples, seed : int
        The samples (default :data:`DEFAULT_SAMPLES` of the method) and the seed (the same
        seed gives the same runs on every backend).
    correlation : mapping or sequence of str
        Rank correlations ``{("a", "b"): 0.5}`` or ``["a,b=0.5"]`` (mc and lhs; a
        Gaussian copula).
    judder_threshold_Nm, temperature_limit_C : float
        The ``judder`` event is ``judder_amplitude_Nm`` above the first [N·m];
        ``over_temperature`` is the friction-surface temperature (``peak_surface_temp_C``,
        with a surface layer; else ``peak_heat_node_temp_C``) above the second [°C].
    out : path, optional
        The sweep's directory (results.parquet, chunks: re-running the same study resumes),
        where the study's files are written too (:func:`write_study`).  Default: a
        temporary directory, removed afterwards.
    metrics, model, overrides, options, backend, workers, address, connect_timeout,
    chunk_size, progress, max_runs, max_output_rows
        As for :func:`clutchsim.studies.sweeps.sweep`.

    Returns
    -------
    UQResult
    """
    from ...scenario import resolve_scenario
    from ..sweeps import DEFAULT_METRICS, METRICS, SweepOptions, SweepSpec, sweep
    from .inputs import scenario_value
    sc = resolve_scenario(scenario, overrides)
    metrics = tuple(DEFAULT_METRICS if metrics is None else metrics)

    def evaluate(design):
        res = sweep(sc, SweepSpec(design=design, metrics=metrics, model=model,
                                  solver_options=options),
                    SweepOptions(backend=backend, workers=workers, address=address,
                                 connect_timeout=connect_timeout, chunk_size=chunk_size,
                                 max_runs=max_runs, max_output_rows=max_output_rows),
                    out=out, load=out is None, progress=progress)
        if res.path is not None:
            cols = read_columns(res.path, metrics)
        else:
            cols = _frame_columns(res.table, metrics)
        units = {m: METRICS[m][0] for m in metrics}
        units.update(res.manifest.get("units", {}))
        info = {"path": res.path, "wall_s": res.wall_s, "batched_runs": res.batched_runs,
                "batch_loop_wall_s": res.batch_loop_wall_s,
                "chunks_resumed": res.chunks_skipped, "units": units}
        return cols, info

    if samples is None:
        samples = DEFAULT_SAMPLES.get(method, 1000)
    result, cols = study(vary if vary is not None else {}, evaluate, method=method,
                         samples=samples, seed=seed, correlation=correlation,
                         judder_threshold_Nm=judder_threshold_Nm,
                         temperature_limit_C=temperature_limit_C, max_runs=max_runs,
                         nominal=lambda key: scenario_value(sc.data, key))
    if result.path is not None:
        write_study(result.path, result)
        if plots:
            from ...plot.uq import write_figures
            write_figures(result.path, result, cols)
    return result
