"""The frequency response of a scenario's driveline at an operating time (docs/judder.md):
simulated to the time, linearised (:mod:`clutchsim.analysis.linear`) and evaluated over a
frequency grid (:mod:`clutchsim.analysis.frf`)."""

from __future__ import annotations

from ..analysis.frf import (
    FrequencyResponse,
    _check_names,
    _frequencies,
    frequency_grid,
    frequency_response,
    state_space,
)
from ..analysis.linear import _continuous, linearise, operating_point

__all__ = ["frf_analysis"]


def frf_analysis(scenario=None, model: str | None = None, at: float = 0.0, *, input: str,
                 output: str, freqs_hz=None, overrides=None) -> FrequencyResponse:
    """The frequency response from ``input`` to ``output`` of ``scenario``'s driveline with
    ``model`` on its clutch, linearised at ``at`` [s] (as
    :func:`~clutchsim.studies.judder.judder_analysis`: simulated to ``at``, inputs frozen,
    locked elements merged).  ``freqs_hz``: the grid [Hz] (default
    :func:`frequency_grid`'s).  The names are checked before the simulation.
    """
    from ..scenario import resolve_scenario
    scenario = resolve_scenario(scenario, overrides)
    if model is None and scenario.models:
        model = scenario.models[0]
    f = frequency_grid() if freqs_hz is None else _frequencies(freqs_hz)

    def check(system):
        cont = [system.state_names[j] for j in _continuous(system)]
        _check_names(input, output, system.input_names, (*system.output_names, *cont),
                     f"{system.name} ({scenario.file})")

    point = operating_point(scenario, model, at, check=check)
    lin = linearise(point.system, point.t_s, point.y, point.u)
    if output in point.system.state_names and output not in \
            {point.system.state_names[j] for j in lin.continuous}:
        raise ValueError(f"output {output!r} is a discrete value held at the operating point "
                         f"t = {point.t_s:g} s (frozen, not linearised): it has no response")
    ss = state_space(point.system, lin, point.y, point.u)
    name = point.system.metadata.get("models", {}).get(scenario.clutch, model or "")
    return frequency_response(ss, input, output, f).with_model(str(name))
