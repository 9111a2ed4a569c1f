"""Analytic Jacobians of the friction models and of the friction rig, against finite differences.

Every model's ``<model>_jacobian`` kernel is compared entry by entry with central finite
differences of its ``<model>_force`` kernel (Richardson-extrapolated: steps ``h`` and
``h/2``, error O(h^4)), at states, velocities, stick forces and capacity multipliers drawn
by hypothesis; the rig's ``_rig_jac`` likewise against its right-hand side.

Steps and tolerance. Each argument ``x_j`` has a typical scale ``S_j`` from the model's
parameters (a velocity: the smallest velocity on which the curve changes, e.g. ``v_t`` or
``v_s``; a state: its steady sliding deflection, e.g. ``F_c/sigma0``; a force: the
friction level; ``scale``: 1), and the step is ``h_j = 1e-4·S_j``. An entry passes when
``|J - J_fd| <= 1e-6·(|J_fd| + T)`` with ``T = S_out/S_j`` (``S_out``: the friction level
for F, the velocity scale for a state derivative): the typical size of that partial
derivative, so that an entry that is zero (or nearly so) is not held to a relative error
of round-off noise. The finite-difference error is far below this: truncation
~(h/S)^4 = 1e-16, round-off ~eps·S/h = 1e-12 relative to ``T``.

Margin from the nonsmooth points. A point is used only if every point of its stencil
(each argument moved by up to ``±h_j``) lies on the same smooth piece as the point itself
(``_piece`` names the pieces of each model: sign of ``v``, stuck/sliding, the clip of the
stick force, the elasto-plastic and GMS zones); so the margin is ``h_j = 1e-4·S_j`` in
every argument. Velocities are drawn with ``|v| >= 1e-2·S_v``; exactly ``v = 0`` is tested
on its own against one-sided (``v -> 0+``) differences, as the kernels document.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from clutchsim import friction as fr
from clutchsim.core.system import call_jac, call_rhs, has_jacobian
from clutchsim.friction import list_parameter_sets, load_parameter_set, make_model
from clutchsim.rig import make_rig

REL = 1e-6
STEP = 1e-4


def _variants():
    """Every packaged parameter set of every model, plus variants that reach the other
    branches of the kernels (Stribeck exponents 1 and non-integer, Dahl's alpha != 1, the
    Stribeck term of coulomb-robust, model (6) with p = 1)."""
    cases = []
    for set_name in list_parameter_sets():
        pset = load_parameter_set(set_name)
        for name in pset.models:
            cases.append((f"{name}[{set_name}]", name, dict(pset.parameters)))
    extra = [
        ("coulomb-robust", {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "delta": 2.0, "sigma2": 0.4}),
        ("coulomb-robust", {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "delta": 1.0, "sigma2": 0.4}),
        ("coulomb-robust", {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "delta": 0.7}),
        ("stribeck", {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "delta": 1.0, "v_t": 1e-5}),
        ("dahl", {"F_c": 1.0, "sigma0": 1e5, "alpha": 0.6}),
        ("dahl", {"F_c": 1.0, "sigma0": 1e5, "alpha": 2.5}),
        ("lugre", {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "sigma0": 1e5, "sigma1": 316.0,
                   "sigma2": 0.4, "delta": 1.0}),
        ("lugre", {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "sigma0": 1e5, "sigma1": 316.0,
                   "sigma2": 0.4, "delta": 1.5}),
        ("elastoplastic", {"F_c": 1.0, "F_s": 1.5, "v_s": 1e-3, "sigma0": 1e5, "sigma1": 316.0,
                           "sigma2": 0.4, "z_ba": 5e-6, "delta": 1.0}),
        ("mykhailevych2020", {"T_stat": 1.5, "k_din": 0.5, "phi0": 1.5e-5, "omega0": 1e-2,
                              "k_v": 316.0, "p": 1.0}),
        # the stop operator: phi held at |phi| >= reset_c·phi0 while v drives it outwards
        ("mykhailevych2020", {"T_stat": 1.5, "k_din": 0.5, "phi0": 1.5e-5, "omega0": 1e-2,
                              "k_v": 316.0, "reset": "stop", "c_ps": 100.0}),
        ("mykhailevych2020", {"T_stat": 240.0, "k_din": 0.95, "phi0": 1e-3, "omega0": 5.0,
                              "k_v": 3.0, "p": 1.0, "reset": "stop", "reset_c": 1.5}),
    ]
    for name, params in extra:
        label = ",".join(f"{k}={v}" if isinstance(v, str) else f"{k}={v:g}"
                         for k, v in params.items() if k not in ("F_c", "F_s"))
        cases.append((f"{name}[{label}]", name, params))
    return cases


CASES = _variants()


def _model(name, params):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return make_model(name, **params)


# --------------------------------------------------------------------- model scales
def _scales(m):
    """Typical scales (force level, velocity, one per state) the model declares."""
    sc = m.typical_scales()
    return sc.force, sc.velocity, list(sc.states)


def _discrete(m):
    """States that are discrete (change only at events): their columns must be exactly
    zero.  A lockable model's one state is its mode."""
    return (0,) if m.lockable else ()


