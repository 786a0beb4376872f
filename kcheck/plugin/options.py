"""A check's options without pydantic on the start-up path (issue 24).

A check declares its options as before, as annotated class attributes with
:func:`Field` (the same arguments as pydantic's ``Field``) on an :class:`Options` subclass.
The class itself is plain Python: a scene that sets no options gets the defaults without
pydantic being imported. Options a scene or the configuration sets are validated by a pydantic
model derived from the same declarations (strict, unknown keys refused, frozen: the old
``Options`` base's configuration), built on first use; its error records are kcheck's error
wording, exactly as when the options were pydantic models, and the values it accepted become
an instance of the check's own class (so ``isinstance`` and the class's methods work).
Declarations written with pydantic's own ``Field`` and validators work too (imported by that
check's module, then).

Names in the annotations are looked up in the check's module, then among the scene's field
types (:mod:`kcheck.scene.models`, e.g. ``MaterialName``), which a check imports only for type
checking.
"""

from __future__ import annotations

import copy
import functools
import operator
import sys
import typing
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

__all__ = ["Options", "Field", "model_validator"]

_MISSING: Any = type("Missing", (), {"__repr__": lambda self: "PydanticUndefined"})()


class _FieldSpec:
    """What :func:`Field` was given; a pydantic ``Field`` is made of it when needed."""

    __slots__ = ("default", "default_factory", "kwargs")

    def __init__(self, default: Any, default_factory: Any, kwargs: dict[str, Any]) -> None:
        self.default = default
        self.default_factory = default_factory
        self.kwargs = kwargs


def Field(default: Any = _MISSING, *, default_factory: Any = None, **kwargs: Any) -> Any:  # noqa: N802
    """A field of an :class:`Options` subclass: pydantic's ``Field`` arguments (``ge``, ``le``,
    ``min_length``, ``description``, ...), read by pydantic only when options are given."""
    return _FieldSpec(default, default_factory, kwargs)


def model_validator(*, mode: str) -> Callable[[Callable[..., Any]], Any]:
    """Mark a method that checks the whole options after their fields (pydantic's
    ``model_validator(mode="after")``): it raises ``ValueError`` with kcheck's message."""
    if mode != "after":
        raise ValueError("only mode='after' validators are supported on kcheck Options")

    def mark(function: Callable[..., Any]) -> Any:
        function.__kcheck_after__ = True  # type: ignore[attr-defined]
        return function

    return mark


def _is_pydantic_field(value: Any) -> bool:
    return type(value).__name__ == "FieldInfo" and type(value).__module__.startswith("pydantic")


def _default_of(spec: Any) -> tuple[bool, Any]:
    """Whether a field has a default, and a fresh copy of it."""
    if isinstance(spec, _FieldSpec):
        if spec.default_factory is not None:
            return True, spec.default_factory()
        return spec.default is not _MISSING, _copied(spec.default)
    if _is_pydantic_field(spec):
        if spec.default_factory is not None:
            return True, spec.default_factory()
        required = spec.is_required()
        return not required, None if required else copy.deepcopy(spec.default)
    return True, _copied(spec)


#: Types whose values ``copy.deepcopy`` returns as they are (immutable, atomic).
_ATOMIC = frozenset({int, float, str, bool, type(None)})


def _copied(value: Any) -> Any:
    """``copy.deepcopy(value)``; an atomic value as it is, as deepcopy would return it (a
    scene's options ask for some sixty defaults, most of them numbers)."""
    return value if type(value) in _ATOMIC else copy.deepcopy(value)


class _ClassAttribute:
    """An attribute computed from the class (pydantic's ``model_fields`` is one)."""

    def __init__(self, get: Callable[[Any], Any]) -> None:
        self.get = get

    def __get__(self, obj: Any, cls: Any) -> Any:
        return self.get(cls)


