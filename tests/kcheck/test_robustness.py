"""Mangled scene files give a located error result, never an exception (property-based).

Two seeds are mangled: the planar scene of the tests and a spatial scene written with coupling
shorthands, preloads and an assembly; the replacements include the classes of bad input the
fuzzer of issue 13 found (non-finite and overflowing numbers, NUL and surrogate escapes,
aliases, odd keys).
"""

from __future__ import annotations

import re

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import Status
from tests.conftest import PLANAR_SCENE

COUPLED_SCENE = """
version: 1
units: mm
body:
  mass: 2
  center_of_mass: [0, 0, 10]
  inertia: [[0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.02]]
  point_masses: [{name: magnet, mass: 0.1, point: [0, 0, 5]}]
couplings:
  - {name: a, type: ball-vee, ball: {center: [0, 50, 0], radius: 6},
     groove: {axis: [0, 1, 0], up: [0, 0, 1], half_angle: 45}}
  - {name: b, type: ball-trihedral, ball: {center: [-43.3, -25, 0], radius: 6},
     up: [0, 0, 1], half_angle: 54.7, reference: [1, 0, 0]}
  - {name: c, type: ball-flat, ball: {center: [43.3, -25, 0], radius: 6}, normal: [0, 0, 1]}
friction: 0.1
gravity: [0, 0, -9.81]
preloads: [{name: spring, point: [0, 0, 20], force: [0, 0, -30]}]
load: {magnitude: 10, direction: [0, 0, -1]}
"""
SEEDS = (PLANAR_SCENE, COUPLED_SCENE)
TOKENS = sorted({t for seed in SEEDS for t in re.findall(r"\S+", seed)})
NASTY = [
    "",
    "-",
    "[",
    "]",
    "{",
    "}",
    ":",
    "'",
    "1e999",
    "-1e3",
    ".nan",
    "null",
    "~",
    "&a",
    "*a",
    "!!python/object:os.system",
    "[1, 2, 3, 4]",
    "0",
    "-0.0",
    "yes",
    "1_0",
    "0x10",
    "\t",
    ".inf",
    "-.inf",
    "1e300",
    "[1e300, 0, 0]",
    "[0, 0, 0]",
    '"\\0"',
    '"\\ud800"',
    "&x [1, 2, 3]",
    "*x",
    "{a: &r {b: *r}}",
    "<<:",
    "null:",
    "true:",
    "1:",
    "ball-cone",
    "ball_on: base,",
    "version: 1.0",
    "friction: 1e9",
]


@settings(
    max_examples=150,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    seed=st.sampled_from(SEEDS),
    edits=st.lists(
        st.tuples(st.sampled_from(TOKENS), st.sampled_from(NASTY + TOKENS)), min_size=1, max_size=3
    ),
)
def test_mangled_scenes_never_raise(tmp_path, seed, edits):
    text = seed
    for old, new in edits:
        text = text.replace(old, new, 1)
    path = tmp_path / "m.kcheck.yaml"
    path.write_text(text)
    result = check_scene(path, load_checks())
    assert result.status in (Status.PASS, Status.FAIL, Status.ERROR)
    if result.status is Status.ERROR:
        assert result.error and "internal error" not in result.error, result.error
        assert str(path) in result.error
        # Located: every input error has a line, except a file with no content at all.
        for finding in result.errors:
            assert finding.line is not None or "empty" in finding.message, finding


def test_a_plugin_raising_in_skip_reason_is_that_checks_error(write_scene):
    # A third-party check that raises while deciding whether it applies: that check is an
    # error result naming it; the other checks of the scene still run.
    from kcheck.plugin import Check, CheckSpec, LoadedCheck

    class Broken(Check):
        id = "broken"
        summary = "raises in skip_reason"
        applies_to = "nothing"

        def skip_reason(self, scene):
            raise ValueError("boom")

    import importlib.metadata

    ep = importlib.metadata.EntryPoint("broken", "x:y", "kcheck.checks")
    checks = [*load_checks(), LoadedCheck(CheckSpec("other", "1", ep), Broken())]
    result = check_scene(write_scene(PLANAR_SCENE), checks)
    by_id = {c.id: c for c in result.checks}
    assert by_id["broken"].status is Status.ERROR and "ValueError: boom" in by_id["broken"].message
    assert by_id["analytical-2d"].status is Status.PASS
