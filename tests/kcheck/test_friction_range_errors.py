"""Friction intervals say how sure they are (issue 21, item 14): every end of a failing
interval carries an error bound, and an interval whose bound is as wide as itself, or a
sliver rounding may hide, is reported as unresolved — never as closing or failing.

The systems are built to be thin and nearly singular: ``M(t) = V D(t) W`` with
``D(t) = diag(1, [[t - t0, h], [±h, t - t0]])`` (so ``det D = (t - t0)^2 ∓ h^2``: a failing
sliver of width ``2 h``, or a near miss that closes with a minimum of ``h^2``) mixed by
random matrices ``V`` and ``W``, one of them nearly singular (condition ``kappa``). The
series, their error bounds and the intervals come from kcheck (as ``range_cases`` builds
them: determinants at the Chebyshev–Lobatto nodes, :func:`determinant_error`, the
Lebesgue constant); the reference is written here: the determinant of the same float
matrices ``A + t B`` in 50-digit arithmetic (mpmath), its sign and its roots by bisection.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

from kcheck.analysis.friction_ranges import bounded_intervals
from kcheck.mechanics.friction_range import RangeCase, determinant_error
from kcheck.numerics import chebyshev as cheb

T0 = 0.2034738  # where issue 21 found a missed failing sliver


def _system(h: float, sign: int, kappa: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Float matrices ``A``, ``B`` with ``M(t) = A + t B = V D(t) W``."""
    rng = np.random.default_rng(seed)
    u, _, vt = np.linalg.svd(rng.standard_normal((3, 3)))
    v = u @ np.diag([1.0, 1.0, 1.0 / kappa]) @ vt  # nearly singular for a large kappa
    w = np.linalg.qr(rng.standard_normal((3, 3)))[0]
    d0 = np.array([[1.0, 0, 0], [0, -T0, h], [0, sign * h, -T0]])
    d1 = np.array([[0.0, 0, 0], [0, 1, 0], [0, 0, 1]])
    return v @ d0 @ w, v @ d1 @ w


def _range_case(a: np.ndarray, b: np.ndarray) -> RangeCase:
    """The case kcheck builds: one condition, ``det M(t) / det M(t_mid)``, as a series."""
    x = cheb.lobatto(a.shape[0] + 2)
    t = 0.5 * (x + 1.0)
    stack = a[None] + t[:, None, None] * b[None]
    _, log0 = np.linalg.slogdet(a + 0.5 * b)
    sign, logdet = np.linalg.slogdet(stack)
    values = sign * np.exp(logdet - log0)
    lebesgue = 2.0 / np.pi * np.log(len(x)) + 1.0
    error = lebesgue * determinant_error(stack, np.full(len(x), log0)).max()
    one = np.zeros(len(x))
    one[0] = 1.0
    return RangeCase(
        index=0,
        effective=np.stack([one, one]),
        numerators=cheb.interpolate(x, values)[None, None],
        trusted=True,
        effective_error=np.zeros(2),
        numerator_error=np.array([[error]]),
    )


def _reference(a: np.ndarray, b: np.ndarray) -> list[tuple[float, float]]:
    """Where ``det(A + t B) < 0`` on [0, 1], in 50 digits: its roots near T0 by bisection
    of the exact polynomial of the float matrices."""
    mpmath.mp.dps = 50
    am, bm = mpmath.matrix(a.tolist()), mpmath.matrix(b.tolist())

    def det(t: mpmath.mpf) -> mpmath.mpf:
        return mpmath.det(am + t * bm)

    # det is a cubic in t: its values at 4 points give it exactly; roots by mpmath.
    ts = [mpmath.mpf(k) / 3 for k in range(4)]
    vander = mpmath.matrix([[t**j for j in range(4)] for t in ts])
    coefs = vander**-1 * mpmath.matrix([det(t) for t in ts])  # lowest degree first
    roots = sorted(
        float(mpmath.re(r))
        for r in mpmath.polyroots(list(coefs), maxsteps=200, extraprec=200, asc=True)
        if abs(mpmath.im(r)) < mpmath.mpf(10) ** -40 and 0 <= mpmath.re(r) <= 1
    )
    edges = [0.0, *roots, 1.0]
    return [
        (lo, hi)
        for lo, hi in zip(edges[:-1], edges[1:], strict=True)
        if hi > lo and det(mpmath.mpf((lo + hi) / 2)) < 0
    ]


CASES = [
    (h, sign, kappa, seed)
    for h in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 3e-9)
    for sign in (1, -1)
    for kappa in (1.0, 1e4)
    for seed in (1, 2)
]


@pytest.mark.parametrize(("h", "sign", "kappa", "seed"), CASES)
def test_thin_intervals_against_50_digits(h, sign, kappa, seed):
    a, b = _system(h, sign, kappa, seed)
    truth = _reference(a, b)
    found = bounded_intervals(_range_case(a, b), None)
    for lo, hi, elo, ehi in found.failing:
        # A resolved interval: its ends within their bounds of the truth, the bounds narrow.
        assert elo + ehi < hi - lo
        match = [(x, y) for x, y in truth if x - elo <= lo <= x + elo and y - ehi <= hi <= y + ehi]
        assert match, (found, truth)
    for x, y in truth:
        # Every true failing interval is reported: failing, or unresolved around it.
        failing = any(lo - elo <= x and y <= hi + ehi for lo, hi, elo, ehi in found.failing)
        unresolved = any(
            lo - elo <= x and y <= hi + ehi for lo, hi, elo, ehi, _ in found.unresolved
        )
        assert failing or unresolved, (found, truth)
    if not truth:
        assert not found.failing  # a near miss is never reported failing
    for *_, condition in found.unresolved:
        assert condition > 0


