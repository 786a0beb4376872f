"""graphical-2d: Koster's construction against independent references.

References used below: the analytical-2d engine (:mod:`kcheck.analysis.cases`, Newton–Euler with
mass), line intersections computed here by hand (poles), and closed forms (methods.md §1.1,
§2.1.2, §5, §7). Every scene is a real YAML file loaded through :func:`kcheck.scene.load_scene`
or run through the CLI.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import pytest
from kcheck_checks.graphical_2d import (
    Attachment,
    Graphical2D,
    GraphicalOptions,
    attachment,
)

from kcheck.analysis import analyse
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.arcs import TAU, ArcSet
from kcheck.plugin import Inputs
from kcheck.result import CheckResult, Status
from kcheck.scene import Preload, Scene, load_scene

ROOT = Path(__file__).resolve().parents[2]
# Arc ends agree to this (degrees): both sides are closed forms in double precision.
BOUNDARY_TOL_DEG = 1e-9


def _num(x: float) -> str:
    return repr(float(x))


def planar_yaml(
    points: np.ndarray,
    normals: np.ndarray,
    mu: Sequence[float],
    *,
    load_point: np.ndarray | None = None,
    com: np.ndarray | None = None,
    inertia: float = 1e-3,
    angle: float | None = None,
    torque: float = 0.0,
    units: str = "mm",
    gravity: Sequence[float] | None = None,
) -> str:
    """A planar scene file; a body with explicit mass properties when ``com`` is given."""
    lines = ["version: 1", "name: graphical test scene", f"units: {units}"]
    if com is not None:
        lines.append(
            f"body: {{mass: 1, center_of_mass: [{_num(com[0])}, {_num(com[1])}, 0], "
            f"inertia: {_num(inertia)}}}"
        )
    lines.append("supports:")
    for i, (p, n, m) in enumerate(zip(points, normals, mu, strict=True)):
        lines.append(
            f"  - {{name: s{i + 1}, position: [{_num(p[0])}, {_num(p[1])}, 0], "
            f"normal: [{_num(n[0])}, {_num(n[1])}, 0], friction: {_num(m)}}}"
        )
    load = ["magnitude: 1"]
    if load_point is not None:
        load.append(f"point: [{_num(load_point[0])}, {_num(load_point[1])}, 0]")
    if angle is not None:
        load.append(f"angle: {_num(angle)}")
    if torque:
        load.append(f"torque: [0, 0, {_num(torque)}]")
    lines.append("load: {" + ", ".join(load) + "}")
    if gravity is not None:
        lines.append(f"gravity: [{_num(gravity[0])}, {_num(gravity[1])}, 0]")
    return "\n".join(lines) + "\n"


def run_graphical(scene: Scene, min_margin_deg: float = 0.0) -> CheckResult:
    """The check exactly as the runner calls it: mass properties only when it asks for them."""
    check = Graphical2D()
    assert check.skip_reason(scene) is None
    mass = None
    if check.needs_mass_for(scene):
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
    return check.run(Inputs(scene, mass, GraphicalOptions(min_margin_deg=min_margin_deg)))


def arcs_rad(ranges_deg: Sequence[Sequence[float]]) -> ArcSet:
    return tuple((np.radians(s), np.radians(e)) for s, e in ranges_deg)


def inside(arcs: ArcSet, angle: float, tol: float) -> bool:
    """Whether an angle (rad) lies in an arc set, widened by ``tol``."""
    return any(s - tol <= angle + k * TAU <= e + tol for s, e in arcs for k in (-1, 0, 1))


def subset(small: ArcSet, big: ArcSet, tol: float) -> bool:
    """Exact arc-set inclusion: no end of ``big`` strictly inside ``small``, midpoints inside."""
    big_ends = [x % TAU for arc in big for x in arc] if big != ((0.0, TAU),) else []
    for s, e in small:
        mid = 0.5 * (s + e)
        if not inside(big, mid, tol):
            return False
        for b in big_ends:
            for k in (-1, 0, 1):
                if s + tol < b + k * TAU < e - tol:
                    return False
    return True


def ends_deg(arcs: ArcSet) -> np.ndarray:
    """Arc ends in degrees [0, 360), sorted; none for the full circle."""
    if len(arcs) == 1 and arcs[0][1] - arcs[0][0] >= TAU - 1e-15:
        return np.zeros(0)
    return np.sort(np.degrees([x % TAU for arc in arcs for x in arc]) % 360.0)


def zero_angles_deg(a: float, b: float, c: float) -> np.ndarray:
    """Angles (deg) where ``a + b cos + c sin`` changes sign, sorted."""
    r = np.hypot(b, c)
    if r == 0 or abs(a) >= r:
        return np.zeros(0)
    centre, half = np.arctan2(c, b), np.arccos(-a / r)
    return np.sort(np.degrees([centre - half, centre + half]) % 360.0)


def angle_gap_deg(x: np.ndarray, y: np.ndarray) -> float:
    """Largest circular distance between matched sorted angle lists (deg)."""
    if len(x) != len(y):
        return float("inf")
    if not len(x):
        return 0.0
    best = float("inf")
    for shift in range(len(y)):
        d = (np.roll(y, shift) - x + 180.0) % 360.0 - 180.0
        best = min(best, float(np.abs(d).max()))
    return best


def random_layout(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Three supports in a 100 mm box with random normals, away from concurrency."""
    while True:
        points = rng.uniform(0.0, 100.0, (3, 2))
        angles = rng.uniform(0.0, TAU, 3)
        normals = np.column_stack([np.cos(angles), np.sin(angles)])
        rows = np.column_stack(
            [points[:, 0] / 100 * normals[:, 1] - points[:, 1] / 100 * normals[:, 0], normals]
        )
        s = np.linalg.svd(rows, compute_uv=False)
        if s[-1] > 1e-3 * s[0]:
            return points, normals


