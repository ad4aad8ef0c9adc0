"""The base layer: array helpers, units, the registry, checks and limits, tables and constants.

Nothing here knows any physics or any other layer; every other layer may import it.
"""
