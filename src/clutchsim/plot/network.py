"""The figure of a run of any network (not a launch): positions, speeds, torques or forces,
friction power and temperatures over time (docs/outputs.md)."""

from __future__ import annotations

from ..network.spec import DOMAINS
from ._style import new_figure

__all__ = ["network_panels", "plot_network"]


def network_panels(result) -> list[tuple[str, str, list[str]]]:
    """What :func:`plot_network` draws: ``(title, y label, [signal, ...])`` per panel, the
    panels without a signal left out: the node positions (``phi_<node>`` [rad] /
    ``s_<node>`` [m], when the run outputs them), the node speeds (``omega_<node>``
    [rad/s] / ``v_<node>`` [m/s]), the torques or forces of the components
    (``T_<component>`` [N·m] / ``F_<component>`` [N]: sources, loads, friction elements),
    the friction elements' power ``P_<element>`` [W] and the temperatures ``theta_<node>``
    [°C]."""
    meta = result.metadata
    d = DOMAINS[meta.get("domain", "rotational")]
    kinds = dict(meta.get("kinds", {}))
    nodes = set(meta.get("nodes", ())) | set(kinds)
    units = result.units

    def named(prefix, unit, names):
        return [f"{prefix}_{n}" for n in names
                if f"{prefix}_{n}" in result.signals and units[f"{prefix}_{n}"] == unit]

    ordered = [s.split("_", 1)[1] for s in result.signals if "_" in s]
    node_names = [n for n in dict.fromkeys(ordered) if n in nodes]
    rotational = d.name == "rotational"
    panels = [
        ("angles" if rotational else "positions",
         f"{'angle' if rotational else 'position'} [{d.position_unit}]",
         named(d.position, d.position_unit, node_names)),
        ("speeds" if rotational else "velocities",
         f"{'speed' if rotational else 'velocity'} [{d.speed_unit}]",
         named(d.speed, d.speed_unit, node_names)),
        ("torques" if rotational else "forces",
         f"{'torque' if rotational else 'force'} [{d.effort_unit}]",
         named(d.effort, d.effort_unit, kinds)),
        ("friction power", "power [W]", named("P", "W", meta.get("models", {}))),
        ("temperatures", "temperature [°C]",
         [s for s in result.signals if s.startswith("theta_")]),
    ]
    return [p for p in panels if p[2]]


def plot_network(result, *, title: str = "", **kw):
    """One panel per kind of signal of :func:`network_panels`, over time; returns
    ``(figure, axes)``.  Unknown keywords raise."""
    if kw:
        raise TypeError(f"plot_network: unknown keyword(s) {', '.join(kw)}")
    panels = network_panels(result)
    if not panels:
        panels = [("signals", "value", [])]
    fig, ax = new_figure(len(panels), 1, figsize=(9.0, 2.6 * len(panels) + 0.8),
                         sharex=True)
    for a, (head, ylabel, names) in zip(ax[:, 0], panels):
        for n in names:
            a.plot(result.t, result[n], label=n)
        a.set_title(head, fontsize=10)
        a.set_ylabel(ylabel)
        if names:
            a.legend(loc="best", fontsize=8)
        a.grid(True, alpha=0.3)
    ax[-1, 0].set_xlabel("time [s]")
    models = sorted(set(result.metadata.get("models", {}).values()))
    with_models = f" — {', '.join(models)}" if models else ""
    fig.suptitle(title or f"{result.system}{with_models} ({result.status})")
    return fig, ax
