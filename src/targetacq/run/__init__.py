"""Running the model: the model chain, the step API and its simulation, search over time,
false targets, range options and sweeps, design and streaming.

Orchestrators: they compile inputs and call :mod:`targetacq.core`; they hold no physics.
"""
