"""``clutchsim.sweep``: run a scenario over a grid or random samples of its parameters."""

from __future__ import annotations

import logging
import math
import tempfile
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..._util import DEFAULT_MAX_OUTPUT_ROWS, DEFAULT_MAX_RUNS, check_run_size
from .backends import DEFAULT_CONNECT_TIMEOUT, dask_client, run_dask, run_threads
from .design import (
    Design,
    Grid,
    Normal,
    SweepError,
    Uniform,
    Values,
    key_unit,
    make_design,
    parse_vary,
)
from .runner import DEFAULT_METRICS, METRICS
from .store import FORMAT, SweepStore, chunk_id, digest, read_results

__all__ = ["SweepOptions", "SweepResult", "SweepSpec", "sweep"]

log = logging.getLogger("clutchsim")


@dataclass(frozen=True)
class SweepResult:
    """What a sweep did: the table (one row per run) and where it was written."""

    table: object = field(repr=False)    # pandas DataFrame, or None with load=False
    path: Path | None
    runs: int
    chunks: int
    chunks_skipped: int
    wall_s: float
    status_counts: dict
    manifest: dict = field(repr=False)
    #: runs per machine-readable outcome (``completed``, ``stalled``, ``chatter``, ...)
    outcome_counts: dict = field(default_factory=dict)
    #: runs that completed with warnings (the ``warnings`` column says which)
    runs_with_warnings: int = 0
    #: runs of this call that ran in compiled batches (:func:`~clutchsim.studies.sweeps.runner.
    #: run_chunk`) and the wall time of those batches' compiled loops [s] (integrator
    #: and metrics kernel, summed over the workers)
    batched_runs: int = 0
    batch_loop_wall_s: float = 0.0


def _default_chunk_size(n: int) -> int:
    # depends on the number of runs only (never on the backend), so every backend and
    # every resume cuts the same chunks; ~100 chunks, 64..1000 runs each: a chunk file
    # costs ~3-5 ms to build, write and read back and a chunk's batch ~0.5 ms to set up,
    # ~0.06 ms per run at 64 runs (0.12 ms at the former floor of 32, 0.5 ms at 8), and
    # 64 launches are ~0.2 s of integration.  The runs are then spread evenly over that
    # many chunks (200 runs: 4 of 50, not 64, 64, 64 and 8), so that workers get even
    # shares
    size = int(min(1000, max(64, math.ceil(n / 100))))
    return max(1, math.ceil(n / math.ceil(n / size))) if n > 0 else size


def _probe_values(spec) -> list[float]:
    if isinstance(spec, Grid):
        return [spec.lo, spec.hi]
    if isinstance(spec, Values):
        return [min(spec.items), max(spec.items)]
    if isinstance(spec, Uniform):
        return [spec.a, spec.b]
    if isinstance(spec, Normal):
        return [spec.mu]
    return [spec.a, spec.b]


def _check_keys(sc, probes: dict, model, max_rows: int, solver_items: dict) -> None:
    """Every key must be a scenario key the loader accepts (unknown: suggest the closest),
    and the extreme values (``probes``: key -> values to try) must give runs within the
    output limit."""
    from ..._util import ResourceError, check_run_size
    from ...scenario import ScenarioError, resolve_scenario
    from ...scenario.loader import toml_value, with_solver_options
    for key, values in probes.items():
        for v in values:
            try:
                probe = with_solver_options(resolve_scenario(sc, [f"{key}={toml_value(v)}"]),
                                            solver_items)
                check_run_size(probe.estimate(model), probe.options,
                               what=f"{key} = {v:g}", max_rows=max_rows)
            except ResourceError as exc:
                raise ResourceError(f"--vary {key}: {exc}") from None
            except (ScenarioError, ValueError, KeyError, TypeError) as exc:
                raise SweepError(f"--vary {key}: {exc}{_component_hint(sc, key)}") from None


def _component_hint(sc, key: str) -> str:
    """For a key of a table the scenario does not have (``vehicle.mass`` in a network
    scenario), the component keys that name the same value: "; did you mean ..."."""
    section, _, rest = key.partition(".")
    if "[" in section or not rest or section in sc.data:
        return ""
    found = [f"component[{i}].{rest}" for i, c in enumerate(sc.data.get("component", []))
             if isinstance(c, dict) and section in (c.get("type"), c.get("name"))
             and rest.split(".")[0] in c]
    if not found:
        return ""
    return (f" (this scenario has no [{section}] table; its components: did you mean "
            f"{' or '.join(found)}?)")


