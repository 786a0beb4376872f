"""kcheck.mechanics.statics against closed forms and brute force.

References: the block of methods.md §7 (a block on a plane holds iff ``tan(theta) <= mu``,
§1.1), non-negative least squares (scipy ``nnls``: is ``-W`` a non-negative combination of
the edge wrenches?) as an independent cone-membership test, and force-by-force checks of the
conic solver's equilibria.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import nnls

from kcheck.mechanics.arcs import TAU, contains
from kcheck.mechanics.cones import cone_facets
from kcheck.mechanics.kinematics import free_twist, wrenches
from kcheck.mechanics.least_friction import (
    least_friction,
)
from kcheck.mechanics.statics import (
    build_statics,
    closing_condition,
    edge_wrenches,
    equilibria,
    equilibrium_forces,
    friction_edges,
    holds,
    holds_exactly,
)

MU = 0.1
E1, E2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])


def planar_block(mu: float = MU):
    """methods.md §7: y1 (20, 0), y2 (80, 0) normal +y, x1 (0, 30) normal +x, load at the
    centre of mass (50, 30) mm."""
    return build_statics(
        points=np.array([[0.02, 0, 0], [0.08, 0, 0], [0, 0.03, 0]]),
        normals=np.array([[0, 1.0, 0], [0, 1.0, 0], [1.0, 0, 0]]),
        friction=np.full(3, mu),
        names=("y1", "y2", "x1"),
        dim=2,
        force=1.0,
        swept_point=np.array([0.05, 0.03, 0]),
        swept_magnitude=1.0,
    )


def test_block_on_two_supports_holds_within_the_friction_angle() -> None:
    """Retract x1: the block rests on y1 and y2; it is held iff the load lies within
    atan(mu) of straight down (and its line passes between the supports, which it does)."""
    statics = planar_block()
    keep = np.array([0, 1])
    held, error = equilibria(statics, keep).arcs(E1, E2)
    half = np.degrees(np.arctan(MU))
    assert len(held) == 1
    start, end = np.degrees(held[0])
    assert start == pytest.approx(270 - half, abs=1e-9)
    assert end == pytest.approx(270 + half, abs=1e-9)
    assert np.degrees(error) < 1e-9
    # Without friction the free motion (translation along -x) closes for F_x < 0.
    a, c = closing_condition(statics, free_twist(statics.points, statics.normals, 2).twist)
    assert a == 0.0 and c[0] < 0 and abs(c[1]) < 1e-15


def test_least_friction_is_the_tangent_of_the_load_angle() -> None:
    statics = planar_block()
    keep = np.array([0, 1])
    theta = np.radians(5.0)
    d = np.array([-np.sin(theta), -np.cos(theta)])
    wrench = statics.wrench(d)
    found = least_friction(lambda mu: holds(statics, keep, wrench, np.full(3, mu)), 0.05)
    assert found == pytest.approx(np.tan(theta), rel=2e-6)
    assert found >= np.tan(theta)


def test_cone_kinds() -> None:
    statics = planar_block(mu=0.0)
    assert equilibria(statics, np.array([0, 1])).kind == "flat"  # frictionless: a line only
    # Two opposed supports with friction 2 (cones wider than 90°) hold any load.
    g = edge_wrenches(
        np.array([[0.0, 0.0], [0.0, 1.0]]),
        friction_edges(np.array([[0, 1.0], [0, -1.0]]), np.array([2.0, 2.0])),
    )
    assert cone_facets(g) == "everywhere"


def random_planar(
    rng: np.random.Generator, mu_max: float = 0.5, preload: bool = True, torque_share: float = 1.0
):
    """Three supports in a 100 mm box with random normals (away from concurrency), friction
    up to ``mu_max``, a load at a random point; a random preload (``preload``) and, in a
    share ``torque_share`` of the scenes, a torque."""
    while True:
        points = rng.uniform(0, 0.1, (3, 2))
        angles = rng.uniform(0, TAU, 3)
        normals = np.column_stack([np.cos(angles), np.sin(angles)])
        s = np.linalg.svd(wrenches(points / 0.1, normals), compute_uv=False)
        if s[-1] > 1e-3 * s[0]:
            break
    fixed = ((np.append(rng.uniform(0, 0.1, 2), 0), np.append(rng.normal(size=2), 0)),)
    torque = rng.normal() * 0.03 if rng.uniform() < torque_share else 0.0
    return build_statics(
        points=np.column_stack([points, np.zeros(3)]),
        normals=np.column_stack([normals, np.zeros(3)]),
        friction=rng.uniform(0, mu_max, 3),
        names=("a", "b", "c"),
        dim=2,
        force=1.0,
        swept_point=np.append(rng.uniform(0, 0.1, 2), 0),
        swept_magnitude=1.0,
        fixed_forces=fixed if preload else (),
        torque=np.array([0, 0, torque]),
    )


def test_planar_held_arcs_against_nonnegative_least_squares() -> None:
    """Membership of every 2° direction in 60 random scenes (with a preload and a torque),
    away from the arc ends, equals nnls's answer."""
    rng = np.random.default_rng(3)
    angles = np.radians(np.arange(0, 360, 2.0)) + 1e-3
    directions = np.column_stack([np.cos(angles), np.sin(angles)])
    compared = held_count = 0
    for _ in range(60):
        statics = random_planar(rng)
        for r in range(3):
            keep = np.flatnonzero(np.arange(3) != r)
            held, _ = equilibria(statics, keep).arcs(E1, E2)
            ends = np.array([x % TAU for arc in held for x in arc])
            g = edge_wrenches(
                statics.points[keep], friction_edges(statics.normals[keep], statics.friction[keep])
            )
            for alpha, d in zip(angles, directions, strict=True):
                if len(ends) and np.min(np.abs((alpha - ends + np.pi) % TAU - np.pi)) < 1e-6:
                    continue
                residual = nnls(g.T, -statics.wrench(d))[1]
                expected = residual < 1e-9 * (1 + np.linalg.norm(statics.wrench(d)))
                assert contains(held, alpha) == expected
                compared += 1
                held_count += expected
    assert compared > 30000 and held_count > 1500


