"""Random valid driveline networks (hypothesis) and the properties every run must have.

Used by ``test_fuzz_networks.py`` (a bounded number of examples in ``make test``) and by
``scripts/fuzz_networks.py`` (thousands, with a count and a seed).

A network: 2-6 inertias (initial speeds equal, different or zero) joined in a tree by
couplings (friction clutches with every friction model a clutch accepts, one-way
clutches, spring-dampers, elasto-backlash, ideal gears, one lossy gear at most
(no planetary set yet), sometimes a coupling in parallel with another (a loop), brakes to the
housing and torque sources whose signals start at 0, cross 0, step, ramp and oscillate;
friction commands that start at 0, step, ramp, release and oscillate in [0, 1].

Properties of a run (:func:`check_run`): it ends with an outcome of the core (never an
exception); a completed run breaks no physics invariant
(:mod:`clutchsim.network.invariants`, the outcome ``invariant_violated`` otherwise) and
closes its energy balance; a rerun with tolerances 100 times tighter ends the same way,
at final speeds that agree (a network with a naive switching law may end its tight rerun
in chatter, that law's documented outcome at lock-up).  Where they do not agree, a third
run tells a wrong loose run from a sensitive network: the tight run again, with initial
speeds and inertias perturbed by the loose tolerance (the speeds by ``1 + rtol``, the
inertias by ``1 ± rtol`` in turn, so that it acts on a network at rest as well).  When it
ends as far from the tight run as the loose run did (at least a tenth of that), the network
amplifies tolerance-level errors (an undamped backlash rattling between a light and a heavy
inertia is chaotic: its final speeds at rtol 1e-7 ... 1e-11 all differ by rad/s while every
run converges over the first 0.25 s) and no solver can do better: not a problem, counted as
``sensitive``.  Where the perturbed run moved at least 100 times the perturbation (it
amplifies: chaos) but less than that tenth, the loose run runs again at 1.25 times its
tolerance: where that alone moves the final speeds a tenth as far, the loose result is
decided by its step sequence (a rattle whose impacts a step more or less reorders; measured
on fuzz seed 31: at 0.8 and 1.25 times the tolerance the loose run moved 0.033 and
0.37 rad/s, six and seventy times its distance from the tight run): ``sensitive``.  In a
network that does not amplify, a result that moves with the step sequence is a numerical
fault (e.g. a crossing lost in a long step), so that run is not asked there.  The
perturbation alone can miss a sensitive network (the loose run's step errors all along are
larger than the perturbation), so the last run is the convergence test: the tight run
against a tighter one (rtol 1e-11).  A run that converges with its tolerance moves about a
hundred times less from 1e-9 to 1e-11 than from 1e-7 to 1e-9; when they still differ by a
tenth of what the loose run did, the network does not converge at any tolerance here:
``sensitive`` too.  Otherwise the loose run was wrong beyond its tolerance, consistently at
nearby tolerances: a problem.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np
from hypothesis import strategies as st

from clutchsim.core import Outcome, SolverOptions, simulate
from clutchsim.core.signals import Constant, Ramp, Sine, Step
from clutchsim.friction import MODELS, make_model
from clutchsim.network import Network, NetworkError
from clutchsim.network.components import (
    Brake,
    Clutch,
    ElastoBacklash,
    IdealGear,
    Inertia,
    LossyGear,
    OneWayClutch,
    SpringDamper,
    TorqueSource,
)

T_END = 0.6
#: the loose run and the tight rerun
LOOSE = {"rtol": 1e-7, "atol": 1e-9}
TIGHT = {"rtol": 1e-9, "atol": 1e-11}
#: the tighter rerun of a network whose loose and tight runs disagree (check_run)
TIGHTER = {"rtol": 1e-11, "atol": 1e-13}
#: the loose run again at a tolerance this many times its own, in a network that amplifies
#: a perturbation of the loose tolerance at least AMPLIFIES times (check_run)
NEARBY = 1.25
AMPLIFIES = 100.0
#: the fraction of the loose run's difference that the perturbed tight run must reach for
#: the network to count as sensitive (check_run)
SENSITIVE = 0.1
#: budgets that keep a fuzzed run bounded (a run that exhausts one is a legal outcome)
BUDGET = {"max_steps": 200_000, "wall_time": 20.0, "chatter_events": 200}
#: outcomes a run may end with (a failed run is a result, not an error)
LEGAL = {Outcome.COMPLETED, Outcome.STOPPED, Outcome.CHATTER, Outcome.BUDGET,
         Outcome.WALL_TIME, Outcome.STEP_COLLAPSE}


@dataclass
class Case:
    """A fuzzed network with its inputs, and a text that rebuilds it (for reports)."""

    components: list
    connect: list
    inputs: dict
    text: list = field(default_factory=list)

    def network(self) -> Network:
        return Network(self.components, self.connect, name="fuzz")

    def __repr__(self) -> str:
        return "Case(\n  " + "\n  ".join(self.text) + "\n)"


def _torque_signal(draw, T):
    kind = draw(st.sampled_from(["const", "step", "ramp", "sine", "sine_offset", "zero"]))
    a = draw(st.floats(0.2, 3.0)) * T * draw(st.sampled_from([1.0, -1.0]))
    f = draw(st.sampled_from([1.0, 2.5, 5.0]))
    t = draw(st.sampled_from([0.0, 0.1, 0.25]))
    return {"const": lambda: Constant(a), "zero": lambda: Constant(0.0),
            "step": lambda: Step(t, a), "ramp": lambda: Ramp(t, 0.2, a),
            "sine": lambda: Sine(a, f),
            "sine_offset": lambda: Sine(a, f, offset=0.5 * a)}[kind](), kind


def _command_signal(draw):
    kind = draw(st.sampled_from(["one", "zero", "ramp_up", "step_up", "release",
                                 "oscillate", "half"]))
    t = draw(st.sampled_from([0.0, 0.05, 0.2]))
    return {"one": lambda: Constant(1.0), "zero": lambda: Constant(0.0),
            "half": lambda: Constant(0.5), "ramp_up": lambda: Ramp(t, 0.2, 1.0),
            "step_up": lambda: Step(t, 1.0), "release": lambda: Ramp(t, 0.2, -1.0, 1.0),
            "oscillate": lambda: Sine(0.5, 2.0, offset=0.5)}[kind](), kind


def _model(draw, T):
    """A friction model of capacity about ``T`` N·m (rotational magnitudes)."""
    name = draw(st.sampled_from(sorted(MODELS)))
    peak = draw(st.sampled_from([1.0, 1.1, 1.3]))
    base = make_model(name)
    k = T / base.static_capacity()
    over = {"coulomb-naive": {"F_c": T, "F_s": peak * T},
            "coulomb-robust": {"F_c": T, "F_s": peak * T},
            "karnopp": {"F_c": T, "F_s": peak * T}}.get(name)
    if over is None:
        # scale every force parameter of the model's own set by k
        forces = [p for p, (kind, _doc) in base.parameter_info.items()
                  if kind in ("force", "force/velocity", "force/displacement", "force/time")]
        over = {p: (tuple(x * k for x in getattr(base, p))
                    if isinstance(getattr(base, p), tuple) else getattr(base, p) * k)
                for p in forces}
    return name, base.with_(**over)


@st.composite
def cases(draw) -> Case:
    n = draw(st.integers(2, 6))
    T = draw(st.sampled_from([1.0, 10.0, 50.0]))
    speeds = draw(st.sampled_from(["equal", "zero", "random"]))
    w_eq = draw(st.floats(-20.0, 20.0))
    comps, text, inputs = [], [], {}
    groups: dict[str, list[str]] = {}
    for i in range(n):
        w = {"equal": w_eq, "zero": 0.0}.get(speeds) or draw(st.floats(-20.0, 20.0))
        J = draw(st.sampled_from([0.05, 0.2, 1.0, 4.0]))
        comps.append(Inertia(f"I{i}", J=J, omega0=w))
        groups[f"I{i}"] = [f"I{i}.a"]
        text.append(f"Inertia I{i}: J = {J}, omega0 = {w}")
    lossy_used = [False]

    def friction(name, cls, a, b, owner):
        mname, model = _model(draw, T)
        sig, kind = _command_signal(draw)
        inputs[f"f_{name}"] = sig
        text.append(f"{cls.__name__} {name}: {a}-{b}, {mname} {model}, command {kind} {sig}")
        return cls(name, model, command=f"f_{name}")

    def coupling(k, a, b):
        kinds = ["clutch", "clutch", "spring", "backlash", "gear", "one_way"]
        if not lossy_used[0]:
            kinds.append("lossy")
        kind = draw(st.sampled_from(kinds))
        name = f"c{k}"
        if kind == "clutch":
            c = friction(name, Clutch, a, b, None)
        elif kind == "spring":
            c = SpringDamper(name, c=draw(st.sampled_from([10.0, 1e3, 1e5])),
                             d=draw(st.sampled_from([0.0, 0.5, 20.0])))
            text.append(f"SpringDamper {name}: {a}-{b}, c = {c.values['c']}, d = {c.values['d']}")
        elif kind == "backlash":
            c = ElastoBacklash(name, b=draw(st.sampled_from([0.0, 0.01, 0.1])),
                               c=draw(st.sampled_from([1e3, 1e5])),
                               d=draw(st.sampled_from([0.0, 10.0])))
            text.append(f"ElastoBacklash {name}: {a}-{b}, {c.values}")
        elif kind == "gear":
            r = draw(st.sampled_from([0.5, 2.0, -3.0]))
            c = IdealGear(name, ratio=r)
            text.append(f"IdealGear {name}: {a}-{b}, ratio {r}")
        elif kind == "lossy":
            lossy_used[0] = True
            eta = draw(st.sampled_from([0.9, 0.7]))
            tb = draw(st.sampled_from([0.0, 0.1 * T]))
            r = draw(st.sampled_from([2.0, -1.5]))
            c = LossyGear(name, ratio=r, loss_table=((0.0, eta, eta, tb, tb),))
            text.append(f"LossyGear {name}: {a}-{b}, ratio {r}, eta {eta}, tau_bf {tb}")
        else:
            sig, ck = _command_signal(draw)
            inputs[f"f_{name}"] = sig
            ts = T * draw(st.sampled_from([0.5, 1.0]))
            c = OneWayClutch(name, command=f"f_{name}", T_slide=ts, peak=1.1)
            text.append(f"OneWayClutch {name}: {a}-{b}, T_slide {ts}, command {ck} {sig}")
        return c

    edges = set()
    speeds_of = {f"I{i}": comps[i].values["omega0"] for i in range(n)}
    k = 0
    for i in range(1, n):
        j = draw(st.integers(0, i - 1))
        a, b = f"I{j}", f"I{i}"
        c = coupling(k, a, b)
        k += 1
        # a freewheel starts with omega_b >= omega_a
        if isinstance(c, OneWayClutch) and speeds_of[b] < speeds_of[a]:
            comps[i] = Inertia(b, J=comps[i].values["J"], omega0=speeds_of[a])
            speeds_of[b] = speeds_of[a]
            text.append(f"  ({b}'s initial speed set to {speeds_of[a]} by the freewheel)")
        # the rigid couplings must agree with the initial speeds: re-set b's speed
        if isinstance(c, (IdealGear, LossyGear)):
            w_b = speeds_of[a] / c.values["ratio"]
            comps[i] = Inertia(b, J=comps[i].values["J"], omega0=w_b)
            speeds_of[b] = w_b
            text.append(f"  ({b}'s initial speed set to {w_b} by the gear)")
        comps.append(c)
        edges.add((j, i))
        groups[a].append(f"{c.name}.a")
        groups[b].append(f"{c.name}.b")
    # a loop: a friction or compliant element in parallel with a path
    if n >= 3 and draw(st.booleans()):
        i, j = draw(st.sampled_from([e for e in ((0, n - 1), (1, n - 1), (0, n - 2))
                                     if e not in edges] or [(0, n - 1)]))
        name = f"c{k}"
        k += 1
        if draw(st.booleans()):
            c = friction(name, Clutch, f"I{i}", f"I{j}", None)
        else:
            c = SpringDamper(name, c=1e3, d=1.0)
            text.append(f"SpringDamper {name}: I{i}-I{j} (loop), c = 1e3, d = 1")
        comps.append(c)
        groups[f"I{i}"].append(f"{c.name}.a")
        groups[f"I{j}"].append(f"{c.name}.b")
    # brakes and sources
    for i in range(n):
        if draw(st.integers(0, 3)) == 0:
            name = f"br{i}"
            comps.append(friction(name, Brake, f"I{i}", "ground", None))
            groups[f"I{i}"].append(f"{name}.flange")
    n_src = draw(st.integers(1, 2))
    for s in range(n_src):
        i = draw(st.integers(0, n - 1))
        sig, kind = _torque_signal(draw, T)
        inputs[f"tau{s}"] = sig
        comps.append(TorqueSource(f"src{s}", input=f"tau{s}"))
        groups[f"I{i}"].append(f"src{s}.flange")
        text.append(f"TorqueSource src{s} on I{i}: {kind} {sig}")
    connect = [g for g in groups.values() if len(g) > 1]
    # inertias left alone by every coupling still need a connection list entry? no: a
    # free inertia is its own node
    return Case(comps, connect, inputs, text)


def energy_residual(res) -> tuple[float, float]:
    """``(residual [J], scale [J])`` of the run's energy books."""
    acc = ["W_friction", "W_damping", "W_road", "E_grade", "W_sync"]
    w_in = float(res["W_in"][-1])
    d_ke = float(res["E_kinetic"][-1] - res["E_kinetic"][0])
    d_pe = float(res["E_spring"][-1] - res["E_spring"][0])
    resid = w_in - d_ke - d_pe - sum(float(res[a][-1]) for a in acc)
    scale = max(abs(w_in), float(np.max(res["E_kinetic"])), float(np.max(abs(res["W_friction"]))),
                1e-9)
    return resid, scale


