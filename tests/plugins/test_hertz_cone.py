"""Issue 28: `hertz` on a ball in a cone, a ring (line) contact around a circle.

A Kelvin clamp (cone, vee, flat), each ball pushed straight down by its own spring: each
coupling carries its own ball's load (the statics are determinate), so the cone's three
contacts each carry ``F / (3 cos h)`` and the ring's line load is ``w = F / (cos h 2 pi r_c)``
with ``r_c = R sin h`` (the shorthand's ``half_angle`` h is the normal's angle from the axis).
Reference, computed here independently of kcheck: Johnson, *Contact Mechanics* (1985), §4.3,
``b = sqrt(4 w R / (pi E*))``, ``p0 = 2 w / (pi b)``; the approach kcheck assumes (docs/checks.md,
hertz) ``delta = w / (pi E*) (2 ln(4R/b) - 1)``, its stiffness per length ``pi E* / (2 (ln(4R/b)
- 1))``; the cone's axial stiffness ``2 pi r_c k' cos^2 h``, radial ``pi r_c k' sin^2 h``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import Status

E_STAR = 1.0 / (2 * (1 - 0.3**2) / 210e9)  # 52100 on 52100
R, H, F = 5e-3, np.radians(40.0), 100.0

SCENE = """\
version: 1
units: mm
couplings:
  - {{name: A, type: ball-cone, ball: {{center: [0, 35, 0], radius: 5}}, up: [0, 0, 1],
     half_angle: 40, ball_material: 52100, seat_material: 52100}}
  - {{name: B, type: ball-vee, ball: {{center: [-30.311, -17.5, 0], radius: 5}},
     groove: {{axis: [-0.5, -0.866, 0], up: [0, 0, 1], half_angle: 45}},
     ball_material: 52100, seat_material: 52100}}
  - {{name: C, type: ball-flat, ball: {{center: [30.311, -17.5, 0], radius: 5}},
     normal: [0, 0, 1], ball_material: 52100, seat_material: 52100}}
preloads:
  - {{name: a, point: [0, 35, 0], force: [0, 0, -100]}}
  - {{name: b, point: [-30.311, -17.5, 0], force: [0, 0, -100]}}
  - {{name: c, point: [30.311, -17.5, 0], force: [0, 0, -100]}}
{checks}
"""


def _hertz(tmp_path: Path, checks: str = ""):
    path = tmp_path / "cone.kcheck.yaml"
    path.write_text(SCENE.format(checks=checks), encoding="utf-8")
    result = check_scene(path, [lc for lc in load_checks() if lc.spec.name == "hertz"])
    assert result.error is None, result.error
    (check,) = [c for c in result.checks if c.id == "hertz"]
    return check


def _ring(w: float) -> tuple[float, float, float, float]:
    """Half-width, p0, approach and stiffness per length of the ring under line load w."""
    b = np.sqrt(4 * w * R / (np.pi * E_STAR))
    log = np.log(4 * R / b)
    return (
        b,
        2 * w / (np.pi * b),
        w / (np.pi * E_STAR) * (2 * log - 1),
        np.pi * E_STAR / (2 * (log - 1)),
    )


G = 210e9 / (2 * 1.3)  # 52100's shear modulus (E = 210 GPa, nu = 0.3)


def _ring_tangential(b: float) -> tuple[float, float]:
    """The line contact's no-slip tangential stiffness per length across and along the line,
    two like bodies in series, datum R deep (docs/checks.md, hertz): Flamant's plane-strain
    line load (Johnson §2.2) under the full-stick traction q / (pi sqrt(b^2 - x^2)) (§7.1)
    gives each body q / (pi G) ((1 - nu) ln(2R/b) + 1/2) across, q / (pi G) ln(2R/b) along."""
    log = np.log(2 * R / b)
    return np.pi * G / (2 * ((1 - 0.3) * log + 0.5)), np.pi * G / (2 * log)


def test_antiplane_line_compliance_against_a_numerical_integration():
    """Along the line the strip shears antiplane: a line load S on a half-space displaces the
    surface by -(S / (pi G)) ln r (exact). Integrating the full-stick traction numerically,
    the strip's centre against a point d deep below it gives ln(2d/b) / (pi G) per unit load:
    the closed form kcheck's along-the-line stiffness uses (here d = R, like materials)."""
    from scipy.integrate import quad

    from kcheck.mechanics.ring_contact import line_tangential_stiffness

    b = 20e-6
    # s = b sin(t) removes the traction's end singularities: q ds = dt / pi
    surface = quad(lambda t: -np.log(abs(b * np.sin(t)) + 1e-300) / np.pi, -np.pi / 2,
                   np.pi / 2, points=[0.0], limit=200)[0]  # fmt: skip
    datum = quad(lambda t: -0.5 * np.log((b * np.sin(t)) ** 2 + R**2) / np.pi, -np.pi / 2,
                 np.pi / 2)[0]  # fmt: skip
    per_body = (surface - datum) / (np.pi * G)  # m per N/m of line load
    assert per_body * np.pi * G == pytest.approx(np.log(2 * R / b), rel=1e-6)
    _, along = line_tangential_stiffness(b, R, 210e9, 0.3, 210e9, 0.3)
    assert float(along) == pytest.approx(1 / (2 * per_body), rel=1e-6)
    across, _ = line_tangential_stiffness(b, R, 210e9, 0.3, 210e9, 0.3)
    assert float(across) == pytest.approx(_ring_tangential(b)[0], rel=1e-12)


