"""Gear lash (``elasto_backlash``, Modelica ElastoBacklash): free flight and elastic
contact in closed form, the limited damping against an independent integration of
Modelica's equations, the energy balance, the exact Jacobian in every contact mode, and
bad input."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_network import _jac_fd

from clutchsim.analysis.launch_metrics import energy_balance
from clutchsim.core import SolverOptions, simulate
from clutchsim.network import Network
from clutchsim.network.components import ElastoBacklash, Inertia, TorqueSource

J1, J2 = 1.0, 2.0
OPTS = SolverOptions(rtol=1e-10, atol=1e-12, dt_out=1e-4)


def two_mass(w0=1.0, **lash):
    """Inertia a (at rest, driven by input tau) -> lash -> inertia b (turning at w0)."""
    return Network([TorqueSource("drive", input="tau"), Inertia("a", J=J1),
                    ElastoBacklash("lash", **lash), Inertia("b", J=J2, omega0=w0)],
                   [["drive.flange", "a.a"], ["a.b", "lash.a"], ["lash.b", "b.a"]])


def modelica_torque(s, w, b, c, d):
    """ElastoBacklash's flange torque (MSL 4.x equations, written out independently)."""
    if b <= 1e-10:
        return c * s + d * w
    tc = c * (s - b / 2) if s > b / 2 else (c * (s + b / 2) if s < -b / 2 else 0.0)
    td = d * w
    if s > b / 2:
        return 0.0 if tc + td <= 0 else tc + min(tc, td)
    if s < -b / 2:
        return 0.0 if tc + td >= 0 else tc + max(tc, td)
    return 0.0


def test_free_flight_and_elastic_contact_in_closed_form():
    """d = 0: the twist grows at w0 across the half gap (t = b/2/w0), the contact is half a
    period of the reduced two-mass spring (π·sqrt(J_r/c)), and the relative speed comes
    back reversed; then the flight across the whole gap takes b/w0."""
    b, c, w0 = 0.02, 1e4, 1.0
    res = simulate(two_mass(w0, b=b, c=c).build(), (0.0, 0.14), {"tau": 0.0}, options=OPTS)
    assert res.status == "completed", res.message
    half = np.pi * np.sqrt(J1 * J2 / (J1 + J2) / c)
    t_edges = [b / 2 / w0]
    for k in range(5):
        t_edges.append(t_edges[-1] + (half if k % 2 == 0 else b / w0))
    ev = [e.t for e in res.events]
    assert np.allclose(ev[:6], t_edges, atol=1e-8)
    names = [e.name for e in res.events]
    assert names[:4] == ["lash: gap edge +b/2"] * 2 + ["lash: gap edge -b/2"] * 2
    w_rel = res["omega_b"] - res["omega_a"]
    flight = (res.t > t_edges[1] + 1e-4) & (res.t < t_edges[2] - 1e-4)
    assert np.allclose(w_rel[flight], -w0, atol=1e-7)
    gap = (res.t > 1e-4) & (res.t < t_edges[0] - 1e-4)
    assert np.all(res["T_lash"][gap] == 0.0)
    assert energy_balance(res)["energy_balance_rel"] < 1e-6


def test_limited_damping_matches_modelica_equations():
    """d > 0: the contact never pulls (its torque keeps the side's sign, and is 0 while
    cut off), the rebound is slower than the approach, and the run follows an independent
    integration of Modelica's ElastoBacklash equations (tube 2e-3, met by far)."""
    b, c, d, w0, rel0 = 0.02, 1e4, 40.0, 1.0, 0.004
    lash = {"b": b, "c": c, "d": d, "phi_rel0": rel0, "phi0": rel0}
    res = simulate(two_mass(w0, **lash).build(), (0.0, 0.3), {"tau": 0.0}, options=OPTS)
    assert res.status == "completed", res.message

    def f(t, y):
        phi, wa, wb = y
        tau = modelica_torque(phi - rel0, wb - wa, b, c, d)
        return [wb - wa, tau / J1, -tau / J2]

    ref = solve_ivp(f, (0.0, 0.3), [rel0, 0.0, w0], method="DOP853", rtol=1e-11, atol=1e-13,
                    t_eval=res.t, max_step=2e-4)
    for k, name in enumerate(("phi_lash", "omega_a", "omega_b")):
        err = np.max(np.abs(res[name] - ref.y[k])) / max(np.max(np.abs(ref.y[k])), 1.0)
        assert err < 1e-6, name
    tau, side = res["T_lash"], res["contact_lash"]
    assert np.all(side * tau >= 0.0) and np.all(tau[side == 0.0] == 0.0)
    w_rel = res["omega_b"] - res["omega_a"]
    first_flight_back = np.flatnonzero((side == 0.0) & (w_rel < 0.0))[0]
    assert 0.0 < -w_rel[first_flight_back] < 0.95 * w0       # energy lost in the contact
    eb = energy_balance(res)
    assert eb["energy_balance_rel"] < 1e-6 and eb["W_damping"] > 0.0


