"""Dynamics of a retracted case (kcheck.mechanics.dynamics): Painlevé-type cases, the outcome rule,
and preloads, against closed forms derived by hand in the docstrings.

The Painlevé case is a long, light body sliding on two rough supports: y1 (-a, 0) and
y2 (a, 0) push up (+y), x1 (-b, h) pushes along +x at the height h of the centre of mass
(0, h); mass 1, radius of gyration k (I = k^2). Retract y1: the body turns about the pole
P = (a, h) where the normals of y2 and x1 meet, counter-clockwise; y2 slides along +x and x1
along -y, so forward friction tilts their reaction lines to (-mu, 1) at y2 and (1, mu) at x1,
which meet at the friction pole P' = (a - mu s, s), s = (h + mu (a + b)) / (1 + mu^2). The
effective mass along the free rotation is ``xi'^T M xi = w w' (m (c - P) . (c - P') + I)``,
zero where ``(c - P) . (c - P') = -k^2``; with c - P = (-a, 0) that is ``a mu s = a^2 + k^2``:

    (b - k^2 / a) mu^2 + h mu - (a + k^2 / a) = 0   (forward)

and, with the friction reversed (s -> (h - mu (a + b)) / (1 + mu^2), mu -> -mu),

    (k^2 - a b) mu^2 + a h mu + (a^2 + k^2) = 0     (backward).

With a = 0.2, b = 1, h = 0.1, k^2 = 0.01: mu* = (-0.1 + sqrt(0.96)) / 1.9 = 0.46305 forward
and (0.02 + sqrt(0.0384)) / 0.38 = 0.56832 backward.
"""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.dynamics import analyse_case, build_problem
from kcheck.mechanics.friction import friction_intervals
from kcheck.mechanics.outcomes import closing_conditions, outcome, outcomes, safe_arcs

A, B, H, K2 = 0.2, 1.0, 0.1, 0.01
MU_FORWARD = (-H + np.sqrt(H**2 + 4 * (B - K2 / A) * (A + K2 / A))) / (2 * (B - K2 / A))
MU_BACKWARD = (A * H + np.sqrt((A * H) ** 2 + 4 * (A * B - K2) * (A**2 + K2))) / (2 * (A * B - K2))


def rod_kwargs(mu: float, gravity: tuple[float, float] = (0.0, 0.0)) -> dict:
    """Arguments of :func:`build_problem` for the long light body of the module docstring (SI),
    friction ``mu`` on every support, a 1 N load at the centre of mass."""
    return dict(
        points=np.array([[-A, 0, 0], [A, 0, 0], [-B, H, 0]]),
        normals=np.array([[0, 1.0, 0], [0, 1.0, 0], [1.0, 0, 0]]),
        friction=np.full(3, mu),
        names=("y1", "y2", "x1"),
        dim=2,
        mass=1.0,
        com=np.array([0, H, 0]),
        inertia=np.diag([np.nan, np.nan, K2]),
        gravity=np.array([*gravity, 0.0]),
        load_magnitude=1.0,
        load_point=None,
        torque=np.zeros(3),
    )


def rod(mu: float, gravity: tuple[float, float] = (0.0, 0.0)):
    """The long light body as a problem."""
    return build_problem(**rod_kwargs(mu, gravity))


def test_hand_derived_onsets() -> None:
    assert MU_FORWARD == pytest.approx(0.4630504721648796, rel=1e-15)
    assert MU_BACKWARD == pytest.approx((0.02 + np.sqrt(0.0384)) / 0.38, rel=1e-15)


@pytest.mark.parametrize(("index", "onset"), [(0, MU_FORWARD), (1, MU_BACKWARD)])
def test_effective_mass_changes_sign_at_the_hand_derived_mu(index: int, onset: float) -> None:
    below = analyse_case(rod(onset * (1 - 1e-6)), 0).effective_mass
    above = analyse_case(rod(onset * (1 + 1e-6)), 0).effective_mass
    assert below is not None and above is not None
    assert below[index] > 0 > above[index]


def test_painleve_interval_starts_at_the_forward_onset() -> None:
    problem = rod(0.6)
    found = friction_intervals(problem, analyse_case(problem, 0), np.array([0.0, -1.0]))
    assert found.painleve == ((pytest.approx(MU_FORWARD, rel=1e-12), np.inf),)
    assert found.painleve_from == pytest.approx(MU_FORWARD, rel=1e-12)
    # No friction coefficient inside the Painlevé interval closes the case.
    assert all(hi <= MU_FORWARD * (1 + 1e-12) for _, hi in found.intervals)


