"""kcheck contacts, the library: contacts found on assemblies of trimesh primitives, against
the closed-form geometry of tests/contact_assemblies.py (contact = ball centre - r n, n the
flat's normal; on a pin along the line from its axis to the ball centre; crossed pins on the
common perpendicular of their axes)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
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


def test_trihedral_seat_through_float32_is_still_a_ball_trihedral():
    # An STL stores float32 coordinates: 50 mm from the origin each flat is tilted by up to
    # ~1e-7 rad, and the three fitted normals miss the shorthand's own expansion (made from
    # two angles and an axis) by that much. The shorthand is still written (fixtures/kelvin).
    c = np.array([0.0, 50.0, 0.0])
    normals = trihedral_normals()
    base = combine([flat(c, n, side=6.0) for n in normals])
    body = ball(c)
    for mesh in (base, body):
        mesh.vertices = np.asarray(mesh.vertices, dtype=np.float32).astype(float)
    found, _ = _found(base, body)
    assert [e.kind for e in found.elements] == ["ball-trihedral"]
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


def test_ball_in_a_conical_seat_is_a_ball_cone():
    # A 90 deg countersink (generator 45 deg from the axis, apex at z = -10): a ball of
    # radius R touches it on a circle of radius R cos 45 around the axis, R sin 45 below its
    # centre, which sits R / sin 45 above the apex; the seat's normal there leans 45 deg in.
    profile = [[0, -12], [20, -12], [20, 0], [10, 0], [2, -8], [0, -8]]
    seat = trimesh.creation.revolve(profile, sections=128)
    h = np.radians(45.0)
    c = np.array([0.0, 0.0, -10 + R / np.sin(h)])
    found, _ = _found(seat, ball(c))
    assert [e.kind for e in found.elements] == ["ball-cone"]
    assert not found.unusable
    e = found.elements[0]
    assert np.linalg.norm(e.fields["ball"]["center"] - c) <= POSITION_TOL
    assert _angle(e.fields["up"], [0, 0, 1]) <= ANGLE_TOL
    assert abs(e.fields["half_angle"] - 45.0) <= ANGLE_TOL
    assert len(e.contacts) == 3
    for contact in e.contacts:
        radial = contact.point[:2] - c[:2]
        assert abs(np.linalg.norm(radial) - R * np.cos(h)) <= POSITION_TOL
        assert abs(contact.point[2] - (c[2] - R * np.sin(h))) <= POSITION_TOL
        u = np.append(radial / np.linalg.norm(radial), 0.0)
        expected = -np.cos(h) * u + np.sin(h) * np.array([0, 0, 1.0])
        assert _angle(contact.normal, expected) <= ANGLE_TOL


def test_ball_off_the_cone_axis_is_refused():
    profile = [[0, -12], [20, -12], [20, 0], [10, 0], [2, -8], [0, -8]]
    seat = trimesh.creation.revolve(profile, sections=128)
    # Moved 1 along +x and lowered onto that flank (x = z + 10 in the xz plane, at the
    # distance (z + 9) / sqrt 2 = R from the centre): it touches one side of the circle only.
    c = np.array([1.0, 0.0, R * np.sqrt(2) - 9])
    found, _ = _found(seat, ball(c))
    assert not found.elements
    assert any("off the cone's axis" in u.why for u in found.unusable)


def test_canoe_ball_in_a_vee():
    # A canoe ball: the outside of a torus's tube (circle radius 40, tube 8, axis along y),
    # its lowest tube section resting in a 90 deg vee along x. Its contacts are those of a
    # ball of radius 8 centred on the tube's circle at the bottom (the origin); its surface
    # radii there are 8 across the groove and (40 + 8 cos 45) / cos 45 along it (the torus's
    # principal curvature cos v / (R + a cos v), v the normal's angle from the torus's plane).
    canoe = trimesh.creation.torus(
        major_radius=40.0, minor_radius=8.0, major_sections=512, minor_sections=128
    )
    canoe.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    canoe.apply_translation([0, 0, 40.0])
    normals = vee_normals([1, 0, 0], [0, 0, 1], 45.0)
    base = combine([flat([0, 0, 0], n, 8.0) for n in normals])
    found, _ = _found(base, canoe)
    assert [e.kind for e in found.elements] == ["ball-vee"]
    assert not found.unusable
    b = found.elements[0].fields["ball"]
    assert np.linalg.norm(b["center"]) <= POSITION_TOL
    assert abs(b["radius"] - 8.0) <= POSITION_TOL
    along = (40 + 8 * np.cos(np.radians(45))) / np.cos(np.radians(45))
    assert np.allclose(b["surface_radii"], [along, 8.0], atol=POSITION_TOL)
    assert abs(abs(unit(b["surface_direction"]) @ [1, 0, 0]) - 1) < 1e-9
    _match(found, [(-8.0 * n, n) for n in normals])


def test_two_bodies_whose_faces_coincide_under_the_ball_give_one_contact():
    """A body file of two closed bodies, a box and a smaller one inside it whose top face lies
    on the box's top face where the ball touches: one contact (not the same one twice, with a
    0/0 in its geometry), and neither body is taken for part of the base (they overlap; nothing
    of the base sits in a groove)."""
    import warnings

    from kcheck.body.contact_regions import merged_pieces

    c = np.array([0.0, 0.0, 0.0])
    n = unit([0.2, -0.1, 1.0])
    base = ball(c)
    body = combine([flat(c, n), flat(c, n, side=6.0, thickness=2.0)])
    size = float(np.linalg.norm(np.ptp(np.vstack([base.bounds, body.bounds]), axis=0)))
    gap = CONTACT_GAP_RTOL * size
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the repeated contact divided 0 by 0
        found, _ = _found(base, body)
    assert [e.kind for e in found.elements] == ["ball-flat"]
    assert found.contact_count == 1
    # The ball is the base's: the normal points into the body, down the flat's.
    _match(found, [(c - R * n, -n)])
    pieces = merged_pieces(body, base, gap)
    # The boxes' volumes in closed form: 1.6 R x 1.6 R x 4 and 6 x 6 x 2 (mm^3).
    volumes = sorted(piece.volume for piece, _ in pieces)
    assert np.allclose(volumes, [6.0 * 6.0 * 2.0, (1.6 * R) ** 2 * 4.0])
    assert [swallowed for _, swallowed in pieces] == [False, False]
