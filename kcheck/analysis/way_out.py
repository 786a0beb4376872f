"""The nearest friction that makes a scene pass: a scan downwards from the scene's coefficient,
then bisection, each step judged by the check's own verdict (findings' ``hint``, issue 21).

Used where no closed form gives the bound (a margin the whole safe region must keep, the
tolerated tilt of a gravity-only scene). The answer is rounded down to three significant
digits and judged once more at that value: only a coefficient that passes is returned.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from kcheck.fmt import rounded_bound
from kcheck.scene import Scene

__all__ = ["with_friction", "passing_friction"]

#: Steps of the scan from the scene's coefficient down to zero, and bisection steps after it.
SCAN_STEPS = 10
BISECTIONS = 8


def with_friction(scene: Scene, mu: float) -> Scene:
    """The scene with every rough support's coefficient scaled so the largest is ``mu``."""
    top = max(s.friction for s in scene.supports)
    factor = 0.0 if top <= 0 else mu / top
    supports = tuple(dataclasses.replace(s, friction=s.friction * factor) for s in scene.supports)
    return dataclasses.replace(scene, supports=supports)


def passing_friction(scene: Scene, passes: Callable[[Scene], bool]) -> float | None:
    """The largest coefficient below the scene's (the largest one; the others in proportion)
    at which ``passes`` holds, to three significant digits rounded down, judged again there;
    None for coefficient ranges or static/kinetic pairs, or when no coefficient passes."""
    if any(not s.coefficients.plain for s in scene.supports):
        return None  # ranges and static/kinetic pairs: no one number to lower
    mu = max(s.friction for s in scene.supports)
    if not mu > 0:
        return None
    fails = mu
    for value in np.linspace(mu, 0.0, SCAN_STEPS + 1)[1:]:
        if passes(with_friction(scene, float(value))):
            good = float(value)
            break
        fails = float(value)
    else:
        return None
    for _ in range(BISECTIONS):
        middle = 0.5 * (good + fails)
        if passes(with_friction(scene, middle)):
            good = middle
        else:
            fails = middle
    if good <= 0:
        return 0.0
    rounded = rounded_bound(good, 3, up=False)
    if rounded > 0 and passes(with_friction(scene, rounded)):
        return rounded
    return good if passes(with_friction(scene, good)) else None
