"""Studies: many runs of a scenario and what they add up to.

Each study takes a :class:`~clutchsim.scenario.Scenario` (or a path), runs it through the
scenario runner and post-processes the results with :mod:`clutchsim.analysis`:

* :mod:`.sweeps`: grids and seeded random samples of a scenario's keys (:func:`sweep`);
* :mod:`.durability`: a duty cycle of launches with wear and temperature carried over;
* :mod:`.judder`: the modes at an operating time and judder maps over two keys;
* :mod:`.frf`: a scenario's frequency response at an operating time;
* :mod:`.uq`: uncertain inputs in, outcome probabilities, quantiles and sensitivity
  indices out (:func:`~clutchsim.studies.uq.uq`).

This package sits above :mod:`clutchsim.scenario` and below plotting, reports and the
command line.  Import the module you need; nothing is imported here.
"""