def where_force_acts(scene: Scene) -> Attachment:
    """The check's attachment of the swept force (the centre of mass by default)."""
    com = None
    if Graphical2D().needs_mass_for(scene):
        com = body_mass_properties(scene.body, scene.scale).center_of_mass  # type: ignore[arg-type]
    found = attachment(scene, com=com)
    assert not isinstance(found, str), found
    return found


# --- cross-checks with analytical-2d on random scenes ---------------------------------------


def _random_scenes(
    tmp_path: Path, count: int, seed: int, mu_max: float, weight: bool = False
) -> list[tuple[int, Scene]]:
    """Random planar scenes; with ``weight``, gravity in the plane makes the 1 kg body's weight
    0.2 to 3 times the 1 N load, and every third scene gets a preload (a spring at a random
    point, up to 1 N) — the fixed forces the construction must add to the swept one."""
    rng = np.random.default_rng(seed)
    scenes = []
    for k in range(count):
        points, normals = random_layout(rng)
        com = rng.uniform(0.0, 100.0, 2)
        at_com = k % 3 == 0  # a third use the default point (the centre of mass)
        gravity = None
        if weight:
            turn = rng.uniform(0, TAU)
            gravity = rng.uniform(0.2, 3.0) * np.array([np.cos(turn), np.sin(turn)])
        text = planar_yaml(
            points,
            normals,
            rng.uniform(0.0, mu_max, 3),
            com=com,
            load_point=None if at_com else rng.uniform(0.0, 100.0, 2),
            inertia=float(rng.uniform(0.05, 0.6) ** 2 * 1e-2),  # radius of gyration 5-60 mm
            gravity=gravity,
        )
        path = tmp_path / f"random-{k}.kcheck.yaml"
        path.write_text(text, encoding="utf-8")
        scene = load_scene(path)
        if weight and k % 3 == 1:
            spring = Preload(
                "spring",
                np.append(rng.uniform(0.0, 0.1, 2), 0.0),
                np.append(rng.normal(size=2) * 0.5, 0.0),
            )
            scene = dataclasses.replace(scene, preloads=(spring,))
        scenes.append((k, scene))
    return scenes


