"""What the checks say when a coupling fails: one located finding per reason, with the numbers
a designer needs, written through kcheck.fmt (issue 9 #1, #2, #6, #7; issue 10 #4, #5, #7).

References are closed forms derived in the docstrings (the methods.md §7 block) or the checks'
own exact numbers re-derived independently (nearest safe angle, friction interval ends).
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from kcheck_checks.analytical_2d import Analytical2D, AnalyticalOptions
from kcheck_checks.analytical_3d import Analytical3D, Analytical3DOptions
from kcheck_checks.graphical_2d import Graphical2D, GraphicalOptions
from kcheck_checks.maxwell import Maxwell
from kcheck_checks.wording import ranges_text

from kcheck.body.mass import body_mass_properties
from kcheck.plugin import Inputs
from kcheck.result import CheckResult, Status
from kcheck.scene import Scene, load_scene
from tests.plugins.test_analytical_2d import block_scene

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = ROOT / "fixtures"


def block(**changes: Any) -> dict[str, Any]:
    """The methods.md §7 block (mm) as a scene mapping (tests/plugins/test_analytical_2d.py)."""
    return block_scene(name="block", **changes)


def scene_of(tmp_path: Path, data: dict[str, Any], name: str = "scene") -> Scene:
    path = tmp_path / f"{name}.kcheck.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return load_scene(path)


def run(check: Any, scene: Scene, options: Any = None) -> CheckResult:
    mass = None
    if check.needs_mass_for(scene):
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
    return check.run(Inputs(scene, mass, options or check.options()))


def messages(result: CheckResult) -> list[str]:
    return [f.message for f in result.findings]


def test_needs_friction(tmp_path: Path) -> None:
    """x1 retracted, the 1 N load at 225° on an arm 45 mm below the centre of mass, q = (50,
    -15) mm. Moments about the centre of mass (translation along -x, friction mu N along +x at
    the supports): 0.03 (N2 - N1) = 0.045 |F_x| - 0.03 mu (N1 + N2), N1 + N2 = |F_y|. So
    N1 > 0 needs mu > 0.045 / 0.03 - 1 = 0.5, and lambda > 0 (|F_x| > mu |F_y|) needs mu < 1:
    the case closes for 0.5 <= mu <= 1 exactly."""
    data = block(load={"magnitude": 1.0, "angle": 225.0, "point": [50, -15, 0]})
    closes = run(Analytical2D(), scene_of(tmp_path, {**data, "friction": 0.6}, "rough"))
    x1 = closes.cases[2]
    assert x1.outcome == "closes"
    assert x1.details["friction_intervals"] == [[pytest.approx(0.5), pytest.approx(1.0)]]
    assert x1.limiting_friction == pytest.approx(1.0)
    slippery = run(Analytical2D(), scene_of(tmp_path, {**data, "friction": 0.3}, "smooth"))
    assert slippery.cases[2].outcome == "loses_contact"
    (finding,) = [f for f in slippery.findings if f.field == ("supports", 2)]
    assert finding.code == "loses-contact"
    # N1 by hand at mu = 0.3: (|F_y| - D) / 2 with D = 0.045 |F_x| / 0.03 - mu |F_y|.
    f = np.sqrt(0.5)
    n1 = (f - (1.5 * f - 0.3 * f)) / 2
    assert slippery.cases[2].normal_forces["y1"] == pytest.approx(n1, rel=1e-12)
    assert finding.message == (
        f"retract x1 → y1 loses contact (N = {n1:.3g} N); it closes for 0.5 ≤ μ ≤ 1"
    )


def test_jamming_case_says_which_friction_closes_it(tmp_path: Path) -> None:
    """x1 retracted at 250°: a translation along -x needs tan(20°) = 0.364 > mu (methods.md
    §1.1); at mu = 0.6 it jams and closes for mu <= tan(20°)."""
    result = run(
        Analytical2D(),
        scene_of(tmp_path, block(friction=0.6, load={"magnitude": 1.0, "angle": 250.0})),
    )
    (x1,) = [f for f in result.findings if f.field == ("supports", 2)]
    assert x1.code == "jams"
    limit = np.tan(np.radians(20.0))
    assert (
        x1.message
        == f"retract x1 → jams at μ = 0.6 (friction holds the body); it closes for μ ≤ {limit:.3g}"
    )
    assert result.cases[2].details["friction_intervals"] == [[0.0, pytest.approx(limit)]]
    assert result.status is Status.FAIL and x1.hint is not None and "force angles" in x1.hint


def test_disjoint_ranges_are_named(tmp_path: Path) -> None:
    """At mu = 0.6 the y1 and y2 retractions close on angle ranges that do not overlap; the
    finding names both ranges (each checked against that case's own ranges)."""
    result = run(
        Analytical2D(),
        scene_of(tmp_path, block(friction=0.6, load={"magnitude": 1.0, "angle": 250.0})),
    )
    (disjoint,) = [f for f in result.findings if f.code == "ranges-disjoint"]
    y1, y2 = result.cases[0].safe_ranges_deg, result.cases[1].safe_ranges_deg
    assert y1 and y2
    expected = (
        f"the safe ranges of y1 ({y1[0][0]:.2f}°–{y1[0][1]:.2f}°) and y2 "
        f"({y2[0][0]:.2f}°–{y2[0][1]:.2f}°) do not overlap"
    )
    assert disjoint.message == expected
    assert "no safe force angle" in result.message and "-180" not in result.message


def test_design_outside_reports_the_distance_and_the_nearest_angle(tmp_path: Path) -> None:
    """§7 block, combined safe range 196.20°–264.29° (test_analytical_2d): a design at 100°
    lies 96.20° from the range (its nearest end); the distance, not a boundary's."""
    result = run(Analytical2D(), scene_of(tmp_path, block(load={"magnitude": 1.0, "angle": 100.0})))
    ((start, end),) = result.safe_ranges_deg
    assert result.details["design_margin_deg"] == pytest.approx(-(start - 100.0), abs=1e-9)
    assert result.details["nearest_safe_deg"] == pytest.approx(start, abs=1e-9)
    (design,) = [f for f in result.findings if f.code == "design-outside"]
    assert design.field == ("load", "angle")
    assert f"lies {start - 100:.2f}° outside" in design.message
    assert f"the nearest safe angle is {start:.2f}°" in design.message


def test_no_placeholder_margin_when_nothing_is_safe(tmp_path: Path) -> None:
    data = block(friction=0.6, load={"magnitude": 1.0, "angle": 250.0})
    result = run(Analytical2D(), scene_of(tmp_path, data))
    assert result.safe_ranges_deg == () and "design_margin_deg" not in result.details
    assert "; ;" not in result.message and not result.message.endswith("; ")
    assert "required" not in result.message


def test_graphical_message_says_mass_free(tmp_path: Path) -> None:
    """Thesis Appendix A: graphically safe, analytically not — the graphical verdict says what
    it cannot see."""
    scene = load_scene(FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml")
    result = run(Graphical2D(), scene, GraphicalOptions())
    assert result.status is Status.PASS
    assert "mass-free: contact loss not checked" in result.message


def test_angles_in_messages_follow_the_convention(tmp_path: Path) -> None:
    """Every angle in a message is in [0°, 360°) with two decimals; ranges through 0° say so."""
    scene = load_scene(FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml")
    for check, options in (
        (Graphical2D(), GraphicalOptions()),
        (Analytical2D(), AnalyticalOptions()),
    ):
        result = run(check, scene, options)
        for text in [result.message, *messages(result)]:
            for value in re.findall(r"(-?\d+\.\d+)°", text):
                assert 0.0 <= float(value) < 360.0 and len(value.split(".")[1]) == 2, text
    graphical = run(Graphical2D(), scene, GraphicalOptions())
    y1 = graphical.cases[0].safe_ranges_deg
    assert y1 is not None and y1[0][1] > 360  # the y1 case wraps: JSON and text say so
    ((start, end),) = graphical.to_json()["cases"][0]["safe_ranges_deg"]
    assert 0 <= end < start < 360
    assert ranges_text(y1) == f"{start:.2f}°–{end:.2f}° (through 0°)"


def test_contact_loss_at_every_angle_hints_at_the_load_point() -> None:
    """Thesis Appendix A: retracting x3 lifts y1 off for every force angle (thesis: contact
    is lost). The finding's hint names what is left to change, since only the direction was
    swept."""
    scene = load_scene(FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml")
    result = run(Analytical2D(), scene, AnalyticalOptions())
    (x3,) = [f for f in result.findings if f.message.startswith("retract x3")]
    assert "loses contact" in x3.message
    # The scene's load has no point: it acts at the centre of mass.
    assert x3.hint == (
        "no direction closes this case: move or turn support y1, or move the centre of mass "
        "(where the force acts)"
    )


def test_maxwell_is_a_warning() -> None:
    """Maxwell's rule of thumb never fails a run on its own (issue 9 #10)."""
    assert Maxwell.severity == "warning"
    scene = load_scene(FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml")
    result = run(Maxwell(), scene)
    assert result.status is Status.FAIL
    assert all(f.code == "maxwell" and f.field[0] == "supports" for f in result.findings)  # type: ignore[index]
    assert "cos θ = 0.555" in result.findings[0].message


# --- spatial -----------------------------------------------------------------------------------


def groove(tmp_path: Path, **changes: Any) -> Scene:
    """The three-groove fixture with explicit mass properties and fields replaced."""
    from tests.plugins.test_analytical_3d import scene_dict

    data = scene_dict(FIXTURES / "three-groove" / "coupling.kcheck.yaml", explicit=True)
    data.update(changes)
    return scene_of(tmp_path, data, "groove")


def test_spatial_design_outside_is_a_distance_and_offers_the_nearest_direction(
    tmp_path: Path,
) -> None:
    """A design direction pulling sideways: its margin is minus the exact distance to the safe
    region (a direction of the region lies at that angle from it and none closer — see
    tests/kcheck/test_caps.py), and the finding names the nearest safe direction."""
    from kcheck_checks.analytical_3d import direction_caps

    from kcheck.mechanics.arcs import cap_margins

    scene = groove(
        tmp_path, load={"point": [0, 0, 24.5], "magnitude": 100, "direction": [1, 0, -0.5]}
    )
    result = run(Analytical3D(), scene, Analytical3DOptions())
    margin = result.details["design_margin_deg"]
    nearest = np.array(result.details["nearest_safe_direction"])
    design = np.array([1, 0, -0.5]) / np.linalg.norm([1, 0, -0.5])
    assert margin < 0
    assert np.degrees(np.arccos(nearest @ design)) == pytest.approx(-margin, abs=1e-9)
    from kcheck.analysis import analyse

    analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))  # type: ignore[arg-type]
    _, a, c, _, _ = direction_caps(analysis.problem, analysis)
    assert cap_margins(a, c, nearest[None])[0] > -1e-10  # the nearest direction is safe
    design_finding = result.findings[0]
    assert design_finding.code == "design-outside" and design_finding.field == ("load", "direction")
    assert f"lies {-margin:.2f}° outside" in design_finding.message
    assert (
        "turn the force to (0, 0, -1), the most robust direction (19.10° from every boundary"
        in (design_finding.hint or "")
    )


def test_no_negative_margin_offered_as_a_remedy(tmp_path: Path) -> None:
    """With 1 N the plate cannot be pushed off two flanks: nothing is safe, and no "most robust
    direction" with a negative margin is offered (issue 9 #2)."""
    scene = groove(
        tmp_path,
        load={"point": [0, 0, 24.5], "magnitude": 1, "direction": [0, 0, -1]},
        friction=0.5,
    )
    result = run(Analytical3D(), scene, Analytical3DOptions())
    assert result.status is Status.FAIL
    assert result.details["safe_solid_angle_fraction"] == 0
    assert (
        "most_robust_direction" not in result.details and "design_margin_deg" not in result.details
    )
    assert "most robust" not in result.message
    assert result.message.startswith("no safe force direction")


def test_default_sweep_plane_goes_through_design_and_robust_directions() -> None:
    """block-321 has no `sweep`: the plane is through the design direction (angle 0) and the
    most robust one, and the result says so."""
    scene = load_scene(FIXTURES / "block-321" / "block.kcheck.yaml")
    result = run(Analytical3D(), scene, Analytical3DOptions())
    plane = result.details["sweep_plane"]
    assert plane["chosen"] == "through the design and most robust directions"
    design = np.array([-0.57, -0.82, 0.04]) / np.linalg.norm([-0.57, -0.82, 0.04])
    robust = np.array(result.details["most_robust_direction"])
    np.testing.assert_allclose(plane["zero"], design, atol=1e-12)
    assert abs(np.dot(plane["normal"], robust)) < 1e-12
    assert result.details["sweep_design_margin_deg"] > 0
    assert "in the plane through the design and most robust directions" in result.message


def test_no_safe_direction_in_this_plane_is_not_a_failure(tmp_path: Path) -> None:
    """The three-groove coupling closes for directions near straight down; a horizontal sweep
    plane holds none of them. The check passes and says the plane has no safe direction."""
    scene = groove(tmp_path, sweep={"normal": [0, 0, 1], "zero": [1, 0, 0]})
    result = run(Analytical3D(), scene, Analytical3DOptions())
    assert result.status is Status.PASS
    assert result.safe_ranges_deg == ()
    assert "no safe direction in the sweep plane" in result.message
    assert "no safe force direction" not in result.message


def test_pure_rotation_and_clean_axes(tmp_path: Path) -> None:
    """The §7 block embedded in space (frictionless table): retracting y1 turns the block about
    a vertical axis through the pole (80, 30) mm — a pure rotation, its axis exactly (0, 0, ±1)
    with no rounding noise."""
    from tests.plugins.test_analytical_3d import embedded_pair

    _, spatial = embedded_pair(tmp_path, 225.0)
    result = run(Analytical3D(), spatial, Analytical3DOptions())
    y1 = result.cases[0].details
    assert y1["motion"] == "rotation" and "pitch_m" not in y1
    assert y1["axis"] in ([0.0, 0.0, 1.0], [0.0, 0.0, -1.0])
    np.testing.assert_allclose(y1["axis_point"][:2], [0.08, 0.03], atol=1e-15)


def test_findings_are_located_by_the_runner(tmp_path: Path) -> None:
    """Through the runner, a case's finding carries the line of its support in the file."""
    from kcheck.gate.runner import check_scene
    from kcheck.plugin import load_checks

    path = tmp_path / "jam.kcheck.yaml"
    path.write_text(
        yaml.safe_dump(
            block(friction=0.6, load={"magnitude": 1.0, "angle": 250.0}), sort_keys=False
        )
    )
    result = check_scene(path, [lc for lc in load_checks() if lc.spec.name == "analytical-2d"])
    (check,) = result.checks
    lines = path.read_text().splitlines()
    for finding in check.findings:
        if finding.field and finding.field[0] == "supports":
            name = ["y1", "y2", "x1"][finding.field[1]]  # type: ignore[misc]
            assert finding.line is not None and f"name: {name}" in lines[finding.line - 1]


def test_preload_acts_like_a_force_at_its_point(tmp_path: Path) -> None:
    """A preload (a spring pushing the block) enters the dynamics like the load: §7 block, x1
    retracted, a 0.5 N preload along -x at the centre of mass adds to F_x, so the case's
    acceleration rises by 0.5 N / 1 kg exactly (a = -(F_x + mu (N1 + N2)) / m, N unchanged)."""
    from kcheck.scene import Preload

    scene = scene_of(tmp_path, block())
    plain = run(Analytical2D(), scene)
    spring = Preload("spring", np.array([0.05, 0.03, 0.0]), np.array([-0.5, 0.0, 0.0]))
    pushed = run(Analytical2D(), dataclasses.replace(scene, preloads=(spring,)))
    a0, a1 = plain.cases[2].acceleration, pushed.cases[2].acceleration
    assert a1 == pytest.approx(a0 + 0.5, rel=1e-12)
    assert pushed.cases[2].normal_forces == pytest.approx(plain.cases[2].normal_forces, rel=1e-12)
    graphical = run(
        Graphical2D(), dataclasses.replace(scene, preloads=(spring,)), GraphicalOptions()
    )
    assert "preloads act with the swept force" in graphical.details["notes"]


def test_preload_replaces_gravity_in_space() -> None:
    """block-321: the weight acts like a fixed force m g at the centre of mass. Without gravity
    but with that preload, every case, the exact safe share and the margins are the same."""
    from kcheck.scene import Preload

    scene = load_scene(FIXTURES / "block-321" / "block.kcheck.yaml")
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    weight = Preload("weight as a spring", mass.center_of_mass, mass.mass * scene.gravity)
    sprung = dataclasses.replace(scene, gravity=np.zeros(3), preloads=(weight,))
    a = Analytical3D().run(Inputs(scene, mass, Analytical3DOptions()))
    b = Analytical3D().run(Inputs(sprung, mass, Analytical3DOptions()))
    for key in ("safe_solid_angle_fraction", "design_margin_deg", "robust_margin_deg"):
        assert b.details[key] == pytest.approx(a.details[key], rel=1e-9, abs=1e-12)
    for ca, cb in zip(a.cases, b.cases, strict=True):
        assert cb.outcome == ca.outcome
        assert cb.normal_forces == pytest.approx(ca.normal_forces, rel=1e-9)


def test_gravity_map_with_a_preload_against_case_by_case_outcomes() -> None:
    """thesis-block-5-2 has no load: the map is over gravity directions (the block's tilt),
    and a preload fixed to the block acts in every tilt. For random tilts, "inside the map"
    equals every case closing when the scene is solved again with that gravity."""
    from kcheck_checks.analytical_3d import direction_caps

    from kcheck.analysis import analyse
    from kcheck.mechanics.arcs import cap_margins
    from kcheck.scene import Preload

    scene = load_scene(FIXTURES / "thesis-block-5-2" / "block.kcheck.yaml")
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    spring = Preload("spring", np.array([0.05, 0.07, 0.08]), np.array([-20.0, -10.0, -15.0]))
    sprung = dataclasses.replace(scene, preloads=(spring,))
    analysis = analyse(sprung, mass)
    swept, a, c, _, _ = direction_caps(analysis.problem, analysis)
    assert swept == "gravity"
    g = float(np.linalg.norm(scene.gravity))
    from kcheck.mechanics.caps import region
    from kcheck.mechanics.deepest import deepest_point

    robust, _ = deepest_point(region(a, c))
    assert robust is not None
    rng = np.random.default_rng(17)
    inside = outside = 0
    # Random tilts, and tilts within about 20° of the most robust one (the region is small).
    for d in np.vstack([rng.normal(size=(30, 3)), robust + 0.35 * rng.normal(size=(30, 3))]):
        d /= np.linalg.norm(d)
        margin = float(cap_margins(a, c, d[None])[0])
        if abs(margin) < 1e-6:
            continue
        tilted = analyse(dataclasses.replace(sprung, gravity=g * d), mass)
        closes = all(r.outcome == "closes" for r in tilted.results)
        assert closes == (margin > 0)
        inside += closes
        outside += not closes
    assert inside >= 3 and outside >= 3


def test_findings_on_shorthand_supports_point_at_their_coupling_entry():
    """A support made by a coupling shorthand is written in its `couplings:` entry: findings
    about it carry that field and line (not a `supports[i]` that does not exist)."""
    from kcheck.gate.runner import check_scene
    from kcheck.plugin import load_checks
    from tests.conftest import FIXTURES

    path = FIXTURES / "three-groove-beta-15" / "coupling.kcheck.yaml"
    lines = path.read_text().splitlines()
    entry = {
        name: lines.index(next(x for x in lines if f"name: {name}," in x)) + 1
        for name in ("g1", "g2", "g3")
    }
    maxwell = [lc for lc in load_checks() if lc.spec.name == "maxwell"]
    (check,) = check_scene(path, maxwell).checks
    assert check.findings  # β = 15°: every cos θ is 0.5
    for finding in check.findings:
        coupling = finding.message.split()[1].split(".")[0]  # "retracting g2.1 frees ..."
        assert finding.field == ("couplings", int(coupling[1]) - 1)
        assert finding.line == entry[coupling]


def test_findings_of_one_coupling_merge_per_support_once() -> None:
    """A new user's Kelvin clamp (ball-cone A modelled as A.1–A.3, one field `couplings[0]`)
    read "retract A.1 → jams …; no gravity direction closes it" three times over: the
    findings of A.2 and A.3 were merged into A.1's because they share the field. Each support
    keeps its own finding, and a reason already said is not repeated."""
    from kcheck_checks.wording import merge_findings

    from kcheck.result import Finding

    field = ("couplings", 0)
    jams = [Finding(f"retract A.{k} → jams at μ = 0.8", code="jams", field=field) for k in (1, 2)]
    nowhere = [
        Finding(f"retract A.{k} → no gravity direction closes it", field=field)
        for k in (1, 1, 2, 3)
    ]
    merged = merge_findings(jams, nowhere)
    assert [f.message for f in merged] == [
        "retract A.1 → jams at μ = 0.8; no gravity direction closes it",
        "retract A.2 → jams at μ = 0.8; no gravity direction closes it",
        "retract A.3 → no gravity direction closes it",
    ]


def test_a_coupling_s_contacts_keep_their_own_findings(tmp_path: Path) -> None:
    """The user's Kelvin clamp at μ 0.8: A.1, A.2, A.3 are the cone's three contacts and
    share one field (`couplings[0]`). The map's "no gravity direction closes it" for A.2 and
    A.3 was appended to A.1's finding (three times over); each now goes to its own support's
    finding — exactly those whose own closing share of the sphere is 0."""
    from tests.couplings import user_kelvin

    scene = load_scene(user_kelvin(tmp_path, friction=0.8))
    result = run(Analytical3D(), scene, Analytical3DOptions())
    nowhere = {
        c.retracted for c in result.cases if c.details.get("closing_solid_angle_fraction") == 0
    }
    assert {"A.1", "A.2", "A.3"} <= nowhere
    said = set()
    for finding in result.findings:
        subject = finding.message.partition(" → ")[0].removeprefix("retract ")
        assert finding.message.count("no gravity direction closes it") <= 1
        if "no gravity direction closes it" in finding.message:
            said.add(subject)
    assert said == nowhere
