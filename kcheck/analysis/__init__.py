"""From a scene to its analysed retraction cases, and what is built on them (sanity
warnings, kcheck suggest).

:func:`analyse` is the entry point: at the scene's friction coefficients
(:mod:`.cases`), or, when they are ranges, closing for every coefficient in them
(:mod:`.friction_ranges`, which evaluates :mod:`.cases` at the worst coefficients).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from kcheck.analysis.cases import Analysis, analyse_fixed, analyse_fixed_many
from kcheck.analysis.friction_ranges import analyse_range
from kcheck.result import MassProperties
from kcheck.scene import Scene

__all__ = ["analyse", "analyse_many"]


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


def analyse_many(
    scenes: Sequence[Scene], masses: Sequence[MassProperties], sweep: bool = True
) -> list[Analysis]:
    """:func:`analyse` of several scenes (e.g. the scenes of a worker's chunk, or a study's
    variants): the cases' algebra of every scene at fixed coefficients is stacked and solved
    in one batch of numpy calls (:func:`kcheck.analysis.cases.analyse_fixed_many`); scenes with
    ranges of coefficients are analysed one by one. Each result equals :func:`analyse`'s.
    ``sweep`` False: at fixed coefficients without the ranges in the scene's plane
    (:func:`kcheck.analysis.cases.scene_plane_ranges` adds them)."""
    out: list[Analysis | None] = [None] * len(scenes)
    fixed = []
    for i, scene in enumerate(scenes):
        low, high = scene.friction_range("kinetic")
        if np.array_equal(low, high):
            fixed.append(i)
        else:
            out[i] = analyse_range(scene, masses[i], low, high)
    batch = analyse_fixed_many([scenes[i] for i in fixed], [masses[i] for i in fixed], sweep=sweep)
    for i, analysis in zip(fixed, batch, strict=True):
        out[i] = analysis
    return [a for a in out if a is not None]