@pytest.mark.parametrize(("weight", "seed"), [(False, 20031), (True, 1998)])
def test_graphical_contains_analytical_on_random_scenes(
    tmp_path: Path, weight: bool, seed: int
) -> None:
    """Reference: analytical-2d's exact safe arcs (methods.md §5: graphical ⊇ analytical),
    also with the weight and preloads acting with the load, and with friction up to 1 so that
    Painlevé-type cases occur: those are ambiguous, closing nowhere, and so contained too."""
    checked = nonempty = ambiguous = 0
    for _, scene in _random_scenes(tmp_path, 150, seed=seed, mu_max=1.0, weight=weight):
        mass = body_mass_properties(scene.body, scene.scale)  # type: ignore[arg-type]
        analysis = analyse(scene, mass)
        graphical = run_graphical(scene)
        assert analysis.arcs is not None
        for r, case in enumerate(graphical.cases):
            if analysis.results[r].outcome in ("undetermined", "ill_conditioned"):
                continue
            ambiguous += analysis.cases[r].painleve
            big = arcs_rad(case.safe_ranges_deg or ())
            assert subset(analysis.arcs[r], big, tol=1e-9), (scene.path, case.retracted)
            checked += 1
            nonempty += bool(analysis.arcs[r])
        assert subset(analysis.combined or (), arcs_rad(graphical.safe_ranges_deg or ()), 1e-9)
    assert checked >= 400 and nonempty >= 100 and ambiguous >= 5


@pytest.mark.parametrize("weight", [False, True])
def test_forward_lambda_sign_changes_are_the_friction_boundaries(
    tmp_path: Path, weight: bool
) -> None:
    """Reference: zeros of analytical-2d's forward lambda(alpha) (closed form, methods.md §4).

    At lambda = 0 inertia plays no part, so they are exactly the graphical friction boundaries
    — also when the weight and preloads act with the load (their moments about the friction
    pole enter both sides alike).
    """
    worst = 0.0
    compared = 0
    for _, scene in _random_scenes(tmp_path, 100, seed=7, mu_max=0.3, weight=weight):
        mass = body_mass_properties(scene.body, scene.scale)  # type: ignore[arg-type]
        analysis = analyse(scene, mass)
        graphical = run_graphical(scene)
        e1, e2 = scene.sweep.e1[:2], scene.sweep.e2[:2]
        for r, case in enumerate(analysis.cases):
            if case.forward is None or not case.well_conditioned:
                continue
            a, c = case.forward.a[0], case.forward.c[0]
            expected = zero_angles_deg(a, float(c @ e1), float(c @ e2))
            got = ends_deg(arcs_rad(graphical.cases[r].details["friction_deg"]))
            gap = angle_gap_deg(expected, got)
            worst = max(worst, gap)
            compared += 1
    assert compared >= 250
    assert worst < BOUNDARY_TOL_DEG, worst


def _normal_line_intersection(
    p1: np.ndarray, n1: np.ndarray, p2: np.ndarray, n2: np.ndarray
) -> np.ndarray:
    """Where two normal lines meet (test-only reference, solved by hand)."""
    matrix = np.column_stack([n1, -n2])
    s = np.linalg.solve(matrix, p2 - p1)
    return p1 + s[0] * n1


def test_frictionless_sign_change_when_force_line_passes_through_pole(
    tmp_path: Path,
) -> None:
    """Reference: the pole as the intersection of the two remaining normal lines (by hand);
    analytical-2d's lambda (mu = 0) changes sign exactly where the force line meets it."""
    rng = np.random.default_rng(11)
    worst_line = worst_pole = 0.0
    for k in range(40):
        points, normals = random_layout(rng)
        q = rng.uniform(0.0, 100.0, 2)
        path = tmp_path / f"frictionless-{k}.kcheck.yaml"
        path.write_text(
            planar_yaml(points, normals, [0, 0, 0], com=rng.uniform(0, 100, 2), load_point=q)
        )
        scene = load_scene(path)
        analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))  # type: ignore[arg-type]
        graphical = run_graphical(scene)
        for r, case in enumerate(analysis.cases):
            keep = [j for j in range(3) if j != r]
            pole = _normal_line_intersection(
                points[keep[0]], normals[keep[0]], points[keep[1]], normals[keep[1]]
            )
            reported = np.asarray(graphical.cases[r].details["pole"]) * 1e3
            worst_pole = max(worst_pole, float(np.linalg.norm(reported - pole)) / 100)
            assert case.forward is not None
            a, c = case.forward.a[0], case.forward.c[0]
            for alpha in zero_angles_deg(a, float(c[0]), float(c[1])):
                d = np.array([np.cos(np.radians(alpha)), np.sin(np.radians(alpha))])
                rel = pole - q
                # Distance of the pole from the force line, relative to the layout size.
                worst_line = max(worst_line, abs(rel[0] * d[1] - rel[1] * d[0]) / 100)
            # The graphical funnel boundaries are the same angles.
            got = ends_deg(arcs_rad(graphical.cases[r].details["funnel_deg"]))
            assert angle_gap_deg(zero_angles_deg(a, float(c[0]), float(c[1])), got) < 1e-9
    assert worst_pole < 1e-10 and worst_line < 1e-10


