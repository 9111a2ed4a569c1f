"""The launch explorer: a session that re-runs a scenario as its parameters change
(:mod:`.session`, plain Python) and a small web app over it (:mod:`.app`: Tornado and
uPlot, optional extra ``explore``; ``clutchsim explore``)."""

from .session import ENGAGEMENT, METRICS, TORQUE_FACTOR, ExplorerRun, Parameter, Session

__all__ = ["ENGAGEMENT", "METRICS", "TORQUE_FACTOR", "ExplorerRun", "Parameter", "Session"]
