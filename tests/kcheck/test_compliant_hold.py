"""The compliant seat's response to a lost support (tests.plugins.compliant_hold) against
closed forms worked by hand and against statics."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.kinematics import wrenches
from tests.plugins.compliant_hold import (
    compliant_hold,
    hertz_stiffness,
    mindlin_ratio,
    slip_hold,
)

# A planar block on a floor (s1 at x = +a, s2 at x = -a, normals +y) against a wall (s3 at
# (-b, h), normal +x), pushed by (-P, -Q) at (0, y).
A, B, H = 0.02, 0.03, 0.01
POINTS = np.array([[A, 0.0], [-A, 0.0], [-B, H]])
NORMALS = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])


def _wrench(p: float, q: float, y: float) -> np.ndarray:
    """Moment about the origin (x F_y - y F_x = P y), then the force."""
    return np.array([p * y, -p, -q])


def _seated(p: float, q: float, y: float) -> np.ndarray:
    """Frictionless seat by hand: N3 = P; N1 + N2 = Q; moments about the origin:
    a (N1 - N2) - h N3 + P y = 0."""
    n1_minus_n2 = p * (H - y) / A
    return np.array([(q + n1_minus_n2) / 2, (q - n1_minus_n2) / 2, p])


def test_the_hand_worked_seat_balances_the_load() -> None:
    """The seat the tests start from is an equilibrium: sum N_i w_i = -W."""
    p, q, y = 3.0, 10.0, 0.015
    total = _seated(p, q, y) @ wrenches(POINTS, NORMALS)
    assert total == pytest.approx(-_wrench(p, q, y), abs=1e-12)


def test_two_floor_contacts_share_the_lost_wall_force_by_stiffness() -> None:
    """Hand-worked: with the wall retracted the floor contacts' normal forces are statically
    determinate (N1 + N2 = Q, a (N1 - N2) = -P y) and the lost wall force P must come from
    friction, T1 + T2 = P, split in proportion to the contacts' tangential stiffnesses
    (the floor's tangential springs have no lever about the origin, so the split does not
    depend on the tangential/normal ratio): k2 = 3 k1 gives T1 = P / 4, T2 = 3 P / 4. At
    mu = 0.35 the rigid model holds (capacity mu Q = 3.5 > P = 3), yet s2 needs
    2.25 / (0.35 x 6.125) = 1.05 of its cone: the compliant seat slips at s2."""
    p, q, y, mu = 3.0, 10.0, 0.015, 0.35
    seated = _seated(p, q, y)
    ratios = np.array([2 / 3, 1.0, 5.0])
    hold = compliant_hold(
        POINTS, NORMALS, np.full(3, mu), seated, 2, np.array([1.0, 3.0, 1.0]), ratios
    )
    n1 = (q - p * y / A) / 2
    n2 = q - n1
    for r in range(len(ratios)):
        assert hold.normal[r] == pytest.approx([n1, n2, 0.0], rel=1e-9, abs=1e-12)
        assert hold.tangential[r] == pytest.approx([p / 4, 3 * p / 4, 0.0], rel=1e-9, abs=1e-12)
        assert hold.usage[r, :2] == pytest.approx(
            [p / 4 / (mu * n1), 3 * p / 4 / (mu * n2)], rel=1e-9
        )
    assert list(hold.separated[0]) == [False, False, True]
    assert list(hold.slips[0]) == [False, True, False]
    assert not hold.holds.any()
    # Equal stiffnesses: T = P / 2 each; s2 (the more loaded) at 1.5 / 2.14 = 0.70, s1 at
    # 1.5 / (0.35 x 3.875) = 1.106: s1 slips instead.
    equal = compliant_hold(POINTS, NORMALS, np.full(3, mu), seated, 2, np.ones(3), ratios)
    assert equal.tangential[0, :2] == pytest.approx([p / 2, p / 2], rel=1e-9)
    assert list(equal.slips[0]) == [True, False, False]


def test_a_pulling_contact_lets_go() -> None:
    """Pushed high (y = 0.1), the floor's s1 would need N1 = (Q - P y / a) / 2 = -2.5 N once
    the wall is gone: it lets go, and s2 alone (two springs for three freedoms) cannot hold
    the block elastically: it does not hold."""
    seated = _seated(3.0, 10.0, 0.1)
    hold = compliant_hold(POINTS, NORMALS, np.full(3, 0.5), seated, 2, np.ones(3), [1.0])
    assert hold.separated[0, 0] and hold.separated[0, 2]
    assert not hold.holds[0]


def test_released_forces_balance_the_load() -> None:
    """Random spatial seats: the remaining contacts' forces after the release balance the
    load (statics), whichever contacts let go, and the tangential magnitudes are those of the
    forces' components in the tangent planes."""
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(200):
        points = rng.uniform(-1, 1, (6, 3))
        normals = -points + rng.normal(0, 0.5, (6, 3))
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        if np.linalg.cond(wrenches(points, normals)) > 1e4:
            continue
        # a seat pressing every contact: the load its positive forces balance
        seated = rng.uniform(1, 10, 6)
        wrench = -seated @ wrenches(points, normals)
        hold = compliant_hold(
            points, normals, np.full(6, 0.3), seated, 0, hertz_stiffness(seated), [0.7, 1.0]
        )
        if np.isinf(hold.usage).any():
            continue  # too few contacts left to hold the body elastically
        checked += 1
        for r in range(2):
            total = wrenches(points, hold.forces[r]).sum(axis=0)
            assert total == pytest.approx(-wrench, abs=1e-9 * (1 + np.abs(wrench).max()))
            friction = np.linalg.norm(
                hold.forces[r] - np.sum(hold.forces[r] * normals, axis=1)[:, None] * normals,
                axis=1,
            )
            assert friction == pytest.approx(hold.tangential[r], abs=1e-9)
    assert checked > 10


def test_mindlin_ratio() -> None:
    """2 (1 - nu) / (2 - nu): 1 at nu = 0, 2/3 at nu = 0.5, 0.824 at steel's 0.3."""
    assert mindlin_ratio([0.0, 0.5, 0.3]) == pytest.approx([1.0, 2 / 3, 1.4 / 1.7], rel=1e-12)


def test_after_local_slip_the_floor_holds_when_the_rigid_model_does() -> None:
    """The same block, k2 = 3 k1, mu = 0.35: s2 slips (above) and then carries mu N2 =
    0.35 x 6.125 = 2.144 N of the lost 3 N; s1 carries the rest, 0.856 N, under its
    mu N1 = 0.35 x 3.875 = 1.356 N: the seat holds after s2 slips. At mu = 0.25 the rigid
    model cannot hold (mu Q = 2.5 < P = 3): s1 must slip too, and with both floor contacts
    slipping nothing stops the block."""
    seated = _seated(3.0, 10.0, 0.015)
    stiffness = np.array([1.0, 3.0, 1.0])
    held = slip_hold(POINTS, NORMALS, np.full(3, 0.35), seated, 2, stiffness, 0.8)
    assert held.holds
    assert list(held.slipping) == [False, True, False]
    moves = slip_hold(POINTS, NORMALS, np.full(3, 0.25), seated, 2, stiffness, 0.8)
    assert not moves.holds
