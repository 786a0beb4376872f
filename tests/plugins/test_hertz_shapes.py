"""Issue 28: canoe balls (two principal radii) and grooves with a radius (gothic arch,
conformal) in the shorthands and in `hertz`.

Reference: Johnson, *Contact Mechanics* (1985), §4.1-4.2, computed here independently of
kcheck with scipy's complete elliptic integrals: the curvature sums ``A <= B`` of the two
surfaces, the eccentricity ``e`` of the contact ellipse from

    B / A = ((a/b)^2 E(e) - K(e)) / (K(e) - E(e)),   b/a = sqrt(1 - e^2),

then ``a^3 = 3 P (K - E) / (2 pi A E* e^2)`` (from ``A = p0 b (K - E) / (E* e^2 a^2)`` and
``P = 2/3 pi a b p0``), ``b``, and ``p0 = 3 P / (2 pi a b)``; a sphere (``A = B``) is
``a^3 = 3 P R / (4 E*)`` with ``R = 1 / (2 A)``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import Status
from kcheck.scene import load_scene

E_STAR = 1.0 / (2 * (1 - 0.3**2) / 210e9)  # 52100 on 52100


def _johnson(force: float, sum_a: float, sum_b: float) -> tuple[float, float, float]:
    """Semi-axes a >= b and p0 of a Hertz contact (Johnson §4.2), independently of kcheck."""
    if np.isclose(sum_a, sum_b, rtol=1e-12):
        a = (3 * force / (2 * sum_a) / (4 * E_STAR)) ** (1 / 3)
        return a, a, 3 * force / (2 * np.pi * a * a)

    def mismatch(e):
        m = e * e
        k, big_e = ellipk(m), ellipe(m)
        return ((big_e / (1 - m)) - k) / (k - big_e) - sum_b / sum_a

    e = brentq(mismatch, 1e-6, 1 - 1e-12, xtol=1e-15)
    m = e * e
    k, big_e = ellipk(m), ellipe(m)
    a = (3 * force * (k - big_e) / (2 * np.pi * sum_a * E_STAR * m)) ** (1 / 3)
    b = a * np.sqrt(1 - m)
    return a, b, 3 * force / (2 * np.pi * a * b)


def _scene(tmp_path: Path, ball: str, groove: str, extra: str = "") -> Path:
    """Three radial vees, balls on the body, each pushed down by a 100 N spring."""
    lines = ["version: 1", "units: mm", "couplings:"]
    for k, phi in enumerate((90.0, 210.0, 330.0)):
        c, s = np.cos(np.radians(phi)), np.sin(np.radians(phi))
        lines.append(
            f"  - {{name: g{k + 1}, type: ball-vee, ball: {{center: [{50 * c:.9f}, "
            f"{50 * s:.9f}, 0], radius: 6{ball}}}, groove: {{axis: [{c:.12f}, {s:.12f}, 0], "
            f"up: [0, 0, 1], half_angle: 45{groove}}}}}"
        )
    lines.append("preloads:")
    for k, phi in enumerate((90.0, 210.0, 330.0)):
        c, s = np.cos(np.radians(phi)), np.sin(np.radians(phi))
        lines.append(
            f"  - {{name: s{k + 1}, point: [{50 * c:.9f}, {50 * s:.9f}, 0], force: [0, 0, -100]}}"
        )
    lines.append("checks: {hertz: {ball_material: 52100, seat_material: 52100}}")
    path = tmp_path / "shapes.kcheck.yaml"
    path.write_text("\n".join(lines) + "\n" + extra, encoding="utf-8")
    return path


def _hertz(path: Path):
    result = check_scene(path, [lc for lc in load_checks() if lc.spec.name == "hertz"])
    assert result.error is None, result.error
    (check,) = [c for c in result.checks if c.id == "hertz"]
    return check


def _against_johnson(check, sum_a: float, sum_b: float) -> None:
    assert check.status is Status.PASS, check.message
    force = 100 / (2 * np.cos(np.radians(45)))  # each flank of a symmetric vee
    a, b, p0 = _johnson(force, sum_a, sum_b)
    for c in check.details["contacts"]:
        assert c["normal_force"] == pytest.approx(force, rel=1e-9)
        assert c["curvature_sums"] == pytest.approx([sum_a, sum_b], rel=1e-12)
        assert c["semi_axes"] == pytest.approx([a, b], rel=1e-9)
        assert c["max_pressure"] == pytest.approx(p0, rel=1e-9)


def test_gothic_arch_groove(tmp_path):
    r, rg = 6e-3, 6.6e-3
    path = _scene(tmp_path, "", ", radius: 6.6")
    check = _hertz(path)
    # across the groove: ball 1/r, flank -1/rg; along it: ball 1/r, flank flat
    _against_johnson(check, 0.5 * (1 / r - 1 / rg), 0.5 / r)
    # the ellipse's long axis runs across the groove (the smaller curvature sum); each
    # groove runs radially, along its ball's centre
    for c, s in zip(check.details["contacts"], load_scene(path).supports, strict=True):
        groove = _unit(s.geometry.ball_center)
        assert abs(np.array(c["major_axis"]) @ groove) < 1e-9


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def test_canoe_ball_on_flat_flanks_is_a_big_sphere(tmp_path):
    # Slocum's canoe balls: a 500 mm surface radius on a ball placed like a 6 mm one
    check = _hertz(_scene(tmp_path, ", surface_radii: [500, 500]", ""))
    _against_johnson(check, 0.5 / 0.5, 0.5 / 0.5)


def test_canoe_ball_with_two_radii_in_a_gothic_groove(tmp_path):
    # 400 mm along the groove, 40 mm across it; the flank 45 mm across: all principal
    # directions line up, so A and B are half the sums along and across
    path = _scene(tmp_path, ", surface_radii: [400, 40]", ", radius: 45")
    text = path.read_text()
    # each ball's first surface radius along its own groove
    for k, phi in enumerate((90.0, 210.0, 330.0)):
        c, s = np.cos(np.radians(phi)), np.sin(np.radians(phi))
        text = text.replace(
            f"name: g{k + 1}, type: ball-vee, ball: {{center: [{50 * c:.9f}, {50 * s:.9f}, 0], "
            "radius: 6, surface_radii: [400, 40]",
            f"name: g{k + 1}, type: ball-vee, ball: {{center: [{50 * c:.9f}, {50 * s:.9f}, 0], "
            f"radius: 6, surface_radii: [400, 40], surface_direction: [{c:.12f}, {s:.12f}, 0]",
        )
    path.write_text(text, encoding="utf-8")
    along, across = 0.5 * (1 / 0.4 + 0), 0.5 * (1 / 0.04 - 1 / 0.045)
    _against_johnson(_hertz(path), min(along, across), max(along, across))


def test_expand_keeps_canoe_and_groove_radii(tmp_path):
    from kcheck.cli.expand import expanded_text

    path = _scene(tmp_path, ", surface_radii: [500, 500]", ", radius: 600")
    expanded = tmp_path / "expanded.kcheck.yaml"
    expanded.write_text(expanded_text(path), encoding="utf-8")
    assert "ball_radii: [500.0, 500.0]" in expanded.read_text()
    assert "seat_radii: [null, -600.0]" in expanded.read_text()
    original, again = _hertz(path), _hertz(expanded)
    for c, d in zip(original.details["contacts"], again.details["contacts"], strict=True):
        assert d["max_pressure"] == pytest.approx(c["max_pressure"], rel=1e-9)
        assert d["semi_axes"] == pytest.approx(c["semi_axes"], rel=1e-9)


def test_groove_radius_below_the_ball_is_a_located_error(tmp_path):
    with pytest.raises(Exception, match=r"couplings\[0\]\.groove\.radius.*must exceed"):
        load_scene(_scene(tmp_path, "", ", radius: 5"))


def test_canoe_radii_without_a_direction_is_a_located_error(tmp_path):
    with pytest.raises(Exception, match=r"couplings\[0\]\.ball\.surface_direction"):
        load_scene(_scene(tmp_path, ", surface_radii: [400, 40]", ""))
