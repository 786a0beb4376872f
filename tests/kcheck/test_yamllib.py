"""kcheck.scene.yamllib: PyYAML with its pure-Python reader's pattern compiled on first use."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from kcheck.scene.yamllib import NON_PRINTABLE, yaml


def test_the_pattern_is_pyyamls_and_finds_the_same_characters():
    # The stand-in replaces this very pattern, and answers as the compiled one.
    assert yaml.reader.Reader.NON_PRINTABLE.pattern == NON_PRINTABLE
    text = "ok\x01 \x7f\ufffe\U0001f600\t"
    found = [m.group() for m in re.finditer(NON_PRINTABLE, text)]
    assert [yaml.reader.Reader.NON_PRINTABLE.search(text).group()] == found[:1]
    assert found == ["\x01", "\x7f", "\ufffe"]


def test_the_pure_python_reader_still_refuses_a_control_character():
    with pytest.raises(yaml.reader.ReaderError):
        yaml.load("a: \x01", Loader=yaml.SafeLoader)  # noqa: S506 - the pure-Python loader


def test_importing_it_compiles_every_other_pattern_and_leaves_re_as_it_was():
    code = (
        "import re; c = re.compile; from kcheck.scene.yamllib import yaml; "
        "print(re.compile is c, type(yaml.reader.Reader.NON_PRINTABLE).__name__, "
        "isinstance(yaml.resolver.Resolver.yaml_implicit_resolvers['t'][0][1], re.Pattern))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "_OnFirstUse", "True"]
