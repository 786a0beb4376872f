"""``kcheck suggest`` end to end: a suggested design checks as safe with the reported margin.

The verification is independent of the search: the written scene file goes through the real
parser and the `analytical-3d` check, whose design margin must equal the reported one.
"""

from __future__ import annotations

import json
import shutil

import pytest

from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from tests.conftest import FIXTURES, PLANAR_SCENE

FAST = ("--points", "200", "--directions", "150")


def _analytical_3d(path):
    result = check_scene(path, [lc for lc in load_checks() if lc.spec.name != "hertz"])
    (check,) = [c for c in result.checks if c.id == "analytical-3d"]
    return check


@pytest.fixture
def fixture_copy(tmp_path):
    def copy(name):
        folder = tmp_path / name
        shutil.copytree(FIXTURES / name, folder)
        return folder

    return copy


def test_three_groove_suggestion_checks_safe(cli, fixture_copy):
    folder = fixture_copy("three-groove")
    out = folder / "suggested.kcheck.yaml"
    code, stdout, _ = cli(
        "suggest",
        str(folder / "coupling.kcheck.yaml"),
        *FAST,
        "--format",
        "json",
        "--write",
        str(out),
    )
    assert code == 0
    doc = json.loads(stdout)
    best = doc["best"][0]
    assert best["margin_deg"] > doc["design"]["margin_deg"] > 0  # better than the design
    check = _analytical_3d(out)
    assert check.status.value == "pass"
    assert check.details["design_margin_deg"] == pytest.approx(best["margin_deg"], abs=1e-6)
    assert all(c.outcome == "closes" for c in check.cases)


def test_block_321_original_design_is_not_placeable_at_10_newtons(cli, fixture_copy):
    # The 3-2-1 block's original design: 10 N along (-0.3, -0.4, -0.87) at the top face's
    # centre has no safe direction. No point of the surface has one at 10 N either (weight
    # 67.5 N, mu = 0.11); suggest says so and finds the least force that has one.
    folder = fixture_copy("block-321")
    scene = folder / "block.kcheck.yaml"
    scene.write_text(
        scene.read_text()
        .replace("magnitude: 50", "magnitude: 10")
        .replace("direction: [-0.57, -0.82, 0.04]", "direction: [-0.3, -0.4, -0.87]"),
        encoding="utf-8",
    )
    code, stdout, _ = cli("suggest", str(scene), *FAST, "--format", "json")
    assert code == 1
    doc = json.loads(stdout)
    assert doc["design"]["margin_deg"] < 0 and doc["best"][0]["margin_deg"] < 0
    least = doc["least_force"]
    assert 10 < least < 30
    # with that force (and a little more) a placement exists and checks safe as reported
    out = folder / "suggested.kcheck.yaml"
    code, stdout, _ = cli(
        "suggest",
        str(scene),
        *FAST,
        "--magnitude",
        f"{1.2 * least:.3g}",
        "--format",
        "json",
        "--write",
        str(out),
    )
    assert code == 0
    best = json.loads(stdout)["best"][0]
    assert best["margin_deg"] > 0
    check = _analytical_3d(out)
    assert check.details["design_margin_deg"] == pytest.approx(best["margin_deg"], abs=1e-6)
    assert all(c.outcome == "closes" for c in check.cases)


def test_text_report_and_picture(cli, tmp_path):
    pytest.importorskip("matplotlib")
    plot = tmp_path / "where.png"
    code, stdout, stderr = cli(
        "suggest",
        str(FIXTURES / "three-groove" / "coupling.kcheck.yaml"),
        *FAST,
        "--plot",
        str(plot),
        "--top",
        "2",
    )
    assert code == 0
    assert "design: at (0, 0, 24.5) mm along (0, 0, -1): margin 19.10°" in stdout
    assert "best: margin" in stdout and "pulls" in stdout
    assert plot.exists() and "wrote" in stderr  # PNG, as its suffix says
    assert not plot.with_suffix(".svg").exists()


def test_bad_input_is_exit_2(cli, write_scene, tmp_path):
    code, _, err = cli("suggest", str(write_scene(PLANAR_SCENE)))
    assert code == 2 and "give --box" in err  # no mesh to sample: a box is needed
    code, _, err = cli(
        "suggest", str(FIXTURES / "three-groove" / "coupling.kcheck.yaml"), "--magnitude", "-1"
    )
    assert code == 2 and "--magnitude must be positive" in err
    code, _, err = cli("suggest", str(tmp_path / "missing.kcheck.yaml"))
    assert code == 2 and "missing.kcheck.yaml" in err


