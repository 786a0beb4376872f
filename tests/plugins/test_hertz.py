"""The `hertz` check on coupling scenes built from the shorthands' contact formulas.

Reference values:

* closed forms: a symmetric three-vee pressed down by ``F`` per ball carries ``F / (2 cos b)``
  on each contact, a ball on a flat has Johnson's sphere-on-flat contact (tests/kcheck/
  test_hertz.py), and the vertical point stiffness on the axis is ``6 k cos^2 b``;
* the published example: A. Slocum's three-groove design spreadsheet
  ``Kinematic_Coupling_3Groove_Design.xls`` (MIT PERG, last modified 2012-10-28, as shown at
  vdocuments.us/kinematic-coupling-20121028.html), see test_slocum_spreadsheet_example.
"""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pytest
from kcheck_checks.hertz import Hertz
from kcheck_checks.hertz_materials import HertzOptions

from kcheck.gate.runner import check_scene
from kcheck.mechanics.hertz import contact_modulus, hertz
from kcheck.plugin import Inputs, load_checks
from kcheck.result import MassProperties, Status
from kcheck.scene import Preload, load_scene
from tests.conftest import FIXTURES
from tests.couplings import ball_cylinders, coupling_scene, kelvin, three_vee, with_preloads

BALL = 6e-3
BETA = 45.0


def _run(scene, mass=None, **options):
    """Run hertz; 52100 balls and seats unless the test names other materials (the check has
    no default material: tests/plugins/test_hertz_materials.py)."""
    options = {"ball_material": "52100", "seat_material": "52100"} | options
    check = Hertz()
    assert check.skip_reason(scene) is None
    return check.run(Inputs(scene, mass, HertzOptions(**options)))


def _ball_preloads(scene, force):
    centres = {s.geometry.coupling: s.geometry.ball_center for s in scene.supports}
    return [Preload(f"spring {n}", c, np.asarray(force, float)) for n, c in centres.items()]


@pytest.fixture
def three_vee_scene(tmp_path):
    scene = coupling_scene(tmp_path, three_vee(0.05, BALL, BETA))
    return with_preloads(scene, _ball_preloads(scene, [0.0, 0.0, -200.0]))


def test_three_vee_closed_forms(three_vee_scene):
    result = _run(three_vee_scene)
    assert result.status is Status.PASS, result.message
    contacts = result.details["contacts"]
    force = 200.0 / (2 * np.cos(np.radians(BETA)))
    modulus = contact_modulus(210e9, 0.3, 210e9, 0.3)
    a = (3 * force * BALL / (4 * modulus)) ** (1 / 3)
    for c in contacts:
        assert c["normal_force"] == pytest.approx(force, rel=1e-12)
        assert c["semi_axes"] == pytest.approx([a, a], rel=1e-12)
        assert c["max_pressure"] == pytest.approx(3 * force / (2 * np.pi * a * a), rel=1e-12)
        assert c["stiffness"] == pytest.approx(2 * modulus * a, rel=1e-12)
        assert c["allowable_pressure"] == 4.2e9
    # a force on the axis moves a point on the axis straight along it: 6 k cos^2(beta)
    kz = result.details["point_stiffness"][2]
    assert kz == pytest.approx(6 * 2 * modulus * a * np.cos(np.radians(BETA)) ** 2, rel=1e-10)
    big_k = np.array(result.details["stiffness_matrix"])
    assert big_k.shape == (6, 6) and np.all(np.linalg.eigvalsh(big_k) > 0)
    assert "peak contact pressure" in result.message and "N/µm" in result.message
    assert result.error_estimate < 1e-12


def test_disturbing_load_error_motion(three_vee_scene):
    result = _run(
        three_vee_scene,
        disturbing_force=[0.0, 0.0, -30.0],
        error_point=[0.0, 0.0, 30.0],
    )
    motion = result.details["error_motion"]
    # down the axis: the exact Hertz law gives dz = -(delta(N1) - delta(N0)) / cos(beta)
    cos = np.cos(np.radians(BETA))
    modulus = contact_modulus(210e9, 0.3, 210e9, 0.3)
    n0, n1 = 200.0 / (2 * cos), 210.0 / (2 * cos)  # 30 N over three balls
    d0, d1 = (hertz(n, 0.5 / BALL, 0.5 / BALL, modulus).approach for n in (n0, n1))
    np.testing.assert_allclose(motion["translation"], [0, 0, -(d1 - d0) / cos], atol=1e-16)
    np.testing.assert_allclose(motion["rotation"], 0.0, atol=1e-15)
    assert result.details["contacts"][0]["normal_force_worst"] == pytest.approx(n1, rel=1e-12)
    assert "error motion" in result.message


