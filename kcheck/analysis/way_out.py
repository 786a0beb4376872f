"""The nearest friction, or the least closing force, that makes a scene pass: a scan from the
scene's value, then bisection, each step judged by the check's own verdict (findings' ``hint``,
issue 21).

Used where no closed form gives the bound (a margin the whole safe region must keep, the
tolerated tilt of a gravity-only scene). The answer is rounded down to three significant
digits and judged once more at that value: only a coefficient that passes is returned.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np

from kcheck.fmt import rounded_bound
from kcheck.records import dataclass
from kcheck.result import MassProperties
from kcheck.scene import Scene

__all__ = [
    "with_friction",
    "passing_friction",
    "ClosingForce",
    "closing_force",
    "with_closing_force",
    "passing_closing_force",
    "Screen",
    "trial_screens",
]

#: Steps of the scan from the scene's coefficient down to zero, and bisection steps after it.
SCAN_STEPS = 10
BISECTIONS = 8

#: The closing force is scanned over factors 2**k of the scene's, k = ±1 ... ±FORCE_OCTAVES,
#: then bisected FORCE_BISECTIONS times (a relative width of 2**-12 of an octave: below the
#: three significant digits the answer is written with).
FORCE_OCTAVES = 10
FORCE_BISECTIONS = 12

#: A cheaper first test of many trial scenes at once: False where ``passes`` is surely False
#: (its own first test, e.g. a case that does not close), True where it must be asked.
Screen = Callable[[Sequence[Scene]], Sequence[bool]]


def with_friction(scene: Scene, mu: float) -> Scene:
    """The scene with every rough support's coefficient scaled so the largest is ``mu``."""
    top = max(s.friction for s in scene.supports)
    factor = 0.0 if top <= 0 else mu / top
    supports = tuple(dataclasses.replace(s, friction=s.friction * factor) for s in scene.supports)
    return dataclasses.replace(scene, supports=supports)


def passing_friction(
    scene: Scene, passes: Callable[[Scene], bool], screen: Screen | None = None
) -> float | None:
    """The largest coefficient below the scene's (the largest one; the others in proportion)
    at which ``passes`` holds, to three significant digits rounded down, judged again there;
    None for coefficient ranges or static/kinetic pairs, or when no coefficient passes.
    ``screen`` tests the scan's trial scenes in one call first (the same answer, sooner)."""
    if any(not s.coefficients.plain for s in scene.supports):
        return None  # ranges and static/kinetic pairs: no one number to lower
    mu = max(s.friction for s in scene.supports)
    if not mu > 0:
        return None
    fails = mu
    values = [float(v) for v in np.linspace(mu, 0.0, SCAN_STEPS + 1)[1:]]
    trials = [with_friction(scene, v) for v in values]
    worth = [True] * len(trials) if screen is None else list(screen(trials))
    for value, trial, ask in zip(values, trials, worth, strict=True):
        if ask and passes(trial):
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


@dataclass(frozen=True)
class ClosingForce:
    """What a designer can set to close a scene harder: the preloads (the largest one named,
    the others in proportion) or, without preloads, the load magnitude (which only matters
    beside the weight or a torque). ``value`` in N."""

    kind: str  # "preload" or "load"
    name: str  # the preload's name, or "load"
    value: float
    proportional: bool  # other preloads scaled with the named one


def closing_force(scene: Scene) -> ClosingForce | None:
    """The closing force whose magnitude can be changed, or None (no preload in the plane of
    motion, and no load magnitude that has anything to be weighed against)."""
    dim = scene.dim
    pushing = [p for p in scene.preloads if np.any(p.force[:dim] != 0)]
    if pushing:
        top = max(pushing, key=lambda p: float(np.linalg.norm(p.force[:dim])))
        return ClosingForce(
            "preload", top.name, float(np.linalg.norm(top.force[:dim])), len(pushing) > 1
        )
    load = scene.load
    if load is None or not load.magnitude > 0:
        return None
    torque = load.torque[2:] if dim == 2 else load.torque
    if not np.any(scene.gravity[:dim]) and not np.any(torque):
        return None  # the load alone: its magnitude does not change any verdict
    return ClosingForce("load", "load", float(load.magnitude), False)


def with_closing_force(scene: Scene, force: ClosingForce, value: float) -> Scene:
    """The scene with the closing force ``force`` set to ``value`` N (preloads in proportion)."""
    factor = value / force.value
    if force.kind == "preload":
        preloads = tuple(dataclasses.replace(p, force=p.force * factor) for p in scene.preloads)
        return dataclasses.replace(scene, preloads=preloads)
    assert scene.load is not None
    return dataclasses.replace(scene, load=dataclasses.replace(scene.load, magnitude=value))


