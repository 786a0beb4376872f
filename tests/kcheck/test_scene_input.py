"""Bad input never wins (issue 13, the loader's part): every class of bad scene found by the
fuzzer is a located input error naming file, field, line and the allowed range; every error
of a file is reported; YAML attacks end in bounded time and memory; bad mesh paths are
located errors, never tracebacks."""

from __future__ import annotations

import math
import os
import time
import tracemalloc
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from kcheck.errors import SceneError
from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import Status
from kcheck.scene import load_scene
from kcheck.scene.yamlio import HAVE_LIBYAML, YamlLimits, read_yaml
from tests.conftest import FIXTURES, PLANAR_SCENE


def _edit(old: str, new: str, text: str = PLANAR_SCENE) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def _errors(path: Path) -> list[SceneError]:
    with pytest.raises(SceneError) as info:
        load_scene(path)
    errors = list(info.value.all())
    for e in errors:
        assert e.path == str(path)
    return errors


def _one(path: Path, field: str | None, fragment: str) -> SceneError:
    errors = _errors(path)
    found = [e for e in errors if e.field == field and fragment in e.message]
    assert found, [str(e) for e in errors]
    assert found[0].line is not None
    return found[0]


# (scene text, field, fragment of the message). PLANAR_SCENE has no mesh.
NONSENSE = {
    "infinite load": (_edit("magnitude: 1", "magnitude: .inf"), "load.magnitude", "finite"),
    "nan angle": (_edit("angle: 225", "angle: .nan"), "load.angle", "finite"),
    "huge load": (_edit("magnitude: 1", "magnitude: 1e9"), "load.magnitude", "1e+07 N"),
    "vanishing load": (_edit("magnitude: 1", "magnitude: 1e-300"), "load.magnitude", "1e-06 N"),
    "infinite mass": (_edit("mass: 1", "mass: .inf"), "body.mass", "finite"),
    "tiny mass": (_edit("mass: 1", "mass: 1e-320"), "body.mass", "1e-09 ≤ mass"),
    "infinite margin option": (
        PLANAR_SCENE + "checks:\n  analytical-2d: {min_margin_deg: .inf}\n",
        "checks.analytical-2d.min_margin_deg",
        "finite",
    ),
    "version true": (_edit("version: 1", "version: true"), "version", "integer 1"),
    "version 1.0": (_edit("version: 1", "version: 1.0"), "version", "integer 1"),
    "overflowing normal": (
        _edit("normal: [1, 0, 0]", "normal: [1e300, 0, 0]"),
        "supports[2].normal",
        "largest component",
    ),
    "far position": (
        _edit("[0, 30, 0]", "[0, 3e9, 0]"),
        "supports[2].position",
        "|x| ≤ 1000 m",
    ),
    "friction beyond maximum": (_edit("friction: 0.1", "friction: 1000"), "friction", "≤ 100"),
    "negative friction": (_edit("friction: 0.1", "friction: -0.1"), "friction", "0 ≤ friction"),
    "huge angle": (_edit("angle: 225", "angle: 1e6"), "load.angle", "deg"),
    "NUL in a name": (_edit("name: x1", 'name: "x\\0"'), "supports[2].name", "NUL"),
    "huge integer": (_edit("magnitude: 1", "magnitude: " + "9" * 400), "load.magnitude", "large"),
    "gravity overflow": (
        PLANAR_SCENE + "gravity: [1e200, 0, 0]\n",
        "gravity",
        "|g| ≤ 1000",
    ),
    "non-symmetric inertia": (
        _edit("inertia: 0.001", "inertia: [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]"),
        "body.inertia",
        "symmetric",
    ),
    "misspelt key": (_edit("friction: 0.1", "fricton: 0.1"), "fricton", "did you mean `friction`"),
    "misspelt nested key": (_edit("magnitude: 1", "magnitud: 1"), "load.magnitud", "`magnitude`"),
}