class Options:
    """Base of a check's options (the scene's ``checks: {id: {...}}``); unknown keys fail."""

    __slots__ = ("__dict__", "model_fields_set")  # the fields in __dict__, and nothing else
    #: name -> what the class body gave (a :func:`Field`, a pydantic ``Field`` or a default)
    _fields: ClassVar[dict[str, Any]] = {}
    _annotations: ClassVar[dict[str, Any]] = {}
    _extras: ClassVar[dict[str, Any]] = {}
    _pydantic: ClassVar[Any] = None
    model_fields_set: set[str]

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        fields: dict[str, Any] = {}
        annotations: dict[str, Any] = {}
        extras: dict[str, Any] = {}
        for base in reversed(cls.__mro__[1:]):
            if issubclass(base, Options):
                fields.update(base._fields)
                annotations.update(base._annotations)
                extras.update(base._extras)
        for name, annotation in cls.__dict__.get("__annotations__", {}).items():
            if typing.get_origin(annotation) is ClassVar or (
                isinstance(annotation, str) and annotation.startswith(("ClassVar", "typing.Cl"))
            ):
                continue
            fields[name] = cls.__dict__.get(name, _FieldSpec(_MISSING, None, {}))
            annotations[name] = annotation
            if name in cls.__dict__:
                delattr(cls, name)
        for name, value in list(cls.__dict__.items()):
            # pydantic validators of a check written against pydantic (decorator proxies)
            if getattr(value, "__kcheck_after__", False) or type(value).__name__ == (
                "PydanticDescriptorProxy"
            ):
                extras[name] = value
        cls._fields, cls._annotations, cls._extras = fields, annotations, extras
        cls._pydantic = None

    def __init__(self, **data: Any) -> None:
        made = type(self).model_validate(data)
        object.__setattr__(self, "__dict__", made.__dict__)
        object.__setattr__(self, "model_fields_set", made.model_fields_set)

    # --- pydantic's model API, as far as checks and kcheck use it ---------------------------

    @classmethod
    def model_validate(cls, obj: Any) -> Any:
        """Validated options of a mapping (pydantic's ``ValidationError`` when wrong)."""
        if isinstance(obj, Mapping) and not obj:
            made = cls._defaults()
            if made is not None:
                return made
        return cls._from_pydantic(cls.pydantic_model().model_validate(obj))

    @classmethod
    def _defaults(cls) -> Any:
        """The options nobody set, without pydantic; None when only pydantic can say (a
        required field, a validator that refuses the defaults)."""
        values = {}
        for name, spec in cls._fields.items():
            has, value = _default_of(spec)
            if not has:
                return None
            values[name] = value
        made = cls._build(values, set())
        for check in cls._extras.values():
            if not getattr(check, "__kcheck_after__", False):
                return None  # a pydantic validator: pydantic runs it
            try:
                check(made)
            except ValueError:
                return None
        return made

    @classmethod
    def _build(cls, values: dict[str, Any], given: set[str]) -> Any:
        made = object.__new__(cls)
        object.__setattr__(made, "__dict__", values)
        object.__setattr__(made, "model_fields_set", given)
        return made

    @classmethod
    def _from_pydantic(cls, model: Any) -> Any:
        values = {name: _light(getattr(model, name)) for name in cls._fields}
        return cls._build(values, set(model.model_fields_set))

    @classmethod
    def pydantic_model(cls) -> Any:
        """The pydantic model of these options (built once, on first use)."""
        if cls.__dict__.get("_pydantic") is None:
            cls._pydantic = _derive(cls)
        return cls._pydantic

    @classmethod
    def model_json_schema(cls, *args: Any, **kwargs: Any) -> dict[str, Any]:
        """The options' JSON Schema (pydantic's)."""
        return cls.pydantic_model().model_json_schema(*args, **kwargs)

    model_fields = _ClassAttribute(lambda cls: cls.pydantic_model().model_fields)

    def _pydantic_instance(self) -> Any:
        twin = type(self).pydantic_model()
        values = {k: _heavy(v) for k, v in self.__dict__.items()}
        return twin.model_construct(_fields_set=set(self.model_fields_set), **values)

    def model_dump(self, **kwargs: Any) -> dict[str, Any]:
        """The options as plain data (pydantic's ``model_dump``)."""
        return self._pydantic_instance().model_dump(**kwargs)

    def model_copy(self, *, update: Mapping[str, Any] | None = None, deep: bool = False) -> Any:
        """A copy with some fields replaced, not validated (pydantic's ``model_copy``)."""
        values = copy.deepcopy(self.__dict__) if deep else dict(self.__dict__)
        values.update(update or {})
        return type(self)._build(values, set(self.model_fields_set) | set(update or {}))

    def __setattr__(self, name: str, value: Any) -> None:
        raise TypeError(f"{type(self).__name__} is frozen: options are not changed once read")

    def __delattr__(self, name: str) -> None:
        raise TypeError(f"{type(self).__name__} is frozen: options are not changed once read")

    def __reduce__(self) -> tuple[Any, ...]:  # copies and pickles (frozen: no setattr)
        return (_rebuild, (type(self), self.__dict__, self.model_fields_set))

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and other.__dict__ == self.__dict__

    def __hash__(self) -> int:
        return hash((type(self), *self.__dict__.values()))

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in self.__dict__.items())
        return f"{type(self).__name__}({fields})"