@dataclass(frozen=True)
class SweepSpec:
    """What a sweep runs: the variants of a scenario and the columns kept.  Everything here
    is part of the sweep's identity (a directory resumes only the same spec).

    Attributes
    ----------
    vary : mapping or sequence of str
        ``{"vehicle.mass": "1100:1500:5", "vehicle.grade": "uniform(0, 10)"}`` or the CLI
        form ``["vehicle.mass=1100:1500:5", ...]``.  Grid axes (``LO:HI:N``, value lists)
        form the full product; distributions (``uniform(a,b)``, ``loguniform(a,b)``,
        ``normal(mu,sigma)``) are drawn ``samples`` times with ``seed``.
    samples, seed : int, optional
        Number of random samples and the seed (the same seed gives the same table on every
        backend).
    metrics : sequence of str, optional
        Columns to keep (default: all of :data:`~clutchsim.studies.sweeps.METRICS` but
        ``wall_s``).
    model : str, optional
        Friction model of the clutch (default: the scenario's first).
    overrides : sequence of str
        ``key.path=value`` applied to the base scenario before the sweep.
    solver_options : mapping, optional
        Solver options of every run (``{"rtol": 1e-7, "wall_time": 30}``: the keys of
        :meth:`~clutchsim.core.SolverOptions.from_mapping`, the CLI's ``--option``), over
        the scenario's ``[solver]`` table and a varied ``solver.*`` key.
    keep_traces : bool
        Also write each run's time series to ``out/traces/run-NNNNNNN.parquet``.
    design : Design, optional
        The variants as a table computed by the caller (an uncertainty study's samples,
        :mod:`clutchsim.studies.uq`) instead of ``vary``, ``samples`` and ``seed``: run
        ``i`` is ``design.row(i)``; the sweep's id holds a hash of the table, so the same
        design resumes.
    """

    vary: Mapping | Sequence[str] = ()
    samples: int | None = None
    seed: int | None = None
    metrics: Sequence[str] | None = None
    model: str | None = None
    overrides: Sequence[str] = ()
    solver_options: Mapping | None = None
    keep_traces: bool = False
    design: Design | None = None

    def __post_init__(self):
        object.__setattr__(self, "overrides", tuple(self.overrides or ()))
        if self.metrics is not None:
            object.__setattr__(self, "metrics", tuple(self.metrics))


@dataclass(frozen=True)
class SweepOptions:
    """Where and how a sweep's runs execute, and the limits checked before any runs.  None
    of it changes the table (every backend and chunk size gives the same rows).

    Attributes
    ----------
    backend : "threads", "dask" or a distributed.Client
        ``threads``: this process, ``workers`` threads (default: all cores).  ``dask``: a
        LocalCluster (``address="local"``) or the scheduler at ``address``.
    workers : int, optional
        Threads, or Dask workers of a LocalCluster.
    address : str
        The Dask scheduler (``"local"``: start a LocalCluster).
    connect_timeout : float
        Seconds to wait for a Dask scheduler before giving up with an error [s].
    chunk_size : int, optional
        Runs per chunk (the unit of streaming and resume; default from the number of runs).
    max_runs : int or None
        Refuse a design of more runs (:class:`~clutchsim._util.ResourceError`, before any
        memory is allocated for it); ``None``: no limit.
    max_output_rows : int or None
        Refuse a base scenario (or an extreme of a varied key) whose fixed output grid has
        more rows per run; a run storing every step stores at most this many.
    """

    backend: object = "threads"
    workers: int | None = None
    address: str = "local"
    connect_timeout: float = DEFAULT_CONNECT_TIMEOUT
    chunk_size: int | None = None
    max_runs: int | None = DEFAULT_MAX_RUNS
    max_output_rows: int | None = DEFAULT_MAX_OUTPUT_ROWS


