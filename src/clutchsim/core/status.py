"""Named codes of the simulation core, one meaning each.

* :class:`Action`: what a plant's reset map did at a located event (returned by
  ``reset(t, y, u, p, k)``).
* :class:`Code`: how the compiled integration loop ended (internal, integer so that the
  compiled code can return it).
* :class:`Outcome`: the machine-readable reason a run ended, as carried by
  :attr:`clutchsim.core.Result.outcome` and every JSON summary.  Code reads this, never the
  human message beside it.

numba treats ``IntEnum`` members as compile-time integer constants, so the compiled loop
uses the same names as Python.
"""

from __future__ import annotations

import enum

__all__ = ["Action", "Code", "Outcome"]


class Action(enum.IntEnum):
    """What a plant's reset map did at event ``k``."""

    #: the event is recorded, the state is unchanged
    CONTINUE = 0
    #: the reset map changed the state; integration restarts from it
    STATE_CHANGED = 1
    #: stop the run successfully (a terminal event)
    STOP = 2
    #: stop the run as failed (e.g. the engine stalled)
    FAIL = 3
    #: the event is recorded, the state is unchanged and the right-hand side is smooth
    #: across the crossing (a monitoring event): integration goes on through it
    PASS = 4


#: the words for :class:`Action` in :attr:`clutchsim.core.Event.action`
ACTION_WORDS = {Action.CONTINUE: "recorded", Action.STATE_CHANGED: "reset",
                Action.STOP: "stop", Action.FAIL: "fail", Action.PASS: "recorded"}


class Code(enum.IntEnum):
    """How the compiled integration loop ended."""

    DONE = 0
    EVENT_STOP = 1
    EVENT_FAIL = 2
    MAX_STEPS = 3
    WALL_TIME = 4
    STEP_COLLAPSE = 5
    CHATTER = 6
    NON_FINITE = 7
    JAC_NON_FINITE = 8


class Outcome(enum.StrEnum):
    """Why a run ended (machine-readable; the human message says where and what to do)."""

    #: reached the end time
    COMPLETED = "completed"
    #: a terminal event ended the run as intended
    STOPPED = "stopped"
    #: a plant event declared the run failed (:attr:`Result.event` names it, e.g. an
    #: engine stall)
    EVENT_FAILED = "event_failed"
    #: the step budget (``SolverOptions.max_steps``) was exhausted
    BUDGET = "budget"
    #: the wall-time budget (``SolverOptions.wall_time``) was exhausted
    WALL_TIME = "wall_time"
    #: the step size fell below its floor (a discontinuity not declared as an event)
    STEP_COLLAPSE = "step_collapse"
    #: too many events in a short window (a sliding mode)
    CHATTER = "chatter"
    #: a NaN or infinity appeared in the state or its derivative
    NAN = "nan"
    #: a scipy reference backend reported an error of its own
    SOLVER_ERROR = "solver_error"
    #: the run broke a physics invariant the plant declares (:attr:`System.invariants`:
    #: e.g. friction that created energy); the message names the part, the check, the
    #: time and the values
    INVARIANT_VIOLATED = "invariant_violated"

    @property
    def status(self) -> str:
        """The coarse status: ``completed``, ``stopped`` or ``failed``."""
        if self in (Outcome.COMPLETED, Outcome.STOPPED):
            return self.value
        return "failed"


#: outcome of each integrator code
OUTCOME_OF_CODE = {Code.DONE: Outcome.COMPLETED, Code.EVENT_STOP: Outcome.STOPPED,
                   Code.EVENT_FAIL: Outcome.EVENT_FAILED, Code.MAX_STEPS: Outcome.BUDGET,
                   Code.WALL_TIME: Outcome.WALL_TIME, Code.STEP_COLLAPSE: Outcome.STEP_COLLAPSE,
                   Code.CHATTER: Outcome.CHATTER, Code.NON_FINITE: Outcome.NAN,
                   Code.JAC_NON_FINITE: Outcome.NAN}
