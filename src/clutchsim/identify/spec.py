"""TOML fit specifications: data file, column mapping and units, plant, model, parameters.

A specification describes one fit completely, so that the command line and a script run the
same thing.  Layout (every table but ``[data]`` and ``[fit]`` optional)::

    [data]
    file = "DATA_EMPS.mat"          # relative to the TOML file; CSV, NPZ or MAT
    time = "t"
    columns = {q = "qm", q_ref = "qg"}   # new name = column in the file
    scale = {}                      # unit factors per new name
    tare = []                       # columns from which the first value is subtracted
    nan = "error"                   # or "drop", "interpolate"
    window = [0.0, 24.84]           # optional time window [s]

    [plant]
    kind = "emps"                   # rig-force, rig-velocity, emps
    options = {M = 95.11}

    [fit]
    model = "lugre"                 # default model (the CLI's --model overrides it)
    input = "q_ref"
    output = "q"
    starts = 1

    [solver]                        # optional, the keys of a scenario's [solver] table:
    method = "dopri5"               # integrator (default the core's, rodas4)
    rtol = 1e-8                     # options over identify.FIT_SOLVER_DEFAULTS (atol from
    wall_time = 30.0                # the output scale unless given)

    [models.lugre]                  # per model: start values, fitted parameters, bounds
    start = {F_c = 20.0, ...}
    params = ["F_c", "sigma2", "M", "offset"]
    bounds = {F_c = [1.0, 100.0]}
    fixed = {}

    [validate]                      # optional: other records, same mapping
    files = ["other.mat"]
    initial = "rest"                # or "fit-end" (the whole state at the fit's end), or
    #                                 [z, ...] (the model's states)
    warmup = 0.0                    # [s] simulated at the start, not compared

Measured inputs beyond the drive signal, one table per column (after mapping and derived)::

    [inputs.F_pulse]
    to = "force"                    # force, controller (emps) or scale (rig kinds)
    gain = 1.0
    unit = "N"

Derived columns (``[data] derived``), by the grammar of :mod:`clutchsim.data.column_expr`,
computed on the whole file before the window::

    derived = { s = { expr = "(F_act1 + F_act2) / 60.0", unit = "-" } }   # or s = "expr"

Several records fitted at once replace ``[data] file`` (the mapping stays in ``[data]``)::

    [[records]]
    file = "a.npz"
    window = [0.0, 10.0]            # optional
    weight = 1.0                    # optional

with ``[fit] per_record = ["offset"]`` for plant parameters fitted once per record.  Errors
name the spec file, the line and the key.
"""


from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from .._util import toml_line
from ..core import SolverOptions
from ..core.options import check_solver
from ..core.system import closest
from ..data import Measurement, read_measurements
from ..friction import get_model_class, make_model
from ..friction.base import FrictionModel
from .plants import INPUT_TARGETS, InputSpec, PlantSpec, absent_input

__all__ = ["FitSpec", "load_spec"]

_TABLES = {"data": ("file", "time", "columns", "scale", "tare", "nan", "window", "units",
                    "derived"),
           "plant": ("kind", "options"),
           "fit": ("model", "input", "output", "signal", "starts", "seed", "max_nfev",
                   "diff_step", "tol", "per_record"),
           "solver": ("method", *SolverOptions.MAPPING_KEYS),
           "validate": ("files", "window", "initial", "warmup"),
           "inputs": None,
           "records": None,
           "models": None}
_INPUT_KEYS = ("to", "gain", "unit")
_RECORD_KEYS = ("file", "window", "weight")


def _key_path(table: str):
    """The key path of a table named as in messages: ``"inputs.F"``, ``"records"`` (the
    first ``[[records]]``) or ``"records#k"`` (the k-th, 0-based)."""
    name, _, nth = table.partition("#")
    return [(name, int(nth))] if nth else name


