"""The friction-surface temperature (issue 35 §3): a thin surface node between the
clutch's friction power and the pressure plate's bulk, sized against the semi-infinite
solid, and the metric ``peak_surface_temp_C`` that reads it."""

from __future__ import annotations

import math
import tomllib

import pytest
from _dl_paths import EXAMPLES

from clutchsim import run_scenario
from clutchsim.scenario import load_scenario
from clutchsim.scenario.run import surface_node

SURFACE = EXAMPLES / "launch_surface.toml"
#: cast iron (the example's header): k [W/(m·K)], rho [kg/m³], c [J/(kg·K)]; slip time [s]
K, RHO, C, T_SLIP = 50.0, 7200.0, 460.0, 0.6


def test_the_layer_rises_as_the_semi_infinite_solid_at_the_end_of_a_slip():
    """Carslaw and Jaeger §2.9: ΔT = 2q·sqrt(t/(π·k·ρ·c)) under a constant flux q; the
    lumped layer (C, G to a bulk that stays put) gives (q·A/G)·(1 − exp(−t·G/C))."""
    data = tomllib.loads(SURFACE.read_text(encoding="utf-8"))
    layer = next(t for t in data["thermal"] if t["name"] == "plate_surface")
    clutch = data["coupling"][0]
    area = math.pi * (clutch["r_outer"] ** 2 - clutch["r_inner"] ** 2)
    cap, g = layer["capacity"], layer["link_conductance"]
    q = 1e5                                   # W/m², any flux: both are linear in it
    lumped = q * area / g * (1.0 - math.exp(-T_SLIP * g / cap))
    exact = 2.0 * q * math.sqrt(T_SLIP / (math.pi * K * RHO * C))
    assert lumped == pytest.approx(exact, rel=0.03)
    # the plate keeps its total capacity: bulk + layer = 3.5 kg × 460 J/(kg·K)
    plate = next(t for t in data["thermal"] if t["name"] == "pressure_plate")
    assert plate["capacity"] + cap == pytest.approx(1600.0)


def test_the_surface_runs_hotter_than_the_bulk_and_the_metric_says_so():
    m = run_scenario(SURFACE, "coulomb-robust").metrics
    assert surface_node(load_scenario(SURFACE)) == "plate_surface"
    surface, bulk = m["peak_surface_temp_C"], m["peak_heat_node_temp_C"]
    assert bulk is not None and surface is not None
    # half of the ~2.5 kJ slip energy into the plate face: the bulk rises under 1 K, the
    # face (0.6 s of ~140 kW/m²) some 5-15 K
    assert 40.0 < bulk < 41.0 and bulk + 4.0 < surface < 60.0, (bulk, surface)


def test_without_a_surface_layer_the_metric_is_null():
    assert run_scenario(None, "coulomb-robust").metrics["peak_surface_temp_C"] is None
