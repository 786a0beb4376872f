"""The sliding limit (``sliding_limit.sliding_limit``): the least holding friction of five
contacts in space from Newton's method on the twist along which every contact slides, with
its own certificate. References: bisection over the exact conic decision (clarabel) to
1e-8, and 32-sided inscribed and circumscribed pyramids (linear programmes, no conic
solver), which bracket the circular cones."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from kcheck.analysis.jamming_cases import analyse_jamming, jam_statics
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.least_friction import least_friction, least_friction_exactly
from kcheck.mechanics.sliding_limit import sliding_limit
from kcheck.mechanics.statics import _contact_axes, build_statics, holds, holds_exactly
from kcheck.scene import load_scene

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures"
SCENES = ("three-groove", "three-groove-beta-15", "kelvin")


def _cases():
    """Every determined case of three spatial fixtures at their load direction: the statics,
    the kept supports and the wrench."""
    for name in SCENES:
        scene = load_scene(FIXTURES / name / "coupling.kcheck.yaml")
        assert scene.body is not None
        statics, swept, design = jam_statics(scene, body_mass_properties(scene.body, scene.scale))
        assert design is not None
        for case in analyse_jamming(statics, swept, design, 8).cases:
            if case.determined:
                yield statics, case.keep, statics.wrench(design)


def test_sliding_limit_equals_bisection_and_lies_between_fine_pyramids() -> None:
    """Where it answers, the sliding limit is bisection's value to the conic solver's own
    tolerance (bisection's is within 1e-8 above the decision's boundary, which the solver's
    feasibility tolerances put up to a few 1e-7 below the exact one), far inside the 1e-4 it
    is certified to; the 32-sided pyramids bracket it (the inscribed pyramid at
    ``mu`` lies inside the circular cone, the circumscribed one at ``mu cos(pi / m)`` too);
    and ``least_friction_exactly`` returns it."""
    answered = 0
    m, tol = 32, 1e-6
    for statics, keep, wrench in _cases():
        scale = np.ones(len(statics.friction))
        found = sliding_limit(_contact_axes(statics, keep)[1], wrench, scale[keep], 1e-4)
        if found is None:
            continue

        def feasible(mu: float, t=statics, k=keep, w=wrench, s=scale) -> bool:
            return holds_exactly(t, k, w, mu * s)

        reference = least_friction(feasible, 0.1, rtol=1e-8)
        assert reference is not None
        assert reference * (1 - 1e-8) <= found <= reference * (1 + 1e-6)
        assert holds(statics, keep, wrench, found * (1 + tol) * scale, edges=m)
        assert holds(
            statics, keep, wrench, found / np.cos(np.pi / m) * (1 + tol) * scale, edges=m,
            pyramid="inscribed",
        )  # fmt: skip
        assert not holds(
            statics, keep, wrench, found * (1 - tol) * scale, edges=m, pyramid="inscribed"
        )
        assert not holds(
            statics, keep, wrench, found * np.cos(np.pi / m) * (1 - tol) * scale, edges=m
        )
        assert least_friction_exactly(statics, keep, wrench, scale, 0.1, rtol=1e-4) == found
        answered += 1
    assert answered >= 12


def test_sliding_limit_where_supports_lift_off_or_one_is_frictionless() -> None:
    """Where the least holding friction leaves supports unloaded, the limit of the contacts
    that stay pressed, equal to bisection's (to the conic solver's tolerance); a frictionless
    support cannot slide at the limit: no answer there (the conic search decides), rather
    than a wrong one. A 100 x 60 x 40 mm block on z1-z3 (+z), y1, y2 (+y), x1 retracted,
    loaded down and towards -x (every support pressed) and also towards +y (away from y1,
    y2, which lift off); then with z2 frictionless."""
    points = np.array(
        [[0.02, 0.01, 0], [0.08, 0.01, 0], [0.05, 0.05, 0], [0.02, 0, 0.02], [0.08, 0, 0.02],
         [0, 0.03, 0.02]]
    )  # fmt: skip
    normals = np.array([[0, 0, 1.0]] * 3 + [[0, 1.0, 0]] * 2 + [[1.0, 0, 0]])
    statics = build_statics(
        points=points,
        normals=normals,
        friction=np.full(6, 0.3),
        names=("z1", "z2", "z3", "y1", "y2", "x1"),
        dim=3,
        force=1.0,
        swept_point=np.array([0.05, 0.03, 0.02]),
        swept_magnitude=1.0,
    )
    keep = np.arange(5)
    columns = _contact_axes(statics, keep)[1]
    for d in ([-0.2, 0.0, -1.0], [-0.2, 0.1, -1.0], [-0.3, 0.3, -1.0]):
        wrench = statics.wrench(np.array(d) / np.linalg.norm(d))
        found = sliding_limit(columns, wrench, np.ones(5), 1e-4)

        def feasible(mu: float, w=wrench) -> bool:
            return holds_exactly(statics, keep, w, np.full(6, mu))

        reference = least_friction(feasible, 0.1, rtol=1e-8)
        assert found is not None and reference is not None
        assert reference * (1 - 1e-8) <= found <= reference * (1 + 1e-6)
        assert sliding_limit(columns, wrench, np.array([1.0, 0.0, 1.0, 1.0, 1.0]), 1e-4) is None
    # y1 and y2 carry nothing at the limit when the load pulls towards +y.
    lifting = statics.wrench(np.array([-0.3, 0.3, -1.0]) / np.linalg.norm([-0.3, 0.3, -1.0]))
    mu = sliding_limit(columns, lifting, np.ones(5), 1e-4)
    assert mu is not None
    assert holds_exactly(statics, np.arange(3), lifting, np.full(6, mu * (1 + 1e-6)))
