"""Every check's error estimate is honest (issue 10 #6): on random scenes it is not below the
actual error (allowing a factor 2 for the luck of rounding) and, as the geometric mean over
the scenes, within 10 times of it.

The actual error is measured against independent 50-digit computations written here with
mpmath from the scene's SI data (sharing no code with kcheck):

* analytical-2d: the range ends of tests/plugins/test_stiff_2d.py's reference;
* graphical-2d: the free twist and the friction-tilted twist as cross products of constraint
  rows, the virtual power ``a + c . d`` of the load, weight and preloads, its zero angles;
* analytical-3d: the free twist as the cofactor vector of the five remaining rows, the 6x6
  Newton–Euler systems, their affine solutions, the caps' radii, the design direction's margin
  and the sweep-plane range ends;
* maxwell: cos theta from the same twists.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from kcheck_checks.analytical_3d import Analytical3D, Analytical3DOptions
from kcheck_checks.graphical_2d import Graphical2D, GraphicalOptions
from kcheck_checks.maxwell import Maxwell, MaxwellOptions
from mpmath import mp, mpf

from kcheck.body.mass import body_mass_properties
from kcheck.plugin import Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene, load_scene
from tests.plugins.test_analytical_3d import random_layout, scene_dict
from tests.plugins.test_stiff_2d import reference_case
from tests.plugins.test_stiff_2d import run as run_2d


@pytest.fixture(autouse=True)
def _fifty_digits():
    """The 50-digit references of this module, whatever another module set (mpmath's
    precision is global)."""
    with mp.workdps(50):
        yield


RATIO_MEAN = 10.0  # geometric mean of estimate / actual at most this
RATIO_LOW = 0.5  # no estimate below half the actual error
ANGLE_ULP = 180.0 * float(np.finfo(float).eps)  # half an ulp of an angle below 360 deg


def write(tmp_path: Path, data: dict[str, Any], name: str) -> Path:
    path = tmp_path / f"{name}.kcheck.yaml"
    path.write_text(yaml.safe_dump(json.loads(json.dumps(data)), sort_keys=False))
    return path


def honest(pairs: list[tuple[float, float]], floor: float) -> None:
    """(estimate, actual) pairs: never far below, and within 10x on (geometric) average. An
    actual error below ``floor`` — half a unit in the last place of the reported number —
    counts as ``floor``: a result cannot be more exact than its representation."""
    est = np.array([e for e, _ in pairs])
    act = np.maximum(np.array([a for _, a in pairs]), floor)
    ratio = est / act
    assert np.all(ratio >= RATIO_LOW), sorted(ratio)[:5]
    assert float(np.exp(np.mean(np.log(ratio)))) <= RATIO_MEAN, np.quantile(ratio, [0.5, 0.9])


def mp_vec(v: Any) -> list[Any]:
    return [mpf(float(x)) for x in v]


def mp_unit(v: Any) -> list[Any]:
    v = mp_vec(v)
    n = mp.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def mp_ends(a: Any, b: Any, c: Any) -> list[Any]:
    """Angles (deg, [0, 360)) where ``a + b cos + c sin`` changes sign."""
    r = mp.hypot(b, c)
    if r == 0 or abs(a) >= r:
        return []
    return [mp.degrees(mp.atan2(c, b) + s * mp.acos(-a / r)) % 360 for s in (1, -1)]


def gap_deg(value: float, ends: list[Any]) -> float:
    """Distance (deg) of a reported end to the nearest reference end."""
    return float(min(abs((mpf(value) - e + 180) % 360 - 180) for e in ends))


def case_ends_error(result: CheckResult, reference_ends: list[list[Any]]) -> float:
    """Largest distance of any reported range end to the reference ends of its case."""
    worst = 0.0
    for case, ends in zip(result.cases, reference_ends, strict=True):
        for start, end in case.safe_ranges_deg or ():
            if end - start >= 360 - 1e-9:
                continue
            worst = max(worst, gap_deg(start % 360, ends), gap_deg(end % 360, ends))
    return worst


# --- planar scenes -------------------------------------------------------------------------


def planar_scene(rng: np.random.Generator, weight: bool) -> dict[str, Any]:
    """Three supports on a circle with normals tilted up to 57° from the centre."""
    phi = np.sort(rng.uniform(0, 2 * np.pi, 3))
    points = np.column_stack([np.cos(phi), np.sin(phi)]) * 50 + 50
    tilt = rng.uniform(-1, 1, 3)
    inward = -(points - 50) / 50
    normals = np.column_stack(
        [
            np.cos(tilt) * inward[:, 0] - np.sin(tilt) * inward[:, 1],
            np.sin(tilt) * inward[:, 0] + np.cos(tilt) * inward[:, 1],
        ]
    )
    data: dict[str, Any] = {
        "version": 1,
        "units": "mm",
        "body": {
            "mass": float(rng.uniform(0.1, 10)),
            "center_of_mass": [*rng.uniform(20, 80, 2).tolist(), 0.0],
            "inertia": float(10 ** rng.uniform(-5, -2)),
        },
        "supports": [
            {
                "name": f"s{i}",
                "position": [*points[i].tolist(), 0.0],
                "normal": [*normals[i].tolist(), 0.0],
            }
            for i in range(3)
        ],
        "friction": float(rng.uniform(0, 0.5)),
        "load": {"magnitude": 1.0, "point": [*rng.uniform(0, 100, 2).tolist(), 0.0]},
    }
    if weight:
        data["gravity"] = [*(rng.normal(size=2) * 3).tolist(), 0.0]
    return data


def test_analytical_2d_error_estimate_is_honest(tmp_path: Path) -> None:
    rng = np.random.default_rng(2024)
    pairs = []
    for k in range(30):
        scene, mass, result = run_2d(write(tmp_path, planar_scene(rng, k % 2 == 0), f"a{k}"))
        if result.error_estimate is None:
            continue
        ends = [
            [mp.degrees(e) % 360 for e in reference_case(scene, mass, r).ends()] for r in range(3)
        ]
        actual = case_ends_error(result, ends)
        pairs.append((result.error_estimate, actual))
    assert len(pairs) >= 15
    honest(pairs, ANGLE_ULP)


def graphical_ends(scene: Scene, mass: Any, retracted: int) -> list[Any]:
    """Zero angles of the virtual power about the pole and the friction pole, 50 digits: the
    ends of every graphical range of the case."""
    pts = [mp_vec(s.position[:2]) for s in scene.supports]
    nrm = [mp_unit(s.normal[:2]) for s in scene.supports]
    mus = [mpf(float(s.friction)) for s in scene.supports]
    keep = [j for j in range(3) if j != retracted]

    def row(p: Any, f: Any) -> list[Any]:
        return [p[0] * f[1] - p[1] * f[0], f[0], f[1]]

    def cross(a: Any, b: Any) -> list[Any]:
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    def vel(t: Any, p: Any) -> list[Any]:
        return [t[1] - t[0] * p[1], t[2] + t[0] * p[0]]

    plain = cross(row(pts[keep[0]], nrm[keep[0]]), row(pts[keep[1]], nrm[keep[1]]))
    u = vel(plain, pts[retracted])
    if nrm[retracted][0] * u[0] + nrm[retracted][1] * u[1] > 0:
        plain = [-x for x in plain]
    tilted_rows = []
    for j in keep:
        v = vel(plain, pts[j])
        speed = mp.sqrt(v[0] ** 2 + v[1] ** 2)
        f = [nrm[j][i] - mus[j] * v[i] / speed for i in range(2)]
        tilted_rows.append(row(pts[j], f))
    tilted = cross(*tilted_rows)
    plain0 = cross(row(pts[keep[0]], nrm[keep[0]]), row(pts[keep[1]], nrm[keep[1]]))
    sign = 1 if sum(x * y for x, y in zip(plain0, plain, strict=True)) > 0 else -1
    tilted = [sign * x for x in tilted]
    load = scene.load
    assert load is not None
    q = mp_vec((mass.center_of_mass if load.point is None else load.point)[:2])
    com = mp_vec(mass.center_of_mass[:2])
    weight = [
        mpf(float(mass.mass)) * mpf(float(g)) / mpf(float(load.magnitude))
        for g in scene.gravity[:2]
    ]
    ends = []
    for t in (plain, tilted):
        c = vel(t, q)
        uc = vel(t, com)
        a = weight[0] * uc[0] + weight[1] * uc[1]
        ends += mp_ends(a, c[0], c[1])
    return ends


def test_graphical_2d_error_estimate_is_honest(tmp_path: Path) -> None:
    rng = np.random.default_rng(77)
    pairs = []
    for k in range(30):
        scene = load_scene(write(tmp_path, planar_scene(rng, k % 2 == 0), f"g{k}"))
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        result = Graphical2D().run(Inputs(scene, mass, GraphicalOptions()))
        if result.error_estimate is None:
            continue
        actual = case_ends_error(result, [graphical_ends(scene, mass, r) for r in range(3)])
        pairs.append((result.error_estimate, actual))
    assert len(pairs) >= 15
    honest(pairs, ANGLE_ULP)


# --- spatial scenes ------------------------------------------------------------------------


def mp_det(rows: list[list[Any]]) -> Any:
    return mp.det(mp.matrix(rows))


def mp_null(rows: list[list[Any]]) -> list[Any]:
    """The null vector of five 6-vectors: its cofactors."""
    return [
        (-1) ** i * mp_det([[r[k] for k in range(6) if k != i] for r in rows]) for i in range(6)
    ]


def cross3(a: Any, b: Any) -> list[Any]:
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def spatial_reference(scene: Scene, mass: Any, retracted: int) -> tuple[list[Any], list[Any]]:
    """Caps ``a_k + c_k . d > 0`` (c_k a 3-vector) of one case, 50 digits; empty when the case
    is Painlevé-type (ambiguous everywhere)."""
    pts = [mp_vec(s.position) for s in scene.supports]
    nrm = [mp_unit(s.normal) for s in scene.supports]
    mus = [mpf(float(s.friction)) for s in scene.supports]
    keep = [j for j in range(6) if j != retracted]
    rows = [cross3(pts[j], nrm[j]) + nrm[j] for j in keep]
    twist = mp_null(rows)
    w, v = twist[:3], twist[3:]

    def vel(p: Any) -> list[Any]:
        wp = cross3(w, p)
        return [v[i] + wp[i] for i in range(3)]

    ur = vel(pts[retracted])
    if sum(nrm[retracted][i] * ur[i] for i in range(3)) > 0:
        twist = [-x for x in twist]
        w, v = twist[:3], twist[3:]
    m = mpf(float(mass.mass))
    com = mp_vec(mass.center_of_mass)
    inertia = [[mpf(float(x)) for x in row] for row in mass.inertia]
    iw = [sum(inertia[i][k] * w[k] for k in range(3)) for i in range(3)]
    uc = vel(com)

    def matrix(sense: int, friction: bool = True) -> list[list[Any]]:
        cols = [iw + [m * x for x in uc]]
        for j in keep:
            u = vel(pts[j])
            speed = mp.sqrt(sum(x * x for x in u))
            mu = mus[j] if friction else 0
            f = [nrm[j][i] - sense * mu * u[i] / speed for i in range(3)]
            lever = [pts[j][i] - com[i] for i in range(3)]
            cols.append([-x for x in cross3(lever, f) + f])
        return [[cols[c][r] for c in range(6)] for r in range(6)]

    base = mp_det(matrix(1, friction=False))
    if any(mp_det(matrix(s)) / base <= 0 for s in (1, -1)):
        return [], []
    load = scene.load
    assert load is not None
    size = mpf(float(load.magnitude))
    q = mp_vec(mass.center_of_mass if load.point is None else load.point)
    lever = [q[i] - com[i] for i in range(3)]
    b0 = [mpf(0)] * 3 + [m * mpf(float(g)) for g in scene.gravity]
    basis = []
    for axis in range(3):
        e = [mpf(int(i == axis)) for i in range(3)]
        basis.append([size * x for x in cross3(lever, e)] + [size * x for x in e])
    k = mp.matrix(matrix(1))
    sol_a = mp.lu_solve(k, mp.matrix(b0))
    sol_c = [mp.lu_solve(k, mp.matrix(b)) for b in basis]
    a = [sol_a[i] for i in range(6)]
    c = [[sol_c[axis][i] for axis in range(3)] for i in range(6)]
    return a, c


def perturbed_block(rng: np.random.Generator) -> dict[str, Any]:
    """The 3-2-1 block fixture with its mass made explicit, supports moved up to 5 mm and
    turned up to 6°, another friction, load point and direction: couplings that close."""
    path = Path(__file__).resolve().parents[2] / "fixtures" / "block-321" / "block.kcheck.yaml"
    data = scene_dict(path, explicit=True)
    for support in data["supports"]:
        support["position"] = (np.array(support["position"]) + rng.uniform(-5, 5, 3)).tolist()
        support["normal"] = (np.array(support["normal"]) + rng.normal(size=3) * 0.1).tolist()
    data["friction"] = float(rng.uniform(0, 0.2))
    data["load"]["point"] = (np.array(data["load"]["point"]) + rng.uniform(-20, 20, 3)).tolist()
    data["load"]["direction"] = (
        np.array(data["load"]["direction"]) + rng.normal(size=3) * 0.1
    ).tolist()
    data.pop("checks", None)
    return data


def dot(u: Any, v: Any) -> Any:
    return sum(x * y for x, y in zip(u, v, strict=True))


def plane_ends(a: list[Any], c: list[Any], e1: list[Any], e2: list[Any]) -> list[Any]:
    """Zero angles (deg) of the caps ``a_k + c_k . d`` on the sweep plane ``(e1, e2)``."""
    out = []
    for ak, ck in zip(a, c, strict=True):
        out += mp_ends(ak, dot(ck, e1), dot(ck, e2))
    return out


def test_analytical_3d_error_estimate_is_honest(tmp_path: Path) -> None:
    """The check's estimate (degrees) covers the sweep-plane range ends and the safe region's
    margins; compared with the ends and with the most robust direction's margin from the
    50-digit caps (its direction rounded to double, the margin recomputed in 50 digits)."""
    rng = np.random.default_rng(5)
    pairs = []
    for k in range(12):
        data = perturbed_block(rng)
        scene = load_scene(write(tmp_path, data, f"s{k}"))
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        result = Analytical3D().run(Inputs(scene, mass, Analytical3DOptions()))
        if result.error_estimate is None:
            continue
        refs = {r: spatial_reference(scene, mass, r) for r in range(6)}
        plane = result.details["sweep_plane"]
        e1 = mp_vec(plane["zero"])
        e2 = cross3(mp_vec(plane["normal"]), e1)

        ends = [plane_ends(*refs[r], e1, e2) for r in range(6)]
        actual = case_ends_error(result, ends)
        robust = result.details.get("most_robust_direction")
        if robust is not None:
            d = mp_unit(robust)
            margin = mpf(10) ** 10
            for a, c in refs.values():
                for ak, ck in zip(a, c, strict=True):
                    size = mp.sqrt(sum(x * x for x in ck))
                    ratio = -ak / size
                    if abs(ratio) < 1:
                        axis = [x / size for x in ck]
                        angle = mp.acos(dot(axis, d))
                        margin = min(margin, mp.acos(ratio) - angle)
            actual = max(
                actual, abs(float(mp.degrees(margin)) - result.details["robust_margin_deg"])
            )
        pairs.append((result.error_estimate, actual))
    assert len(pairs) >= 6
    honest(pairs, ANGLE_ULP)


def test_maxwell_error_estimate_is_honest(tmp_path: Path) -> None:
    rng = np.random.default_rng(9)
    pairs = []
    for k in range(20):
        scene = load_scene(write(tmp_path, random_layout(rng), f"m{k}"))
        result = Maxwell().run(Inputs(scene, None, MaxwellOptions(min_cos=0.0)))
        if result.error_estimate is None:
            continue
        pts = [mp_vec(s.position) for s in scene.supports]
        nrm = [mp_unit(s.normal) for s in scene.supports]
        worst = 0.0
        for r, case in enumerate(result.cases):
            keep = [j for j in range(6) if j != r]
            twist = mp_null([cross3(pts[j], nrm[j]) + nrm[j] for j in keep])
            u = [twist[3 + i] + cross3(twist[:3], pts[r])[i] for i in range(3)]
            cos = abs(sum(nrm[r][i] * u[i] for i in range(3))) / mp.sqrt(sum(x * x for x in u))
            worst = max(worst, abs(float(cos) - case.cos_maxwell))
        pairs.append((result.error_estimate, worst))
    honest(pairs, float(np.finfo(float).eps) / 2)


def test_safe_share_error_estimate_is_honest(tmp_path: Path) -> None:
    """The exact safe share's estimate against the share of the 50-digit caps (rounded to
    double only at the end): the error the caps' coefficients carry into the area."""
    from kcheck_checks.analytical_3d import sphere_map

    from kcheck.analysis import analyse
    from kcheck.mechanics.caps import region

    rng = np.random.default_rng(1)
    pairs = []
    for k in range(8):
        scene = load_scene(write(tmp_path, perturbed_block(rng), f"f{k}"))
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        smap = sphere_map(scene, analyse(scene, mass))
        assert smap is not None and not smap.empty
        a_ref: list[float] = []
        c_ref: list[list[float]] = []
        for r in range(6):
            a, c = spatial_reference(scene, mass, r)
            a_ref += [float(x) for x in a] or [-1.0]
            c_ref += [[float(x) for x in row] for row in c] or [[0.0, 0.0, 0.0]]
        reference = region(np.array(a_ref), np.array(c_ref)).fraction
        pairs.append((smap.fraction.error, abs(smap.fraction.fraction - reference)))
    honest(pairs, float(np.finfo(float).eps) / 2 * 0.01)
