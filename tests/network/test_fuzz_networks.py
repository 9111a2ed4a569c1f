"""Fuzzed networks (issue 34): random valid drivelines, every friction model a clutch
accepts, commands and torques that start at 0, cross 0, step, ramp and oscillate.  Each run
must end with an outcome of the core, break no physics invariant, close its energy balance
and agree with a rerun at tolerances 100 times tighter (:mod:`_fuzz`).

A bounded number of examples runs here (each new topology compiles a plant: about 1-2 s,
10-40 s for the few models that fall back to numba); ``scripts/fuzz_networks.py`` runs
thousands with a count and a seed.  A failing case, shrunk by hypothesis, becomes a
regression test below.
"""

import os

from hypothesis import HealthCheck, given, settings

from _fuzz import cases, check_run

EXAMPLES = int(os.environ.get("CLUTCHSIM_FUZZ_EXAMPLES", "12"))


@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(cases())
def test_fuzzed_networks_keep_the_physics(case):
    assert check_run(case) == [], case
