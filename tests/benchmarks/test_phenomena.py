"""The measured phenomena matrix: rules, generated docs, and a re-measurement.

(a) every classification rule on synthetic metrics, with a case that passes and one that
    fails;
(b) the docs generated from the committed ``docs/phenomena.json`` equal the committed
    ``docs/phenomena.md`` and the model-page sections, and the stored verdicts follow from
    the stored metrics with the current rules;
(c) a few cheap models re-measured against the JSON, and the literature's drift facts.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from clutchsim.benchmarks import phenomena as ph
from clutchsim.benchmarks.phenomena import Measurement, ModelMetrics, Thresholds

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"


# --------------------------------------------------------------------------- (a) rules

def _lugre_like(**changes) -> ModelMetrics:
    """Synthetic metrics shaped like LuGre's; ``changes``: ``bench__metric=value`` or
    ``bench=Measurement``."""
    values = {
        "curves": {"f_static_N": 1.5, "f_kinetic_N": 1.0, "fall_N": 0.5, "fall_from_N": 1.5,
                   "fall_from_speed_m_s": 1e-7, "fall_to_N": 1.0,
                   "fall_to_speed_m_s": 3e-3},
        "drift": {"d1_drift_per_cycle_m": 6.6e-6, "d1_x_end_m": 1.4e-4,
                  "d1_backward_travel_last_cycle_m": 6e-6, "d2_drift_per_cycle_m": 6.6e-6},
        "breakaway": {"rates_N_s": (1.0, 10.0, 50.0), "breakaway_N": (1.43, 1.22, 1.01)},
        "presliding": {"x_first_ramp_m": 4.5e-5, "loop_width_m": 5.4e-5, "closure_m": 0.0,
                       "loop_closes": True},
        "lag": {"omegas_rad_s": (1.0, 10.0, 25.0), "loop_width_N": (0.001, 0.013, 0.036)},
    }
    benches = {}
    for bench, vals in values.items():
        if isinstance(changes.get(bench), Measurement):
            benches[bench] = changes[bench]
            continue
        vals = dict(vals)
        for key, value in changes.items():
            b, _, metric = key.partition("__")
            if b == bench:
                assert metric in vals, key
                vals[metric] = value
        benches[bench] = Measurement("ok", vals)
    return ModelMetrics("synthetic", "synthetic (test)", benches)


def _verdict(key, metrics, th=ph.THRESHOLDS):
    return ph.classify(metrics, th)[key].verdict


def test_lugre_like_metrics_show_every_phenomenon_but_drift():
    verdicts = ph.classify(_lugre_like())
    assert {k: v.verdict for k, v in verdicts.items()} == {
        "stiction": "yes", "stribeck": "yes", "presliding": "yes", "lag": "yes",
        "varying_breakaway": "yes", "no_drift": "no"}
    for v in verdicts.values():
        assert v.rule and v.reason and v.evidence and v.key
        assert all(e.unit or isinstance(e.value, bool) for e in v.evidence)


@pytest.mark.parametrize("changes", [
    {"breakaway__breakaway_N": (1.01, 1.0, 0.99)},     # peak not above the sliding level
    {"breakaway__breakaway_N": (None, None, None)},    # no peak at all
    {"curves__f_static_N": 1e-4},                      # creeps: cannot hold at rest
])
def test_stiction_no(changes):
    assert _verdict("stiction", _lugre_like(**changes)) == "no"


def test_stiction_threshold_is_used():
    m = _lugre_like(breakaway__breakaway_N=(1.03, 1.02, 1.01))
    assert _verdict("stiction", m) == "yes"
    assert _verdict("stiction", m, Thresholds(stiction_margin=0.05)) == "no"


def test_stribeck_yes_and_no():
    assert _verdict("stribeck", _lugre_like()) == "yes"
    assert _verdict("stribeck", _lugre_like(curves__fall_N=0.0)) == "no"
    # a fall smaller than stribeck_drop·F_k does not count
    assert _verdict("stribeck", _lugre_like(curves__fall_N=0.005)) == "no"


def test_presliding_yes_and_no():
    assert _verdict("presliding", _lugre_like()) == "yes"
    assert _verdict("presliding",
                    _lugre_like(drift__d1_backward_travel_last_cycle_m=0.0)) == "no"
    # T2 numbers are evidence only, D1 decides
    m = _lugre_like(presliding=Measurement("not applicable", message="n/a here"))
    assert _verdict("presliding", m) == "yes"


@pytest.mark.parametrize("widths", [
    (0.036, 0.013, 0.001),          # shrinks with frequency
    (-2e-8, 2e-7, 9e-7),            # grows, but at noise level
])
def test_lag_no(widths):
    assert _verdict("lag", _lugre_like(lag__loop_width_N=widths)) == "no"


@pytest.mark.parametrize("forces", [
    (1.5, 1.5, 1.5),                # constant (Coulomb)
    (1.5, 0.4, 1.3),                # changes, not monotone
    (1.5, None, 1.3),               # no peak at one rate
])
def test_varying_breakaway_no(forces):
    assert _verdict("varying_breakaway", _lugre_like(breakaway__breakaway_N=forces)) == "no"


def test_varying_breakaway_rising_counts():
    m = _lugre_like(breakaway__breakaway_N=(1.1, 1.2, 1.4))
    assert _verdict("varying_breakaway", m) == "yes"


def test_no_drift_yes_and_no():
    assert _verdict("no_drift", _lugre_like()) == "no"
    assert _verdict("no_drift", _lugre_like(drift__d1_drift_per_cycle_m=-8e-15)) == "yes"
    m = _lugre_like(drift__d1_drift_per_cycle_m=5e-9)
    assert _verdict("no_drift", m) == "no"
    assert _verdict("no_drift", m, Thresholds(drift_m_per_cycle=1e-8)) == "yes"


def test_failed_or_inapplicable_benchmark_gives_na_with_reason():
    failed = Measurement("failed", message="step budget exhausted: 400000 steps. Raise it.")
    v = ph.classify(_lugre_like(breakaway=failed))
    assert v["stiction"].verdict == v["varying_breakaway"].verdict == "n/a"
    assert v["stiction"].reason == ("benchmark did not complete: breakaway: step budget "
                                    "exhausted: 400000 steps.")
    assert v["stribeck"].verdict == "yes"   # other phenomena unaffected
    na = Measurement("not applicable", message="the lag benchmark does not apply to x")
    assert ph.classify(_lugre_like(lag=na))["lag"].reason == na.message


def test_compare_with_literature():
    assert ph.compare("yes", "yes") == "agrees"
    assert ph.compare("no", "yes") == "disagrees"
    assert ph.compare("no", "depends") == "depends"
    assert ph.compare("n/a", "no") == "not measured"


def test_metrics_and_verdicts_round_trip_through_json():
    m = _lugre_like(breakaway__breakaway_N=(1.43, None, 1.01))
    again = ModelMetrics.from_dict(json.loads(json.dumps(m.to_dict())))
    assert again == m
    v = ph.classify(m)["varying_breakaway"]
    assert ph.Verdict.from_dict(json.loads(json.dumps(v.to_dict()))) == v


def test_splice_section_replaces_only_the_section():
    page = "# x\n\n## Phenomena\n\nold text\n\n| a |\n\n## Reference\n\nref\n"
    once = ph.splice_section(page, f"{ph.BEGIN_MARKER}\nnew\n{ph.END_MARKER}\n")
    assert once == (f"# x\n\n## Phenomena\n\n{ph.BEGIN_MARKER}\nnew\n{ph.END_MARKER}\n\n"
                    "## Reference\n\nref\n")
    twice = ph.splice_section(once, f"{ph.BEGIN_MARKER}\nnewer\n{ph.END_MARKER}\n")
    assert twice == once.replace("\nnew\n", "\nnewer\n")
    with pytest.raises(ValueError, match="Phenomena"):
        ph.splice_section("# no section\n", "x")


# --------------------------------------------------------------------------- (b) docs

@pytest.fixture(scope="module")
def committed():
    return json.loads((DOCS / "phenomena.json").read_text(encoding="utf-8"))


def test_committed_json_uses_current_rules_and_thresholds(committed):
    th = Thresholds(**committed["thresholds"])
    assert th == ph.THRESHOLDS, "thresholds changed: rerun scripts/phenomena_matrix.py"
    for model in committed["models"]:
        verdicts = ph.classify(ph.metrics_from_report(committed, model), th)
        assert ph.verdicts_from_report(committed, model) == verdicts, model
        assert committed["rules"] == {k: v.rule for k, v in verdicts.items()}


def test_committed_json_covers_every_model_and_literature(committed):
    from clutchsim.friction import MODELS
    assert list(committed["models"]) == list(MODELS)
    for model, entry in committed["models"].items():
        assert entry["literature"] == {k: {"expected": e, "text": t}
                                       for k, (e, t) in MODELS[model].phenomena.items()}
    assert committed["clutchsim_version"] and committed["date"]


def test_phenomena_md_is_rendered_from_the_json(committed):
    text = (DOCS / "phenomena.md").read_text(encoding="utf-8")
    assert text == ph.render_matrix(committed), (
        "docs/phenomena.md differs from docs/phenomena.json: run "
        "scripts/phenomena_matrix.py --render-only")


def test_model_pages_are_rendered_from_the_json(committed):
    pages = {p.stem: p.read_text(encoding="utf-8") for p in (DOCS / "models").glob("*.md")}
    rendered = ph.render_pages(committed, pages)
    assert set(rendered) == set(committed["models"])
    for name, text in rendered.items():
        assert pages[name].count(ph.BEGIN_MARKER) == 1, name
        assert text == pages[name], (f"docs/models/{name}.md differs from the JSON: run "
                                     "scripts/phenomena_matrix.py --render-only")


# --------------------------------------------------------------------------- (c) re-measure

#: models whose benchmark runs take about a second each once compiled
CHEAP = ("lugre", "dahl", "elastoplastic", "mykhailevych2020")


@pytest.fixture(scope="module")
def measured():
    return {name: ph.measure_model(name) for name in CHEAP}


def _close(new, old, key=""):
    if isinstance(old, dict):
        assert set(new) == set(old), key
        for k in old:
            _close(new[k], old[k], f"{key}.{k}")
    elif isinstance(old, list):
        assert len(new) == len(old), key
        for i, (a, b) in enumerate(zip(new, old, strict=True)):
            _close(a, b, f"{key}[{i}]")
    elif isinstance(old, float) and not isinstance(old, bool):
        # lengths to 0.1 nm, forces to 1 µN, or 1e-3 relative
        floor = 1e-10 if key.endswith("_m") else 1e-6
        assert new == pytest.approx(old, rel=1e-3, abs=floor), key
    else:
        assert new == old, key


@pytest.mark.parametrize("name", CHEAP)
def test_remeasured_metrics_match_the_json(measured, committed, name):
    m = measured[name]
    stored = ph.metrics_from_report(committed, name)
    _close(m.to_dict(), stored.to_dict(), name)
    assert {k: v.verdict for k, v in ph.classify(m).items()} == {
        k: v["verdict"] for k, v in committed["models"][name]["verdicts"].items()}


def test_literature_drift_facts(measured):
    drift = {k: m["drift"].values["d1_drift_per_cycle_m"] for k, m in measured.items()}
    assert drift["lugre"] == pytest.approx(6.637e-6, rel=0.02)     # friction-models.md T6
    assert drift["dahl"] == pytest.approx(16.661e-6, rel=0.05)
    assert abs(drift["elastoplastic"]) < 1e-9                      # true elastic zone
    from clutchsim.friction import make_model
    assert make_model("mykhailevych2020").reset == "clamp"
    assert abs(drift["mykhailevych2020"]) < 1e-9                   # reset = clamp (default)
    verdicts = {k: ph.classify(m)["no_drift"].verdict for k, m in measured.items()}
    assert verdicts == {"lugre": "no", "dahl": "no", "elastoplastic": "yes",
                        "mykhailevych2020": "yes"}


def test_thresholds_are_a_frozen_dataclass():
    with pytest.raises(dataclasses.FrozenInstanceError):
        ph.THRESHOLDS.drift_m_per_cycle = 1.0
