"""Hertz contact against textbook closed forms, tables and an independent computation.

References:

* Johnson, K. L., *Contact Mechanics*, Cambridge University Press 1985, §4.1 (curvature sums of
  two surfaces with crossed principal planes) and §4.2 (Hertz theory: a sphere on a flat,
  ``a = (3PR/4E*)^(1/3)``, ``p0 = 3P/(2 pi a^2)``, ``delta = a^2/R``).
* Puttock, M. J. and Thwaite, E. G., *Elastic Compression of Spheres and Cylinders at Point and
  Line Contact*, CSIRO National Standards Laboratory Technical Paper 25, 1969: case 5, equal
  cylinders crossed at right angles behave as a sphere of the same radius on a flat.
* Hamrock, B. J. and Brewe, D. E., "Simplified solution for stresses and deformations",
  J. Lubr. Technol. 105 (1983) 171-177: curve fits of ``a/b``, ``K`` and ``E`` against ``B/A``
  good to a few per cent (an independent, approximate check of the ellipse's shape).
* The elliptical cases are also solved independently from Johnson's equations with mpmath
  (its own elliptic integrals and root finder, 30 digits).
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
from scipy.special import ellipe, ellipk

from kcheck.mechanics.hertz import (
    contact_modulus,
    curvature_sums,
    curvature_sums_crossed,
    curvature_tensor,
    ellipse_ratio,
    elliptic_integrals,
    hertz,
)

STEEL = contact_modulus(210e9, 0.3, 210e9, 0.3)


def _sphere_on_flat(force: float, radius: float, modulus: float) -> tuple[float, float, float]:
    """Johnson §4.2: contact radius, peak pressure and approach of a sphere on a flat."""
    a = (3 * force * radius / (4 * modulus)) ** (1 / 3)
    return a, 3 * force / (2 * np.pi * a * a), a * a / radius


def _mp_hertz(force: float, sum_a: float, sum_b: float, modulus: float) -> tuple[float, ...]:
    """Johnson's elliptical equations solved with mpmath: (a, b, p0, delta)."""
    mp.mp.dps = 30
    ratio = mp.mpf(sum_b) / mp.mpf(sum_a)

    def f(k: mp.mpf) -> mp.mpf:
        m = 1 - k**2
        kk, ee = mp.ellipk(m), mp.ellipe(m)
        return (ee / k**2 - kk) / (kk - ee) - ratio

    k = mp.findroot(f, (mp.mpf("1e-6"), mp.mpf(1) - mp.mpf("1e-12")), solver="anderson")
    m = 1 - k**2
    kk, ee = mp.ellipk(m), mp.ellipe(m)
    # A = p0 b (K - E) / (E* e^2 a^2) with p0 = 3P / (2 pi a b):
    a = mp.cbrt(3 * force * (kk - ee) / (2 * mp.pi * modulus * m * sum_a))
    b = k * a
    p0 = 3 * force / (2 * mp.pi * a * b)
    delta = p0 * b * kk / modulus
    return float(a), float(b), float(p0), float(delta)


def test_elliptic_integrals_match_mpmath_to_rounding():
    mp.mp.dps = 40
    kp = np.array([1.0, 1 - 1e-9, 0.999999, 0.9, 0.5, 0.1, 1e-3, 1e-8])
    big_k, big_e = elliptic_integrals(kp)
    for k, got_k, got_e in zip(kp, big_k, big_e, strict=True):
        m = 1 - mp.mpf(k) ** 2
        assert got_k == pytest.approx(float(mp.ellipk(m)), rel=4e-16)
        assert got_e == pytest.approx(float(mp.ellipe(m)), rel=4e-15)
    # and scipy's, where its argument m = 1 - k'^2 is still exact in floating point
    m = 1 - kp[3:6] ** 2
    np.testing.assert_allclose(big_k[3:6], ellipk(m), rtol=1e-15)
    np.testing.assert_allclose(big_e[3:6], ellipe(m), rtol=1e-15)


