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
    solver = "dopri5"
    rtol = 1e-8
    starts = 1

    [models.lugre]                  # per model: start values, fitted parameters, bounds
    start = {F_c = 20.0, ...}
    params = ["F_c", "sigma2", "M", "offset"]
    bounds = {F_c = [1.0, 100.0]}
    fixed = {}

    [validate]                      # optional: other records, same mapping
    files = ["other.mat"]
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..core.system import closest
from ..data import Measurement, read_measurements
from ..friction import get_model_class, make_model
from ..friction.base import FrictionModel
from .plants import PlantSpec

__all__ = ["FitSpec", "load_spec"]

_TABLES = {"data": ("file", "time", "columns", "scale", "tare", "nan", "window", "units"),
           "plant": ("kind", "options"),
           "fit": ("model", "input", "output", "signal", "solver", "rtol", "atol", "starts",
                   "seed", "max_nfev", "diff_step", "wall_time", "tol"),
           "validate": ("files", "window"),
           "models": None}


@dataclass(frozen=True, eq=False)
class FitSpec:
    """A parsed fit specification (paths resolved)."""

    path: Path
    data: dict
    plant: PlantSpec
    fit: dict
    models: dict
    validate: dict = field(default_factory=dict)

    def read(self, file: str | Path | None = None, window=None) -> Measurement:
        """Read the spec's data file (or ``file`` with the same mapping)."""
        d = self.data
        m = read_measurements(file or d["file"], time=d.get("time", "t"),
                              columns=d.get("columns"), scale=d.get("scale"),
                              units=d.get("units"), tare=d.get("tare", ()),
                              nan=d.get("nan", "error"))
        window = window if window is not None else (d.get("window") if file is None else None)
        return m.window(*window) if window else m

    def validation_data(self) -> list[Measurement]:
        return [self.read(f, self.validate.get("window")) for f in self.validate.get("files", [])]

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
        doc = tomllib.loads(path.read_text())
    except OSError as exc:
        raise ValueError(f"{path}: cannot read fit specification ({exc.strerror})") from None
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: invalid TOML ({exc})") from None
    _check_keys(path, "top level", doc, _TABLES)
    for table, allowed in _TABLES.items():
        if allowed is not None and table in doc:
            _check_keys(path, table, doc[table], allowed)
    for table in ("data", "fit"):
        if table not in doc:
            raise ValueError(f"{path}: missing table [{table}]")
    data = dict(doc["data"])
    if "file" not in data:
        raise ValueError(f"{path}: [data] needs file = \"...\"")
    data["file"] = _resolve(path, data["file"])
    fitd = dict(doc["fit"])
    for key in ("input", "output"):
        if key not in fitd:
            raise ValueError(f"{path}: [fit] needs {key} = \"column\"")
    plant = doc.get("plant", {})
    spec = PlantSpec(plant.get("kind", "rig-force"), dict(plant.get("options", {})))
    validate = dict(doc.get("validate", {}))
    validate["files"] = [_resolve(path, f) for f in validate.get("files", [])]
    return FitSpec(path, data, spec, fitd, dict(doc.get("models", {})), validate)


def _resolve(spec_path: Path, file: str) -> Path:
    """A data path relative to the spec; ``${CLUTCHSIM_SHARED}`` expands to the shared dir."""
    from ..data.shared import shared_dir
    text = str(file)
    if "${CLUTCHSIM_SHARED}" in text:
        text = text.replace("${CLUTCHSIM_SHARED}", str(shared_dir()))
    p = Path(text)
    return p if p.is_absolute() else (spec_path.parent / p).resolve()
