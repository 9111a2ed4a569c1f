#!/usr/bin/env python
"""Reproduce the real-data identification tables and figures of docs/identification.md.

    python scripts/validate_real_data.py                # all three data sets
    python scripts/validate_real_data.py --only emps    # one of emps, brfd, brfd-loads, tribo

Reads the shared data sets ($CLUTCHSIM_SHARED, or ../shared next to the repository; they
are never copied into the repository), fits the models, and writes
docs/identification/*.png, docs/identification/results.json and the generated block of
docs/identification.md (between the BEGIN/END GENERATED markers).  Wall times depend on
the machine and its load; they are measured, not promised.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from clutchsim.core.options import DEFAULT_METHOD
from clutchsim.data import moving_average, read_measurements, shared_dir
from clutchsim.friction import make_model
from clutchsim.identify import FitOptions, FitProblem, evaluate, fit, load_spec
from clutchsim.identify.parameters import apply_to_model
from clutchsim.plot._style import new_figure, save_png
from clutchsim.plot.fit import plot_fit, plot_loop, plot_residuals

OUT = ROOT / "docs" / "identification"
DOC = ROOT / "docs" / "identification.md"
BEGIN, END = "<!-- BEGIN GENERATED -->", "<!-- END GENERATED -->"
BRFD_NOTE = ("Tables and figures derived from the BRFD data (Coble, Huggins, Cao, Ricles, "
             "Downey, *Dataset-Friction-Damper-with-Backlash*, ARTS Lab, GitHub, 2022) are "
             "licensed CC BY-SA 4.0 (https://creativecommons.org/licenses/by-sa/4.0/).")


def _fmt(value, digits=4):
    return "undetermined" if value is None else f"{value:.{digits}g}"


def _params(res, digits=4):
    return ", ".join(f"{k} = {_fmt(v, digits)} ± {_fmt(res.stderr.get(k), 2)}"
                     for k, v in res.parameters.items())


# ---------------------------------------------------------------- EMPS
def run_emps(log) -> dict:
    spec = load_spec(ROOT / "examples" / "fit_emps.toml")
    data = spec.read()
    f = spec.fit
    # the spec's [solver] table: the integrator and the options of every simulation
    common = dict(input=f["input"], output=f["output"], plant="emps",
                  solver=spec.solver.get("method", DEFAULT_METHOD),
                  options={k: v for k, v in spec.solver.items() if k != "method"})
    columns, solving = _fit_common(common, f)
    rows = []
    # the authors' IDIM values, simulated in our closed loop (no fit)
    published = make_model("tanh", F_c=20.39, v_t=1e-3, sigma2=203.5)
    for tau in (0.0, 0.00164):
        tr = evaluate(published, data, plant_options={"M": 95.11, "offset": -3.165,
                                                      "tau_v": tau, "voltage": "vir"},
                      **common)
        rows.append({"case": f"published IDIM values (tau_v = {tau * 1e3:g} ms), no fit",
                     "model": "tanh", "parameters": "F_c = 20.39, sigma2 = 203.5, M = 95.11, "
                     "offset = -3.165", "nrmse": tr.nrmse, **tr.metrics, "time_s": None,
                     "evaluations": 0})
    fits = {}

    def one(case, name, params=None, plant=None, fixed_plant=True):
        model, entry = spec.model_entry(name)
        opts = dict(spec.plant.options)
        if not fixed_plant:
            opts.update(entry["plant_start"])
        opts.update(plant or {})
        params = params or list(entry["params"])
        bounds = {k: tuple(v) for k, v in entry.get("bounds", {}).items() if k in params}
        res = fit(model, data, FitProblem(params=params, bounds=bounds, plant_options=opts,
                                          **columns), FitOptions(**solving))
        fits[case] = res
        rows.append({"case": case, "model": name, "parameters": _params(res),
                     "nrmse": res.nrmse_fit, **res.fit_trace.metrics,
                     "time_s": res.wall_time, "evaluations": res.evaluations,
                     "at_bound": list(res.at_bound)})
        log(f"EMPS {case}: {_params(res)}; NRMSE {res.nrmse_fit:.4g}; "
            f"{res.wall_time:.1f} s")
        return res

    cv0 = one("Coulomb + viscous, no velocity lag", "tanh",
              ["F_c", "sigma2", "M", "offset"], {"tau_v": 0.0, "M": 95.0, "offset": 0.0})
    cv = one("Coulomb + viscous, with velocity lag", "tanh", fixed_plant=False)
    cvm = one("Coulomb + viscous, M held at 95.11 kg", "tanh", ["F_c", "sigma2", "offset",
                                                                 "tau_v"],
              {"M": 95.11, "offset": 0.0, "tau_v": 0.0015})
    held = {k: cv.parameters[k] for k in ("M", "offset", "tau_v")}
    dyn = {}
    for name in ("lugre", "gms", "mykhailevych2020"):
        dyn[name] = one(f"{name}, plant from the C+V fit", name, plant=held)
    for case, res in (("cv", cv), ("lugre", dyn["lugre"])):
        fig, _, _ = plot_fit(res, unit="m")
        save_png(fig, OUT / f"emps_{case}_fit.png")
        fig, _, _ = plot_residuals(res, unit="m")
        save_png(fig, OUT / f"emps_{case}_residuals.png")
    del cv0, cvm
    return {"rows": rows, "held_plant": held, "cross": _emps_cross(spec, data, common, log)}


#: the reference reverses at q = 0 (a momentary standstill) here: the two halves of the record
EMPS_SPLIT = 12.464
EMPS_CV = {"tanh": ["F_c", "sigma2", "M", "offset", "tau_v"]}


def _fit_common(common: dict, f: dict) -> tuple[dict, dict]:
    """``common`` (evaluate's keywords) as FitProblem's and FitOptions' keywords."""
    columns = {k: common[k] for k in ("input", "output", "plant")}
    solving = {"solver": common["solver"], "solver_options": common["options"],
               "tol": float(f.get("tol", 1e-8))}
    return columns, solving


def _emps_cross(spec, data, common, log) -> list[dict]:
    """Two-fold cross-validation on the estimation record (the benchmark's validation record
    is held out): fit on one half, simulate the other.  The second half continues the first,
    so it starts from the friction state at the first half's end (``"fit-end"``; the drive is
    at a reversal there, q_ref at rest); the first half starts at rest.  C+V is fitted with the
    mass, offset and velocity lag; the dynamic models hold that fold's C+V plant."""
    halves = {"first": data.window(None, EMPS_SPLIT), "second": data.window(EMPS_SPLIT, None)}
    columns, solving = _fit_common(common, spec.fit)
    rows = []
    for fold, other, initial in (("first", "second", "fit-end"), ("second", "first", "rest")):
        plant = dict(spec.plant.options)
        for name in ("tanh", "lugre", "gms", "mykhailevych2020"):
            model, entry = spec.model_entry(name)
            params = EMPS_CV.get(name) or list(entry["params"])
            opts = {**plant, **(entry["plant_start"] if name == "tanh" else {})}
            bounds = {k: tuple(v) for k, v in entry.get("bounds", {}).items() if k in params}
            res = fit(model, halves[fold], FitProblem(params=params, bounds=bounds,
                                                      plant_options=opts, **columns),
                      FitOptions(**solving), validate=[halves[other]], validate_initial=initial)
            if name == "tanh":
                plant.update({k: res.parameters[k] for k in ("M", "offset", "tau_v")})
            val = res.validation[0]
            rows.append({"fit_on": fold, "validate_on": other, "initial": initial,
                         "model": name, "parameters": dict(res.parameters),
                         "nrmse_fit": res.nrmse_fit, "nrmse_validation": val.nrmse,
                         "force_error_pct_fit": res.fit_trace.metrics.get("force_error_pct"),
                         "force_error_pct_validation": val.metrics.get("force_error_pct"),
                         "time_s": res.wall_time, "evaluations": res.evaluations})
            log(f"EMPS cross-validation {name}, fit on the {fold} half: NRMSE fit "
                f"{res.nrmse_fit:.4g}, {other} half {val.nrmse:.4g}; {res.wall_time:.1f} s")
    return rows


# ---------------------------------------------------------------- BRFD
BRFD_FIT = "dataset-2_characterization_0.5Hz30lbtension1amplitude.npz"
BRFD_SMOOTH = 1
BRFD_MODELS = {
    "dahl": (dict(F_c=1.2e4, sigma0=1e7, alpha=1.0), ["F_c", "sigma0", "alpha", "offset"],
             {"F_c": (1e3, 5e4), "sigma0": (1e5, 1e9), "alpha": (0.2, 5.0)}),
    "lugre": (dict(F_c=1.0e4, F_s=1.5e4, v_s=0.01, sigma0=1e7, sigma1=1e4, sigma2=1e4),
              ["F_c", "F_s", "v_s", "sigma0", "sigma2", "offset"],
              {"F_c": (1e3, 5e4), "F_s": (1e3, 5e4), "v_s": (1e-4, 1.0),
               "sigma0": (1e5, 1e9), "sigma2": (1.0, 1e6)}),
    "gms": (dict(k=(1e7, 2e6), alpha=(0.5, 0.5), C=1e5, F_c=1.0e4, F_s=1.2e4, v_s=0.01,
                 sigma1=0.0, sigma2=1e4),
            ["k[0]", "k[1]", "F_c", "F_s", "v_s", "sigma2", "offset"],
            {"k[0]": (1e5, 1e9), "k[1]": (1e5, 1e9), "F_c": (1e3, 5e4), "F_s": (1e3, 5e4),
             "v_s": (1e-4, 1.0), "sigma2": (1.0, 1e6)}),
    "mykhailevych2020": (dict(T_stat=1.2e4, k_din=0.9, phi0=1e-3, omega0=0.01, k_v=1e4),
                         ["T_stat", "k_din", "phi0", "omega0", "k_v", "offset"],
                         {"T_stat": (1e3, 5e4), "k_din": (0.05, 1.0), "phi0": (1e-5, 1e-2),
                          "omega0": (1e-4, 1.0), "k_v": (1.0, 1e6)}),
}


def _brfd(path: Path, n_ref: float | None):
    m = read_measurements(path, columns=["x", "F", "F_act1", "F_act2"],
                          scale={"x": 0.0254, "F": 4448.222, "F_act1": 4.448222,
                                 "F_act2": 4.448222},
                          units={"x": "m", "F": "N", "F_act1": "N", "F_act2": "N"})
    # normal-load proxy: the two band actuators' forces, unfiltered (BRFD_SMOOTH samples of
    # moving average; averaging over 0.25 s was tried and raised every NRMSE)
    n = moving_average(m["F_act1"] + m["F_act2"], BRFD_SMOOTH)
    n_ref = n_ref or float(np.mean(n))
    return m.with_column("s", n / n_ref, "-"), n_ref


def _brfd_validation(index, fitted) -> list[dict]:
    """Every test not fitted whose band tension was measured (the 7 flagged 0 lb tests
    out)."""
    return [r for r in index if r["file"] not in fitted and r["tension_flagged"] != "True"]


def run_brfd(log) -> dict:
    folder = shared_dir() / "data" / "brfd_friction_damper"
    index = _index(folder / "index.csv")
    data, n_ref = _brfd(folder / BRFD_FIT, None)
    val_files = _brfd_validation(index, {BRFD_FIT})
    val = [_brfd(folder / r["file"], n_ref)[0] for r in val_files]
    plant = {"differentiate": True, "smooth": 9, "scale": "s"}
    out = {"licence": BRFD_NOTE, "fit_file": BRFD_FIT, "n_ref_N": n_ref, "models": {},
           "tests": []}
    for r in val_files:
        out["tests"].append({k: r[k] for k in ("file", "kind", "freq_hz", "amplitude_in",
                                               "tension_lb")})
    for name, (start, params, bounds) in BRFD_MODELS.items():
        res = fit(make_model(name, **start), data, FitProblem(input="x", output="F",
                  params=params, bounds=bounds, plant="rig-velocity", plant_options=plant),
                  FitOptions(starts=2, seed=0, tol=1e-6), validate=val)
        out["models"][name] = {"parameters": dict(res.parameters), "stderr": dict(res.stderr),
                               "nrmse_fit": res.nrmse_fit,
                               "nrmse_validation": [v.nrmse for v in res.validation],
                               "time_s": res.wall_time, "evaluations": res.evaluations}
        log(f"BRFD {name}: NRMSE fit {res.nrmse_fit:.3g}, validation mean "
            f"{res.nrmse_validation:.3g}; {res.wall_time:.1f} s")
        fig, axes = new_figure(1, 3, figsize=(13.0, 4.0))
        picks = [res.fit_trace] + [res.validation[i] for i, r in enumerate(val_files)
                                   if r["file"] in (
                                       "dataset-2_characterization_1Hz36lbtension1.5amplitude.npz",
                                       "dataset-4_semiactive_harmonic_harmonic0.03ea1forward.npz")]
        srcs = [data] + [val[i] for i, r in enumerate(val_files) if r["file"] in (
            "dataset-2_characterization_1Hz36lbtension1.5amplitude.npz",
            "dataset-4_semiactive_harmonic_harmonic0.03ea1forward.npz")]
        for ax, tr, m in zip(axes[0], picks, srcs):
            label = Path(tr.source).stem.replace("dataset-2_characterization_", "").replace(
                "dataset-4_semiactive_harmonic_", "semi-active ")
            plot_loop(tr, m["x"], ax=ax, title=f"{label}\nNRMSE {tr.nrmse:.3g}")
        fig.suptitle(f"BRFD, {name} fitted on {BRFD_FIT} (CC BY-SA 4.0 data)", fontsize=10)
        save_png(fig, OUT / f"brfd_{name}_loops.png")
    return out


BRFD_LOADS_SPEC = ROOT / "examples" / "fit_brfd_loads.toml"


def run_brfd_loads(log, single: dict | None = None) -> dict:
    """Shared parameters and the load fraction fitted to three tensions at once.

    With ``single`` (the one-record results of :func:`run_brfd`) each model starts from its
    one-record fit (and λ = 0.7): from the spec's own start values the joint Dahl fit ends in
    a local optimum (alpha ≈ 1) about twice as bad on every record."""
    spec = load_spec(BRFD_LOADS_SPEC)
    folder = shared_dir() / "data" / "brfd_friction_damper"
    index = _index(folder / "index.csv")
    records = spec.fit_data()
    fitted = {Path(r["file"]).name for r in spec.records}
    val_files = _brfd_validation(index, fitted)
    val = [spec.read(folder / r["file"]) for r in val_files]
    spec.check_inputs(records, val)
    out = {"licence": BRFD_NOTE, "fit_files": sorted(fitted), "models": {},
           "start": "the one-record fits" if single else "the spec's start values",
           "tests": [{k: r[k] for k in ("file", "kind", "freq_hz", "amplitude_in",
                                        "tension_lb")} for r in val_files]}
    for name in BRFD_MODELS:
        model, entry = spec.model_entry(name)
        params = list(entry["params"])
        if single and name in single.get("models", {}):
            model = apply_to_model(model, {k: v for k, v in
                                           single["models"][name]["parameters"].items()
                                           if k in params})
        res = fit(model, records, FitProblem(input=spec.fit["input"], output=spec.fit["output"],
                  params=params, bounds={k: tuple(v) for k, v in entry["bounds"].items()},
                  plant=spec.plant, per_record=spec.fit["per_record"], inputs=spec.inputs,
                  weights=spec.weights()), FitOptions(tol=float(spec.fit["tol"])), validate=val)
        out["models"][name] = {"parameters": dict(res.parameters), "stderr": dict(res.stderr),
                               "nrmse_fit": [r.nrmse for r in res.records],
                               "nrmse_pooled": res.nrmse_pooled,
                               "nrmse_validation": [v.nrmse for v in res.validation],
                               "time_s": res.wall_time, "evaluations": res.evaluations}
        log(f"BRFD loads {name}: load_fraction {res.parameters['load_fraction']:.3g}, pooled "
            f"NRMSE {res.nrmse_pooled:.3g}, validation mean {res.nrmse_validation:.3g}; "
            f"{res.wall_time:.1f} s")
    return out


def _index(path: Path) -> list[dict]:
    import csv
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


# ---------------------------------------------------------------- micro-tribometer
TRIBO_FIT = (8.5, 50.78)
TRIBO_VAL_FROM = 50.78
TRIBO_MODELS = {
    "dahl": (dict(F_c=2.2, sigma0=5e4, alpha=1.0), ["F_c", "sigma0", "alpha", "offset"],
             {"F_c": (0.5, 5.0), "sigma0": (1e3, 1e7), "alpha": (0.2, 5.0)}),
    "lugre": (dict(F_c=2.2, F_s=2.3, v_s=1e-4, sigma0=5e4, sigma1=10.0, sigma2=0.0),
              ["F_c", "F_s", "sigma0", "sigma1", "offset"],
              {"F_c": (0.5, 5.0), "F_s": (0.5, 5.0), "sigma0": (1e3, 1e7),
               "sigma1": (1e-2, 1e4)}),
    "elastoplastic": (dict(F_c=2.2, F_s=2.3, v_s=1e-4, sigma0=5e4, sigma1=10.0, sigma2=0.0,
                           z_ba=2e-5), ["F_c", "sigma0", "z_ba", "offset"],
                      {"F_c": (0.5, 5.0), "sigma0": (1e3, 1e7), "z_ba": (1e-7, 1e-3)}),
    "gms": (dict(k=(1e5, 3e4, 1e4), alpha=(0.3, 0.3, 0.4), C=10.0, F_c=2.2, F_s=2.2,
                 v_s=1e-4, sigma1=0.0, sigma2=0.0),
            ["k[0]", "k[1]", "k[2]", "F_c", "offset"],
            {"k[0]": (1e3, 1e7), "k[1]": (1e3, 1e7), "k[2]": (1e3, 1e7), "F_c": (0.5, 5.0)}),
    "mykhailevych2020": (dict(T_stat=2.3, k_din=0.95, phi0=3e-5, omega0=1e-4, k_v=0.0,
                              reset="clamp", reset_c=2.0),
                         ["T_stat", "phi0", "reset_c", "offset"],
                         {"T_stat": (0.5, 5.0), "phi0": (1e-7, 1e-3), "reset_c": (0.1, 10.0)}),
}


def run_tribo(log) -> dict:
    path = shared_dir() / "data" / "microtribometer_reciprocating" / \
        "reciprocating_5N_part1.txt"
    full = read_measurements(path, time="Time [s]",
                             columns={"N": "Normal [uN]", "x": "Position [mm]",
                                      "F": "Friction [uN]"},
                             scale={"N": 1e-6, "x": 1e-3, "F": -1e-6}, tare=["x"],
                             units={"N": "N", "x": "m", "F": "N"})
    full = full.with_column("s", full["N"] / 5.0, "-").window(TRIBO_FIT[0], None)
    data = full.window(*TRIBO_FIT)
    plant = {"differentiate": True, "smooth": 5, "scale": "s"}
    out = {"fit_window_s": list(TRIBO_FIT), "validation_from_s": TRIBO_VAL_FROM,
           "models": {}}
    later = full.window(TRIBO_VAL_FROM, None)
    for name, (start, params, bounds) in TRIBO_MODELS.items():
        try:
            # the later strokes continue the fit window: they start from its end state
            res = fit(make_model(name, **start), data, FitProblem(input="x", output="F",
                      params=params, bounds={**bounds, "offset": (-0.5, 0.5)},
                      plant="rig-velocity", plant_options=plant), FitOptions(tol=1e-6),
                      validate=[later], validate_initial="fit-end")
        except RuntimeError as exc:
            log(f"tribo {name}: failed: {exc}")
            out["models"][name] = {"error": str(exc)}
            continue
        model = res.model
        opts = {**plant, "offset": res.parameters["offset"]}
        val = res.validation[0].nrmse
        # the same strokes from rest, with one 4 s cycle simulated and discarded
        warm = evaluate(model, later, input="x", output="F", plant="rig-velocity",
                        plant_options=opts, warmup=4.0).nrmse
        whole = evaluate(model, full, input="x", output="F", plant="rig-velocity",
                         plant_options=opts)
        out["models"][name] = {"parameters": dict(res.parameters), "stderr": dict(res.stderr),
                               "nrmse_fit": res.nrmse_fit, "nrmse_validation": val,
                               "nrmse_validation_warmup": warm,
                               "time_s": res.wall_time, "evaluations": res.evaluations}
        log(f"tribo {name}: {_params(res)}; NRMSE fit {res.nrmse_fit:.3g}, later strokes "
            f"{val:.3g} (from rest after a 4 s warm-up {warm:.3g}); {res.wall_time:.1f} s")
        fig, axes = new_figure(1, 2, figsize=(11.0, 4.0), width_ratios=[2, 1])
        ax = axes[0, 0]
        ax.plot(whole.t, whole.measured, lw=0.6, color="0.2", label="measured")
        ax.plot(whole.t, whole.simulated, lw=0.6, color="C3", label="simulated")
        ax.axvline(TRIBO_VAL_FROM, color="0.5", ls="--", lw=0.8)
        ax.set_xlim(40, 66)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("friction force [N]")
        ax.set_title("end of fit window | later strokes (not fitted)", fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
        sel = (whole.t >= 90) & (whole.t <= 98)
        x = full["x"]
        axes[0, 1].plot(x[sel] * 1e6, whole.measured[sel], lw=0.7, color="0.2")
        axes[0, 1].plot(x[sel] * 1e6, whole.simulated[sel], lw=0.7, color="C3")
        axes[0, 1].set_xlabel("stage position [µm]")
        axes[0, 1].set_title("loops 90-98 s (not fitted)", fontsize=9)
        fig.suptitle(f"micro-tribometer, {name}: NRMSE fit {res.nrmse_fit:.3g}, later "
                     f"strokes {val:.3g}", fontsize=10)
        save_png(fig, OUT / f"tribo_{name}.png")
    return out


# ---------------------------------------------------------------- tables
def tables(results: dict) -> str:
    lines = ["_Generated by `python scripts/validate_real_data.py`; do not edit by hand._", ""]
    if "emps" in results:
        lines += ["### EMPS (estimation record, 24 841 samples)", "",
                  "| case | parameters (± std. error) | NRMSE (tracking) | position error "
                  "[%] | force error [%] | wall time [s] | simulations |",
                  "|---|---|---|---|---|---|---|"]
        for r in results["emps"]["rows"]:
            t = "–" if r["time_s"] is None else f"{r['time_s']:.1f}"
            lines.append(f"| {r['case']} | {r['parameters']} | {_fmt(r['nrmse'])} | "
                         f"{_fmt(r['position_error_pct'], 3)} | "
                         f"{_fmt(r.get('force_error_pct', np.nan), 3)} | {t} | "
                         f"{r['evaluations']} |")
        lines.append("")
        cross = results["emps"].get("cross")
        if cross:
            lines += [f"### EMPS, two-fold cross-validation (halves split at {EMPS_SPLIT} s)", "",
                      "| model | fitted on | NRMSE fit | NRMSE other half (start) | force error "
                      "fit / other half [%] | wall time [s] |", "|---|---|---|---|---|---|"]
            for r in cross:
                lines.append(
                    f"| {r['model']} | {r['fit_on']} half | {_fmt(r['nrmse_fit'], 3)} | "
                    f"{_fmt(r['nrmse_validation'], 3)} ({r['initial']}) | "
                    f"{_fmt(r['force_error_pct_fit'], 3)} / "
                    f"{_fmt(r['force_error_pct_validation'], 3)} | {r['time_s']:.1f} |")
            lines += ["", "| model | fitted on | parameters |", "|---|---|---|"]
            for r in cross:
                par = ", ".join(f"{k} = {_fmt(v)}" for k, v in r["parameters"].items())
                lines.append(f"| {r['model']} | {r['fit_on']} half | {par} |")
            lines.append("")
    if "brfd" in results:
        b = results["brfd"]
        names = list(b["models"])
        lines += ["### BRFD (fitted on " + b["fit_file"] + ")", "", BRFD_NOTE, "",
                  "| test | f [Hz] | A [in] | T [lb] | " + " | ".join(names) + " |",
                  "|---|---|---|---|" + "---|" * len(names)]
        lines.append("| **fit record** | 0.5 | 1 | 30 | " + " | ".join(
            f"**{_fmt(b['models'][n]['nrmse_fit'], 3)}**" for n in names) + " |")
        for i, test in enumerate(b["tests"]):
            lab = test["file"].replace("dataset-2_characterization_", "").replace(
                "dataset-4_semiactive_harmonic_", "semi-active ").replace(".npz", "")
            vals = " | ".join(_fmt(b["models"][n]["nrmse_validation"][i], 3) for n in names)
            tens = test["tension_lb"] if test["tension_lb"] not in ("", "nan") else "varies"
            lines.append(f"| {lab} | {test['freq_hz']} | {test['amplitude_in']} | {tens} | "
                         f"{vals} |")
        for label, pick in (("loaded tests", _loaded), ("0 lb tests", _unloaded)):
            lines.append(f"| **mean over {label}** | | | | " + " | ".join(
                f"**{_fmt(_mean(b['models'][n]['nrmse_validation'], b['tests'], pick), 3)}**"
                for n in names) + " |")
        lines += ["", "| model | fitted parameters | wall time [s] |", "|---|---|---|"]
        for n in names:
            m = b["models"][n]
            par = ", ".join(f"{k} = {_fmt(v)}" for k, v in m["parameters"].items())
            lines.append(f"| {n} | {par} | {m['time_s']:.1f} |")
        lines.append("")
    if "brfd-loads" in results:
        b = results["brfd-loads"]
        names = list(b["models"])
        lines += ["### BRFD, three tensions fitted at once (0, 30, 36 lb at 0.5 Hz, 1 in)", "",
                  "Spec `examples/fit_brfd_loads.toml`: shared parameters, the load fraction "
                  "λ (capacity `(1 − λ) + λ·s`) and one offset per record; started from "
                  f"{b.get('start', 'the spec')}.", "",
                  "| model | λ | NRMSE fit 0 / 30 / 36 lb | pooled | validation: loaded tests "
                  "| validation: 0 lb tests | wall time [s] |", "|---|---|---|---|---|---|---|"]
        for n in names:
            m = b["models"][n]
            lines.append(
                f"| {n} | {_fmt(m['parameters']['load_fraction'], 3)} | "
                + " / ".join(_fmt(v, 3) for v in m["nrmse_fit"])
                + f" | {_fmt(m['nrmse_pooled'], 3)} | "
                f"{_fmt(_mean(m['nrmse_validation'], b['tests'], _loaded), 3)} | "
                f"{_fmt(_mean(m['nrmse_validation'], b['tests'], _unloaded), 3)} | "
                f"{m['time_s']:.1f} |")
        lines += ["", "| model | fitted parameters |", "|---|---|"]
        for n in names:
            par = ", ".join(f"{k} = {_fmt(v)}" for k, v in b["models"][n]["parameters"].items())
            lines.append(f"| {n} | {par} |")
        lines.append("")
    lines += generalisation(results)
    if "tribo" in results:
        tr = results["tribo"]
        lines += ["### Micro-tribometer (fit 8.5–50.78 s, validation 50.78–111.78 s)", "",
                  "| model | fitted parameters (± std. error) | NRMSE fit | NRMSE later "
                  "strokes (from the fit's end state) | from rest, 4 s warm-up | wall time "
                  "[s] |", "|---|---|---|---|---|---|"]
        for n, m in tr["models"].items():
            if "error" in m:
                lines.append(f"| {n} | failed: {m['error']} | | | | |")
                continue
            par = ", ".join(f"{k} = {_fmt(v)} ± {_fmt(m['stderr'].get(k), 2)}"
                            for k, v in m["parameters"].items())
            lines.append(f"| {n} | {par} | {_fmt(m['nrmse_fit'], 3)} | "
                         f"{_fmt(m['nrmse_validation'], 3)} | "
                         f"{_fmt(m.get('nrmse_validation_warmup'), 3)} | {m['time_s']:.1f} |")
        lines.append("")
    return "\n".join(lines)


def _loaded(test) -> bool:
    return test["tension_lb"] in ("", "nan") or float(test["tension_lb"]) > 0


def _unloaded(test) -> bool:
    return not _loaded(test)


def _mean(values, tests, pick):
    chosen = [v for v, t in zip(values, tests) if pick(t)]
    return float(np.mean(chosen)) if chosen else None


def generalisation(results: dict) -> list[str]:
    """One table: per data set and model, the fit NRMSE and the NRMSE on records not fitted."""
    rows = []
    for key, what, fit_key in (("brfd", "BRFD, one record (30 lb)", "nrmse_fit"),
                               ("brfd-loads", "BRFD, three tensions", "nrmse_pooled")):
        b = results.get(key)
        for n, m in (b["models"].items() if b else ()):
            rows.append((what, n, m[fit_key], _mean(m["nrmse_validation"], b["tests"], _loaded),
                         _mean(m["nrmse_validation"], b["tests"], _unloaded)))
    if "tribo" in results:
        for n, m in results["tribo"]["models"].items():
            if "error" not in m:
                rows.append(("micro-tribometer", n, m["nrmse_fit"], m["nrmse_validation"], None))
    cross = results.get("emps", {}).get("cross") or []
    for n in dict.fromkeys(r["model"] for r in cross):      # the mean over the two folds
        mine = [r for r in cross if r["model"] == n]
        rows.append(("EMPS, two-fold (halves)", n,
                     float(np.mean([r["nrmse_fit"] for r in mine])),
                     float(np.mean([r["nrmse_validation"] for r in mine])), None))
    if not rows:
        return []
    lines = ["### Generalisation: fit error and error on records that were not fitted", "",
             "| data set, fit | model | NRMSE fit | NRMSE not fitted | NRMSE not fitted, "
             "0 lb |", "|---|---|---|---|---|"]
    for what, n, f, v, v0 in rows:
        lines.append(f"| {what} | {n} | {_fmt(f, 3)} | {_fmt(v, 3)} | "
                     f"{'–' if v0 is None else _fmt(v0, 3)} |")
    return lines + [""]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", choices=("emps", "brfd", "brfd-loads", "tribo"), action="append")
    args = ap.parse_args(argv)
    if not (shared_dir() / "data").is_dir():
        print(f"shared data not found at {shared_dir()}; set CLUTCHSIM_SHARED", file=sys.stderr)
        return 2
    OUT.mkdir(parents=True, exist_ok=True)
    store = OUT / "results.json"
    results = json.loads(store.read_text()) if store.is_file() else {}

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    runners = {"emps": run_emps, "brfd": run_brfd,
               "brfd-loads": lambda log: run_brfd_loads(log, results.get("brfd")),
               "tribo": run_tribo}
    for name in args.only or list(runners):
        t0 = time.perf_counter()
        results[name] = runners[name](log)
        log(f"{name}: {time.perf_counter() - t0:.0f} s")
    store.write_text(json.dumps(results, indent=1, default=float))
    text = DOC.read_text() if DOC.is_file() else f"{BEGIN}\n{END}\n"
    head, _, rest = text.partition(BEGIN)
    _, _, tail = rest.partition(END)
    DOC.write_text(f"{head}{BEGIN}\n{tables(results)}\n{END}{tail}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