@pytest.mark.parametrize("kp", [1 - 1e-9, 0.999999, 0.9, 0.5, 0.1, 1e-3, 1e-6])
def test_ellipse_ratio_inverts_the_elliptic_equation(kp):
    mp.mp.dps = 40
    k = mp.mpf(kp)
    kk, ee = mp.ellipk(1 - k**2), mp.ellipe(1 - k**2)
    ratio = float((ee / k**2 - kk) / (kk - ee))
    assert ellipse_ratio(ratio) == pytest.approx(kp, rel=1e-13)


def test_ellipse_ratio_of_a_circle_is_one():
    assert ellipse_ratio(1.0) == 1.0
    np.testing.assert_array_equal(ellipse_ratio(np.array([1.0, 1.0])), [1.0, 1.0])
    with pytest.raises(ValueError, match="B/A >= 1"):
        ellipse_ratio(0.5)


@pytest.mark.parametrize("radius", [1e-3, 6e-3, 0.5])
@pytest.mark.parametrize("force", [0.1, 100.0, 15000.0])
def test_sphere_on_flat_closed_form(radius, force):
    c = hertz(force, 0.5 / radius, 0.5 / radius, STEEL)
    a, p0, delta = _sphere_on_flat(force, radius, STEEL)
    assert c.a == pytest.approx(a, rel=1e-14) and c.b == pytest.approx(a, rel=1e-14)
    assert c.max_pressure == pytest.approx(p0, rel=1e-14)
    assert c.approach == pytest.approx(delta, rel=1e-14)
    # dP/d delta of P = 4/3 E* R^(1/2) delta^(3/2) is 2 E* a (Johnson §4.2).
    assert c.stiffness == pytest.approx(2 * STEEL * a, rel=1e-14)
    assert c.mean_pressure == pytest.approx(2 / 3 * p0, rel=1e-14)


def test_two_spheres_and_a_ball_in_a_socket():
    # Johnson §4.2: two spheres act as one of radius R1 R2 / (R1 + R2) on a flat; a concave
    # socket (negative radius) the same with 1/R = 1/R1 - 1/|R2|.
    for r1, r2 in ((5e-3, 8e-3), (5e-3, -6e-3)):
        tensor = curvature_tensor(np.array([r1, r1]), None, np.array([0.0, 0.0, 1.0]))
        tensor = tensor + curvature_tensor(np.array([r2, r2]), None, np.array([0.0, 0.0, 1.0]))
        sum_a, sum_b, _ = curvature_sums(tensor, np.array([0.0, 0.0, 1.0]))
        equivalent = 1 / (1 / r1 + 1 / r2)
        c = hertz(50.0, sum_a, sum_b, STEEL)
        a, p0, delta = _sphere_on_flat(50.0, equivalent, STEEL)
        assert (c.a, c.max_pressure, c.approach) == pytest.approx((a, p0, delta), rel=1e-13)


def test_equal_crossed_cylinders_are_a_sphere_on_a_flat():
    # Puttock & Thwaite case 5; Johnson §4.1: A = B = 1/(2R) at 90 deg.
    r = 4e-3
    sum_a, sum_b = curvature_sums_crossed((r, np.inf), (r, np.inf), np.pi / 2)
    assert sum_a == pytest.approx(0.5 / r, rel=1e-15) and sum_b == pytest.approx(0.5 / r)
    c = hertz(200.0, sum_a, sum_b, STEEL)
    assert (c.a, c.max_pressure, c.approach) == pytest.approx(
        _sphere_on_flat(200.0, r, STEEL), rel=1e-13
    )