def spatial_block(mu: float):
    """A 100 x 60 x 40 mm block on z1-z3 (+z), y1, y2 (+y) and x1 (+x), load at the centre."""
    points = np.array(
        [[0.02, 0.01, 0], [0.08, 0.01, 0], [0.05, 0.05, 0], [0.02, 0, 0.02], [0.08, 0, 0.02],
         [0, 0.03, 0.02]]
    )  # fmt: skip
    normals = np.array([[0, 0, 1.0]] * 3 + [[0, 1.0, 0]] * 2 + [[1.0, 0, 0]])
    return build_statics(
        points=points,
        normals=normals,
        friction=np.full(6, mu),
        names=("z1", "z2", "z3", "y1", "y2", "x1"),
        dim=3,
        force=1.0,
        swept_point=np.array([0.05, 0.03, 0.02]),
        swept_magnitude=1.0,
    )


@pytest.mark.parametrize("theta_deg", [3.0, 8.0, 15.0])
def test_spatial_least_friction_between_fine_pyramids(theta_deg: float) -> None:
    """Retract x1, load in the xz-plane at theta from -z towards -x. Reference: 32-sided
    inscribed and circumscribed pyramids (polyhedral facets, no conic solver) bracket the
    circular cones, so the exact least friction lies between theirs (0.5 % apart). It is at
    most tan(theta), what the z supports alone need: friction at the z supports pressing the
    body onto y1, y2 lets those carry part of the load (a wedge)."""
    statics = spatial_block(MU)
    keep = np.arange(5)
    theta = np.radians(theta_deg)
    wrench = statics.wrench(np.array([-np.sin(theta), 0.0, -np.cos(theta)]))
    found = least_friction(lambda mu: holds_exactly(statics, keep, wrench, np.full(6, mu)), 0.1)
    assert found is not None and found <= np.tan(theta) * (1 + 1e-6)
    assert holds_exactly(statics, keep, wrench) == (found <= MU)
    # inscribed(m) <= exact <= circumscribed(m), and circumscribed(mu) = inscribed(mu / cos).
    m, tol = 32, 1e-5
    assert holds(statics, keep, wrench, np.full(6, found), edges=m)
    assert not holds(
        statics, keep, wrench, np.full(6, found * (1 - tol)), edges=m, pyramid="inscribed"
    )
    assert not holds(
        statics, keep, wrench, np.full(6, found * np.cos(np.pi / m) * (1 - tol)), edges=m
    )