@dataclass(frozen=True, eq=False)
class FitSpec:
    """A parsed fit specification (paths resolved)."""

    path: Path
    data: dict
    plant: PlantSpec
    fit: dict
    models: dict
    validate: dict = field(default_factory=dict)
    #: the [solver] table (checked on load): ``method`` and the solver options
    solver: dict = field(default_factory=dict)
    inputs: tuple = ()
    records: tuple = ()
    text: str = ""

    def where(self, table: str, key: str | None = None) -> str:
        """``"FILE:LINE: [table] key"`` for messages."""
        line = toml_line(self.text, _key_path(table), key)
        shown = (f"[[{table.partition('#')[0]}]] #{int(table.partition('#')[2] or 0) + 1}"
                 if table.startswith("records") else f"[{table}]")
        return f"{self.path}" + (f":{line}" if line else "") + f": {shown}" + \
            (f" {key}" if key else "")

    def read(self, file: str | Path | None = None, window=None) -> Measurement:
        """Read the spec's data file (or ``file`` with the same mapping), derived columns
        computed, then the window applied."""
        d = self.data
        m = read_measurements(file or d["file"], time=d.get("time", "t"),
                              columns=d.get("columns"), scale=d.get("scale"),
                              units=d.get("units"), tare=d.get("tare", ()),
                              nan=d.get("nan", "error"),
                              optional=[i.column for i in self.inputs])
        m = self._derive(m)
        window = window if window is not None else (d.get("window") if file is None else None)
        return m.window(*window) if window else m

    def _derive(self, m: Measurement) -> Measurement:
        from ..data.column_expr import evaluate_column
        for name, entry in dict(self.data.get("derived", {})).items():
            expr, unit = (entry, "") if isinstance(entry, str) else \
                (entry.get("expr"), str(entry.get("unit", "")))
            try:
                values = evaluate_column(expr, {"t": m.t, **m.columns})
            except ValueError as exc:
                raise ValueError(f"{self.where('data', name)}: {exc} (in {m.source})") from None
            m = m.with_column(name, values, unit)
        return m

    def fit_data(self, window=None) -> list[Measurement]:
        """The fitting records: ``[data] file``, or every ``[[records]]`` with its window.

        ``window`` (the CLI's --window) overrides every record's own window.  Their sampling
        intervals are checked; the declared inputs are checked by :meth:`check_inputs`, once
        the validation records are read too."""
        if self.records:
            out = [self.read(r["file"], window if window is not None else r.get("window"))
                   for r in self.records]
        else:
            out = [self.read(window=window)]
        self._check_rates(out)
        return out

    def weights(self) -> list[float] | None:
        if not self.records:
            return None
        return [float(r.get("weight", 1.0)) for r in self.records]

    def _check_rates(self, records) -> None:
        import numpy as np
        dts = [float(np.median(np.diff(m.t))) for m in records]
        for k, (m, dt) in enumerate(zip(records, dts)):
            if abs(dt - dts[0]) > 0.01 * dts[0]:
                raise ValueError(
                    f"{self.where(f'records#{k}', 'file')}: {m.source} is sampled every "
                    f"{dt:.6g} s, {records[0].source} every {dts[0]:.6g} s; records of one "
                    "fit must share the sampling interval (refused, not resampled: resample "
                    "the files to one rate)")

    def check_inputs(self, fitting, validation=()) -> None:
        """Every declared input column must be in at least one record, fitting or validation
        (:func:`~clutchsim.identify.plants.absent_input`); the error names this file, the
        line and the ``[inputs.COLUMN]`` table."""
        absent = absent_input(self.inputs, fitting, validation)
        if absent:
            raise ValueError(f"{self.where('inputs.' + absent[0].column)}: {absent[1]}")

    def validation_data(self) -> list[Measurement]:
        return [self.read(f, self.validate.get("window")) for f in self.validate.get("files", [])]

    def validation_initial(self, model: FrictionModel):
        """``[validate] initial`` checked against ``model`` (None: rest)."""
        import numpy as np
        init = self.validate.get("initial")
        if init is None or init == "rest":
            return None
        if isinstance(init, str):
            if init != "fit-end":
                raise ValueError(f"{self.where('validate', 'initial')} = {init!r} must be "
                                 "'rest', 'fit-end' or a list of the model's states")
            return init
        z = np.asarray(init, dtype=float).ravel() if isinstance(init, list) else None
        if z is None or z.size != model.n_states:
            n = "?" if z is None else z.size
            raise ValueError(f"{self.where('validate', 'initial')} has {n} entries; "
                             f"{model.name} has {model.n_states} state(s) "
                             f"({', '.join(model.state_names()) or 'none'})")
        return z

    def model_entry(self, name: str | None) -> tuple[FrictionModel, dict]:
        """The start model and its ``[models.NAME]`` entry (params, bounds, fixed)."""
        name = name or self.fit.get("model")
        if not name:
            raise ValueError(f"{self.path}: no model: give --model or [fit] model")
        get_model_class(name)
        entry = dict(self.models.get(name, {}))
        unknown = [k for k in entry if k not in ("start", "params", "bounds", "fixed",
                                                 "parameter_set")]
        if unknown:
            raise ValueError(f"{self.path}: [models.{name}] unknown key(s) "
                             f"{', '.join(unknown)}; keys: start, params, bounds, fixed, "
                             "parameter_set")
        start = dict(entry.get("start", {}))
        cls = get_model_class(name)
        model_start = {k: (tuple(v) if isinstance(v, list) else v)
                       for k, v in start.items() if k in cls.parameter_info}
        plant_start = {k: v for k, v in start.items() if k not in cls.parameter_info}
        try:
            model = make_model(name, entry.get("parameter_set"), **model_start)
        except TypeError as exc:
            raise ValueError(f"{self.path}: [models.{name}] start: {exc}") from None
        entry["plant_start"] = plant_start
        return model, entry


