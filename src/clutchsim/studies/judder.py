"""Judder studies: the modes of a slipping driveline at an operating time of a scenario,
and the judder margin over a grid of scenario variants.

:func:`judder_analysis` linearises a scenario's driveline at an operating time and reports
every mode and every switching element's friction slope (docs/judder.md).  The classic
criterion: the slipping mode loses its damping when the driveline damping plus the
friction slope ``dT/dω`` falls below zero.  :func:`judder_map` repeats it over a 2-D grid
of scenario keys.  The time-domain metric of a run is
:func:`clutchsim.analysis.judder_band.judder_amplitude`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.linear import LinearModel, Mode, OperatingPoint, linearise, modes, operating_point

__all__ = ["JudderMap", "JudderResult", "judder_analysis", "judder_map"]


@dataclass(frozen=True)
class JudderResult:
    """The modes of a scenario's driveline at ``point.t_s`` (see :func:`judder_analysis`)."""

    model: str
    point: OperatingPoint
    linear: LinearModel
    modes: tuple[Mode, ...]

    @property
    def stable(self) -> bool:
        return all(m.stable for m in self.modes)

    def as_dict(self) -> dict:
        """The JSON document of ``clutchsim judder --json``."""
        return {"kind": "judder", "model": self.model,
                "operating_point": {"t_s": self.point.t_s,
                                    "elements": {e.name: e.as_dict()
                                                 for e in self.point.elements}},
                "modes": [m.as_dict() for m in self.modes], "stable": self.stable}


def judder_analysis(scenario=None, model: str | None = None, at: float = 0.0, *,
                    overrides=None, elements=None) -> JudderResult:
    """Linearise ``scenario``'s driveline with ``model`` on its clutch at ``at`` [s].

    Simulates from 0 to ``at`` (inputs as the scenario gives them), freezes the inputs,
    linearises (:func:`~clutchsim.analysis.linear.linearise`: locked elements merged,
    slipping ones through their friction slope) and returns the modes and the elements
    (``elements``: report only these; an unknown name is a ``ValueError``).
    ``scenario``: a loaded :class:`~clutchsim.scenario.Scenario`, a path or None (the
    default launch), with ``overrides`` (``key=value`` strings) for a path or None.
    """
    from ..scenario import resolve_scenario
    scenario = resolve_scenario(scenario, overrides)
    if model is None and scenario.models:
        model = scenario.models[0]
    point = operating_point(scenario, model, at, elements=elements)
    lin = linearise(point.system, point.t_s, point.y, point.u)
    name = point.system.metadata.get("models", {}).get(scenario.clutch, model or "")
    return JudderResult(str(name), point, lin, modes(lin))


@dataclass(frozen=True)
class JudderMap:
    """Judder margin over a 2-D grid of scenario variants (see :func:`judder_map`).

    ``x_key``/``y_key`` the scenario keys, ``x``/``y`` their values; arrays of shape
    ``(len(y), len(x))``: ``damping_ratio`` the smallest damping ratio of the oscillatory
    modes [-] (the judder margin; NaN without one), ``growth_rate_1_s`` their largest
    growth rate [1/s], ``frequency_hz`` the frequency of the least-damped one [Hz],
    ``friction_slope_Nms`` the clutch's friction slope (NaN when not slipping),
    ``stable`` whether every oscillatory mode is stable.  ``classic`` names the axis
    (``"x"`` or ``"y"``) that is a driveline damping c [N·m·s/rad], for the classic
    boundary ``c + dT/dω = 0``, or None.
    """

    x_key: str
    x: np.ndarray
    y_key: str
    y: np.ndarray
    t_s: float
    model: str
    damping_ratio: np.ndarray
    growth_rate_1_s: np.ndarray
    frequency_hz: np.ndarray
    friction_slope_Nms: np.ndarray
    stable: np.ndarray
    classic: str | None = None

    def rows(self) -> list[dict]:
        """One dict per grid point (the table)."""
        out = []
        for i, yv in enumerate(self.y):
            for j, xv in enumerate(self.x):
                out.append({self.x_key: float(xv), self.y_key: float(yv),
                            "damping_ratio": _num(self.damping_ratio[i, j]),
                            "growth_rate_1_s": _num(self.growth_rate_1_s[i, j]),
                            "frequency_hz": _num(self.frequency_hz[i, j]),
                            "friction_slope_Nms": _num(self.friction_slope_Nms[i, j]),
                            "stable": bool(self.stable[i, j])})
        return out

    def as_dict(self) -> dict:
        return {"kind": "judder_map", "model": self.model, "t_s": self.t_s,
                "x": {"key": self.x_key, "values": [float(v) for v in self.x]},
                "y": {"key": self.y_key, "values": [float(v) for v in self.y]},
                "points": self.rows()}


def _num(v) -> float | None:
    return None if not np.isfinite(v) else float(v)


def _axis(spec, what: str):
    try:
        key, values = spec
        values = np.asarray([float(v) for v in values], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"judder_map: {what} = {spec!r} must be (key, values)") from None
    if not isinstance(key, str) or not key or values.size < 1 or \
            not np.all(np.isfinite(values)):
        raise ValueError(f"judder_map: {what} = {spec!r} must be (key, finite values)")
    return key, values


def judder_map(scenario=None, model: str | None = None, *, x, y, at: float = 0.0,
               overrides=(), classic: str | None = None, progress=None) -> JudderMap:
    """The judder margin of ``scenario`` at ``at`` [s] over the grid ``x`` × ``y``.

    ``x``, ``y``: ``(key, values)`` with ``key`` a scenario key (as ``--set``) and
    ``values`` its grid.  Every point is a :func:`judder_analysis` of the scenario with
    ``overrides`` plus ``key=value`` of both axes (a linearisation, after a simulation to
    ``at`` when ``at > 0``).  ``scenario`` is a path or None (the default launch).
    """
    x_key, xs = _axis(x, "x")
    y_key, ys = _axis(y, "y")
    if classic not in (None, "x", "y"):
        raise ValueError(f"judder_map: classic = {classic!r} must be 'x', 'y' or None")
    shape = (ys.size, xs.size)
    zeta, growth, freq, slope = (np.full(shape, np.nan) for _ in range(4))
    stable = np.zeros(shape, dtype=bool)
    name = model or ""
    for i, yv in enumerate(ys):
        for j, xv in enumerate(xs):
            ov = [*overrides, f"{x_key}={float(xv)!r}", f"{y_key}={float(yv)!r}"]
            r = judder_analysis(scenario, model, at, overrides=ov)
            name = r.model
            osc = [m for m in r.modes if m.frequency_hz > 0.0]
            if osc:
                worst = min(osc, key=lambda m: m.damping_ratio)
                zeta[i, j], freq[i, j] = worst.damping_ratio, worst.frequency_hz
                growth[i, j] = max(m.growth_rate_1_s for m in osc)
            stable[i, j] = all(m.stable for m in osc)
            clutch = [e for e in r.point.elements if e.state == "slipping"]
            if clutch and clutch[0].friction_slope_Nms is not None:
                slope[i, j] = clutch[0].friction_slope_Nms
            if progress is not None:
                progress.update(1)
    return JudderMap(x_key, xs, y_key, ys, float(at), name, zeta, growth, freq, slope,
                     stable, classic)
