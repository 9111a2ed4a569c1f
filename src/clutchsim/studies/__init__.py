"""Studies built on many runs of a scenario: uncertainty quantification (:mod:`.uq`)."""