def test_tensor_sums_equal_johnsons_closed_form_at_any_angle():
    n = np.array([0.0, 0.0, 1.0])
    for psi in np.radians([0.0, 20.0, 45.0, 70.0, 90.0, 133.0]):
        body1, body2 = (3e-3, 7e-3), (-9e-3, np.inf)
        t1 = curvature_tensor(np.array(body1), np.array([1.0, 0.0, 0.0]), n)
        t2 = curvature_tensor(np.array(body2), np.array([np.cos(psi), np.sin(psi), 0.0]), n)
        sum_a, sum_b, _ = curvature_sums(t1 + t2, n)
        expected = curvature_sums_crossed(body1, body2, psi)
        assert (sum_a, sum_b) == pytest.approx(expected, rel=1e-13)


@pytest.mark.parametrize(
    ("body1", "body2", "angle_deg"),
    [
        ((5e-3, 5e-3), (np.inf, -5.2e-3), 0.0),  # ball in a conformal groove (f = 0.52)
        ((6.35e-3, 6.35e-3), (np.inf, -6.6e-3), 0.0),  # Harris-type raceway conformity
        ((4e-3, np.inf), (9e-3, np.inf), 90.0),  # unequal cylinders crossed at 90 deg
        ((4e-3, np.inf), (4e-3, np.inf), 30.0),  # equal cylinders crossed at 30 deg
        ((2e-3, 10e-3), (np.inf, np.inf), 0.0),  # a barrel (canoe) on a flat
    ],
)
def test_elliptical_contacts_against_mpmath(body1, body2, angle_deg):
    sum_a, sum_b = curvature_sums_crossed(body1, body2, np.radians(angle_deg))
    c = hertz(300.0, sum_a, sum_b, STEEL)
    a, b, p0, delta = _mp_hertz(300.0, sum_a, sum_b, STEEL)
    assert float(c.a) == pytest.approx(a, rel=1e-10)
    assert float(c.b) == pytest.approx(b, rel=1e-10)
    assert float(c.max_pressure) == pytest.approx(p0, rel=1e-10)
    assert float(c.approach) == pytest.approx(delta, rel=1e-10)
    # the tangent stiffness is the derivative of the force-approach law (P ~ delta^(3/2))
    h = 1e-4
    up, down = (
        hertz(300.0 * (1 + h), sum_a, sum_b, STEEL),
        hertz(300.0 * (1 - h), sum_a, sum_b, STEEL),
    )
    slope = 2 * h * 300.0 / float(up.approach - down.approach)
    assert float(c.stiffness) == pytest.approx(slope, rel=1e-7)


def test_hamrock_brewe_estimates_within_their_accuracy():
    # Hamrock & Brewe (1983): a/b ~ 1.0339 (B/A)^0.636, K ~ 1.5277 + 0.6023 ln(B/A),
    # E ~ 1.0003 + 0.5968 A/B; curve fits good to a few per cent for moderate B/A.
    for ratio in (1.0, 1.5, 4.0, 10.0, 20.0):
        kp = float(ellipse_ratio(ratio))
        big_k, big_e = elliptic_integrals(kp)
        assert 1 / kp == pytest.approx(1.0339 * ratio**0.636, rel=0.035)
        assert float(big_k) == pytest.approx(1.5277 + 0.6023 * np.log(ratio), rel=0.03)
        assert float(big_e) == pytest.approx(1.0003 + 0.5968 / ratio, rel=0.03)


def test_zero_force_is_a_point_and_bad_geometry_is_refused():
    c = hertz(np.array([0.0, 10.0]), 100.0, 100.0, STEEL)
    assert c.a[0] == 0 and c.max_pressure[0] == 0 and c.stiffness[0] == 0
    assert c.max_pressure[1] > 0
    with pytest.raises(ValueError, match="do not touch at a point"):
        hertz(1.0, 0.0, 10.0, STEEL)
    with pytest.raises(ValueError, match="cannot pull"):
        hertz(-1.0, 10.0, 10.0, STEEL)
    with pytest.raises(ValueError, match="needs a direction"):
        curvature_tensor(np.array([1.0, 2.0]), None, np.array([0.0, 0.0, 1.0]))