@pytest.mark.parametrize("b, phi, w_rel, mode", [
    (0.02, 0.0, 0.7, "gap"),
    (0.02, 0.015, 0.5, "spring and damper"),
    (0.02, 0.015, 2.0, "damping limited to the spring"),
    (0.02, 0.015, -2.0, "cut off"),
    (0.02, -0.015, -0.5, "spring and damper"),
    (0.02, -0.015, -2.0, "damping limited to the spring"),
    (0.02, -0.015, 2.0, "cut off"),
    (0.0, 0.003, 0.3, "plain spring-damper"),
])
def test_exact_jacobian_in_every_contact_mode(b, phi, w_rel, mode):
    sys_ = two_mass(b=b, c=1e4, d=50.0).build()
    y = sys_.y0.copy()
    names = sys_.state_names
    y[names.index("omega_a")] = 3.0
    y[names.index("omega_b")] = 3.0 + w_rel
    y[names.index("phi_lash")] = phi
    J, Jfd = _jac_fd(sys_, y, np.zeros(1))
    assert np.max(np.abs(J - Jfd) / np.maximum(np.abs(Jfd), 1.0)) < 1e-6, mode
    if mode == "gap":
        assert not np.any(J[:2, :3])


def test_bad_backlash_names_component_key_value_and_rule():
    with pytest.raises(ValueError, match=r"elasto backlash 'lash': b = -0.01 rad must be >= 0"):
        ElastoBacklash("lash", b=-0.01, c=1e4)
    with pytest.raises(ValueError, match=r"c = 0 N·m/rad must be > 0"):
        ElastoBacklash("lash", b=0.01, c=0.0)


def test_bad_backlash_in_a_scenario_gives_file_and_line(tmp_path):
    from clutchsim.scenario import ScenarioError, load_scenario
    path = tmp_path / "lash.toml"
    path.write_text(
        '[scenario]\nname = "bad lash"\nt_end = 0.1\n\n[inputs]\ntau = 0.0\n\n'
        '[network]\nconnect = [["drive.flange", "a.a"], ["a.b", "lash.a"], ["lash.b", "b.a"]]\n\n'
        '[[component]]\ntype = "torque"\nname = "drive"\ninput = "tau"\n\n'
        '[[component]]\ntype = "inertia"\nname = "a"\nJ = 1.0\n\n'
        '[[component]]\ntype = "elasto_backlash"\nname = "lash"\nb = -0.01\nc = 1e4\n\n'
        '[[component]]\ntype = "inertia"\nname = "b"\nJ = 2.0\n')
    with pytest.raises(ScenarioError) as exc:
        load_scenario(path).network()
    msg = str(exc.value)
    assert "lash.toml:24" in msg and "component[2].b" in msg and "-0.01 rad" in msg
    assert ">= 0" in msg


def test_tip_in_clunk_example_reverses_the_torque_through_the_lash():
    """examples/tip_in_clunk.toml: on the drive flanks (T < 0) before the tip-out, across the
    gap onto the coast flanks (T > 0) after it, back onto the drive flanks after the tip-in;
    every crossing is a located gap-edge event; energy balanced."""
    from _dl_paths import EXAMPLES

    from clutchsim.scenario import run_scenario
    r = run_scenario(EXAMPLES / "tip_in_clunk.toml")
    res = r.result
    assert res.status == "completed", res.message
    t, tau, side = res.t, res["T_lash"], res["contact_lash"]
    assert np.all(tau[t < 0.5] < 0.0) and np.all(side[t < 0.5] == -1.0)
    coast = (t > 0.55) & (t < 1.5)
    assert np.max(tau[coast]) > 40.0 and np.any(side[coast] == 1.0)
    assert np.all(tau[t > 1.7] < 0.0)
    first = {name: min(e.t for e in res.events if e.name == name)
             for name in ("lash: gap edge -b/2", "lash: gap edge +b/2")}
    assert 0.5 < first["lash: gap edge -b/2"] < first["lash: gap edge +b/2"] < 0.7
    assert any(1.5 < e.t < 1.6 and e.name == "lash: gap edge -b/2" for e in res.events)
    assert r.metrics["energy_balance_rel"] < 1e-6


def test_run_writes_the_components_figure(tmp_path):
    """``write_runs`` (what ``clutchsim run --out`` calls) adds ``components_MODEL.png`` for a
    run with gear lash, and not for the default launch, which has none of those parts."""
    from _dl_paths import EXAMPLES

    from clutchsim.scenario import load_scenario
    from clutchsim.scenario.outputs import write_runs
    sc = load_scenario(EXAMPLES / "tip_in_clunk.toml")
    model = sc.models[0] if sc.models else None
    write_runs(sc, [model], tmp_path / "lash")
    assert sorted(p.name for p in (tmp_path / "lash").glob("components_*.png"))
    write_runs(load_scenario(None), ["mykhailevych2020"], tmp_path / "launch")
    assert not list((tmp_path / "launch").glob("components_*.png"))
