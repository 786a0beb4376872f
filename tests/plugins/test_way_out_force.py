"""The least preload that makes a failing scene pass (issue 21, "a way out of every failure").

A planar block on y1, y2 (normals +y) and x1 (normal +x), its weight m g down and a spring
pushing it towards x1 (−x) through the centre of mass. With x1 retracted, the spring slides
the block along y1 and y2 against their friction, whose sum is μ (N1 + N2) = μ m g whatever
the spring's moment (it is horizontal): the case closes only for a spring force F > μ m g
(closed form, computed here). Too weak a spring is a failing case whose hint names the least
preload; applying it, the check passes.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

MASS, G, MU = 1.0, 9.81, 0.1

SCENE = """\
version: 1
name: preloaded block
units: mm
body: {{mass: {mass}, center_of_mass: [50, 30, 0], inertia: 0.001}}
supports:
  - {{name: y1, position: [20, 0, 0], normal: [0, 1, 0]}}
  - {{name: y2, position: [80, 0, 0], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 30, 0], normal: [1, 0, 0]}}
friction: {mu}
gravity: [0, -{g}, 0]
preloads:
  - {{name: spring, point: [50, 30, 0], force: [-{force}, 0, 0]}}
"""


def _check(tmp_path: Path, cli_json, force: float) -> dict:
    path = tmp_path / f"block-{force}.kcheck.yaml"
    path.write_text(SCENE.format(mass=MASS, g=G, mu=MU, force=force), encoding="utf-8")
    _, doc = cli_json(str(path), "--select", "analytical-2d")
    (check,) = doc["scenes"][0]["checks"]
    return check


def test_a_too_weak_spring_is_told_the_least_preload_that_passes(tmp_path, cli_json) -> None:
    least = MU * MASS * G  # closed form: the spring must beat the friction on y1 and y2
    check = _check(tmp_path, cli_json, 0.5)
    assert check["status"] == "fail"
    hints = [f.get("hint") or "" for f in check["findings"]]
    x1 = next(f for f in check["findings"] if f["message"].startswith("retract x1 →"))
    assert "jams" in x1["message"]
    found = re.search(r"the check passes with preload `spring` at least ([\d.]+) N", x1["hint"])
    assert found is not None, hints
    value = float(found.group(1))
    # Rounded outward (up) to three significant digits, from a bisection bracketing the bound.
    assert least <= value <= least * 1.01
    assert check["passing_closing_force"]["value"] == pytest.approx(value)
    assert _check(tmp_path, cli_json, value)["status"] == "pass"
    # Just under the closed form the x1 case still jams: the bound is the least.
    below = _check(tmp_path, cli_json, least * 0.995)
    assert below["status"] == "fail"
    assert next(c for c in below["cases"] if c["retracted"] == "x1")["outcome"] == "jams"


def test_a_passing_scene_gets_no_preload_hint(tmp_path, cli_json) -> None:
    check = _check(tmp_path, cli_json, 2.0)
    assert check["status"] == "pass"
    assert "passing_closing_force" not in check


LOADED = """\
version: 1
name: loaded block
units: mm
body: {{mass: {mass}, center_of_mass: [50, 30, 0], inertia: 0.001}}
supports:
  - {{name: y1, position: [20, 0, 0], normal: [0, 1, 0]}}
  - {{name: y2, position: [80, 0, 0], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 30, 0], normal: [1, 0, 0]}}
friction: {mu}
gravity: [0, -{g}, 0]
load: {{magnitude: {force}, angle: 180}}
"""


def _loaded(tmp_path: Path, cli_json, force: float) -> dict:
    path = tmp_path / f"loaded-{force}.kcheck.yaml"
    path.write_text(LOADED.format(mass=MASS, g=G, mu=MU, force=force), encoding="utf-8")
    _, doc = cli_json(str(path), "--select", "analytical-2d")
    (check,) = doc["scenes"][0]["checks"]
    return check


def test_without_a_preload_the_load_magnitude_is_the_closing_force(tmp_path, cli_json) -> None:
    """The same block pushed by its swept load at 180° instead of a spring: below μ m g no
    angle near −x closes the x1 retraction (closed form), so the least magnitude is above it
    (more, since the design direction must also keep the required margin); the magnitude the
    hint writes passes."""
    check = _loaded(tmp_path, cli_json, 0.5)
    assert check["status"] == "fail"
    hint = next(f["hint"] for f in check["findings"] if f["message"].startswith("retract x1"))
    found = re.search(r"the check passes with a load magnitude at least ([\d.]+) N", hint)
    assert found is not None, hint
    value = float(found.group(1))
    assert value >= MU * MASS * G
    assert _loaded(tmp_path, cli_json, value)["status"] == "pass"
    assert _loaded(tmp_path, cli_json, MU * MASS * G * 0.995)["status"] == "fail"


@pytest.mark.parametrize("spatial", [False, True])
def test_without_hints_the_verdict_and_figures_are_the_same(tmp_path, spatial) -> None:
    """``Inputs.hints`` False (a study's variants) skips only the way-out searches: the same
    status, message, margin, cases and findings, less the hints and their details."""
    import dataclasses
    import sys

    from kcheck.body.mass import body_mass_properties
    from kcheck.plugin import Inputs
    from kcheck.scene import load_scene

    if spatial:
        sys.path.append(str(Path(__file__).resolve().parents[1]))
        from kcheck_checks.analytical_3d import Analytical3D as Check
        from spatial_scenes import write_spatial_scenes

        paths = write_spatial_scenes(tmp_path, range(8))
    else:
        from kcheck_checks.analytical_2d import Analytical2D as Check

        paths = [tmp_path / "block.kcheck.yaml"]
        paths[0].write_text(SCENE.format(mass=MASS, g=G, mu=MU, force=0.5), encoding="utf-8")
    check, failing = Check(), 0
    for path in paths:
        scene = load_scene(path)
        if check.skip_reason(scene) is not None:
            continue
        inputs = Inputs(scene, body_mass_properties(scene.body, scene.scale), check.options())
        full = check.run(inputs)
        bare = check.run(dataclasses.replace(inputs, hints=False))
        failing += any(f.hint and "passes with" in f.hint for f in full.findings)
        assert _without_hints(bare.to_json()) == _without_hints(full.to_json())
        assert not any(f.hint and "passes with" in f.hint for f in bare.findings)
    assert failing  # the way-out search found a passing force or friction somewhere


def _without_hints(doc: dict) -> dict:
    """A result's JSON less run time, the way-out searches' answers and the findings' hints."""
    out = {k: v for k, v in doc.items() if not k.startswith("passing_") and "time" not in k}
    out["findings"] = [{k: v for k, v in f.items() if k != "hint"} for f in doc["findings"]]
    return out