def run(case: Case, tol: dict):
    system = case.network().build({k: 0.0 for k in case.inputs})
    return simulate(system, (0.0, T_END), case.inputs, solver="rodas4",
                    options=SolverOptions(**tol, **BUDGET))


def _switches_at_zero_slip(case: Case) -> bool:
    """Does the network hold a friction element whose force jumps at zero slip with no
    stuck mode (:attr:`FrictionModel.jumps`: coulomb-naive)?  Such a law has no solution
    at lock-up but a sliding mode, and the chatter guard ending the run there is its
    documented outcome (docs/models/coulomb-naive.md), at one tolerance or another: the
    run that completed stepped over the sliding mode."""
    return any(getattr(getattr(c, "model", None), "jumps", False) for c in case.components)


def _jumps_without_events(case: Case) -> bool:
    """Does the network hold a friction element whose force jumps away from zero slip where
    no event marks it (:attr:`FrictionModel.edge_jumps`: Karnopp's window edges)?  A slip
    that hovers at such an edge beside a stiff part collapses the step of a tight run there
    (docs/models/karnopp.md): its documented outcome."""
    return any(getattr(getattr(c, "model", None), "edge_jumps", False)
               for c in case.components)


def _in_chatter_window(res, warning: str) -> bool:
    """Is the time a physics warning names inside the window in which the chatter guard
    counted the events that ended ``res``?  There the modes of a network with a naive
    switching law (:func:`_switches_at_zero_slip`) did not settle: the run ends there,
    failed, its message says why, and a row of the window is the chatter itself, not
    another problem.  A warning before the window is counted."""
    at = re.search(r" at t = ([-+0-9.eE]+) s", warning)
    window = re.search(r"events within ([-+0-9.eE]+) s", res.message)
    if at is None or window is None:
        return False
    return float(at.group(1)) >= float(res.t[-1]) - float(window.group(1))