def _clip_zone(F_e, scale, F_s):
    bound = scale * F_s
    return 1 if F_e > bound else (-1 if F_e < -bound else 0)


def _stribeck(m, v, F_c, F_s, v_s):
    return F_c + (F_s - F_c) * math.exp(-abs(v / v_s) ** m.delta)


def _piece(m, z, v, F_e, scale):
    """Which smooth piece of model ``m`` is active at (z, v, F_e, scale)."""
    name, sv = m.name, np.sign(v)
    if name == "coulomb-naive":
        return (sv,) if v != 0.0 else (0, _clip_zone(F_e, scale, m.F_s))
    if name == "karnopp":
        if abs(v) < m.DV:
            return ("window", _clip_zone(F_e, scale, m.F_s))
        return ("sliding", sv)
    if name == "coulomb-robust":
        if z[0] == 0.0:
            return ("stuck", _clip_zone(F_e, scale, m.F_s))
        return ("sliding", z[0], sv)
    if name == "dahl":
        r = m.sigma0 * z[0] * sv / m.F_c
        if m.alpha < 1.0 and abs(1.0 - r) < 1e-3:
            # (1 - r)^alpha with alpha < 1 has unbounded curvature at the saturation r = 1:
            # within 1e-3 of it differences are no reference (a stencil of 1e-4 of the
            # state's scale, 6e-4 from it, was off by 6e-6: found by a random draw).  Every
            # point here is a piece of its own, so the draw is rejected.
            return ("near saturation", float(r))
        return (sv, np.sign(1.0 - r))
    if name == "elastoplastic":
        z_max = _stribeck(m, v, m.F_c, m.F_s, m.v_s) / m.sigma0
        return (sv, np.sign(z[0]), abs(z[0]) <= m.z_ba, abs(z[0]) >= z_max)
    if name == "gms":
        s = _stribeck(m, v, m.F_c, m.F_s, m.v_s)
        zones = []
        for zi, k, a in zip(z, m.k, m.alpha):
            r = k * abs(zi) / (a * s)
            zones.append((r > 1.0 - m.stick_band, r >= 1.0) if zi * v > 0.0 else "sticks")
        return (sv, tuple(zones))
    if name == "mykhailevych2020" and m.reset == "stop":
        return (sv, _stopped(m, z, v))
    return (sv,)   # smooth models, and the kink of |v| at 0


def _stopped(m, z, v):
    """Does model (6)'s stop operator hold phi (|phi| >= reset_c·phi0, v driving it out)?"""
    return bool(abs(z[0]) >= m.reset_c * m.phi0 and v * z[0] > 0.0)


# --------------------------------------------------------------------- kernels
def _kernels(m):
    """The model's own compiled force and Jacobian kernels (as it declares them)."""
    return m.kernels.force, m.kernels.jacobian


def _call_force(kernel, p, z, v, F_e, scale):
    dz = np.zeros(z.size)
    F = kernel(p, np.ascontiguousarray(z, dtype=np.float64), float(v), float(F_e),
               float(scale), dz)
    return np.concatenate(([F], dz))


