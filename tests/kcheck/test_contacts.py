"""kcheck contacts, the library: contacts found on assemblies of trimesh primitives, against
the closed-form geometry of tests/contact_assemblies.py (contact = ball centre - r n, n the
flat's normal; on a pin along the line from its axis to the ball centre; crossed pins on the
common perpendicular of their axes)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("trimesh")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact_assemblies import (  # noqa: E402
    R,
    ball,
    combine,
    expected_three_vee,
    flat,
    pin,
    three_vee,
    trihedral_normals,
    unit,
    vee,
    vee_normals,
)

from kcheck.body.contact_regions import contact_regions  # noqa: E402
from kcheck.body.coupling_elements import recognise  # noqa: E402
from kcheck.numerics.thresholds import CONTACT_GAP_RTOL  # noqa: E402

POSITION_TOL = 0.01  # mm, issue 29
ANGLE_TOL = 0.1  # degrees, issue 29


def _found(base, body, gap=None):
    size = float(np.linalg.norm(np.ptp(np.vstack([base.bounds, body.bounds]), axis=0)))
    gap = CONTACT_GAP_RTOL * size if gap is None else gap
    regions, depth = contact_regions(base, body, gap)
    return recognise(regions, gap), depth


def _angle(a, b):
    return np.degrees(np.arccos(np.clip(unit(a) @ unit(b), -1, 1)))


def _match(found, expected):
    """Every expected (point, normal) is a found contact within the issue's tolerances."""
    contacts = [c for e in found.elements for c in e.contacts]
    assert len(contacts) == len(expected)
    for point, normal in expected:
        d = [np.linalg.norm(c.point - point) for c in contacts]
        k = int(np.argmin(d))
        assert d[k] <= POSITION_TOL
        assert _angle(contacts[k].normal, normal) <= ANGLE_TOL


def test_three_vee_each_ball_a_vee():
    base, body = three_vee()
    found, depth = _found(base, body)
    assert [e.kind for e in found.elements] == ["ball-vee"] * 3
    assert not found.unusable
    assert depth < 1e-3
    _match(found, expected_three_vee())
    for e in found.elements:
        assert abs(e.ball.radius - R) < 1e-4
        assert abs(e.fields["groove"]["half_angle"] - 45.0) < ANGLE_TOL


def test_ball_flat():
    c = np.array([0.0, 0.0, 0.0])
    n = unit([0.2, -0.1, 1.0])
    found, _ = _found(flat(c, n), ball(c))
    assert [e.kind for e in found.elements] == ["ball-flat"]
    _match(found, [(c - R * n, n)])


def test_ball_in_trihedral_seat():
    c = np.array([1.0, 2.0, 3.0])
    normals = trihedral_normals()
    base = combine([flat(c, n, side=6.0) for n in normals])
    found, _ = _found(base, ball(c))
    assert [e.kind for e in found.elements] == ["ball-trihedral"]
    assert abs(found.elements[0].fields["half_angle"] - 54.7356103172) < ANGLE_TOL
    _match(found, [(c - R * n, n) for n in normals])


def test_ball_on_two_pins():
    # Two parallel pins of radius 2 along y, 8.4 apart (the tool changer's): the ball centre
    # is sqrt((R + 2)^2 - 4.2^2) above their axes.
    rp, half = 2.0, 4.2
    h = np.sqrt((R + rp) ** 2 - half**2)
    c = np.array([0.0, 0.0, h])
    axes = [np.array([s * half, 0.0, 0.0]) for s in (-1, 1)]
    base = combine([pin(a, [0, 1, 0], rp) for a in axes])
    found, _ = _found(base, ball(c))
    assert [e.kind for e in found.elements] == ["ball-cylinders"]
    expected = []
    for a in axes:
        n = unit(c - a)
        expected.append((c - R * n, n))
    _match(found, expected)
    radii = sorted(cyl[2] for cyl in found.elements[0].fields["cylinders"])
    assert np.allclose(radii, [rp, rp], atol=1e-3)


def test_ball_on_a_ball():
    c2 = np.array([0.0, 0.0, 0.0])
    n = unit([0.3, 0.2, 1.0])
    c = c2 + (R + 4.0) * n
    found, _ = _found(ball(c2, 4.0), ball(c))
    assert [e.kind for e in found.elements] == ["ball-sphere"]
    _match(found, [(c - R * n, n)])


def test_cylinder_on_two_crossed_cylinders():
    # The Renishaw-style probe seat: a pin along x (radius 3) on two pins along y (radius 2)
    # at x = +-10, axes 5 apart in z: contacts straight below the body pin's axis.
    body = pin([0, 0, 0], [1, 0, 0], 3.0, length=30)
    base = combine([pin([s * 10.0, 0, -5.0], [0, 1, 0], 2.0) for s in (-1, 1)])
    found, _ = _found(base, body)
    assert [e.kind for e in found.elements] == ["cylinder-crossed"]
    _match(found, [(np.array([s * 10.0, 0, -3.0]), np.array([0, 0, 1.0])) for s in (-1, 1)])


def test_ball_on_the_base_in_the_bodys_vee():
    # The balls on the base, the vee in the body (opening downwards): normals still point
    # from the base into the body, i.e. from the ball towards the flanks.
    c = np.array([0.0, 0.0, 0.0])
    normals = vee_normals([0, 1, 0], [0, 0, -1], 45.0)
    body = combine(vee(c, [0, 1, 0], up=[0, 0, -1]))
    found, _ = _found(ball(c), body)
    assert [(e.kind, e.ball_on) for e in found.elements] == [("ball-vee", "base")]
    _match(found, [(c - R * n, -n) for n in normals])


def test_area_contact_is_refused():
    import trimesh

    base = trimesh.creation.box(extents=[20, 20, 10]).apply_translation([0, 0, -5])
    body = trimesh.creation.box(extents=[10, 10, 10]).apply_translation([0, 0, 5])
    found, _ = _found(base, body)
    assert found.contact_count == 0
    assert [(u.why.split(" (")[0], u.constraints) for u in found.unusable] == [
        ("an area contact", 3)
    ]


def test_line_contact_is_refused():
    import trimesh

    base = trimesh.creation.box(extents=[40, 40, 10]).apply_translation([0, 0, -5])
    body = pin([0, 0, 3.0], [1, 0, 0], 3.0)
    found, _ = _found(base, body)
    assert found.contact_count == 0
    assert [u.constraints for u in found.unusable] == [2]
    assert "line contact" in found.unusable[0].why


def test_near_miss_is_a_gap_with_no_contact():
    # One flank 0.3 mm away: 3 times the gap tolerance of 0.1 mm, so seen but not touching.
    c = np.array([0.0, 0.0, 0.0])
    n1, n2 = vee_normals([0, 1, 0], [0, 0, 1], 45.0)
    base = combine([flat(c, n1), flat(c - 0.3 * n2, n2)])
    found, _ = _found(base, ball(c), gap=0.1)
    assert [e.kind for e in found.elements] == ["ball-flat"]
    assert [u.constraints for u in found.unusable] == [0]
    assert "gap with no contact" in found.unusable[0].why
