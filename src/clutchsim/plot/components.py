"""Figures of the network components around the clutch (docs/components.md): gear lash,
dual-mass flywheels, torque converters and the friction elements of a run."""

from __future__ import annotations

from ._style import new_figure

__all__ = ["component_panels", "plot_components"]


def component_panels(result) -> list[tuple[str, str, list[tuple[str, str, float]]]]:
    """What :func:`plot_components` draws: ``(title, y label, [(signal, label, factor)])``
    per panel, found from the run's signals (``contact_<lash>``, ``T_spring_<dmf>``,
    ``speed_ratio_<converter>``, ``T_friction_<element>``)."""
    sig = result.signals
    panels = []
    for name in sig:
        if name.startswith("contact_") and f"T_{name[8:]}" in sig:
            lash = name[8:]
            panels.append((f"gear lash {lash!r}: torque (< 0 drive flanks, > 0 coast)", "N·m",
                           [(f"T_{lash}", "torque", 1.0)]))
            panels.append((f"gear lash {lash!r}: flanks in contact", "-",
                           [(name, "contact side (-1, 0, +1)", 1.0)]))
        elif name.startswith("T_spring_") and f"phi_{name[9:]}" in sig:
            dmf = name[9:]
            panels.append((f"dual-mass flywheel {dmf!r}: arc spring and friction ring", "N·m",
                           [(name, "arc spring", 1.0),
                            (f"T_friction_{dmf}", "friction ring", 1.0)]))
            panels.append((f"dual-mass flywheel {dmf!r}: twist", "rad",
                           [(f"phi_{dmf}", "twist", 1.0)]))
        elif name.startswith("speed_ratio_"):
            tc = name[12:]
            panels.append((f"torque converter {tc!r}: pump and turbine torque", "N·m",
                           [(f"T_pump_{tc}", "pump", 1.0), (f"T_turbine_{tc}", "turbine", 1.0)]))
            panels.append((f"torque converter {tc!r}: speed ratio", "-", [(name, "turbine/pump",
                                                                          1.0)]))
    clutches = [n for n in sig if n.startswith("T_friction_")
                and f"T_spring_{n[11:]}" not in sig]
    if clutches:
        # drawn as the torque side a passes on to side b (the launch figure's convention)
        panels.append(("friction elements: torque passed on", "N·m",
                       [(n, n[11:], -1.0) for n in clutches]))
    return panels


def plot_components(result, **kw):
    """One panel per quantity of :func:`component_panels`; returns ``(figure, axes)``, or
    None when the run has none of these components.  Unknown keywords raise."""
    if kw:
        raise TypeError(f"plot_components: unknown keyword(s) {', '.join(kw)}")
    panels = component_panels(result)
    if not panels:
        return None
    fig, ax = new_figure(len(panels), 1, figsize=(9.0, 2.4 * len(panels)), sharex=True)
    for a, (title, unit, lines) in zip(ax[:, 0], panels):
        for name, label, factor in lines:
            if name in result.signals:
                a.plot(result.t, factor * result[name], label=label)
        a.set_title(title, fontsize=10)
        a.set_ylabel(f"[{unit}]")
        a.grid(True, alpha=0.3)
        if len(lines) > 1:
            a.legend(loc="best", fontsize=8)
    ax[-1, 0].set_xlabel("time [s]")
    fig.suptitle(f"{result.system}: components")
    return fig, ax
