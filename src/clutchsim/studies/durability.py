"""Durability: a duty cycle of manoeuvres run cycle by cycle with temperatures and lining
wear carried over, and an accelerated mode for thousands of cycles.

A duty file (TOML)::

    [duty]
    name = "..."
    cycles = 1000                 # default number of cycles
    model = "coulomb-robust"      # friction model of the clutch (default: each scenario's)
    clamp_force = 4000.0          # N: clamp force at which the clutch's capacity is given

    [[manoeuvre]]
    name = "launch"
    scenario = "launch.toml"      # relative to the duty file; its clutch has a wear law
    set = ["vehicle.grade=5"]     # optional overrides: a variant of the scenario
    rest = 60.0                   # s of cooling after it (thermal network, no friction)

    [[cycle]]                     # one cycle: these manoeuvres in order, each `count` times
    manoeuvre = "launch"
    count = 8

Every manoeuvre run starts from the thermal nodes' temperatures and the wear where the last
one ended; the wear moves the diaphragm spring's installed (engaged) position from 1 to
``1 + shift·h`` (the clutch's ``installed_shift``), so the clamp force of the engaged
clutch follows its ``clamp_table`` there.
Between manoeuvres the thermal network cools for ``rest`` seconds (its linear equations,
solved exactly by a matrix exponential).

The accelerated mode simulates probes of ``PROBE`` consecutive cycles and extrapolates a
block of cycles after each: the temperature history of a linear thermal network under a
periodic load approaches its periodic state geometrically, so the cycle-to-cycle changes
of the cycle-start temperatures and of the wear per cycle are extrapolated with the ratio
of their last two changes (per node; clipped to [0, 0.999]).  A block is at most as long
as all cycles before it (the simulated cycles thin out geometrically) and adds at most
``BLOCK_WEAR`` of the wear reserve (the clamp force, and with it the slip work, changes
with the wear).

End of life.  The study stops, with the life reported (``life_cycles``, ``end_of_life``:
the cycle, the criterion, the wear, clamp force and capacity there) and the curve so far
kept, at the first of

* ``"wear_reserve"``: the wear reaches the reserve (``wear >= reserve``);
* a manoeuvre does not complete (the engine stalls, the clutch never locks up, ...) and the
  same manoeuvre, from the same temperatures with a new lining (wear 0), does: the worn
  clutch can no longer do the job, which *is* its end of life.  The criterion says how the
  wear ended it: ``"capacity"`` when the capacity has fallen below the new clutch's (the
  diaphragm spring past its peak), ``"engagement"`` otherwise (the wear moved the engaged
  position, so the duty's fixed pedal profile clamps earlier and harder: a stall, a jerk).

A manoeuvre that fails with a new lining too fails for another reason (the duty, the
temperatures, the solver): the study stops with ``outcome = "failed"`` and ``failure``
(the cycle, the manoeuvre, the run's outcome and message), keeping the finished cycles.
In the accelerated mode an end of life found in the probe after a block lies within that
block (at most ``BLOCK_WEAR`` of the reserve, or as many cycles as before it, earlier).
"""

from __future__ import annotations

import math
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["BLOCK_WEAR", "PROBE", "DurabilityResult", "Duty", "describe_end", "load_duty",
           "run_durability", "write_durability"]

#: a block of extrapolated cycles adds at most this fraction of the wear reserve
BLOCK_WEAR = 0.02
#: consecutive cycles simulated before each block of extrapolated cycles
PROBE = 3


class _ManoeuvreFailed(Exception):
    """A manoeuvre run that did not complete, with the wear and temperatures it started
    from (the study stops there; :func:`run_durability` tells wear from other causes)."""

    def __init__(self, runner, result, theta: dict, wear: float):
        super().__init__(result.message)
        self.runner, self.result, self.theta, self.wear = runner, result, theta, wear


@dataclass(frozen=True)
class Manoeuvre:
    name: str
    scenario: object        # clutchsim.scenario.Scenario
    rest: float


@dataclass(frozen=True)
class Duty:
    """A loaded duty file (:func:`load_duty`)."""

    name: str
    file: str
    cycles: int
    model: str | None
    clamp_force: float
    manoeuvres: dict
    sequence: tuple          # (manoeuvre name, count) in order


def _fail(file, text, problem, key):
    from .._util import toml_line
    from ..scenario.errors import ScenarioError
    raise ScenarioError(problem, file=file, key=key, line=toml_line(text, key) if key else None)