def test_painleve_case_is_ambiguous_in_every_direction() -> None:
    """Beyond the onset the forward and backward assumptions are both consistent or both
    inconsistent somewhere, and the rigid-body answer is not unique anywhere: no safe angle."""
    angles = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    directions = np.column_stack([np.cos(angles), np.sin(angles)])
    below = analyse_case(rod(0.3), 0)
    above = analyse_case(rod(0.6), 0)
    assert not below.painleve and above.painleve
    assert "ambiguous" not in set(outcomes(below, directions))
    assert set(outcomes(above, directions)) == {"ambiguous"}
    assert safe_arcs(above, np.array([1.0, 0]), np.array([0, 1.0]))[0] == ()
    assert safe_arcs(below, np.array([1.0, 0]), np.array([0, 1.0]))[0] != ()
    # The symptom: somewhere both sliding directions are consistent, somewhere neither.
    assert above.forward is not None and above.backward is not None
    fwd = above.forward.a[0] + directions @ above.forward.c[0] > 0
    bwd = above.backward.a[0] + directions @ above.backward.c[0] < 0
    assert np.any(fwd & bwd) and np.any(~fwd & ~bwd)
    a, c, _ = closing_conditions(above)
    assert np.all(a <= 0) and not np.any(c)


def test_opens_needs_positive_normal_forces() -> None:
    """§7 block, x1 retracted, the force pushes away from x1: with a downward component both y
    contacts carry it (opens); pulled up, N1 + N2 = -F_y < 0 (opens while losing contact)."""
    block = build_problem(
        points=np.array([[0.02, 0, 0], [0.08, 0, 0], [0, 0.03, 0]]),
        normals=np.array([[0, 1.0, 0], [0, 1.0, 0], [1.0, 0, 0]]),
        friction=np.full(3, 0.1),
        names=("y1", "y2", "x1"),
        dim=2,
        mass=1.0,
        com=np.array([0.05, 0.03, 0]),
        inertia=np.diag([np.nan, np.nan, 1.0 * (0.1**2 + 0.06**2) / 12]),
        gravity=np.zeros(3),
        load_magnitude=1.0,
        load_point=None,
        torque=np.zeros(3),
    )
    case = analyse_case(block, 2)
    down = np.array([np.cos(np.radians(315)), np.sin(np.radians(315))])
    state, x = outcome(case, down)
    assert state == "opens" and x is not None and np.all(x[1:] > 0)
    state, x = outcome(case, -down[::-1] * [1, -1])  # 45 deg: away and up
    assert state == "opens_loses_contact" and x is not None and x[1] + x[2] < 0


def test_preload_at_the_centre_of_mass_is_gravity() -> None:
    """A fixed force m g at the centre of mass is the weight: identical equations."""
    g = (1.5, -7.0)
    weighed = rod(0.2, gravity=g)
    plain = rod(0.2)
    loaded = build_problem(
        **{
            **rod_kwargs(0.2),
            "preloads": ((np.array([0, H, 0]), np.array([g[0], g[1], 0.0])),),
        }
    )
    for r in range(3):
        a, b = analyse_case(weighed, r), analyse_case(loaded, r)
        assert a.forward is not None and b.forward is not None
        np.testing.assert_allclose(b.forward.a, a.forward.a, rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose(b.forward.c, a.forward.c, rtol=1e-13, atol=1e-15)
        assert not np.allclose(analyse_case(plain, r).forward.a, a.forward.a)  # type: ignore[union-attr]


def test_extreme_magnitudes_scale_away() -> None:
    """Forces are compared in log space: a 1e-300 N load against a weight of 1e-300 N gives
    the same nondimensional system as 1 N against 1 N; a mass of 1e-320 kg (subnormal) still
    gives finite equations (issue 13: no overflow, no solver failure)."""
    base = rod(0.1, gravity=(0.0, -1.0))
    tiny = build_problem(
        **{**rod_kwargs(0.1), "load_magnitude": 1e-300, "gravity": np.array([0, -1e-300, 0])}
    )
    for r in range(3):
        a, b = analyse_case(base, r), analyse_case(tiny, r)
        assert a.forward is not None and b.forward is not None
        np.testing.assert_allclose(b.forward.a, a.forward.a, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(b.forward.c, a.forward.c, rtol=1e-12, atol=1e-15)
    for mass in (1e-320, 1e308):
        heavy = build_problem(
            **{
                **rod_kwargs(0.1, gravity=(0.0, -9.81)),
                "mass": mass,
                "inertia": np.diag([np.nan, np.nan, mass * K2]),
            }
        )
        case = analyse_case(heavy, 0)
        assert case.determined and case.forward is not None
        assert np.all(np.isfinite(case.forward.a)) and np.all(np.isfinite(case.forward.c))
        assert np.isfinite(heavy.gravity).all() and np.abs(heavy.gravity).max() <= 1.0
