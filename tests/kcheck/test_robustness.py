"""Mangled scene files give an error result, never an exception (property-based)."""

from __future__ import annotations

import re

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kcheck.plugin import load_checks
from kcheck.result import Status
from kcheck.runner import check_scene
from tests.conftest import PLANAR_SCENE

TOKENS = re.findall(r"\S+", PLANAR_SCENE)
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
]


@settings(
    max_examples=150,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    edits=st.lists(
        st.tuples(st.sampled_from(TOKENS), st.sampled_from(NASTY + TOKENS)), min_size=1, max_size=3
    )
)
def test_mangled_scenes_never_raise(tmp_path, edits):
    text = PLANAR_SCENE
    for old, new in edits:
        text = text.replace(old, new, 1)
    path = tmp_path / "m.kcheck.yaml"
    path.write_text(text)
    result = check_scene(path, load_checks())
    assert result.status in (Status.PASS, Status.FAIL, Status.ERROR)
    if result.status is Status.ERROR:
        assert result.error and "internal error" not in result.error, result.error
        assert str(path) in result.error
