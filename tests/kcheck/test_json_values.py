"""``to_json_value``'s exact-type shortcuts (the JSON report's time, issue 24) give what the
general conversion it had before gives (``_reference``, a copy of it recursing into itself),
on every kind of value a result holds."""

from __future__ import annotations

import enum
import json
import math
from collections.abc import Mapping
from types import MappingProxyType

import numpy as np

from kcheck.result import Status, to_json_value


def _reference(value: object) -> object:
    """``to_json_value`` as it was before the shortcuts (numpy's ``tolist`` first)."""
    tolist = getattr(value, "tolist", None)
    if tolist is not None:
        value = tolist()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {str(k): _reference(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_reference(v) for v in value]
    if isinstance(value, enum.Enum):
        return value.value
    return value


class _Word(str, enum.Enum):
    A = "a"


class _Float(float):
    pass


def _values() -> list[object]:
    leaves: list[object] = [
        0.0, -0.0, 1.5, math.nan, math.inf, -math.inf, 3, -7, True, False, None, "text", "",
        np.float64(2.5), np.float64(math.nan), np.int64(4), np.bool_(True), np.array([1.0, np.inf]),
        np.arange(4).reshape(2, 2), Status.PASS, _Word.A, _Float(1.25), _Float(math.inf),
    ]  # fmt: skip
    nested: list[object] = [
        {"a": 1.0, 2: [math.nan, (1, 2.0)], "b": MappingProxyType({"c": np.float64(1.0)})},
        MappingProxyType({"x": [{"y": math.inf}], "z": (None, "w")}),
        [(1.0, 2.0), (3.0, -math.inf)],
        ((np.array([0.5]), {"k": _Word.A}),),
    ]
    return leaves + nested


def test_shortcuts_equal_the_general_path():
    for value in _values():
        fast, general = to_json_value(value), _reference(value)
        assert json.dumps(fast) == json.dumps(general)
        assert type(fast) is type(general)
    # the non-finite floats are null, as the JSON format says
    assert to_json_value([math.nan, math.inf, 1.0]) == [None, None, 1.0]