def test_kelvin_with_weight_and_materials(tmp_path):
    body = {"mass": 2.0, "center_of_mass": [0, 0, 20], "inertia": np.diag([1e-3] * 3).tolist()}
    scene = coupling_scene(
        tmp_path, kelvin(0.05, BALL, 35.0), {"body": body, "gravity": [0, 0, -9.81]}
    )
    mass = MassProperties(2.0, np.array([0, 0, 0.02]), np.eye(3) * 1e-3, "explicit")
    result = _run(
        scene,
        mass,
        ball_material="si3n4",
        seat_material="aluminium-6061-t6",
        couplings={"flat": {"seat": "hard"}},
        materials={
            "hard": {"youngs_modulus_gpa": 200, "poisson": 0.3, "allowable_pressure_mpa": 9}
        },
        error_point=[0.0, 0.0, 20.0],
        disturbing_force=[0.1, 0.0, 0.0],
    )
    contacts = {c["support"]: c for c in result.details["contacts"]}
    assert contacts["cone.1"]["seat_material"] == "6061-t6"
    assert contacts["cone.1"]["seat_material_from"] == "checks.hertz.seat_material"
    assert contacts["flat.1"]["seat_material"] == "hard"
    assert contacts["flat.1"]["allowable_pressure"] == pytest.approx(9e6)
    # the weight balances: sum of contact forces along the normals equals m g
    normals = np.array([s.normal for s in scene.supports])
    forces = np.array([contacts[s.name]["normal_force"] for s in scene.supports])
    np.testing.assert_allclose(forces @ normals, [0, 0, 2.0 * 9.81], atol=1e-12)
    # the flat's 9 MPa allowable fails, located at its coupling entry, with a hint
    assert result.status is Status.FAIL
    (finding,) = result.findings
    # located where the test scene file writes the flat's contact (explicit supports)
    assert finding.code == "contact-stress" and finding.field == ("supports", 5)
    assert "flat.1" in finding.message and "hard's allowable 9 MPa" in finding.message
    assert "larger ball" in finding.hint
    assert "error_motion" in result.details


def test_dowel_pins_are_elliptical(tmp_path):
    contacts = ball_cylinders("tool", [0, 0, 0], 5e-3, [1, 0, 0], 1.5e-3, 45.0)
    contacts += ball_cylinders("b", [0.04, 0.03, 0], 5e-3, [0, 1, 0], 1.5e-3, 45.0)
    contacts += ball_cylinders("c", [-0.04, 0.03, 0], 5e-3, [1, 1, 0], 1.5e-3, 45.0)
    scene = coupling_scene(tmp_path, contacts)
    scene = with_preloads(scene, _ball_preloads(scene, [0, 0, -20.0]))
    result = _run(scene)
    for c in result.details["contacts"]:
        # ball 1/R both ways, pin 1/r across its axis: A = 1/(2R), B = (1/R + 1/r)/2
        assert c["curvature_sums"] == pytest.approx([0.5 / 5e-3, 0.5 / 5e-3 + 0.5 / 1.5e-3])
        a, b = c["semi_axes"]
        assert b < a
        # the long axis runs along the pin
        axis = np.array(c["major_axis"])
        pin = {"tool": [1, 0, 0], "b": [0, 1, 0], "c": [0.5**0.5, 0.5**0.5, 0]}[c["coupling"]]
        assert abs(axis @ np.array(pin)) == pytest.approx(1.0, abs=1e-12)