def test_ring_tangential_stiffness_adds_to_the_cone_s_stiffness_matrix(tmp_path):
    """The ball in the cone with tangential compliance: the three arcs' springs along their
    normals and both tangents give, summed here as sum k d d^T over the 2 pi r_c ring
    (independently of kcheck's matrices), axially 2 pi r_c (k' cos^2 h + k'_m sin^2 h) and
    radially pi r_c (k' sin^2 h + k'_m cos^2 h + k'_c); kcheck's matrix with tangential
    stiffness differs from the normal one by the three couplings' tangential springs."""
    from kcheck.mechanics.ring_contact import cone_tangential_stiffness

    check = _hertz(tmp_path)
    ring_radius = R * np.sin(H)
    b, _, _, k_line = _ring(F / np.cos(H) / (2 * np.pi * ring_radius))
    k_m, k_c = _ring_tangential(b)
    # three points 120 deg apart, each an arc 2 pi r_c / 3: n, meridional and circumferential
    total = np.zeros((3, 3))
    for theta in 2 * np.pi * np.arange(3) / 3:
        radial = np.array([np.cos(theta), np.sin(theta), 0.0])
        circ = np.array([-np.sin(theta), np.cos(theta), 0.0])
        n = np.cos(H) * np.array([0, 0, 1.0]) - np.sin(H) * radial  # up and inwards
        t_m = np.cross(n, circ)
        arc = 2 * np.pi * ring_radius / 3
        for k, d in ((k_line, n), (k_m, t_m), (k_c, circ)):
            total += k * arc * np.outer(d, d)
    axial = 2 * np.pi * ring_radius * (k_line * np.cos(H) ** 2 + k_m * np.sin(H) ** 2)
    radial_k = np.pi * ring_radius * (k_line * np.sin(H) ** 2 + k_m * np.cos(H) ** 2 + k_c)
    assert np.allclose(total, np.diag([radial_k, radial_k, axial]), rtol=1e-12, atol=1e-6)
    (ring,) = check.details["rings"]
    t_axial, t_radial = cone_tangential_stiffness(k_m, k_c, ring_radius, H)
    assert ring["axial_tangential_stiffness"] == pytest.approx(float(t_axial), rel=1e-9)
    assert ring["radial_tangential_stiffness"] == pytest.approx(float(t_radial), rel=1e-9)
    assert ring["axial_stiffness"] + float(t_axial) == pytest.approx(axial, rel=1e-9)
    assert ring["radial_stiffness"] + float(t_radial) == pytest.approx(radial_k, rel=1e-9)
    # the whole matrix: its translation block gains every contact's tangential springs,
    # whose trace is 2 k_t for a point contact (both tangents) and k_m + k_c for a ring's
    k = np.array(check.details["stiffness_matrix"])
    kt = np.array(check.details["stiffness_matrix_with_tangential"])
    contacts = check.details["contacts"]
    points = sum(2 * c["tangential_stiffness"] for c in contacts if c["coupling"] != "A")
    ring = 3 * (k_m + k_c) * 2 * np.pi * ring_radius / 3
    assert np.trace((kt - k)[3:, 3:]) == pytest.approx(points + ring, rel=1e-9)
    assert np.all(np.linalg.eigvalsh(kt - k) > -1e-9 * np.abs(kt).max())  # springs add


