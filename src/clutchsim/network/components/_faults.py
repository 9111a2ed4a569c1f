"""Time-triggered faults of a component as scheduled value changes (docs/components.md,
faults).

A fault changes the component's values at located time events (``e.event(..., "bank")``,
:meth:`~clutchsim.network.component.Component.schedule`): the right-hand side before the
event never sees the fault, so the integrator steps up to it smoothly, the event is located
at its time, and the new values take effect there.  The fault's phase (0 before, 1 from
``fault_time``, 2 once a gradual loss is complete) is not a scenario key: only the
schedule sets it.
"""

from __future__ import annotations


class FaultPhase:
    """Mixin: the fault's phase, set by the schedule (``fault_phase``) through
    :meth:`with_values`."""

    fault_phase = 0

    def with_values(self, **changes):
        phase = changes.pop("fault_phase", None)
        new = super().with_values(**changes)
        if phase is not None:
            new.fault_phase = int(phase)
        new.check_fault()
        return new

    def check_fault(self) -> None:
        """Checks of its fault keys together (at construction and after with_values)."""

    def format_values(self) -> dict:
        """Its values and ``fault_description``, for its event names."""
        return {**self.values, "fault_description": self.fault_description() or ""}
