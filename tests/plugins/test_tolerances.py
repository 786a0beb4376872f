"""The `tolerances` check: Monte Carlo over the made coupling, the load direction exact.

References: the full analysis of each perturbed scene (kcheck.analysis.cases + the exact sphere map,
an independent route through the code: SVD free twists, per-scene solves); the exact friction
intervals of kcheck.analysis.friction_ranges for friction-only tolerances; scipy's beta quantiles
for the Clopper–Pearson bounds.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from kcheck_checks.analytical_2d import Analytical2D
from kcheck_checks.tolerances import Tolerances, TolerancesOptions

from kcheck.analysis import analyse
from kcheck.analysis.cases import problem_for
from kcheck.analysis.sphere_map import sphere_map
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.tolerance import perturb, sample_margins
from kcheck.numerics.stats import clopper_pearson
from kcheck.plugin import Inputs
from kcheck.scene import Scene, load_scene
from tests.conftest import FIXTURES, PLANAR_SCENE

THREE_GROOVE = FIXTURES / "three-groove" / "coupling.kcheck.yaml"


def _as_made(scene: Scene, problem, layouts, i: int) -> Scene:
    """Sample ``i`` written back as a scene (SI), through the ordinary scene types."""
    points = problem.frame.origin[: scene.dim] + problem.frame.length * layouts.points[i]
    supports = []
    for j, s in enumerate(scene.supports):
        position = s.position.copy()
        position[: scene.dim] = points[j]
        normal = np.zeros(3)
        normal[: scene.dim] = layouts.normals[i][j]
        supports.append(
            dataclasses.replace(
                s,
                position=position,
                normal=normal,
                friction=float(layouts.friction[i][j]),
                friction_spec=None,
            )
        )
    return dataclasses.replace(scene, supports=tuple(supports))


@pytest.mark.parametrize("fixture", ["three-groove", "planar"])
def test_sample_margins_are_the_analysis_of_each_made_coupling(write_scene, fixture):
    """Every sampled margin equals the design margin of the same coupling analysed on its own
    (sphere map in space, safe arcs in a plane), to 1e-9 degrees where it closes; the two
    agree on closing everywhere."""
    if fixture == "planar":
        scene = load_scene(write_scene(PLANAR_SCENE.replace("friction: 0.1", "friction: 0.3")))
    else:
        scene = load_scene(THREE_GROOVE)
    mass = body_mass_properties(scene.body, scene.scale)
    problem = problem_for(scene, mass)
    layouts = perturb(
        problem,
        position=2e-3 if fixture == "planar" else 1e-3,
        normal=np.radians(6.0),
        friction_low=problem.friction * 0.2,
        friction_high=problem.friction * 3.0,
        count=40,
        rng=np.random.default_rng(1),
        independent=True,
    )
    margins = sample_margins(problem, layouts, scene.load.direction[: scene.dim])
    closing = 0
    for i in range(len(margins)):
        made = _as_made(scene, problem, layouts, i)
        analysis = analyse(made, mass)
        if fixture == "planar":
            exact = analysis.design_margin_deg
            closes = analysis.every_case_closes
        else:
            smap = sphere_map(made, analysis)
            exact = None if smap.design_margin is None else np.degrees(smap.design_margin)
            closes = analysis.every_case_closes
        assert (margins[i] > 0) == closes, i
        if closes:
            assert np.degrees(margins[i]) == pytest.approx(exact, abs=1e-9)
            closing += 1
    assert 5 < closing < len(margins)  # both kinds occur


def test_load_direction_tolerance_is_exact(write_scene):
    """A planar sample passes a load tolerance ±δ iff every direction within ±δ closes: the
    analysis at the design direction turned by ±δ (and within) against the margin rule."""
    scene = load_scene(write_scene(PLANAR_SCENE))
    mass = body_mass_properties(scene.body, scene.scale)
    check = Analytical2D()
    margin = check.run(Inputs(scene, mass, check.options())).details["design_margin_deg"]
    for delta in (margin - 0.01, margin + 0.01):
        turned = [scene.design_angle_deg + a for a in np.linspace(-delta, delta, 41)]
        every = all(
            analyse(dataclasses.replace(scene, load=_turned(scene, a)), mass).every_case_closes
            for a in turned
        )
        text = PLANAR_SCENE + f"tolerances: {{load_direction: {delta}}}\n"
        result = Tolerances().run(
            # The failure line alone: no marginal band (100 samples bound the pass
            # probability only to 0.96, below the default band of 0.99).
            Inputs(
                load_scene(write_scene(text)),
                mass,
                TolerancesOptions(samples=100, marginal_pass_probability=0.0),
            )
        )
        assert (result.status == "pass") == every == (delta < margin)


def _turned(scene: Scene, angle_deg: float):
    return dataclasses.replace(scene.load, direction=scene.sweep.direction(angle_deg))


def test_friction_only_pass_probability_is_the_share_of_the_range(write_scene):
    """With only a friction range uncertain, the coupling passes for the coefficients up to
    its limiting friction: the pass probability is that share of the range (exact, from the
    range analysis), and the Clopper–Pearson interval of 10^4 draws holds it."""
    text = (FIXTURES / "three-groove-beta-55" / "coupling.kcheck.yaml").read_text()
    text = text.replace("friction: 0.1", "friction: {min: 0.1, max: 0.3}\ntolerances: {}")
    scene = load_scene(write_scene(text))
    mass = body_mass_properties(scene.body, scene.scale)
    spans = [
        r.details["friction_range"]["fails_for"]
        for r in analyse(scene, mass).results
        if r.details["friction_range"]["fails_for"]
    ]
    start = min(lo for span in spans for lo, _ in span)  # the limiting friction, 0.262
    share = (start - 0.1) / 0.2
    result = Tolerances().run(Inputs(scene, mass, TolerancesOptions(samples=10_000, seed=3)))
    low, high = result.details["pass_probability_bounds"]
    assert low <= share <= high and high - low < 0.02
    assert result.details["pass_probability"] == pytest.approx(share, abs=0.015)
    # the worst case is exact: the nominal coupling at the top of the range
    assert result.status == "fail" and result.details["nominal_worst_margin_deg"] < 0


def test_three_groove_fixture_reports_worst_case_and_probability(cli_json):
    """The fixture's tolerances (±0.05 mm, ±0.5°, load ±2°) through the real CLI: a pass with
    every sample passing, its worst margin below the nominal one by at least the load
    tolerance, reproducible with its seed."""
    code, doc = cli_json(str(THREE_GROOVE), "--select", "tolerances,analytical-3d")
    checks = {c["id"]: c for c in doc["scenes"][0]["checks"]}
    tol, nominal = checks["tolerances"], checks["analytical-3d"]
    assert tol["status"] == "pass" and tol["samples"] == 10_000 and tol["passed"] == 10_000
    assert tol["pass_probability"] == 1.0
    low, high = tol["pass_probability_bounds"]
    assert high == 1.0 and low == pytest.approx(0.025 ** (1 / 10_000))  # (alpha/2)^(1/n)
    assert tol["nominal_worst_margin_deg"] == pytest.approx(nominal["design_margin_deg"] - 2.0)
    assert tol["worst_margin_deg"] <= tol["nominal_worst_margin_deg"]
    assert 0 < tol["worst_margin_deg"] < nominal["design_margin_deg"] - 2.0
    sample = tol["worst_sample"]["supports"]
    assert max(s["displacement"] for s in sample.values()) <= 0.05e-3 * np.sqrt(3)
    assert max(s["tilt_deg"] for s in sample.values()) <= 0.5 + 1e-9
    code2, doc2 = cli_json(str(THREE_GROOVE), "--select", "tolerances")
    again = doc2["scenes"][0]["checks"][0]
    assert again["worst_margin_deg"] == tol["worst_margin_deg"]


def test_pass_probability_option_and_skips(write_scene):
    scene = load_scene(write_scene(PLANAR_SCENE))
    assert "no `tolerances:`" in Tolerances().skip_reason(scene)
    text = PLANAR_SCENE.replace("  angle: 225\n", "") + "tolerances: {normal: 1}\n"
    assert "design direction" in Tolerances().skip_reason(load_scene(write_scene(text)))
    wide = PLANAR_SCENE + "tolerances: {position: 10, normal: 20}\n"
    scene = load_scene(write_scene(wide))
    mass = body_mass_properties(scene.body, scene.scale)
    strict = Tolerances().run(Inputs(scene, mass, TolerancesOptions(samples=2000)))
    p = strict.details["pass_probability"]
    assert strict.status == "fail" and 0.2 < p < 0.98
    assert (
        strict.findings[0].field == ("tolerances",)
        and "made couplings fail" in strict.findings[0].message
    )
    lenient = TolerancesOptions(samples=2000, min_pass_probability=p / 2)
    # Above the failure line, below the default band (0.99): marginal; without the band: pass.
    assert Tolerances().run(Inputs(scene, mass, lenient)).status == "marginal"
    no_band = lenient.model_copy(update={"marginal_pass_probability": 0.0})
    assert Tolerances().run(Inputs(scene, mass, no_band)).status == "pass"


@pytest.mark.parametrize(("x", "n"), [(0, 10), (10, 10), (5, 10), (37, 100), (9990, 10_000)])
def test_clopper_pearson_against_scipy(x, n):
    stats = pytest.importorskip("scipy.stats")
    low, high = clopper_pearson(x, n, 0.95)
    assert low == pytest.approx(stats.beta.ppf(0.025, x, n - x + 1) if x else 0.0, abs=1e-12)
    assert high == pytest.approx(stats.beta.ppf(0.975, x + 1, n - x) if x < n else 1.0, abs=1e-12)


def test_chunks_are_the_batch_margins_of_their_own_draws(write_scene):
    """Each chunk draws its made couplings from its own stream (SeedSequence(seed) spawned by
    the chunk's index, computed here with numpy's own spawn) and its margins are those of
    the same layouts solved by `sample_margins`; the check's sample count and worst sample
    follow from the chunks, the last one short."""
    from kcheck.mechanics.tolerance import (
        CHUNK,
        Box,
        chunk_layouts,
        chunk_margins,
        margin_chunks,
    )

    wide = PLANAR_SCENE + "tolerances: {position: 10, normal: 20}\n"
    scene = load_scene(write_scene(wide))
    mass = body_mass_properties(scene.body, scene.scale)
    problem = problem_for(scene, mass)
    design = scene.load.direction[: scene.dim]
    box = Box(1e-3, np.radians(5.0), problem.friction, problem.friction * 2.0)
    chunks = margin_chunks(problem, box, design, 2 * CHUNK + 17, seed=3)
    assert [c.count for c in chunks] == [CHUNK, CHUNK, 17]
    children = np.random.SeedSequence(3).spawn(3)
    for chunk, child in zip(chunks, children, strict=True):
        drawn = perturb(
            problem,
            position=1e-3,
            normal=np.radians(5.0),
            friction_low=problem.friction,
            friction_high=problem.friction * 2.0,
            count=chunk.count,
            rng=np.random.default_rng(child),
        )
        mine = chunk_layouts(chunk)
        np.testing.assert_array_equal(drawn.points, mine.points)
        np.testing.assert_array_equal(drawn.normals, mine.normals)
        np.testing.assert_array_equal(chunk_margins(chunk), sample_margins(problem, drawn, design))
    opts = TolerancesOptions(samples=CHUNK + 100, seed=5)
    result = Tolerances().run(Inputs(scene, mass, opts))
    margins = np.concatenate(
        [
            chunk_margins(c)
            for c in margin_chunks(problem, box_of(scene, problem), design, opts.samples, 5)
        ]
    )
    spread = np.radians(scene.tolerances.load_direction_deg)
    assert result.details["passed"] == int(
        np.count_nonzero((margins > 0) & (margins - spread >= 0))
    )
    assert result.details["worst_sample"]["index"] == int(np.argmin(margins))


def box_of(scene: Scene, problem):
    """The scene's tolerance box as the check takes it (coefficients along their range)."""
    from kcheck.mechanics.tolerance import Box

    low, high = scene.friction_range("kinetic")
    return Box(scene.tolerances.position, float(np.radians(scene.tolerances.normal_deg)), low, high)


