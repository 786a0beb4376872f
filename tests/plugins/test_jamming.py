"""jamming: the statics check against graphical-2d, analytical-3d and closed forms.

References: graphical-2d's construction (Koster's friction poles: an SVD null vector of the
tilted reaction rows, an independent computation of the same boundary as the statics' facet
of the contact-wrench cone), analytical-3d's forward dynamics (kcheck.mechanics.dynamics), the conic
solver's equilibria checked force by force, and the block of methods.md §7.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from kcheck_checks.graphical_2d import construct_case
from kcheck_checks.jamming import Jamming, JammingOptions

from kcheck.analysis.jamming_cases import analyse_jamming, case_arcs, tidy
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.arcs import TAU, ArcSet, complement, intersect, union
from kcheck.mechanics.dynamics import analyse_case, build_problem
from kcheck.mechanics.kinematics import wrenches
from kcheck.mechanics.outcomes import outcomes
from kcheck.mechanics.sphere import fibonacci_sphere
from kcheck.mechanics.statics import build_statics, equilibrium_forces
from kcheck.plugin import Inputs
from kcheck.result import Status
from kcheck.scene import load_scene
from tests.kcheck.test_statics import random_planar

ROOT = Path(__file__).resolve().parents[2]
BOUNDARY_TOL_DEG = 1e-9
E1, E2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])


def ends_deg(arcs: ArcSet) -> np.ndarray:
    """Arc ends in degrees [0, 360), sorted; none for the full circle."""
    if len(arcs) == 1 and arcs[0][1] - arcs[0][0] >= TAU - 1e-15:
        return np.zeros(0)
    return np.sort(np.degrees([x % TAU for arc in arcs for x in arc]) % 360.0)


def gap_deg(x: np.ndarray, y: np.ndarray) -> float:
    """Largest circular distance between matched sorted angle lists (deg)."""
    if len(x) != len(y):
        return float("inf")
    if not len(x):
        return 0.0
    return min(
        float(np.abs((np.roll(y, s) - x + 180.0) % 360.0 - 180.0).max()) for s in range(len(y))
    )


def measure(arcs: ArcSet) -> float:
    return float(sum(e - s for s, e in arcs))


def test_planar_jamming_reproduces_graphical_on_random_scenes() -> None:
    """On 500 random scenes, every case where Koster's forward friction limit is a facet of
    the contact-wrench cone: graphical-2d's jamming arcs are exactly the statics' jamming
    arcs plus its lift-off arcs (ends to 1e-9°), and the jamming arcs lie inside them. In the
    other cases the rotation about the friction pole presses into a contact and the
    construction does not describe the equilibria (counted; the statics is checked against
    nnls in tests/kcheck/test_statics.py).

    graphical-2d orients the friction twist to the side where the body slides shut (the sign
    of det K(mu) / det K(0), exact outside Painlevé cases whatever the mass); the friction
    cones hold the load on the side where friction would do negative work. Where these two
    differ, both outcomes are consistent — the body may slide shut or stay wedged — and then
    graphical-2d's safe arcs are exactly the statics' held arcs within the funnel (a few
    cases in 1500, counted)."""
    rng = np.random.default_rng(2003)
    counts: Counter[str] = Counter()
    worst = 0.0
    for _ in range(500):
        # Graphical-2d has no preloads; half the scenes have a torque.
        statics = random_planar(rng, mu_max=0.3, preload=False, torque_share=0.5)
        arm = float(statics.fixed[0])
        q = statics.swept[0, ::-1] * np.array([1.0, -1.0])  # moment row (-q_y, q_x) -> q
        analysis = analyse_jamming(statics, "load", None)
        for case in analysis.cases:
            reference = construct_case(
                statics.points, statics.normals, statics.friction, case.retracted, q, arm, E1, E2
            )
            arcs = case_arcs(case, E1, E2)
            assert gap_deg(ends_deg(arcs.closing), ends_deg(reference.funnel)) < BOUNDARY_TOL_DEG
            if arcs.lifts_off is None:
                counts["construction not applicable"] += 1
                continue
            both = tidy(union(arcs.jamming, arcs.lifts_off))
            if double_solution(statics, case.retracted, reference):
                assert gap_deg(ends_deg(both), ends_deg(reference.safe)) < BOUNDARY_TOL_DEG
                counts["double solution"] += 1
                continue
            gap = gap_deg(ends_deg(both), ends_deg(reference.jamming))
            worst = max(worst, gap)
            outside = intersect(arcs.jamming, complement(reference.jamming))
            assert measure(outside) < 1e-12
            counts["regular"] += 1
            counts["jamming arcs"] += bool(arcs.jamming)
            counts["lift-off arcs"] += bool(arcs.lifts_off)
            counts["equal without lift-off"] += not arcs.lifts_off
    assert worst < BOUNDARY_TOL_DEG, worst
    assert counts["regular"] >= 0.85 * 1500, counts
    assert counts["jamming arcs"] >= 500 and counts["lift-off arcs"] >= 300, counts
    assert counts["equal without lift-off"] >= 500, counts
    assert 1 <= counts["double solution"] <= 0.01 * 1500, counts


def double_solution(statics, retracted: int, reference) -> bool:
    """Whether friction at the friction pole's closing side does positive work: there the
    construction's closing side is also the side where the friction cones hold the load."""
    from kcheck.mechanics.dynamics import friction_directions
    from kcheck.mechanics.kinematics import free_twist, point_velocity

    free = free_twist(statics.points, statics.normals, retracted)
    keep = np.flatnonzero(np.arange(len(statics.points)) != retracted)
    t, _ = friction_directions(free.twist, statics.points[keep], +1)
    velocity = point_velocity(reference.tilted, statics.points[keep])
    return float(np.sum(statics.friction[keep] * np.einsum("ij,ij->i", t, velocity))) > 0


