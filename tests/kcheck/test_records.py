"""kcheck.records.dataclass gives the class the standard library's decorator gives.

Reference: :func:`dataclasses.dataclass` itself. Each case defines the same class body twice,
once with each decorator, and compares what a user of the class can observe.
"""

from __future__ import annotations

import copy
import dataclasses
import inspect
import pickle
import re
from typing import Any, ClassVar

import pytest

from kcheck.records import dataclass as fast


def _both(body: str, decorator: str = "frozen=True") -> tuple[type, type]:
    """The class ``C`` of ``body`` made by the standard library and by kcheck.records."""
    made = []
    for name in ("dataclasses.dataclass", "fast"):
        scope: dict[str, Any] = {
            "dataclasses": dataclasses,
            "fast": fast,
            "ClassVar": ClassVar,
            "__name__": __name__,
        }
        exec(f"@{name}({decorator})\nclass C:\n{body}", scope)  # noqa: S102
        made.append(scope["C"])
    return made[0], made[1]


BODY = '''
    """A record."""

    a: float
    b: tuple = ()
    c: tuple = dataclasses.field(default_factory=tuple)
    d: str = dataclasses.field(default="x", repr=False)
    e: int = dataclasses.field(default=0, compare=False)
    f: float = dataclasses.field(default=1.0, hash=False)
'''


def _observed(cls: type, *args: Any, **kwargs: Any) -> dict[str, Any]:
    one, two = cls(*args, **kwargs), cls(*args, **kwargs)
    other = cls(*(args[0] + 1, *args[1:]), **kwargs)
    seen: dict[str, Any] = {
        "repr": re.sub(" at 0x[0-9a-f]+", "", repr(one)),
        "eq": (one == two, one != two, one == other, one.__eq__(object())),
        "fields": [
            (f.name, f.type, f.default, f.repr, f.compare, f.hash) for f in dataclasses.fields(cls)
        ],
        "match_args": getattr(cls, "__match_args__", None),
        "params": repr(cls.__dataclass_params__),  # type: ignore[attr-defined]
        "signature": str(inspect.signature(cls)),
        "replace": re.sub(" at 0x[0-9a-f]+", "", repr(dataclasses.replace(one, a=7.0))),
        "copy": (copy.copy(one) == one, re.sub(" at 0x[0-9a-f]+", "", repr(copy.deepcopy(one)))),
        "asdict": dataclasses.asdict(one),
        "hashable": cls.__hash__ is not None,
        "names": [(n, getattr(cls, n).__qualname__) for n in ("__init__", "__repr__", "__eq__")],
        "init": (cls.__init__.__module__, repr(cls.__init__.__defaults__)),
    }
    if cls.__hash__ is not None:
        seen["hash"] = (hash(one) == hash(two), hash(one) == hash(cls(*args, e=5)))
    try:
        one.a = 3.0
        seen["set"] = one.a
    except dataclasses.FrozenInstanceError as exc:
        seen["set"] = str(exc)
    try:
        del one.b
        seen["del"] = "deleted"
    except dataclasses.FrozenInstanceError as exc:
        seen["del"] = str(exc)
    return seen


@pytest.mark.parametrize(
    "decorator", ["frozen=True", "", "eq=False", "repr=False", "frozen=True, match_args=False"]
)
def test_the_same_class_as_the_standard_librarys(decorator):
    standard, ours = _both(BODY, decorator)
    assert _observed(ours, 1.5, (1, 2)) == _observed(standard, 1.5, (1, 2))


def test_the_fast_path_is_taken_for_a_plain_frozen_class():
    _, ours = _both(BODY)
    # The standard library's __repr__ is wrapped by its recursion guard; ours is a closure.
    assert ours.__repr__.__code__.co_filename == fast.__code__.co_filename


def test_the_signature_before_and_after_the_first_instance():
    for decorator in ("frozen=True", ""):
        standard, ours = _both(BODY, decorator)
        assert str(inspect.signature(ours)) == str(inspect.signature(standard))
        ours(1.0)
        assert str(inspect.signature(ours)) == str(inspect.signature(standard))
        assert ours.__init__.__qualname__ == standard.__init__.__qualname__


