"""Model (6) of Mykhailevych (2020): limits, damping, pre-sliding, reset policies (T11)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clutchsim.friction import RESET_POLICIES, Mykhailevych2020, SelfExcitedWarning, make_model


@pytest.fixture
def m6():
    return Mykhailevych2020.from_parameters("mykhailevych2020_translational")


def test_translational_set_is_T11(m6):
    assert (m6.T_stat, m6.phi0, m6.omega0, m6.k_v, m6.p, m6.reset, m6.reset_c) == (
        1.5,
        1.5e-5,
        1e-2,
        316.0,
        2.0,
        "clamp",
        2.0,
    )
    assert m6.T_din == pytest.approx(1.0)
    assert m6.c_eff == 316.0


def test_clutch_set_capacity_and_damping():
    clutch = Mykhailevych2020.from_parameters("mykhailevych2020_clutch")
    assert clutch.T_stat == pytest.approx(4000.0 * 0.3 * 0.1 * 2)
    assert clutch.c_eff > 0.0
    assert 0.5 <= clutch.omega0 <= 10.0 and 1e-4 <= clutch.phi0 <= 1e-2
    assert clutch.unit_of("T_stat", "rotational") == "N·m"
    assert clutch.state_units("rotational") == ("rad",)


def test_steady_sliding_limits(m6, force):
    # v -> 0+ in steady sliding (tanh = +1): the static capacity T_stat
    assert float(m6.steady_state_force(1e-12)) == pytest.approx(m6.T_stat, rel=1e-9)
    assert float(m6.steady_state_force(-1e-12)) == pytest.approx(-m6.T_stat, rel=1e-9)
    # far out: T_din + k_v·v
    for v in (0.2, 1.0):
        assert float(m6.steady_state_force(v)) == pytest.approx(m6.T_din + m6.k_v * v, rel=1e-12)
    # at v = 0 the force is the elastic term alone (not T_stat): T_stat·tanh(phi/phi0)
    phi = 0.3 * m6.phi0
    F, dz = force(m6, [phi], 0.0)
    assert F == pytest.approx(m6.T_stat * math.tanh(0.3), rel=1e-14)
    assert dz[0] == 0.0


def test_c_eff_derivation_matches_numerical_slope(force):
    for p, k_v in ((1, 600.0), (2, 316.0)):
        model = make_model("mykhailevych2020", p=p, k_v=k_v)
        h = 1e-9
        slope = (force(model, [0.0], h)[0] - force(model, [0.0], -h)[0]) / (2 * h)
        assert slope == pytest.approx(model.c_eff, rel=1e-4)
    assert make_model("mykhailevych2020", p=1, k_v=600.0).c_eff == pytest.approx(600.0 - 50.0)


def test_self_excited_warning_p1():
    with pytest.warns(SelfExcitedWarning, match="c_eff = -499.6"):
        model = Mykhailevych2020(T_stat=1.5, k_din=2 / 3, phi0=1e-3, omega0=1e-3, k_v=0.4, p=1)
    assert model.c_eff == pytest.approx(-499.6)


def test_no_warning_when_damped(recwarn):
    Mykhailevych2020(T_stat=1.5, k_din=2 / 3, phi0=1e-3, omega0=1e-3, k_v=0.4, p=2)
    Mykhailevych2020(T_stat=1.5, k_din=2 / 3, phi0=1e-3, omega0=1e-2, k_v=60.0, p=1)
    assert not [w for w in recwarn if issubclass(w.category, SelfExcitedWarning)]


def test_unknown_reset_policy_lists_valid_ones(m6):
    with pytest.raises(
        ValueError, match="reset = 'clip'.*clamp, zero, plus_phi0, minus_phi0, none"
    ):
        m6.with_(reset="clip")


@pytest.mark.parametrize(
    ("policy", "phi", "expected", "ret"),
    [
        ("clamp", 5.0, 2.0, 1),
        ("clamp", -5.0, -2.0, 1),
        ("clamp", 1.5, 1.5, 0),
        ("zero", 0.7, 0.0, 1),
        ("plus_phi0", -0.3, -1.0, 1),
        ("minus_phi0", 0.3, -1.0, 1),
        ("minus_phi0", -4.0, 1.0, 1),
        ("none", 9.0, 9.0, 0),
    ],
)
def test_reset_map(m6, policy, phi, expected, ret):
    from clutchsim.friction import friction_reset

    model = m6.with_(reset=policy)
    z = np.array([phi * model.phi0])
    assert friction_reset(model.code, model.pack(), z, 0.0, 0.0, 1.0, 0) == ret
    assert z[0] == pytest.approx(expected * model.phi0, rel=1e-15)
    assert RESET_POLICIES[policy] == int(model.pack()[6])


def test_presliding_equilibrium_under_constant_force(m6, simulate_mass):
    """M1: constant 0.5 N on 1 kg settles at phi* = phi0·atanh(T/T_stat)."""
    T = 0.5
    states, _ = simulate_mass(m6, lambda t: T, [1.0])
    x, v, phi = states[0]
    expected = m6.phi0 * math.atanh(T / m6.T_stat)
    assert expected == pytest.approx(5.199e-6, rel=1e-3)  # T11 table
    assert x == pytest.approx(expected, rel=1e-3)
    assert phi == pytest.approx(expected, rel=1e-3)
    assert abs(v) < 1e-9


def _m2(t):
    return 0.5 + 0.4 * math.sin(2 * math.pi * t)


def test_clamp_reset_does_not_drift(m6, simulate_mass):
    """M2 (T11) with the default clamp policy: drift per cycle < 1e-9 m."""
    states, n_events = simulate_mass(m6, _m2, [3.0, 4.0, 5.0])
    x3, x4, x5 = states[:, 0]
    assert n_events >= 4  # the velocity reversals were located
    assert abs(x5 - x4) < 1e-9 and abs(x4 - x3) < 1e-9
    assert 0.0 < x4 < 2 * m6.phi0  # stays in the elastic range


def test_zero_reset_ratchets_forward(m6, simulate_mass):
    """M2 with the seed's literal 'zeroing': ratchets forward (T11: +490.99 µm/cycle).

    Our events are located by scipy (T11 used fixed-step RK4 resetting at the
    sampled sign change), so we compare to 1 %; the looser rtol keeps it fast.
    """
    states, n_events = simulate_mass(m6.with_(reset="zero"), _m2, [1.0, 2.0],
                                     rtol=1e-6, atol=1e-10)  # fmt: skip
    x1, x2 = states[:, 0]
    assert x1 > 100e-6 and x2 - x1 > 100e-6
    assert x2 - x1 == pytest.approx(490.99e-6, rel=0.01)
    assert n_events > 50


def test_plus_phi0_reset_ratchets_backward(m6, simulate_mass):
    """M2 with phi := +sign(phi)·phi0: ratchets backward (T11: -477.74 µm/cycle)."""
    states, _ = simulate_mass(m6.with_(reset="plus_phi0"), _m2, [1.0, 2.0],
                              rtol=1e-6, atol=1e-10)  # fmt: skip
    x1, x2 = states[:, 0]
    assert x2 - x1 < -100e-6
    assert x2 - x1 == pytest.approx(-477.74e-6, rel=0.01)


def test_none_reset_keeps_no_permanent_slip(m6, simulate_mass):
    """R0 under M1: exact elastic equilibrium, like clamp (T11: 5.199 µm)."""
    states, _ = simulate_mass(m6.with_(reset="none"), lambda t: 0.5, [0.5])
    assert states[0, 0] == pytest.approx(m6.phi0 * math.atanh(1 / 3), rel=1e-3)


def test_event_declaration(m6):
    assert m6.n_events == 1
    assert m6.event_names() == ("velocity_zero_crossing",)
    assert m6.event_directions().tolist() == [0]
    assert m6.event_directions().dtype == np.int64


# ------------------------------------------------------------ the stop operator (no event)
def test_stop_declares_no_event_and_its_kernel_writes_none(m6):
    """Policy ``stop`` needs no event: the model declares none, and the events kernel
    leaves the (empty) indicator vector alone; every other policy keeps the zero crossing."""
    from clutchsim.friction import friction_events

    stop = m6.with_(reset="stop")
    assert stop.n_events == 0 and stop.event_names() == ()
    assert stop.event_directions().shape == (0,)
    g = np.full(1, np.nan)
    friction_events(stop.code, stop.pack(), np.array([3e-5]), 0.2, 0.0, 1.0, g)
    assert np.isnan(g[0])
    for policy in RESET_POLICIES:
        if policy != "stop":
            assert m6.with_(reset=policy).event_names() == ("velocity_zero_crossing",)


def _stop_closed_form(x, cap):
    """The stop operator of hysteresis theory on the sampled input x(t) (phi(0) = 0):
    phi follows every increment of x and is clipped to [-cap, cap]; exact for any x
    sampled finely enough that each sample's increment is one-signed."""
    phi = np.zeros_like(x)
    for i in range(1, x.size):
        phi[i] = min(max(phi[i - 1] + x[i] - x[i - 1], -cap), cap)
    return phi