@pytest.mark.parametrize("name", list(NONSENSE))
def test_nonsense_is_a_located_error(write_scene, name):
    text, field, fragment = NONSENSE[name]
    _one(write_scene(text), field, fragment)


def test_lone_surrogate(write_scene):
    # Said once, in kcheck's words (pydantic refuses the text too, in its own), whichever
    # parser read the escape.
    (error,) = _errors(write_scene(_edit("name: x1", 'name: "\\ud800"')))
    assert (error.field, error.line) == ("supports[2].name", 11)
    assert error.message == "the text contains an unpaired surrogate (not valid Unicode text)"


# Wrong types are said in kcheck's words, not pydantic's (whose wording changes between
# releases): what was expected, and what came.
TYPE_ERRORS = {
    "not a list": (
        "normal: [1, 0, 0]",
        "normal: 3",
        "supports[2].normal",
        "expected a list, got 3",
    ),
    "name too long": (
        "name: x1",
        "name: " + "n" * 300,
        "supports[2].name",
        "expected at most 200 character(s), got 300",
    ),
    "not a mapping": ("friction: 0.1", "friction: 0.1\nchecks: 3", "checks", "expected a mapping"),
    "a validator's own words": (
        "version: 1",
        "version: true",
        "version",
        "expected the integer 1, got True",
    ),
    "unknown unit": (
        "units: mm",
        "units: furlong",
        "units",
        "expected one of 'm', 'cm', 'mm', 'um', 'in', got 'furlong'",
    ),
}


@pytest.mark.parametrize("name", list(TYPE_ERRORS))
def test_type_errors_in_kchecks_words(write_scene, name):
    old, new, field, message = TYPE_ERRORS[name]
    error = _one(write_scene(_edit(old, new)), field, message)
    assert error.message.startswith(message)


@pytest.mark.parametrize(
    ("value", "message"),
    [("x", "expected a number, got 'x'"), ("2", "out of range: expected min_cos ≤ 1, got 2")],
)
def test_check_options_in_kchecks_words(write_scene, value, message):
    text = PLANAR_SCENE + f"checks:\n  maxwell: {{min_cos: {value}}}\n"
    result = check_scene(write_scene(text), load_checks())
    (error,) = result.errors
    assert result.status is Status.ERROR and error.field == ("checks", "maxwell", "min_cos")
    assert error.line == 17 and error.message == message


def test_planar_inertia_in_range(write_scene):
    _one(write_scene(_edit("inertia: 0.001", "inertia: 1e300")), "body.inertia", "kg m^2")


MESH_BODY = "  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n"


@pytest.mark.parametrize(
    ("body", "field", "fragment"),
    [
        ("  mesh: m.stl\n  material: steel\n  density: 7850\n", "body", "not both"),
        ("  mesh: m.stl\n  material: unobtainium\n", "body.material", "unknown material"),
        ("  mesh: m.stl\n  density: .inf\n", "body.density", "finite"),
        ("  mesh: m.stl\n  density: 1e308\n", "body.density", "≤ 30000 kg/m^3"),
        (
            "  parts:\n    - {mesh: m.stl, material: steel, density: 7850}\n",
            "body.parts[0]",
            "not both",
        ),
        (
            "  parts:\n    - {mesh: m.stl, material: kryptonite}\n",
            "body.parts[0].material",
            "unknown material",
        ),
        (
            "  parts:\n    - {mesh: m.stl, material: steel, transform: {rotate: "
            "[[1, 0, 0], [0, 1, 0], [0, 0, -1]]}}\n",
            "body.parts[0].transform.rotate",
            "mirrors",
        ),
        (
            "  parts:\n    - {mesh: m.stl, material: steel, transform: {rotate: "
            "[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]}}\n",
            "body.parts[0].transform.rotate",
            "orthonormal",
        ),
        (
            "  mesh: m.stl\n  material: steel\n  point_masses: [{name: a, mass: -1, point: "
            "[0, 0, 0]}]\n",
            "body.point_masses[0].mass",
            "0 < mass",
        ),
    ],
)
def test_body_fields(write_scene, tmp_path, body, field, fragment):
    (tmp_path / "m.stl").write_text("solid x\nendsolid x\n")
    _one(write_scene(_edit(MESH_BODY, body)), field, fragment)


