"""analytical-3d's way-out searches (the friction and the closing force at which a failing
scene passes) judge their trial scenes through cheap first tests: the trial's factor on the
closing force in closed form, the cases' algebra alone (a case that does not close fails), a
scan's trials in one batch, and the design direction's margin in closed form before the
sphere map. They only skip work: the check's result must be
the one the searches give when every trial is judged in full (computed here by switching the
first tests off), on generated spatial scenes that fail and search.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from spatial_scenes import write_spatial_scenes  # noqa: E402

from kcheck.body.mass import body_mass_properties  # noqa: E402
from kcheck.plugin import Inputs  # noqa: E402
from kcheck.scene import load_scene  # noqa: E402


def _results(scenes, masses):
    from kcheck_checks.analytical_3d import Analytical3D

    check = Analytical3D()
    return [
        check.run(Inputs(s, m, check.options(**s.check_options.get(check.id, {}))))
        for s, m in zip(scenes, masses, strict=True)
    ]


def test_first_tests_change_no_way_out(tmp_path, monkeypatch):
    import kcheck_checks.analytical_3d as module

    from kcheck.analysis import way_out

    scenes = [load_scene(p) for p in write_spatial_scenes(tmp_path, range(16))]
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]
    screened = _results(scenes, masses)
    searched = [r for r in screened if "passing_closing_force" in r.details]
    assert len(searched) >= 3  # the scenes exercise the closing-force search

    monkeypatch.setattr(module, "closing_analysis", _in_full)
    monkeypatch.setattr(module, "_map_passes", lambda scene, analysis, options: None)
    monkeypatch.setattr(module, "_short_of_margin", lambda analysis, options: False)
    monkeypatch.setattr(way_out, "trial_screens", _no_screens)
    assert _results(scenes, masses) == screened


def test_verdict_from_the_safe_region_is_the_full_results(tmp_path, monkeypatch):
    """Each trial the searches judge from its caps and safe region alone (``_map_passes``)
    gets the verdict of the whole result (``spatial_result``'s status on the full analysis),
    with the default margins, a larger minimum margin and none."""
    import kcheck_checks.analytical_3d as module

    from kcheck.analysis.cases import closing_analysis
    from kcheck.result import Status

    lean = module._map_passes
    compared = []

    def both(scene, analysis, options):
        got = lean(scene, analysis, options)
        full = closing_analysis(scene, masses[0])
        assert full is not None  # closing_cases said every case closes
        want = not module._short_of_margin(full, options) and (
            module.spatial_result("analytical-3d", scene, full, options)[0].status is Status.PASS
        )
        assert got is None or got == want
        compared.append(got == want)
        return got

    monkeypatch.setattr(module, "_map_passes", both)
    check = module.Analytical3D()
    masses = [None]
    for path in write_spatial_scenes(tmp_path, range(12)):
        scene = load_scene(path)
        masses[0] = body_mass_properties(scene.body, scene.scale)
        for options in ({}, {"min_margin_deg": 3.0}, {"min_margin_deg": 0.0, "marginal_deg": 0.0}):
            check.run(Inputs(scene, masses[0], check.options(**options)))
    assert sum(compared) >= 50 and any(compared)  # many trials, each the full verdict


def _no_screens(scene, mass):
    def every(trials):
        return [True] * len(trials)

    return every, every


def _in_full(scene, mass):
    """A trial through the full analysis: None only where a case does not close."""
    from kcheck.analysis import analyse

    full = analyse(scene, mass)
    closes = full.trustworthy and all(r.outcome in ("closes", "swept") for r in full.results)
    return full if closes else None


PLANAR = """\
version: 1
name: planar block
units: mm
body: {{mass: 1.0, center_of_mass: [50, 30, 0], inertia: 0.001}}
supports:
  - {{name: y1, position: [{a}, 0, 0], normal: [0, 1, 0]}}
  - {{name: y2, position: [80, 0, 0], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 30, 0], normal: [1, 0, 0]}}
friction: {mu}
gravity: [0, -9.81, 0]
load: {{magnitude: 1, angle: {angle}}}
"""


def test_first_tests_change_no_planar_way_out(tmp_path, monkeypatch):
    """The same for analytical-2d, on planar blocks that jam or lose contact under a load at
    several angles and frictions (some search the friction, some the load magnitude)."""
    import kcheck_checks.analytical_2d as module
    from kcheck_checks.analytical_2d import Analytical2D

    from kcheck.analysis import way_out

    check = Analytical2D()
    scenes = []
    for n, (mu, angle, a) in enumerate(
        (mu, angle, a) for mu in (0.3, 0.9) for angle in (200, 212, 236, 260) for a in (20, 35)
    ):
        path = tmp_path / f"block-{n}.kcheck.yaml"
        path.write_text(PLANAR.format(mu=mu, angle=angle, a=a), encoding="utf-8")
        scenes.append(load_scene(path))
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]

    def results():
        # repr: the planar details hold arrays, which == does not compare.
        pairs = zip(scenes, masses, strict=True)
        return [repr(check.run(Inputs(s, m, check.options()))) for s, m in pairs]

    screened = results()
    assert sum("passing_closing_force" in r for r in screened) >= 2
    monkeypatch.setattr(module, "closing_analysis", _in_full)
    monkeypatch.setattr(way_out, "trial_screens", _no_screens)
    assert results() == screened


def test_margin_screen_agrees_with_the_sphere_map(tmp_path):
    """The closed-form margin of the design direction equals the sphere map's (the check's
    ``design_margin_deg``) to within the screen's band: asked for that margin plus twice the
    band the trial is short of it, asked for that margin minus twice the band it is not."""
    from kcheck_checks.analytical_3d import Analytical3D, _short_of_margin

    from kcheck.analysis import analyse
    from kcheck.numerics.thresholds import MARGIN_SCREEN_DEG

    check = Analytical3D()
    scenes = [load_scene(p) for p in write_spatial_scenes(tmp_path, range(30))]
    tried = 0
    for scene in scenes:
        mass = body_mass_properties(scene.body, scene.scale)
        analysis = analyse(scene, mass)
        if not all(r.outcome == "closes" for r in analysis.results):
            continue
        result = check.run(Inputs(scene, mass, check.options()))
        margin = result.details.get("design_margin_deg")
        if margin is None or margin < 1e-3:
            continue
        tried += 1
        for shift, short in ((2 * MARGIN_SCREEN_DEG, True), (-2 * MARGIN_SCREEN_DEG, False)):
            options = check.options(min_margin_deg=margin + shift, marginal_deg=0.0)
            assert _short_of_margin(analysis, options) is short
    assert tried >= 3
