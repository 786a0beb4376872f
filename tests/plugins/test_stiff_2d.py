"""Stiff and extreme planar cases: `analytical-2d` is right or says it cannot be trusted.

The reference is an independent high-precision computation written here with mpmath (50
digits): the free twist as the cross product of the two remaining constraint rows (pole-free,
exact for a pole at infinity), Newton–Euler about the centre of mass as a 3x3 system in SI
units, solved by LU in mpmath, and the arc ends of methods.md §4 in mpmath. It shares no code
with kcheck: it reads the same scene file through the real loader and stops there.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh
import yaml
from kcheck_checks.analytical_2d import Analytical2D, AnalyticalOptions
from mpmath import mp, mpf

from kcheck.body.mass import body_mass_properties
from kcheck.plugin import Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene, load_scene
from kcheck.scene.limits import LIMITS, Range


@pytest.fixture(autouse=True)
def _fifty_digits():
    """The 50-digit references of this module, whatever another module set (mpmath's
    precision is global)."""
    with mp.workdps(50):
        yield


DIAGNOSTIC = ("ill_conditioned", "undetermined")


@pytest.fixture(autouse=True)
def _beyond_physical_ranges(monkeypatch: pytest.MonkeyPatch) -> None:
    """These tests probe the numerics far beyond the loader's physical ranges (masses to
    1e15 kg and down to a 100 um block's 3e-10 kg and 1e-19 kg m², layouts to 10 km): widen
    the ranges they need."""
    monkeypatch.setitem(LIMITS, "mass", Range(1e-12, 1e20, "kg", "mass"))
    monkeypatch.setitem(LIMITS, "inertia", Range(1e-30, 1e20, "kg m^2", "principal moment"))
    monkeypatch.setitem(LIMITS, "coordinate", Range(-1e5, 1e5, "m", "each coordinate"))


# --- scene files ------------------------------------------------------------------------------


def write_scene(directory: Path, data: dict[str, Any], name: str = "scene") -> Path:
    """Write a scene mapping as a real ``*.kcheck.yaml`` file."""
    path = directory / f"{name}.kcheck.yaml"
    plain = json.loads(json.dumps(data, default=float))  # numpy scalars to plain floats
    path.write_text(yaml.safe_dump(plain, sort_keys=False), encoding="utf-8")
    return path


def run(path: Path) -> tuple[Scene, Any, CheckResult]:
    """Load a scene with the real loader, its mass properties, and run `analytical-2d`."""
    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    options = AnalyticalOptions.model_validate(scene.check_options.get("analytical-2d", {}))
    return scene, mass, Analytical2D().run(Inputs(scene, mass, options))


def scene_data(
    supports: list[tuple[str, list[float], list[float]]],
    *,
    mass: float = 1.0,
    com: list[float] | None = None,
    inertia: float = 1e-3,
    mu: float = 0.1,
    angle: float | None = 225.0,
    units: str = "mm",
    gravity: list[float] | None = None,
    point: list[float] | None = None,
    magnitude: float = 1.0,
) -> dict[str, Any]:
    """A planar scene mapping with explicit mass properties."""
    load: dict[str, Any] = {"magnitude": magnitude}
    if angle is not None:
        load["angle"] = angle
    if point is not None:
        load["point"] = point
    data: dict[str, Any] = {
        "version": 1,
        "units": units,
        "body": {"mass": mass, "center_of_mass": com or [50, 30, 0], "inertia": inertia},
        "supports": [{"name": n, "position": p, "normal": d} for n, p, d in supports],
        "friction": mu,
        "load": load,
    }
    if gravity is not None:
        data["gravity"] = gravity
    return data


BLOCK = [
    ("y1", [20, 0, 0], [0, 1, 0]),
    ("y2", [80, 0, 0], [0, 1, 0]),
    ("x1", [0, 30, 0], [1, 0, 0]),
]


# --- the independent reference ------------------------------------------------------------------


@dataclass
class Reference:
    """mpmath solution of one retracted case: ``x = A + B cos(alpha) + C sin(alpha)``."""

    a: list[Any]  # [lambda-acceleration of the retracted point (m/s^2), N_j (N) ...]
    b: list[Any]
    c: list[Any]

    def at(self, alpha: Any) -> list[Any]:
        """Unknowns at a force angle (rad)."""
        return [
            a + b * mp.cos(alpha) + c * mp.sin(alpha)
            for a, b, c in zip(self.a, self.b, self.c, strict=True)
        ]

    def ends(self) -> list[Any]:
        """Angles (rad, [0, 2 pi)) where some unknown changes sign."""
        out = []
        for a, b, c in zip(self.a, self.b, self.c, strict=True):
            r = mp.hypot(b, c)
            if r > 0 and abs(a) < r:
                for s in (1, -1):
                    out.append((mp.atan2(c, b) + s * mp.acos(-a / r)) % (2 * mp.pi))
        return out

    def closes(self, alpha: Any) -> bool:
        """Whether every unknown is positive."""
        return all(x > 0 for x in self.at(alpha))


def _system(
    scene: Scene, mass: Any, retracted: int, sense: int = 1, friction: bool = True
) -> tuple[Any, list[Any], Any]:
    """The case's Newton–Euler matrix in 50 digits, its right-hand sides (fixed, cos, sin) and
    the closing rate of the retracted point; friction opposes the motion along the closing
    twist (``sense`` +1) or the reverse (-1), or is left out (``friction`` False)."""
    pts = [[mpf(float(v)) for v in s.position[:2]] for s in scene.supports]
    nrm = []
    for s in scene.supports:
        n = [mpf(float(v)) for v in s.normal[:2]]
        length = mp.sqrt(n[0] ** 2 + n[1] ** 2)
        nrm.append([n[0] / length, n[1] / length])
    mus = [mpf(float(s.friction)) if friction else mpf(0) for s in scene.supports]
    keep = [j for j in range(3) if j != retracted]

    def row(j: int) -> list[Any]:
        p, n = pts[j], nrm[j]
        return [p[0] * n[1] - p[1] * n[0], n[0], n[1]]

    ra, rb = row(keep[0]), row(keep[1])
    twist = [
        ra[1] * rb[2] - ra[2] * rb[1],
        ra[2] * rb[0] - ra[0] * rb[2],
        ra[0] * rb[1] - ra[1] * rb[0],
    ]

    def vel(p: list[Any]) -> list[Any]:
        return [twist[1] - twist[0] * p[1], twist[2] + twist[0] * p[0]]

    u_r = vel(pts[retracted])
    gap = nrm[retracted][0] * u_r[0] + nrm[retracted][1] * u_r[1]
    if gap > 0:
        twist, gap = [-t for t in twist], -gap
    m = mpf(float(mass.mass))
    c = [mpf(float(v)) for v in mass.center_of_mass[:2]]
    inertia = mpf(float(mass.inertia[2, 2]))
    uc = vel(c)
    rows = [[inertia * twist[0]], [m * uc[0]], [m * uc[1]]]
    for j in keep:
        u = vel(pts[j])
        speed = mp.sqrt(u[0] ** 2 + u[1] ** 2)
        t = [-sense * u[0] / speed, -sense * u[1] / speed]
        f = [nrm[j][0] + mus[j] * t[0], nrm[j][1] + mus[j] * t[1]]
        r = [pts[j][0] - c[0], pts[j][1] - c[1]]
        col = [-(r[0] * f[1] - r[1] * f[0]), -f[0], -f[1]]
        for i in range(3):
            rows[i].append(col[i])
    load = scene.load
    assert load is not None
    fs = mpf(float(load.magnitude))
    q = c if load.point is None else [mpf(float(v)) for v in load.point[:2]]
    g = [m * mpf(float(v)) for v in scene.gravity[:2]]
    torque = mpf(float(load.torque[2]))
    lever = [q[0] - c[0], q[1] - c[1]]
    rhs0 = mp.matrix([torque, g[0], g[1]])
    rhs_cos = mp.matrix([lever[0] * 0 - lever[1] * fs, fs, 0])  # F = fs (1, 0)
    rhs_sin = mp.matrix([lever[0] * fs, 0, fs])  # F = fs (0, 1)
    return mp.matrix(rows), [rhs0, rhs_cos, rhs_sin], -gap


def reference(scene: Scene, mass: Any, retracted: int, sense: int = 1) -> Reference:
    """The case in 50 digits from the scene's SI data (methods.md §3); friction opposes the
    motion along the closing twist (``sense`` +1) or the reverse (-1)."""
    matrix, rhs, closing = _system(scene, mass, retracted, sense)
    sols = [mp.lu_solve(matrix, b) for b in rhs]
    scale = [closing, 1, 1]  # lambda -> acceleration of the retracted point
    return Reference(*([sol[i] * scale[i] for i in range(3)] for sol in sols))


def painleve(scene: Scene, mass: Any, retracted: int) -> bool:
    """Whether friction makes the effective mass along the free twist non-positive:
    ``det K / det K(mu = 0)`` <= 0 under forward or backward friction (methods of
    kcheck.mechanics.dynamics, recomputed here from the determinants)."""
    base = mp.det(_system(scene, mass, retracted, 1, friction=False)[0])
    return any(mp.det(_system(scene, mass, retracted, s)[0]) / base <= 0 for s in (1, -1))


@dataclass
class ReferenceCase:
    """Both friction assumptions of one case in 50 digits, and whether it is Painlevé-type."""

    forward: Reference
    backward: Reference
    painleve: bool

    def outcome(self, alpha: Any) -> str:
        """The outcome rule of docs/checks.md, in mpmath: a Painlevé-type case is ambiguous;
        else forward (closes / loses contact), backward (opens / opens while losing contact)
        or neither (jams)."""
        x, xb = self.forward.at(alpha), self.backward.at(alpha)
        if self.painleve:
            return "ambiguous"
        if x[0] > 0:
            return "closes" if all(n > 0 for n in x[1:]) else "loses_contact"
        if xb[0] < 0:
            return "opens" if all(n > 0 for n in xb[1:]) else "opens_loses_contact"
        return "jams"

    def ends(self) -> list[Any]:
        """Angles where an unknown of the forward solution changes sign (the ends of the
        closing ranges are among them)."""
        return self.forward.ends()


def reference_case(scene: Scene, mass: Any, retracted: int) -> ReferenceCase:
    """:class:`ReferenceCase` of one retracted support."""
    return ReferenceCase(
        reference(scene, mass, retracted, +1),
        reference(scene, mass, retracted, -1),
        painleve(scene, mass, retracted),
    )


def reference_outcome(scene: Scene, mass: Any, retracted: int, alpha: Any) -> str:
    """The outcome at a force angle (rad) (:meth:`ReferenceCase.outcome`)."""
    return reference_case(scene, mass, retracted).outcome(alpha)


def _inside(ranges: Any, deg: float) -> bool:
    return any(s <= deg <= e or s <= deg + 360 <= e for s, e in ranges)


def assert_matches(scene: Scene, mass: Any, result: CheckResult, rel: float = 1e-9) -> int:
    """Every case that is not flagged agrees with the reference; returns how many did.

    At the design direction: the outcome, and the numbers relative to the largest unknown.
    Ranges: every end within the check's own error estimate (deg) plus 1e-10 deg of a
    reference end, and inside/outside equal on 72 angles and at every reference arc's middle.
    """
    compared = 0
    design = scene.design_angle_deg
    tol = (result.error_estimate or 0.0) + 1e-10
    for r, case in enumerate(result.cases):
        if case.outcome in DIAGNOSTIC:
            assert "diagnostic" in case.details
            continue
        ref = reference_case(scene, mass, r)
        ends = [float(mp.degrees(e)) for e in ref.ends()]
        if design is not None:
            alpha = mp.radians(design)
            assert case.outcome == ref.outcome(alpha), case.retracted
            if case.outcome not in ("jams", "ambiguous"):  # no motion to report otherwise
                sense = -1 if case.outcome.startswith("opens") else 1
                x = reference(scene, mass, r, sense).at(alpha)
                got = [case.acceleration, *case.normal_forces.values()]
                size = max(abs(float(v)) for v in x)
                for g, e in zip(got, x, strict=True):
                    assert abs(g - float(e)) <= rel * size, (case.retracted, got, x)
        if ref.painleve:  # ambiguous everywhere: no safe angle
            assert case.safe_ranges_deg == ()
            compared += 1
            continue
        got_ends = [v % 360 for arc in case.safe_ranges_deg for v in arc if arc != (0.0, 360.0)]
        for v in got_ends:
            assert min(abs((v - e + 180) % 360 - 180) for e in ends) <= tol, (case.retracted, v)
        samples = [float(v) for v in np.arange(0.0, 360.0, 5.0) + 0.123]
        srt = sorted(ends)
        nxt = srt[1:] + srt[:1]
        samples += [(a + (b if b > a else b + 360)) / 2 for a, b in zip(srt, nxt, strict=True)]
        for deg in samples:
            if min((abs((deg - e + 180) % 360 - 180) for e in ends), default=180) > 10 * tol:
                expected = ref.outcome(mp.radians(deg)) == "closes"
                assert _inside(case.safe_ranges_deg, deg) == expected, (case.retracted, deg)
        compared += 1
    return compared


# --- near-parallel normals: the pole runs off to infinity -------------------------------------


@pytest.mark.parametrize("exponent", [3, 6, 9, 12, 15])
def test_near_parallel_normals(tmp_path: Path, exponent: int) -> None:
    """y2's normal tilted by eps puts the pole of the x1 case ~60 mm / eps away: 1e3 to 1e15
    times the layout. The twist formulation must stay exact (mpmath agrees to 1e-9)."""
    eps = 10.0**-exponent
    supports = [BLOCK[0], ("y2", [80, 0, 0], [np.sin(eps), np.cos(eps), 0]), BLOCK[2]]
    scene, mass, result = run(write_scene(tmp_path, scene_data(supports)))
    assert assert_matches(scene, mass, result) == 3
    x1 = result.cases[2]
    assert x1.details["condition"] < 10
    pole_distance = 1e3 * (1 / eps)  # mm, rough
    if x1.details["motion"] == "rotation":
        assert np.hypot(*x1.details["pole"]) == pytest.approx(pole_distance * 60e-6, rel=0.5)
    else:
        assert exponent >= 12  # reported as a translation beyond 1e12 layout sizes


# --- nearly concurrent normals: the layout approaches a disc on three supports ---------------


@pytest.mark.parametrize("exponent", [2, 5, 8, 11, 14, 17])
def test_nearly_concurrent_normals(tmp_path: Path, exponent: int) -> None:
    """Three radial normals of a disc (radius 50 mm) meet in its centre; one support is moved
    along its tangent by 50 mm * delta so its normal misses the centre. Every case's free motion
    then barely closes its gap (rate ~ delta): right to mpmath, or flagged, never nonsense."""
    delta = 10.0**-exponent
    radius = 50.0
    supports = []
    for k, phi in enumerate(np.radians([90.0, 210.0, 330.0])):
        p = radius * np.array([np.cos(phi), np.sin(phi)])
        if k == 0:
            p = p + radius * delta * np.array([-np.sin(phi), np.cos(phi)])
        supports.append((f"s{k}", [p[0], p[1], 0.0], [-np.cos(phi), -np.sin(phi), 0.0]))
    data = scene_data(supports, com=[0, 0, 0], inertia=1.25e-3, angle=100.0, point=[0, 40, 0])
    scene, mass, result = run(write_scene(tmp_path, data))
    compared = assert_matches(scene, mass, result, rel=max(1e-9, 1e-14 / delta))
    flagged = [c for c in result.cases if c.outcome in DIAGNOSTIC]
    assert compared + len(flagged) == 3
    if delta <= 1e-11:
        assert flagged, "the gap cannot be told to close at this rounding level"


# --- friction from none to very large -----------------------------------------------------------


SKEW = [
    ("a", [10, 0, 0], [0.2, 1, 0]),
    ("b", [90, 5, 0], [-0.3, 1, 0]),
    ("c", [0, 40, 0], [1, -0.1, 0]),
]


@pytest.mark.parametrize("mu", [0.0, 0.5, 1.0, 2.0, 5.0, 50.0])
@pytest.mark.parametrize("layout", ["block", "skew"])
def test_friction_zero_to_large(tmp_path: Path, mu: float, layout: str) -> None:
    """mu = 0 and mu >= 1 against mpmath (the forward system can turn singular at some mu)."""
    supports = BLOCK if layout == "block" else SKEW
    data = scene_data(supports, mu=mu, inertia=4e-4, angle=235.0, point=[60, 45, 0])
    scene, mass, result = run(write_scene(tmp_path, data))
    assert (
        assert_matches(scene, mass, result) + sum(c.outcome in DIAGNOSTIC for c in result.cases)
        == 3
    )


def test_frictionless_sign_flips_at_pole(tmp_path: Path) -> None:
    """mu = 0: lambda changes sign exactly where the force line passes through the pole
    (methods.md §7), so the range ends are the directions from the load point to the poles."""
    data = scene_data(SKEW, mu=0.0, angle=None, point=[60, 45, 0])
    scene, mass, result = run(write_scene(tmp_path, data))
    q = np.array([60.0, 45.0]) * 1e-3
    for case in result.cases:
        pole = np.array(case.details["pole"])
        towards = np.degrees(np.arctan2(*(pole - q)[::-1])) % 360
        ends = {round(v % 360, 6) for arc in case.safe_ranges_deg for v in arc}
        ref = reference(scene, mass, [c.retracted for c in result.cases].index(case.retracted))
        lam_ends = [
            float(mp.degrees(e)) for e in Reference([ref.a[0]], [ref.b[0]], [ref.c[0]]).ends()
        ]
        got = sorted(v % 180 for v in lam_ends)
        assert got == pytest.approx([towards % 180] * 2, abs=1e-9)
        assert ends  # the safe range is bounded


# --- scale: um to 100 m, the same numbers in different units -----------------------------------


def test_units_um_mm_m_give_identical_ranges(tmp_path: Path) -> None:
    """The same mesh file and numbers in um, mm, cm, m: a 100 um to a 100 m aluminium block.
    Mass scales as L^3 and inertia as L^5, so I / (m L^2) and every force angle are unchanged."""
    mesh = trimesh.creation.box(extents=(100.0, 60.0, 20.0))
    mesh.apply_translation([50.0, 30.0, 10.0])
    ranges = {}
    for units in ("um", "mm", "cm", "m"):
        folder = tmp_path / units
        folder.mkdir()
        mesh.export(folder / "block.stl")
        data = {
            "version": 1,
            "units": units,
            "body": {"mesh": "block.stl", "material": "aluminium"},
            "supports": [{"name": n, "position": p, "normal": d} for n, p, d in SKEW],
            "friction": 0.15,
            "load": {"magnitude": 1.0, "point": [60, 45, 10], "angle": 235.0},
        }
        _, _, result = run(write_scene(folder, data))
        ranges[units] = [r for c in result.cases for r in c.safe_ranges_deg]
    flat = {u: np.array(r).ravel() for u, r in ranges.items()}
    for units in ("um", "cm", "m"):
        np.testing.assert_allclose(flat[units], flat["mm"], rtol=0, atol=1e-9)


@pytest.mark.parametrize("size_m", [1e-5, 1e-3, 1.0, 10.0])
def test_scale_against_mpmath(tmp_path: Path, size_m: float) -> None:
    """A 10 um to 10 m layout (explicit mass properties, fixed shape) agrees with mpmath."""
    k = size_m / 0.1
    supports = [(n, [v * k for v in p], d) for n, p, d in SKEW]
    data = scene_data(
        supports,
        units="m" if size_m >= 1 else "mm",
        mass=1.0,
        com=[0.05 * k, 0.03 * k, 0],
        inertia=1e-3 * (size_m / 0.1) ** 2,
        point=[0.06 * k, 0.045 * k, 0],
    )
    if size_m < 1:  # positions in mm
        for s in data["supports"]:
            s["position"] = [v * 1e3 for v in s["position"]]
        data["body"]["center_of_mass"] = [v * 1e3 for v in data["body"]["center_of_mass"]]
        data["load"]["point"] = [v * 1e3 for v in data["load"]["point"]]
    scene, mass, result = run(write_scene(tmp_path, data))
    assert assert_matches(scene, mass, result) == 3


# --- mass and inertia over many decades, gravity much larger than the load --------------------


@pytest.mark.parametrize("log_mass", [-9, -3, 0, 3, 9])
@pytest.mark.parametrize("log_gyration", [-6, -2, 0, 2, 6])
def test_mass_and_inertia_over_decades(tmp_path: Path, log_mass: int, log_gyration: int) -> None:
    """m from 1e-9 to 1e9 kg, I / (m L^2) from 1e-6 to 1e6 (L = 0.1 m): right or flagged."""
    m = 10.0**log_mass
    inertia = m * 0.01 * 10.0**log_gyration
    data = scene_data(SKEW, mass=m, inertia=inertia, angle=235.0, point=[60, 45, 0])
    scene, mass, result = run(write_scene(tmp_path, data))
    assert (
        assert_matches(scene, mass, result) + sum(c.outcome in DIAGNOSTIC for c in result.cases)
        == 3
    )


@pytest.mark.parametrize("ratio", [1e1, 1e4, 1e8, 1e12])
def test_gravity_much_larger_than_load(tmp_path: Path, ratio: float) -> None:
    """Weight = ratio x load, pulling into the corner: the load barely moves the answer."""
    g = 9.81
    data = scene_data(
        BLOCK, mass=ratio / g, inertia=ratio / g * 1e-3, gravity=[-g * 0.3, -g, 0], angle=45.0
    )
    scene, mass, result = run(write_scene(tmp_path, data))
    assert assert_matches(scene, mass, result) == 3
    assert all(c.outcome == "closes" for c in result.cases)


@pytest.mark.parametrize("ratio", [1e2, 1e6, 1e10, 1e14, 1e16])
def test_gravity_through_a_pole(tmp_path: Path, ratio: float) -> None:
    """Frictionless, the weight's line passes exactly through the pole of the y1 case (the
    centre of mass is placed on it), so only the 1 N load decides lambda's sign however heavy
    the body: the y1 range stays 180-270 deg (lambda > 0 for 180-360 deg, x1 pushes for 90-270
    deg; reference: mpmath). A tolerance shared by all unknowns once erased x1's load term."""
    g = 9.81
    data = scene_data(
        BLOCK,
        mu=0.0,
        mass=ratio / g,
        com=[80, 30, 0],
        inertia=ratio / g * 1e-3,
        gravity=[0, -g, 0],
        angle=225.0,
        point=[50, 30, 0],
    )
    scene, mass, result = run(write_scene(tmp_path, data))
    assert assert_matches(scene, mass, result) == 3
    assert list(result.cases[0].safe_ranges_deg[0]) == pytest.approx([180.0, 270.0], abs=1e-9)
    assert len(result.cases[0].safe_ranges_deg) == 1
