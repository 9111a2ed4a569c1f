"""Linearisation and modes against closed forms and time simulation."""

import math
import warnings

import numpy as np
import pytest

from clutchsim.analysis import element_points, linearise, modes
from clutchsim.core import SolverOptions, simulate
from clutchsim.friction import make_model
from clutchsim.network import Network
from clutchsim.network.components import Brake, Clutch, IdealGear, Inertia, SpringDamper

# J·θ'' + (c + s)·θ' + k·θ = 0: a disc on a torsional spring to a drive held at w0 (an
# inertia 1e10 times the disc's), braked by a Stribeck brake slipping at w0
J, K, C, W0 = 0.1, 1000.0, 1.0, 1.0
F_C, F_S, V_S = 10.0, 15.0, 2.0


def _series(inertias, couplings, brakes=()):
    """Inertias in series, coupling k between inertia k (flange a) and k+1 (flange b), and
    ``(brake, inertia name)`` brakes to the housing."""
    conns = [pair for k, c in enumerate(couplings)
             for pair in ((f"{inertias[k].name}.b", f"{c.name}.a"),
                          (f"{c.name}.b", f"{inertias[k + 1].name}.a"))]
    conns += [(f"{b.name}.flange", f"{node}.a") for b, node in brakes]
    return Network([*inertias, *couplings, *(b for b, _ in brakes)], conns)


def _slope(v):
    """dT/dω of the Stribeck brake at v (tanh(v/v_t) = 1 there)."""
    return -(F_S - F_C) * 2.0 * v / V_S**2 * math.exp(-((v / V_S) ** 2))


def _belt(phi0):
    brake = make_model("stribeck", F_c=F_C, F_s=F_S, v_s=V_S, delta=2.0, v_t=1e-5, sigma2=0.0)
    net = _series([Inertia("drive", J=1e9, omega0=W0), Inertia("disc", J=J, omega0=W0)],
                  [SpringDamper("spring", c=K, d=C, phi0=phi0)],
                  [(Brake("brake", brake, "com"), "disc")])
    return net.build({"com": 1.0})


def _oscillatory(ms):
    return [m for m in ms if m.frequency_hz > 0.0]


def test_slipping_mode_equals_the_closed_form():
    system = _belt(0.0)
    lin = linearise(system, 0.0, system.y0, np.array([1.0]))
    (mode,) = _oscillatory(modes(lin))
    s = _slope(W0)
    wn = math.sqrt(K / J)
    zeta = (C + s) / (2.0 * math.sqrt(K * J))
    assert mode.frequency_hz == pytest.approx(wn / (2 * math.pi), rel=1e-6)
    assert mode.damping_ratio == pytest.approx(zeta, rel=1e-6)
    assert mode.growth_rate_1_s == pytest.approx(-(C + s) / (2 * J), rel=1e-6)
    assert not mode.stable and zeta < 0          # c + dT/dω < 0: self-excited
    assert set(mode.dominant_states) <= {"omega_disc", "phi_spring"}
    (e,) = element_points(system, 0.0, system.y0, np.array([1.0]))
    assert e.state == "slipping" and e.slip_rad_s == pytest.approx(W0)
    assert e.friction_slope_Nms == pytest.approx(s, rel=1e-7)


def test_simulated_oscillation_grows_at_the_predicted_rate():
    s = _slope(W0)
    growth = -(C + s) / (2 * J)
    # equilibrium twist: the spring holds the brake torque; start 1e-5 rad off it
    T0 = (F_C + (F_S - F_C) * math.exp(-((W0 / V_S) ** 2)))
    system = _belt(0.0)
    y0 = system.y0.copy()
    i_phi = system.state_names.index("phi_spring")
    y_eq = -T0 / K if _res_sign(system) < 0 else T0 / K
    y0[i_phi] = y_eq + 1e-5
    res = simulate(system, (0.0, 0.6), {"com": 1.0}, y0=y0,
                   options=SolverOptions(rtol=1e-10, atol=1e-13, dt_out=1e-4))
    assert res.status == "completed"
    x = res["phi_spring"] - y_eq
    t = res.t
    peaks = [i for i in range(1, x.size - 1) if x[i] > x[i - 1] and x[i] >= x[i + 1]]
    assert len(peaks) > 5
    tp, xp = [], []
    for i in peaks:                                  # parabolic peak interpolation
        a, b, c = x[i - 1], x[i], x[i + 1]
        d = 0.5 * (a - c) / (a - 2 * b + c)
        tp.append(t[i] + d * (t[1] - t[0]))
        xp.append(b - 0.25 * (a - c) * d)
    rate = np.polyfit(tp, np.log(xp), 1)[0]
    assert rate == pytest.approx(growth, rel=0.02)
    assert max(abs(res["omega_disc"] - W0)) < 0.05   # stayed in the linear range


def _res_sign(system):
    """Sign of the spring torque on the disc for a positive twist (from the plant)."""
    from clutchsim.core.system import call_rhs
    y = system.y0.copy()
    y[system.state_names.index("phi_spring")] = 1e-3
    dy = np.zeros(system.n_states)
    call_rhs(system.tag, 0.0, y, np.array([0.0]), system.params, dy)
    return np.sign(dy[system.state_names.index("omega_disc")])


