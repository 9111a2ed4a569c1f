"""clutchsim: dry friction clutch and driveline simulation.

Friction models that do not stall the solver, a compiled simulation core with located
events, friction benchmarks, vehicle launches and parameter fitting.

>>> import clutchsim as cs
>>> res = cs.run_rig(cs.make_model("lugre"), 30.0, force=0.0, spring=2.0, pull_speed=0.1)
>>> res.status
'completed'

The names below are imported on first use (PEP 562): ``import clutchsim`` alone loads
neither numba nor the subpackages, so the command line's ``--help`` and a script that
needs one part do not pay for the others.  Every compiled module imports
:mod:`clutchsim._jit` (numba's cache settings) itself before it defines a kernel.
"""

from importlib import import_module

from ._version import __version__

#: public name -> the subpackage or module that defines it
_EXPORTS = {
    **dict.fromkeys(("Constant", "Pulse", "Ramp", "Result", "Sine", "SolverOptions", "Step",
                     "System", "Table", "register_system", "simulate"), "core"),
    **dict.fromkeys(("MODELS", "describe_models", "get_model_class", "load_parameter_set",
                     "make_model"), "friction"),
    "make_rig": "rig",
    "run_rig": "rig",
    "run_scenario": "scenario",
    **dict.fromkeys(("SweepOptions", "SweepSpec", "sweep"), "studies.sweeps"),
}

__all__ = [  # noqa: RUF022  (the names of _EXPORTS, in its order)
    "Constant", "Pulse", "Ramp", "Result", "Sine", "SolverOptions", "Step", "System", "Table",
    "register_system", "simulate", "MODELS", "describe_models", "get_model_class",
    "load_parameter_set", "make_model", "make_rig", "run_rig", "run_scenario", "SweepOptions",
    "SweepSpec", "sweep", "__version__",
]


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'clutchsim' has no attribute {name!r}")
    value = getattr(import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted({*globals(), *_EXPORTS})