def test_conic_solver_forces_balance_and_lie_in_the_cones() -> None:
    """The equilibrium clarabel returns, checked force by force (not trusting its status)."""
    statics = spatial_block(MU)
    keep = np.arange(5)
    d = np.array([-0.05, -0.02, -1.0])
    d /= np.linalg.norm(d)
    forces = equilibrium_forces(statics, keep, statics.wrench(d))
    assert forces is not None
    balance = wrenches(statics.points[keep], forces).sum(axis=0) + statics.wrench(d)
    assert np.abs(balance).max() < 1e-7
    normal = np.sum(forces * statics.normals[keep], axis=1)
    tangential = np.linalg.norm(forces - normal[:, None] * statics.normals[keep], axis=1)
    assert np.all(normal >= -1e-8) and np.all(tangential <= MU * normal + 1e-7)
    assert equilibrium_forces(statics, keep, statics.wrench(np.array([0, 0, 1.0]))) is None


def test_frictionless_supports_only_push() -> None:
    """With μ = 0 the friction cone is the normal ray: a support may push, never pull. A load
    lifting the block off its z supports cannot be held (before, the conic problem let the
    frictionless supports pull with N = -0.25, -0.25, -0.5); one pressing it down can."""
    statics = spatial_block(0.0)
    keep = np.arange(5)  # x1 retracted
    assert equilibrium_forces(statics, keep, statics.wrench(np.array([0, 0, 1.0]))) is None
    assert not holds_exactly(statics, keep, statics.wrench(np.array([0, 0, 1.0])))
    down = equilibrium_forces(statics, np.arange(6), statics.wrench(np.array([0, 0, -1.0])))
    assert down is not None and np.all(np.sum(down * statics.normals, axis=1) >= -1e-9)


def _planar_cases(
    rng: np.random.Generator, scenes: int, directions: int, some_friction: bool = True
):
    """Random planar retraction cases ``(statics, keep, wrench, scale)``: ``scenes``
    :func:`random_planar` scenes, each with a random mask of frictionless supports (``scale``
    0; at least one rough one when ``some_friction``), every retracted support, ``directions``
    random load directions."""
    for _ in range(scenes):
        statics = random_planar(rng)
        scale = (rng.uniform(size=3) < 0.8).astype(float)
        if some_friction and not scale.any():
            scale[:] = 1.0
        for r in range(3):
            keep = np.flatnonzero(np.arange(3) != r)
            for angle in rng.uniform(0, TAU, directions):
                yield statics, keep, statics.wrench(np.array([np.cos(angle), np.sin(angle)])), scale


def test_planar_least_friction_from_candidates_equals_bisection() -> None:
    """The exact least friction (the least feasible root of the pair determinants,
    ``friction_candidates``) against the bisection it replaces, run to 1e-10: 20 random
    scenes (preloads, torques), every retracted case, 6 load directions each, some supports
    frictionless (rough mask), both run to 1e-10 (where the least is an infimum, not
    attained, both give a value that far above it). They agree within 1e-7 relative (the
    rounding of the polynomial roots; the worst seen, 7e-9, at mu = 42) or 1e-9 absolute
    (``holds`` accepts a wrench within 1e-10 of a facet, so the bisection may stop that far
    below); the result holds, and that far below it does not (it is the least)."""
    from kcheck.mechanics.least_friction import friction_candidates

    rng = np.random.default_rng(11)
    compared = infeasible = 0
    for statics, keep, wrench, scale in _planar_cases(rng, 20, 6):

        def feasible(mu: float, s=statics, k=keep, w=wrench, f=scale) -> bool:
            return holds(s, k, w, mu * f)

        candidates = friction_candidates(statics, keep, wrench, scale)
        exact = least_friction(feasible, 0.2, rtol=1e-10, candidates=candidates)
        reference = least_friction(feasible, 0.2, rtol=1e-10)
        assert (exact is None) == (reference is None)
        if exact is None:
            infeasible += 1
            continue
        assert exact == pytest.approx(reference, rel=1e-7, abs=1e-9)
        assert feasible(exact)
        if exact > 0:
            assert not feasible(exact * (1 - 1e-7) - 1e-9)
        compared += 1
    assert compared > 150 and infeasible > 10  # both outcomes exercised


