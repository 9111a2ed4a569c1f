"""Friction parameter sets carry a domain: a translational set on a clutch is refused."""

from __future__ import annotations

import subprocess
import sys

import pytest
from _dl_paths import EXAMPLES

from clutchsim.friction import list_parameter_sets, make_model
from clutchsim.scenario import ScenarioError, load_scenario

LAUNCH = (EXAMPLES / "launch.toml").read_text(encoding="utf-8")
OWN = ('friction = { model = "mykhailevych2020", parameter_set = "mykhailevych2020_clutch", '
       'alternatives = { coulomb-robust = { F_c = 192.0, F_s = 240.0 }, coulomb-naive = '
       '{ F_c = 192.0, F_s = 240.0 } } }')


def _scenario(tmp_path, friction: str):
    assert OWN in LAUNCH
    text = LAUNCH.replace(OWN, friction)
    p = tmp_path / "s.toml"
    p.write_text(text, encoding="utf-8")
    line = next(i for i, s in enumerate(text.splitlines(), 1) if s.startswith("friction = "))
    return p, line


def _refusal(tmp_path, friction: str, model=None):
    p, line = _scenario(tmp_path, friction)
    with pytest.raises(ScenarioError) as info:
        load_scenario(p).network(model)
    return str(info.value), f"{p}:{line}"


def test_lugre_default_set_on_a_clutch_is_refused(tmp_path):
    # the trap: lugre's own set is LuGre Table I (F_c = 1 N for a 1 kg mass); on a clutch it
    # was read as F_c = 1 N·m, a viscous coupling that let the engine race to 5,600 rpm
    msg, where = _refusal(tmp_path, 'friction = { model = "lugre" }')
    assert where in msg                                    # file:line
    assert "'clutch'" in msg and "'lugre'" in msg and "'lugre_canudas1995'" in msg
    assert "translational (N, m, m/s)" in msg and "rotational units (N·m, rad, rad/s)" in msg
    # the rotational sets that exist (lugre has none: the models that have one)
    for name in list_parameter_sets(domain="rotational"):
        assert name in msg
    assert "F_c, F_s, v_s, sigma0, sigma1, sigma2" in msg  # what to give instead


def test_translational_set_is_accepted_once_every_unit_parameter_is_given(tmp_path):
    # LuGre with rotational numbers: the set only contributes delta [-]
    p, _ = _scenario(tmp_path, 'friction = { model = "lugre", overrides = { F_c = 192.0, '
                     'F_s = 240.0, v_s = 1.0, sigma0 = 2.4e5, sigma1 = 50.0, sigma2 = 0.0 } }')
    model = load_scenario(p).network().component("clutch").model
    assert model.F_s == 240.0 and model.delta == 2.0


def test_rotational_set_accepted_and_translational_model6_set_refused(tmp_path):
    p, _ = _scenario(tmp_path, 'friction = { model = "mykhailevych2020", parameter_set = '
                     '"mykhailevych2020_clutch" }')
    assert load_scenario(p).network().component("clutch").model.T_stat == 240.0
    msg, _ = _refusal(tmp_path, 'friction = { model = "mykhailevych2020" }')
    assert "'mykhailevych2020_translational'" in msg and "mykhailevych2020_clutch" in msg


def test_alternatives_fall_back_to_the_default_set_or_name_the_missing_keys(tmp_path):
    # only T_stat given: the rest would come from the (translational) default set -> named
    msg, where = _refusal(tmp_path, 'friction = { model = "coulomb-robust", overrides = { '
                          'F_c = 192.0, F_s = 240.0 }, alternatives = { mykhailevych2020 = { '
                          'T_stat = 300.0 } } }', "mykhailevych2020")
    assert where in msg and "alternatives.mykhailevych2020" in msg
    assert "phi0, omega0, k_v" in msg and "T_stat" not in msg.split("takes")[1].split("from")[0]
    # with a set, the keys not given come from it, as `overrides` does
    p, _ = _scenario(tmp_path, 'friction = { model = "coulomb-robust", overrides = { '
                     'F_c = 192.0, F_s = 240.0 }, alternatives = { mykhailevych2020 = { '
                     'parameter_set = "mykhailevych2020_clutch", T_stat = 300.0 } } }')
    model = load_scenario(p).network("mykhailevych2020").component("clutch").model
    assert model == make_model("mykhailevych2020", "mykhailevych2020_clutch", T_stat=300.0)
    # every unit parameter given without a set: the default set supplies the [-] ones
    p, _ = _scenario(tmp_path, 'friction = { model = "coulomb-robust", overrides = { '
                     'F_c = 192.0, F_s = 240.0 }, alternatives = { mykhailevych2020 = { '
                     'T_stat = 300.0, phi0 = 1e-3, omega0 = 5.0, k_v = 0.05 } } }')
    model = load_scenario(p).network("mykhailevych2020").component("clutch").model
    ref = make_model("mykhailevych2020")
    assert (model.T_stat, model.k_din, model.p, model.reset) == (300.0, ref.k_din, ref.p,
                                                                 ref.reset)


def test_cli_refuses_with_exit_2_and_no_traceback(tmp_path):
    p, line = _scenario(tmp_path, 'friction = { model = "lugre" }')
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "clutchsim", "run", str(p), "--model", "lugre",
                        "--out", str(out), "--no-plots"], capture_output=True, text=True,
                       timeout=600, check=False)
    assert r.returncode == 2, r.stderr
    assert "Traceback" not in r.stderr and f"{p}:{line}" in r.stderr
    assert not out.exists()