# --- special cases ----------------------------------------------------------------------------


def test_concurrent_normals_are_not_determined(write_scene: Callable[..., Path]) -> None:
    """Reference: methods.md §2.1.2 — three normals through one point leave a rotation free."""
    angles = np.radians([90.0, 210.0, 330.0])
    points = 50 * np.column_stack([np.cos(angles), np.sin(angles)])
    scene = load_scene(
        write_scene(planar_yaml(points, -points / 50, [0.1] * 3, load_point=np.zeros(2)))
    )
    result = run_graphical(scene)
    assert result.status is Status.FAIL
    assert "not determined" in result.message
    assert result.safe_ranges_deg is None
    assert all(c.outcome == "undetermined" for c in result.cases)


def _pinwheel(
    write_scene: Callable[..., Path], turn_deg: float, mu: float = 0.0, arm_mm: float = 0.0
) -> tuple[CheckResult, np.ndarray]:
    """Disc of radius 50 mm on three supports whose normals are all turned the same way.

    Returns the result and the poles computed by hand (mm), in support order.
    """
    angles = np.radians([90.0, 210.0, 330.0])
    points = 50 * np.column_stack([np.cos(angles), np.sin(angles)])
    turn = np.radians(turn_deg)
    rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    normals = (-points / 50) @ rot.T
    text = planar_yaml(
        points, normals, [mu] * 3, load_point=np.zeros(2), torque=arm_mm * 1e-3, angle=0
    )
    poles = []
    for r in range(3):
        j, k = [i for i in range(3) if i != r]
        poles.append(_normal_line_intersection(points[j], normals[j], points[k], normals[k]))
    name = f"pinwheel-{turn_deg}-{mu}-{arm_mm}.kcheck.yaml"
    return run_graphical(load_scene(write_scene(text, name))), np.array(poles)


def test_all_senses_equal_needs_a_torque(write_scene: Callable[..., Path]) -> None:
    """Reference: methods.md §5 / thesis Figures 2.12–2.13 — with every pole needing the same
    sense, a force through a point inside the pole triangle cannot close all three cases.

    By symmetry the three ``u_r(q)`` are 120° apart with length ``|w| rho`` (``rho`` = distance
    of the centre from a hand-computed pole), so a torque arm ``M / F`` of that sense opens a
    safe range exactly when it exceeds ``rho / 2``.
    """
    result, poles = _pinwheel(write_scene, 20.0)
    senses = result.details["senses"]
    assert len(set(senses)) == 1 and senses[0] in ("ccw", "cw")
    assert result.status is Status.FAIL and result.safe_ranges_deg == ()
    assert "torque" in result.message and "pole triangle" in result.message
    triangle = np.asarray(result.details["pole_triangle"]) * 1e3
    np.testing.assert_allclose(triangle, poles, atol=1e-9)
    # The attachment point (the disc's centre) lies inside the pole triangle.
    edges = np.roll(triangle, -1, axis=0) - triangle
    cross = edges[:, 0] * -triangle[:, 1] - edges[:, 1] * -triangle[:, 0]
    assert np.all(cross > 0) or np.all(cross < 0)
    rho = float(np.linalg.norm(poles[0]))
    sign = 1.0 if senses[0] == "ccw" else -1.0
    assert _pinwheel(write_scene, 20.0, arm_mm=sign * 0.99 * rho / 2)[0].safe_ranges_deg == ()
    assert _pinwheel(write_scene, 20.0, arm_mm=sign * 1.01 * rho / 2)[0].safe_ranges_deg
    assert _pinwheel(write_scene, 20.0, arm_mm=-sign * 2 * rho)[0].safe_ranges_deg == ()


