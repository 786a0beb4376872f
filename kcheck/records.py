"""``dataclass``: the standard library's decorator, made cheaper to apply (issue 24: start-up).

Python 3.11's :func:`dataclasses.dataclass` compiles every method it writes with an ``exec`` of
its own: ``__init__``, ``__repr__``, ``__eq__``, ``__hash__`` and, for a frozen class,
``__setattr__`` and ``__delattr__``: about 0.45 ms a class, and kcheck creates some sixty at
every start. Here the standard library only collects the fields (their defaults, the
parameters' record, ``__match_args__``: nothing compiled); ``__repr__``, ``__eq__``,
``__hash__``, ``__setattr__`` and ``__delattr__`` are closures over the field names that
behave as the compiled ones (the same text, the same hash, ``...`` for a recursive ``repr``,
the same ``FrozenInstanceError``, and the running Python's ``__eq__``: tuples of the fields
compared on 3.10-3.12, ``self is other`` then the fields' ``==`` joined by ``and`` on 3.13),
and ``__init__``, the one method whose speed matters, is compiled as the standard library
writes it (an outer function binding the names it reads; the class's module as its
globals, so ``typing.get_type_hints(C.__init__)`` and ``inspect.signature(C,
eval_str=True)`` resolve string annotations as they do for the standard class) at the
class's first instance, or when ``C.__init__`` is first read (about 0.12 ms then; 0.085 ms
a class at import, 0.21 ms with ``__init__`` compiled at once). The class's annotations are
read with :func:`inspect.get_annotations` (3.14's lazy annotations). One difference
remains, by design: before the first instance or read of ``C.__init__``, the class's own
``__dict__`` (``vars(C)["__init__"]``, ``inspect.getattr_static(C, "__init__")``) holds the
stand-in, a callable taking the instance and the arguments, not a function.
``tests/kcheck/test_records.py`` compares both decorators' classes.

Anything else (``ClassVar`` or ``InitVar`` fields, keyword-only fields, ``order``,
``unsafe_hash``, ``slots``, a dataclass base, a class without a docstring, whose docstring the
standard library writes from the signature) is handed to the standard library as it is. Type
checkers see the standard decorator itself.
"""

from __future__ import annotations

import dataclasses
import inspect  # imported by dataclasses already: free
import sys
from operator import attrgetter
from types import MethodType
from typing import TYPE_CHECKING, Any

__all__ = ["dataclass"]

#: Options handled here; any other given as true goes to the standard library whole.
_OWN = frozenset({"init", "repr", "eq", "frozen", "match_args", "kw_only"})


def _values(names: tuple[str, ...]) -> Any:
    """A function from an instance to the tuple of those fields' values."""
    if len(names) > 1:
        return attrgetter(*names)
    if names:
        (name,) = names

        def one(obj: object) -> tuple[Any, ...]:
            return (getattr(obj, name),)

        return one
    return lambda obj: ()


def _method(cls: type, fn: Any, name: str) -> None:
    fn.__name__ = name
    fn.__qualname__ = f"{cls.__qualname__}.{name}"
    setattr(cls, name, fn)


def _repr_fn(names: tuple[str, ...]) -> Any:
    from _thread import get_ident

    running: set[tuple[int, int]] = set()

    def __repr__(self: object) -> str:
        key = id(self), get_ident()
        if key in running:  # a field holding the instance itself
            return "..."
        running.add(key)
        try:
            inner = ", ".join(f"{n}={getattr(self, n)!r}" for n in names)
            return f"{self.__class__.__qualname__}({inner})"
        finally:
            running.discard(key)

    return __repr__


def _eq_fn(names: tuple[str, ...]) -> Any:
    """``__eq__`` as the running Python's dataclasses writes it: 3.10-3.12 compare the tuples
    of the fields' values; 3.13 answers true for the instance itself, else joins the fields'
    ``==`` with ``and`` (a NaN field: unequal to a copy, equal to itself)."""
    if sys.version_info >= (3, 13):
        getters = tuple(attrgetter(n) for n in names)

        def __eq__(self: object, other: object) -> Any:
            if self is other:
                return True
            if other.__class__ is self.__class__:
                same: Any = True
                for get in getters:  # `a == b and c == d`: the first false value, or the last
                    same = get(self) == get(other)
                    if not same:
                        return same
                return same
            return NotImplemented

        return __eq__
    values = _values(names)

    def __eq__(self: object, other: object) -> Any:
        if other.__class__ is self.__class__:
            return values(self) == values(other)
        return NotImplemented

    return __eq__


def _hash_fn(names: tuple[str, ...]) -> Any:
    values = _values(names)

    def __hash__(self: object) -> int:
        return hash(values(self))

    return __hash__


class _Factory:
    """The default of a parameter whose field has a default factory (as the standard
    library's: ``<factory>`` in the signature)."""

    def __repr__(self) -> str:
        return "<factory>"