def _call_jac(kernel, p, z, v, F_e, scale):
    nz = z.size
    dz = np.full(nz, np.nan)
    Jz = np.full((nz, nz + 1), np.nan)
    dF = np.full(nz + 3, np.nan)
    F = kernel(p, np.ascontiguousarray(z, dtype=np.float64), float(v), float(F_e),
               float(scale), dz, Jz, dF)
    return F, dz, Jz, dF


def _as_matrix(Jz, dF):
    """Rows (F, dz_0, ...), columns (z_0, ..., v, F_e, scale); ``dz`` is flat in F_e, scale."""
    nz = Jz.shape[0]
    out = np.zeros((nz + 1, nz + 3))
    out[0] = dF
    out[1:, :nz + 1] = Jz
    return out


def _args(x, nz):
    return x[:nz], x[nz], x[nz + 1], x[nz + 2]


def _fd(f, x, steps, columns, piece=None, one_sided=()):
    """Richardson-extrapolated differences of ``f`` at ``x`` in the ``columns``.

    Central (steps ±h, ±h/2), or forward for the columns in ``one_sided`` (0, h/2, h, 2h).
    With ``piece``, returns None when a stencil point leaves the piece of ``x``."""
    f0 = f(x)
    out = np.zeros((f0.size, x.size))
    for j in columns:
        h = steps[j]
        ref = None
        if piece is not None:   # a forward difference is taken on the piece right of x
            xr = x.copy()
            xr[j] += 0.25 * h if j in one_sided else 0.0
            ref = piece(xr)

        def at(offset, j=j, ref=ref):
            y = x.copy()
            y[j] += offset
            if piece is not None and piece(y) != ref:
                raise _OffPiece
            return f(y)
        try:
            if j in one_sided:
                def d(hh):
                    return (-3.0 * f0 + 4.0 * at(hh) - at(2.0 * hh)) / (2.0 * hh)
            else:
                def d(hh):
                    return (at(hh) - at(-hh)) / (2.0 * hh)
            out[:, j] = (4.0 * d(h / 2.0) - d(h)) / 3.0
        except _OffPiece:
            return None
    return out


class _OffPiece(Exception):
    pass


def _check_close(J, J_fd, typical, what):
    bad = np.abs(J - J_fd) > REL * (np.abs(J_fd) + typical)
    assert not bad.any(), (
        f"{what}: analytic and finite-difference Jacobians differ at {np.argwhere(bad).tolist()}"
        f"\nanalytic\n{J}\nfinite differences\n{J_fd}\ntypical sizes\n{typical}")


def _model_check(m, x, one_sided=(), skip=()):
    """Compare model ``m``'s Jacobian at ``x = (z..., v, F_e, scale)`` with differences of
    its force kernel; ``False`` if the stencil leaves the piece (the caller rejects x)."""
    force, jac = _kernels(m)
    p, nz = m.pack(), m.n_states
    F_scale, V, Z = _scales(m)
    S = np.array([*Z, V, F_scale, 1.0])
    discrete = _discrete(m)
    columns = [j for j in range(nz + 3) if j not in discrete and j not in skip]
    J_fd = _fd(lambda y: _call_force(force, p, *_args(y, nz)), x, STEP * S, columns,
               piece=lambda y: _piece(m, *_args(y, nz)), one_sided=one_sided)
    if J_fd is None:
        return False
    F, dz, Jz, dF = _call_jac(jac, p, *_args(x, nz))
    # F and dz are the force kernel's, bit for bit
    ref = _call_force(force, p, *_args(x, nz))
    assert np.asarray(F, dtype=np.float64).tobytes() == ref[:1].tobytes()
    assert dz.tobytes() == ref[1:].tobytes()
    J = _as_matrix(Jz, dF)
    assert np.all(np.isfinite(J)), J
    for j in discrete:
        assert np.all(J[:, j] == 0.0), f"{m.name}: column of discrete state {j} must be 0"
    typical = np.outer([F_scale] + [V] * nz, 1.0 / S)
    for j in set(discrete) | set(skip):
        J_fd[:, j] = J[:, j]
    _check_close(J, J_fd, typical, f"{m.name} at z={x[:nz]}, v={x[nz]:g}, "
                                   f"F_e={x[nz + 1]:g}, scale={x[nz + 2]:g}")
    return True


