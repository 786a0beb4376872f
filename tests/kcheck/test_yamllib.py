"""kcheck.scene.yamllib: PyYAML with its patterns compiled on first use."""

from __future__ import annotations

import copy
import pickle
import re
import subprocess
import sys

import pytest

from kcheck.scene.yamllib import NON_PRINTABLE, _OnFirstUse, yaml


def test_the_pattern_is_pyyamls_and_finds_the_same_characters():
    # The stand-in answers as the compiled pattern, compiled from the same text.
    assert yaml.reader.Reader.NON_PRINTABLE.pattern == NON_PRINTABLE
    text = "ok\x01 \x7f\ufffe\U0001f600\t"
    found = [m.group() for m in re.finditer(NON_PRINTABLE, text)]
    assert [yaml.reader.Reader.NON_PRINTABLE.search(text).group()] == found[:1]
    assert found == ["\x01", "\x7f", "\ufffe"]


def test_the_pure_python_reader_still_refuses_a_control_character():
    with pytest.raises(yaml.reader.ReaderError):
        yaml.load("a: \x01", Loader=yaml.SafeLoader)  # noqa: S506 - the pure-Python loader


def test_resolver_and_constructor_answer_as_before():
    # Implicit tags (YAML 1.1: dates, booleans, hex) and the timestamp, through the deferred
    # patterns, against libyaml's loader; and what a dump quotes.
    text = "a: 2001-12-14\nb: yes\nc: 1e3\nd: 0x10\ne: 2001-12-14t21:59:43.10-05:00\n"
    pure = yaml.load(text, Loader=yaml.SafeLoader)  # noqa: S506
    assert pure["a"].isoformat() == "2001-12-14" and pure["b"] is True and pure["d"] == 16
    assert pure["c"] == "1e3" and pure["e"].utcoffset().total_seconds() == -5 * 3600
    if yaml.__with_libyaml__:
        assert pure == yaml.load(text, Loader=yaml.CSafeLoader)  # noqa: S506
    assert yaml.safe_dump({"x": "yes", "y": "12", "z": "plain"}) == "x: 'yes'\ny: '12'\nz: plain\n"


def test_importing_it_defers_only_yamls_patterns_and_leaves_re_as_it_was():
    code = (
        "import re; c = re.compile; from kcheck.scene.yamllib import yaml; "
        "print(re.compile is c, type(yaml.reader.Reader.NON_PRINTABLE).__name__, "
        "type(yaml.resolver.Resolver.yaml_implicit_resolvers['t'][0][1]).__name__, "
        "isinstance(re.compile('x'), re.Pattern))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "_OnFirstUse", "_OnFirstUse", "True"]


def test_a_deferred_pattern_copied_or_pickled_is_the_compiled_pattern():
    # PyYAML's resolver keeps (tag, pattern) pairs; a copied or pickled resolver copies them.
    # A stand-in of its own: in a session where PyYAML was imported before kcheck's module,
    # the resolver holds compiled patterns (nothing was deferred).
    deferred = _OnFirstUse("true|True|TRUE|false|False|FALSE", re.X)
    resolvers = {"t": [("tag:yaml.org,2002:bool", deferred)]}
    compiled = re.compile("true|True|TRUE|false|False|FALSE", re.X)
    for made in (
        copy.copy(deferred),
        copy.deepcopy(deferred),
        pickle.loads(pickle.dumps(deferred)),
        copy.deepcopy(resolvers)["t"][0][1],
    ):
        assert made == compiled and made.match("true") is not None
    fresh = object.__new__(type(deferred))  # no __init__: its slots unset
    with pytest.raises(AttributeError):
        fresh.match  # noqa: B018
    with pytest.raises(AttributeError):
        fresh.__deepcopy__  # noqa: B018
