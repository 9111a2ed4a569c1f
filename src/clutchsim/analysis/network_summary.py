"""The summary of a run of any network (not a launch): speeds, energies, friction
elements, temperatures and events, read from a :class:`~clutchsim.core.Result`.

Pure post-processing of a result's signals and events (a network plant's, which names its
components' kinds, its friction models and its domain in ``metadata``).  Every value is a
finite number, a string, a bool or a list of them: no nulls, and every key is present in
every run (lists may be empty).  The keys are documented in docs/outputs.md ("Runs of
any network"); a launch gets the launch metrics instead
(:func:`clutchsim.analysis.launch_metrics.is_launch`)."""

from __future__ import annotations

import math

import numpy as np

from ..network.spec import DOMAINS
from ._kernels import energy_balance

__all__ = ["ENERGY_ACCOUNTS", "LOCKUP_TIMES_MAX", "network_summary"]

#: the plant's energy accounts [J] (final values of its integrals) -> their summary keys;
#: everything but ``W_in`` is dissipated (``E_grade`` is potential energy of a grade)
ENERGY_ACCOUNTS = (("W_in", "work_in"), ("W_friction", "friction"), ("W_damping", "damping"),
                   ("W_road", "road"), ("E_grade", "grade"), ("W_sync", "impacts"))
#: at most this many lock-up times are listed per friction element (``lockups`` counts all)
LOCKUP_TIMES_MAX = 50
#: source named for the events that belong to no component
PLANT = "plant"


def network_summary(res) -> dict:
    """The summary of one run of a network: outcome, warnings, solver statistics, node
    speeds, energies, friction elements, temperatures and located events (keys:
    docs/outputs.md, "Runs of any network").

    ``speeds``: one record per node speed (``omega_<node>`` [rad/s], ``v_<node>`` [m/s]):
    initial, final, min and max.  ``energies`` [J]: the work put in, the energy dissipated by
    friction, damping, road resistance and impacts (``heat``: their sum), the kinetic and
    the stored (spring) energy at the start and the end; ``energy_balance_rel``: the
    relative residual of that account.  ``friction_elements``: per element its model, the
    work it dissipated, its peak power and, for an element with a switching law (a
    ``<element>.locked`` signal), its lock-ups and releases (a smooth friction model never
    locks: 0).  ``located_events``: the located events, one record per event name
(``events``: how many there were in all, with the other solver statistics)."""
    t = res.t
    meta = res.metadata
    kinds = dict(meta.get("kinds", {}))
    out = {"completed": res.status == "completed", "outcome": str(res.outcome),
           "message": res.message, "warnings": list(res.warnings),
           "t_end_s": float(t[-1]) if t.size else 0.0}
    out.update({k: v for k, v in res.stats.as_dict().items()
                if k in ("steps", "rhs_evals", "events", "min_step_s", "wall_s")})
    energies, rel = _energies(res)
    out["energy_balance_rel"] = rel
    out["speeds"] = _speeds(res, kinds)
    out["energies"] = energies
    out["friction_elements"] = _friction_elements(res, kinds)
    out["temperatures"] = _temperatures(res)
    out["located_events"] = _events(res)
    return out


def _finite(x) -> float:
    """``x`` as a float; a non-finite value is a bug of the caller (JSON has no NaN)."""
    v = float(x)
    if not math.isfinite(v):
        raise ValueError(f"a summary value is not finite ({v})")
    return v


def _range(x) -> dict | None:
    """Initial, final, min and max of the finite samples of ``x`` (None if none is)."""
    x = np.asarray(x, dtype=float)
    ok = x[np.isfinite(x)]
    if not ok.size:
        return None
    return {"initial": float(ok[0]), "final": float(ok[-1]), "min": float(ok.min()),
            "max": float(ok.max())}


def _speeds(res, kinds) -> list[dict]:
    """A record per node speed: the nodes the plant integrates and the inertias (masses)
    it outputs the speed of (a node is named after its inertia)."""
    domain = DOMAINS[res.metadata.get("domain", "rotational")]
    nodes = set(res.metadata.get("nodes", ())) | set(kinds)
    prefix = f"{domain.speed}_"
    rows = []
    for name in res.signals:
        if not name.startswith(prefix) or name[len(prefix):] not in nodes:
            continue
        if res.units.get(name) != domain.speed_unit:
            continue
        r = _range(res[name])
        if r is not None:
            rows.append({"name": name[len(prefix):], "unit": domain.speed_unit, **r})
    return rows


