"""The closing force's bisection stops once its rounded answer is settled
(:func:`kcheck.analysis.way_out.passing_closing_force`): the same answer as the full bisection
for any verdict, monotone or not, checked against a copy of the full bisection written here."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from kcheck.analysis import way_out
from kcheck.fmt import rounded_bound


@dataclasses.dataclass(frozen=True)
class _Load:
    magnitude: float


@dataclasses.dataclass(frozen=True)
class _Scene:
    load: _Load


def _full_bisection(base: float, passes) -> tuple[float, str] | None:
    """passing_closing_force's search before the early stop: every step, then the rounding."""
    for sense, sign in (("at least", 1), ("at most", -1)):
        fails = base
        for k in range(1, way_out.FORCE_OCTAVES + 1):
            value = base * 2.0 ** (sign * k)
            if passes(value):
                good = value
                break
            fails = value
        else:
            continue
        for _ in range(way_out.FORCE_BISECTIONS):
            middle = math.sqrt(good * fails)
            if passes(middle):
                good = middle
            else:
                fails = middle
        for candidate in (rounded_bound(good, 3, up=sign > 0), good):
            if candidate > 0 and passes(candidate):
                return candidate, sense
    return None


def _verdicts(rng: np.random.Generator):
    """A threshold verdict, sometimes with a few random flips (not monotone) near it."""
    threshold = float(np.exp(rng.uniform(-3, 8)))
    noisy = rng.random() < 0.5
    flips: dict[float, bool] = {}

    def passes(value: float) -> bool:
        above = value >= threshold
        if noisy and abs(math.log(value / threshold)) < 0.01:
            return flips.setdefault(value, bool(rng.random() < 0.5))
        return above

    return passes


@pytest.mark.parametrize("seed", range(40))
def test_early_stop_gives_the_full_bisections_answer(monkeypatch, seed: int) -> None:
    rng = np.random.default_rng(seed)
    base = float(np.exp(rng.uniform(-2, 6)))
    for _ in range(25):
        passes = _verdicts(rng)
        memo: dict[float, bool] = {}

        def judged(value: float, passes=passes, memo=memo) -> bool:
            return memo.setdefault(value, passes(value))

        expected = _full_bisection(base, judged)
        monkeypatch.setattr(
            way_out,
            "closing_force",
            lambda scene: way_out.ClosingForce("load", "load", base, False),
        )
        monkeypatch.setattr(
            way_out,
            "with_closing_force",
            lambda scene, force, value: _Scene(_Load(value)),
        )
        found = way_out.passing_closing_force(
            _Scene(_Load(base)),  # type: ignore[arg-type]
            lambda trial: judged(trial.load.magnitude),
        )
        assert (None if found is None else found[1:]) == expected


def test_settled_bound_is_every_ending_s_rounding() -> None:
    """Each path of the remaining steps (enumerated here independently) rounds to the bound."""
    rng = np.random.default_rng(7)
    settled = 0
    for _ in range(300):
        fails = float(np.exp(rng.uniform(-5, 5)))
        good = fails * float(np.exp(rng.uniform(1e-6, 0.003)))
        steps = int(rng.integers(1, way_out.SETTLE_STEPS + 1))
        up = bool(rng.random() < 0.5)
        found = way_out._settled_bound(good, fails, steps, up)
        endings = set()
        for path in range(2**steps):
            g, f = good, fails
            for bit in range(steps):
                middle = math.sqrt(g * f)
                g, f = (middle, f) if path >> bit & 1 else (g, middle)
            endings.add(rounded_bound(g, 3, up=up))
        assert (found is not None) == (len(endings) == 1)
        if found is not None:
            settled += 1
            assert endings == {found}
    assert settled > 30  # the test covers the settled case too
