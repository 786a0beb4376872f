"""No check crashes on extreme but finite input (issue 13): regression tests for each crash
class that reached the mechanics, and a property test over extreme magnitudes.

Scenes are built programmatically from the fixtures (``dataclasses.replace``), since the loader
may reject some of these inputs before they reach a check; the mechanics must survive them
anyway. Every warning is an error here: numpy's RuntimeWarnings must be handled, not printed.
"""

from __future__ import annotations

import dataclasses
import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kcheck.body.mass import body_mass_properties
from kcheck.plugin import Inputs, load_checks
from kcheck.result import CheckResult, Status
from kcheck.scene import Body, ExplicitMass, Preload, Scene, load_scene

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures"
CHECKS = {lc.spec.name: lc.check for lc in load_checks() if lc.spec.package == "kcheck"}
MECHANICS = ("maxwell", "analytical-2d", "analytical-3d", "graphical-2d")


def fixture(name: str) -> tuple[Scene, Any]:
    path = next((FIXTURES / name).glob("*.kcheck.yaml"))
    scene = load_scene(path)
    assert scene.body is not None
    return scene, body_mass_properties(scene.body, scene.scale)


PLANAR = fixture("planar-block")
SPATIAL = fixture("block-321")


def explicit(scene: Scene, mass: Any, kg: float, scale_inertia: float = 1.0) -> Scene:
    """The scene with explicit mass properties of ``kg``, same centre and gyration radii."""
    with np.errstate(all="ignore"):
        inertia = mass.inertia / mass.mass * kg * scale_inertia
    return dataclasses.replace(scene, body=Body((), ExplicitMass(kg, mass.center_of_mass, inertia)))


def run_all(scene: Scene) -> dict[str, CheckResult]:
    """Every applicable mechanics check, warnings as errors; results must serialise."""
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for check_id in MECHANICS:
            check = CHECKS[check_id]
            if check.skip_reason(scene) is not None:
                continue
            mass = None
            if check.needs_mass_for(scene):
                assert scene.body is not None
                with np.errstate(all="ignore"):
                    mass = body_mass_properties(scene.body, scene.scale)
            result = check.run(Inputs(scene, mass, check.options()))
            json.dumps(result.to_json(), allow_nan=False)
            out[check_id] = result
    return out


@pytest.mark.parametrize("base", [PLANAR, SPATIAL], ids=["planar", "spatial"])
def test_a_huge_normal_is_the_same_direction(base: tuple[Scene, Any]) -> None:
    """A normal like [0, 0, 1e300] (its square overflows) crashed every check with "SVD did not
    converge"; it is the direction it points in."""
    scene, _ = base
    supports = list(scene.supports)
    supports[0] = dataclasses.replace(supports[0], normal=supports[0].normal * 1e300)
    huge = run_all(dataclasses.replace(scene, supports=tuple(supports)))
    plain = run_all(scene)
    assert huge.keys() == plain.keys()
    for check_id, result in huge.items():
        assert result.status is plain[check_id].status
        assert [c.outcome for c in result.cases] == [c.outcome for c in plain[check_id].cases]
        if result.safe_ranges_deg:
            np.testing.assert_allclose(
                result.safe_ranges_deg, plain[check_id].safe_ranges_deg, atol=1e-9
            )


@pytest.mark.parametrize("base", [PLANAR, SPATIAL], ids=["planar", "spatial"])
@pytest.mark.parametrize("kg", [1e-320, 1e-30, 1e30, 1e308])
def test_extreme_masses_run(base: tuple[Scene, Any], kg: float) -> None:
    """Masses of 1e-320 kg (subnormal) to 1e308 kg (its weight overflows): the old generalised
    eigensolver "did not converge"; now every check answers. Only numbers beyond the largest
    float are infinite (null in JSON): the acceleration of 1e-320 kg under a load of newtons,
    the support forces under a weight of 1e309 N."""
    scene, mass = base
    results = run_all(explicit(scene, mass, kg))
    for result in results.values():
        assert result.status in (Status.PASS, Status.FAIL)
        for case in result.cases:
            if case.acceleration is not None:
                assert np.isfinite(case.acceleration) == (kg > 1e-300)
            for force in (case.normal_forces or {}).values():
                assert np.isfinite(force) or kg > 1e300


def test_a_solver_failure_is_ill_conditioned() -> None:
    """A non-finite inertia tensor (no loader lets one through) makes the linear algebra fail:
    every case is ill_conditioned with its reason, and the check fails saying so."""
    scene, mass = SPATIAL
    broken = dataclasses.replace(
        scene, body=Body((), ExplicitMass(mass.mass, mass.center_of_mass, np.full((3, 3), np.nan)))
    )
    result = run_all(broken)["analytical-3d"]
    assert result.status is Status.FAIL and result.error_estimate is None
    assert all(c.outcome == "ill_conditioned" for c in result.cases)
    assert all("nearly singular" in c.details["diagnostic"] for c in result.cases)
    assert "no trustworthy answer" in result.message


