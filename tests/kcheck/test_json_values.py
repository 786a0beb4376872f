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


def _former_is_ranges(value: object) -> bool:
    """``_is_ranges`` as it was before its loop (``all`` of generators)."""
    return isinstance(value, (list, tuple)) and all(
        isinstance(r, (list, tuple))
        and len(r) == 2
        and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in r)
        for r in value
    )


def _former_details_json(details: Mapping[str, object]) -> object:
    """``details_json`` as it was: every value converted, then the ranges in degrees
    replaced in place."""
    from kcheck.result import ranges_json

    out = to_json_value(details)
    assert isinstance(out, dict)
    for key, value in details.items():
        if key.endswith("_deg") and value and _former_is_ranges(value):
            out[key] = ranges_json(value)  # type: ignore[arg-type]
    return out


def test_details_in_one_pass_equal_the_former_two():
    from kcheck.result import _is_ranges, details_json

    ranges: list[object] = [
        [(350.0, 10.0), (20.0, 30.0)], ((0.0, 360.0),), [[-10.0, 5.0]], [(1, 2)], [],
        [(True, 2.0)], [(1.0, 2.0, 3.0)], [(np.float64(400.0), 2.0)], [(np.int64(1), 2.0)],
        [(1.0, "2")], "text", 5.0, None, [(math.nan, 1.0)], [1.0, 2.0],
    ]  # fmt: skip
    for value in ranges:
        assert _is_ranges(value) == _former_is_ranges(value)
    details = {f"k{i}{suffix}": v for i, v in enumerate(ranges) for suffix in ("_deg", "")}
    details.update({f"v{i}": v for i, v in enumerate(_values())})
    for mapping in (details, MappingProxyType(details), {}):
        fast, former = details_json(mapping), _former_details_json(mapping)
        assert json.dumps(fast) == json.dumps(former)
        assert list(fast) == list(former)  # the same keys in the same order
