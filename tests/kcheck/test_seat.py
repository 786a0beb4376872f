"""The seated coupling: determinate contact forces, stiffness matrix, error motion.

Closed forms (derived in the test docstrings): a symmetric three-vee coupling with flank
normals ``beta`` from up, pressed down by ``F`` per ball, carries ``F / (2 cos beta)`` on
every contact; moved down by ``dz`` every contact's approach grows by ``dz cos beta``, so its
vertical stiffness is ``6 k cos^2 beta``. The stiffness matrix is ``sum k_i w_i w_i^T`` by
definition; the error motion from compatibility must approach ``K^-1 dW`` for small loads.
"""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.hertz import contact_modulus, hertz
from kcheck.mechanics.seat import (
    contact_forces,
    external_wrench,
    point_translation,
    seat_layout,
    stiffness_matrix,
    twist_from_approach,
)
from kcheck.scene import Preload
from tests.couplings import kelvin, three_vee

STEEL = contact_modulus(210e9, 0.3, 210e9, 0.3)
BALL = 6e-3
BETA = 40.0


def _layout(contacts):
    points = np.array([p for p, _, _ in contacts])
    normals = np.array([n for _, n, _ in contacts])
    return points, normals


def _ball_loads(contacts, force):
    centres = {g.coupling: g.ball_center for _, _, g in contacts}
    return [Preload(name, c, force) for name, c in centres.items()]


def test_three_vee_preload_shares_and_vertical_stiffness():
    contacts = three_vee(0.05, BALL, BETA)
    points, normals = _layout(contacts)
    seat = seat_layout(points, normals, 3, 100.0)
    per_ball = 100.0
    loads = _ball_loads(contacts, np.array([0.0, 0.0, -per_ball]))
    sol = contact_forces(seat, external_wrench(seat, loads, np.zeros(3)))
    expected = per_ball / (2 * np.cos(np.radians(BETA)))
    np.testing.assert_allclose(sol.value, expected, rtol=1e-13)
    assert sol.condition < 100 and np.all(sol.error < 1e-10 * expected)
    k = hertz(sol.value, 0.5 / BALL, 0.5 / BALL, STEEL).stiffness
    big_k = stiffness_matrix(seat, k)
    # vertical translation: every approach grows by dz cos(beta)
    assert big_k[5, 5] == pytest.approx(6 * k[0] * np.cos(np.radians(BETA)) ** 2, rel=1e-13)
    np.testing.assert_allclose(big_k, big_k.T, atol=1e-9 * np.abs(big_k).max())
    assert np.all(np.linalg.eigvalsh(big_k) > 0)
    # and by definition: sum k_i w_i w_i^T with the physical wrenches (p - o) x n, n
    rows = np.hstack([np.cross(points - points.mean(axis=0), normals), normals])
    np.testing.assert_allclose(big_k, rows.T @ np.diag(k) @ rows, rtol=1e-12, atol=1e-6)


def test_vertical_error_motion_is_exact():
    contacts = three_vee(0.05, BALL, BETA)
    points, normals = _layout(contacts)
    seat = seat_layout(points, normals, 3, 100.0)
    n0 = np.full(6, 100.0 / (2 * np.cos(np.radians(BETA))))
    dn = 30.0 / (6 * np.cos(np.radians(BETA)))  # 30 N more, straight down the axis
    h0 = hertz(n0, 0.5 / BALL, 0.5 / BALL, STEEL)
    h1 = hertz(n0 + dn, 0.5 / BALL, 0.5 / BALL, STEEL)
    motion = twist_from_approach(seat, h1.approach - h0.approach)
    dz = -(h1.approach[0] - h0.approach[0]) / np.cos(np.radians(BETA))
    np.testing.assert_allclose(motion.value[:5], 0.0, atol=1e-15)
    assert motion.value[5] == pytest.approx(dz, rel=1e-13)
    top = np.array([0.0, 0.0, 0.03])
    np.testing.assert_allclose(point_translation(seat, motion.value, top), [0, 0, dz], atol=1e-18)


@pytest.mark.parametrize("make", [three_vee, kelvin])
def test_small_disturbance_follows_the_stiffness_matrix(make):
    contacts = make(0.05, BALL, BETA)
    points, normals = _layout(contacts)
    seat = seat_layout(points, normals, 3, 100.0)
    loads = _ball_loads(contacts, np.array([0.0, 0.0, -100.0]))
    n0 = contact_forces(seat, external_wrench(seat, loads, np.zeros(3))).value
    assert np.all(n0 > 0)
    h0 = hertz(n0, 0.5 / BALL, 0.5 / BALL, STEEL)
    big_k = stiffness_matrix(seat, h0.stiffness)
    point = np.array([0.01, -0.02, 0.04])
    disturbance = Preload("d", point, np.array([0.3, -0.2, 0.5]))
    torque = np.array([0.01, 0.0, -0.02])
    dw = external_wrench(seat, [disturbance], torque)
    dn = contact_forces(seat, dw).value
    h1 = hertz(n0 + dn, 0.5 / BALL, 0.5 / BALL, STEEL)
    exact = twist_from_approach(seat, h1.approach - h0.approach).value
    o = seat.frame.origin
    physical = np.concatenate([np.cross(point - o, disturbance.force) + torque, disturbance.force])
    linear = np.linalg.solve(big_k, physical)
    # second-order terms of the Hertz law: relative size ~ dN/N ~ 1e-3
    np.testing.assert_allclose(exact, linear, rtol=3e-3, atol=3e-3 * np.abs(linear).max())


def test_planar_seat():
    # Three planar supports of the methods.md block; a push along -x and -y seats it.
    points = np.array([[0.02, 0.0, 0.0], [0.08, 0.0, 0.0], [0.0, 0.03, 0.0]])
    normals = np.array([[0.0, 1.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    seat = seat_layout(points, normals, 2, 1.0)
    push = Preload("p", np.array([0.05, 0.03, 0.0]), np.array([-1.0, -1.0, 0.0]))
    forces = contact_forces(seat, external_wrench(seat, [push], np.zeros(3))).value
    # x1 takes the x force; y1 and y2 share the y force by moments about the push line
    assert forces[2] == pytest.approx(1.0, rel=1e-14)
    assert forces[0] + forces[1] == pytest.approx(1.0, rel=1e-14)
    # moments about the centre of mass (0.05, 0.03): x1 at y = 0.03 has no arm
    assert -0.03 * forces[0] + 0.03 * forces[1] == pytest.approx(0.0, abs=1e-15)
    big_k = stiffness_matrix(seat, np.array([1e6, 2e6, 3e6]))
    assert big_k.shape == (3, 3) and np.all(np.linalg.eigvalsh(big_k) > 0)


def test_singular_layout_gives_no_numbers():
    # six normals through one point: not determinate
    phi = np.radians(np.arange(6) * 60.0)
    points = np.column_stack([np.cos(phi), np.sin(phi), np.zeros(6)]) * 0.05
    normals = -points / 0.05
    seat = seat_layout(points, normals, 3, 1.0)
    sol = contact_forces(seat, external_wrench(seat, [], np.array([0.0, 0.0, 1.0])))
    assert sol.singular and sol.value is None and sol.condition > 1e12
