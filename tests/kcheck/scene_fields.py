"""The acceptor's field table (:data:`kcheck.scene.accept.FIELDS`) derived from the pydantic
scene models. ``python -m tests.kcheck.scene_fields`` prints it, to paste into
``kcheck/scene/accept.py`` when a model changes."""

from __future__ import annotations

import typing
from typing import Any

import annotated_types as at
from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic.functional_validators import BeforeValidator
from pydantic_core import PydanticUndefined

from kcheck.scene import models as M


def _bounds(meta: list[Any]) -> tuple[Any, Any, Any, Any]:
    ge = gt = le = lt = None
    for m in meta:
        if isinstance(m, at.Ge):
            ge = m.ge
        elif isinstance(m, at.Gt):
            gt = m.gt
        elif isinstance(m, at.Le):
            le = m.le
        elif isinstance(m, at.Lt):
            lt = m.lt
    return ge, gt, le, lt


def _lengths(meta: list[Any]) -> tuple[Any, Any]:
    lo = hi = None
    for m in meta:
        if isinstance(m, at.MinLen):
            lo = m.min_length
        elif isinstance(m, at.MaxLen):
            hi = m.max_length
    return lo, hi


KNOWN_META = (at.Ge, at.Gt, at.Le, at.Lt, at.MinLen, at.MaxLen)


def spec(annotation: Any, meta: list[Any], models: dict, discriminator: Any = None) -> Any:
    meta = list(meta)
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        base, *extra = typing.get_args(annotation)
        more: list[Any] = []
        disc = discriminator
        for e in extra:
            if isinstance(e, FieldInfo):
                more.extend(e.metadata)
                if e.discriminator is not None:
                    disc = e.discriminator
            elif type(e).__name__ == "Discriminator":
                disc = e
            elif type(e).__name__ in ("Tag", "WithJsonSchema"):
                continue
            else:
                more.append(e)
        return spec(base, meta + more, models, disc)
    for m in meta:
        if type(m).__name__ == "Discriminator":
            discriminator = m
    meta = [m for m in meta if type(m).__name__ != "Discriminator"]
    befores = [m for m in meta if isinstance(m, BeforeValidator)]
    rest = [m for m in meta if not isinstance(m, BeforeValidator)]
    for m in rest:
        assert isinstance(m, KNOWN_META), m
    if befores:
        assert annotation is str and befores[0].func is M._material_name
        return ("material", *_lengths(rest))
    if annotation is float:
        return ("float", *_bounds(rest))
    if annotation is int:
        return ("int", *_bounds(rest))
    if annotation is bool:
        assert not rest
        return ("bool",)
    if annotation is str:
        return ("str", *_lengths(rest))
    if annotation is type(None):
        return ("none",)
    if annotation is Any:
        return ("any",)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        assert not rest
        walk(annotation, models)
        return ("model", annotation.__name__)
    if origin is typing.Literal:
        return ("literal", typing.get_args(annotation))
    if origin is list:
        (item,) = typing.get_args(annotation)
        return ("list", spec(item, [], models), *_lengths(rest))
    if origin is dict:
        key, value = typing.get_args(annotation)
        assert not rest
        return ("mapping", spec(key, [], models), spec(value, [], models))
    if origin in (typing.Union, __import__("types").UnionType):
        args = typing.get_args(annotation)
        if discriminator is None:
            if rest:  # constraints of an optional field apply to its value (pydantic)
                assert len(args) == 2 and args[1] is type(None), annotation
                return ("union", (spec(args[0], rest, models), ("none",)))
            return ("union", tuple(spec(a, [], models) for a in args))
        if isinstance(discriminator, str):
            tags = []
            for a in args:
                walk(a, models)
                (tag,) = typing.get_args(a.model_fields[discriminator].annotation)
                tags.append((tag, a.__name__))
            return ("tagged", discriminator, tuple(tags))
        branches = []
        for a in args:
            tag = next(e.tag for e in typing.get_args(a)[1:] if type(e).__name__ == "Tag")
            branches.append((tag, spec(a, [], models)))
        return ("pick", discriminator.discriminator.__name__, tuple(branches))
    raise AssertionError(f"unknown annotation {annotation!r}")


def walk(model: type[BaseModel], models: dict) -> None:
    if model.__name__ in models:
        return
    models[model.__name__] = None
    fields = []
    for name, f in model.model_fields.items():
        s = spec(f.annotation, f.metadata, models, f.discriminator)
        if f.default_factory is not None:
            value = f.default_factory()
            default = (
                ("model", type(value).__name__)
                if isinstance(value, BaseModel)
                else ("value", value)
            )
        elif f.default is PydanticUndefined:
            default = ("required",)
        else:
            default = ("value", f.default)
        fields.append((name, s, default))
    assert model.model_config.get("extra") == "forbid" and model.model_config.get("strict")
    assert model.model_config.get("allow_inf_nan") is False
    validators = model.__pydantic_decorators__
    # The one field validator (the format version: the integer 1, not 1.0 or true) is what a
    # strict literal is in the acceptor; any other validator is not in its vocabulary.
    assert set(validators.field_validators) <= {"_integer_version"}, model
    assert not validators.model_validators and not validators.model_serializers, model
    models[model.__name__] = tuple(fields)


def derive() -> dict:
    models: dict = {}
    walk(M.SceneModel, models)
    return models


if __name__ == "__main__":
    import pprint

    pprint.pprint(derive(), width=96, sort_dicts=False)