def test_lifting_off_and_opening_are_findings(tmp_path):
    scene = coupling_scene(tmp_path, three_vee(0.05, BALL, BETA))
    # one spring pulls up beside ball g1: g1 is unloaded
    off = [Preload("tilt", np.array([0.0, 0.05, 0.0]), np.array([0, 0, 50.0]))]
    off += [Preload("hold", np.array([0.0, -0.02, 0.0]), np.array([0, 0, -60.0]))]
    result = _run(with_preloads(scene, off))
    assert result.status is Status.FAIL
    assert {f.code for f in result.findings} == {"lifts-off"}
    # issue 21 item 9: the lift-off is the headline, and no stress of a pulling solution
    assert result.message.startswith("the body lifts off at g1.1, g1.2 under the seated load")
    assert "contacts" not in result.details and "peak contact pressure" not in result.message
    assert all(result.details["seated_forces"][n] < 0 for n in result.details["lifted"])
    # the first coupling's contacts: the first two items the test scene file writes
    assert {f.field for f in result.findings} <= {("supports", 0), ("supports", 1)}
    assert "would have to pull" in result.findings[0].message
    seated = with_preloads(scene, _ball_preloads(scene, [0, 0, -10.0]))
    result = _run(seated, disturbing_force=[0.0, 0.0, 100.0])
    assert {f.code for f in result.findings} == {"opens-under-disturbance"}
    assert "error_motion" not in result.details
    # stresses shown only where the contact presses: an opened contact carries none
    worst = [c["normal_force_worst"] for c in result.details["contacts"]]
    assert min(c["max_pressure_worst"] for c in result.details["contacts"]) >= 0
    assert all(w >= 0 for w in worst)


def test_explicit_supports_are_skipped_with_the_reason(tmp_path):
    folder = tmp_path / "tg"
    shutil.copytree(FIXTURES / "three-groove", folder)
    scene = folder / "coupling.kcheck.yaml"
    # only the hertz check: the fixture's options for the others go
    scene.write_text(scene.read_text().split("checks:")[0], encoding="utf-8")
    result = check_scene(scene, [lc for lc in load_checks() if lc.spec.name == "hertz"])
    (check,) = [c for c in result.checks if c.id == "hertz"]
    assert check.status is Status.SKIPPED
    assert "g1a, g1b, g2a, g2b, ..." in check.message and "couplings:" in check.message


def test_unknown_material_is_a_located_input_error(tmp_path):
    folder = tmp_path / "tg"
    shutil.copytree(FIXTURES / "three-groove", folder)
    scene = folder / "coupling.kcheck.yaml"
    scene.write_text(
        scene.read_text() + "  hertz: {ball_material: unobtainium}\n", encoding="utf-8"
    )
    result = check_scene(scene, load_checks())
    assert result.status is Status.ERROR
    assert "unknown material(s) unobtainium" in result.error
    assert result.errors[0].line is not None and "checks.hertz" in result.error


def test_unknown_coupling_name_is_reported(three_vee_scene):
    result = _run(three_vee_scene, couplings={"nope": {"ball": "440c"}})
    assert result.status is Status.ERROR and "nope" in result.message


def test_json_has_the_stiffness_matrix(three_vee_scene):
    doc = _run(three_vee_scene, disturbing_torque=[0.0, 0.0, 0.01]).to_json()
    assert len(doc["stiffness_matrix"]) == 6 and len(doc["stiffness_matrix"][0]) == 6
    for key in ("reference_point", "seated_load", "contacts", "point_stiffness", "error_motion"):
        assert key in doc
    assert doc["error_motion"]["rotation"][2] > 0  # a ccw torque turns the body ccw


