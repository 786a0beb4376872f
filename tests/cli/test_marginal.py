"""The marginal band (issue 21): a pass closer to its failure line than the check's minimum
margin is ``marginal``, for every margin kind, in every format, failing only with --strict.

For each kind, a scene just above its failure line is marginal, one comfortably above passes
and one below fails. Where the scene itself is moved (the design angle, the friction), the
reference is the check's own failure line read from a run (the safe range's end, the least
holding friction), and the band's decision is checked against it; where a margin scales
exactly with an option (Hertz utilisation with the safety factor, the tolerance pass
probability's Clopper–Pearson bound (α/2)^(1/n) when every sample passes), the value is the
closed form.
"""

from __future__ import annotations

import json
import math
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import yaml

from kcheck.numerics.margins import (
    MARGINAL_ANGLE_DEG,
    MARGINAL_COS,
    MARGINAL_FRICTION_RATIO,
    MARGINAL_PASS_PROBABILITY,
    MARGINAL_UTILISATION,
)
from tests.conftest import FIXTURES, PLANAR_SCENE

TOLERANCES = "tolerances: {position: 0.05, normal: 0.5, load_direction: 2}\n"


def _with(text: str, **fields: object) -> str:
    """A scene's YAML text with top-level fields replaced."""
    data = yaml.safe_load(text)
    data.update(fields)
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def _check(doc: dict, check_id: str) -> dict:
    (scene,) = doc["scenes"]
    return next(c for c in scene["checks"] if c["id"] == check_id)


def _run(cli_json, path: Path, check_id: str, *args: str) -> dict:
    _, doc = cli_json(str(path), "--select", check_id, "--no-cache", *args)
    return _check(doc, check_id)


# --- force-angle margin: analytical-2d and graphical-2d move the design angle ---------------


@pytest.mark.parametrize("check_id", ["analytical-2d", "graphical-2d"])
def test_force_angle_margin_bands(write_scene, cli_json, check_id):
    base = _run(cli_json, write_scene(PLANAR_SCENE), check_id)
    ((start, end),) = base["safe_ranges_deg"]  # the failure line: the safe range's ends
    assert end - start > 4 * MARGINAL_ANGLE_DEG
    expected = {
        start + 0.5 * MARGINAL_ANGLE_DEG: "marginal",  # just inside the range
        (start + end) / 2: "pass",  # the middle
        start - 1.0: "fail",  # just outside
    }
    for angle, status in expected.items():
        path = write_scene(_with(PLANAR_SCENE, load={"magnitude": 1, "angle": float(angle)}))
        result = _run(cli_json, path, check_id)
        assert result["status"] == status, (angle, result["message"])
        if status != "fail":
            margin = min(angle - start, end - angle)
            assert result["margin"]["value"] == pytest.approx(margin, abs=1e-6)
            assert result["margin"]["limit"] == MARGINAL_ANGLE_DEG
        if status == "marginal":
            codes = [f.get("code") for f in result["findings"]]
            assert codes == ["marginal"]
            assert "turn the force" in result["findings"][0]["hint"]


def _fixture_copy(tmp_path: Path, name: str) -> Path:
    """A copy of a fixture's folder (scene and meshes); the scene's path."""
    folder = shutil.copytree(FIXTURES / name, tmp_path / name)
    (scene,) = Path(folder).glob("*.kcheck.yaml")
    return scene


def _rewrite(path: Path, **fields: object) -> Path:
    path.write_text(_with(path.read_text(encoding="utf-8"), **fields), encoding="utf-8")
    return path


def test_analytical_3d_margin_band_against_the_failure_line(cli_json, tmp_path):
    """The spatial check's design margin against the minimum (failure) margin and the band,
    set around the margin the unchanged scene has."""
    path = _fixture_copy(tmp_path, "three-groove-beta-65")
    margin = _run(cli_json, path, "analytical-3d")["design_margin_deg"]
    assert margin > MARGINAL_ANGLE_DEG  # the fixture passes with the default band
    cases = {
        "marginal": {"marginal_deg": margin + 1.0},
        "pass": {"marginal_deg": margin - 1.0},
        "fail": {"min_margin_deg": margin + 1.0},
    }
    for status, options in cases.items():
        _rewrite(path, checks={"analytical-3d": options})
        assert _run(cli_json, path, "analytical-3d")["status"] == status