def _check_keys(path, table, keys, allowed):
    for key in keys:
        if key not in allowed:
            raise ValueError(f"{path}: [{table}] unknown key {key!r}{closest(key, allowed)}; "
                             f"keys: {', '.join(allowed)}")


def load_spec(path: str | Path) -> FitSpec:
    """Read and check a TOML fit specification."""
    path = Path(path)
    try:
        text = path.read_text()
        doc = tomllib.loads(text)
    except OSError as exc:
        raise ValueError(f"{path}: cannot read fit specification ({exc.strerror})") from None
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: invalid TOML ({exc})") from None
    _check_keys(path, "top level", doc, _TABLES)
    moved = [k for k in ("solver", "rtol", "atol", "wall_time") if k in doc.get("fit", {})]
    if moved:
        line = toml_line(text, "fit", moved[0])
        raise ValueError(f"{path}{f':{line}' if line else ''}: [fit] {moved[0]}: the "
                         "integrator and its options are written in a [solver] table, as in "
                         f"a scenario (keys: {', '.join(_TABLES['solver'])}; the integrator "
                         "is method = \"NAME\")")
    for table, allowed in _TABLES.items():
        if allowed is not None and table in doc:
            _check_keys(path, table, doc[table], allowed)
    for table in ("data", "fit"):
        if table not in doc:
            raise ValueError(f"{path}: missing table [{table}]")
    data = dict(doc["data"])
    if "file" not in data and not doc.get("records"):
        raise ValueError(f"{path}: [data] needs file = \"...\" (or give [[records]])")
    if "file" in data:
        data["file"] = _resolve(path, data["file"])
    fitd = dict(doc["fit"])
    for key in ("input", "output"):
        if key not in fitd:
            raise ValueError(f"{path}: [fit] needs {key} = \"column\"")
    plant = doc.get("plant", {})
    spec = PlantSpec(plant.get("kind", "rig-force"), dict(plant.get("options", {})))
    validate = dict(doc.get("validate", {}))
    validate["files"] = [_resolve(path, f) for f in validate.get("files", [])]
    solver = dict(doc.get("solver", {}))
    partial = FitSpec(path, data, spec, fitd, {}, validate, solver, text=text)
    for key, value in solver.items():       # each value, with its line (the fit reads
        try:                                # them again, all at once)
            if key == "method":
                check_solver(value)
            else:
                SolverOptions.from_mapping({key: value})
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{partial.where('solver', key)}: {exc}") from None
    if not isinstance(data.get("derived", {}), dict):
        raise ValueError(  # noqa: TRY004
            f"{partial.where('data', 'derived')}: must be a table name = "
            "\"expression\" or name = {{ expr = \"...\", unit = \"...\" }}")
    for name, entry in data.get("derived", {}).items():
        if not (isinstance(entry, str) or (isinstance(entry, dict) and "expr" in entry
                                           and set(entry) <= {"expr", "unit"})):
            raise ValueError(f"{partial.where('data', name)}: derived column {name!r} must be "
                             "\"expression\" or { expr = \"...\", unit = \"...\" }")
    if "warmup" in validate and not (isinstance(validate["warmup"], (int, float))
                                     and validate["warmup"] >= 0):
        raise ValueError(f"{partial.where('validate', 'warmup')} = {validate['warmup']!r} "
                         "must be a number of seconds >= 0")
    inputs = []
    for name, entry in dict(doc.get("inputs", {})).items():
        where = partial.where(f"inputs.{name}")
        if not isinstance(entry, dict):
            raise ValueError(  # noqa: TRY004
                f"{where}: must be a table with to = \"force\" (or controller, scale), gain, "
                "unit")
        bad = [k for k in entry if k not in _INPUT_KEYS]
        if bad or "to" not in entry:
            raise ValueError(f"{where}: " + (f"unknown key {bad[0]!r}; keys: "
                                             f"{', '.join(_INPUT_KEYS)}" if bad else
                                             "needs to = \"force\", \"controller\" or "
                                             "\"scale\""))
        try:
            inp = InputSpec(name, str(entry["to"]), entry.get("gain", 1.0),
                            str(entry.get("unit", "")))
        except ValueError as exc:
            raise ValueError(f"{partial.where(f'inputs.{name}', 'to')}: {exc}") from None
        if inp.to not in INPUT_TARGETS[spec.kind]:
            raise ValueError(f"{partial.where(f'inputs.{name}', 'to')}: to = {inp.to!r} is not "
                             f"available for plant {spec.kind!r}; targets: "
                             f"{', '.join(INPUT_TARGETS[spec.kind])}")
        inputs.append(inp)
    records = []
    raw_records = doc.get("records", [])
    if not isinstance(raw_records, list):
        raise ValueError(  # noqa: TRY004
            f"{partial.where('records')}: write each record as [[records]]")
    for k, r in enumerate(raw_records):
        bad = [key for key in r if key not in _RECORD_KEYS]
        if bad or "file" not in r:
            raise ValueError(f"{partial.where(f'records#{k}', bad[0] if bad else None)}: "
                             + (f"unknown key {bad[0]!r}; keys: {', '.join(_RECORD_KEYS)}"
                                if bad else "needs file = \"...\""))
        rec = dict(r)
        rec["file"] = _resolve(path, r["file"])
        if "weight" in r and not (isinstance(r["weight"], (int, float)) and r["weight"] >= 0):
            raise ValueError(f"{partial.where(f'records#{k}', 'weight')} = {r['weight']!r} "
                             "must be a number >= 0")
        records.append(rec)
    return FitSpec(path, data, spec, fitd, dict(doc.get("models", {})), validate, solver,
                   tuple(inputs), tuple(records), text)


def _resolve(spec_path: Path, file: str) -> Path:
    """A data path relative to the spec; ``${CLUTCHSIM_SHARED}`` expands to the shared dir."""
    from ..data.shared import shared_dir
    text = str(file)
    if "${CLUTCHSIM_SHARED}" in text:
        text = text.replace("${CLUTCHSIM_SHARED}", str(shared_dir()))
    p = Path(text)
    return p if p.is_absolute() else (spec_path.parent / p).resolve()
