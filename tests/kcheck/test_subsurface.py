"""Stress below a Hertz contact (issue 28): the largest shear and von Mises stresses and their
depths.

References:

* circle: Johnson, *Contact Mechanics* (1985), eq. 3.46, the stresses on the axis of a
  spherical Hertz contact, ``sigma_z = -p0 / (1 + zeta^2)``, ``sigma_r = sigma_theta = -p0
  [(1 + nu)(1 - zeta atan(1/zeta)) - 1 / (2 (1 + zeta^2))]`` with ``zeta = z / a``; maximised
  here with scipy; the textbook figures 0.31 p0 and 0.62 p0 at 0.48 a for nu = 0.3;
* ellipse: Boussinesq's point-load stresses in Cartesian form (Johnson eq. 3.21a) integrated
  over the elliptical Hertz pressure with scipy's ``dblquad`` in x and y (kcheck integrates in
  polar coordinates with its own rules);
* a long ellipse tends to the line contact: ``tau_max = 0.30 p0`` at ``z = 0.78 b`` (Johnson
  §4.3).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import dblquad
from scipy.optimize import minimize_scalar

from kcheck.mechanics.subsurface import axis_stresses, subsurface_stress


def _johnson_axis(zeta: float, nu: float) -> tuple[float, float]:
    """(sigma_r, sigma_z) / p0 on the axis of a circular contact (Johnson eq. 3.46)."""
    sz = -1.0 / (1.0 + zeta**2)
    sr = -(1.0 + nu) * (1.0 - zeta * np.arctan(1.0 / zeta)) + 0.5 / (1.0 + zeta**2)
    return sr, sz


@pytest.mark.parametrize("zeta", [0.05, 0.3, 0.48, 1.0, 2.5])
@pytest.mark.parametrize("nu", [0.22, 0.3, 0.33])
def test_axis_stresses_of_a_circle_are_johnsons(zeta, nu):
    a, p0 = 2e-4, 1.5e9
    sx, sy, sz = axis_stresses(zeta * a, a, a, p0, nu)
    sr, sz_ref = _johnson_axis(zeta, nu)
    assert sx == pytest.approx(sr * p0, abs=1e-7 * p0)
    assert sy == pytest.approx(sr * p0, abs=1e-7 * p0)
    assert sz == pytest.approx(sz_ref * p0, abs=1e-7 * p0)


def test_circle_maxima_are_the_textbook_values():
    nu = 0.3
    a, p0 = 1e-4, 2e9
    found = subsurface_stress(a, a, p0, nu)
    # the closed form's maxima, found independently
    shear = minimize_scalar(
        lambda z: -0.5 * abs(np.subtract(*_johnson_axis(z, nu))), bounds=(0.1, 2), method="bounded",
        options={"xatol": 1e-10},
    )  # fmt: skip
    assert found.max_shear == pytest.approx(-shear.fun * p0, rel=1e-6)
    assert found.max_shear_depth == pytest.approx(shear.x * a, rel=1e-4)
    # on the axis sigma_r = sigma_theta, so von Mises is twice the largest shear
    assert found.von_mises == pytest.approx(-2 * shear.fun * p0, rel=1e-6)
    assert found.von_mises_depth == pytest.approx(shear.x * a, rel=1e-4)
    # the published round figures (Johnson §4.2, nu = 0.3)
    assert found.max_shear / p0 == pytest.approx(0.31, abs=0.005)
    assert found.max_shear_depth / a == pytest.approx(0.48, abs=0.005)
    assert found.von_mises / p0 == pytest.approx(0.62, abs=0.005)


def _boussinesq_on_axis(z, a, b, p0, nu):
    """sigma_x, sigma_y, sigma_z at (0, 0, z) under p0 sqrt(1 - x^2/a^2 - y^2/b^2): Johnson
    eq. 3.21a for a point load at (x, y), the field point at offset (-x, -y), integrated."""

    def kernel(y, x, which):
        p = p0 * np.sqrt(max(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0))
        r2 = x * x + y * y
        rho = np.sqrt(r2 + z * z)
        if which == "z":
            return p * -3 * z**3 / (2 * np.pi * rho**5)
        u2, v2 = (x * x, y * y) if which == "x" else (y * y, x * x)
        soft = 1.0 / (rho * (rho + z))  # (1 - z/rho) / r^2
        term = (1 - 2 * nu) * (soft * (u2 - v2) / r2 + z * v2 / (r2 * rho**3)) if r2 else 0.0
        return p / (2 * np.pi) * (term - 3 * z * u2 / rho**5)

    def edge(x):
        return b * np.sqrt(max(1.0 - (x / a) ** 2, 0.0))

    return [
        dblquad(kernel, -a, a, lambda x: -edge(x), edge, args=(w,), epsabs=1e-10 * p0,
                epsrel=1e-10)[0]
        for w in ("x", "y", "z")
    ]  # fmt: skip


@pytest.mark.parametrize(("ratio", "zeta"), [(2.0, 0.6), (5.0, 0.75), (1.3, 0.3)])
def test_axis_stresses_of_an_ellipse_against_a_cartesian_integration(ratio, zeta):
    b, p0, nu = 1e-4, 1e9, 0.3
    a = ratio * b
    kcheck = axis_stresses(zeta * b, a, b, p0, nu)
    reference = _boussinesq_on_axis(zeta * b, a, b, p0, nu)
    np.testing.assert_allclose(kcheck, reference, rtol=0, atol=1e-6 * p0)


def test_a_long_ellipse_tends_to_the_line_contact():
    b, p0 = 1e-4, 1e9
    found = subsurface_stress(60 * b, b, p0, 0.3)
    assert found.max_shear / p0 == pytest.approx(0.30, abs=0.01)
    assert found.max_shear_depth / b == pytest.approx(0.786, abs=0.02)


def test_vectorised_and_zero_force():
    found = subsurface_stress([1e-4, 0.0, 3e-4], [1e-4, 0.0, 1e-4], [1e9, 0.0, 1e9], 0.3)
    assert found.max_shear.shape == (3,)
    assert found.max_shear[1] == 0 and found.von_mises_depth[1] == 0
    alone = subsurface_stress(3e-4, 1e-4, 1e9, 0.3)
    assert found.von_mises[2] == pytest.approx(float(alone.von_mises), rel=1e-12)


def test_a_nearly_circular_ellipse_meets_the_circle():
    # b/a = 0.999 goes through the quadrature, b = a through the closed form
    a, p0, nu = 1e-4, 1e9, 0.3
    near = subsurface_stress(a, 0.999 * a, p0, nu)
    circle = subsurface_stress(a, a, p0, nu)
    assert near.max_shear == pytest.approx(float(circle.max_shear), rel=2e-3)
    assert near.von_mises == pytest.approx(float(circle.von_mises), rel=2e-3)
    assert near.max_shear_depth == pytest.approx(float(circle.max_shear_depth), rel=5e-3)


@pytest.mark.parametrize("zeta", [0.02, 0.3, 1.0, 4.0])
def test_ray_integrals_against_quadrature(zeta):
    from scipy.integrate import quad

    from kcheck.mechanics.subsurface import _ray_integrals

    def q(s):
        return np.sqrt(s * s + zeta * zeta)

    kernels = [
        lambda s: s * np.sqrt(1 - s * s) / (q(s) * (q(s) + zeta)),
        lambda s: zeta * s * np.sqrt(1 - s * s) / q(s) ** 3,
        lambda s: 3 * zeta * s**3 * np.sqrt(1 - s * s) / q(s) ** 5,
        lambda s: 3 * zeta**3 * s * np.sqrt(1 - s * s) / q(s) ** 5,
    ]
    reference = [quad(k, 0, 1, epsabs=1e-13, epsrel=1e-12, limit=200)[0] for k in kernels]
    np.testing.assert_allclose(_ray_integrals(np.array(zeta)), reference, rtol=1e-9, atol=1e-13)
