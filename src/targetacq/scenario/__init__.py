"""Scenario files: the schema of sensors, targets, path and time, read and checked
(:mod:`targetacq.scenario.schema`)."""
