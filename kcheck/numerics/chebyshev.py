"""Polynomials on [-1, 1] as Chebyshev series, many at once: values, interpolation, real roots
and positivity, with numpy alone.

A stack of series is an array (..., d + 1) of coefficients, lowest degree first (numpy's
``chebval`` convention). Roots are the eigenvalues of the scaled companion matrix (numpy's
``chebcompanion``), batched over series of the same degree and polished by Newton steps.
"""

from __future__ import annotations

import functools

import numpy as np

from kcheck.numerics.thresholds import DEGREE_RTOL, IMAG_TOL, ROOT_SLACK_RTOL

__all__ = [
    "lobatto",
    "interpolate",
    "values",
    "derivative",
    "product",
    "roots",
    "real_roots",
    "positive",
    "abs_bound",
]


def lobatto(count: int) -> np.ndarray:
    """Chebyshev–Lobatto points ``cos(pi j / (count - 1))`` on [-1, 1], ascending; they include
    both ends and interpolate well."""
    return -np.cos(np.pi * np.arange(count) / (count - 1))


def interpolate(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Coefficients (..., m) of the series through ``y`` (m, ...) at the m points ``x``: the
    trailing axes of ``y`` become leading axes of the result."""
    # numpy.polynomial costs ~8 ms to import: only scenes with friction ranges need it
    from numpy.polynomial import chebyshev as cheb

    m = len(x)
    flat = y.reshape(m, -1)
    coefs = np.linalg.solve(cheb.chebvander(x, m - 1), flat)  # (m, p)
    return np.moveaxis(coefs.reshape((m,) + y.shape[1:]), 0, -1)


def values(coefs: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Values of a stack of series (..., d + 1) at points ``x`` (m,): (..., m)."""
    from numpy.polynomial import chebyshev as cheb

    return coefs @ cheb.chebvander(np.asarray(x, float), coefs.shape[-1] - 1).T


def derivative(coefs: np.ndarray) -> np.ndarray:
    """Derivatives (..., d + 1) of a stack of series (the top coefficient becomes 0)."""
    from numpy.polynomial import chebyshev as cheb

    flat = coefs.reshape(-1, coefs.shape[-1])
    out = np.zeros_like(flat)
    if flat.shape[1] > 1:
        out[:, :-1] = cheb.chebder(flat.T).T
    return out.reshape(coefs.shape)


@functools.cache
def _product_map(d: int, e: int) -> np.ndarray:
    """(d e, d + e - 1): where each product of basis terms goes, ``T_i T_j = (T_{i+j} +
    T_{|i-j|}) / 2``."""
    out = np.zeros((d * e, d + e - 1))
    for i in range(d):
        for j in range(e):
            out[i * e + j, i + j] += 0.5
            out[i * e + j, abs(i - j)] += 0.5
    return out


def product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Products of two stacks of series (..., d + 1) and (..., e + 1): (..., d + e + 1)."""
    outer = a[..., :, None] * b[..., None, :]
    d, e = outer.shape[-2:]
    return outer.reshape(outer.shape[:-2] + (d * e,)) @ _product_map(d, e)


def _companion(coefs: np.ndarray) -> np.ndarray:
    """Scaled companion matrices (p, d, d) of series (p, d + 1) of exact degree d >= 2."""
    p, d = coefs.shape[0], coefs.shape[1] - 1
    base = np.zeros((d, d))
    off = np.full(d - 1, 0.5)
    off[0] = np.sqrt(0.5)
    base[np.arange(d - 1), np.arange(1, d)] = off
    base[np.arange(1, d), np.arange(d - 1)] = off
    scl = np.array([1.0] + [np.sqrt(0.5)] * (d - 1))
    mats = np.repeat(base[None], p, axis=0)
    mats[:, :, -1] -= (coefs[:, :-1] / coefs[:, -1:]) * (scl / scl[-1]) * 0.5
    return mats


def roots(coefs: np.ndarray) -> np.ndarray:
    """Every root (complex) of a stack of series (p, d + 1): (p, d), NaN-padded where the
    degree is lower (a series that is zero everywhere has none)."""
    coefs = np.atleast_2d(np.asarray(coefs, float))
    p, size = coefs.shape
    out = np.full((p, max(size - 1, 1)), np.nan, dtype=complex)
    scale = np.abs(coefs).max(axis=1)
    live = np.abs(coefs) > DEGREE_RTOL * np.where(scale > 0, scale, 1.0)[:, None]
    degree = np.where(live.any(axis=1), size - 1 - np.argmax(live[:, ::-1], axis=1), 0)
    for d in np.unique(degree):
        rows = np.flatnonzero(degree == d)
        if d == 0:
            continue
        c = coefs[rows, : d + 1]
        if d == 1:
            out[rows, :1] = -c[:, :1] / c[:, 1:]
        else:
            with np.errstate(all="ignore"):
                out[rows, :d] = np.linalg.eigvals(_companion(c))
    return out


def real_roots(
    coefs: np.ndarray, lo: float = -1.0, hi: float = 1.0, imag_tol: float = IMAG_TOL
) -> np.ndarray:
    """Real roots in [lo, hi] of a stack of series (p, d + 1): (p, d), sorted, NaN-padded.

    Roots whose imaginary part is below ``imag_tol`` (relative) count as real: a double root
    split by rounding into a complex pair is kept (a loose tolerance only adds candidates).
    """
    coefs = np.atleast_2d(np.asarray(coefs, float))
    found = roots(coefs)
    real = np.abs(found.imag) <= imag_tol * (1.0 + np.abs(found.real))
    x = np.where(real, found.real, np.nan)
    x = _polish(coefs, x)
    slack = ROOT_SLACK_RTOL * (hi - lo)
    x = np.where((x >= lo - slack) & (x <= hi + slack), np.clip(x, lo, hi), np.nan)
    return np.sort(x, axis=1)


def _polish(coefs: np.ndarray, x: np.ndarray, steps: int = 2) -> np.ndarray:
    """Newton steps on roots ``x`` (p, r) of series (p, d + 1); a step that does not reduce
    the residual is not taken."""
    from numpy.polynomial import chebyshev as cheb

    der = derivative(coefs)
    for _ in range(steps):
        # A root far outside [-1, 1] (1e12, of a series whose high terms are negligible)
        # overflows the full-degree Vandermonde matrix; it is dropped by the caller anyway,
        # and a step that gives no finite, smaller residual is not taken.
        with np.errstate(all="ignore"):
            vander = cheb.chebvander(np.nan_to_num(x), coefs.shape[1] - 1)  # (p, r, d + 1)
            f = np.einsum("prd,pd->pr", vander, coefs)
            g = np.einsum("prd,pd->pr", vander, der)
            step = np.where(g != 0, f / g, 0.0)
            new = x - step
            v2 = cheb.chebvander(np.nan_to_num(new), coefs.shape[1] - 1)
            f2 = np.einsum("prd,pd->pr", v2, coefs)
            x = np.where(np.abs(f2) < np.abs(f), new, x)
    return x


def positive(coefs: np.ndarray, lo: float = -1.0, hi: float = 1.0) -> np.ndarray:
    """Whether each series of a stack (..., d + 1) is positive on all of [lo, hi] (a root where
    it only touches zero counts as positive: a single point)."""
    from numpy.polynomial import chebyshev as cheb

    shape = coefs.shape[:-1]
    flat = coefs.reshape(-1, coefs.shape[-1])
    roots = real_roots(flat, lo, hi)
    edges = np.concatenate([np.full((len(flat), 1), lo), roots, np.full((len(flat), 1), hi)], 1)
    edges = np.sort(np.where(np.isnan(edges), hi, edges), axis=1)
    probes = np.concatenate([edges, 0.5 * (edges[:, 1:] + edges[:, :-1])], axis=1)
    vander = cheb.chebvander(probes, flat.shape[1] - 1)  # (p, q, d + 1)
    at = np.einsum("pqd,pd->pq", vander, flat)
    # The ends and the roots themselves are probes: only their neighbourhoods must be > 0.
    inner = at[:, edges.shape[1] :]
    ok = np.all(inner > 0, axis=1) & (at[:, 0] >= 0) & (at[:, edges.shape[1] - 1] >= 0)
    return ok.reshape(shape)


def abs_bound(coefs: np.ndarray) -> np.ndarray:
    """An upper bound of ``|p(x)|`` on [-1, 1] for a stack of series: the sum of the absolute
    coefficients (``|T_k| <= 1`` there)."""
    return np.abs(coefs).sum(axis=-1)