def sweep(scenario=None, spec: SweepSpec | Mapping | Sequence[str] | None = None,
          options: SweepOptions | None = None, *, out=None, plots: bool = False,
          load: bool = True, progress=None) -> SweepResult:
    """Simulate ``scenario`` once per variant and collect the launch metrics in a table.

    Parameters
    ----------
    scenario : Scenario, str, Path or None
        The base scenario (``None``: the packaged default launch).
    spec : SweepSpec, or its ``vary`` alone
        The variants and the columns (a mapping or sequence of ``key=spec`` strings is
        ``SweepSpec(vary=...)``).
    options : SweepOptions, optional
        The backend, its workers, the chunk size and the size limits.
    out : str or Path, optional
        Output directory (results.parquet, chunk files, sweep.json).  Re-running the same
        sweep on it resumes; a directory holding another sweep is refused.  Default: a
        temporary directory, removed afterwards.
    plots : bool
        Write figures (heat map for 2-D grids, histograms and scatter for samples).
    load : bool
        Read the results table back into ``SweepResult.table``.
    progress : callable, optional
        ``progress(done_runs, total_runs)`` after each chunk.

    Returns
    -------
    SweepResult

    Notes
    -----
    An interrupted sweep (Ctrl-C, SIGTERM, a failed worker) keeps its finished chunks in
    ``out``: the same call resumes from them.  A sweep that fails before finishing any
    chunk (a Dask scheduler that does not answer, for one) removes the directory it
    created.
    """
    spec = spec if isinstance(spec, SweepSpec) else SweepSpec(vary=spec or ())
    options = SweepOptions() if options is None else options
    scenario, design, manifest = _plan(scenario, spec, options)
    tmp = None
    if out is None:
        tmp = tempfile.TemporaryDirectory(prefix="clutchsim-sweep-")
        path = Path(tmp.name) / "sweep"
    else:
        path = Path(out)
    created = not path.exists()
    try:
        _resume_chunk_size(path, manifest)
        store = SweepStore(path, manifest)
        store.open()
        try:
            result = _execute(store, scenario, design, manifest, options, progress)
        except BaseException:
            _after_failure(path, created, tmp is None)
            raise
        table = read_results(path) if (load or plots or tmp is not None) else None
        if plots:
            from ...plot.sweep import write_figures
            write_figures(path, table, manifest)
        return SweepResult(table=table, path=None if tmp else path, manifest=manifest,
                           **result)
    finally:
        if tmp is not None:
            tmp.cleanup()


def _plan(scenario, spec: SweepSpec, options: SweepOptions):
    """The scenario with the solver options, the design of the runs (checked against the
    limits) and the manifest that identifies the sweep."""
    from ..._version import __version__
    from ...scenario import resolve_scenario
    from ...scenario.loader import with_solver_options
    scenario = resolve_scenario(scenario, list(spec.overrides) or None)
    solver_items = dict(spec.solver_options or {})
    try:
        scenario = with_solver_options(scenario, solver_items)
    except (TypeError, ValueError) as exc:
        raise SweepError(f"--option: {exc}") from None
    model = spec.model
    if model is None and scenario.models:
        model = scenario.models[0]
    given = spec.design is not None
    if given and (spec.vary or spec.samples is not None or spec.seed is not None):
        raise SweepError("give either a design or vary/samples/seed, not both")
    vary = {} if given else parse_vary(spec.vary)
    metrics = tuple(DEFAULT_METRICS if spec.metrics is None else spec.metrics)
    for m in metrics:
        if m not in METRICS:
            from ...scenario.schema import suggest
            raise SweepError(f"metric {m!r} is not known{suggest(m, METRICS)} (metrics: "
                             f"{', '.join(METRICS)})")
    if len(set(metrics)) != len(metrics):
        raise SweepError(f"metrics listed twice: {', '.join(metrics)}")
    if given:
        from ..._util import check_run_count
        design = spec.design
        if options.max_runs is not None:
            check_run_count(design.n, options.max_runs)
        probes = {k: sorted({float(np.min(c)), float(np.max(c))}) if len(c) else []
                  for k, c in design.columns.items()}
        spec_texts = {k: "design" for k in design.keys}
    else:
        design = make_design(vary, spec.samples, spec.seed, max_runs=options.max_runs)
        probes = {k: _probe_values(s) for k, s in vary.items()}
        spec_texts = {k: s.text() for k, s in vary.items()}
    rows = options.max_output_rows if options.max_output_rows is not None else 2**62
    check_run_size(scenario.estimate(model), scenario.options,
                   what=f"{scenario.file}: {model or 'its own model'}", max_rows=rows)
    _check_keys(scenario, probes, model, rows, solver_items)
    identity = {"format": FORMAT, "scenario": scenario.data, "model": model,
                "vary": spec_texts, "samples": spec.samples if design.random_keys else None,
                "seed": spec.seed if design.random_keys else None, "metrics": list(metrics),
                "keep_traces": bool(spec.keep_traces)}
    if given:
        identity["design"] = design.digest()
    if solver_items:        # (absent when not given: the ids of earlier sweeps hold)
        identity["options"] = solver_items
    sweep_id = digest(identity)
    units = {k: key_unit(scenario.data, k) for k in design.keys}
    manifest = {"format": FORMAT, "sweep_id": sweep_id, "scenario_name": scenario.name,
                "scenario_file": scenario.file, "scenario_sha": digest(scenario.data),
                "model": model, "vary": spec_texts, "keys": list(design.keys),
                "grid_keys": list(design.grid_keys), "random_keys": list(design.random_keys),
                "samples": identity["samples"], "seed": identity["seed"],
                "metrics": list(metrics), "keep_traces": bool(spec.keep_traces), "units": units,
                "options": solver_items,
                "runs": design.n,
                "chunk_size": options.chunk_size or _default_chunk_size(design.n),
                "clutchsim": __version__}
    return scenario, design, manifest


