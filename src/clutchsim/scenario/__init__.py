"""Scenario files: TOML schema, loader and errors (file, key path, line), and running
them (:func:`run_scenario`)."""

from .errors import ScenarioError
from .loader import (
    Scenario,
    apply_overrides,
    default_scenario_text,
    load_scenario,
    resolve_scenario,
)
from .run import LaunchResult, run_scenario
from .schema import reference_markdown

__all__ = [
    "LaunchResult",
    "Scenario",
    "ScenarioError",
    "apply_overrides",
    "default_scenario_text",
    "load_scenario",
    "reference_markdown",
    "resolve_scenario",
    "run_scenario",
]
