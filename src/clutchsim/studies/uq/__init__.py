"""Uncertainty quantification: distributions on scenario keys in, probabilities of each
outcome, quantiles of every metric and sensitivity indices out (docs/uq.md).

>>> from clutchsim.studies.uq import uq
>>> r = uq(None, {"vehicle.grade": "uniform(0,8)"}, samples=200, seed=1)  # doctest: +SKIP
>>> r.probabilities["stalled"]["p"], r.probabilities["stalled"]["ci95"]   # doctest: +SKIP
"""

from .inputs import (
    Dist,
    UQInputError,
    correlation_matrix,
    parse_correlation,
    parse_dist,
    parse_inputs,
)
from .study import (
    METHODS,
    OUTCOMES,
    UQResult,
    clopper_pearson,
    make_samples,
    study,
    study_runs,
    uq,
    write_study,
)

__all__ = [
    "METHODS",
    "OUTCOMES",
    "Dist",
    "UQInputError",
    "UQResult",
    "clopper_pearson",
    "correlation_matrix",
    "make_samples",
    "parse_correlation",
    "parse_dist",
    "parse_inputs",
    "study",
    "study_runs",
    "uq",
    "write_study",
]
