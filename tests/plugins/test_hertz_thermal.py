"""Issue 28: thermal pose shift and thermal centre of a seated coupling (`hertz`, option
``temperature_change``).

References computed here: with the balls of the body's material every contact keeps
``N_i . u(p_i) = 0`` for the relative displacement field ``u(x) = v + omega x x + beta x``,
``beta = (alpha_body - alpha_base) dT`` (the ball's growth and the body's cancel at the
contact point); six such equations give ``(v, omega)`` and ``u(x*) = 0`` the thermal centre.
A symmetric three-vee's centre is its centre (its grooves all point at it); a Kelvin
coupling's lies over its trihedral socket, the one ball that cannot slide.
"""

from __future__ import annotations

import numpy as np
from kcheck_checks.hertz import Hertz
from kcheck_checks.hertz_materials import HertzOptions

from kcheck.plugin import Inputs
from kcheck.scene import Preload
from tests.couplings import coupling_scene, kelvin, three_vee, with_preloads

BALL = 6e-3
ALU, STEEL = 23.6e-6, 11.9e-6  # 6061-t6 and 52100 in docs/materials.md


def _seated(scene):
    centres = {s.geometry.coupling: s.geometry.ball_center for s in scene.supports}
    return with_preloads(
        scene, [Preload(f"s {n}", c, np.array([0.0, 0.0, -100.0])) for n, c in centres.items()]
    )


def _run(scene, **options):
    options = {"ball_material": "6061-t6", "seat_material": "52100"} | options
    return Hertz().run(Inputs(scene, None, HertzOptions(**options)))


def _reference(scene, beta):
    """(v, omega) from N_i . u(p_i) = 0 (origin 0) and the thermal centre."""
    rows, rhs = [], []
    for s in scene.supports:
        rows.append(np.concatenate([s.normal, np.cross(s.position, s.normal)]))
        rhs.append(-beta * s.normal @ s.position)
    v_w = np.linalg.solve(np.array(rows), np.array(rhs))
    v, w = v_w[:3], v_w[3:]
    m = beta * np.eye(3) + np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    return v, w, np.linalg.solve(m, -v)


def test_symmetric_three_vee_centre_is_its_centre(tmp_path):
    scene = _seated(coupling_scene(tmp_path, three_vee(0.05, BALL, 45.0)))
    result = _run(scene, temperature_change=20.0, body_material="6061-t6", base_material="52100")
    thermal = result.details["thermal"]
    centre = np.array(thermal["centre"])
    np.testing.assert_allclose(centre[:2], [0.0, 0.0], atol=1e-12)
    _, _, expected = _reference(scene, (ALU - STEEL) * 20.0)
    np.testing.assert_allclose(centre, expected, atol=1e-12)
    np.testing.assert_allclose(thermal["rotation"], 0.0, atol=1e-15)
    assert "thermal shift (+20 K)" in result.message and "thermal centre" in result.message


def test_three_vee_with_steel_balls_keeps_its_centre_in_the_plane(tmp_path):
    scene = _seated(coupling_scene(tmp_path, three_vee(0.05, BALL, 45.0)))
    result = _run(
        scene,
        ball_material="440c",  # balls of a third expansion coefficient
        temperature_change=-15.0,
        body_material="6061-t6",
        base_material="52100",
    )
    np.testing.assert_allclose(result.details["thermal"]["centre"][:2], [0, 0], atol=1e-12)


def test_kelvin_against_the_reference_and_its_socket(tmp_path):
    scene = _seated(coupling_scene(tmp_path, kelvin(0.05, BALL, 35.0)))
    d_t = 10.0
    beta = (ALU - STEEL) * d_t
    v, w, expected = _reference(scene, beta)
    socket = next(
        s.geometry.ball_center for s in scene.supports if s.geometry.kind == "ball-trihedral"
    )
    options = {"temperature_change": d_t, "body_material": "6061-t6", "base_material": "52100"}
    result = _run(scene, error_point=[30.0, -10.0, 15.0], **options)  # mm: the scene's units
    thermal = result.details["thermal"]
    np.testing.assert_allclose(thermal["centre"], expected, atol=1e-12)
    x = np.array([30.0, -10.0, 15.0]) * 1e-3
    np.testing.assert_allclose(thermal["shift"], v + np.cross(w, x) + beta * x, atol=1e-15)
    # the socket's ball cannot slide: its three flanks (35 deg from up) only let it rise by
    # the ball's growth against the base, beta r / cos 35 deg, straight up
    at_socket = _run(scene, error_point=list(socket / 1e-3), **options).details["thermal"]
    rise = beta * BALL / np.cos(np.radians(35.0))
    np.testing.assert_allclose(at_socket["shift"], [0.0, 0.0, rise], atol=1e-15)


def test_unknown_expansion_is_said_not_assumed(tmp_path):
    scene = _seated(coupling_scene(tmp_path, three_vee(0.05, BALL, 45.0)))
    result = _run(scene, temperature_change=5.0, body_material="6061-t6")
    assert "thermal shift not computed: the base's expansion" in result.message
    assert "thermal" in result.details and "centre" not in result.details["thermal"]


def test_same_expansion_has_no_centre(tmp_path):
    scene = _seated(coupling_scene(tmp_path, three_vee(0.05, BALL, 45.0)))
    result = _run(
        scene,
        ball_material="6061-t6",
        temperature_change=30.0,
        body_material="6061-t6",
        base_material="6061-t6",
    )
    thermal = result.details["thermal"]
    assert thermal["centre"] is None
    np.testing.assert_allclose(thermal["shift"], 0.0, atol=1e-18)
