"""Numerics with no physics in them: Chebyshev series, statistics, array helpers and the
named numerical thresholds."""