def test_pole_on_a_support_leaves_friction_undetermined(
    write_scene: Callable[..., Path],
) -> None:
    """Reference: hand geometry — turned 30°, each normal line runs along a side of the support
    triangle, so the pole of every case lies on a remaining support (methods.md §3)."""
    result, poles = _pinwheel(write_scene, 30.0, mu=0.2)
    names = ["s1", "s2", "s3"]
    for r, case in enumerate(result.cases):
        np.testing.assert_allclose(np.asarray(case.details["pole"]) * 1e3, poles[r], atol=1e-9)
        (stuck,) = case.details["friction_undetermined"]
        assert stuck in names and stuck != names[r]
        assert "undetermined" in case.details["diagnostic"]


def test_pole_at_infinity_closed_form(write_scene: Callable[..., Path]) -> None:
    """Reference: methods.md §7 block and §1.1 — x1 retracted is a translation along -x; the
    funnel is 90°–270°, the friction boundary 180° + atan(1/mu) (tan(theta) > mu)."""
    mu = 0.1
    points = np.array([[20.0, 0.0], [80.0, 0.0], [0.0, 30.0]])
    normals = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
    text = planar_yaml(points, normals, [mu] * 3, load_point=np.array([50.0, 30.0]), angle=225)
    result = run_graphical(load_scene(write_scene(text)))
    x1 = result.cases[2].details
    assert x1["pole_at_infinity"] and x1["sense"] == "translation"
    np.testing.assert_allclose(x1["translation_direction"], [-1.0, 0.0], atol=1e-15)
    assert x1["friction_pole_at_infinity"]
    np.testing.assert_allclose(x1["funnel_deg"], [[90.0, 270.0]], atol=1e-12)
    end = 180.0 + np.degrees(np.arctan(1 / mu))
    np.testing.assert_allclose(result.cases[2].safe_ranges_deg, [[90.0, end]], atol=1e-12)
    # Reference: the hand-computed poles (80, 30) mm, ccw for y1 out; (20, 30) mm, cw for y2.
    np.testing.assert_allclose(result.cases[0].details["pole"], [0.08, 0.03], atol=1e-15)
    np.testing.assert_allclose(result.cases[1].details["pole"], [0.02, 0.03], atol=1e-15)
    assert result.details["senses"] == ["ccw", "cw", "translation"]
    assert result.status is Status.PASS and result.cases[2].outcome == "closes"


def test_mass_free_scene_and_skip_reasons(write_scene: Callable[..., Path]) -> None:
    """A scene without a body runs when the load has a point; without one it is skipped."""
    points = np.array([[20.0, 0.0], [80.0, 0.0], [0.0, 30.0]])
    normals = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
    scene = load_scene(write_scene(planar_yaml(points, normals, [0.1] * 3, load_point=[50, 30])))
    assert scene.body is None and Graphical2D().needs_mass_for(scene) is False
    assert run_graphical(scene).status is Status.PASS
    no_point = load_scene(write_scene(planar_yaml(points, normals, [0.1] * 3), "b.kcheck.yaml"))
    reason = Graphical2D().skip_reason(no_point)
    assert reason is not None and "load.point" in reason


def test_design_margin_option(write_scene: Callable[..., Path]) -> None:
    """Reference: the §7 block's combined range 196.20°–264.29° (analytical-2d agrees)."""
    points = np.array([[20.0, 0.0], [80.0, 0.0], [0.0, 30.0]])
    normals = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
    text = planar_yaml(points, normals, [0.1] * 3, com=np.array([50.0, 30.0]), angle=260)
    scene = load_scene(write_scene(text))
    margin = run_graphical(scene).details["design_margin_deg"]
    assert margin == pytest.approx(264.2894068625 - 260, abs=1e-9)
    assert run_graphical(scene, min_margin_deg=5.0).status is Status.FAIL


def test_fixture_through_cli_with_plots(
    tmp_path: Path, cli_json: Callable[..., tuple[int, dict]]
) -> None:
    """The planar-block fixture end to end: JSON result and the Figure 2.8-like picture."""
    pytest.importorskip("matplotlib")
    plots = tmp_path / "plots"
    code, doc = cli_json(
        str(ROOT / "fixtures" / "planar-block"), "--plots", str(plots), "--plot-format", "png,svg"
    )
    assert code == 0
    (scene,) = doc["scenes"]
    check = next(c for c in scene["checks"] if c["id"] == "graphical-2d")
    assert check["status"] == "pass"
    png = plots / "planar-rectangular-block-graphical-2d.png"
    svg = plots / "planar-rectangular-block-graphical-2d.svg"
    assert str(png) in scene["plots"] and str(svg) in scene["plots"]
    assert png.stat().st_size > 30_000
    text = svg.read_text(encoding="utf-8")
    assert "planar rectangular block" in text and "safe force directions" in text


