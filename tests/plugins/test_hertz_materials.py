"""Issue 21 items 1, 12, 13: `hertz` takes each contact's materials from the scene (never a
silent default), one material vocabulary for the body, its parts and `hertz`, and explicit
supports with local contact radii.

Reference values are closed forms computed here: the contact modulus ``1/E* = (1 - nu1^2)/E1 +
(1 - nu2^2)/E2`` and the sphere-on-flat peak pressure ``p0 = (6 P E*^2 / (pi^3 R^2))^(1/3)``
(Johnson, *Contact Mechanics*, §4.2), with the datasheet values of docs/materials.md typed in.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from kcheck_checks.hertz import Hertz
from kcheck_checks.hertz_materials import HertzOptions

from kcheck.gate.runner import check_scene
from kcheck.plugin import Inputs, load_checks
from kcheck.result import Status
from kcheck.scene import load_scene
from kcheck.scene.materials import ALIASES, TABLE, canonical, density_of, lookup
from tests.conftest import FIXTURES

ROOT = Path(__file__).resolve().parents[2]


def _p0_sphere_on_flat(force: float, radius: float, e1, nu1, e2, nu2) -> float:
    modulus = 1.0 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)
    return (6 * force * modulus**2 / (np.pi**3 * radius**2)) ** (1 / 3)


def _hertz(path: Path):
    result = check_scene(path, [lc for lc in load_checks() if lc.spec.name == "hertz"])
    assert result.error is None, result.error
    (check,) = [c for c in result.checks if c.id == "hertz"]
    return check


def _maxwell(tmp_path: Path, edit=lambda text: text) -> Path:
    folder = tmp_path / "maxwell"
    shutil.copytree(FIXTURES / "maxwell-three-vee", folder)
    path = folder / "coupling.kcheck.yaml"
    path.write_text(edit(path.read_text()), encoding="utf-8")
    return path


def test_maxwell_fixture_is_not_checked_without_its_ball_material(tmp_path):
    # the aluminium plate's grooves are known (the body's material); the balls' are not
    check = _hertz(_maxwell(tmp_path))
    assert check.status is Status.SKIPPED
    assert check.message.startswith("not checked: material of v1's ball unknown")
    assert {f.code for f in check.findings} == {"material-unknown"}
    assert "ball_material" in check.findings[0].hint
    assert "52100" not in check.message  # nothing assumed


def test_aluminium_grooves_fail_against_6061_t6(tmp_path):
    # 52100 balls (unquoted: YAML reads a number) in grooves cut into the aluminium plate
    path = _maxwell(
        tmp_path, lambda t: t.replace("ball_on: base,", "ball_on: base, ball_material: 52100,")
    )
    check = _hertz(path)
    assert check.status is Status.FAIL
    contact = check.details["contacts"][0]
    assert contact["ball_material"] == "52100"
    assert contact["seat_material"] == "aluminium" and contact["seat_material_grade"] == "6061-t6"
    assert contact["seat_material_from"] == "the body's material"
    # flat flanks: a sphere on a flat, from the contact's own normal force
    force = contact["normal_force_worst"]
    p0 = _p0_sphere_on_flat(force, 6e-3, 210e9, 0.30, 68.9e9, 0.33)
    assert contact["max_pressure_worst"] == pytest.approx(p0, rel=1e-10)
    allowable = 1.60 * 276e6  # Johnson's first yield of 6061-T6 (ASM: Y = 276 MPa)
    assert contact["allowable_pressure"] == pytest.approx(allowable)
    assert check.details["max_utilisation"] == pytest.approx(p0 / allowable, rel=1e-10)
    assert "materials: 52100 balls on aluminium (as 6061-t6) seats" in check.message
    assert check.findings[0].message.startswith(
        "v1.1 (52100 ball on aluminium (as 6061-t6) seat): peak pressure"
    )
    assert "aluminium (as 6061-t6)'s allowable 442 MPa" in check.findings[0].message
    # issue 28: the largest von Mises stress below the seat, on the axis of a circular contact
    # (Johnson eq. 3.46, maximised here): sigma_z - sigma_r at its worst depth
    from scipy.optimize import minimize_scalar

    def mises(zeta, nu=0.33):
        sz = -1.0 / (1.0 + zeta**2)
        sr = -(1.0 + nu) * (1.0 - zeta * np.arctan(1.0 / zeta)) + 0.5 / (1.0 + zeta**2)
        return abs(sz - sr)

    best = minimize_scalar(lambda z: -mises(z), bounds=(0.1, 2), method="bounded")
    seat = contact["subsurface"]["seat"]
    assert seat["von_mises"] == pytest.approx(-best.fun * p0, rel=1e-6)
    assert seat["yield_utilisation"] == pytest.approx(-best.fun * p0 / 276e6, rel=1e-6)
    assert check.details["max_yield_utilisation"] == pytest.approx(seat["yield_utilisation"])


def test_scene_fields_come_before_the_options(tmp_path):
    # per coupling in the scene > per coupling in the options > the body > global options
    path = _maxwell(
        tmp_path,
        lambda t: (
            t.replace(
                "name: v1, type: ball-vee, ball_on: base,",
                "name: v1, type: ball-vee, ball_on: base, seat_material: '440C',",
            )
            + "checks:\n  hertz:\n    ball_material: silicon-nitride\n    seat_material: steel\n"
            "    couplings: {v2: {seat: Ti-6Al-4V}}\n"
        ),
    )
    contacts = {c["support"]: c for c in _hertz(path).details["contacts"]}
    assert contacts["v1.1"]["seat_material"] == "440c"
    assert contacts["v1.1"]["seat_material_from"] == "couplings[0].seat_material"
    assert contacts["v2.1"]["seat_material"] == "ti-6al-4v"
    assert contacts["v3.1"]["seat_material"] == "aluminium"  # cut into the body
    assert contacts["v3.1"]["ball_material"] == "silicon-nitride"
    assert contacts["v3.1"]["ball_material_from"] == "checks.hertz.ball_material"


def test_a_material_without_elastic_constants_is_not_checked(tmp_path):
    path = _maxwell(
        tmp_path,
        lambda t: (
            t.replace("material: aluminium", "material: granite")
            + "checks: {hertz: {ball_material: 52100}}\n"
        ),
    )
    check = _hertz(path)
    assert check.status is Status.SKIPPED
    assert "material of v1's seat (granite) has no elastic constants" in check.message
    assert "checks: hertz: materials" in check.findings[0].hint


def test_parts_of_several_materials_need_the_seat_named(tmp_path):
    path = _maxwell(
        tmp_path,
        lambda t: (
            t.replace(
                "body: {mesh: plate.stl, material: aluminium}",
                "body: {parts: [{mesh: plate.stl, material: 6061-T6}, "
                "{mesh: plate.stl, material: steel}]}",
            )
            + "checks: {hertz: {ball_material: 52100}}\n"
        ),
    )
    check = _hertz(path)
    assert check.status is Status.SKIPPED
    assert "v1's seat unknown" in check.message
    assert "parts are of several materials" in check.findings[0].hint


def test_unknown_material_in_a_coupling_is_a_located_error(tmp_path):
    path = _maxwell(
        tmp_path, lambda t: t.replace("ball_on: base,", "ball_on: base, ball_material: mithril,", 1)
    )
    with pytest.raises(Exception, match=r"couplings\[0\]\.ball_material.*unknown material"):
        load_scene(path)


# --- one vocabulary ----------------------------------------------------------------------

REQUIRED = {
    "52100": "52100",
    "440C": "440c",
    "17-4PH H900": "17-4ph-h900",
    "6061-T6": "6061-t6",
    "7075-T6": "7075-t6",
    "Ti-6Al-4V": "ti-6al-4v",
    "silicon nitride": "silicon-nitride",
    "zirconia": "zirconia",
    "tungsten carbide": "tungsten-carbide",
}


@pytest.mark.parametrize(("written", "name"), REQUIRED.items())
def test_the_table_covers_the_required_materials(written, name):
    m = lookup(written)
    assert m is not None and m.name == name and m.elastic
    assert m.density and m.thermal_expansion is not None and m.source and m.basis
    assert 0 < m.poisson < 0.5 and 1e9 < m.youngs_modulus < 1e12
    if m.yield_strength is not None and "first yield" in m.basis:
        assert m.allowable_pressure == pytest.approx(1.60 * m.yield_strength)  # Johnson §6.2
    if "ring crack" in m.basis:  # p0 = 3 sigma_f / (1 - 2 nu), Johnson §4.2
        sigma = float(re.search(r"strength (\d+) MPa", m.basis).group(1)) * 1e6
        assert m.allowable_pressure == pytest.approx(3 * sigma / (1 - 2 * m.poisson))


def test_allowable_comes_from_the_material_not_a_bearing_steel_default():
    allowables = {lookup(n).allowable_pressure for n in REQUIRED}
    assert len(allowables) == len(REQUIRED)  # each its own
    assert lookup("52100").allowable_pressure == 4200e6  # ISO 76's static rating


def test_families_keep_their_density_and_name_their_grade():
    steel = lookup("steel")
    assert steel.density == 7850.0 and steel.grade == "aisi-1018"
    assert steel.youngs_modulus == lookup("aisi-1018").youngs_modulus
    assert lookup("stainless-steel").label == "stainless-steel (as stainless-304)"
    assert density_of("aluminum") == 2700.0 and lookup("aluminum").grade == "6061-t6"


def test_numbers_and_spellings_are_one_name():
    assert canonical(52100) == canonical("52100") == canonical("100Cr6") == "52100"
    assert canonical("Stainless_Steel") == "stainless-steel"
    assert canonical("17-4PH") == "17-4ph-h900"
    assert canonical("unobtainium") is None


def test_steel_and_stainless_steel_are_accepted_by_the_hertz_options():
    options = HertzOptions(ball_material="steel", seat_material="stainless-steel")
    assert options.lookup("steel").elastic
    numeric = HertzOptions.model_validate(
        {"ball_material": 52100, "couplings": {"a": {"seat": 304}}}
    )
    assert numeric.ball_material == "52100" and numeric.couplings["a"].seat == "304"


def test_unquoted_52100_as_the_body_material(tmp_path):
    path = _maxwell(tmp_path, lambda t: t.replace("material: aluminium", "material: 52100"))
    scene = load_scene(path)
    assert scene.body.materials == ("52100",)
    assert scene.body.parts[0].density == 7810.0


def test_every_name_and_alias_is_documented():
    doc = (ROOT / "docs" / "materials.md").read_text()
    for name in (*TABLE, *ALIASES):
        assert f"`{name}`" in doc, name


# --- explicit supports with contact radii -------------------------------------------------


def _three_groove(tmp_path: Path, contact: str) -> Path:
    folder = tmp_path / "tg"
    shutil.copytree(FIXTURES / "three-groove", folder)
    path = folder / "coupling.kcheck.yaml"
    text = path.read_text().split("checks:")[0]
    text = re.sub(r"(normal: \[[^\]]*\])\}", rf"\1, contact: {contact}}}", text)
    path.write_text(text, encoding="utf-8")
    return path


def test_explicit_supports_with_a_ball_radius_are_checked(tmp_path):
    # the three-groove fixture's balls (radius 6 mm, on the steel plate) on flat flanks
    path = _three_groove(
        tmp_path, "{ball_radius: 6, ball_on: body, ball_material: 52100, seat_material: 440C}"
    )
    check = _hertz(path)
    assert check.status is Status.PASS, check.message
    for c in check.details["contacts"]:
        p0 = _p0_sphere_on_flat(c["normal_force"], 6e-3, 210e9, 0.30, 200e9, 0.28)
        assert c["max_pressure"] == pytest.approx(p0, rel=1e-10)
        assert c["seat_material_from"].endswith(".contact.seat_material")
    assert "materials: 52100 balls on 440c seats" in check.message


def test_explicit_ball_on_a_pin_is_elliptical(tmp_path):
    # a ball (R = 6 mm) on a pin (r = 2 mm) along x: A = 1/(2R), B = (1/R + 1/r)/2
    path = _three_groove(
        tmp_path,
        "{ball_radius: 6, ball_on: body, seat_radii: [null, 2], seat_direction: [0, 0, 1], "
        "ball_material: 52100, seat_material: 52100}",
    )
    for c in _hertz(path).details["contacts"]:
        assert c["curvature_sums"] == pytest.approx([0.5 / 6e-3, 0.5 / 6e-3 + 0.5 / 2e-3])


def test_explicit_seat_radii_without_a_direction_is_a_located_error(tmp_path):
    path = _three_groove(tmp_path, "{ball_radius: 6, seat_radii: [null, 2]}")
    with pytest.raises(Exception, match=r"supports\[0\]\.contact\.seat_direction"):
        load_scene(path)


def test_explicit_supports_without_contact_say_how_to_give_it(tmp_path):
    folder = tmp_path / "b"
    shutil.copytree(FIXTURES / "block-321", folder)
    path = folder / "block.kcheck.yaml"
    path.write_text(path.read_text().split("checks:")[0], encoding="utf-8")
    check = _hertz(path)
    assert check.status is Status.SKIPPED
    assert check.message.startswith("not checked:") and "contact: {ball_radius" in check.message


def test_check_run_directly_reports_unknown_materials(tmp_path):
    path = _three_groove(tmp_path, "{ball_radius: 6, ball_on: body}")
    scene = load_scene(path)
    result = Hertz().run(Inputs(scene, None, HertzOptions()))
    # the seat is on the base (ball on the body): no body material applies to it
    assert result.status is Status.SKIPPED
    assert result.message.startswith("not checked: material of g1a's ball unknown")
    assert {(u["coupling"], u["side"]) for u in result.details["unknown_materials"]} >= {
        ("g1a", "ball"),
        ("g1a", "seat"),
    }


def test_expanded_scene_checks_as_the_original(tmp_path):
    from kcheck.cli.expand import expanded_text

    path = _maxwell(
        tmp_path, lambda t: t.replace("ball_on: base,", "ball_on: base, ball_material: 52100,")
    )
    expanded = path.with_name("expanded.kcheck.yaml")
    expanded.write_text(expanded_text(path), encoding="utf-8")
    original, again = _hertz(path), _hertz(expanded)
    assert again.status is original.status is Status.FAIL
    assert again.details["max_utilisation"] == pytest.approx(
        original.details["max_utilisation"], rel=1e-9
    )
    assert again.details["materials"] == original.details["materials"]


def test_the_picture_names_the_materials(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    import kcheck_checks.pictures.hertz as picture

    titles = []

    def keep(fig, directory, name):
        titles.append(fig._suptitle.get_text())
        return []

    monkeypatch.setattr(picture, "save", keep)
    path = _maxwell(tmp_path, lambda t: t + "checks: {hertz: {ball_material: 440c}}\n")
    scene = load_scene(path)
    from kcheck.body.mass import body_mass_properties

    inputs = Inputs(scene, body_mass_properties(scene.body), HertzOptions(ball_material="440c"))
    result = Hertz().run(inputs)
    Hertz().plot(inputs, result, tmp_path / "plots")
    assert "materials: 440c balls on aluminium (as 6061-t6) seats" in titles[0]


def test_headline_names_the_seat_material_too_when_balls_and_seats_are_unknown():
    # the three-groove fixtures name no material at all: balls and seats both unknown
    check = _hertz(FIXTURES / "three-groove-beta-45" / "coupling.kcheck.yaml")
    assert check.status is Status.SKIPPED
    assert {u["side"] for u in check.details["unknown_materials"]} == {"ball", "seat"}
    assert "`ball_material`" in check.message
    assert "`seat_material`" in check.message
