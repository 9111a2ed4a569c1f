"""``clutchsim._util.toml_line``: the line a key of a TOML file is set on, the one place
that scenario, fit-spec, calibration-spec and channel-map errors find their line."""

import tomllib

import pytest

from clutchsim._util import toml_line

TEXT = """\
# a scenario
name = "top"            # a top-level key before the first header
[scenario]
t_end = 4.0
# models = ["not", "this"]
models = ["a", "b"]

[[coupling]]
name = "clutch"
friction = { model = "coulomb-robust", overrides = { F_c = 1.0 } }
heat = [{ node = "plate", share = 0.5 }, { node = "flywheel", share = 0.5 }]

[[coupling]]
name = "damper"
c = 600.0

[ inputs.F ]
gain = 2.0

[channels."engine speed"]
name = "EEC1.EngSpeed"
"EEC1.EngSpeed" = 3
"""


def _line(needle: str, nth: int = 0) -> int:
    lines = [i for i, line in enumerate(TEXT.splitlines(), 1) if needle in line]
    return lines[nth]


def test_the_text_is_toml():
    tomllib.loads(TEXT)


@pytest.mark.parametrize(("path", "key", "needle", "nth"), [
    ("name", None, 'name = "top"', 0),                       # top level, before any header
    ("scenario", None, "[scenario]", 0),
    ("scenario.models", None, 'models = ["a"', 0),           # the comment is skipped
    ("coupling[0].name", None, 'name = "clutch"', 0),
    ("coupling[1].name", None, 'name = "damper"', 0),
    ("coupling[1].c", None, "c = 600.0", 0),
    ("coupling[0].friction.model", None, "friction = {", 0),  # inside an inline table
    ("coupling[0].friction.overrides.F_c", None, "friction = {", 0),
    ("coupling[0].heat[1].node", None, "heat = [", 0),       # an inline array of tables
    ("inputs.F.gain", None, "gain = 2.0", 0),                # a dotted header with spaces
    ("inputs", None, "[ inputs.F ]", 0),                     # only its sub-table is written
    ('channels."engine speed".name', None, 'name = "EEC1', 0),
    ([("coupling", 1)], "c", "c = 600.0", 0),               # parts, and a key as it is
    ('channels."engine speed"', "EEC1.EngSpeed", '"EEC1.EngSpeed" = 3', 0),
])
def test_a_key_is_found_on_its_line(path, key, needle, nth):
    assert toml_line(TEXT, path, key) == _line(needle, nth)


@pytest.mark.parametrize(("path", "needle"), [
    ("scenario.dt_out", "[scenario]"),          # not written: its table, where to add it
    ("coupling[1].friction", '[[coupling]]'),    # (the second one: index 1)
    ("coupling[5].name", None),                  # no sixth coupling: nothing reached
    ("vehicle.mass", None),                      # no such table
    ("t_end", None),                             # not a top-level key (it is in [scenario])
])
def test_a_key_not_written_gives_the_line_reached(path, needle):
    expected = None if needle is None else _line(needle, 1 if "coupling[1]" in path else 0)
    assert toml_line(TEXT, path) == expected


def test_a_path_that_is_not_a_key_path_is_refused():
    with pytest.raises(ValueError, match="not a key path"):
        toml_line(TEXT, "coupling[x")