def test_cone_gets_stress_stiffness_and_error_motion(tmp_path):
    check = _hertz(
        tmp_path, "checks: {hertz: {disturbing_force: [0, 0, -10], error_point: [0, 35, 0]}}"
    )
    assert check.status is Status.PASS, check.message
    assert "ring contact A" in check.message and "error motion" in check.message
    ring_radius = R * np.sin(H)
    w = F / np.cos(H) / (2 * np.pi * ring_radius)
    b, p0, _, k_line = _ring(w)
    cone = [c for c in check.details["contacts"] if c["coupling"] == "A"]
    assert len(cone) == 3
    for c in cone:
        # materials come from the scene's coupling entry
        assert c["ball_material_from"] == "couplings[0].ball_material"
        assert c["seat_material_from"] == "couplings[0].seat_material"
        assert c["normal_force"] == pytest.approx(F / (3 * np.cos(H)), rel=1e-9)
        assert c["semi_axes"][1] == pytest.approx(b, rel=1e-9)
        assert c["max_pressure"] == pytest.approx(p0, rel=1e-9)
        assert c["stiffness"] == pytest.approx(k_line * 2 * np.pi * ring_radius / 3, rel=1e-9)
        # the ring's tangential (no-slip) stiffness, across and along the line, per arc
        k_m, k_c = _ring_tangential(b)
        arc = 2 * np.pi * ring_radius / 3
        assert c["tangential_stiffness"] == pytest.approx(k_m * arc, rel=1e-9)
        assert c["tangential_stiffness_along_line"] == pytest.approx(k_c * arc, rel=1e-9)
        ball = c["subsurface"]["ball"]
        assert ball["max_shear"] / ball["von_mises"] == pytest.approx(0.30 / 0.56, abs=0.01)
    (ring,) = check.details["rings"]
    assert ring["ring_radius"] == pytest.approx(ring_radius, rel=1e-9)
    assert ring["normal_angle_deg"] == pytest.approx(40.0, rel=1e-9)
    assert ring["axial_stiffness"] == pytest.approx(
        2 * np.pi * ring_radius * k_line * np.cos(H) ** 2, rel=1e-9
    )
    assert ring["radial_stiffness"] == pytest.approx(
        np.pi * ring_radius * k_line * np.sin(H) ** 2, rel=1e-9
    )
    assert 0 < ring["stiffness_uncertainty"] < 0.2
    # the forces' rounding through p0 ~ N^(1/2): tiny, finite
    assert check.error_estimate is not None and 0 <= check.error_estimate < 1e-9


def test_cone_error_motion_is_its_ring_s_approach(tmp_path):
    # 10 N more straight down on the cone's ball stays with the cone (determinate statics):
    # the ball sinks along the axis by the change of the ring's approach over cos h
    check = _hertz(
        tmp_path, "checks: {hertz: {disturbing_force: [0, 0, -10], error_point: [0, 35, 0]}}"
    )
    ring_radius = R * np.sin(H)
    arc = 2 * np.pi * ring_radius
    delta0 = _ring(F / np.cos(H) / arc)[2]
    delta1 = _ring((F + 10) / np.cos(H) / arc)[2]
    motion = check.details["error_motion"]["translation"]
    assert motion[2] == pytest.approx(-(delta1 - delta0) / np.cos(H), rel=1e-6)
    assert abs(motion[0]) < 1e-6 * abs(motion[2]) and abs(motion[1]) < 1e-6 * abs(motion[2])


