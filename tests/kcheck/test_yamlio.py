"""YAML reading: YAML 1.2 numbers and booleans, duplicate keys, line numbers."""

from __future__ import annotations

import pytest

from kcheck.errors import SceneError
from kcheck.scene.yamlio import HAVE_LIBYAML, load_yaml, read_yaml


def test_exponent_without_dot_is_a_number(tmp_path):
    # PyYAML (YAML 1.1) reads `1e3` as the string "1e3" (yaml/pyyaml#173).
    path = tmp_path / "a.yaml"
    path.write_text("a: 1e3\nb: -2.5E-3\nc: 7\nd: '1e3'\n")
    data, _ = load_yaml(path)
    assert data == {"a": 1000.0, "b": -0.0025, "c": 7, "d": "1e3"}
    assert isinstance(data["c"], int)


def test_yaml11_booleans_stay_strings(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("a: yes\nb: on\nc: true\nd: no\n")
    data, _ = load_yaml(path)
    assert data == {"a": "yes", "b": "on", "c": True, "d": "no"}


def test_duplicate_key_names_both_lines(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("load:\n  magnitude: 1\n  magnitude: 2\n")
    with pytest.raises(SceneError) as info:
        load_yaml(path)
    err = info.value
    assert err.line == 3 and err.field == "load.magnitude"
    assert "first given on line 2" in err.message


def test_lines_of_nested_fields(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("supports:\n  - name: a\n    normal: [1, 0, 0]\n  - name: b\n")
    _, lines = load_yaml(path)
    assert lines[("supports", 0, "normal")] == 3
    assert lines[("supports", 1)] == 4


def test_syntax_error_gives_line(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("a: [1, 2\nb: 3\n")
    with pytest.raises(SceneError) as info:
        load_yaml(path)
    assert info.value.line is not None and "YAML syntax error" in info.value.message


def test_empty_file(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("# nothing\n")
    with pytest.raises(SceneError, match="empty"):
        load_yaml(path)


@pytest.mark.parametrize("backend", ["c", "python"] if HAVE_LIBYAML else ["python"])
def test_control_character_is_located(tmp_path, backend):
    # Fuzz finding (issue 13): a control character gave "YAML error: ... position 518" with
    # no line. Non-ASCII text before it: libyaml counts bytes, PyYAML characters.
    path = tmp_path / "a.yaml"
    path.write_text("name: Größe\nfriction: 0.\x011\n", encoding="utf-8")
    with pytest.raises(SceneError) as info:
        read_yaml(path, backend=backend)
    err = info.value
    assert (err.line, err.column) == (2, 13)
    assert "U+0001" in err.message and "position" not in err.message


def test_a_pipe_or_device_is_refused_without_blocking(tmp_path):
    # Fuzz finding (issue 13): `kcheck expand pipe` hung opening a FIFO nobody writes to.
    import os

    pipe = tmp_path / "pipe.kcheck.yaml"
    os.mkfifo(pipe)
    for path in (pipe, "/dev/zero"):
        with pytest.raises(SceneError) as info:
            read_yaml(path)
        assert "not a regular file" in info.value.message


def test_an_os_error_is_said_in_kchecks_words(tmp_path):
    # Not the C library's strerror text, whose wording is the platform's.
    path = tmp_path / "missing.yaml"
    with pytest.raises(SceneError) as info:
        read_yaml(path)
    assert info.value.path == str(path) and info.value.line is None
    assert info.value.message == "cannot read the file: no such file or folder"


def test_plain_scalar_shortcut_answers_as_the_patterns():
    # Texts whose first character no core-schema pattern accepts are returned as they are;
    # compared with the patterns applied in full, in the schema's order (the function before
    # the shortcut).
    import math

    from kcheck.scene import yamlcompose as yc

    def by_patterns(text):
        if yc._NULL.match(text):
            return None
        if yc._BOOL.match(text):
            return text[0] in "tT"
        if yc._INT10.match(text):
            return int(text)
        if yc._INT8.match(text):
            return int(text[2:], 8)
        if yc._INT16.match(text):
            return int(text[2:], 16)
        if yc._FLOAT.match(text):
            return float(text)
        if yc._INF.match(text):
            return -math.inf if text[0] == "-" else math.inf
        if yc._NAN.match(text):
            return math.nan
        return text

    texts = ["", "~", "null", "Null", "true", "False", "12", "-3", "+4", "0o7", "0x1F", ".5",
             "1e3", ".inf", "-.Inf", ".nan", "name", "y1", "block.stl", "aluminium", "mm",
             "Ünïcode", " lead", "_x", "#", "@", "Zed", "0", "n", "t", "f", "-", "+", "."]  # fmt: skip  # noqa: E501
    for text in texts:
        got, expected = yc.plain_scalar(text, 0, 0), by_patterns(text)
        assert type(got) is type(expected)
        assert repr(got) == repr(expected)


@pytest.mark.parametrize("backend", ["c", "python"] if HAVE_LIBYAML else ["python"])
def test_a_key_read_as_a_value_is_named_where_it_is(tmp_path, backend):
    """A mapping key YAML reads as a boolean or number is refused, naming the mapping it is
    in (the top level, or its field path) and its line."""
    path = tmp_path / "a.yaml"
    path.write_text("name: x\ntrue: 1\n")
    with pytest.raises(SceneError) as info:
        read_yaml(path, backend=backend)
    assert "`true` (in the top level) is read as a boolean" in info.value.message
    assert info.value.line == 2
    path.write_text("load:\n  magnitude: 1\n  12: 2\n")
    with pytest.raises(SceneError) as info:
        read_yaml(path, backend=backend)
    assert "`12` (in load) is read as an integer" in info.value.message
    assert info.value.line == 3


@pytest.mark.parametrize("backend", ["c", "python"] if HAVE_LIBYAML else ["python"])
def test_the_value_limit_counts_scalars_and_collections(tmp_path, backend):
    """``max_values`` counts every scalar and collection (keys included): a document with
    exactly that many is read, one more is refused at the value that passes it."""
    from kcheck.scene.yamlio import YamlLimits

    path = tmp_path / "a.yaml"
    path.write_text("a: 1\nb: [2, 3]\n")  # the mapping, a, 1, b, the list, 2, 3: seven
    assert read_yaml(path, limits=YamlLimits(max_values=7), backend=backend).data == {
        "a": 1,
        "b": [2, 3],
    }
    with pytest.raises(SceneError) as info:
        read_yaml(path, limits=YamlLimits(max_values=6), backend=backend)
    assert "holds more than 6 values" in info.value.message
    assert info.value.line == 2
