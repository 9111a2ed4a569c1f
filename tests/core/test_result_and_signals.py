"""Results are immutable and carry units; signals evaluate, declare breakpoints, and reject
bad tables with the file and row."""

import dataclasses

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clutchsim.core import Constant, Pulse, Ramp, Sine, SolverOptions, Step, Table, simulate
from clutchsim.core.reference_problems import oscillator


@pytest.fixture(scope="module")
def res():
    return simulate(oscillator(), (0.0, 2.0), {"F": Sine(1.0, 1.0)},
                    options=SolverOptions(dt_out=0.1))


def test_result_is_immutable(res):
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.status = "completed"
    with pytest.raises(ValueError):
        res["x"][0] = 1.0
    with pytest.raises(TypeError):
        res.data["x"] = np.zeros(3)


def test_signals_by_name_and_with_units(res):
    assert np.array_equal(res["x"], res["x [m]"])
    assert res.unit("v") == "m/s"
    with pytest.raises(KeyError, match="did you mean 'x'"):
        res["xx"]
    assert res.success and res.stats.steps > 0 and res.stats.rhs_evals > res.stats.steps


def test_notebook_view_shows_status_signals_and_escapes_text(res):
    page = res._repr_html_()
    assert page.count("<tr>") == 6 and "completed" in page and "x [m]" in page
    assert f"{res.stats.steps} / {res.stats.events}" in page
    odd = dataclasses.replace(res, warnings=("a < b & c",))
    page = odd._repr_html_()
    assert page.count("<tr>") == 7 and "a &lt; b &amp; c" in page and "a < b" not in page


def test_frame_csv_and_parquet_round_trip_keep_units(res, tmp_path):
    frame = res.to_frame()
    assert list(frame.columns) == ["time [s]", "x [m]", "v [m/s]", "F [N]"]
    back = pd.read_csv(res.to_csv(tmp_path / "r.csv"))
    assert np.array_equal(back["x [m]"].to_numpy(), res["x"])
    table = pq.read_table(res.to_parquet(tmp_path / "r.parquet"))
    assert table.column_names == list(frame.columns)
    assert b"clutchsim" in table.schema.metadata
    assert not list(tmp_path.glob("*.tmp"))


def test_signal_values_and_breakpoints():
    assert Constant(2.5)(3.0)[0] == 2.5
    s = Step(1.0, height=2.0, offset=-1.0)
    assert list(s([0.5, 1.0, 2.0])) == [-1.0, 1.0, 1.0]
    r = Ramp(1.0, 2.0, height=4.0)
    assert list(r([0.0, 2.0, 5.0])) == [0.0, 2.0, 4.0]
    assert list(r.breakpoints()) == [1.0, 3.0]
    assert Sine(2.0, 0.25, start=1.0)([0.5, 2.0]) == pytest.approx([0.0, 2.0])
    p = Pulse(1.0, 50.0, 2.0, start=0.5, horizon=5.0)
    assert list(p([0.4, 0.6, 1.6, 2.6])) == [0.0, 1.0, 0.0, 1.0]
    total = Constant(0.5) + Sine(0.4, 1.0)
    assert total([0.25])[0] == pytest.approx(0.9)


def test_table_jump_and_hold():
    t = Table([0.0, 1.0, 1.0, 2.0], [0.0, 1.0, 3.0, 3.0])
    assert list(t([-1.0, 0.5, 1.0, 5.0])) == [0.0, 0.5, 3.0, 3.0]
    assert 1.0 in t.breakpoints()


@pytest.mark.parametrize("text, fragment", [
    ("t,v\n0,1\n,\n2,3\n", ":3: empty row"),
    ("t,v\n0,1\n2\n", ":3: expected 2 columns"),
    ("t,v\n0,1\n2,abc\n", ":3: not a number"),
    ("t,v\n0,1\n2,nan\n", "row 2"),
    ("t,v\n0,1\n2,2\n1,3\n", "non-decreasing"),
])
def test_bad_csv_tables_name_file_and_row(tmp_path, text, fragment):
    path = tmp_path / "input.csv"
    path.write_text(text)
    with pytest.raises(ValueError) as info:
        Table.from_csv(path)
    assert str(path) in str(info.value) and fragment in str(info.value)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1e3, 1e3), min_size=2, max_size=20),
       st.floats(-10.0, 30.0))
def test_table_interpolation_stays_within_its_values(values, t):
    times = np.linspace(0.0, 20.0, len(values))
    v = Table(times, values)(t)[0]
    assert min(values) - 1e-9 <= v <= max(values) + 1e-9


@settings(max_examples=100, deadline=None)
@given(counts=st.lists(st.integers(0, 3), min_size=1, max_size=4),
       t=st.floats(-1.0, 5.0))
def test_bank_assigns_each_channel_the_sum_of_its_terms(counts, t):
    # the compiled evaluation assigns a channel at its first term and adds the others (no
    # clearing of u): channels of none, one and several terms, beside each other
    from clutchsim.core.signals import Sum, build_bank, eval_inputs
    pool = [Constant(0.5), Ramp(0.2, 1.0, 2.0), Step(1.0, -3.0), Sine(0.7, 2.0),
            Table([0.0, 1.0, 3.0], [1.0, -1.0, 4.0])]
    channels = [Sum(tuple(pool[(i + k) % len(pool)] for k in range(c)))
                for i, c in enumerate(counts)]
    u = np.full(len(channels), np.nan)
    eval_inputs(build_bank(channels), t, t, u)
    for ch, value in zip(channels, u):
        want = sum((float(s(t)[0]) for s in ch.parts), 0.0)
        assert value == pytest.approx(want, rel=1e-12, abs=1e-12)


_SIGNALS = st.one_of(
    st.builds(Constant, st.floats(-5, 5)),
    st.builds(Step, st.floats(-1, 3), st.floats(-5, 5)),
    st.builds(Ramp, st.floats(-1, 3), st.floats(1e-3, 2), st.floats(-5, 5)),
    st.builds(Sine, st.floats(-5, 5), st.floats(0.01, 20)),
    st.builds(Pulse, st.floats(-5, 5), st.floats(5, 95), st.floats(0.05, 2),
              horizon=st.just(5.0)),
    st.lists(st.floats(-5, 5), min_size=1, max_size=20).map(
        lambda v: Table(np.linspace(0.0, 3.0, len(v)), v)))


@settings(max_examples=200, deadline=None)
@given(st.lists(_SIGNALS, min_size=1, max_size=4),
       st.lists(st.floats(-1.0, 5.0), min_size=1, max_size=30))
def test_a_signal_is_evaluated_by_the_engine_as_by_numba(parts, times):
    # Signal.__call__ runs the C engine's input evaluation where the engine is available;
    # numba's (without an engine, and the scipy backend's) must give the same bits, at
    # every kind of signal, on and off its breakpoints
    from clutchsim.core import cengine
    from clutchsim.core.signals import Sum, _eval_series, build_bank
    sig = Sum(tuple(parts))
    t = np.array(sorted(times + list(sig.breakpoints())[:10]))
    if not cengine.available():
        pytest.skip("the C engine is not available here (no C compiler)")
    got = sig(t)
    want = np.empty_like(t)
    _eval_series(build_bank([sig]), t, want)
    assert np.array_equal(got, want), np.nonzero(got != want)