def test_sideways_load_raises_the_ring_s_peak(tmp_path):
    # a sideways disturbance loads one side of the ring: its peak line load exceeds the mean
    check = _hertz(
        tmp_path, "checks: {hertz: {disturbing_force: [5, 0, 0], disturbing_point: [0, 35, 0]}}"
    )
    (ring,) = check.details["rings"]
    mean = ring["normal_force"] / (2 * np.pi * ring["ring_radius"])
    assert ring["peak_line_load_worst"] > mean * 1.01
    b = np.sqrt(4 * ring["peak_line_load_worst"] * R / (np.pi * E_STAR))
    assert ring["max_pressure_worst"] == pytest.approx(
        2 * ring["peak_line_load_worst"] / (np.pi * b), rel=1e-9
    )


def test_a_ring_loaded_to_one_side_warns_that_it_partly_lifts(tmp_path):
    # Fx through the cone's ball stays with the cone: N_k = N0 + N1 cos theta_k with
    # N0 = F / (3 cos h) and N1 = Fx / (1.5 sin h); at N1 = 1.5 N0 the three supports still
    # press (N0 - N1/2 > 0) but the ring's first harmonic dips below zero (N0 - N1 < 0)
    n0 = F / (3 * np.cos(H))
    fx = 1.5 * n0 * 1.5 * np.sin(H)
    options = f"disturbing_force: [{float(fx)!r}, 0, 0], disturbing_point: [0, 35, 0]"
    check = _hertz(tmp_path, f"checks: {{hertz: {{{options}}}}}")
    assert check.status is Status.PASS, check.message
    (ring,) = check.details["rings"]
    arc = 2 * np.pi * R * np.sin(H) / 3
    # the peak of the disturbed state's own distribution, at support A.1 (theta = 0)
    assert ring["peak_line_load_worst"] == pytest.approx((n0 + 1.5 * n0) / arc, rel=1e-6)
    assert any("ring contact A is unloaded along part" in n for n in check.details["notes"])


def test_the_ring_s_stress_hint_lands_on_the_allowable(tmp_path):
    # a 52100 ball in an aluminium cone under 1 kN: over the allowable. On a ring p0 ~
    # sqrt(N) / R at a fixed cone angle (w ~ N / R, p0 ~ sqrt(w / R)), so the hint's ball,
    # u times larger, lands on the allowable exactly
    def scene(radius: float) -> str:
        text = SCENE.replace(
            "radius: 5}}, up: [0, 0, 1],\n     half_angle: 40, ball_material: 52100, "
            "seat_material: 52100",
            f"radius: {radius!r}}}}}, up: [0, 0, 1],\n     half_angle: 40, ball_material: 52100, "
            "seat_material: 6061-t6",
        )
        return text.replace(
            "force: [0, 0, -100]}}\n  - {{name: b", "force: [0, 0, -1000]}}\n  - {{name: b"
        )

    path = tmp_path / "cone.kcheck.yaml"
    hertz = [lc for lc in load_checks() if lc.spec.name == "hertz"]
    path.write_text(scene(5.0).format(checks=""), encoding="utf-8")
    (check,) = check_scene(path, hertz).checks
    assert check.status is Status.FAIL, check.message
    # each of the ring's supports carries the ring's peak
    findings = [f for f in check.findings if f.code == "contact-stress"]
    assert len(findings) == 3
    u = max(c["utilisation"] for c in check.details["contacts"] if c["coupling"] == "A")
    assert all(f"a ball {u:.2g}x larger" in f.hint for f in findings)
    path.write_text(scene(5.0 * u).format(checks=""), encoding="utf-8")
    (check,) = check_scene(path, hertz).checks
    scaled = max(c["utilisation"] for c in check.details["contacts"] if c["coupling"] == "A")
    assert scaled == pytest.approx(1.0, rel=1e-9)