@pytest.mark.parametrize("design", ["latin-hypercube", "sobol"])
def test_stratified_designs_hit_the_friction_share(write_scene, design):
    """A Latin hypercube or Sobol design of the box (kcheck.numerics.design, as studies
    sample) with only friction uncertain: one coefficient column, so the pass fraction of
    n samples is the exact share of the range (from the range analysis) to within a few
    1/n — far inside plain Monte Carlo's ±1.5 % at this n — and repeats with its seed."""
    text = (FIXTURES / "three-groove-beta-55" / "coupling.kcheck.yaml").read_text()
    text = text.replace("friction: 0.1", "friction: {min: 0.1, max: 0.3}\ntolerances: {}")
    scene = load_scene(write_scene(text))
    mass = body_mass_properties(scene.body, scene.scale)
    spans = [
        r.details["friction_range"]["fails_for"]
        for r in analyse(scene, mass).results
        if r.details["friction_range"]["fails_for"]
    ]
    share = (min(lo for span in spans for lo, _ in span) - 0.1) / 0.2
    opts = TolerancesOptions(samples=1024, seed=3, design=design)
    result = Tolerances().run(Inputs(scene, mass, opts))
    assert result.details["design"] == design
    assert result.details["pass_probability"] == pytest.approx(share, abs=3 / 1024)
    again = Tolerances().run(Inputs(scene, mass, opts))
    assert again.details == result.details


