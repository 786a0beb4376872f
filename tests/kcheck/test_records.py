"""kcheck.records.dataclass gives the class the standard library's decorator gives.

Reference: :func:`dataclasses.dataclass` itself. Each case defines the same class body twice,
once with each decorator, and compares what a user of the class can observe.
"""

from __future__ import annotations

import copy
import dataclasses
import inspect
import os
import pickle
import re
import subprocess
import sys
import textwrap
import typing
from typing import Any, ClassVar

import pytest

from kcheck.records import dataclass as fast


def _both(body: str, decorator: str = "frozen=True", future: bool = True) -> tuple[Any, Any]:
    """The class ``C`` of ``body`` made by the standard library and by kcheck.records; its
    annotations are strings (``from __future__ import annotations``, this module's) or, with
    ``future=False``, the evaluated objects."""
    made = []
    for name in ("dataclasses.dataclass", "fast"):
        scope: dict[str, Any] = {
            "dataclasses": dataclasses,
            "fast": fast,
            "ClassVar": ClassVar,
            "__name__": __name__,
        }
        text = f"@{name}({decorator})\nclass C:\n{body}"
        exec(compile(text, "<test>", "exec", dont_inherit=not future), scope)  # noqa: S102
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


def _observed(cls: Any, *args: Any, **kwargs: Any) -> dict[str, Any]:
    one, two = cls(*args, **kwargs), cls(*args, **kwargs)
    other = cls(*(args[0] + 1, *args[1:]), **kwargs)
    seen: dict[str, Any] = {
        "repr": re.sub(" at 0x[0-9a-f]+", "", repr(one)),
        "eq": (one == two, one != two, one == other, one.__eq__(object())),
        "fields": [
            (f.name, f.type, f.default, f.repr, f.compare, f.hash) for f in dataclasses.fields(cls)
        ],
        "match_args": getattr(cls, "__match_args__", None),
        "params": repr(cls.__dataclass_params__),
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


def test_pickled_and_loaded_back_unchanged():
    one = Pickled(2.0)
    back = pickle.loads(pickle.dumps(one, protocol=pickle.HIGHEST_PROTOCOL))
    assert back == one and repr(back) == "Pickled(a=2.0, b=(1,))" and hash(back) == hash(one)


def test_pickled_through_a_process_boundary_unchanged(tmp_path, monkeypatch):
    # A module both processes import: the parent pickles an instance, a fresh interpreter
    # loads it, compares it with one it makes, and sends its own back.
    (tmp_path / "kcheck_pickled_record.py").write_text(
        textwrap.dedent(
            '''
            from kcheck.records import dataclass

            @dataclass(frozen=True)
            class Record:
                """A module's class, for pickle."""

                a: float
                b: tuple = (1,)
            '''
        )
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    from kcheck_pickled_record import Record  # type: ignore[import-not-found]

    child = (
        "import pickle, sys; from kcheck_pickled_record import Record; "
        "back = pickle.loads(sys.stdin.buffer.read()); "
        "sys.stdout.buffer.write(pickle.dumps((repr(back), back == Record(2.0), hash(back), "
        "Record(3.0, (4,))), protocol=pickle.HIGHEST_PROTOCOL))"
    )
    out = subprocess.run(
        [sys.executable, "-c", child],
        input=pickle.dumps(Record(2.0), protocol=pickle.HIGHEST_PROTOCOL),
        capture_output=True,
        check=True,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )
    text, equal, hashed, sent = pickle.loads(out.stdout)
    assert (text, equal, hashed) == ("Record(a=2.0, b=(1,))", True, hash(Record(2.0)))
    assert sent == Record(3.0, (4,)) and repr(sent) == "Record(a=3.0, b=(4,))"


HINTED = '''
    """Annotations naming this module's imports."""

    a: Any
    b: re.Pattern = dataclasses.field(default="x")  # (3.10 would add Optional to a None)
    c: typing.SupportsFloat = 0.0
'''


@pytest.mark.parametrize("decorator", ["frozen=True", ""])
def test_type_hints_and_evaluated_signature_before_and_after_the_first_instance(decorator):
    # The standard library's __init__ has the class's module as its globals: string
    # annotations resolve there, before and after the first instance.
    assert sys.modules[__name__].__dict__ is globals()
    standard, ours = _both(HINTED, decorator)

    def seen(cls: Any) -> tuple[Any, ...]:
        return (
            typing.get_type_hints(cls.__init__),
            str(inspect.signature(cls, eval_str=True)),
            cls.__init__.__globals__ is globals(),
        )

    assert seen(ours) == seen(standard)
    assert seen(ours)[0] == {
        "a": Any,
        "b": re.Pattern,
        "c": typing.SupportsFloat,
        "return": type(None),
    }
    ours(1), standard(1)
    assert seen(ours) == seen(standard)


def test_a_nan_field_compares_as_the_running_pythons_dataclasses():
    # 3.10-3.12 compare tuples (identity first: the same NaN object is equal to itself);
    # 3.13 compares field by field with == after `self is other`.
    standard, ours = _both('    """x"""\n    v: float\n    w: Any = None\n')
    nan = float("nan")
    seen = {}
    for cls in (standard, ours):
        one = cls(nan)
        seen[cls] = [cls(nan) == cls(nan), cls(1.0, nan) == cls(1.0, nan), one == one]
    expected_same = sys.version_info < (3, 13)
    assert seen[ours] == seen[standard] == [expected_same, expected_same, True]


class _Truthy:
    """Equal to everything as a non-boolean true value."""

    def __eq__(self, other: object) -> Any:
        return "yes"

    __hash__ = object.__hash__


def test_eq_returns_what_the_standard_librarys_returns():
    standard, ours = _both('    """x"""\n    v: Any\n    w: Any = 0\n')
    seen = {}
    for cls in (standard, ours):
        t = _Truthy()
        seen[cls] = [cls(t, 1) == cls(t, 1), cls(_Truthy(), _Truthy()) == cls(1, 2)]
    assert seen[ours] == seen[standard]


@pytest.mark.parametrize("future", [True, False])
@pytest.mark.parametrize(
    "body",
    [
        '    """x"""\n    a: int\n    k: dataclasses.InitVar[int] = 0\n'
        "    def __post_init__(self, k):\n        object.__setattr__(self, 'z', k)\n",
        '    """x"""\n    a: int\n    _: dataclasses.KW_ONLY\n    b: int = 0\n',
        '    """x"""\n    a: int\n    n: ClassVar[int] = 3\n',
    ],
)
def test_pseudo_fields_go_to_the_standard_library_with_or_without_future_annotations(body, future):
    standard, ours = _both(body, future=future)
    assert str(inspect.signature(ours)) == str(inspect.signature(standard))
    assert ours.__init__.__code__.co_filename == standard.__init__.__code__.co_filename
    assert [f.name for f in dataclasses.fields(ours)] == [
        f.name for f in dataclasses.fields(standard)
    ]
    if "InitVar" in body:
        assert ours(1, 5).z == standard(1, 5).z == 5