def test_spatial_least_friction_by_fractional_steps_equals_bisection() -> None:
    """``least_friction_exactly`` (Dinkelbach-type steps on the largest friction ratio of
    balancing forces) against bisection over the exact conic decision run to 1e-8 (the
    reference), on the spatial block: two retracted supports, 8 load directions, all
    supports rough or z2 frictionless. It is never below the reference by more than the
    solver's tolerance, and within the requested 1e-4 above it."""
    from kcheck.mechanics.least_friction import least_friction_exactly

    statics = spatial_block(MU)
    rng = np.random.default_rng(2)
    compared = 0
    for r, scale in ((5, np.ones(6)), (3, np.array([1.0, 0.0, 1.0, 1.0, 1.0, 1.0]))):
        keep = np.flatnonzero(np.arange(6) != r)
        for theta in rng.uniform(0.0, 0.6, 4):
            d = np.array([-np.sin(theta), rng.uniform(-0.3, 0.3), -np.cos(theta)])
            wrench = statics.wrench(d / np.linalg.norm(d))

            def feasible(mu: float, k=keep, w=wrench, s=scale) -> bool:
                return holds_exactly(statics, k, w, mu * s)

            reference = least_friction(feasible, 0.1, rtol=1e-8)
            found = least_friction_exactly(statics, keep, wrench, scale, 0.1, rtol=1e-4)
            assert (found is None) == (reference is None)
            if reference is None:
                continue
            assert reference * (1 - 1e-7) <= found <= reference * (1 + 1e-4)
            compared += 1
    assert compared >= 6


