"""The full JSON result of every bundled fixture, against the one recorded before the layout
move of issue 20 (tests/golden/fixtures.json): a refactoring must not change a verdict, a
number or a word.

The recording is kcheck's own output at commit b5af425 (the flat layout), run time fields
aside. Numbers are compared to 1e-9 relative, so that the suite also passes at the declared
lower bounds of numpy and scipy, whose last bits differ (quantities a solver finds to a
stated accuracy, at that accuracy: SOLVER_RTOL); every string, verdict and key must be
identical. When a change is meant to alter results, regenerate the file with
``KCHECK_RECORD_GOLDEN=1 pytest tests/cli/test_fixture_results.py`` and say why in the commit.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

from kcheck.numerics.thresholds import JAM_MU_RTOL

ROOT = Path(__file__).resolve().parents[2]
#: Quantities an iterative solver finds to a stated accuracy, compared at that accuracy (the
#: conic solver's versions differ in their last digits): the jamming check's least holding
#: friction is bisected to JAM_MU_RTOL.
SOLVER_RTOL = {"holding_friction": JAM_MU_RTOL}
#: Margins whose value is a solver-found quantity over an input, keyed by their quantity: the
#: jamming margin is the bisected least holding friction over the design friction.
MARGIN_RTOL = {"least holding friction / design friction": JAM_MU_RTOL}
GOLDEN = ROOT / "tests" / "golden" / "fixtures.json"


def _strip(value):
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if "time" not in k and k != "kcheck_version"}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    return value


def _differences(expected, actual, where="$", key=""):
    if isinstance(expected, dict) and isinstance(actual, dict):
        if key == "margin" and expected.get("quantity") in MARGIN_RTOL:
            rtol = MARGIN_RTOL[expected["quantity"]]
            if not math.isclose(expected["value"], actual.get("value", math.nan), rel_tol=rtol):
                yield f"{where}.value: {expected['value']!r}, now {actual.get('value')!r}"
            expected = {k: v for k, v in expected.items() if k != "value"}
            actual = {k: v for k, v in actual.items() if k != "value"}
        if expected.keys() != actual.keys():
            yield f"{where}: keys {sorted(expected.keys() ^ actual.keys())} differ"
        for key in expected.keys() & actual.keys():
            yield from _differences(expected[key], actual[key], f"{where}.{key}", key)
    elif isinstance(expected, list) and isinstance(actual, list):
        if len(expected) != len(actual):
            yield f"{where}: {len(expected)} items, now {len(actual)}"
        for i, (e, a) in enumerate(zip(expected, actual, strict=False)):
            yield from _differences(e, a, f"{where}[{i}]", key)
    elif (
        isinstance(expected, float)
        and isinstance(actual, (int, float))
        and not isinstance(actual, bool)
    ):
        rtol = SOLVER_RTOL.get(key, 1e-9)
        if not math.isclose(expected, actual, rel_tol=rtol, abs_tol=1e-12):
            yield f"{where}: {expected!r}, now {actual!r}"
    elif expected != actual or type(expected) is not type(actual):
        yield f"{where}: {expected!r}, now {actual!r}"


def test_every_fixture_gives_the_recorded_result():
    run = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", "fixtures", "--format", "json", "--no-cache"]
        + ["-j", "1", "--color", "never"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 1, run.stderr  # thesis Appendix A fails on purpose
    actual = _strip(json.loads(run.stdout))
    if os.environ.get("KCHECK_RECORD_GOLDEN"):
        GOLDEN.write_text(json.dumps(actual, indent=1, sort_keys=True) + "\n")
    expected = json.loads(GOLDEN.read_text())
    assert len(expected["scenes"]) == len(list((ROOT / "fixtures").glob("*/*.kcheck.yaml")))
    differences = list(_differences(expected, actual))
    assert not differences, "\n".join(differences[:40])