# --- least holding friction against the design friction (jamming) ---------------------------


def test_friction_ratio_bands(write_scene, cli_json):
    scene = _with(PLANAR_SCENE, load={"magnitude": 1, "angle": 200.0})
    base = _run(cli_json, write_scene(scene), "jamming")
    holding = min(c["holding_friction"] for c in base["cases"] if c.get("holding_friction"))
    expected = {
        holding / (0.5 * (1 + MARGINAL_FRICTION_RATIO)): "marginal",  # between 1 and 1.3x
        holding / (2 * MARGINAL_FRICTION_RATIO): "pass",
        holding * 1.1: "fail",  # friction holds the body: it jams
    }
    for mu, status in expected.items():
        result = _run(cli_json, write_scene(_with(scene, friction=float(mu))), "jamming")
        assert result["status"] == status, (mu, result["message"])
        if status != "fail":
            band = result["margin"]
            assert band["value"] == pytest.approx(holding / mu, rel=1e-3)
            assert band["limit"] == MARGINAL_FRICTION_RATIO


# --- contact stress utilisation (hertz) --------------------------------------------------------


def test_utilisation_bands(cli_json, tmp_path):
    """Utilisation is peak pressure over allowable / safety factor: exactly proportional to
    the safety factor, so the factor places it anywhere."""
    path = _fixture_copy(tmp_path, "three-groove-beta-25")
    materials = {"ball_material": "52100", "seat_material": "52100"}

    def run(factor: float) -> dict:
        _rewrite(path, checks={"hertz": {**materials, "safety_factor": factor}})
        return _run(cli_json, path, "hertz")

    base = run(1.0)
    u0 = base["max_utilisation"]
    assert base["status"] == "pass" and u0 < 0.5 * MARGINAL_UTILISATION
    marginal = run(0.5 * (1 + MARGINAL_UTILISATION) / u0)
    assert marginal["status"] == "marginal"
    assert marginal["margin"]["value"] == pytest.approx(0.5 * (1 + MARGINAL_UTILISATION), rel=1e-9)
    assert run(1.2 / u0)["status"] == "fail"


# --- tolerance pass probability ----------------------------------------------------------------


def test_pass_probability_bands(write_scene, cli_json):
    """Every sample passes: the two-sided 95 % Clopper–Pearson lower bound is (0.025)^(1/n),
    below 0.99 for n = 200 (0.9817) and above it for n = 2000 (0.9982)."""
    scene = PLANAR_SCENE + TOLERANCES

    def run(samples: int, text: str = scene) -> dict:
        options = {"checks": {"tolerances": {"samples": samples}}}
        return _run(cli_json, write_scene(_with(text, **options)), "tolerances")

    small = run(200)
    assert small["status"] == "marginal"
    assert small["margin"]["value"] == pytest.approx(0.025 ** (1 / 200), rel=1e-6)
    assert small["margin"]["limit"] == MARGINAL_PASS_PROBABILITY
    assert run(2000)["status"] == "pass"
    loose = PLANAR_SCENE + "tolerances: {position: 0.05, normal: 0.5, load_direction: 29}\n"
    assert run(200, loose)["status"] == "fail"


# --- Maxwell's cos θ ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("beta", "status"),
    # Maxwell's angle of the groove couplings is about |90° - 2β| (fixtures/generate.py), so
    # the worst cos θ is about sin 2β: 0.643 (β 20°, below the 0.7 line), 0.719 (β 23°, in the band
    # 0.7–0.75), 0.866 (β 30°).
    [(20, "fail"), (23, "marginal"), (30, "pass")],
)
def test_maxwell_cos_bands(cli_json, tmp_path, beta, status):
    path = _fixture_copy(tmp_path, "three-groove-beta-25")
    text = path.read_text(encoding="utf-8").replace("half_angle: 65", f"half_angle: {90 - beta}")
    path.write_text(text, encoding="utf-8")
    result = _run(cli_json, path, "maxwell")
    assert result["status"] == status
    worst = min(c["cos_maxwell"] for c in result["cases"])
    # (to 1e-4: the contacts sit on the balls, slightly off the grooves' mid-planes)
    assert worst == pytest.approx(math.sin(math.radians(2 * beta)), abs=1e-3)
    if status != "fail":
        assert result["margin"]["limit"] == MARGINAL_COS
        assert result["margin"]["value"] == worst