def _final(res, name: str) -> float:
    x = res.data.get(name)
    return float(x[-1]) if x is not None and x.size and math.isfinite(x[-1]) else 0.0


def _energies(res) -> tuple[dict, float]:
    e = {key: _final(res, sig) for sig, key in ENERGY_ACCOUNTS}
    e["heat"] = e["friction"] + e["damping"] + e["road"] + e["impacts"]
    rel = 0.0
    for sig, key in (("E_kinetic", "kinetic"), ("E_spring", "stored")):
        x = res.data.get(sig)
        ok = x[np.isfinite(x)] if x is not None else np.empty(0)
        e[f"{key}_initial"] = float(ok[0]) if ok.size else 0.0
        e[f"{key}_final"] = float(ok[-1]) if ok.size else 0.0
    ke, pe = res.data.get("E_kinetic"), res.data.get("E_spring")
    if ke is not None and pe is not None and ke.size and np.all(np.isfinite(ke)) \
            and np.all(np.isfinite(pe)):
        losses = np.array([e[key] for _, key in ENERGY_ACCOUNTS[1:]])
        _, _, resid, scale = energy_balance(e["work_in"], losses, np.ascontiguousarray(ke),
                                            np.ascontiguousarray(pe))
        rel = abs(resid) / scale
    return {f"{k}_J": _finite(v) for k, v in e.items()}, _finite(rel)


def _friction_elements(res, kinds) -> list[dict]:
    models = dict(res.metadata.get("models", {}))
    t = res.t
    rows = []
    for name, model in models.items():
        power = res.data.get(f"P_{name}")
        work = res.data.get(f"W_friction_{name}")
        if work is None and len(models) == 1:
            work = res.data.get("W_friction")
        row = {"name": name, "kind": kinds.get(name, ""), "model": model,
               "work_J": float(work[-1]) if work is not None and work.size else
               (float(np.trapezoid(power, t)) if power is not None and t.size > 1 else 0.0),
               "peak_power_W": float(np.max(np.abs(power))) if power is not None
               and power.size else 0.0,
               # the open-pack drag of a wet clutch (its own account, inside W_damping)
               "drag_work_J": _final(res, f"W_drag_{name}")}
        row.update(_lockups(res, name))
        rows.append({k: (_finite(v) if isinstance(v, float) else v) for k, v in row.items()})
    return rows


def _lockups(res, name: str) -> dict:
    """Lock-ups and releases of a friction element with a switching law: the rises and
    falls of its ``<name>.locked`` signal, each timed by the element's last located event
    since the sample before (the event that switched it), else by the sample."""
    locked = res.data.get(f"{name}.locked")
    if locked is None or not locked.size:
        return {"lockups": 0, "releases": 0, "lockup_times_s": [], "locked_at_end": False}
    t = res.t
    on = np.asarray(locked) > 0.5
    rises = np.flatnonzero(on[1:] & ~on[:-1]) + 1
    falls = np.flatnonzero(~on[1:] & on[:-1]) + 1
    ev = np.sort(res.events.times(name))
    times = []
    for i in rises[:LOCKUP_TIMES_MAX]:
        j = np.searchsorted(ev, t[i], side="right") - 1
        times.append(float(ev[j]) if j >= 0 and ev[j] > t[i - 1] else float(t[i]))
    return {"lockups": int(rises.size), "releases": int(falls.size),
            "lockup_times_s": times, "locked_at_end": bool(on[-1])}


def _temperatures(res) -> list[dict]:
    """A record per thermal node (``theta_<node>`` [°C]): initial, final, min, max."""
    rows = []
    for name in res.signals:
        if name.startswith("theta_"):
            r = _range(res[name])
            if r is not None:
                rows.append({"name": name[6:], **{f"{k}_C": v for k, v in r.items()}})
    return rows


def _events(res) -> list[dict]:
    """One record per event name: the component it belongs to, how often it was located,
    and the first and the last time [s]."""
    groups: dict = {}
    for e in res.events:
        g = groups.setdefault(e.name, {"name": e.name, "element": e.source or PLANT,
                                        "count": 0, "first_s": e.t, "last_s": e.t})
        g["count"] += 1
        g["last_s"] = e.t
    return [{**g, "first_s": float(g["first_s"]), "last_s": float(g["last_s"])}
            for g in groups.values()]
