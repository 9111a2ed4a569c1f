"""Drift test D1 (friction-models.md T6): u = 0.5 + 0.4·sin(2πt) N on 1 kg, from rest.

Reference values are the sheet's independent re-implementation [C]:
LuGre drifts 6.637 µm per cycle; elasto-plastic with z_ba = 0.95·F_c/sigma0
sits at x = 4.920 µm at every integer t (no drift).
"""

from __future__ import annotations

import math

import pytest

from clutchsim.friction import make_model


def _d1(t):
    return 0.5 + 0.4 * math.sin(2 * math.pi * t)


def test_lugre_drifts_6_6_um_per_cycle(simulate_mass):
    states, _ = simulate_mass(make_model("lugre"), _d1, [1.0, 2.0], rtol=1e-8, atol=1e-12,
                              max_step=2e-3)  # fmt: skip
    x1, x2 = states[:, 0]
    assert x2 - x1 == pytest.approx(6.637e-6, rel=0.01)


def test_elastoplastic_does_not_drift(simulate_mass):
    states, _ = simulate_mass(make_model("elastoplastic"), _d1, [1.0, 2.0], rtol=1e-8,
                              atol=1e-12, max_step=2e-3)  # fmt: skip
    x1, x2 = states[:, 0]
    assert abs(x2 - x1) < 1e-9
    assert x1 == pytest.approx(4.920e-6, abs=1e-9)