# --------------------------------------------------------------------- draws
@st.composite
def _points(draw, m, v_zero=False):
    """(z..., v, F_e, scale) for model ``m``: |v| from 1e-2 to 30 velocity scales
    (log-uniform, either sign) or exactly 0, states around their sliding range (a GMS
    element in its stick-to-slip band half of the time: the band is only 1 % of the
    range), |F_e| up to twice the friction level, scale in [0, 2]."""
    F_scale, V, Z = _scales(m)
    unit = st.floats(-1.0, 1.0)
    if v_zero:
        v = 0.0
    else:
        v = V * 10.0 ** draw(st.floats(-2.0, math.log10(30.0))) * draw(st.sampled_from([-1, 1]))
    if m.lockable:
        z = [float(draw(st.sampled_from([-1.0, 0.0, 1.0])))]
    elif m.name == "mykhailevych2020":
        z = [3.0 * Z[0] * draw(unit)]
    elif m.name == "gms":
        s = _stribeck(m, v, m.F_c, m.F_s, m.v_s)
        z = []
        for k, a in zip(m.k, m.alpha):
            if draw(st.booleans()):
                r = 1.0 - m.stick_band * draw(st.floats(0.0, 1.0))
                z.append(r * a * s / k * (1.0 if v >= 0.0 else -1.0))
            else:
                z.append(1.5 * a * m.F_s / k * draw(unit))
    else:
        z = [1.5 * zj * draw(unit) for zj in Z]
    F_e = 2.0 * F_scale * draw(unit)
    scale = draw(st.floats(0.0, 2.0))
    return np.array([*z, v, F_e, scale], dtype=np.float64)


_SETTINGS = settings(max_examples=25, deadline=None,
                     suppress_health_check=[HealthCheck.filter_too_much])


@pytest.mark.parametrize(("label", "name", "params"), CASES, ids=[c[0] for c in CASES])
def test_model_jacobian_matches_finite_differences(label, name, params):
    """Every partial of every model (and parameter set) equals finite differences of its
    force kernel at random points; F and dz are bit for bit those of the force kernel."""
    m = _model(name, params)

    @_SETTINGS
    @given(x=_points(m))
    def check(x):
        assume(_model_check(m, x))

    check()


def _at_zero(m, z):
    """How the v column at v = 0 is checked: ``right`` (the force and the state
    derivatives are continuous in v there, a kink at most: the derivative v -> 0+),
    ``central`` (karnopp: v = 0 is inside its window), ``flat`` (the clipped stick force of
    coulomb-naive and of coulomb-robust stuck: flat in v), ``stick`` (GMS: every element
    sticks, dz_i = v), ``stop`` (model (6)'s stop operator on its bound: dphi/dt = v
    inwards, 0 outwards, a kink of dphi/dt in v; the force is smooth in v) or ``stand-in`` (the slope is unbounded; see the test below)."""
    if m.name == "karnopp":
        return "central"
    if m.name == "coulomb-naive" or (m.name == "coulomb-robust" and z[0] == 0.0):
        return "flat"
    if m.name == "coulomb-robust" and m.v_s > 0.0 and m.delta < 1.0:
        return "stand-in"
    if m.name == "gms":
        return "stick"
    if m.name == "mykhailevych2020" and m.reset == "stop" and abs(z[0]) >= m.reset_c * m.phi0:
        return "stop"
    return "right"