def test_stop_kernel_is_the_stop_operator_and_lands_on_the_clamp_value(m6):
    """Driven by v = A·cos(ωt) (travel ±3·phi0 between reversals, past the bound
    c·phi0 = 2·phi0), dphi/dt of the compiled kernel integrates to the stop operator's
    closed form, and at every zero crossing of v phi equals clamp's reset value
    sign(phi)·min(|phi|, c·phi0) = ±2·phi0 — without an event."""
    from scipy.integrate import solve_ivp

    from clutchsim.friction import friction_force

    stop = m6.with_(reset="stop")
    p, phi0, cap = stop.pack(), stop.phi0, stop.reset_c * stop.phi0
    w = 2.0 * math.pi
    A = 3.0 * phi0 * w
    dz = np.zeros(1)

    def rhs(t, y):
        friction_force(stop.code, p, y, A * math.cos(w * t), 0.0, 1.0, dz)
        return dz.copy()

    t = np.linspace(0.0, 3.0, 30001)
    sol = solve_ivp(rhs, (0.0, 3.0), [0.0], t_eval=t, method="DOP853", rtol=1e-12,
                    atol=1e-12 * phi0, max_step=1e-3)
    assert sol.status == 0
    exact = _stop_closed_form(3.0 * phi0 * np.sin(w * t), cap)
    assert np.max(np.abs(sol.y[0] - exact)) < 1e-6 * phi0
    reversals = np.arange(0.25, 3.0, 0.5)        # zeros of cos(ωt)
    at = np.interp(reversals, t, sol.y[0])
    np.testing.assert_allclose(at, cap * np.sign(np.sin(w * reversals)), rtol=1e-6)
    assert np.max(np.abs(sol.y[0])) <= cap * (1.0 + 1e-6)