# --- exit codes, scene status and every format -------------------------------------------------


@pytest.fixture
def marginal_scene(write_scene) -> Path:
    """A scene whose only run check (tolerances, 200 samples) is marginal."""
    text = PLANAR_SCENE + TOLERANCES + "checks:\n  tolerances: {samples: 200}\n"
    return write_scene(text)


def test_marginal_fails_the_run_only_with_strict(cli, marginal_scene):
    args = ("check", str(marginal_scene), "--select", "tolerances", "--no-cache")
    code, out, _ = cli(*args)
    assert code == 0
    assert out.count("MARGINAL") >= 1 and "1 marginal" in out
    code, _, _ = cli(*args, "--strict")
    assert code == 1


def test_a_scene_with_a_marginal_check_is_marginal(cli_json, marginal_scene):
    _, doc = cli_json(str(marginal_scene), "--select", "tolerances,maxwell", "--no-cache")
    (scene,) = doc["scenes"]
    assert doc["format_version"] == 3
    assert {c["id"]: c["status"] for c in scene["checks"]} == {
        "maxwell": "pass",
        "tolerances": "marginal",
    }
    assert scene["status"] == "marginal"


def _format(cli, scene: Path, fmt: str, strict: bool = False) -> str:
    args = ["check", str(scene), "--select", "tolerances", "--no-cache", "--format", fmt]
    code, out, _ = cli(*args, *(["--strict"] if strict else []))
    assert code == (1 if strict else 0)
    return out


def test_every_format_says_marginal(cli, marginal_scene):
    assert "marginal" in _format(cli, marginal_scene, "concise")
    assert "🔶 marginal" in _format(cli, marginal_scene, "markdown")
    html = _format(cli, marginal_scene, "html")
    assert 'class="badge marginal"' in html or "badge marginal" in html
    github = _format(cli, marginal_scene, "github")
    assert github.startswith("::warning ") and "tolerances/marginal" in github
    assert "::error " in _format(cli, marginal_scene, "github", strict=True)
    sarif = json.loads(_format(cli, marginal_scene, "sarif"))
    (result,) = sarif["runs"][0]["results"]
    assert result["level"] == "warning" and result["ruleId"] == "tolerances/marginal"
    gitlab = json.loads(_format(cli, marginal_scene, "gitlab"))
    assert [(e["check_name"], e["severity"]) for e in gitlab] == [("tolerances/marginal", "minor")]
    junit = ET.fromstring(_format(cli, marginal_scene, "junit"))
    case = next(tc for tc in junit.iter("testcase") if tc.get("name") == "tolerances")
    assert case.find("failure") is None
    assert (case.findtext("system-out") or "").startswith("marginal:")
    strict = ET.fromstring(_format(cli, marginal_scene, "junit", strict=True))
    case = next(tc for tc in strict.iter("testcase") if tc.get("name") == "tolerances")
    assert case.find("failure") is not None
    doc = json.loads(_format(cli, marginal_scene, "json"))
    assert _check(doc, "tolerances")["findings"][0]["code"] == "marginal"


def test_the_band_is_set_in_the_configuration(cli, write_scene, tmp_path, monkeypatch):
    """`[tool.kcheck.checks.<id>]` sets a band for every scene (and a scene's own wins)."""
    scene = write_scene(PLANAR_SCENE + TOLERANCES + "checks:\n  tolerances: {samples: 200}\n")
    (tmp_path / "kcheck.toml").write_text("[checks.tolerances]\nmarginal_pass_probability = 0.9\n")
    monkeypatch.chdir(tmp_path)
    code, out, _ = cli("check", str(scene), "--select", "tolerances", "--no-cache", "--strict")
    assert code == 0 and "MARGINAL" not in out
