"""parse_signal: formulas, CSV tables, round trips and rejection of anything else."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clutchsim.core import Constant, Pulse, Ramp, Sine, Step, Table
from clutchsim.signal_expr import format_signal, parse_signal

T = np.linspace(0.0, 5.0, 101)
num = st.floats(-1e3, 1e3, allow_nan=False).map(lambda x: round(x, 6))
pos = st.floats(0.01, 10.0).map(lambda x: round(x, 6))
signals = st.one_of(
    st.builds(Constant, num),
    st.builds(Step, pos, num, num),
    st.builds(Ramp, pos, pos, num, num),
    st.builds(Sine, num, pos, num, num, pos),
    st.builds(Pulse, num, st.floats(1.0, 100.0), pos, num, pos),
)


@settings(max_examples=60, deadline=None)
@given(st.lists(signals, min_size=1, max_size=3))
def test_format_parse_round_trip(parts):
    sig = parts[0] if len(parts) == 1 else sum(parts[1:], parts[0])
    back = parse_signal(format_signal(sig))
    np.testing.assert_allclose(back(T), sig(T), rtol=1e-12, atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(num, num, pos)
def test_arithmetic_matches_python(a, k, f):
    sig = parse_signal(f"{a} + {k}*sine({1.0}, {f}) - const(2)")
    expected = a + k * np.sin(2 * math.pi * f * T) - 2.0
    np.testing.assert_allclose(sig(T), expected, rtol=1e-12, atol=1e-9)


def test_keywords_and_pi():
    sig = parse_signal("sine(amplitude=0.4, freq=1, offset=0.5, phase=pi/2)")
    assert sig(0.0)[0] == pytest.approx(0.9)
    assert parse_signal("step(t=1, height=2, offset=-1)")(2.0)[0] == pytest.approx(1.0)
    assert parse_signal("pulse(1, 50, 2)")(1.5)[0] == 0.0
    assert parse_signal("3")(0.0)[0] == 3.0
    assert parse_signal("-(ramp(0, 2, 4))*0.5")(1.0)[0] == pytest.approx(-1.0)


@pytest.mark.parametrize("text, token", [
    ("__import__('os')", "__import__"),
    ("sine(1, 1).real", "sine(1, 1).real"),
    ("os.system('ls')", "os.system"),
    ("x + 1", "'x'"),
    ("[1, 2]", "[1, 2]"),
    ("lambda: 1", "lambda"),
    ("sine(1, 1) * sine(1, 2)", "multiplied by a number"),
    ("2 ** 3", "2 ** 3"),
    ("step(1)", "missing argument(s) height"),
    ("step(1, 2, foo=3)", "no argument 'foo'"),
    ("sine(*[1, 2])", "*[1, 2]"),
    ("ramp(0, -1, 1)", "duration"),
    ("'text'", "'text'"),
    ("1 +", "not a valid formula"),
])
def test_rejections_name_the_token(text, token):
    with pytest.raises(ValueError) as info:
        parse_signal(text)
    msg = str(info.value)
    assert token in msg
    assert "\n" not in msg


def test_csv_table_and_errors(tmp_path):
    good = tmp_path / "f.csv"
    good.write_text("time [s],force [N]\n0,0\n1,2\n")
    sig = parse_signal("f.csv", base_dir=tmp_path)
    assert isinstance(sig, Table)
    assert sig(0.5)[0] == pytest.approx(1.0)
    assert sig(7.0)[0] == pytest.approx(2.0)   # held after the last row
    bad = tmp_path / "bad.csv"
    bad.write_text("time,value\n0,0\n1\n")
    with pytest.raises(ValueError, match=r"bad\.csv:3"):
        parse_signal(str(bad))
    with pytest.raises(ValueError, match="not found"):
        parse_signal(str(tmp_path / "missing.csv"))