def test_every_error_of_a_file_in_line_order(write_scene):
    text = _edit("magnitude: 1", "magnitude: .inf")
    text = _edit("friction: 0.1", "fricton: 0.1", text)
    text = _edit("normal: [1, 0, 0]", "normal: [0, 0, 0]", text)
    errors = _errors(write_scene(text))
    assert [e.field for e in errors] == ["supports[2].normal", "fricton", "load.magnitude"]
    assert [e.line for e in errors] == sorted(e.line for e in errors)
    assert all(e.column is not None for e in errors)
    # A wrong `units` stops at the fields: every length would be read in a unit not meant.
    wrong_units = _edit("units: mm", "units: furlong", text)
    assert [e.field for e in _errors(write_scene(wrong_units))] == [
        "units",
        "fricton",
        "load.magnitude",
    ]


def test_three_mistakes_in_one_run(write_scene, tmp_path):
    """Issue 21: mistakes in `friction` (a structure error), one support's `normal` and
    `load` (value errors) come out together, each at its own line, from the loader and as
    exit 2 from the command line, without a traceback."""
    import subprocess
    import sys

    text = _edit("friction: 0.1", "friction: -0.1")
    text = _edit("normal: [0, 1, 0]}", "normal: [0, 0, 0]}", text)
    text = _edit("angle: 225", "angle: 225\n  direction: [1, 0, 0]", text)
    path = write_scene(text)
    lines = path.read_text().splitlines()
    errors = _errors(path)
    by_field = {e.field: e for e in errors}
    assert set(by_field) == {"friction", "supports[0].normal", "load"}
    for field, written in (
        ("friction", "friction: -0.1"),
        ("supports[0].normal", "name: y1"),
        ("load", "load:"),
    ):
        assert written in lines[by_field[field].line - 1], field
    run = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(path)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert run.returncode == 2
    assert "Traceback" not in run.stdout + run.stderr
    for e in errors:
        assert f"{path.name}:{e.line}:" in run.stdout


def test_a_dropped_item_does_not_make_errors_of_its_own(write_scene):
    """A support whose `normal` is missing is left out to check the rest, which must not
    turn into "2 supports" or a duplicate name: only the mistake itself is said."""
    text = _edit(", normal: [0, 1, 0]}", "}")
    text = _edit("magnitude: 1", "magnitude: -1", text)
    errors = _errors(write_scene(text))
    assert {e.field for e in errors} == {"supports[0].normal", "load.magnitude"}


def test_slips_a_new_user_made_are_said_once_with_the_fix(write_scene):
    """From a new user's first scene: a misspelt required key (`normals:`) was reported twice
    (the key unknown, and `normal` missing); a unit written out (`millimetres`) and gravity
    in mm/s² got no hint of the fix."""
    text = _edit("normal: [1, 0, 0]", "normals: [1, 0, 0]")
    text = _edit("units: mm", "units: millimetres", text)
    errors = _errors(write_scene(text))
    by_field = {e.field: e.message for e in errors}
    assert set(by_field) == {"units", "supports[2].normals"}
    assert by_field["supports[2].normals"].endswith("did you mean `normal`?")
    assert by_field["units"].endswith("did you mean `mm`?")
    gravity = _edit("units: mm", "units: mm\ngravity: [0, -9810, 0]")
    (error,) = _errors(write_scene(gravity))
    assert error.field == "gravity" and "m/s² whatever `units` says" in error.message


def test_semantic_errors_are_all_reported(write_scene):
    text = _edit("normal: [1, 0, 0]", "normal: [0, 0, 0]")
    text = _edit("name: y2", "name: y1", text)
    text = _edit("[20, 0, 0]", "[2e7, 0, 0]", text)
    fields = {e.field for e in _errors(write_scene(text))}
    assert fields == {"supports[0].position", "supports[1].name", "supports[2].normal"}