@pytest.mark.parametrize(("label", "name", "params"), CASES, ids=[c[0] for c in CASES])
def test_model_jacobian_at_zero_velocity(label, name, params):
    """At exactly v = 0: the v column is the one-sided derivative v -> 0+ where the force is
    continuous there; the switching pieces (stuck, clipped stick force) and GMS's sticking
    elements give the derivative of the piece the force kernel evaluates."""
    m = _model(name, params)
    nz = m.n_states
    _, jac = _kernels(m)

    @_SETTINGS
    @given(x=_points(m, v_zero=True))
    def check(x):
        z, v, F_e, scale = _args(x, nz)
        mode = _at_zero(m, z)
        if mode == "right":
            assume(_model_check(m, x, one_sided=(nz,)))
            return
        if mode == "central":
            assume(_model_check(m, x))
            return
        if mode == "stop":      # the force's v column one-sided, dphi/dt's by hand
            assume(_model_check(m, x, one_sided=(nz,), skip=(nz,)))
            _, _, Jz, dF = _call_jac(jac, m.pack(), z, v, F_e, scale)
            assert Jz[0, nz] == 1.0     # v·phi = 0 does not drive phi outwards: not held
            force, _ = _kernels(m)
            h = STEP * m.omega0
            right = [_call_force(force, m.pack(), z, s * h, F_e, scale)[0] for s in (1, 2)]
            left = [_call_force(force, m.pack(), z, -s * h, F_e, scale)[0] for s in (1, 2)]
            F0 = _call_force(force, m.pack(), z, 0.0, F_e, scale)[0]
            for side, (f1, f2) in ((1.0, right), (-1.0, left)):
                fd = side * (-3.0 * F0 + 4.0 * f1 - f2) / (2.0 * h)
                assert abs(dF[nz] - fd) <= REL * (abs(fd) + m.T_stat / m.omega0)
            return
        assume(_model_check(m, x, skip=(nz,)))
        _, _, Jz, dF = _call_jac(jac, m.pack(), z, v, F_e, scale)
        if mode == "stick":
            assert np.all(Jz[:, nz] == 1.0)
            assert np.all(np.diag(Jz[:, :nz]) == 0.0)
            assert dF[nz] == pytest.approx(scale * (nz * m.sigma1 + m.sigma2), rel=1e-14)
        elif mode == "flat":
            assert dF[nz] == 0.0
            assert np.all(Jz[:, nz] == 0.0)
        else:
            assert dF[nz] == scale * m.sigma2

    check()


def test_unbounded_slopes_get_a_finite_stand_in():
    """Where the exact slope is infinite (Stribeck exponent < 1 at v = 0; Dahl with
    alpha < 1 at r = 0, i.e. steady sliding) the kernels write 0, never inf or NaN."""
    cr = make_model("coulomb-robust", F_c=1.0, F_s=1.5, v_s=1e-3, delta=0.7)
    _, jac = _kernels(cr)
    _, _, _, dF = _call_jac(jac, cr.pack(), np.array([1.0]), 0.0, 0.3, 1.0)
    assert dF[1] == 0.0
    dahl = make_model("dahl", F_c=1.0, sigma0=1e5, alpha=0.6)
    _, jac = _kernels(dahl)
    z = dahl.sliding_state(1e-3)
    _, dz, Jz, _ = _call_jac(jac, dahl.pack(), z, 1e-3, 0.0, 1.0)
    assert dz[0] == 0.0
    assert Jz[0, 0] == 0.0
    assert Jz[0, 1] == 0.0   # |r|^alpha·sign(r) at r = 0
    # next to it the slope is large and finite, and it is what the kernel gives
    _, _, Jz, _ = _call_jac(jac, dahl.pack(), z * (1.0 - 1e-9), 1e-3, 0.0, 1.0)
    assert np.isfinite(Jz[0, 0]) and Jz[0, 0] < -1e3


