"""Confidence bounds of a proportion estimated by Monte Carlo, without scipy.

Clopper–Pearson (exact binomial) interval: with ``x`` successes in ``n`` trials the bounds at
confidence ``1 - alpha`` are quantiles of beta distributions, ``B(alpha/2; x, n - x + 1)``
and ``B(1 - alpha/2; x + 1, n - x)``. The regularised incomplete beta function is evaluated
by its continued fraction (modified Lentz; Numerical Recipes §6.4) and inverted by bisection.
"""

from __future__ import annotations

import math

from kcheck.numerics.thresholds import LENTZ_RTOL, QUANTILE_ATOL, ZERO_GUARD

__all__ = ["incomplete_beta", "beta_quantile", "clopper_pearson"]


def _continued_fraction(a: float, b: float, x: float) -> float:
    """The continued fraction of ``I_x(a, b)`` (converges for ``x < (a + 1) / (a + b + 2)``)."""
    c, d = 1.0, 1.0 - (a + b) * x / (a + 1.0)
    d = 1.0 / (d if abs(d) > ZERO_GUARD else ZERO_GUARD)
    h = d
    for m in range(1, 10_000):
        m2 = 2 * m
        for num in (
            m * (b - m) * x / ((a + m2 - 1.0) * (a + m2)),
            -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0)),
        ):
            d = 1.0 + num * d
            d = 1.0 / (d if abs(d) > ZERO_GUARD else ZERO_GUARD)
            c = 1.0 + num / c
            c = c if abs(c) > ZERO_GUARD else ZERO_GUARD
            h *= d * c
        if abs(d * c - 1.0) < LENTZ_RTOL:
            break
    return h


def incomplete_beta(a: float, b: float, x: float) -> float:
    """The regularised incomplete beta function ``I_x(a, b)`` for ``a, b > 0``."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    log_front = (
        math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x)
    )
    front = math.exp(log_front)
    if x < (a + 1.0) / (a + b + 2.0):
        return front * _continued_fraction(a, b, x) / a
    return 1.0 - front * _continued_fraction(b, a, 1.0 - x) / b


def beta_quantile(p: float, a: float, b: float) -> float:
    """The ``x`` with ``I_x(a, b) = p`` (bisection to 1e-13)."""
    lo, hi = 0.0, 1.0
    while hi - lo > QUANTILE_ATOL:
        mid = 0.5 * (lo + hi)
        if incomplete_beta(a, b, mid) < p:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def clopper_pearson(successes: int, trials: int, confidence: float = 0.95) -> tuple[float, float]:
    """Two-sided Clopper–Pearson bounds of a proportion: ``(low, high)``."""
    if trials <= 0:
        return 0.0, 1.0
    alpha = 1.0 - confidence
    x, n = successes, trials
    low = 0.0 if x == 0 else beta_quantile(alpha / 2.0, x, n - x + 1)
    high = 1.0 if x == n else beta_quantile(1.0 - alpha / 2.0, x + 1, n - x)
    return low, high