def test_wide_intervals_are_resolved_and_slivers_are_not():
    """The classification itself: a well-conditioned 2e-4 wide interval is resolved with
    error bounds far below its width; a 6e-9 wide one in a nearly singular system, whose
    ends rounding moves by about its width, is unresolved, as is a near miss of 1e-17."""
    wide = bounded_intervals(_range_case(*_system(1e-4, 1, 1.0, 1)), None)
    assert len(wide.failing) == 1 and not wide.unresolved
    lo, hi, elo, ehi = wide.failing[0]
    assert max(elo, ehi) < 1e-6 * (hi - lo)
    thin = bounded_intervals(_range_case(*_system(3e-9, 1, 1e4, 1)), None)
    assert not thin.failing and thin.unresolved
    miss = bounded_intervals(_range_case(*_system(3e-9, -1, 1e4, 1)), None)
    assert not miss.failing and miss.unresolved


# --- one coefficient: the ends of a case's friction intervals --------------------------------


@pytest.mark.parametrize("fixture", ["planar-block", "thesis-appendix-a", "three-groove-beta-55"])
def test_friction_interval_ends_within_their_bounds_of_50_digits(fixture):
    """Each finite end of every case's friction intervals is a root of one of the case's
    pencils ``det(K0 + μ F)`` (``K`` itself, or with a column replaced by the load): found
    again here in 50 digits (mpmath.findroot from the reported end, on the same float
    matrices), it lies within the reported error bound."""
    from kcheck.analysis import analyse
    from kcheck.body.mass import body_mass_properties
    from kcheck.mechanics.friction import friction_intervals
    from kcheck.scene import load_scene
    from tests.conftest import FIXTURES

    scene = load_scene(next((FIXTURES / fixture).glob("*.kcheck.yaml")))
    analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))
    problem, design = analysis.problem, analysis.design
    mpmath.mp.dps = 50
    checked = 0
    for case in analysis.cases:
        if not case.determined or case.k0 is None:
            continue
        found = friction_intervals(problem, case, design)
        assert len(found.errors) == len(found.intervals)
        k0 = mpmath.matrix(case.k0.tolist())
        big_f = mpmath.matrix(case.k_friction.tolist())
        rhs = problem.wrench(design)
        n = case.k0.shape[0]

        def pencil(j: int, sign: int, k0=k0, big_f=big_f, rhs=rhs, n=n):
            def det(mu):
                m = k0 + sign * mu * big_f
                if j > 0:
                    for i in range(n):
                        m[i, j - 1] = mpmath.mpf(float(rhs[i]))
                return mpmath.det(m)

            return det

        for (lo, hi), (elo, ehi) in zip(found.intervals, found.errors, strict=True):
            for end, err in ((lo, elo), (hi, ehi)):
                if end <= 0 or not np.isfinite(end):
                    continue
                best = None
                for j in range(n + 1):
                    for sign in (1, -1):
                        try:
                            root = mpmath.findroot(pencil(j, sign), mpmath.mpf(end), tol=1e-40)
                        except (ValueError, ZeroDivisionError):
                            continue
                        gap = abs(float(root) - end)
                        best = gap if best is None else min(best, gap)
                assert best is not None and best <= err, (fixture, case, end, best, err)
                checked += 1
    assert checked > 0


def test_an_unresolved_case_is_neither_closing_nor_failing(write_scene, cli_json, monkeypatch):
    """Wiring: a case whose only failing sliver is unresolved gets no verdict of its own (no
    trustworthy answer, the unresolved interval named), `closes_throughout` null."""
    import kcheck.analysis.friction_ranges as ranges
    from tests.conftest import PLANAR_SCENE

    real = ranges.bounded_intervals

    def with_a_sliver(rc, direction):
        found = real(rc, direction)
        if rc.index != 0:
            return found
        return ranges.Bounded((), ((0.4, 0.4 + 6e-9, 4e-9, 4e-9, 3e7),))

    monkeypatch.setattr(ranges, "bounded_intervals", with_a_sliver)
    scene = write_scene(PLANAR_SCENE.replace("friction: 0.1", "friction: {min: 0.05, max: 0.15}"))
    _, doc = cli_json(str(scene), "--select", "analytical-2d", "--no-cache", "-j", "1")
    (check,) = doc["scenes"][0]["checks"]
    first = check["cases"][0]
    assert first["outcome"] == "ill_conditioned" and "unresolved near μ 0.09" in first["diagnostic"]
    assert first["friction_range"]["closes_throughout"] is None
    (sliver,) = first["friction_range"]["unresolved"]
    assert sliver["mu"][0] == pytest.approx(0.05 + 0.4 * 0.1) and sliver["condition"] == 3e7
    assert check["friction_range"]["unresolved_cases"] == [first["retracted"]]
    assert check["status"] == "fail" and "no trustworthy answer" in check["message"]