@pytest.mark.slow
def test_suggestion_over_the_scene_friction_range(cli, fixture_copy):
    """`suggest` reads the scene's friction range (no option needed): the best candidate's
    margin is exact over the whole range — the margin analytical-3d reports for the written
    scene, which keeps the range — and `--friction MIN MAX` on a plain scene gives the same."""
    folder = fixture_copy("three-groove")
    scene = folder / "coupling.kcheck.yaml"
    plain = scene.read_text()
    ranged = folder / "ranged.kcheck.yaml"
    ranged.write_text(plain.replace("friction: 0.1", "friction: {min: 0.05, max: 0.15}"))
    out = folder / "suggested.kcheck.yaml"
    code, stdout, _ = cli("suggest", str(ranged), *FAST, "--format", "json", "--write", str(out))
    assert code == 0
    doc = json.loads(stdout)
    best = doc["best"][0]
    assert doc["friction"][0] == 0.05 and doc["friction"][-1] == 0.15
    check = _analytical_3d(out)
    assert check.details["friction_range"]["min"] == 0.05  # the range went into the file
    assert check.details["design_margin_deg"] == pytest.approx(best["margin_deg"], abs=1e-6)
    code, again, _ = cli(
        "suggest", str(scene), *FAST, "--format", "json", "--friction", "0.05", "0.15"
    )
    assert json.loads(again)["best"][0]["margin_deg"] == pytest.approx(best["margin_deg"])


def test_write_is_checked_before_the_search_and_read_back_as_written(cli, fixture_copy):
    # Fuzz finding (issue 13): `--write /dev/full` ended in a traceback after the search; and
    # the scene was written by PyYAML (YAML 1.1), so a name `1e3` came back as a number.
    folder = fixture_copy("three-groove")
    code, out, err = cli("suggest", str(folder / "coupling.kcheck.yaml"), "--write", "/dev/full")
    assert code == 2 and out == "" and err.startswith("kcheck: error: --write /dev/full")
    scene = folder / "coupling.kcheck.yaml"
    scene.write_text(scene.read_text().replace("name: three-groove", "name: '1e3' #"))
    code, _, _ = cli("suggest", str(scene), *FAST, "--write", str(folder / "s.kcheck.yaml"))
    assert code == 0
    from kcheck.scene import load_scene

    assert load_scene(folder / "s.kcheck.yaml").name == "1e3"


@pytest.mark.parametrize(
    "option",
    [["--magnitude", "inf"], ["--magnitude", "1e300"], ["--friction", "0", "1e308"]],
)
def test_numbers_past_the_scene_ranges_are_usage_errors(cli, option):
    # Fuzz finding (issue 13): `--magnitude inf` ran the search and printed numpy's
    # RuntimeWarning; `--friction 0 1e308` blamed the coupling ("no unique motion").
    scene = str(FIXTURES / "kelvin" / "coupling.kcheck.yaml")
    code, out, err = cli("suggest", scene, *option)
    assert code == 2 and out == ""
    assert "at most 1e+07" in err or "<= MAX <= 100" in err


def test_a_box_of_one_point_is_reported_as_one_point(cli):
    """`--box 0 0 0 0 0 0` is allowed (XMIN <= XMAX) and searches a single point: the report
    says "1 point in the box", not the number of (repeated) samples."""
    code, stdout, _ = cli(
        "suggest",
        str(FIXTURES / "three-groove" / "coupling.kcheck.yaml"),
        *FAST,
        "--box",
        *("0",) * 6,
    )
    assert code in (0, 1)
    assert "1 point in the box" in stdout and "points in the box" not in stdout


def test_planar_scene_suggestion_checks_safe(cli, write_scene, tmp_path):
    """A planar scene is searched (in a box: its body has no mesh); the written scene's
    analytical-2d design margin is the margin suggest reported."""
    from kcheck_checks.analytical_2d import Analytical2D, AnalyticalOptions

    from kcheck.body.mass import body_mass_properties
    from kcheck.plugin import Inputs
    from kcheck.scene import load_scene

    out = tmp_path / "suggested.kcheck.yaml"
    args = ("--box", "0", "0", "0", "100", "60", "0", "--points", "200", "--format", "json")
    code, stdout, _ = cli("suggest", str(write_scene(PLANAR_SCENE)), *args, "--write", str(out))
    assert code == 0
    best = json.loads(stdout)["best"][0]
    assert best["direction"][2] == 0.0 and best["margin_deg"] > 0
    scene = load_scene(out)
    mass = body_mass_properties(scene.body, scene.scale)
    check = Analytical2D().run(Inputs(scene, mass, AnalyticalOptions()))
    assert check.details["design_margin_deg"] == pytest.approx(best["margin_deg"], abs=1e-6)