def test_stop_capacity_sliding_force_and_presliding_equilibrium(m6, simulate_mass):
    """The normalised spring T_stat·tanh(phi/phi0)/tanh(c): the force held at the bound is
    T_stat exactly (clamp's capacity), steady sliding is clamp's T_ss(v) — the pre-sliding
    damper c_ps·v·(1 - th²) vanishes at the bound, as sech² does in clamp's sliding — and
    a constant load T is held at phi* = phi0·atanh(T·tanh(c)/T_stat) (M1: 0.5 N on 1 kg)."""
    from clutchsim.friction import friction_force

    stop = m6.with_(reset="stop")
    p, cap = stop.pack(), stop.reset_c * stop.phi0
    dz = np.zeros(1)
    assert friction_force(stop.code, p, np.array([cap]), 0.0, 0.0, 1.0, dz) == \
        pytest.approx(stop.T_stat, rel=1e-15)
    damped = stop.with_(c_ps=100.0)
    for v in (-0.3, -1e-3, 2e-3, 0.05):
        F = friction_force(stop.code, damped.pack(), stop.sliding_state(v), v, 0.0, 1.0, dz)
        assert F == pytest.approx(float(m6.steady_state_force(v)), rel=1e-14)
        assert dz[0] == 0.0                   # the stop holds phi in sliding
    T = 0.5
    states, n_events = simulate_mass(stop, lambda t: T, [1.0])
    x, v, phi = states[0]
    expected = stop.phi0 * math.atanh(T * math.tanh(stop.reset_c) / stop.T_stat)
    assert n_events == 0
    assert x == pytest.approx(expected, rel=1e-3) and phi == pytest.approx(expected, rel=1e-3)
    assert abs(v) < 1e-9


def _d2(t):
    """D2 (docs/benchmarks.md): 1.6 N > T_stat for 0.5 s (gross sliding), then D1's
    biased sine."""
    return 1.6 if t < 0.5 else 0.5 + 0.4 * math.sin(2 * math.pi * (t - 0.5))


def test_stop_does_not_drift_after_gross_sliding(m6, simulate_mass):
    """D2 with the stop operator: after 0.5 s of gross sliding phi stands at the bound
    c·phi0 (clamp's value at the next reversal), and the biased sine that follows makes
    no drift per cycle (< 1e-9 m) — with no event located.  The slip of the sliding phase
    stays, as with clamp (x within phi0 of clamp's: 156.9 against 162.1 µm); with
    ``none`` phi is left at 12.5·phi0 and the body slides back to 5.1 µm."""
    stop = m6.with_(reset="stop")
    states, n_events = simulate_mass(stop, _d2, [0.5, 3.5, 4.5, 5.5])
    assert n_events == 0
    assert states[0, 2] == pytest.approx(stop.reset_c * stop.phi0, rel=1e-6)
    x3, x4, x5 = states[1:, 0]
    assert abs(x5 - x4) < 1e-9 and abs(x4 - x3) < 1e-9
    clamp, n_clamp = simulate_mass(m6, _d2, [3.5])
    assert n_clamp > 0 and abs(x3 - clamp[0, 0]) < m6.phi0
    free, _ = simulate_mass(m6.with_(reset="none"), _d2, [3.5])
    assert free[0, 0] < 2.0 * m6.phi0 and x3 > 10.0 * m6.phi0


def test_plants_read_the_events_from_the_policy(m6):
    """The rig and the network plant take the model's events: none with stop, the zero
    crossing with clamp; the two are different structures, so a network compiled for one
    policy is never reused for the other (a sweep over ``reset`` builds both)."""
    from clutchsim.network.plant import structure_key
    from clutchsim.rig import make_rig
    from clutchsim.scenario import load_scenario

    stop = m6.with_(reset="stop")
    assert make_rig(stop).event_names == ()
    assert make_rig(m6).event_names == ("mykhailevych2020: velocity_zero_crossing",)
    nets = [load_scenario(None, overrides=over).network("mykhailevych2020")
            for over in ([], ["coupling[0].friction.overrides.reset='stop'"])]
    nets = [n if hasattr(n, "components") else n.network() for n in nets]
    assert structure_key(nets[0]) != structure_key(nets[1])