def test_weight_as_the_closing_force(write_scene: Callable[..., Path]) -> None:
    """Without a load the weight at the centre of mass is swept; its direction is the design.

    Reference, by hand: with y1 out the block turns ccw about (80, 30); y2 slides +x and x1
    slides -y, so the tilted reaction lines (80, 0) + s (-mu, 1) and (0, 30) + t (1, mu) meet
    at the friction pole P' = (80 - mu s, s) with s = (30 + 80 mu) / (1 + mu^2). The safe range
    starts where the force line through the centre of mass (50, 30) passes through P'; it ends
    at 180° + atan(1 / mu) (x1 out, a translation).
    """
    text = """
    version: 1
    name: block on a tilted table
    units: mm
    body: {mass: 1, center_of_mass: [50, 30, 0], inertia: 0.001}
    supports:
      - {name: y1, position: [20, 0, 0], normal: [0, 1, 0]}
      - {name: y2, position: [80, 0, 0], normal: [0, 1, 0]}
      - {name: x1, position: [0, 30, 0], normal: [1, 0, 0]}
    friction: 0.1
    gravity: [-6.9367, -6.9367, 0]
    """
    mu = 0.1
    s = (30 + 80 * mu) / (1 + mu**2)
    start = 180.0 + np.degrees(np.arctan2(s - 30.0, 80.0 - mu * s - 50.0))
    end = 180.0 + np.degrees(np.arctan(1 / mu))
    result = run_graphical(load_scene(write_scene(text)))
    assert result.details["force"] == "weight"
    np.testing.assert_allclose(result.safe_ranges_deg, [[start, end]], atol=1e-9)
    assert result.details["design_margin_deg"] == pytest.approx(225.0 - start, abs=1e-9)
    pole = np.asarray(result.cases[0].details["friction_pole"]) * 1e3
    np.testing.assert_allclose(pole, [80 - mu * s, s], atol=1e-9)


def test_centre_of_mass_comes_from_the_runner_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """The force acts at the centre of mass: the runner reads the mesh once for every check."""
    import kcheck.body.meshio
    from kcheck.gate.runner import check_scene
    from kcheck.plugin import load_checks

    calls: list[Path] = []
    original = kcheck.body.meshio.load_mesh

    def counting(path: Path, scale: float, field: object, **kwargs: object) -> object:
        calls.append(path)
        return original(path, scale, field, **kwargs)

    monkeypatch.setattr(kcheck.body.meshio, "load_mesh", counting)
    scene = Path(__file__).resolve().parents[2] / "fixtures" / "planar-block" / "block.kcheck.yaml"
    result = check_scene(scene, load_checks())
    statuses = {c.id: c.status for c in result.checks}
    assert statuses["graphical-2d"] is Status.PASS and statuses["analytical-2d"] is Status.PASS
    assert len(calls) == 1


def test_bad_mesh_is_an_input_error_for_graphical_alone(
    write_scene: Callable[..., Path], tmp_path: Path
) -> None:
    """Without a load point the construction needs the centre of mass: an inverted mesh is
    then the scene's input error (field and line), not a crashed check."""
    import trimesh

    from kcheck.gate.runner import check_scene
    from kcheck.plugin import load_checks

    mesh = trimesh.creation.box(extents=(100.0, 60.0, 20.0))
    mesh.invert()
    mesh.export(tmp_path / "inv.stl")
    path = write_scene(
        """
        version: 1
        units: mm
        body: {mesh: inv.stl, material: aluminium}
        supports:
          - {name: y1, position: [20, 0, 10], normal: [0, 1, 0]}
          - {name: y2, position: [80, 0, 10], normal: [0, 1, 0]}
          - {name: x1, position: [0, 30, 10], normal: [1, 0, 0]}
        load: {magnitude: 1, angle: 225}
        """
    )
    only = [lc for lc in load_checks() if lc.spec.name == "graphical-2d"]
    result = check_scene(path, only)
    assert result.status is Status.ERROR and result.checks == ()
    assert f"{path}:3:8: field `body.mesh`:" in result.error and "inverted" in result.error