def check_run(case: Case, res=None, notes: list | None = None) -> list[str]:
    """The properties of the module docstring; the problems found (empty: none).  A
    network the library refuses with a clear error (:class:`NetworkError`, e.g. two
    clutches joining the same two shafts) is no problem.  ``res``: the run at the loose
    tolerances when the caller has it; ``notes``: a list to which a sensitive network's
    line is appended."""
    problems = []
    if res is None:
        try:
            res = run(case, LOOSE)
        except NetworkError:
            return []
    if res.outcome not in LEGAL:
        problems.append(f"outcome {res.outcome}: {res.message}")
    physics = [w for w in res.warnings if "physics check" in w]
    if res.outcome == Outcome.CHATTER and _switches_at_zero_slip(case):
        physics = [w for w in physics if not _in_chatter_window(res, w)]
    if physics:
        problems.append("warnings: " + "; ".join(physics))
    if res.outcome != Outcome.COMPLETED:
        return problems
    resid, scale = energy_residual(res)
    if abs(resid) > 1e-5 * scale + 1e-9:
        problems.append(f"energy balance: residual {resid:.3g} J of {scale:.3g} J")
    ref = run(case, TIGHT)
    if ref.outcome in (Outcome.BUDGET, Outcome.WALL_TIME):
        return problems         # no comparison (Karnopp's window at 1e-9 can be that slow)
    if ref.outcome == Outcome.CHATTER and _switches_at_zero_slip(case):
        return problems         # the documented outcome of a naive switching law
    if ref.outcome == Outcome.STEP_COLLAPSE and _jumps_without_events(case):
        return problems         # the documented outcome of an unmarked jump (Karnopp)
    if ref.outcome != Outcome.COMPLETED:
        problems.append(f"tight rerun ended {ref.outcome}: {ref.message}")
        return problems
    speeds = [n for n in res.signals if n.startswith("omega_")]
    wmax = 1.0 + max(float(np.max(abs(res[n]))) for n in speeds)
    d1 = final_difference(res, ref, speeds)
    if d1 > 1e-3 * wmax:
        # the perturbed tight run, the loose run at a nearby tolerance (only where the
        # network amplifies the perturbation: chaos), then the convergence test (module
        # docstring); the first that moves a tenth as far as the loose run did makes the
        # network sensitive, and the later ones are not run
        def moved(d):
            return np.isfinite(d) and d > SENSITIVE * d1

        def sensitive(d, what):
            if moved(d) and notes is not None:
                notes.append(f"sensitive: the loose run ends {d1:.3g} rad/s from the tight "
                             f"run; {what}: {d:.3g} rad/s")
            return moved(d)

        d2 = final_difference(ref, run(perturbed(case, LOOSE["rtol"]), TIGHT), speeds)
        if sensitive(d2, "a tight run from speeds and inertias perturbed by the loose "
                         "tolerance"):
            return problems
        d4 = 0.0
        if np.isfinite(d2) and d2 >= AMPLIFIES * LOOSE["rtol"] * wmax:
            nearby = {k: v * NEARBY for k, v in LOOSE.items()}
            d4 = final_difference(res, run(case, nearby), speeds)
            if sensitive(d4, f"the loose run at {NEARBY:g} times its tolerance"):
                return problems
        d3 = final_difference(ref, run(case, TIGHTER), speeds)
        if sensitive(d3, f"the tight run from a tighter one (rtol {TIGHTER['rtol']:g})"):
            return problems
        problems.append(f"final speeds differ from the tight rerun by {d1:.3g} rad/s "
                        f"(scale {wmax:.3g}; perturbed by the loose tolerance, the tight run "
                        f"moves {d2:.3g} rad/s; at {NEARBY:g} times its tolerance the loose "
                        f"run moves {d4:.3g} rad/s; the tight run is {d3:.3g} rad/s from a "
                        "tighter one)")
    return problems


