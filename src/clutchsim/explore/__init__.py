"""The launch explorer: a session that re-runs a scenario as its parameters change
(:mod:`.session`, plain Python) and a Bokeh server app over it (:mod:`.app`, optional
extra ``explore``; ``clutchsim explore``)."""

from .session import ENGAGEMENT, METRICS, TORQUE_FACTOR, ExplorerRun, Parameter, Session

__all__ = ["ENGAGEMENT", "METRICS", "TORQUE_FACTOR", "ExplorerRun", "Parameter", "Session"]
