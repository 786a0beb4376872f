"""Check options without pydantic on the start-up path (issue 24, kcheck.plugin.options).

Defaults are built without pydantic and must equal what the derived pydantic model makes of
no options; given options go through that model (its errors, its values), and come back as
the check's own class.
"""

from __future__ import annotations

import copy
import pickle

import pytest
from pydantic import Field as PydanticField
from pydantic import ValidationError

from kcheck.plugin import Field, Options, load_checks, model_validator


def _built_in() -> list[type[Options]]:
    return [lc.check.options for lc in load_checks()]


def test_defaults_without_pydantic_equal_the_pydantic_models_defaults():
    classes = _built_in()
    assert len(classes) >= 8
    for cls in classes:
        light = cls.model_validate({})
        derived = cls._from_pydantic(cls.pydantic_model().model_validate({}))
        assert type(light) is cls and light == derived, cls
        assert light.model_fields_set == set()


class _Inner(Options):
    radius: float = Field(gt=0)


class _Sample(Options):
    """A sample."""

    count: int = Field(3, ge=1, le=10, description="how many")
    scale: float | None = None
    inner: dict[str, _Inner] = Field({})
    legacy: float = PydanticField(0.5, ge=0)  # a check written against pydantic's Field

    @model_validator(mode="after")
    def _not_both(self) -> _Sample:
        if self.scale is not None and self.inner:
            raise ValueError("give scale or inner, not both")
        return self


def test_given_options_are_validated_by_the_derived_model():
    made = _Sample(count=4, inner={"a": {"radius": 2}})
    assert isinstance(made.inner["a"], _Inner)
    assert (made.count, made.inner["a"].radius, made.legacy) == (4, 2.0, 0.5)
    assert made.model_fields_set == {"count", "inner"}
    kinds = {
        "count": ({"count": 11}, "less_than_equal"),
        "scale": ({"scale": "1"}, "float_type"),
        "inner": ({"inner": {"a": {}}}, "missing"),
        "legacy": ({"legacy": -1.0}, "greater_than_equal"),
        "extra": ({"colour": 1}, "extra_forbidden"),
        "after": ({"scale": 1.0, "inner": {"a": {"radius": 1}}}, "value_error"),
    }
    for what, (raw, kind) in kinds.items():
        with pytest.raises(ValidationError) as info:
            _Sample.model_validate(raw)
        assert info.value.errors()[0]["type"] == kind, what
    schema = _Sample.model_json_schema()
    assert schema["properties"]["count"]["description"] == "how many"
    assert schema["properties"]["count"]["maximum"] == 10


def test_options_are_frozen_values():
    made = _Sample(count=2)
    with pytest.raises(TypeError):
        made.count = 3
    assert copy.deepcopy(made) == made and pickle.loads(pickle.dumps(made)) == made
    assert copy.deepcopy(made).model_fields_set == {"count"}
    assert made.model_copy(update={"count": 5}).count == 5 and made.count == 2
    assert made.model_dump() == {"count": 2, "scale": None, "inner": {}, "legacy": 0.5}
    assert hash(_Inner(radius=1)) == hash(_Inner(radius=1.0))  # as pydantic: by the fields
