"""Rigid-body mechanics of a coupling, one physics concept per module: small pure functions
over numpy arrays, SI inside, nondimensional where a solve needs it."""