@pytest.mark.parametrize("name", sorted(fr.MODELS))
def test_dispatcher_agrees_with_each_model_kernel(name):
    """friction_jacobian(code, ...) is the model's own kernel, bit for bit."""
    m = make_model(name)
    _, jac = _kernels(m)
    nz = m.n_states
    rng = np.random.default_rng(7)
    for x in [np.array([*z, v, F_e, s]) for z, v, F_e, s in (
            (rng.uniform(-1e-5, 1e-5, nz), 3e-4, 0.4, 1.0),
            (rng.uniform(-1e-5, 1e-5, nz), -2e-3, -1.7, 0.5),
            (np.zeros(nz), 0.0, 0.9, 1.3))]:
        if m.lockable:
            x[0] = 1.0
        own = _call_jac(jac, m.pack(), *_args(x, nz))
        dz = np.full(nz, np.nan)
        Jz = np.full((nz, nz + 1), np.nan)
        dF = np.full(nz + 3, np.nan)
        F = fr.friction_jacobian(m.code, m.pack(), np.ascontiguousarray(x[:nz]), float(x[nz]),
                                 float(x[nz + 1]), float(x[nz + 2]), dz, Jz, dF)
        assert np.float64(F).tobytes() == np.float64(own[0]).tobytes()
        for a, b in zip((dz, Jz, dF), own[1:]):
            assert a.tobytes() == b.tobytes()
        # and F, dz are friction_force's
        dz2 = np.zeros(nz)
        F2 = fr.friction_force(m.code, m.pack(), np.ascontiguousarray(x[:nz]), float(x[nz]),
                               float(x[nz + 1]), float(x[nz + 2]), dz2)
        assert np.float64(F2).tobytes() == np.float64(F).tobytes()
        assert dz2.tobytes() == dz.tobytes()
        assert Jz.shape == (nz, nz + 1) and dF.shape == (nz + 3,)


# --------------------------------------------------------------------- the rig
@pytest.mark.parametrize("domain", ["translational", "rotational"])
@pytest.mark.parametrize("drive", ["force", "velocity"])
@pytest.mark.parametrize(("label", "name", "params"), CASES, ids=[c[0] for c in CASES])
def test_rig_jacobian_matches_finite_differences(label, name, params, drive, domain):
    """The rig's exact Jacobian (call_jac) equals central differences of its right-hand side
    (call_rhs) at random states, for both drives (the force drive with a spring, so that the
    stick force of the switching models depends on the position) and both domains."""
    # the same numbers in either domain: a copy made from the numbers carries no parameter
    # set, so the rig's domain check (a translational set on a rotational rig) does not apply
    m = dataclasses.replace(_model(name, params))
    F_scale, V, Z = _scales(m)
    nz = m.n_states
    mass, k = 2.0, 1e4
    kw = {"spring": k, "pull_speed": V, "spring_offset": F_scale / k} if drive == "force" else {}
    system = make_rig(m, domain=domain, drive=drive, mass=mass, **kw)
    tag, p = system.tag, system.params
    assert has_jacobian(tag)
    n = system.n_states
    # state scales: x (the spring stretch per friction level), v, z...
    S = np.array([F_scale / k, V, *Z]) if drive == "force" else np.array([F_scale / k, *Z])
    rates = [V, F_scale / mass] + [V] * nz if drive == "force" else [V] * (1 + nz)
    typical = np.outer(rates, 1.0 / S)
    discrete = [j + n - nz for j in _discrete(m)]

    def contact(y, u, t):
        """The friction model's arguments (z, v, F_e, scale) in the rig at y."""
        if drive == "force":
            return y[2:], y[1], u[0] + k * (F_scale / k + V * t - y[0]), u[1]
        return y[1:], u[0], 0.0, u[1]

    @_SETTINGS
    @given(x=_points(m), t=st.floats(0.0, 1.0), x0=st.floats(-1.0, 1.0))
    def check(x, t, x0):
        z, v, F_e, scale = _args(x, nz)
        u = np.array([F_e if drive == "force" else v, scale])
        y = np.array([x0 * S[0], v, *z] if drive == "force" else [x0 * S[0], *z])

        def rhs(yy):
            dy = np.zeros(n)
            call_rhs(tag, t, yy, u, p, dy)
            return dy

        columns = [j for j in range(n) if j not in discrete]
        J_fd = _fd(rhs, y, STEP * S, columns, piece=lambda yy: _piece(m, *contact(yy, u, t)))
        assume(J_fd is not None)
        J = np.full((n, n), np.nan)
        call_jac(tag, t, y, u, p, J)
        assert np.all(np.isfinite(J))
        for j in discrete:
            assert np.all(J[:, j] == 0.0)
            J_fd[:, j] = 0.0
        _check_close(J, J_fd, typical, f"{system.name} ({drive}) at y={y}, u={u}, t={t:g}")

    check()
