"""The scene file's fields accepted without pydantic (issue 24: start-up).

A valid scene file, the common case, is read here: :data:`FIELDS` declares every model of
:mod:`kcheck.scene.models` in a small vocabulary (strict numbers with their bounds, text with
its length, literals, optional values, lists of bounded length, nested records, tagged
unions; unknown keys refused), and :func:`accept` walks a document against it, building
:class:`Record` values that read like the models (the same attributes and
``model_fields_set``). Whatever it does not accept exactly — any mistake, anything unusual —
goes to the pydantic models, whose error records are the only source of kcheck's error
wording (:mod:`kcheck.scene.validate`), so no message or location depends on this module.

:data:`FIELDS` is derived from the pydantic models (``python -m tests.kcheck.scene_fields``
prints it); ``tests/kcheck/test_scene_accept.py`` asserts that it still is, and that the
acceptor never accepts what pydantic refuses and builds the values pydantic builds.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping
from typing import Any

__all__ = [
    "FIELDS",
    "COUPLING_TYPES",
    "Record",
    "accept",
    "is_model",
    "friction_kind",
    "coefficient_kind",
]

COUPLING_TYPES = (
    "ball-vee",
    "ball-cylinders",
    "ball-sphere",
    "ball-trihedral",
    "ball-cone",
    "ball-flat",
)


def friction_kind(value: Any) -> str:
    """Which branch a ``friction`` value is: a number, a range or a static/kinetic pair."""
    if isinstance(value, dict):
        pair = {"static", "kinetic"} & set(value)
        return "FrictionPairModel" if pair else "FrictionRangeModel"
    return "float"


def coefficient_kind(value: Any) -> str:
    """Which branch a static or kinetic coefficient is: a number or a range."""
    return "FrictionRangeModel" if isinstance(value, dict) else "float"


class Record:
    """A validated record of the scene file: its fields as attributes, the model's name, and
    the keys the file gave (``model_fields_set``), as a pydantic model has them."""

    __slots__ = ("__dict__", "model_name", "model_fields_set")

    def __init__(self, model_name: str, values: Mapping[str, Any], given: set[str]) -> None:
        self.__dict__.update(values)
        self.model_name = model_name
        self.model_fields_set = given

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Record) and (
            self.model_name,
            self.__dict__,
            self.model_fields_set,
        ) == (other.model_name, other.__dict__, other.model_fields_set)

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in self.__dict__.items())
        return f"{self.model_name}({fields})"


def is_model(value: Any, name: str) -> bool:
    """Whether a value is a record of the model ``name``."""
    return isinstance(value, Record) and value.model_name == name


class _Refused(Exception):
    """The acceptor does not accept a value exactly (pydantic says why)."""


#: Every model's fields: ``(name, type, default)``, in the models' order (derived).
FIELDS: dict[str, tuple[Any, ...]] = {
    "SceneModel": (
        ("version", ("literal", (1,)), ("required",)),
        ("name", ("union", (("str", None, 200), ("none",))), ("value", None)),
        ("units", ("literal", ("m", "cm", "mm", "um", "in")), ("value", "m")),
        ("body", ("union", (("model", "BodyModel"), ("none",))), ("value", None)),
        ("supports", ("list", ("model", "SupportModel"), None, 6), ("value", [])),
        (
            "couplings",
            (
                "list",
                (
                    "tagged",
                    "type",
                    (
                        ("ball-vee", "BallVeeModel"),
                        ("ball-cylinders", "BallCylindersModel"),
                        ("ball-sphere", "BallSphereModel"),
                        ("ball-trihedral", "BallTrihedralModel"),
                        ("ball-cone", "BallConeModel"),
                        ("ball-flat", "BallFlatModel"),
                    ),
                ),
                None,
                6,
            ),
            ("value", []),
        ),
        (
            "friction",
            (
                "pick",
                "friction_kind",
                (
                    ("float", ("float", 0.0, None, 100.0, None)),
                    ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                    ("FrictionPairModel", ("model", "FrictionPairModel")),
                ),
            ),
            ("value", 0.0),
        ),
        (
            "gravity",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
        ("load", ("union", (("model", "LoadModel"), ("none",))), ("value", None)),
        ("preloads", ("list", ("model", "PreloadModel"), None, 100), ("value", [])),
        ("sweep", ("model", "SweepModel"), ("model", "SweepModel")),
        ("tolerances", ("union", (("model", "TolerancesModel"), ("none",))), ("value", None)),
        (
            "checks",
            (
                "mapping",
                ("str", None, None),
                ("union", (("mapping", ("str", None, None), ("any",)), ("none",))),
            ),
            ("value", {}),
        ),
    ),
    "BodyModel": (
        ("mesh", ("union", (("str", None, None), ("none",))), ("value", None)),
        ("material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("density", ("union", (("float", 1.0, None, 30000.0, None), ("none",))), ("value", None)),
        ("repair", ("bool",), ("value", False)),
        (
            "parts",
            ("union", (("list", ("model", "PartModel"), 1, 1000), ("none",))),
            ("value", None),
        ),
        ("point_masses", ("list", ("model", "PointMassModel"), None, 1000), ("value", [])),
        ("mass", ("union", (("float", None, 0, None, None), ("none",))), ("value", None)),
        (
            "center_of_mass",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
        (
            "inertia",
            (
                "union",
                (
                    ("list", ("list", ("float", None, None, None, None), 3, 3), 3, 3),
                    ("float", None, None, None, None),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
    ),
    "PartModel": (
        ("mesh", ("str", None, None), ("required",)),
        ("material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("density", ("union", (("float", 1.0, None, 30000.0, None), ("none",))), ("value", None)),
        (
            "units",
            ("union", (("literal", ("m", "cm", "mm", "um", "in")), ("none",))),
            ("value", None),
        ),
        ("transform", ("union", (("model", "TransformModel"), ("none",))), ("value", None)),
        ("repair", ("bool",), ("value", False)),
    ),
    "TransformModel": (
        (
            "translate",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
        (
            "rotate",
            (
                "union",
                (
                    ("model", "AxisAngleModel"),
                    ("list", ("list", ("float", None, None, None, None), 3, 3), 3, 3),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
    ),
    "AxisAngleModel": (
        ("axis", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("angle", ("float", -360.0, None, 360.0, None), ("required",)),
    ),
    "PointMassModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("mass", ("float", None, 0, None, None), ("required",)),
        ("point", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
    ),
    "SupportModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("position", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("normal", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        (
            "friction",
            (
                "union",
                (
                    (
                        "pick",
                        "friction_kind",
                        (
                            ("float", ("float", 0.0, None, 100.0, None)),
                            ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                            ("FrictionPairModel", ("model", "FrictionPairModel")),
                        ),
                    ),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        ("contact", ("union", (("model", "ContactModel"), ("none",))), ("value", None)),
    ),
    "FrictionRangeModel": (
        ("min", ("float", 0.0, None, 100.0, None), ("required",)),
        ("max", ("float", 0.0, None, 100.0, None), ("required",)),
    ),
    "FrictionPairModel": (
        (
            "static",
            (
                "pick",
                "coefficient_kind",
                (
                    ("float", ("float", 0.0, None, 100.0, None)),
                    ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                ),
            ),
            ("required",),
        ),
        (
            "kinetic",
            (
                "pick",
                "coefficient_kind",
                (
                    ("float", ("float", 0.0, None, 100.0, None)),
                    ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                ),
            ),
            ("required",),
        ),
    ),
    "ContactModel": (
        ("ball_radius", ("float", None, 0, None, None), ("required",)),
        (
            "ball_radii",
            ("union", (("list", ("float", None, None, None, None), 2, 2), ("none",))),
            ("value", None),
        ),
        (
            "ball_direction",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
        (
            "seat_radii",
            (
                "union",
                (
                    ("list", ("union", (("float", None, None, None, None), ("none",))), 2, 2),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        (
            "seat_direction",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
        ("ball_on", ("literal", ("body", "base")), ("value", "base")),
        ("ball_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("seat_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
    ),
    "BallVeeModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("ball", ("model", "BallModel"), ("required",)),
        ("ball_on", ("literal", ("body", "base")), ("value", "body")),
        (
            "friction",
            (
                "union",
                (
                    (
                        "pick",
                        "friction_kind",
                        (
                            ("float", ("float", 0.0, None, 100.0, None)),
                            ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                            ("FrictionPairModel", ("model", "FrictionPairModel")),
                        ),
                    ),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        ("ball_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("seat_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("type", ("literal", ("ball-vee",)), ("required",)),
        ("groove", ("model", "GrooveModel"), ("required",)),
    ),
    "BallModel": (
        ("center", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("radius", ("float", None, 0, None, None), ("required",)),
        (
            "surface_radii",
            ("union", (("list", ("float", None, None, None, None), 2, 2), ("none",))),
            ("value", None),
        ),
        (
            "surface_direction",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
    ),
    "GrooveModel": (
        ("axis", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("up", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("half_angle", ("float", None, 0.0, None, 90.0), ("required",)),
        ("radius", ("union", (("float", None, 0, None, None), ("none",))), ("value", None)),
    ),
    "BallCylindersModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("ball", ("model", "BallModel"), ("required",)),
        ("ball_on", ("literal", ("body", "base")), ("value", "body")),
        (
            "friction",
            (
                "union",
                (
                    (
                        "pick",
                        "friction_kind",
                        (
                            ("float", ("float", 0.0, None, 100.0, None)),
                            ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                            ("FrictionPairModel", ("model", "FrictionPairModel")),
                        ),
                    ),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        ("ball_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("seat_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("type", ("literal", ("ball-cylinders",)), ("required",)),
        ("cylinders", ("list", ("model", "CylinderModel"), 1, 3), ("required",)),
    ),
    "CylinderModel": (
        ("point", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("axis", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("radius", ("float", None, 0, None, None), ("required",)),
    ),
    "BallSphereModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("ball", ("model", "BallModel"), ("required",)),
        ("ball_on", ("literal", ("body", "base")), ("value", "body")),
        (
            "friction",
            (
                "union",
                (
                    (
                        "pick",
                        "friction_kind",
                        (
                            ("float", ("float", 0.0, None, 100.0, None)),
                            ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                            ("FrictionPairModel", ("model", "FrictionPairModel")),
                        ),
                    ),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        ("ball_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("seat_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("type", ("literal", ("ball-sphere",)), ("required",)),
        ("spheres", ("list", ("model", "SphereModel"), 1, 3), ("required",)),
    ),
    "SphereModel": (
        ("center", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("radius", ("float", None, 0, None, None), ("required",)),
    ),
    "BallTrihedralModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("ball", ("model", "BallModel"), ("required",)),
        ("ball_on", ("literal", ("body", "base")), ("value", "body")),
        (
            "friction",
            (
                "union",
                (
                    (
                        "pick",
                        "friction_kind",
                        (
                            ("float", ("float", 0.0, None, 100.0, None)),
                            ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                            ("FrictionPairModel", ("model", "FrictionPairModel")),
                        ),
                    ),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        ("ball_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("seat_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("type", ("literal", ("ball-trihedral",)), ("required",)),
        ("up", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("half_angle", ("float", None, 0.0, None, 90.0), ("required",)),
        ("reference", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
    ),
    "BallConeModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("ball", ("model", "BallModel"), ("required",)),
        ("ball_on", ("literal", ("body", "base")), ("value", "body")),
        (
            "friction",
            (
                "union",
                (
                    (
                        "pick",
                        "friction_kind",
                        (
                            ("float", ("float", 0.0, None, 100.0, None)),
                            ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                            ("FrictionPairModel", ("model", "FrictionPairModel")),
                        ),
                    ),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        ("ball_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("seat_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("type", ("literal", ("ball-cone",)), ("required",)),
        ("up", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("half_angle", ("float", None, 0.0, None, 90.0), ("required",)),
        (
            "reference",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
    ),
    "BallFlatModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("ball", ("model", "BallModel"), ("required",)),
        ("ball_on", ("literal", ("body", "base")), ("value", "body")),
        (
            "friction",
            (
                "union",
                (
                    (
                        "pick",
                        "friction_kind",
                        (
                            ("float", ("float", 0.0, None, 100.0, None)),
                            ("FrictionRangeModel", ("model", "FrictionRangeModel")),
                            ("FrictionPairModel", ("model", "FrictionPairModel")),
                        ),
                    ),
                    ("none",),
                ),
            ),
            ("value", None),
        ),
        ("ball_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("seat_material", ("union", (("material", 1, 100), ("none",))), ("value", None)),
        ("type", ("literal", ("ball-flat",)), ("required",)),
        ("normal", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
    ),
    "LoadModel": (
        (
            "point",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
        ("magnitude", ("float", 0.0, None, 10000000.0, None), ("required",)),
        (
            "direction",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
        ("angle", ("union", (("float", -360.0, None, 360.0, None), ("none",))), ("value", None)),
        (
            "torque",
            ("union", (("list", ("float", None, None, None, None), 3, 3), ("none",))),
            ("value", None),
        ),
    ),
    "PreloadModel": (
        ("name", ("str", 1, 200), ("required",)),
        ("point", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
        ("force", ("list", ("float", None, None, None, None), 3, 3), ("required",)),
    ),
    "SweepModel": (
        ("normal", ("list", ("float", None, None, None, None), 3, 3), ("value", [0.0, 0.0, 1.0])),
        ("zero", ("list", ("float", None, None, None, None), 3, 3), ("value", [1.0, 0.0, 0.0])),
    ),
    "TolerancesModel": (
        ("position", ("float", 0, None, None, None), ("value", 0.0)),
        ("normal", ("float", 0.0, None, 30.0, None), ("value", 0.0)),
        ("load_direction", ("float", 0.0, None, 30.0, None), ("value", 0.0)),
    ),
}

_PICKS: dict[str, Callable[[Any], str]] = {
    "friction_kind": friction_kind,
    "coefficient_kind": coefficient_kind,
}


def _number(value: Any, spec: tuple[Any, ...], kind: type) -> Any:
    if type(value) is bool or not isinstance(value, (int, float) if kind is float else int):
        raise _Refused
    if isinstance(value, float) and not math.isfinite(value):
        raise _Refused
    if kind is float:
        try:
            value = float(value)
        except OverflowError:
            raise _Refused from None
    ge, gt, le, lt = spec[1:]
    if (
        (ge is not None and not value >= ge)
        or (gt is not None and not value > gt)
        or (le is not None and not value <= le)
        or (lt is not None and not value < lt)
    ):
        raise _Refused
    return value


def _length(n: int, low: int | None, high: int | None) -> None:
    if (low is not None and n < low) or (high is not None and n > high):
        raise _Refused


def _value(value: Any, spec: tuple[Any, ...]) -> Any:
    kind = spec[0]
    if kind == "float":
        return _number(value, spec, float)
    if kind == "int":
        return _number(value, spec, int)
    if kind == "bool":
        if type(value) is not bool:
            raise _Refused
        return value
    if kind in ("str", "material"):
        if kind == "material" and type(value) is int:  # YAML's unquoted 52100
            value = str(value)
        if type(value) is not str:
            raise _Refused
        _length(len(value), spec[1], spec[2])
        return value
    if kind == "none":
        if value is not None:
            raise _Refused
        return None
    if kind == "any":
        return value
    if kind == "literal":
        if not any(type(value) is type(v) and value == v for v in spec[1]):
            raise _Refused
        return value
    if kind == "list":
        if type(value) is not list:
            raise _Refused
        _length(len(value), spec[2], spec[3])
        return [_value(v, spec[1]) for v in value]
    if kind == "mapping":
        if type(value) is not dict:
            raise _Refused
        return {_value(k, spec[1]): _value(v, spec[2]) for k, v in value.items()}
    if kind == "model":
        return _record(value, spec[1])
    if kind == "union":  # pydantic's smart union: exactly one branch must fit
        fits = []
        for branch in spec[1]:
            try:
                fits.append(_value(value, branch))
            except _Refused:
                continue
        if len(fits) != 1:
            raise _Refused
        return fits[0]
    if kind == "pick":
        branches = dict(spec[2])
        branch = branches.get(_PICKS[spec[1]](value))
        if branch is None:
            raise _Refused
        return _value(value, branch)
    if kind == "tagged":
        if type(value) is not dict:
            raise _Refused
        model = dict(spec[2]).get(value.get(spec[1]))
        if model is None:
            raise _Refused
        return _record(value, model)
    raise _Refused  # a kind this acceptor does not know: pydantic decides


def _record(value: Any, model: str) -> Record:
    if type(value) is not dict:
        raise _Refused
    fields = FIELDS[model]
    known = {name for name, _, _ in fields}
    if any(type(k) is not str or k not in known for k in value):
        raise _Refused
    values: dict[str, Any] = {}
    for name, spec, default in fields:
        if name in value:
            values[name] = _value(value[name], spec)
        elif default[0] == "required":
            raise _Refused
        elif default[0] == "model":
            values[name] = _record({}, default[1])
        else:
            values[name] = copy.deepcopy(default[1])
    return Record(model, values, set(value))


def accept(data: Any, model: str = "SceneModel") -> Record | None:
    """The document as records of ``model`` when it is valid and the acceptor is sure of it;
    None otherwise (then pydantic validates it and says what is wrong)."""
    try:
        return _record(data, model)
    except _Refused:
        return None
    except (
        RecursionError,
        TypeError,
        ValueError,
        OverflowError,
    ):  # an odd document: pydantic decides
        return None