def load_duty(path) -> Duty:
    """Load and check a duty file; errors name the file, the line and the key."""
    from ..scenario import load_scenario
    path = Path(path)
    text = path.read_text()
    file = str(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        _fail(file, text, f"not valid TOML: {exc}", "")

    def fail(problem, key):
        _fail(file, text, problem, key)

    for k in data:
        if k not in ("duty", "manoeuvre", "cycle"):
            fail(f"unknown table [{k}] (tables: duty, manoeuvre, cycle)", k)
    d = data.get("duty", {})
    known = ("name", "cycles", "model", "clamp_force")
    for k in d:
        if k not in known:
            fail(f"unknown key {k!r}; keys: {', '.join(known)}", f"duty.{k}")
    cycles = d.get("cycles", 1)
    if isinstance(cycles, bool) or not isinstance(cycles, int) or cycles < 1:
        fail(f"= {cycles!r} must be an integer >= 1", "duty.cycles")
    clamp = d.get("clamp_force")
    if clamp is None:
        fail("is required: the clamp force [N] at which the clutch's capacity is given",
             "duty.clamp_force")
    if isinstance(clamp, bool) or not isinstance(clamp, (int, float)) or \
            not math.isfinite(clamp) or clamp <= 0:
        fail(f"= {clamp!r} must be a positive number [N]", "duty.clamp_force")
    model = d.get("model")
    mans = {}
    for i, m in enumerate(data.get("manoeuvre", [])):
        key = f"manoeuvre[{i}]"
        for k in m:
            if k not in ("name", "scenario", "set", "rest"):
                fail(f"unknown key {k!r}; keys: name, scenario, set, rest", f"{key}.{k}")
        name = m.get("name")
        if not isinstance(name, str) or not name:
            fail("is required: a name for the cycle to use", f"{key}.name")
        if name in mans:
            fail(f"= {name!r}: a second manoeuvre of that name", f"{key}.name")
        sc_file = m.get("scenario")
        if not isinstance(sc_file, str):
            fail("is required: the scenario file (relative to the duty file)",
                 f"{key}.scenario")
        sc_path = (path.parent / sc_file)
        if not sc_path.is_file():
            fail(f"= {sc_file!r}: no such file ({sc_path})", f"{key}.scenario")
        rest = m.get("rest", 0.0)
        if isinstance(rest, bool) or not isinstance(rest, (int, float)) or rest < 0:
            fail(f"= {rest!r} must be a number >= 0 [s]", f"{key}.rest")
        sets = m.get("set", [])
        if not isinstance(sets, list) or not all(isinstance(s, str) for s in sets):
            fail("must be a list of \"key.path=value\" strings", f"{key}.set")
        sc = load_scenario(sc_path, overrides=sets)
        law = _clutch_wear(sc)
        if law is None:
            fail(f"scenario {sc_file!r}: its clutch {sc.clutch!r} has no wear law "
                 "(a `wear = {...}` table)", f"{key}.scenario")
        mans[name] = Manoeuvre(name, sc, float(rest))
    if not mans:
        fail("a duty cycle needs at least one [[manoeuvre]]", "manoeuvre")
    seq = []
    for i, c in enumerate(data.get("cycle", [])):
        key = f"cycle[{i}]"
        for k in c:
            if k not in ("manoeuvre", "count"):
                fail(f"unknown key {k!r}; keys: manoeuvre, count", f"{key}.{k}")
        name = c.get("manoeuvre")
        if name not in mans:
            from ..scenario.schema import suggest
            fail(f"= {name!r} is not a manoeuvre{suggest(str(name), list(mans))} "
                 f"(manoeuvres: {', '.join(mans)})", f"{key}.manoeuvre")
        count = c.get("count", 1)
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            fail(f"= {count!r} must be an integer >= 1", f"{key}.count")
        seq.append((name, count))
    if not seq:
        fail("a duty cycle needs at least one [[cycle]] entry", "cycle")
    laws = {m.name: _clutch_wear(m.scenario) for m in mans.values()}
    first = next(iter(laws.values()))
    for n, law in laws.items():
        if law != first:
            fail(f"manoeuvre {n!r}: its clutch's wear law differs from the first "
                 "manoeuvre's (one clutch wears through the whole duty cycle)", "manoeuvre")
    return Duty(d.get("name", path.stem), file, cycles, model, float(clamp), mans,
                tuple(seq))


def _clutch_wear(sc):
    for c in sc.network(None).components:
        if c.name == sc.clutch:
            return getattr(c, "wear", None)
    return None


class _Runner:
    """One manoeuvre, compiled once, run from a carried state."""

    def __init__(self, man: Manoeuvre, model):
        from ..network import compile_network
        sc = man.scenario
        self.man = man
        self.clutch = sc.clutch
        self.net = sc.network(model if model is not None else
                              (sc.models[0] if sc.models else None))
        self.plan = compile_network(self.net)
        self.u0 = sc.inputs0()
        self.comp = {c.name: c for c in self.net.components}
        self.law = self.comp[self.clutch].wear
        self.heat_node = self.comp[self.clutch].heat[0][0]
        self.thermal = [c for c in self.net.components if getattr(c, "thermal", False)]

    def simulate(self, theta: dict, wear: float):
        """The manoeuvre's run from the temperatures ``theta`` [°C] and the wear [m]."""
        from ..core import simulate
        sc = self.man.scenario
        comps = []
        for c in self.net.components:
            if c.name in theta:
                c = c.with_values(theta0=theta[c.name])
            elif c.name == self.clutch:
                c = c.with_values(wear0=wear, installed_shift=self.law.shift * wear)
            comps.append(c)
        system = self.plan.system(comps, inputs0=self.u0, name=sc.name)
        inputs = {n: sc.inputs[n] for n in system.input_names}
        return simulate(system, (0.0, sc.t_end), inputs, solver=sc.solver, options=sc.options)

    def run(self, theta: dict, wear: float):
        """(end temperatures after the rest, end wear, peak temperature, energy balance,
        friction work) of the manoeuvre; :class:`_ManoeuvreFailed` when it did not
        complete."""
        from ..analysis.launch_metrics import energy_balance
        res = self.simulate(theta, wear)
        if res.status != "completed":
            raise _ManoeuvreFailed(self, res, theta, wear)
        th_end = {c.name: float(res[f"theta_{c.name}"][-1]) for c in self.thermal}
        th_end = self.cool(th_end, self.man.rest)
        peak = float(np.max(res[f"theta_{self.heat_node}"]))
        return (th_end, float(res[f"wear_{self.clutch}"][-1]), peak,
                energy_balance(res)["energy_balance_rel"], float(res["W_friction"][-1]))

    def cool(self, theta: dict, rest: float) -> dict:
        """Temperatures after ``rest`` seconds of the thermal network alone (exact)."""
        if rest <= 0.0 or not self.thermal:
            return theta
        from scipy.linalg import expm
        names = [c.name for c in self.thermal]
        k = {n: i for i, n in enumerate(names)}
        n = len(names)
        A = np.zeros((n + 1, n + 1))
        for c in self.thermal:
            i = k[c.name]
            A[i, i] -= c.conductance / c.capacity
            A[i, n] += c.conductance * c.ambient / c.capacity
            if c.link is not None:
                j, G = k[c.link], c.link_conductance
                other = self.comp[c.link]
                A[i, i] -= G / c.capacity
                A[i, j] += G / c.capacity
                A[j, j] -= G / other.capacity
                A[j, i] += G / other.capacity
        x = np.append([theta[m] for m in names], 1.0)
        x = expm(A * rest) @ x
        return {m: float(x[k[m]]) for m in names}


@dataclass(frozen=True)
class DurabilityResult:
    """A durability study: per finished cycle, and the summary (:meth:`summary`).

    ``outcome``: ``"completed"`` (every cycle run, the clutch still in service),
    ``"end_of_life"`` (``life_cycles`` and ``end_of_life`` say when and why) or
    ``"failed"`` (a manoeuvre failed for a reason other than wear: ``failure``).  The wear,
    clamp force and capacity are those at the end (of the cycles, of life, or where the
    failed manoeuvre started); ``history`` holds the finished cycles either way.
    """

    duty: str
    mode: str
    cycles: int
    cycles_done: int
    simulated_cycles: int
    history: dict            # arrays over recorded cycles: cycle, wear_m, clamp_force_N, ...
    wear_m: float
    clamp_force_end_N: float
    capacity_end_Nm: float
    outcome: str
    life_cycles: int | None
    end_of_life: dict | None
    failure: dict | None
    max_energy_balance_rel: float
    wall_s: float
    units: dict = field(default_factory=lambda: dict(UNITS))

    def summary(self) -> dict:
        peak = self.history["peak_theta_C"]
        return {"kind": "durability", "duty": self.duty, "mode": self.mode,
                "outcome": self.outcome, "cycles": self.cycles,
                "cycles_done": self.cycles_done, "simulated_cycles": self.simulated_cycles,
                "wear_mm": self.wear_m * 1e3, "clamp_force_end_N": self.clamp_force_end_N,
                "capacity_end_Nm": self.capacity_end_Nm, "life_cycles": self.life_cycles,
                "end_of_life": self.end_of_life, "failure": self.failure,
                "peak_theta_C": float(np.max(peak)) if len(peak) else None,
                "max_energy_balance_rel": self.max_energy_balance_rel,
                "wall_s": self.wall_s}


UNITS = {"cycle": "-", "wear_m": "m", "clamp_force_N": "N", "capacity_Nm": "N·m",
         "peak_theta_C": "°C", "friction_work_J": "J", "simulated": "-"}


def _clamp(duty, fe, wear):
    """(clamp force [N], capacity [N·m]) of the engaged clutch ``fe`` after ``wear`` [m]
    (cold: μ at its reference)."""
    x = 1.0 + fe.wear.shift * wear
    if fe.clamp_table is None:
        f = 1.0
    else:
        xs, ys = fe.clamp_table
        f = float(np.interp(x, xs, ys))
    return duty.clamp_force * f, fe.model.static_capacity() * f


def _ratio(prev, last):
    """Per-entry ratio ``last/prev`` of successive changes, in [0, 0.999] (0 where the
    change vanished or changed sign: no trend to extrapolate)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(prev != 0.0, last / prev, 0.0)
    return np.clip(np.nan_to_num(r), 0.0, 0.999)


def run_durability(duty, cycles: int | None = None, *, accelerated: bool = True,
                   progress=None) -> DurabilityResult:
    """Run the duty cycle ``duty`` (a :class:`Duty` or a path) for ``cycles`` cycles
    (default: the duty's), fully (every cycle simulated) or accelerated (module
    docstring)."""
    t0 = time.perf_counter()
    duty = duty if isinstance(duty, Duty) else load_duty(duty)
    cycles = duty.cycles if cycles is None else int(cycles)
    if cycles < 1:
        raise ValueError(f"cycles = {cycles} must be >= 1")
    runners = {n: _Runner(m, duty.model) for n, m in duty.manoeuvres.items()}
    first = next(iter(runners.values()))
    law = first.law
    fe = first.comp[first.clutch]
    theta = {c.name: c.theta0 for c in first.thermal}
    wear = 0.0
    done = 0
    hist = {k: [] for k in UNITS}
    worst = 0.0

    def one_cycle(theta, wear):
        nonlocal worst
        peak = -math.inf
        work = 0.0
        for name, count in duty.sequence:
            r = runners[name]
            for _ in range(count):
                th_new, wear_new, pk, eb, wf = r.run(theta, wear)
                # carry the nodes the next manoeuvre shares by name
                theta = {**theta, **th_new}
                wear = wear_new
                peak, work = max(peak, pk), work + wf
                worst = max(worst, eb)
        return theta, wear, peak, work

    def record(cycle, wear, peak, work, simulated):
        F, cap = _clamp(duty, fe, wear)
        for k, v in (("cycle", cycle), ("wear_m", wear), ("clamp_force_N", F),
                     ("capacity_Nm", cap), ("peak_theta_C", peak), ("friction_work_J", work),
                     ("simulated", 1.0 if simulated else 0.0)):
            hist[k].append(float(v))

    def end(cycle, criterion, wear, failed=None):
        F, cap = _clamp(duty, fe, wear)
        doc = {"cycle": cycle, "criterion": criterion, "wear_mm": wear * 1e3,
               "clamp_force_N": F, "capacity_Nm": cap}
        if failed is not None:
            doc.update(manoeuvre=failed.runner.man.name, run_outcome=failed.result.outcome,
                       message=failed.result.message)
        return doc

    sims = 0
    eol = failure = None
    run = []             # consecutive simulated cycles since the last block: (start θ, dw)
    while done < cycles and eol is None and failure is None:
        start = np.array(list(theta.values()))
        w_before = wear
        try:
            theta, wear, peak, work = one_cycle(theta, wear)
        except _ManoeuvreFailed as exc:
            sims += 1
            wear = exc.wear
            fresh = exc.runner.simulate(exc.theta, 0.0)
            if fresh.status == "completed":      # a new lining does it: worn out
                worn = _clamp(duty, fe, wear)[1] < _clamp(duty, fe, 0.0)[1]
                eol = end(done + 1, "capacity" if worn else "engagement", wear, exc)
            else:
                failure = {k: v for k, v in end(done + 1, None, wear, exc).items()
                           if k in ("cycle", "manoeuvre", "run_outcome", "message")}
            break
        sims += 1
        done += 1
        record(done, wear, peak, work, True)
        if progress is not None:
            progress(done, cycles)
        if wear >= law.reserve:
            eol = end(done, "wear_reserve", wear)
            break
        run.append((start, wear - w_before))
        if not accelerated or len(run) < PROBE or done >= cycles:
            continue
        # a block: the cycle-to-cycle changes of the start temperatures and of the wear per
        # cycle decay geometrically (a linear thermal network under a periodic load), ratio
        # r from the last three cycles; the block is at most as long as all cycles so far
        (_th0, dw0), (th1, dw1), (th2, dw2) = run[-3:]
        end_th = np.array(list(theta.values()))
        r_th = _ratio(th2 - th1, end_th - th2)
        d2 = end_th - th2
        r = _ratio(np.array([dw1 - dw0]), np.array([dw2 - dw1]))[0]
        n = min(cycles - done, done)
        if dw2 > 0.0:
            n = min(n, max(math.floor(BLOCK_WEAR * law.reserve / dw2), 1))
        dws = dw2 + (dw2 - dw1) * np.cumsum(r ** np.arange(1, n + 1))
        dws = np.maximum(dws, 0.0)
        total = np.cumsum(dws)
        hit = np.flatnonzero(wear + total >= law.reserve)
        if hit.size:
            n = int(hit[0]) + 1
        wear += float(total[n - 1])
        geo = np.where(r_th > 0.0, r_th * (1.0 - r_th ** n) / np.maximum(1.0 - r_th, 1e-300),
                       0.0)
        theta = {k: float(v) for k, v in zip(theta, end_th + d2 * geo)}
        done += n
        record(done, wear, peak, work, False)
        if hit.size:
            eol = end(done, "wear_reserve", wear)
        run = []
    F, cap = _clamp(duty, fe, wear)
    outcome = "failed" if failure else "end_of_life" if eol else "completed"
    return DurabilityResult(duty.name, "accelerated" if accelerated else "full", cycles,
                            done, sims, {k: np.asarray(v) for k, v in hist.items()}, wear, F,
                            cap, outcome, None if eol is None else eol["cycle"], eol, failure,
                            worst, time.perf_counter() - t0)


def describe_end(res: DurabilityResult) -> str:
    """One line: how the study ended (life and its criterion, or the failure)."""
    if res.outcome == "failed":
        f = res.failure
        return (f"failed in cycle {f['cycle']}: manoeuvre {f['manoeuvre']!r} "
                f"({f['run_outcome']}) also fails with a new lining: {f['message']}")
    if res.outcome == "end_of_life":
        e = res.end_of_life
        why = ("wear reserve used up" if e["criterion"] == "wear_reserve" else
               f"{e['criterion']}: manoeuvre {e['manoeuvre']!r} fails with the worn lining "
               f"({e['message']}) and completes with a new one")
        return (f"end of life in cycle {e['cycle']} ({why}; wear {e['wear_mm']:.3f} mm, "
                f"clamp force {e['clamp_force_N']:.0f} N, capacity {e['capacity_Nm']:.0f} N·m)")
    return "life not reached"


def write_durability(res: DurabilityResult, directory, *, plots: bool = True) -> None:
    """``durability.csv`` (with a units row) and, with ``plots``, ``durability.png``:
    wear, clamp force, capacity and peak temperature over the cycles."""
    from .._util import atomic_write
    directory = Path(directory)
    keys = list(UNITS)
    rows = [",".join(keys), ",".join(UNITS[k] for k in keys)]
    for i in range(len(res.history["cycle"])):
        rows.append(",".join(repr(float(res.history[k][i])) for k in keys))
    atomic_write(directory / "durability.csv",
                 lambda p: Path(p).write_text("\n".join(rows) + "\n", encoding="utf-8"))
    if not plots:
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    h = res.history
    fig, ax = plt.subplots(2, 2, figsize=(10, 6.5), sharex=True)
    sim = h["simulated"] > 0.5
    for a, key, label in ((ax[0, 0], "wear_m", "axial wear [mm]"),
                          (ax[0, 1], "clamp_force_N", "clamp force [N]"),
                          (ax[1, 0], "capacity_Nm", "capacity [N·m]"),
                          (ax[1, 1], "peak_theta_C", "peak temperature [°C]")):
        y = h[key] * (1e3 if key == "wear_m" else 1.0)
        a.plot(h["cycle"], y, "-", color="0.6", lw=1)
        a.plot(h["cycle"][sim], y[sim], "o", ms=3, label="simulated")
        a.set_ylabel(label)
        a.grid(alpha=0.3)
    for a in ax[1]:
        a.set_xlabel("cycle")
    ax[0, 0].legend()
    fig.suptitle(f"{res.duty}: {res.cycles_done} of {res.cycles} cycles ({res.mode}, "
                 f"{res.simulated_cycles} simulated); {describe_end(res)}")
    fig.tight_layout()
    atomic_write(directory / "durability.png", lambda p: fig.savefig(p, dpi=110,
                                                                    format="png"))
    plt.close(fig)