def test_slocum_spreadsheet_example(tmp_path):
    """A. Slocum's three-groove design spreadsheet (2012 version), its example design:
    steel "canoe" balls with 500 mm surface radii on flat groove flanks (RC 62 steel, E = 204
    GPa, nu = 0.29), equivalent ball diameter 35 mm, coupling diameter 625 mm, 15 kN preload
    over each ball, 30 kN applied at 10° from the axis at z = 1320.8 mm. The groove angle and
    ball azimuths are not in the published page: 45° flanks with balls at 90/210/330° reproduce
    its largest contact ellipse, as below.

    Spreadsheet: largest contact-ellipse major diameter 8.778 mm. kcheck: 8.752 mm (-0.30 %).
    The spreadsheet takes the ellipse coefficient from Slocum's curve fit
    alpha = 1.939 exp(-5.26 t) + 1.78 exp(-1.09 t) + 0.723 / t + 0.221, t = 90° for a circular
    contact, = 1.0031 where the exact value is 1: 8.752 * 1.0031 = 8.779.
    Its "Z displacement caused by preload" 0.015 mm is half kcheck's 0.0307 mm = delta /
    cos 45° (the ball sinks into the vee by the approach over the cosine); 0.015 mm is
    delta * cos 45°, the approach projected instead of divided: a factor cos^2 45° = 1/2.
    """
    contacts = three_vee(0.3125, 0.0175, 45.0)
    contacts = [
        (p, n, dataclasses.replace(g, body=dataclasses.replace(g.body, radii=(0.5, 0.5))))
        for p, n, g in contacts
    ]
    scene = coupling_scene(tmp_path, contacts)
    scene = with_preloads(scene, _ball_preloads(scene, [0, 0, -15000.0]))
    steel = {"youngs_modulus_gpa": 204.0, "poisson": 0.29, "allowable_pressure_mpa": 1720 * 1.6}
    inclination = np.radians(10.0)
    result = _run(
        scene,
        ball_material="rc62",
        seat_material="rc62",
        materials={"rc62": steel},
        disturbing_force=[0.0, -30000 * np.sin(inclination), -30000 * np.cos(inclination)],
        error_point=[0.0, 0.0, 1320.8],
    )
    # the most loaded contact, its ellipse from the check's peak pressure: a^2 = 3P/(2 pi p0)
    worst = max(result.details["contacts"], key=lambda c: c["normal_force_worst"])
    a_worst = np.sqrt(3 * worst["normal_force_worst"] / (2 * np.pi * worst["max_pressure_worst"]))
    assert 2e3 * a_worst == pytest.approx(8.752, abs=5e-4)
    assert 2e3 * a_worst * 1.00306 == pytest.approx(8.778, abs=1.5e-3)
    # preload sink: delta / cos 45°, twice the spreadsheet's 0.015 mm
    seated = result.details["contacts"][0]
    sink = seated["approach"] / np.cos(np.radians(45.0))
    assert sink * 1e3 == pytest.approx(0.0307, abs=1e-4)
    assert sink * np.cos(np.radians(45.0)) ** 2 * 1e3 == pytest.approx(0.015, abs=5e-4)
    # "largest stress ratio" 0.22: the largest subsurface shear, taken as 0.3 p0, over the
    # Tresca shear yield 0.5 Y (Y = 1720 MPa): 0.3 p0 / (0.5 Y) = 0.217 rounds to it; kcheck's
    # exact largest shear (0.31 p0 for a circle, nu = 0.29) gives 0.225
    p0, shear_yield = worst["max_pressure_worst"], 0.5 * 1720e6
    assert round(0.3 * p0 / shear_yield, 2) == 0.22
    tau = worst["subsurface"]["seat"]["max_shear"]
    assert tau / p0 == pytest.approx(0.31, abs=0.005)
    assert tau / shear_yield == pytest.approx(0.225, abs=0.001)


def test_hint_scales_the_radii_to_the_allowable(tmp_path):
    # p0 ~ (P E*^2 / R^2)^(1/3): radii u^(3/2) times larger bring utilisation u down to 1.
    # Preloads at the ball centres keep the contact forces whatever the ball radius.
    def run(radius):
        scene = coupling_scene(tmp_path, three_vee(0.05, radius, BETA))
        scene = with_preloads(scene, _ball_preloads(scene, [0, 0, -200.0]))
        return _run(scene, seat_material="aluminium-6061-t6")

    result = run(BALL)
    u = result.details["max_utilisation"]
    assert u > 1 and f"radii {u**1.5:.2g}x larger" in result.findings[0].hint
    assert run(BALL * u**1.5).details["max_utilisation"] == pytest.approx(1.0, rel=1e-10)


def test_picture(three_vee_scene, tmp_path):
    pytest.importorskip("matplotlib")
    options = HertzOptions(
        disturbing_force=[5.0, 0, 0],
        error_point=[0, 0, 30.0],
        ball_material="52100",
        seat_material="52100",
    )
    inputs = Inputs(three_vee_scene, None, options)
    result = Hertz().run(inputs)
    from kcheck.pictures.plotting import formats

    files = Hertz().plot(inputs, result, tmp_path / "plots")  # PNG by default
    assert [f.suffix for f in files] == [".png"] and files[0].stat().st_size
    with formats(("png", "svg")):
        files = Hertz().plot(inputs, result, tmp_path / "both")
    assert [f.suffix for f in files] == [".png", ".svg"] and all(f.stat().st_size for f in files)