@pytest.mark.parametrize("fixture", ["planar", "spatial"])
def test_unit_points_map_as_the_draws(write_scene, fixture):
    """Unit points holding the very uniforms `perturb` draws from a generator (shifts, then
    tilt cosines and azimuths or turns, then coefficients, in the order it draws them) give
    the same made couplings: the design mapping is the Monte Carlo draw, point for point."""
    from kcheck.mechanics.tolerance import unit_dimensions

    text = PLANAR_SCENE if fixture == "planar" else None
    scene = load_scene(write_scene(text)) if text else load_scene(THREE_GROOVE)
    mass = body_mass_properties(scene.body, scene.scale)
    problem = problem_for(scene, mass)
    k, dim = problem.points.shape
    box = dict(
        position=1e-3,
        normal=np.radians(4.0),
        friction_low=problem.friction * 0.5,
        friction_high=problem.friction * 2.0,
        count=50,
        independent=True,
    )
    drawn = perturb(problem, **box, rng=np.random.default_rng(11))
    g = np.random.default_rng(11)
    cols = [g.random((50, k, dim)).reshape(50, k * dim)]
    cols += [g.random((50, k))] if dim == 2 else [g.random((50, k)), g.random((50, k))]
    cols.append(g.random((50, k)))
    unit = np.hstack(cols)
    assert unit.shape[1] == unit_dimensions(k, dim, True)
    mapped = perturb(problem, **box, rng=np.random.default_rng(0), unit=unit)
    for a, b in zip(
        (drawn.points, drawn.normals, drawn.friction),
        (mapped.points, mapped.normals, mapped.friction),
        strict=True,
    ):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