def perturbed(case: Case, rel: float) -> Case:
    """``case`` with every initial speed times ``1 + rel`` (gear relations and freewheels
    hold) and the inertias times ``1 ± rel`` in turn (which acts on a network that starts at
    rest too)."""
    comps, k = [], 0
    for c in case.components:
        if isinstance(c, Inertia):
            c = c.with_values(omega0=c.values["omega0"] * (1.0 + rel),
                              J=c.values["J"] * (1.0 + (rel if k % 2 == 0 else -rel)))
            k += 1
        comps.append(c)
    return Case(comps, case.connect, case.inputs, case.text)


def final_difference(a, b, speeds) -> float:
    """The largest difference of the final speeds of two runs [rad/s] (inf when the
    second did not complete)."""
    if b.outcome != Outcome.COMPLETED:
        return np.inf
    return float(np.max(np.abs(np.array([a[n][-1] - b[n][-1] for n in speeds]))))


def _scaled(sig, k: float):
    """A torque signal ``sig`` times ``k`` (its amplitude, height or value)."""
    from dataclasses import replace
    for attr in ("value", "height", "amplitude"):
        if hasattr(sig, attr):
            sig = replace(sig, **{attr: getattr(sig, attr) * k})
    if hasattr(sig, "offset") and not isinstance(sig, (Ramp, Step)):
        sig = replace(sig, offset=sig.offset * k)
    return sig


def variant(case: Case, rng: np.random.Generator) -> Case:
    """The same topology with other values (the compiled plant is reused): inertias scaled
    by factors in [0.5, 2], every initial speed by one factor in [0, 2] (which keeps gear
    relations and freewheels), torque sources by factors in [-2, 2]."""
    s = rng.uniform(0.0, 2.0)
    comps = []
    for c in case.components:
        if isinstance(c, Inertia):
            c = c.with_values(J=c.values["J"] * rng.uniform(0.5, 2.0),
                              omega0=c.values["omega0"] * s)
        comps.append(c)
    inputs = {k: (_scaled(v, rng.uniform(-2.0, 2.0)) if k.startswith("tau") else v)
              for k, v in case.inputs.items()}
    # the text gives every value that changed, so that the case can be rebuilt from it
    return Case(comps, case.connect, inputs,
                case.text + ["variant: " + ", ".join(
                    f"{c.name} J = {c.values['J']!r}, omega0 = {c.values['omega0']!r}"
                    for c in comps if isinstance(c, Inertia))
                    + "; " + ", ".join(f"{k} {v}" for k, v in inputs.items()
                                       if k.startswith("tau"))])