def test_large_contacts_are_flagged(tmp_path):
    # a PLA ball pressed hard: a/R = a * 2B, large, so Hertz theory (half-spaces) is approximate
    scene = coupling_scene(tmp_path, three_vee(0.05, BALL, BETA))
    scene = with_preloads(scene, _ball_preloads(scene, [0, 0, -2000.0]))
    result = _run(scene, ball_material="pla", seat_material="pla")
    sizes = [c["semi_axes"][0] / BALL for c in result.details["contacts"]]
    assert max(sizes) > 0.1
    assert f"a/R up to {max(sizes):.2g}" in result.message and result.details["notes"]


def test_singular_layout_is_reported_not_solved(tmp_path):
    # six balls on flats whose normals all pass through one point: rotations about it are free
    from tests.couplings import BALL_FLAT, ball_contacts

    apex = np.array([0.0, 0.0, 0.08])
    contacts = []
    for k in range(6):
        phi = np.radians(60.0 * k)
        centre = 0.05 * np.array([np.cos(phi), np.sin(phi), 0.0])
        contacts += ball_contacts(f"b{k}", "ball-flat", centre, BALL, [apex - centre], [BALL_FLAT])
    scene = coupling_scene(tmp_path, contacts)
    scene = with_preloads(scene, _ball_preloads(scene, [0, 0, -10.0]))
    result = _run(scene)
    assert result.status is Status.FAIL and "singular" in result.message
    assert result.details["condition"] > 1e12 and "contacts" not in result.details


def test_picture_when_no_contact_carries_load(tmp_path):
    # Fuzz finding (suite seed 13, extreme-13-5): the closing force of three-groove-beta-35
    # turned to +z lifts every ball, so every contact ellipse is a point; the ellipse panel
    # set equal y-limits and matplotlib printed a UserWarning on stderr.
    import warnings

    pytest.importorskip("matplotlib")
    folder = tmp_path / "scene"
    shutil.copytree(FIXTURES / "three-groove-beta-35", folder)
    path = folder / "coupling.kcheck.yaml"
    path.write_text(path.read_text().replace("direction: [0, 0, -1]", "direction: [0, 0, 1]"))
    options = HertzOptions(ball_material="52100", seat_material="52100")
    inputs = Inputs(load_scene(path), None, options)
    result = Hertz().run(inputs)
    # every contact would pull: the lift-off is the result, with no stresses to draw
    assert "lifts off" in result.message and "contacts" not in result.details
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        files = Hertz().plot(inputs, result, tmp_path / "plots")
    assert files == []


def test_three_vee_vertical_stiffness_with_mindlin_tangential_compliance(three_vee_scene):
    # Johnson §7.2: no-slip tangential stiffness k_t = 8 G* a, 1/G* = 2 (2 - nu) / G for two
    # equal materials; with k_n = 2 E* a, k_t / k_n = 2 (1 - nu) / (2 - nu) (Mindlin).
    result = _run(three_vee_scene)
    nu, e = 0.3, 210e9
    g = e / (2 * (1 + nu))
    a = result.details["contacts"][0]["semi_axes"][0]
    k_n = 2 * contact_modulus(e, nu, e, nu) * a
    k_t = 8 * a / (2 * (2 - nu) / g)
    assert k_t / k_n == pytest.approx(2 * (1 - nu) / (2 - nu), rel=1e-12)
    for c in result.details["contacts"]:
        assert c["tangential_stiffness"] == pytest.approx(k_t, rel=1e-12)
    # straight down the axis every contact moves by dz: cos(b) dz along its normal, sin(b) dz
    # in its tangent plane, so k_z = 6 (k_n cos^2 b + k_t sin^2 b)
    b = np.radians(BETA)
    kz = result.details["point_stiffness_with_tangential"][2]
    assert kz == pytest.approx(6 * (k_n * np.cos(b) ** 2 + k_t * np.sin(b) ** 2), rel=1e-10)
    assert kz > result.details["point_stiffness"][2]