def random_spatial(rng: np.random.Generator, mu_max: float):
    """Six supports on a 100 mm box, normals roughly towards the centre of mass (pushing the
    body), a random load point and inertia; statics and dynamics of the same layout."""
    com = rng.uniform(0.03, 0.07, 3)
    points = rng.uniform(0, 0.1, (6, 3))
    normals = (com - points) / np.linalg.norm(com - points, axis=1, keepdims=True)
    normals += 0.6 * rng.normal(size=(6, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    cloud = rng.normal(size=(8, 3)) * 0.05
    cloud -= cloud.mean(axis=0)
    inertia = sum(np.dot(r, r) * np.eye(3) - np.outer(r, r) for r in cloud) / 8
    mu = rng.uniform(0, mu_max, 6)
    q = rng.uniform(0, 0.1, 3)
    names = tuple(f"s{i}" for i in range(6))
    common = dict(points=points, normals=normals, friction=mu, names=names, dim=3)
    problem = build_problem(
        **common, mass=1.0, com=com, inertia=inertia, gravity=np.zeros(3),
        load_magnitude=1.0, load_point=q, torque=np.zeros(3),
    )  # fmt: skip
    statics = build_statics(**common, force=1.0, swept_point=q, swept_magnitude=1.0)
    return problem, statics


def test_spatial_jam_free_region_contains_the_closing_region() -> None:
    """200 random spatial scenes (mu <= 0.3), 100 directions each, every retracted case.

    * The pyramid bounds (square pyramids here, to keep the test fast) are consistent:
      inscribed-held implies circumscribed-held, and the exact conic decision lies between
      them (sampled).
    * Where the forward dynamics close and the circumscribed pyramids say "held", the exact
      decision settles it. Where friction can hold the body although the dynamics close
      (lambda > 0, every N > 0), rigid-body Coulomb friction has two consistent answers —
      sliding shut and staying wedged. Each such direction is verified force by force
      (balance and cones, not trusting the solver's status) and counted; everywhere else the
      jam-free region contains the closing region.
    """
    directions = fibonacci_sphere(100)
    counts: Counter[str] = Counter()
    for seed in range(200):
        problem, statics = random_spatial(np.random.default_rng(seed), 0.3)
        analysis = analyse_jamming(statics, "load", None, edges=4)
        for jc in analysis.cases:
            case = analyse_case(problem, jc.retracted)
            if not case.determined or not case.well_conditioned:
                counts["undetermined"] += 1
                continue
            assert jc.held_inner is not None
            closes = outcomes(case, directions) == "closes"
            outer = jc.held.contains(directions)
            inner = jc.held_inner.contains(directions)
            assert not np.any(inner & ~outer)
            counts["closing directions"] += int(closes.sum())
            counts["held (inscribed)"] += int(inner.sum())
            for k in (int(np.argmax(inner)), int(np.argmin(outer))):  # one held, one free
                if inner[k] or not outer[k]:
                    exact = equilibrium_forces(statics, jc.keep, statics.wrench(directions[k]))
                    assert (exact is not None) == bool(inner[k])
            for d in directions[closes & outer]:
                forces = equilibrium_forces(statics, jc.keep, statics.wrench(d))
                if forces is None:
                    counts["closing, circumscribed pyramids only"] += 1
                    continue
                normals = statics.normals[jc.keep]
                fn = np.sum(forces * normals, axis=1)
                ft = np.linalg.norm(forces - fn[:, None] * normals, axis=1)
                balance = wrenches(statics.points[jc.keep], forces).sum(0) + statics.wrench(d)
                assert np.abs(balance).max() < 1e-7
                assert np.all(ft <= statics.friction[jc.keep] * fn + 1e-7)
                counts["two consistent answers"] += 1
    assert counts["closing directions"] > 500 and counts["held (inscribed)"] > 5000, counts
    assert counts["undetermined"] < 0.05 * 1200, counts


# --- the check on scene files ------------------------------------------------------------------

PLANAR = """
version: 1
name: planar block (methods.md §7)
units: mm
body: {{mass: 1, center_of_mass: [50, 30, 0], inertia: 0.001}}
supports:
  - {{name: y1, position: [20, 0, 0], normal: [0, 1, 0]}}
  - {{name: y2, position: [80, 0, 0], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 30, 0], normal: [1, 0, 0]}}
friction: 0.1
load: {{magnitude: 1, angle: {angle}}}
"""


def test_design_direction_held_fails_with_located_finding(cli_json, write_scene) -> None:
    """At 265° the block on y1, y2 is held (within atan(0.1) = 5.71° of straight down): the
    check fails, names x1's case and the least friction tan(5°) = 0.0875."""
    code, doc = cli_json(str(write_scene(PLANAR.format(angle=265))), "--select", "jamming")
    check = next(c for c in doc["scenes"][0]["checks"] if c["id"] == "jamming")
    assert check["status"] == "fail"
    x1 = next(c for c in check["cases"] if c["retracted"] == "x1")
    assert x1["outcome"] == "jams"
    assert x1["holding_friction"] == pytest.approx(np.tan(np.radians(5.0)), rel=1e-4)
    assert x1["held_deg"] == [pytest.approx([264.2894, 275.7106], abs=1e-4)]
    assert x1["jamming_deg"] == [pytest.approx([264.2894, 270.0], abs=1e-4)]
    assert x1["holds_opening_deg"] == [pytest.approx([270.0, 275.7106], abs=1e-4)]
    (finding,) = check["findings"]
    assert finding["code"] == "jams" and finding["field"] == "supports[2]"
    assert finding["line"] == 8 and "0.0875" in finding["message"] and "x1" in finding["message"]
    assert "y1, y2" in finding["hint"]


def test_design_direction_free_passes(cli_json, write_scene) -> None:
    code, doc = cli_json(str(write_scene(PLANAR.format(angle=225))), "--select", "jamming")
    check = doc["scenes"][0]["checks"][0]
    assert check["status"] == "pass" and code == 0
    assert {c["outcome"] for c in check["cases"]} == {"moves"}
    assert check["design_margin_deg"] == pytest.approx(225 - 196.2, abs=0.01)


def test_mass_only_when_the_weight_or_centre_of_mass_matters(write_scene) -> None:
    check = Jamming()
    point = PLANAR.format(angle=265).replace("magnitude: 1,", "magnitude: 1, point: [50, 30, 0],")
    assert not check.needs_mass_for(load_scene(write_scene(point)))
    assert check.needs_mass_for(load_scene(write_scene(PLANAR.format(angle=265))))
    no_body = point.replace("body: {mass: 1, center_of_mass: [50, 30, 0], inertia: 0.001}\n", "")
    scene = load_scene(write_scene(no_body + "gravity: [0, -9.81, 0]\n"))
    assert "no `body`" in (check.skip_reason(scene) or "")
    result = check.run(Inputs(load_scene(write_scene(point)), None, JammingOptions()))
    assert result.status.value == "fail"
    # Without mass properties the motion beside rest is not looked for: uniqueness unclaimed.
    held = [c for c in result.cases if c.outcome in ("jams", "holds")]
    assert held and all(c.details["unique"] is None for c in held)
    assert all("unique_not_checked" in c.details for c in held)


def test_spatial_fixture_runs_with_map_and_exact_design(cli_json) -> None:
    path = ROOT / "fixtures" / "three-groove" / "coupling.kcheck.yaml"
    code, doc = cli_json(str(path))
    check = next(c for c in doc["scenes"][0]["checks"] if c["id"] == "jamming")
    json.dumps(check)
    assert check["status"] == "pass"
    lo, hi = check["jam_free_solid_angle_fraction"], check["jam_free_solid_angle_fraction_upper"]
    assert 0 < lo <= hi < 1 and check["polyhedral_error_deg"] > 0
    for case in check["cases"]:
        assert case["outcome"] == "moves"
        assert case["held_solid_angle_fraction_lower"] <= case["held_solid_angle_fraction"]


def test_spatial_plots_are_written(tmp_path: Path) -> None:
    scene = load_scene(ROOT / "fixtures" / "three-groove" / "coupling.kcheck.yaml")
    assert scene.body is not None
    inputs = Inputs(scene, body_mass_properties(scene.body, scene.scale), JammingOptions())
    result = Jamming().run(inputs)
    paths = Jamming().plot(inputs, result, tmp_path)
    assert paths and all(p.stat().st_size > 10_000 for p in paths)


def test_a_weight_below_floating_point_is_no_closing_force(cli_json, tmp_path) -> None:
    """Fuzz finding extreme-4244-1282 (issue 13): gravity of -5e-324 m/s² per component (valid
    input) made the weight 0 N and the check crashed ("the force scale must be positive");
    now it is skipped with that reason and the other checks still run."""
    import shutil

    folder = tmp_path / "tool"
    shutil.copytree(Path(__file__).resolve().parents[2] / "fixtures" / "tool-changer", folder)
    scene = folder / "tool.kcheck.yaml"
    text = scene.read_text(encoding="utf-8")
    scene.write_text(text.replace("gravity: [0, 0, -9.81]", "gravity: [-5e-324, -5e-324, -5e-324]"))
    code, doc = cli_json(str(scene))
    checks = {c["id"]: c for c in doc["scenes"][0]["checks"]}
    assert checks["jamming"]["status"] == "skipped"
    assert "not a representable force" in checks["jamming"]["message"]
    assert all(c["status"] != "error" for c in checks.values()) and code in (0, 1)


def test_a_tiny_swept_weight_beside_a_preload_is_scaled_by_the_preload(
    cli_json, tmp_path: Path
) -> None:
    """Fuzz findings extreme-4244-1417/1615 (issue 13): gravity of 1e-300 m/s² swept against
    the tool changer's 40 N magnet. Forces were scaled by the swept weight, so the magnet's
    wrench overflowed (RuntimeWarning, then "SVD did not converge"). Scaled by the largest force
    in the balance, the weight is negligible and the magnet alone decides: it pulls the tool
    straight onto its seats, so every retraction moves back for every weight direction — the
    same verdict analytical-3d reaches independently by its own acceleration test."""
    import shutil
    import warnings

    folder = tmp_path / "tool"
    shutil.copytree(Path(__file__).resolve().parents[2] / "fixtures" / "tool-changer", folder)
    scene = folder / "tool.kcheck.yaml"
    text = scene.read_text(encoding="utf-8")
    scene.write_text(text.replace("gravity: [0, 0, -9.81]", "gravity: [0, 0, 1e-300]"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, doc = cli_json(str(scene))
    checks = {c["id"]: c for c in doc["scenes"][0]["checks"]}
    assert checks["jamming"]["status"] == "pass"
    assert [c["outcome"] for c in checks["jamming"]["cases"]] == ["moves"] * 6
    assert checks["analytical-3d"]["status"] == "pass" and code == 0


def test_spatial_scene_without_sweep_gets_a_plane_through_the_design_gravity(
    tmp_path: Path,
) -> None:
    """A user's report: a spatial scene with no `sweep:` had its jamming ranges in the
    xy-plane, perpendicular to the design gravity (0, 0, -1), so they spoke of horizontal
    gravity only. Now the plane goes through the design direction (angle 0, hand geometry:
    `zero` is (0, 0, -1), the normal is perpendicular to it) and the most jam-free direction.
    Reference for the ranges, an independent computation: the exact circular friction cones
    (clarabel's second-order-cone feasibility, not the pyramids the ranges come from) hold no
    case inside the reported jam-free ranges, including at the design angle 0°."""
    from kcheck.analysis.jamming_cases import held_at, jam_statics
    from kcheck.fmt import normalise_range
    from tests.couplings import tilted_kelvin

    scene = load_scene(tilted_kelvin(tmp_path, 0.1))
    assert scene.body is not None and not scene.sweep.given
    mass = body_mass_properties(scene.body, scene.scale)
    result = Jamming().run(Inputs(scene, mass, JammingOptions()))
    plane = result.details["sweep_plane"]
    assert plane["chosen"] == "through the design and most jam-free directions"
    e1, normal = np.array(plane["zero"]), np.array(plane["normal"])
    np.testing.assert_allclose(e1, [0, 0, -1], atol=1e-12)
    assert abs(normal @ e1) < 1e-12 and abs(np.linalg.norm(normal) - 1) < 1e-12
    e2 = np.cross(normal, e1)
    assert result.details["case_ranges_label"] == "jam-free gravity angles"
    free = [normalise_range(s, e) for s, e in result.details["jam_free_deg"]]
    assert free and result.status.value == "pass"
    statics, swept, design = jam_statics(scene, mass)
    assert swept == "gravity"
    analysis = analyse_jamming(statics, swept, design)
    angles = [0.0] + [(s + ((e - s) % 360) * f) % 360 for s, e in free for f in (0.1, 0.5, 0.9)]
    for angle in angles:
        t = np.radians(angle)
        d = np.cos(t) * e1 + np.sin(t) * e2
        assert not any(held_at(analysis, c, d, statics.friction) for c in analysis.cases)
    # The design angle's margin is its distance to the nearest end of the jam-free ranges.
    ends = np.array([x for r in free for x in r])
    nearest = float(np.min(np.abs((ends + 180.0) % 360.0 - 180.0)))
    assert result.details["design_margin_deg"] == pytest.approx(nearest, abs=1e-9)
    assert f"margin {nearest:.2f}° to a held direction" in result.message


def test_spatial_scene_without_a_design_direction_keeps_the_xy_plane(tmp_path: Path) -> None:
    """Without a design direction (a load with no `direction`) there is nothing to aim the
    plane through: the ranges stay in the xy-plane, as the result says."""
    from tests.couplings import tilted_kelvin

    path = tilted_kelvin(tmp_path, 0.1)
    path.write_text(
        path.read_text(encoding="utf-8") + "load: {point: [0, 0, 18.5], magnitude: 100}\n",
        encoding="utf-8",
    )
    scene = load_scene(path)
    assert scene.body is not None
    inputs = Inputs(scene, body_mass_properties(scene.body, scene.scale), JammingOptions())
    plane = Jamming().run(inputs).details["sweep_plane"]
    assert plane == {
        "normal": [0, 0, 1],
        "zero": [1, 0, 0],
        "chosen": "the xy-plane: no sweep given",
    }


def test_a_plane_with_nothing_jam_free_gives_no_margin(tmp_path: Path) -> None:
    """The user's Kelvin clamp (μ 0.15): every direction of the chosen plane can be held in
    some case. The design direction then has no distance to a jam-free one: no
    `design_margin_deg` (as documented: absent when nothing is safe), never "180.00° inside",
    and the plane's reason says no direction is jam-free for certain."""
    from tests.couplings import user_kelvin

    scene = load_scene(user_kelvin(tmp_path))
    assert scene.body is not None
    inputs = Inputs(scene, body_mass_properties(scene.body, scene.scale), JammingOptions())
    result = Jamming().run(inputs)
    assert result.status.value == "fail" and result.details["jam_free_deg"] == []
    assert "design_margin_deg" not in result.details and "180.00°" not in result.message
    assert "jam-free in the sweep plane: none" in result.message
    plane = result.details["sweep_plane"]
    assert plane["zero"] == pytest.approx([0, 0, -1], abs=1e-12)
    assert plane["chosen"].endswith("inscribed pyramids: none is jam-free for certain")


def test_a_case_held_for_every_weight_direction_is_not_told_to_turn_it(cli_json, tmp_path):
    """The new user's Kelvin clamp at μ = 0.8: friction holds retraction A.1 for every
    direction of the weight on the sphere (the inscribed pyramids, a lower bound, hold it at
    every lattice direction), so the hint names only the friction, and the message says the
    weight (not "a closing load") would close it."""
    from tests.couplings import user_kelvin

    code, doc = cli_json(str(user_kelvin(tmp_path, friction=0.8)), "--select", "jamming")
    (check,) = doc["scenes"][0]["checks"]
    a1 = next(c for c in check["cases"] if c["retracted"] == "A.1")
    assert a1["held_solid_angle_fraction_lower"] == 1.0
    finding = next(f for f in check["findings"] if f["message"].startswith("retract A.1"))
    assert "although the weight would close it" in finding["message"]
    assert finding["hint"].startswith("lower the friction") and "turn" not in finding["hint"]
    assert code == 1


def test_freest_direction_is_the_deepest_of_every_free_direction(tmp_path: Path) -> None:
    """The screened search for the freest lattice direction (cells first, a floor raised from
    the surviving cells, then direction by direction) returns what measuring every free
    direction's depth returns: the first of the deepest (the reference: ``_free_depth`` on
    all 20,000 directions, no screen)."""
    import sys

    from kcheck.analysis.jamming_cases import (
        _free_depth,
        _freest,
        _lattice_slack,
        jam_statics,
    )
    from kcheck.mechanics.lattice_cells import lattice_cells

    sys.path.insert(0, str(ROOT / "tests"))
    from spatial_scenes import write_spatial_scenes

    cells = lattice_cells(20000)
    found = 0
    for path in write_spatial_scenes(tmp_path, range(6)):
        scene = load_scene(path)
        assert scene.body is not None
        statics, swept, design = jam_statics(scene, body_mass_properties(scene.body, scene.scale))
        analysis = analyse_jamming(statics, swept, design)
        sets = [c.held for c in analysis.cases if c.determined]
        slacks = [_lattice_slack(h, cells) for h in sets]
        depth = _free_depth(sets, cells.fine)
        best = int(np.argmax(depth))
        expected = best if depth[best] > 0 and np.isfinite(depth[best]) else None
        assert _freest(sets, cells, slacks) == expected
        found += expected is not None
    assert found >= 3


def test_cell_screen_of_the_freest_direction_with_infinite_bounds() -> None:
    """jamming_cases._some_below (the cells' screen as one product, the radius and the bound
    folded in) against the same bound written out (centre value minus radius, against the
    bound), with facets held nowhere (bound +inf: every cell possible) and everywhere (-inf:
    never), decided without relying on BLAS to carry infinities."""
    from kcheck.analysis.jamming_cases import CELL_GUARD, _some_below
    from kcheck.mechanics.lattice_cells import lattice_cells

    cells = lattice_cells(20000)
    which = np.arange(len(cells.coarse))
    rng = np.random.default_rng(8)
    for _ in range(200):
        k = int(rng.integers(1, 40))
        axes = rng.normal(size=(k, 3))
        axes /= np.linalg.norm(axes, axis=1, keepdims=True)
        bound = rng.uniform(-1.0, 1.0, k)
        kind = rng.random(k)
        bound[kind < 0.05] = np.inf
        bound[(kind >= 0.05) & (kind < 0.15)] = -np.inf
        low = cells.coarse @ axes.T - cells.radius[:, None] - CELL_GUARD
        assert np.array_equal(_some_below(cells, which, axes, bound), np.any(low <= bound, axis=1))


def test_widest_band_margin_is_the_largest_cap_margin() -> None:
    """The map's band width (jamming_cases._widest_margin: arccos at every facet only where a
    direction can attain the largest margin) is the largest of arcs.cap_margins over the same
    directions, the same float; on spherical polygons of 1-80 caps about a random axis and
    random subsets of a lattice."""
    from kcheck.analysis.jamming_cases import _widest_margin
    from kcheck.mechanics.arcs import cap_margins

    rng = np.random.default_rng(6)
    dirs = fibonacci_sphere(4000)
    for _ in range(600):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        k = int(rng.integers(1, 80))
        centres = axis + rng.uniform(0.05, 0.6) * rng.normal(size=(k, 3))
        centres /= np.linalg.norm(centres, axis=1, keepdims=True)
        radius = np.arccos(np.clip(centres @ axis, -1.0, 1.0)) + rng.uniform(0.0, 0.5, k)
        c = centres * rng.uniform(0.5, 2.0, (k, 1))
        a = -np.linalg.norm(c, axis=1) * np.cos(radius)
        some = dirs[rng.random(len(dirs)) < rng.uniform(0.001, 0.2)]
        if len(some):
            assert _widest_margin(a, c, some) == float(cap_margins(a, c, some).max())


def test_a_held_case_the_rigid_model_also_moves_is_held_or_moves(tmp_path: Path) -> None:
    """The reseat agreement test's random-3d-3391 (seed 26): friction can hold the body
    retracting s4, and the rigid model also admits a motion from rest that keeps s1 and s6 and
    lifts off s2, s3 and s5 (the simulation's own first motion there, measured with
    kcheck.analysis.reseat.simulate; tests/kcheck/test_second_answer.py checks the motion
    independently). The verdict stays fail; the case says it is not unique and which motion,
    and every held case of the scene says whether it is unique."""
    from tests.plugins.reseat_agreement import generated

    path = next(p for p in generated(tmp_path, 100) if p.name == "random-3d-3391.kcheck.yaml")
    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    result = Jamming().run(Inputs(scene, mass, JammingOptions()))
    assert result.status is Status.FAIL
    case = next(c for c in result.cases if c.retracted == "s4")
    assert case.outcome in ("jams", "holds")
    assert case.details["unique"] is False
    assert case.details["alternative_lifts_off"] == ["s2", "s3", "s5"]
    finding = next(f for f in result.findings if f.message.startswith("retract s4 "))
    assert "or it lifts off s2, s3 and s5 (the rigid model admits both" in finding.message
    assert "retract s4 (" + case.outcome + ", or moves)" in result.message
    for c in result.cases:
        assert ("unique" in c.details) == (c.outcome in ("jams", "holds"))