_HAS_FACTORY = _Factory()


def _init_fn(cls: type, fields: tuple[Any, ...], frozen: bool) -> Any:
    """``__init__`` as the standard library writes it (dataclasses._init_fn), for fields that
    are all plain (no ``InitVar``, no keyword-only field): one ``exec`` instead of three for
    a frozen class (its ``__setattr__`` and ``__delattr__`` are closures here)."""
    names = [f.name for f in fields]
    me = "__dataclass_self__" if "self" in names else "self"
    scope: dict[str, Any] = {f"_type_{f.name}": f.type for f in fields}
    scope.update(_HAS_DEFAULT_FACTORY=_HAS_FACTORY, __dataclass_builtins_object__=object)
    params, body = [me], []
    for f in fields:
        default = f"_dflt_{f.name}"
        if f.default_factory is not dataclasses.MISSING:
            scope[default] = f.default_factory
            value = (
                f"{default}() if {f.name} is _HAS_DEFAULT_FACTORY else {f.name}"
                if f.init
                else f"{default}()"
            )
        elif f.init:
            if f.default is not dataclasses.MISSING:
                scope[default] = f.default
            value = f.name
        else:
            continue  # read from the class attribute holding its default
        assign = (
            f"__dataclass_builtins_object__.__setattr__({me},{f.name!r},{value})"
            if frozen
            else f"{me}.{f.name}={value}"
        )
        body.append(assign)
        if f.init:
            if f.default is not dataclasses.MISSING:
                params.append(f"{f.name}:_type_{f.name}=_dflt_{f.name}")
            elif f.default_factory is not dataclasses.MISSING:
                params.append(f"{f.name}:_type_{f.name}=_HAS_DEFAULT_FACTORY")
            else:
                params.append(f"{f.name}:_type_{f.name}")
    if hasattr(cls, "__post_init__"):
        body.append(f"{me}.__post_init__()")
    scope["_return_type"] = None
    lines = "\n".join(f"   {b}" for b in body or ["pass"])
    # As dataclasses writes it: an outer function binds the names it reads, and the globals
    # are the class's module's, so typing.get_type_hints(C.__init__) and
    # inspect.signature(C, eval_str=True) resolve string annotations there.
    text = (
        f"def __create_fn__({','.join(scope)}):\n"
        f" def __init__({','.join(params)})->_return_type:\n{lines}\n"
        " return __init__"
    )
    module = sys.modules.get(cls.__module__)
    ns: dict[str, Any] = {}
    # Compiled without this module's `from __future__ import annotations`, as dataclasses does:
    # the parameters' annotations are the fields' types, not the names holding them.
    code = compile(text, "<string>", "exec", dont_inherit=True)
    exec(code, module.__dict__ if module is not None else {}, ns)  # noqa: S102 - as dataclasses
    return ns["__create_fn__"](**scope)


class _FirstInit:
    """A class's ``__init__`` until its first instance: then it writes the real one
    (:func:`_init_fn`), puts it in its place and calls it. A class never instantiated in a run
    (a third of those kcheck creates at start-up) costs no compilation. Read in any way
    (``C.__init__``, as ``inspect.signature(C)`` and ``typing.get_type_hints`` do), it writes
    the real one and answers as it."""

    def __init__(self, cls: type, fields: tuple[Any, ...], frozen: bool) -> None:
        self.made = (cls, fields, frozen)

    def real(self) -> Any:
        cls, fields, frozen = self.made
        init = cls.__dict__.get("__init__")
        if init is self:
            init = _init_fn(cls, fields, frozen)
            _method(cls, init, "__init__")
        return init

    def __get__(self, obj: object, owner: type | None = None) -> Any:
        # Read in any way (an instance made, ``C.__init__`` read by typing.get_type_hints or
        # inspect.signature), it writes the real function and answers as that function.
        init = self.real()
        return init if obj is None else MethodType(init, obj)

    def __call__(self, obj: object, /, *args: Any, **kwargs: Any) -> None:
        self.real()(obj, *args, **kwargs)  # positional-only: a field may be called `obj`


def _setattr_fns(cls: type, names: frozenset[str]) -> tuple[Any, Any]:
    """A frozen class's ``__setattr__`` and ``__delattr__`` (dataclasses._frozen_get_del_attr)."""
    from dataclasses import FrozenInstanceError

    owner: Any = cls

    def __setattr__(self: Any, name: str, value: Any) -> None:
        if type(self) is owner or name in names:
            raise FrozenInstanceError(f"cannot assign to field {name!r}")
        super(owner, self).__setattr__(name, value)

    def __delattr__(self: Any, name: str) -> None:
        if type(self) is owner or name in names:
            raise FrozenInstanceError(f"cannot delete field {name!r}")
        super(owner, self).__delattr__(name)

    return __setattr__, __delattr__


