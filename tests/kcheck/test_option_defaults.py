"""Option defaults are copied as ``copy.deepcopy`` copies them (the atomic ones returned as
they are, without the call: a scene asks for some sixty, issue 24)."""

from __future__ import annotations

import copy

from kcheck.plugin.options import _copied


def test_copied_defaults_are_deepcopys():
    for value in (0, -3, 1.5, float("nan"), True, None, "text", ""):
        assert _copied(value) is copy.deepcopy(value)
    for value in ([1.0, [2.0]], {"a": [1]}, (1.0, [2.0])):
        copied = _copied(value)
        assert copied == value and copied is not value
    nested = {"a": [1]}
    _copied(nested)["a"].append(2)
    assert nested == {"a": [1]}  # a fresh copy: the default is not shared
