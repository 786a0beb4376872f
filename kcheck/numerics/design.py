"""Designs of experiments: points of the unit hypercube, and their map to parameter values.

A study's variants are the rows of ``unit_points`` (full grid, Latin hypercube, Sobol or
plain Monte Carlo, each reproducible from its seed) mapped through each parameter's
distribution by its quantile function (``quantiles``). scipy is imported only for the
sampled designs and the normal quantiles.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["DESIGNS", "grid_indices", "unit_points", "quantiles"]

#: The designs a study may ask for.
DESIGNS = ("grid", "latin-hypercube", "sobol", "monte-carlo")


def grid_indices(counts: Sequence[int]) -> np.ndarray:
    """Every combination of level indices, the last parameter varying fastest: (n, d) ints."""
    rows = list(itertools.product(*(range(c) for c in counts)))
    return np.array(rows, dtype=np.int64).reshape(len(rows), len(counts))


def _qmc_engine(cls: Any, d: int, seed: int) -> Any:
    """A scipy.stats.qmc engine seeded by ``seed`` (``rng`` from scipy 1.15, ``seed`` before)."""
    try:
        return cls(d, rng=np.random.default_rng(seed))
    except TypeError:
        return cls(d, seed=np.random.default_rng(seed))


def unit_points(design: str, n: int, d: int, seed: int) -> np.ndarray:
    """``n`` points of ``[0, 1)^d`` of a sampled design (not ``grid``), reproducible from
    ``seed``: (n, d) floats."""
    if design == "monte-carlo":
        return np.random.default_rng(seed).random((n, d))
    from scipy.stats import qmc

    if design == "latin-hypercube":
        return np.asarray(_qmc_engine(qmc.LatinHypercube, d, seed).random(n))
    if design == "sobol":
        import warnings

        with warnings.catch_warnings():  # n need not be a power of 2: the balance is a nicety
            warnings.simplefilter("ignore", UserWarning)
            return np.asarray(_qmc_engine(qmc.Sobol, d, seed).random(n))
    raise ValueError(f"unknown design {design!r}")


def quantiles(kind: str, u: np.ndarray, p: dict[str, float]) -> np.ndarray:
    """Values at probabilities ``u`` of a ``uniform`` (``min``, ``max``), ``normal``
    (``mean``, ``sd``) or ``truncated-normal`` (``mean``, ``sd``, ``min``, ``max``)
    distribution."""
    if kind == "uniform":
        return p["min"] + u * (p["max"] - p["min"])
    from scipy import stats

    if kind == "normal":
        return np.asarray(stats.norm.ppf(u, loc=p["mean"], scale=p["sd"]))
    if kind == "truncated-normal":
        a = (p["min"] - p["mean"]) / p["sd"]
        b = (p["max"] - p["mean"]) / p["sd"]
        return np.asarray(stats.truncnorm.ppf(u, a, b, loc=p["mean"], scale=p["sd"]))
    raise ValueError(f"unknown distribution {kind!r}")