def test_a_subclass_instantiated_first_writes_its_base_init():
    _, ours = _both(BODY)

    class Sub(ours):  # type: ignore[misc, valid-type]
        """Not a dataclass itself."""

    assert repr(Sub(2.0)).endswith("<locals>.Sub(a=2.0, b=(), c=(), e=0, f=1.0)")
    assert ours(2.0) == ours(2.0) and "__init__" not in Sub.__dict__


def test_fields_named_like_the_methods_arguments():
    body = '''
    """Fields named as the arguments of the methods written here."""

    obj: int
    self: int = 0
    name: str = ""
    value: float = 0.0
    other: int = 0
'''
    standard, ours = _both(body)
    kwargs = {"obj": 1, "self": 2, "name": "n", "value": 3.0, "other": 4}
    assert repr(ours(**kwargs)) == repr(standard(**kwargs))
    assert ours(**kwargs) == ours(**kwargs) and hash(ours(**kwargs)) == hash(ours(**kwargs))


def test_a_recursive_repr_and_an_unhashable_field():
    body = '''
    """Holds anything."""

    x: Any
'''
    standard, ours = _both(body, "")
    for cls in (standard, ours):
        cls.__annotations__  # noqa: B018
    s, o = standard([]), ours([])
    s.x.append(s)
    o.x.append(o)
    assert repr(o) == repr(s).replace("C(", "C(") and repr(o) == "C(x=[...])"
    with pytest.raises(TypeError):
        hash(_both(body)[1]([]))


def test_post_init_and_explicit_methods():
    body = '''
    """With methods of its own."""

    a: int
    b: int = dataclasses.field(init=False, default=0)

    def __post_init__(self):
        object.__setattr__(self, "b", self.a * 2)

    def __hash__(self):
        return 7

    def __eq__(self, other):
        return True
'''
    for decorator in ("frozen=True", ""):
        standard, ours = _both(body, decorator)
        assert (ours(3).b, hash(ours(3)), ours(1) == ours(2), repr(ours(3))) == (
            standard(3).b,
            hash(standard(3)),
            standard(1) == standard(2),
            repr(standard(3)),
        )


@pytest.mark.parametrize(
    "body",
    [
        '    """x"""\n    a: int\n    n: ClassVar[int] = 3\n',
        '    """x"""\n    a: int = dataclasses.field(default=1, kw_only=True)\n',
        "    a: int = 1\n",  # no docstring: the standard library writes one
    ],
)
def test_unusual_classes_go_to_the_standard_library(body):
    standard, ours = _both(body)
    assert ours.__doc__ == standard.__doc__
    assert str(inspect.signature(ours)) == str(inspect.signature(standard))
    assert ours.__init__.__code__.co_filename == standard.__init__.__code__.co_filename


def test_order_and_inheritance_go_to_the_standard_library():
    standard, ours = _both('    """x"""\n    a: int\n', "frozen=True, order=True")
    assert ours(1) < ours(2)

    @fast(frozen=True)
    class Child(ours):  # type: ignore[misc, valid-type]
        """A subclass."""

        b: int = 0

    assert (
        repr(Child(1, 2))
        == "test_order_and_inheritance_go_to_the_standard_library.<locals>.Child(a=1, b=2)"
    )
    with pytest.raises(TypeError, match="non-frozen"):

        @fast
        class Thawed(_both('    """x"""\n    a: int\n')[1]):  # type: ignore[misc]
            """Not frozen below a frozen class: refused, as by the standard library."""


def test_a_default_before_a_required_field_is_refused():
    with pytest.raises(TypeError, match="non-default argument"):
        _both('    """x"""\n    a: int = 1\n    b: int\n')


@fast(frozen=True)
class Pickled:
    """A module's class, for pickle."""

    a: float
    b: tuple[int, ...] = (1,)


def test_pickled_through_a_process_boundary_unchanged():
    one = Pickled(2.0)
    back = pickle.loads(pickle.dumps(one, protocol=pickle.HIGHEST_PROTOCOL))
    assert back == one and repr(back) == "Pickled(a=2.0, b=(1,))" and hash(back) == hash(one)