def test_containment_of_many_directions_is_chunked_and_exact() -> None:
    """Fuzz finding mesh-4245-508 (issue 13, run E): jamming's sphere picture tested 58,081
    directions against a spatial cone's facets all at once, 180 MB on top of a 16 MB mesh,
    and kcheck passed 500 MB. In chunks the answer is the same (the direct product is the
    reference) and the extra memory is a few chunks."""
    import tracemalloc

    from kcheck.mechanics.statics import Equilibria

    rng = np.random.default_rng(5)
    facets = rng.normal(size=(400, 3))
    # Each facet excludes a cap of about 3.6° around -c: together about a third of the sphere.
    offsets = 0.998 * np.linalg.norm(facets, axis=1)
    cone = Equilibria("cone", offsets, facets)
    dirs = rng.normal(size=(58_081, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    direct = np.all(offsets + dirs @ facets.T >= 0, axis=1)
    tracemalloc.start()
    held = cone.contains(dirs)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert np.array_equal(held, direct) and 0 < held.sum() < len(dirs)
    assert peak < 50e6, f"{peak / 1e6:.0f} MB"
    assert cone.contains(dirs[:0]).shape == (0,)


def test_least_friction_ends_at_an_infimum_zero_does_not_attain() -> None:
    """Fuzz finding extreme-4245-885 (issue 13, run E): a degenerate balance feasible for
    every μ > 0 but not at 0 made the bisection halve into denormals and then loop forever
    at 5e-324 (a jamming check past its 120 s budget). It ends at the absolute floor."""
    from kcheck.mechanics.least_friction import MU_FLOOR, least_friction

    calls = []

    def feasible(mu: float) -> bool:
        calls.append(mu)
        return mu > 0

    found = least_friction(feasible, 0.5, rtol=1e-4)
    assert found is not None and 0 < found <= 2 * MU_FLOOR and len(calls) < 100


def test_least_friction_where_the_supports_squeeze_equals_bisection(monkeypatch) -> None:
    """``three-groove-beta-15`` (case 0) and ``kelvin`` (case 5): the remaining supports can
    squeeze the body, so the plain Dinkelbach-type step is unbounded below and the steps go
    on in homogeneous form (normalised forces, the wrench scaled by a variable). The result
    against bisection over the exact conic decision run to 1e-8 (the reference): not below it
    by more than the solver's tolerance, within the requested 1e-4 above it; the homogeneous
    steps ran, and the first lowered the ratio below the coefficient it was asked at."""
    from pathlib import Path

    import kcheck.mechanics.least_friction as lf
    from kcheck.analysis.jamming_cases import analyse_jamming, jam_statics
    from kcheck.body.mass import body_mass_properties
    from kcheck.scene import load_scene

    steps: list[tuple[float, float]] = []
    plain = lf._homogeneous_step

    def recorded(columns, wrench, mu, shrink):
        found = plain(columns, wrench, mu, shrink)
        if found is not None:  # every coefficient is mu.max() here (scale 1)
            steps.append((float(mu.max()), lf.largest_ratio(found[0], np.ones(len(mu)))))
        return found

    monkeypatch.setattr(lf, "_homogeneous_step", recorded)
    # The steps themselves: the sliding limit answers both cases without them.
    monkeypatch.setattr(lf, "sliding_limit", lambda *args: None)
    root = Path(__file__).resolve().parents[2] / "fixtures"
    for fixture, case in (("three-groove-beta-15", 0), ("kelvin", 5)):
        scene = load_scene(root / fixture / "coupling.kcheck.yaml")
        assert scene.body is not None
        statics, swept, design = jam_statics(scene, body_mass_properties(scene.body, scene.scale))
        assert design is not None  # both fixtures have a load direction
        keep = analyse_jamming(statics, swept, design, 8).cases[case].keep
        wrench = statics.wrench(design)
        scale = np.ones(len(statics.friction))

        def feasible(mu: float, t=statics, k=keep, w=wrench, s=scale) -> bool:
            return holds_exactly(t, k, w, mu * s)

        reference = least_friction(feasible, 0.1, rtol=1e-8)
        count = len(steps)
        found = lf.least_friction_exactly(statics, keep, wrench, scale, 0.1, rtol=1e-4)
        assert reference is not None and found is not None
        assert reference * (1 - 1e-6) <= found <= reference * (1 + 1e-4)
        assert len(steps) > count
        assert steps[count][1] < steps[count][0]


def test_planar_holding_answers_as_holds() -> None:
    """``planar_holding`` (the case's parts built once, for the least-friction search) gives
    ``holds``'s answer at every coefficient: 30 random scenes, every two-support case,
    frictionless supports (scale 0), 5 load directions, coefficients from 0 to 50 and the
    exact friction candidates (where the answer changes), both answers compared."""
    from kcheck.mechanics.least_friction import friction_candidates
    from kcheck.mechanics.statics import planar_holding

    rng = np.random.default_rng(5)
    answers = set()
    for statics, keep, wrench, scale in _planar_cases(rng, 30, 5, some_friction=False):
        decide = planar_holding(statics, keep, wrench, scale)
        candidates = friction_candidates(statics, keep, wrench, scale)
        for mu in [0.0, 0.05, 0.3, 1.0, 50.0, *candidates.tolist()]:
            expected = holds(statics, keep, wrench, mu * scale)
            assert decide(mu) == expected
            answers.add(expected)
    assert answers == {True, False}


def _random_planar_contacts(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """1 to 4 random planar contacts (points, normals): points at every scale, normals of
    unit length or, sometimes, rounded to halves (axis-aligned or diagonal), sometimes a
    contact at the origin."""
    k = int(rng.integers(1, 5))
    points = rng.normal(size=(k, 2)) * rng.choice([1e-3, 1.0, 1e3])
    normals = rng.normal(size=(k, 2))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    if rng.random() < 0.3:
        normals = np.round(normals * 2) / 2
        normals[np.all(normals == 0, axis=1)] = (0.0, 1.0)
    if rng.random() < 0.3:
        points[rng.integers(k)] = 0.0
    return points, normals


def test_planar_generators_are_numpys_bits():
    """The planar cone generators in plain float arithmetic (``_planar_generators``) are the
    numpy path's (``edge_wrenches`` of ``friction_edges``) bit for bit, rows in its order,
    on random contacts of every scale, axis-aligned normals, contacts at the origin and
    frictionless supports (coinciding edges removed)."""
    from kcheck.mechanics.statics import _planar_generators

    rng = np.random.default_rng(24)
    for _ in range(2000):
        points, normals = _random_planar_contacts(rng)
        k = len(points)
        mu = rng.choice([0.0, 1e-9, 0.1, 0.3, 2.0], size=k)
        fast = _planar_generators(points, normals, mu)
        slow = edge_wrenches(points, friction_edges(normals, mu))
        assert fast is not None
        assert fast.shape == slow.shape
        assert fast.tobytes() == slow.tobytes()


def test_planar_friction_candidates_polynomials_are_numpys_bits():
    """The candidates' polynomials in plain float arithmetic (``_planar_coefficients``) are
    the numpy formulation's (``_coefficients``, kept as the reference) bit for bit, signs of
    zero included, on random planar contacts (frictionless ones, contacts at the origin,
    loads with a zero component)."""
    from kcheck.mechanics.least_friction import _coefficients, _planar_coefficients

    rng = np.random.default_rng(24)
    for _ in range(2000):
        points, normals = _random_planar_contacts(rng)
        k = len(points)
        scale = rng.choice([0.0, 1.0], size=k)
        x = rng.normal(size=3)
        if rng.random() < 0.2:
            x[rng.integers(3)] = 0.0
        fast = _planar_coefficients(points, normals, scale, x)
        slow = _coefficients(points, normals, scale, x)
        assert fast.shape == slow.shape
        assert fast.tobytes() == slow.tobytes()


def _positive_roots_numpy(coefficients: np.ndarray) -> np.ndarray:
    """The former ``least_friction._positive_roots`` (Newton steps as numpy arrays), the
    reference for its plain-float steps."""
    from kcheck.numerics.thresholds import CUBIC_IMAG_RTOL, POLY_ZERO_RTOL

    size = np.abs(coefficients).sum(axis=1, keepdims=True)
    c = np.where(np.abs(coefficients) > POLY_ZERO_RTOL * size, coefficients, 0.0)
    found = []
    for degree in (3, 2, 1):
        lead = 3 - degree
        rows = c[(c[:, lead] != 0) & np.all(c[:, :lead] == 0, axis=1)]
        if not len(rows):
            continue
        monic = rows[:, lead + 1 :] / rows[:, lead : lead + 1]
        companion = np.zeros((len(rows), degree, degree))
        companion[:, 0, :] = -monic
        companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
        roots = np.linalg.eigvals(companion)
        real = np.abs(roots.imag) <= CUBIC_IMAG_RTOL * np.maximum(np.abs(roots), 1.0)
        owner = np.broadcast_to(np.arange(len(rows))[:, None], roots.shape)[real]
        x, poly = roots.real[real], rows[owner]
        for _ in range(3):
            value = ((poly[:, 0] * x + poly[:, 1]) * x + poly[:, 2]) * x + poly[:, 3]
            slope = (3 * poly[:, 0] * x + 2 * poly[:, 1]) * x + poly[:, 2]
            x = x - np.divide(value, slope, out=np.zeros_like(x), where=slope != 0)
        found.append(x[x > 0])
    return np.concatenate(found) if found else np.zeros(0)


def test_positive_roots_newton_steps_are_numpys_bits():
    """The candidates' roots with the Newton steps in plain float arithmetic are the former
    numpy steps' bit for bit, in the same order: on the polynomials of 600 random planar
    cases (every kept pair, frictionless supports, loads with a zero component) and on 3000
    random cubics, quadratics and lines (double roots, zero and tiny coefficients)."""
    from kcheck.mechanics.least_friction import _planar_coefficients, _positive_roots

    rng = np.random.default_rng(26)
    polys = []
    for _ in range(600):
        points, normals = _random_planar_contacts(rng)
        scale = rng.choice([0.0, 1.0, 1.0], size=len(points))
        x = rng.normal(size=3)
        if rng.random() < 0.2:
            x[rng.integers(3)] = 0.0
        polys.append(_planar_coefficients(points, normals, scale, x))
    for _ in range(3000):
        p = rng.normal(size=(1, 4)) * rng.choice([1e-9, 1.0, 1e6], size=(1, 4))
        p[0, : int(rng.integers(0, 3))] = 0.0  # lines and quadratics
        if rng.random() < 0.2:  # a double root r: (x - r)^2 (x - s)
            r, s = rng.normal(size=2)
            p = np.array([[1.0, -(2 * r + s), r * r + 2 * r * s, -r * r * s]])
        if rng.random() < 0.1:
            p[0, int(rng.integers(4))] = 0.0
        polys.append(p)
    total = 0
    for p in polys:
        fast, slow = _positive_roots(p), _positive_roots_numpy(p)
        assert fast.shape == slow.shape
        assert fast.tobytes() == slow.tobytes()
        total += len(fast)
    assert total > 2000  # roots found and compared


def test_planar_cone_holds_decides_as_numpy_or_not_at_all():
    """``planar_cone_holds`` (a planar cone decision in plain float arithmetic) answers as
    ``np.all(cone_facets(G) @ against >= limit)`` ("everywhere" True, "flat" False) or says
    undecided (None), on random contacts of every scale and coefficient, random wrenches and
    wrenches put on a facet; with the limit set to a facet's own numpy product (the band
    where fused multiply-adds could change the answer) it never answers otherwise; it
    decides most cones."""
    from kcheck.mechanics.cones import cone_facets, planar_cone_holds
    from kcheck.mechanics.statics import _planar_generator_rows
    from kcheck.numerics.thresholds import EPS, FACET_TOL, PRODUCT_ROUNDING

    rng = np.random.default_rng(61)
    decided = asked = 0
    for _ in range(4000):
        points, normals = _random_planar_contacts(rng)
        mu = rng.choice([0.0, 0.05, 0.3, 2.0], size=len(points))
        rows = _planar_generator_rows(points.tolist(), normals.tolist(), mu.tolist())
        assert rows is not None
        generators = np.array(rows)
        facets = cone_facets(generators)
        against = rng.normal(size=3) * rng.choice([1e-3, 1.0, 1e3])
        if isinstance(facets, np.ndarray) and rng.random() < 0.3:
            # on a facet's plane: a combination of two generators on it
            on = np.flatnonzero(np.abs(generators @ facets[0]) < 1e-9)
            if len(on) >= 2:
                against = rng.uniform(0, 2, 2) @ generators[on[:2]]
        size = float(np.linalg.norm(against)) or 1.0
        margin = PRODUCT_ROUNDING * EPS * size
        limits = [-FACET_TOL * size]
        if isinstance(facets, np.ndarray):
            limits.append(float((facets @ against)[rng.integers(len(facets))]))
        for limit in limits:
            if isinstance(facets, str):
                expected = facets == "everywhere"
            else:
                expected = bool(np.all(facets @ against >= limit))
            found = planar_cone_holds(rows, tuple(against.tolist()), limit, margin)
            assert found is None or found == expected
            asked += 1
            decided += found is not None
    assert decided > 0.6 * asked


def test_planar_least_holding_friction_as_before():
    """The least holding coefficient from ``planar_holding`` (decisions in plain arithmetic
    where they are certain) equals, bit for bit, the one from numpy's decisions
    (``_holds_numpy``, ``holds`` before the plain-arithmetic path) at each coefficient:
    40 random scenes, every case, 4 load directions (480 cases), frictionless supports."""
    from kcheck.mechanics.least_friction import friction_candidates
    from kcheck.mechanics.statics import planar_holding

    rng = np.random.default_rng(62)
    found = set()
    for statics, keep, wrench, scale in _planar_cases(rng, 40, 4):
        candidates = friction_candidates(statics, keep, wrench, scale)

        def reference(mu: float, s=statics, k=keep, w=wrench, f=scale) -> bool:
            return _holds_numpy(s, k, w, mu * f)

        fast = planar_holding(statics, keep, wrench, scale)
        new = least_friction(fast, 0.2, rtol=1e-4, candidates=candidates)
        old = least_friction(reference, 0.2, rtol=1e-4, candidates=candidates)
        assert new == old
        found.add(new is None)
    assert found == {True, False}


def _holds_numpy(statics, keep, wrench, mu) -> bool:
    """``holds`` as numpy decides it (the facets' array and its product), the reference of the
    plain-arithmetic decisions."""
    from kcheck.mechanics.cones import FACET_TOL, cone_facets
    from kcheck.mechanics.statics import cone_generators

    facets = cone_facets(cone_generators(statics, keep, np.asarray(mu, float)))
    if isinstance(facets, str):
        return facets == "everywhere"
    scale = float(np.linalg.norm(wrench)) or 1.0
    return bool(np.all(facets @ -wrench >= -FACET_TOL * scale))


def test_planar_holds_as_numpy_decides():
    """``holds`` of planar scenes (plain arithmetic where certain) answers as numpy's
    decision: 300 random scenes, the three cases and all supports, 5 load directions, the
    scene's friction, none and three times it (18,000 decisions, both answers)."""
    rng = np.random.default_rng(63)
    answers = []
    for _ in range(300):
        statics = random_planar(rng)
        for r in range(4):
            keep = np.flatnonzero(np.arange(3) != r) if r < 3 else np.arange(3)
            for angle in rng.uniform(0, TAU, 5):
                wrench = statics.wrench(np.array([np.cos(angle), np.sin(angle)]))
                for mu in (statics.friction, 0.0 * statics.friction, 3.0 * statics.friction):
                    expected = _holds_numpy(statics, keep, wrench, mu)
                    assert holds(statics, keep, wrench, mu) == expected
                    answers.append(expected)
    assert len(answers) == 18000 and 0.1 < np.mean(answers) < 0.9


def test_cached_spatial_generators_equal_edge_wrenches() -> None:
    """cone_generators' spatial path slices every support's edge wrenches, computed once and
    cached (statics._every_edge_wrench); the slices equal edge_wrenches of the kept supports
    computed alone, bit for bit: random spatial supports at several length and friction
    scales, keep as a mask, as indices and as reversed indices, supports that coincide
    (duplicate rows removed) and frictionless ones (coinciding edges), both pyramids; more
    statics than the cache holds, so entries are evicted and recomputed."""
    from kcheck.mechanics.statics import RECENT_EDGE_WRENCHES, Statics, cone_generators

    rng = np.random.default_rng(32)
    compared = 0
    for trial in range(3 * RECENT_EDGE_WRENCHES):
        k = int(rng.integers(2, 7))
        scale = 10.0 ** rng.uniform(-3, 3)
        points = rng.uniform(-1, 1, (k, 3)) * scale
        normals = rng.normal(size=(k, 3))
        if trial % 3 == 0:  # two supports at one point with one normal
            points[1], normals[1] = points[0], normals[0]
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        mu = rng.uniform(0, 1, k) * 10.0 ** rng.uniform(-2, 1)
        if trial % 4 == 0:
            mu[0] = 0.0  # frictionless: its edges coincide
        # Only points and normals are read (no frame: the arrays are nondimensional already).
        frame = None
        statics = Statics(frame, (), points, normals, mu, np.zeros(6), np.zeros((6, 3)))  # type: ignore[arg-type]
        mask = rng.random(k) < 0.7
        mask[0] = True
        for pyramid in ("inscribed", "circumscribed"):
            for keep in (mask, np.flatnonzero(mask), np.flatnonzero(mask)[::-1]):
                got = cone_generators(statics, keep, mu, 8, pyramid)
                alone = edge_wrenches(
                    points[keep], friction_edges(normals[keep], mu[keep], 8, pyramid)
                )
                assert got.shape == alone.shape and np.array_equal(got, alone)
                compared += 1
    assert compared == 3 * 2 * 3 * RECENT_EDGE_WRENCHES