def test_column_of_a_value(write_scene):
    error = _one(write_scene(_edit("magnitude: 1", "magnitude: -1")), "load.magnitude", "0 ≤")
    assert (error.line, error.column) == (14, 3)
    assert str(error).startswith(f"{error.path}:14:3: field `load.magnitude`")


# --- YAML attacks ----------------------------------------------------------------------------


def _bomb(levels: int) -> str:
    lines = ["a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    for i in range(1, levels + 1):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 9) + "]")
    return "\n".join(lines) + "\n"


ATTACKS = {
    "bomb 7 levels": (_bomb(7), "alias bomb"),
    "bomb 8 levels": (_bomb(8), "alias bomb"),
    "bomb 9 levels": (_bomb(9), "alias bomb"),
    "recursive alias": ("a: &a {b: *a}\n", "recursive"),
    "recursive list": ("a: &a [1, *a]\n", "recursive"),
    "deep nesting": ("a: " + "[" * 50_000 + "]" * 50_000 + "\n", "nest deeper"),
    "merge key": ("base: &b {x: 1}\nload:\n  <<: *b\n", "merge keys"),
    "null key": ("version: 1\nload:\n  magnitude: 1\n  null: 3\n", "`null`"),
    "true key": ("version: 1\nload:\n  true: 3\n", "boolean"),
    "integer key": ("version: 1\nload:\n  1: 3\n", "integer"),
    "python tag": ("version: !!python/object:os.system ls\n", "not allowed"),
    "two documents": ("version: 1\n---\nversion: 1\n", "more than one YAML document"),
    "undefined alias": ("a: *nothing\n", "no anchor"),
}


@pytest.mark.parametrize("backend", ["c", "python"] if HAVE_LIBYAML else ["python"])
@pytest.mark.parametrize("name", list(ATTACKS))
def test_yaml_attacks_are_bounded(tmp_path, name, backend):
    text, fragment = ATTACKS[name]
    path = tmp_path / "attack.kcheck.yaml"
    path.write_text(text)
    tracemalloc.start()
    started = time.process_time()  # CPU, not wall: a loaded machine must not fail it
    with pytest.raises(SceneError) as info:
        read_yaml(path, backend=backend)
    elapsed = time.process_time() - started
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert fragment in info.value.message, info.value.message
    assert info.value.line is not None
    # Loose sanity bounds, not a benchmark (docs/performance.md has the times): the 7-level
    # bomb once took 18.7 s and 1.2 GB. PyYAML's own scanner looks far ahead in flow
    # collections, so its deep-nesting case is slower (libyaml's is milliseconds).
    limit_s = 5.0 if (backend == "python" and name == "deep nesting") else 2.0
    assert elapsed < limit_s and peak < 20e6


@pytest.mark.skipif(not HAVE_LIBYAML, reason="PyYAML built without libyaml")
@pytest.mark.parametrize(
    "text",
    [
        "a: " + "[" * 2_000 + "]" * 2_000 + "\n",  # past libyaml's own depth limit (1000)
        "a: " + "{b: " * 1_500 + "1" + "}" * 1_500 + "\n",
        "a: [1, 2\nb: 3\n",
        "a: 'unterminated\n",
        "a: 1\n b: 2\n",
        "- 1\na: 2\n",
    ],
    ids=["lists past libyaml's limit", "mappings past it", "flow", "quote", "indent", "mixed"],
)
def test_both_parsers_give_kcheck_s_error_at_the_same_place(tmp_path, text):
    # Whatever limit or error libyaml trips first, the user reads the same located message
    # from either parser: the pure-Python one (with kcheck's composer) is the reference.
    path = tmp_path / "bad.kcheck.yaml"
    path.write_text(text)
    errors = []
    for backend in ("c", "python"):
        with pytest.raises(SceneError) as info:
            read_yaml(path, backend=backend)
        errors.append(info.value)
    c, py = errors
    assert (c.message, c.line, c.column) == (py.message, py.line, py.column)
    assert c.line is not None and str(path) in str(c)
    if "[" * 100 in text or "{b: " * 100 in text:
        assert c.message == "mappings and lists nest deeper than 64 levels"
        # The root mapping is level 1: the 64th opening bracket after `a: ` is refused.
        width = 1 if text.startswith("a: [") else len("{b: ")
        assert (c.line, c.column) == (1, len("a: ") + 63 * width + 1)