def _after_failure(path: Path, created: bool, keep: bool) -> None:
    """A sweep stopped early: say how to resume, or remove a directory holding nothing."""
    import shutil
    chunks = list((path / "chunks").glob("chunk-*.parquet")) if path.is_dir() else []
    if chunks and keep:
        log.warning("sweep stopped: %d finished chunks are kept in %s; re-run the same "
                    "command to resume", len(chunks), path)
    elif created:
        shutil.rmtree(path, ignore_errors=True)


def _resume_chunk_size(path: Path, manifest: dict) -> None:
    """On resume, cut the chunks as the first attempt did."""
    import json
    mf = path / "sweep.json"
    if mf.exists():
        try:
            old = json.loads(mf.read_text(encoding="utf-8"))
        except ValueError:
            return
        if old.get("sweep_id") == manifest["sweep_id"]:
            manifest["chunk_size"] = old.get("chunk_size", manifest["chunk_size"])


def _execute(store, scenario, design, manifest, options: SweepOptions, progress) -> dict:
    t0 = time.perf_counter()
    backend, workers, address = options.backend, options.workers, options.address
    size = manifest["chunk_size"]
    n_chunks = math.ceil(design.n / size)
    sid = manifest["sweep_id"]

    def chunk(index):
        lo = index * size
        return [(i, design.row(i)) for i in range(lo, min(lo + size, design.n))]

    ids, todo, done_runs = [], [], 0
    for index in range(n_chunks):
        runs = chunk(index)
        cid = chunk_id(sid, runs)
        ids.append((index, cid))
        if store.has_chunk(index, cid):
            done_runs += len(runs)
        else:
            todo.append(index)
    skipped = n_chunks - len(todo)
    log.info("sweep: %d runs in %d chunks of <= %d%s", design.n, n_chunks, size,
             f" ({skipped} chunks already done, resuming)" if skipped else "")
    job = {"sweep_id": sid, "data": scenario.data, "text": scenario.text,
           "file": scenario.file, "model": manifest["model"], "keys": design.keys,
           "metrics": tuple(manifest["metrics"]), "keep_traces": manifest["keep_traces"],
           "max_output": options.max_output_rows, "options": manifest["options"]}
    counts: dict = {}
    outcomes: dict = {}
    state = {"done": done_runs, "warned": 0, "batched": 0, "loop": 0.0}

    def done(index, out):
        store.write_chunk(index, ids[index][1], out)
        cols = out["columns"]
        for status, outcome, warnings in zip(cols["status"], cols["outcome"],
                                             cols["warnings"]):
            counts[status] = counts.get(status, 0) + 1
            outcomes[outcome] = outcomes.get(outcome, 0) + 1
            state["warned"] += bool(warnings)
        state["done"] += out["n"]
        state["batched"] += out.get("batched", 0)
        state["loop"] += out.get("batch_loop_wall_s", 0.0)
        if progress is not None:
            progress(state["done"], design.n)

    items = ((index, chunk(index)) for index in todo)
    if todo:
        if backend == "threads":
            run_threads(job, items, done, workers)
        elif backend == "dask" or hasattr(backend, "submit"):
            client, owned = (backend, False) if hasattr(backend, "submit") else \
                dask_client(address, workers, options.connect_timeout)
            try:
                run_dask(job, items, done, client, workers if owned else None)
            finally:
                if owned:
                    cluster = client.cluster if address == "local" else None
                    client.close()
                    if cluster is not None:
                        cluster.close()
        else:
            raise SweepError(f"backend {backend!r}: expected 'threads', 'dask' or a "
                             "distributed.Client")
    store.assemble(ids)
    if skipped:
        counts, outcomes, state["warned"] = _count_statuses(store.path)
    return {"runs": design.n, "chunks": n_chunks, "chunks_skipped": skipped,
            "wall_s": time.perf_counter() - t0, "status_counts": counts,
            "outcome_counts": outcomes, "runs_with_warnings": state["warned"],
            "batched_runs": state["batched"], "batch_loop_wall_s": state["loop"]}


def _count_statuses(path: Path) -> tuple[dict, dict, int]:
    """Status and outcome counts and the runs with warnings, from results.parquet."""
    import pyarrow.compute as pc
    import pyarrow.parquet as pq
    table = pq.read_table(path / "results.parquet", columns=["status", "outcome", "warnings"])

    def count(name):
        return {d["values"]: d["counts"] for d in pc.value_counts(table[name]).to_pylist()}
    warned = int(pc.sum(pc.greater(pc.list_value_length(table["warnings"]), 0)).as_py() or 0)
    return count("status"), count("outcome"), warned