def _fast(
    cls: type, init: bool, repr: bool, eq: bool, frozen: bool, match_args: bool, kw_only: bool
) -> type:
    # What the standard library decides before it writes anything (dataclasses._process_class).
    class_hash = cls.__dict__.get("__hash__", dataclasses.MISSING)
    explicit_hash = not (
        class_hash is dataclasses.MISSING or (class_hash is None and "__eq__" in cls.__dict__)
    )
    for name in ("__setattr__", "__delattr__") if frozen else ():
        if name in cls.__dict__:
            raise TypeError(f"Cannot overwrite attribute {name} in class {cls.__name__}")
    # The fields, their defaults as class attributes, __match_args__: nothing compiled.
    cls = dataclasses.dataclass(
        cls, init=False, repr=False, eq=False, match_args=match_args, kw_only=kw_only
    )
    fields = dataclasses.fields(cls)
    # The parameters as asked for (the standard library recorded what it was given).
    cls.__dataclass_params__ = _params(  # type: ignore[attr-defined]
        init, repr, eq, frozen, match_args, kw_only
    )
    if init and "__init__" not in cls.__dict__:
        _method(cls, _FirstInit(cls, fields, frozen), "__init__")
    if repr and "__repr__" not in cls.__dict__:
        _method(cls, _repr_fn(tuple(f.name for f in fields if f.repr)), "__repr__")
    if frozen:
        for fn in _setattr_fns(cls, frozenset(f.name for f in fields)):
            _method(cls, fn, fn.__name__)
    if eq and "__eq__" not in cls.__dict__:
        _method(cls, _eq_fn(tuple(f.name for f in fields if f.compare)), "__eq__")
    if eq and not explicit_hash:
        if frozen:
            hashed = tuple(f.name for f in fields if (f.compare if f.hash is None else f.hash))
            _method(cls, _hash_fn(hashed), "__hash__")
        else:
            cls.__hash__ = None  # type: ignore[assignment]
    return cls


#: Words in a class's annotations that make it one for the standard library: pseudo-fields
#: (``ClassVar``, ``InitVar``) and keyword-only fields.
_UNUSUAL = ("ClassVar", "InitVar", "KW_ONLY")


def _plain(cls: type, options: dict[str, Any]) -> bool:
    """Whether this module writes the class: only options it handles, a docstring of its
    own, no dataclass base, plain fields in a valid order."""
    if any(k not in _OWN and v for k, v in options.items()) or options.get("kw_only"):
        return False
    if not cls.__dict__.get("__doc__"):
        return False
    if any(hasattr(b, "__dataclass_fields__") for b in cls.__mro__[1:]):
        return False
    seen_default = False
    for name, kind in inspect.get_annotations(cls).items():
        if any(word in str(kind) for word in _UNUSUAL):
            return False
        default = cls.__dict__.get(name, dataclasses.MISSING)
        if isinstance(default, dataclasses.Field):
            if default.kw_only is True:
                return False
            if not default.init:
                continue
            default = (
                default.default
                if default.default_factory is dataclasses.MISSING
                else default.default_factory
            )
        if default is not dataclasses.MISSING:
            seen_default = True
        elif seen_default:
            return False  # the standard library raises its TypeError
    return True


_PARAMS: dict[tuple[bool, ...], Any] = {}


def _params(*flags: bool) -> Any:
    """The standard library's record of a dataclass's parameters for these flags (init,
    repr, eq, frozen, match_args, kw_only), taken from an empty class it decorated (kept: a
    handful of kinds)."""
    if flags not in _PARAMS:
        init, repr, eq, frozen, match_args, kw_only = flags

        class Empty:
            """Holds the parameters' record."""

        done = dataclasses.dataclass(
            Empty,
            init=init,
            repr=repr,
            eq=eq,
            frozen=frozen,
            match_args=match_args,
            kw_only=kw_only,
        )
        _PARAMS[flags] = done.__dataclass_params__  # type: ignore[attr-defined]
    return _PARAMS[flags]


def _dataclass(cls: type | None = None, /, **options: Any) -> Any:
    def wrap(cls: type) -> type:
        if not _plain(cls, options):
            return dataclasses.dataclass(cls, **options)
        flags = {k: options.get(k, True) for k in ("init", "repr", "eq", "match_args")}
        return _fast(cls, frozen=options.get("frozen", False), kw_only=False, **flags)

    return wrap if cls is None else wrap(cls)


if TYPE_CHECKING:
    from dataclasses import dataclass as dataclass
else:
    dataclass = _dataclass
    dataclass.__name__ = dataclass.__qualname__ = "dataclass"
    dataclass.__doc__ = (
        "dataclasses.dataclass, cheaper to apply at import (kcheck.records): the same class."
    )