def test_keys_are_reported_at_their_own_line(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("version: 1\nload:\n  magnitude: 1\n  null: 3\n")
    with pytest.raises(SceneError) as info:
        read_yaml(path)
    assert (info.value.line, info.value.column) == (4, 3)
    assert info.value.field == "load"


def test_file_size_limit_is_a_parameter(tmp_path):
    path = tmp_path / "big.kcheck.yaml"
    path.write_text("version: 1\n" + "# padding\n" * 2000)
    read_yaml(path)  # 20 kB is fine by default
    with pytest.raises(SceneError, match="larger than"):
        read_yaml(path, limits=YamlLimits(max_bytes=10_000))


@pytest.mark.parametrize(
    ("raw", "fragment", "line"),
    [
        (b"version: 1\nname: a\x00b\n", "NUL", 2),
        (b"version: 1\nname: caf\xe9\n", "not UTF-8", 2),
    ],
)
def test_bytes_that_are_not_text(tmp_path, raw, fragment, line):
    path = tmp_path / "bad.kcheck.yaml"
    path.write_bytes(raw)
    with pytest.raises(SceneError) as info:
        read_yaml(path)
    assert fragment in info.value.message and info.value.line == line


@pytest.mark.skipif(not HAVE_LIBYAML, reason="PyYAML built without libyaml")
@pytest.mark.parametrize(
    "fixture", sorted(FIXTURES.glob("*/*.kcheck.yaml")), ids=lambda p: p.parent.name
)
def test_c_and_python_parsers_agree(fixture):
    c, py = read_yaml(fixture, backend="c"), read_yaml(fixture, backend="python")
    assert c.data == py.data and c.lines == py.lines and c.columns == py.columns


def test_yaml_12_scalars(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("a: 010\nb: 0o10\nc: 1:20\nd: 1_000\ne: 0x1F\nf: .inf\ng: 1e3\nh: ~\n")
    data = read_yaml(path).data
    assert data == {
        "a": 10,
        "b": 8,
        "c": "1:20",
        "d": "1_000",
        "e": 31,
        "f": float("inf"),
        "g": 1000.0,
        "h": None,
    }


# --- mesh paths -------------------------------------------------------------------------------

MESH_SCENE = _edit(MESH_BODY, "  mesh: {mesh}\n  material: steel\n")


def _mesh_error(write_scene, name: str) -> SceneError:
    text = MESH_SCENE.replace("{mesh}", name)
    return _one(write_scene(text), "body.mesh", "")


def test_mesh_path_problems(write_scene, tmp_path):
    (tmp_path / "loop.stl").symlink_to(tmp_path / "loop.stl")
    (tmp_path / "dangling.stl").symlink_to(tmp_path / "gone.stl")
    (tmp_path / "folder.stl").mkdir()
    cases = {
        '"a\\0b.stl"': "NUL",
        "x" * 5000 + ".stl": "too long",
        "loop.stl": "loop of symbolic links",
        "dangling.stl": "dangling symbolic link",
        "folder.stl": "is a folder",
        "missing.stl": "not found",
    }
    for name, fragment in cases.items():
        errors = _errors(write_scene(MESH_SCENE.replace("{mesh}", name)))
        assert any(e.field in ("body.mesh",) and fragment in e.message for e in errors), (
            name,
            [str(e) for e in errors],
        )


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads any file")
def test_unreadable_mesh(write_scene, tmp_path):
    mesh = tmp_path / "m.stl"
    mesh.write_text("solid x\nendsolid x\n")
    mesh.chmod(0)
    _one(write_scene(MESH_SCENE.replace("{mesh}", "m.stl")), "body.mesh", "permission")


def test_runner_reports_every_error_without_internal_error(write_scene):
    text = _edit("magnitude: 1", "magnitude: .inf")
    text = _edit("friction: 0.1", "fricton: 0.1", text)
    result = check_scene(write_scene(text), load_checks())
    assert result.status is Status.ERROR
    assert len(result.errors) == 2 and "internal error" not in (result.error or "")
    assert {e.field for e in result.errors} == {("load", "magnitude"), ("fricton",)}


# --- the documented limits are the enforced ones -------------------------------------------

DOC_ROWS = {
    "coordinate": "| coordinates",
    "radius": "| radii",
    "mass": "| mass (",
    "density": "| density",
    "inertia": "| principal moments",
    "force": "| force (",
    "torque": "| torque",
    "gravity": "| gravity",
    "friction": "| friction",
    "angle": "| angles",
    "half_angle": "| `half_angle`",
    "tolerance_length": "| tolerance of positions",
    "tolerance_angle": "| tolerance of angles",
    "layout": "| layout",
}


def test_limits_table_matches_the_code():
    from kcheck.scene.limits import LIMITS
    from kcheck.scene.yamlio import DEFAULT_LIMITS
    from tests.conftest import ROOT

    doc = (ROOT / "docs" / "scene-format.md").read_text()
    assert set(DOC_ROWS) == set(LIMITS)
    for key, label in DOC_ROWS.items():
        row = next(line for line in doc.splitlines() if line.startswith(label))
        r = LIMITS[key]
        assert f"{r.high:g}" in row, (key, row)
        if r.low > 0:
            assert f"{r.low:g}" in row, (key, row)
    assert f"{DEFAULT_LIMITS.max_bytes / 2**20:g} MiB" in doc
    assert f"| {DEFAULT_LIMITS.max_depth} levels |" in doc
    assert f"{DEFAULT_LIMITS.max_values:,}".replace(",", " ") in doc
    assert f"{DEFAULT_LIMITS.max_alias_values:,}".replace(",", " ") in doc


def test_every_check_option_error_in_one_run(write_scene):
    """Options of several checks, and a misspelt check id, are said together."""
    text = PLANAR_SCENE + (
        "checks:\n  analytical-2d: {min_margin_deg: abc, no_such_option: 1}\n  analytcal-2d: {}\n"
    )
    result = check_scene(write_scene(text), load_checks())
    assert result.status is Status.ERROR
    fields = {e.field for e in result.errors}
    assert fields == {
        ("checks", "analytical-2d", "min_margin_deg"),
        ("checks", "analytical-2d", "no_such_option"),
        ("checks", "analytcal-2d"),
    }
    assert all(e.line is not None for e in result.errors)


def _former_walk(value: Any, path: tuple, budget: list[int]) -> Iterator[tuple[tuple, Any]]:
    """``validate._walk`` as it was: every node (a mapping's keys too), depth first."""
    budget[0] -= 1
    if budget[0] < 0:
        return
    yield path, value
    if isinstance(value, dict):
        for k, v in value.items():
            yield (*path, k), k
            yield from _former_walk(v, (*path, k), budget)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _former_walk(v, (*path, i), budget)


def _former_problems(data: Any, problems: Any, budget: int) -> None:
    """``plain_value_problems`` as it was, over ``_former_walk``."""
    from kcheck.scene.validate import _MAX_INT, _bad_string

    for where, value in _former_walk(data, (), [budget]):
        if isinstance(value, bool) or value is None:
            continue
        if isinstance(value, float) and not math.isfinite(value):
            problems.add(where, f"expected a finite number, got {value}")
        elif isinstance(value, int) and abs(value) > _MAX_INT:
            problems.add(where, "the number is too large to be a physical quantity")
        elif isinstance(value, str):
            bad = _bad_string(value)
            if bad:
                problems.add(where, f"the text {bad}")


class _Text(str):
    pass


def test_plain_value_problems_as_the_former_walk() -> None:
    """The recursive check (``_check_tree``, no generators) finds the same problems at the
    same fields in the same order as the generator walk it replaced, with any budget."""
    from kcheck.scene.validate import Problems, _check_tree

    bad: list[Any] = [
        math.nan, math.inf, -math.inf, 10**301, -(10**301), "a\x00b", "x\ud800y", True, None,
        1.5, 7, "fine", _Text("t\x00"), [], {},
    ]  # fmt: skip
    data = {
        "a": bad,
        "b": {"c": {"d": bad, math.inf: 1, "e\x00": [bad, {"f": bad}]}},
        10**302: "key",
        "g": [[[math.nan, {"h": -math.inf}]]],
        "i": bad[:3],
    }
    found = []
    for budget in (1_000_000, 1, 2, 5, 17, 40, 77):
        mine, former = Problems(Path("x"), {}), Problems(Path("x"), {})
        _check_tree(data, (), [budget], mine)
        _former_problems(data, former, budget)
        assert [(e.where, e.message) for e in mine.errors] == [
            (e.where, e.message) for e in former.errors
        ]
        found.append(len(former.errors))
    assert found[0] > 30 and 0 < found[3] < found[-1] < found[0]  # budgets cut the walk


def test_direction_and_coordinates_as_the_numpy_tests() -> None:
    """``Problems.direction`` and ``coordinates`` (their size tests in Python floats for one
    vector) accept, refuse and word the same as the numpy tests they replaced: zeros,
    tiny and huge components, NaN and infinities anywhere in the vector."""
    import numpy as np

    from kcheck.scene.couplings import unit
    from kcheck.scene.limits import LIMITS, MAX_DIRECTION, MIN_DIRECTION
    from kcheck.scene.validate import Problems

    def former_direction(problems: Problems, vector: list[float]) -> Any:
        v = np.asarray(vector, dtype=float)
        largest = float(np.abs(v).max())
        if largest == 0.0:
            problems.add(("d",), f"expected a non-zero vector for it, got {vector}")
            return None
        if not MIN_DIRECTION <= largest <= MAX_DIRECTION:
            problems.add(("d",), f"it: bad {vector}")
            return None
        return unit(v)

    def former_coordinates(problems: Problems, vector: list[float], scale: float) -> Any:
        v = np.asarray(vector, dtype=float) * scale
        if not np.all(np.abs(v) <= LIMITS["coordinate"].high):
            problems.add(("c",), f"coordinates {vector}")
            return None
        return v

    parts = [0.0, -0.0, 1.0, -2.5, 1e-12, 1e12, 1e300, math.nan, math.inf, -math.inf, 3]
    rng = np.random.default_rng(4)
    vectors = [[float(x) for x in rng.choice(parts, 3)] for _ in range(3000)]
    vectors += [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [math.nan, 1.0, 0.0], [1.0, math.nan, 0.0]]
    for vector in vectors:
        mine, former = Problems(Path("x"), {}), Problems(Path("x"), {})
        with np.errstate(invalid="ignore", over="ignore"):
            got, want = mine.direction(("d",), vector, "it"), former_direction(former, vector)
        assert (got is None) == (want is None) and len(mine.errors) == len(former.errors)
        if got is not None:
            assert got.tobytes() == want.tobytes()
        for scale in (1.0, 1e-3):
            mine, former = Problems(Path("x"), {}), Problems(Path("x"), {})
            with np.errstate(invalid="ignore", over="ignore"):
                got = mine.coordinates(("c",), vector, scale)
                want = former_coordinates(former, vector, scale)
            assert (got is None) == (want is None)
            if got is not None:
                assert got.tobytes() == want.tobytes()