def test_locked_driveline_modes_are_the_mkc_eigenvalues():
    ja, jb, jc, jd, r = 0.3, 0.2, 0.4, 0.7, 2.0
    da, db, dc, dd = 0.02, 0.01, 0.03, 0.1
    k, c = 500.0, 0.5
    strong = make_model("coulomb-robust", F_c=1e4, F_s=1e4)
    net = _series([Inertia("a", J=ja, bearing_damping=da),
                   Inertia("b", J=jb, bearing_damping=db),
                   Inertia("c", J=jc, bearing_damping=dc),
                   Inertia("d", J=jd, bearing_damping=dd)],
                  [Clutch("clutch", strong, "com"), IdealGear("gear", ratio=r),
                   SpringDamper("shaft", c=k, d=c)])
    system = net.build({"com": 1.0})
    u = np.array([1.0])
    lin = linearise(system, 0.0, system.y0, u)
    assert lin.locked == ("clutch",)
    # the network plant holds independent speeds (the gear is solved when it is built):
    # only the locked clutch merges one
    assert len(lin.merged) == 1 and "omega_a" in lin.state_names
    # angles (theta_a, theta_d): the cluster a+b+c (c behind the gear) and d
    M = np.diag([ja + jb + jc / r**2, jd])
    Kq = k * np.array([[1 / r**2, -1 / r], [-1 / r, 1.0]])
    Cq = c * np.array([[1 / r**2, -1 / r], [-1 / r, 1.0]]) + np.diag([da + db + dc / r**2, dd])
    Mi = np.linalg.inv(M)
    big = np.block([[np.zeros((2, 2)), np.eye(2)], [-Mi @ Kq, -Mi @ Cq]])
    expected = np.linalg.eigvals(big)
    expected = np.sort_complex(expected[np.abs(expected) > 1e-9])   # no absolute angle
    got = np.sort_complex(np.linalg.eigvals(lin.A))
    assert got.size == expected.size == 3
    np.testing.assert_allclose(got, expected, rtol=1e-7)
    ms = modes(lin)
    assert [m.frequency_hz > 0 for m in ms] == [False, True]   # a pair counts once
    assert all(m.stable for m in ms)
    (e,) = element_points(system, 0.0, system.y0, u)
    assert e.state == "locked" and e.friction_slope_Nms is None


def test_free_element_and_bad_inputs():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        net = _series([Inertia("a", J=1.0, omega0=5.0), Inertia("b", J=1.0)],
                      [Clutch("clutch", make_model("tanh", F_c=10.0), "com")])
    system = net.build({"com": 0.0})
    (e,) = element_points(system, 0.0, system.y0, np.array([0.0]))
    assert e.state == "free" and e.slip_rad_s == pytest.approx(-5.0)
    with pytest.raises(ValueError, match="'clutc' does not exist.*did you mean 'clutch'"):
        element_points(system, 0.0, system.y0, np.array([0.0]), ["clutc"])
    with pytest.raises(ValueError, match="u has shape"):
        linearise(system, 0.0, system.y0, np.array([0.0, 1.0]))
    with pytest.raises(ValueError, match="not a linearised state"):
        linearise(system, 0.0, system.y0, np.array([0.0]), constraints=[{"omega_x": 1.0}])


def test_frequency_response_matches_a_forced_simulation():
    """Clamp-load oscillation (the brake command) to the disc speed: |H| and phase of the
    linear model against a time simulation driven at 10 Hz (the mode is at 15.9 Hz)."""
    from clutchsim.analysis import frequency_response, state_space
    from clutchsim.core import Sine
    brake = make_model("stribeck", F_c=F_C, F_s=F_S, v_s=V_S, delta=2.0, v_t=1e-5,
                       sigma2=0.0)
    T0 = F_C + (F_S - F_C) * math.exp(-((W0 / V_S) ** 2))
    net = _series([Inertia("drive", J=1e9, omega0=W0), Inertia("disc", J=J, omega0=W0)],
                  [SpringDamper("spring", c=K, d=5.0, phi0=0.0)],
                  [(Brake("brake", brake, "com"), "disc")])
    system = net.build({"com": 1.0})
    y0 = system.y0.copy()
    y0[system.state_names.index("phi_spring")] = T0 / K * _res_sign(system)   # equilibrium
    u = np.array([1.0])
    lin = linearise(system, 0.0, y0, u)
    assert all(m.stable for m in modes(lin))          # c + dT/dω = 3.05 > 0
    f, amp = 10.0, 1e-3
    ss = state_space(system, lin, y0, u)
    fr = frequency_response(ss, "com", "omega_disc", [f])
    res = simulate(system, (0.0, 2.0), {"com": Sine(amp, f, offset=1.0)}, y0=y0,
                   options=SolverOptions(rtol=1e-10, atol=1e-13, dt_out=2e-4))
    assert res.status == "completed"
    sel = res.t >= 1.5                                  # 5 periods after the transient
    t, x = res.t[sel], res["omega_disc"][sel] - W0
    s_ = 2 * np.trapezoid(x * np.sin(2 * np.pi * f * t), t) / (t[-1] - t[0])
    c_ = 2 * np.trapezoid(x * np.cos(2 * np.pi * f * t), t) / (t[-1] - t[0])
    assert math.hypot(s_, c_) == pytest.approx(fr.magnitude[0] * amp, rel=0.02)
    assert math.atan2(c_, s_) == pytest.approx(math.radians(fr.phase_deg[0]), abs=0.03)
    assert fr.input_unit == "-" and fr.output_unit == "rad/s" and fr.unit == "rad/s"
    assert fr.warnings == ()
    with pytest.raises(ValueError, match="not an input"):
        frequency_response(ss, "throttle", "omega_disc", [f])
