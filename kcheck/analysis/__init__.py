"""From a scene to its analysed retraction cases, and what is built on them (sanity
warnings, kcheck suggest).

:func:`analyse` is the entry point: at the scene's friction coefficients
(:mod:`.cases`), or, when they are ranges, closing for every coefficient in them
(:mod:`.friction_ranges`, which evaluates :mod:`.cases` at the worst coefficients).
"""

from __future__ import annotations

import numpy as np

from kcheck.analysis.cases import Analysis, analyse_fixed
from kcheck.analysis.friction_ranges import analyse_range
from kcheck.result import MassProperties
from kcheck.scene import Scene

__all__ = ["analyse"]


def analyse(
    scene: Scene,
    mass: MassProperties,
    plane: tuple[np.ndarray, np.ndarray] | None = None,
    friction: np.ndarray | None = None,
) -> Analysis:
    """Free motion, outcome, forces, friction intervals and exact safe arcs for every case.

    ``plane`` (``e1, e2``, 3-vectors) overrides the scene's sweep plane for the ranges. The
    supports' kinetic coefficients are used; when they are ranges, every case must close for
    every coefficient in them (:func:`kcheck.analysis.friction_ranges.analyse_range`).
    ``friction`` (k,) fixes the coefficients instead.
    """
    if friction is None:
        low, high = scene.friction_range("kinetic")
        if not np.array_equal(low, high):
            return analyse_range(scene, mass, low, high, plane)
    return analyse_fixed(scene, mass, plane, friction)