@settings(max_examples=40, deadline=None, derandomize=True)
@given(
    which=st.sampled_from(["planar-block", "block-321", "three-groove", "thesis-block-5-2"]),
    log_mass=st.sampled_from([None, -320, -30, 0, 30, 308]),
    log_length=st.sampled_from([0, -9, 9, -150, 150]),
    log_load=st.sampled_from([None, -300, -10, 10, 300]),
    friction=st.sampled_from([None, 0.0, 0.5, 5.0, 50.0]),
    tilt=st.floats(-16, -1),
    preload=st.booleans(),
)
def test_extreme_magnitudes_never_crash(
    which: str,
    log_mass: int | None,
    log_length: int,
    log_load: int | None,
    friction: float | None,
    tilt: float,
    preload: bool,
) -> None:
    """Lengths, masses, loads and friction over hundreds of decades, near-parallel normals and
    preloads: every check returns a result, no warning escapes."""
    scene, mass = fixture(which)
    length = 10.0**log_length
    kg = mass.mass if log_mass is None else 10.0**log_mass
    supports = []
    for k, s in enumerate(scene.supports):
        normal = s.normal.copy()
        if k == 0:
            normal[1] += 10.0**tilt  # nearly the neighbour's direction
        supports.append(
            dataclasses.replace(
                s,
                position=s.position * length,
                normal=normal,
                friction=s.friction if friction is None else friction,
            )
        )
    with np.errstate(all="ignore"):
        inertia = mass.inertia / mass.mass * kg * length**2
    if not (np.all(np.isfinite(inertia)) and np.all(np.diag(inertia)[2:] > 0)):
        return  # not a body any loader accepts
    body = Body((), ExplicitMass(kg, mass.center_of_mass * length, inertia))
    load = scene.load
    if load is not None:
        magnitude = load.magnitude if log_load is None else 10.0**log_load
        point = None if load.point is None else load.point * length
        load = dataclasses.replace(load, magnitude=magnitude, point=point)
    preloads = ()
    if preload:
        force = np.array([0.3, -0.2, 0.1 if scene.kind == "spatial" else 0.0]) * 10.0**tilt
        preloads = (Preload("spring", mass.center_of_mass * length, force),)
    changed = dataclasses.replace(
        scene, supports=tuple(supports), body=body, load=load, preloads=preloads
    )
    for result in run_all(changed).values():
        assert result.status in (Status.PASS, Status.FAIL)


#: One envelope series of analytical-3d's friction range on a generated scene (tests/fuzz
#: v2-1-35: a ball cone, a ball on two spheres and a flat support, in µm, friction 0.14–0.24):
#: negligible past its linear term, so its one root lies at -9.4e11, far outside [-1, 1].
FAR_ROOT_SERIES = [
    1.0015610632297246e-08, 1.062442165905252e-20, 3.447638913847274e-21,
    8.747035590369937e-21, -1.745705240637134e-21, 6.337124641115452e-21,
    6.934497952462824e-22, 1.7184680719525236e-23, 2.7430381711927926e-33,
    9.11628414322754e-35, 1.2423678662393543e-33, 5.156647276330155e-35,
    1.5613845553915354e-34, 5.189596886034049e-36, 4.395128998460706e-38,
    1.2647383120376513e-50, -4.3791346701866575e-51, 6.337219715742942e-51,
    -3.306357554490936e-51, -5.076686407436986e-53, 1.864229213664743e-67,
    1.8927761071866046e-67, -1.5280276031033024e-67, -4.8602500413773195e-68,
    3.3323353143762114e-68, -8.35544114113672e-84, 3.65755965210328e-99, 0.0, 0.0,
]  # fmt: skip


def test_a_root_far_outside_the_interval_is_dropped_without_a_warning():
    # Polishing the root at -9.4e11 evaluated the full degree-28 Vandermonde matrix there,
    # T_28(-9.4e11) ~ 1e336: "RuntimeWarning: overflow encountered in multiply" on stderr
    # (a crashed check under -W error). The series is 1e-8 plus terms below 1e-20 on [-1, 1]:
    # positive, no root there.
    from kcheck.numerics import chebyshev

    coefs = np.array([FAR_ROOT_SERIES])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        found = chebyshev.real_roots(coefs)
        assert np.isnan(found).all()
        assert chebyshev.positive(coefs).all()