def passing_closing_force(
    scene: Scene, passes: Callable[[Scene], bool], screen: Screen | None = None
) -> tuple[ClosingForce, float, str] | None:
    """The closing force nearest the scene's at which ``passes`` holds: (the force, its value in
    N, ``"at least"`` or ``"at most"``), rounded outward to three significant digits (up for a
    least force, down for a most) and judged again there; None when no factor 2**±10 of the
    scene's passes, or the scene has no closing force to change.

    Upwards first: a coupling that loses contact or jams mostly wants more closing force. The
    answer is bracketed between a failing and a passing value, so "at least" is the least to
    the resolution of the bisection between them, not a claim about every larger value (more
    force can jam): the value returned is judged to pass. ``screen`` tests each sense's scan
    of trial forces in one call first, and each further trial alone (the same answer,
    sooner)."""
    force = closing_force(scene)
    if force is None:
        return None
    base = force.value

    def judged(value: float) -> bool:
        trial = with_closing_force(scene, force, value)
        if screen is not None and not screen([trial])[0]:
            return False
        return passes(trial)

    for sense, sign in (("at least", 1), ("at most", -1)):
        fails = base
        values = [base * 2.0 ** (sign * k) for k in range(1, FORCE_OCTAVES + 1)]
        worth = [True] * len(values)
        if screen is not None:
            worth = list(screen([with_closing_force(scene, force, v) for v in values]))
        for value, ask in zip(values, worth, strict=True):
            if ask and judged(value):
                good = value
                break
            fails = value
        else:
            continue
        rejected = None  # the rounded bound, once judged to fail before the bisection's end
        for step in range(FORCE_BISECTIONS):
            left = FORCE_BISECTIONS - step
            if rejected is None and left <= SETTLE_STEPS:
                # Every value the remaining steps can end on rounds to one bound: judge it now
                # (the answer when it passes, as after the last step; else go on for `good`).
                settled = _settled_bound(good, fails, left, sign > 0)
                if settled is not None:
                    if settled > 0 and judged(settled):
                        return force, settled, sense
                    rejected = settled
            middle = math.sqrt(good * fails)
            if judged(middle):
                good = middle
            else:
                fails = middle
        rounded = rounded_bound(good, 3, up=sign > 0)
        assert rejected is None or rejected == rounded
        # The rounded bound already judged above (it fails) is not judged again.
        for candidate in (rounded, good) if rejected is None else (good,):
            if candidate > 0 and judged(candidate):
                return force, candidate, sense
    return None


#: Bisection steps left from which :func:`passing_closing_force` asks whether every value they
#: can end on rounds to the same bound (2**SETTLE_STEPS paths enumerated at most).
SETTLE_STEPS = 7


def _settled_bound(good: float, fails: float, steps: int, up: bool) -> float | None:
    """The rounded bound (:func:`kcheck.fmt.rounded_bound`, three digits) of every value the
    closing force's bisection can end on from the bracket ``good``, ``fails`` after ``steps``
    more steps (each path's float arithmetic as the bisection's own), or None when they
    differ. Whatever each trial's verdict, the bisection ends on one of these values."""
    lowest = good
    for _ in range(steps):  # every step passes: the path to the value nearest ``fails``
        lowest = math.sqrt(lowest * fails)
    bound = rounded_bound(good, 3, up=up)
    if rounded_bound(lowest, 3, up=up) != bound:
        return None
    brackets = [(good, fails)]
    for _ in range(steps):
        brackets = [
            pair
            for g, f in brackets
            for middle in (math.sqrt(g * f),)
            for pair in ((middle, f), (g, middle))
        ]
    if all(rounded_bound(g, 3, up=up) == bound for g, _ in brackets):
        return bound
    return None


def trial_screens(scene: Scene, mass: MassProperties) -> tuple[Screen, Screen]:
    """First tests of an analytical check's way-out trials, for :func:`passing_friction` and
    :func:`passing_closing_force`: False only where a case of the trial does not close at the
    design direction (or is undetermined, ill-conditioned), which fails the check whatever
    else is found — so the check's ``passes`` must reject such a trial too.

    The friction scan's trials: the cases' algebra of them all in one batch
    (:func:`kcheck.analysis.cases.cases_close_many`). The closing force's trials: first the
    trial's factor on the scene's closing force in closed form
    (:func:`kcheck.analysis.cases.closing_force_screen`, built on first use: most scenes
    never search), then for a scan's several trials the same batch; one trial alone is left
    to ``passes``. Scenes whose coefficients are ranges are not screened."""
    from kcheck.analysis.cases import cases_close_many, closing_force_screen

    def batch(trials: Sequence[Scene]) -> list[bool]:
        fixed = [np.array_equal(*s.friction_range("kinetic")) for s in trials]
        kept = [s for s, f in zip(trials, fixed, strict=True) if f]
        tested = iter(cases_close_many(kept, [mass] * len(kept)))
        return [next(tested) if f else True for f in fixed]

    force = closing_force(scene)
    built: list[Callable[[float], bool] | None] = []

    def forces(trials: Sequence[Scene]) -> list[bool]:
        if not built:
            usable = force is not None and np.array_equal(*scene.friction_range("kinetic"))
            quick = None
            if usable and force is not None:
                quick = closing_force_screen(scene, mass, force.kind == "preload")
            built.append(quick)
        quick = built[0]
        out = [True] * len(trials)
        if quick is not None and force is not None:
            for i, trial in enumerate(trials):
                now = closing_force(trial)
                out[i] = now is None or quick(now.value / force.value)
        if len(trials) > 1:
            left = [i for i, ok in enumerate(out) if ok]
            for i, ok in zip(left, batch([trials[i] for i in left]), strict=True):
                out[i] = ok
        return out

    return batch, forces