def _rebuild(cls: type[Options], values: dict[str, Any], given: set[str]) -> Any:
    return cls._build(dict(values), set(given))


def _light(value: Any) -> Any:
    """A value the pydantic model accepted, with derived models back as their Options."""
    light = getattr(type(value), "__kcheck_options__", None)
    if light is not None:
        return light._from_pydantic(value)
    if isinstance(value, list):
        return [_light(v) for v in value]
    if isinstance(value, dict):
        return {k: _light(v) for k, v in value.items()}
    return value


def _heavy(value: Any) -> Any:
    if isinstance(value, Options):
        return value._pydantic_instance()
    if isinstance(value, list):
        return [_heavy(v) for v in value]
    if isinstance(value, dict):
        return {k: _heavy(v) for k, v in value.items()}
    return value


def _swap(annotation: Any) -> Any:
    """An annotation with every Options class replaced by its pydantic model."""
    if isinstance(annotation, type) and issubclass(annotation, Options):
        return annotation.pydantic_model()
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is None or not args or origin is typing.Literal:
        return annotation
    swapped = tuple(_swap(a) for a in args[:1]) + (
        args[1:] if origin is typing.Annotated else tuple(_swap(a) for a in args[1:])
    )
    if swapped == args:
        return annotation
    if origin is typing.Annotated:
        return annotation.copy_with((swapped[0],))  # the same metadata
    if origin is typing.Union or type(annotation).__name__ == "UnionType":
        return functools.reduce(operator.or_, swapped)
    return origin[swapped]


def _resolve(cls: type[Options], name: str, annotation: Any) -> Any:
    if not isinstance(annotation, str):
        return annotation
    owner = next(c for c in cls.__mro__ if name in c.__dict__.get("__annotations__", {}))
    module = sys.modules.get(owner.__module__)
    from kcheck.scene import models  # scene field types (MaterialName), for type checking only

    namespace = {**vars(models), **(vars(module) if module is not None else {})}
    return eval(annotation, namespace)  # noqa: S307 - the check's own annotation


def _derive(cls: type[Options]) -> Any:
    """The pydantic model of an Options class, from its declarations."""
    import pydantic

    namespace: dict[str, Any] = {
        "__module__": cls.__module__,
        "__qualname__": cls.__qualname__,
        "__doc__": cls.__doc__,
        "model_config": pydantic.ConfigDict(extra="forbid", strict=True, frozen=True),
        "__annotations__": {},
    }
    for name, spec in cls._fields.items():
        namespace["__annotations__"][name] = _swap(_resolve(cls, name, cls._annotations[name]))
        if isinstance(spec, _FieldSpec):
            if spec.default_factory is not None:
                field = pydantic.Field(default_factory=spec.default_factory, **spec.kwargs)
            elif spec.default is _MISSING:
                field = pydantic.Field(**spec.kwargs)
            else:
                field = pydantic.Field(spec.default, **spec.kwargs)
            namespace[name] = field
        else:
            namespace[name] = spec
    for name, value in cls._extras.items():
        if getattr(value, "__kcheck_after__", False):
            namespace[name] = _after(cls, value)
        else:
            namespace[name] = value
    model = type(cls.__name__, (pydantic.BaseModel,), namespace)
    model.__kcheck_options__ = cls  # type: ignore[attr-defined]
    return model


def _after(cls: type[Options], check: Callable[..., Any]) -> Any:
    import pydantic

    def run(self: Any) -> Any:
        check(cls._from_pydantic(self))
        return self

    run.__name__ = check.__name__
    return pydantic.model_validator(mode="after")(run)
