"""The ring contact of a ball in a cone (kcheck.mechanics.ring_contact) and the stresses below
a line contact (kcheck.mechanics.subsurface.line_subsurface_stress).

References, restated here and computed independently of kcheck:

* Johnson, *Contact Mechanics* (1985), §4.3, the 2D Hertz contact of a cylinder of radius R on
  a flat under a line load w: ``b = sqrt(4 w R / (pi E*))``, ``p0 = 2 w / (pi b) = sqrt(w E* /
  (pi R))``; below it (nu = 0.3) ``tau_max = 0.30 p0`` at ``z = 0.78 b`` and von Mises
  ``0.56 p0`` at ``z = 0.70 b``.
* The approach kcheck assumes (docs/checks.md, hertz): ``delta = w / (pi E*) (2 ln(4R/b) - 1)``;
  its tangent stiffness is checked here by a finite difference, not by the closed form.
* Three springs of stiffness k along the normals of a ball in a cone (normal at h from the
  axis, 120 deg apart) give ``sum k n n^T``: axial ``3 k cos^2 h``, radial ``3/2 k sin^2 h``.
"""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.ring_contact import (
    cone_stiffness,
    line_contact,
    line_uncertainty,
    ring_peak_load,
)
from kcheck.mechanics.subsurface import line_subsurface_stress, subsurface_stress

E_STAR = 1.0 / (2 * (1 - 0.3**2) / 210e9)  # 52100 on 52100


@pytest.mark.parametrize(("w", "radius"), [(500.0, 5e-3), (2e4, 12.7e-3), (1.0, 1e-3)])
def test_line_contact_matches_johnson(w, radius):
    found = line_contact(w, radius, E_STAR)
    b = np.sqrt(4 * w * radius / (np.pi * E_STAR))
    assert found.half_width == pytest.approx(b, rel=1e-12)
    assert found.max_pressure == pytest.approx(2 * w / (np.pi * b), rel=1e-12)
    assert found.max_pressure == pytest.approx(np.sqrt(w * E_STAR / (np.pi * radius)), rel=1e-12)
    assert found.approach == pytest.approx(
        w / (np.pi * E_STAR) * (2 * np.log(4 * radius / b) - 1), rel=1e-12
    )


def test_line_stiffness_is_the_derivative_of_the_approach():
    w, radius, h = 800.0, 6e-3, 1e-4
    up, down = line_contact(w * (1 + h), radius, E_STAR), line_contact(w * (1 - h), radius, E_STAR)
    slope = (2 * w * h) / (up.approach - down.approach)
    assert line_contact(w, radius, E_STAR).stiffness == pytest.approx(slope, rel=1e-7)


def test_zero_load_is_no_contact():
    found = line_contact(0.0, 5e-3, E_STAR)
    assert (found.half_width, found.max_pressure, found.approach, found.stiffness) == (0, 0, 0, 0)


def test_larger_ball_in_the_same_cone_lowers_the_pressure():
    # the same axial force on a ball in a 45 deg cone: ring radius R sin h, so w ~ 1/R and
    # p0 = sqrt(w E* / (pi R)) ~ 1/R
    force, h = 100.0, np.radians(45)
    radii = np.array([2e-3, 5e-3, 10e-3, 20e-3])
    w = force / np.cos(h) / (2 * np.pi * radii * np.sin(h))
    p0 = line_contact(w, radii, E_STAR).max_pressure
    assert np.all(np.diff(p0) < 0)
    assert p0 * radii == pytest.approx(np.full(4, p0[0] * radii[0]), rel=1e-12)


def test_uncertainty_is_the_datum_depth_between_half_and_twice_the_radius():
    w, radius = 500.0, 5e-3
    found = line_contact(w, radius, E_STAR)
    # the approach to a datum at depth d grows by 2 w / (pi E*) ln 2 per doubling of d
    shift = 2 * w / (np.pi * E_STAR) * np.log(2)
    assert line_uncertainty(found.half_width, radius) == pytest.approx(
        shift / found.approach, rel=1e-12
    )


@pytest.mark.parametrize("theta0", [0.0, 0.3, 2.0, -2.5])
def test_ring_peak_load_recovers_a_first_harmonic(theta0):
    w0, w1 = 400.0, 150.0
    theta = 2 * np.pi * np.arange(3) / 3
    samples = w0 + w1 * np.cos(theta - theta0)
    assert ring_peak_load(samples) == pytest.approx(w0 + w1, rel=1e-12)
    assert ring_peak_load(samples[::-1]) == pytest.approx(w0 + w1, rel=1e-12)


def test_cone_stiffness_equals_three_springs_along_the_normals():
    k_line, ring, h = 2.5e10, 3.5e-3, np.radians(50)
    arc = 2 * np.pi * ring / 3
    k = k_line * arc  # each point stands for a third of the circle
    normals = np.array(
        [
            [-np.sin(h) * np.cos(t), -np.sin(h) * np.sin(t), np.cos(h)]
            for t in 2 * np.pi * np.arange(3) / 3
        ]
    )
    springs = k * np.einsum("ia,ib->ab", normals, normals)
    axial, radial = cone_stiffness(k_line, ring, h)
    assert springs[2, 2] == pytest.approx(axial, rel=1e-12)
    assert springs[0, 0] == pytest.approx(radial, rel=1e-12)
    assert springs[1, 1] == pytest.approx(radial, rel=1e-12)
    assert 2 * np.pi * ring * k_line * np.cos(h) ** 2 == pytest.approx(axial, rel=1e-12)


def test_line_subsurface_stress_matches_johnson():
    p0, b = 1.2e9, 3e-5
    found = line_subsurface_stress(b, p0, 0.3)
    # Johnson §4.3 quotes two figures
    assert found.max_shear / p0 == pytest.approx(0.30, abs=0.005)
    assert found.max_shear_depth / b == pytest.approx(0.78, abs=0.01)
    assert found.von_mises / p0 == pytest.approx(0.56, abs=0.005)
    assert found.von_mises_depth / b == pytest.approx(0.70, abs=0.01)


def test_line_subsurface_stress_is_the_limit_of_a_long_ellipse():
    # longer ellipses under the same p0 and b come closer to the line contact (the ellipse's
    # own quadrature, an independent route): within 1 % at b/a = 1/100
    line = line_subsurface_stress(1.0, 1.0, 0.3)
    gaps = []
    for a in (10.0, 30.0, 100.0):
        long = subsurface_stress(a, 1.0, 1.0, 0.3)
        gaps.append(abs(long.max_shear - line.max_shear) + abs(long.von_mises - line.von_mises))
    assert gaps[0] > gaps[1] > gaps[2]
    long = subsurface_stress(100.0, 1.0, 1.0, 0.3)
    assert line.max_shear == pytest.approx(long.max_shear, rel=1e-2)
    assert line.von_mises == pytest.approx(long.von_mises, rel=1e-2)
    assert line.max_shear_depth == pytest.approx(long.max_shear_depth, rel=1e-2)
