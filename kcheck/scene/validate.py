"""Input checks shared by the scene loader: collecting every error of a file, plain-value
checks (finite numbers, clean strings), and pydantic errors in an engineer's words (with the
allowed range, and "did you mean" for a misspelt key)."""

from __future__ import annotations

import math
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.errors import FieldPath, SceneError, SceneErrors
from kcheck.scene.accept import COUPLING_TYPES, Record
from kcheck.scene.limits import LIMITS, MAX_DIRECTION, MIN_DIRECTION, Range
from kcheck.scene.types import position_of

if TYPE_CHECKING:  # pydantic is imported only when a file has a mistake (issue 24)
    from pydantic import BaseModel, ValidationError
    from pydantic_core import ErrorDetails

__all__ = [
    "Problems",
    "plain_value_problems",
    "pydantic_problems",
    "describe_pydantic",
    "did_you_mean",
    "salvage",
    "record_of",
    "consequence_of",
]

# Integers beyond this are refused before they reach float arithmetic (1e300 still squares).
_MAX_INT = 10**300


class Problems:
    """Collects the located errors of one file; raises them together."""

    def __init__(
        self,
        path: Path,
        lines: Mapping[FieldPath, int],
        columns: Mapping[FieldPath, int] | None = None,
    ) -> None:
        self.path = path
        self.lines = lines
        self.columns = columns or {}
        self.errors: list[SceneError] = []
        self._seen: set[tuple[FieldPath, str]] = set()

    def error(self, where: FieldPath, message: str) -> SceneError:
        """A SceneError at a field: its line and column, or those of its nearest enclosing
        field written in the file (a missing field: the mapping it belongs in)."""
        line, column = position_of(self.lines, self.columns, where)
        return SceneError(self.path, message, field=where or None, line=line, column=column)

    def add(self, where: FieldPath, message: str) -> None:
        """Record an error (once per field and message)."""
        if (where, message) not in self._seen:
            self._seen.add((where, message))
            self.errors.append(self.error(where, message))

    def has(self, prefix: FieldPath) -> bool:
        """Whether an error was recorded at or below a field."""
        return any(
            e.where is not None and e.where[: len(prefix)] == prefix for e in self.errors
        ) or (prefix == () and bool(self.errors))

    def raise_if_any(self) -> None:
        """Raise every recorded error, in file order, as one SceneErrors."""
        if self.errors:
            ordered = sorted(self.errors, key=lambda e: (e.line or 0, e.column or 0))
            raise SceneErrors(ordered)

    # --- values -------------------------------------------------------------------------

    def in_range(self, where: FieldPath, value: float, key: str, scale: float = 1.0) -> bool:
        """Check ``value * scale`` against ``LIMITS[key]``; record an error if outside."""
        r = LIMITS[key]
        if r.contains(value * scale):
            return True
        self.add(where, _out_of_range(value, r, scale))
        return False

    def coordinates(self, where: FieldPath, vector: list[float], scale: float) -> np.ndarray | None:
        """A point in the scene's units as metres, each coordinate within the limits."""
        v = np.asarray(vector, dtype=float) * scale
        r = LIMITS["coordinate"]
        high = r.high
        # np.all(np.abs(v) <= high), element by element in Python floats for one point
        inside = (
            all(abs(x) <= high for x in v.tolist())
            if v.ndim == 1
            else bool(np.all(np.abs(v) <= high))
        )
        if not inside:
            self.add(where, f"coordinates must satisfy |x| ≤ {r.high:g} m, got {vector}")
            return None
        return v

    def direction(self, where: FieldPath, vector: list[float], what: str) -> np.ndarray | None:
        """A unit vector from any non-zero vector whose components are of sane size."""
        from kcheck.scene.couplings import unit

        v = np.asarray(vector, dtype=float)
        values = v.tolist() if v.ndim == 1 else []
        if values and all(map(math.isfinite, values)):
            largest = max(map(abs, values))  # float(np.abs(v).max()) of finite parts
        else:
            largest = float(np.abs(v).max())
        if largest == 0.0:
            self.add(where, f"expected a non-zero vector for {what}, got {vector}")
            return None
        if not MIN_DIRECTION <= largest <= MAX_DIRECTION:
            self.add(
                where,
                f"{what}: the largest component must lie between {MIN_DIRECTION:g} and "
                f"{MAX_DIRECTION:g} (only the direction matters; give components of order 1), "
                f"got {vector}",
            )
            return None
        return unit(v)

    def magnitude(self, where: FieldPath, vector: list[float], key: str) -> np.ndarray | None:
        """A vector whose length lies within ``LIMITS[key]`` (force, torque, gravity)."""
        v = np.asarray(vector, dtype=float)
        r = LIMITS[key]
        hint = f"; {r.hint}" if r.hint else ""
        if not np.all(np.abs(v) <= r.high):
            self.add(where, f"expected {r.text()} (its length), got {vector}{hint}")
            return None
        norm = float(np.linalg.norm(v))
        if not r.contains(norm):
            self.add(where, f"expected {r.text()} (its length), got {norm:.6g}{hint}")
            return None
        return v


def _out_of_range(value: float, r: Range, scale: float) -> str:
    got = f"{value:g}" if scale == 1.0 else f"{value:g} ({value * scale:g} {r.unit})"
    return f"out of range: expected {r.text()}, got {got}"


def _bad_string(text: str) -> str | None:
    if "\x00" in text:
        return "contains a NUL character"
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return "contains an unpaired surrogate (not valid Unicode text)"
    return None


def plain_value_problems(data: Any, problems: Problems) -> None:
    """Every number finite and of float size, every string valid text without NUL; anywhere
    in the file, check options included."""
    _check_tree(data, (), [1_000_000], problems)


def _check_tree(value: Any, path: FieldPath, budget: list[int], problems: Problems) -> None:
    """:func:`plain_value_problems` of a value and everything below it (a mapping's keys
    too), in file order (depth first), one node of ``budget`` each."""
    # Shared values (aliases) are walked each time they occur; the YAML reader has bounded
    # their total, and `budget` bounds this walk anyway.
    budget[0] -= 1
    if budget[0] < 0:
        return
    # isinstance of an exact dict or list is as fast as a type test (CPython checks the
    # type first), so one branch per kind serves both.
    if isinstance(value, dict):
        for k, v in value.items():
            where = (*path, k)
            _check_value(k, where, problems)
            _check_tree(v, where, budget, problems)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            _check_tree(v, (*path, i), budget, problems)
    else:
        _check_value(value, path, problems)


def _check_value(value: Any, where: FieldPath, problems: Problems) -> None:
    """One value's problem, if any: a non-finite float, an integer beyond float size, a
    string that is not valid text."""
    if isinstance(value, float):
        if not math.isfinite(value):
            problems.add(where, f"expected a finite number, got {value}")
    elif isinstance(value, str):
        bad = _bad_string(value)
        if bad:
            problems.add(where, f"the text {bad}")
    elif isinstance(value, int) and abs(value) > _MAX_INT:  # a bool is never too large
        problems.add(where, "the number is too large to be a physical quantity")


# --- pydantic errors ------------------------------------------------------------------------


def _models_in(annotation: Any) -> list[type[BaseModel]]:
    """The pydantic models an annotation can hold (through lists, unions, Annotated)."""
    from pydantic import BaseModel

    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    out: list[type[BaseModel]] = []
    for arg in typing.get_args(annotation):
        out.extend(_models_in(arg))
    return out


def _branch(part: Any, models: list[type[BaseModel]]) -> tuple[str, Any] | None:
    """Whether a loc entry names a union branch: ``("tag", model)`` for a discriminated
    union's tag, ``("model", model)`` for a plain union's model, ``("other", None)`` for a
    plain union's non-model branch (``float``, ``list[...]``); None for a field or index."""
    if not isinstance(part, str):
        return None
    for m in models:
        tag = m.model_fields.get("type")
        if tag is not None and typing.get_args(tag.annotation) == (part,):
            return "tag", m
        if part == m.__name__:
            # A branch chosen from the value itself (a callable discriminator) reports only
            # its own errors: like a tag, every one of them is kept.
            return ("tag" if getattr(m, "TAGGED", False) else "model"), m
    if "[" in part or part in ("float", "int", "str", "bool"):
        return "other", None
    return None


def _resolve(loc: tuple[Any, ...], root: type[BaseModel]) -> tuple[FieldPath, Any, int | None]:
    """For a pydantic error location: the field path without union-branch tags, the field
    info (or models) at its end, and the path length at the first plain-union branch (None
    when the location passes through no plain union)."""
    path: list[str | int] = []
    models: list[type[BaseModel]] = [root]
    info: Any = None
    union_at: int | None = None
    for part in loc:
        branch = _branch(part, models)
        if branch is not None:
            kind, model = branch
            if kind != "tag" and union_at is None:
                union_at = len(path)
            if model is not None:
                models, info = [model], None
            continue
        path.append(part)
        if isinstance(part, int):
            continue
        info = next((m.model_fields[part] for m in models if part in m.model_fields), None)
        models = _models_in(info.annotation) if info is not None else []
    return tuple(path), (info, models), union_at


#: Fields that were removed, by the last two parts of their path, and what replaces them.
RETIRED_FIELDS: dict[tuple[str, ...], str] = {
    ("tolerances", "workers"): (
        "no longer an option: samples go to worker processes or a Dask cluster with "
        "`kcheck check --sample-jobs N`, `--dask-local N` or `--scheduler ADDRESS` "
        "(docs/checks.md)"
    ),
}


def did_you_mean(key: str, allowed: list[str]) -> str:
    """`` (did you mean `friction`?)`` for a close match, else the allowed keys."""
    import difflib  # only for a bad key: not on the start-up path

    close = difflib.get_close_matches(key, allowed, n=1, cutoff=0.6)
    if close:
        return f"; did you mean `{close[0]}`?"
    if allowed:
        return f"; allowed here: {', '.join(sorted(allowed))}"
    return ""


def _constraints(info: Any) -> list[Any]:
    """A field's constraints, and those of the number branch of a union field (``friction``:
    a number or a range)."""
    found = list(getattr(info, "metadata", None) or [])
    for arg in typing.get_args(getattr(info, "annotation", None)):
        for extra in getattr(arg, "__metadata__", ()):
            found.extend(getattr(extra, "metadata", None) or [])
    return found


def _bounds(info: Any, name: str) -> str | None:
    """The allowed range of a bounded field, e.g. ``0 ≤ magnitude ≤ 1e+07 N``."""
    low = high = None
    low_sign = high_sign = "≤"
    for m in _constraints(info):
        for attr, sign in (("ge", "≤"), ("gt", "<")):
            if getattr(m, attr, None) is not None:
                low, low_sign = getattr(m, attr), sign
        for attr, sign in (("le", "≤"), ("lt", "<")):
            if getattr(m, attr, None) is not None:
                high, high_sign = getattr(m, attr), sign
    for r in LIMITS.values():
        if (r.low, r.high) == (low, high):
            return Range(r.low, r.high, r.unit, name, r.open).text()
    if low is None and high is None:
        return None
    text = name if low is None else f"{low:g} {low_sign} {name}"
    return text if high is None else f"{text} {high_sign} {high:g}"


def describe_pydantic(err: Mapping[str, Any], root: type[BaseModel] | None = None) -> str:
    """One pydantic error in an engineer's words: what was expected, what came; with
    ``root`` (the model validated), the allowed range and "did you mean" for unknown keys."""
    kind = err["type"]
    got = err.get("input")
    shown = repr(got)
    if len(shown) > 60:
        shown = shown[:57] + "..."
    info: Any = None
    name = str(err["loc"][-1]) if err["loc"] else ""
    if root is not None:
        path, (info, _), _ = _resolve(tuple(err["loc"]), root)
        name = str(path[-1]) if path else name
    if kind == "missing":
        return "required field is missing"
    if kind == "extra_forbidden":
        allowed: list[str] = []
        if root is not None:
            _, (_, parents), _ = _resolve(tuple(err["loc"][:-1]), root)
            allowed = sorted({n for m in parents for n in m.model_fields})
        retired = RETIRED_FIELDS.get(tuple(str(part) for part in err["loc"][-2:]))
        if retired is not None:
            return f"unknown field: {retired}"
        return "unknown field" + did_you_mean(str(err["loc"][-1]), allowed)
    if kind in ("too_short", "too_long") and isinstance(got, list):
        ctx = err.get("ctx") or {}
        if ctx.get("min_length") == 3 and ctx.get("max_length", 3) == 3:
            return f"expected a list of 3 numbers, got {len(got)} item(s)"
        if kind == "too_short":
            return f"expected at least {ctx.get('min_length')} item(s), got {len(got)}"
        return f"expected at most {ctx.get('max_length')} item(s), got {len(got)}"
    if kind in ("string_too_long", "string_too_short") and isinstance(got, str):
        ctx = err.get("ctx") or {}
        if kind == "string_too_long":
            return f"expected at most {ctx.get('max_length')} character(s), got {len(got)}"
        return f"expected at least {ctx.get('min_length')} character(s), got {len(got)}"
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        bounds = _bounds(info, name)
        if bounds is not None:
            return f"out of range: expected {bounds}, got {shown}"
    if kind == "union_tag_not_found":
        return f"required field is missing; expected one of {', '.join(COUPLING_TYPES)}"
    if kind == "union_tag_invalid":
        tag = (err.get("ctx") or {}).get("tag")
        return f"unknown coupling type {tag!r}; expected one of {', '.join(COUPLING_TYPES)}"
    if kind == "value_error":  # a validator's own message: kcheck's words, without pydantic's
        cause = (err.get("ctx") or {}).get("error")
        return str(cause) if cause is not None else str(err["msg"]).removeprefix("Value error, ")
    msg = _expected(kind, err.get("ctx") or {}, info, name)
    if msg is None:  # a rare kind: pydantic's own words, the best there is
        msg = str(err["msg"]).replace("Input should be", "expected")
    if name in ("units", "report_units") and isinstance(got, str):
        unit = _UNIT_WORDS.get(got.strip().lower().rstrip("s").replace("-", ""))
        if unit is not None:
            return f"{msg}, got {shown}; did you mean `{unit}`?"
    return f"{msg}, got {shown}"


#: What a field expected, in kcheck's words, by pydantic's error type: pydantic's own wording
#: is its to change between releases, and kcheck's messages (and the errors it says once, such
#: as a non-finite number found by :func:`plain_value_problems` too) must not change with it.
_EXPECTED = {
    "float_type": "a number",
    "float_parsing": "a number",
    "int_type": "a whole number",
    "int_parsing": "a whole number",
    "int_from_float": "a whole number",
    "finite_number": "a finite number",
    "bool_type": "true or false",
    "bool_parsing": "true or false",
    "string_type": "text",
    "string_unicode": "valid Unicode text",
    "list_type": "a list",
    "tuple_type": "a list",
    "dict_type": "a mapping",
    "model_type": "a mapping",
    "model_attributes_type": "a mapping",
}

_COMPARISONS = {
    "greater_than": ("gt", "<"),
    "greater_than_equal": ("ge", "≤"),
    "less_than": ("lt", "<"),
    "less_than_equal": ("le", "≤"),
}


def _literal_values(annotation: Any) -> list[Any]:
    """The values a ``Literal`` in an annotation allows (through unions and Annotated)."""
    if typing.get_origin(annotation) is typing.Literal:
        return list(typing.get_args(annotation))
    return [v for arg in typing.get_args(annotation) for v in _literal_values(arg)]


def _expected(kind: str, ctx: Mapping[str, Any], info: Any, name: str) -> str | None:
    """What was expected, in kcheck's words, for a pydantic error of type ``kind``; None for
    a kind kcheck has no words for."""
    if kind in _EXPECTED:
        return f"expected {_EXPECTED[kind]}"
    if kind in _COMPARISONS:
        key, sign = _COMPARISONS[kind]
        limit = ctx.get(key)
        if isinstance(limit, (int, float)):
            if kind.startswith("greater"):
                return f"out of range: expected {limit:g} {sign} {name}"
            return f"out of range: expected {name} {sign} {limit:g}"
    if kind == "literal_error":
        allowed = _literal_values(getattr(info, "annotation", None))
        if allowed:
            shown = ", ".join(repr(v) for v in allowed)
            return f"expected {shown}" if len(allowed) == 1 else f"expected one of {shown}"
    return None


# Unit names as people write them (singular, lower case, no hyphen) → kcheck's symbol.
_UNIT_WORDS = {
    "metre": "m",
    "meter": "m",
    "centimetre": "cm",
    "centimeter": "cm",
    "millimetre": "mm",
    "millimeter": "mm",
    "micrometre": "um",
    "micrometer": "um",
    "micron": "um",
    "µm": "um",
    "μm": "um",
    "inche": "in",
    "inch": "in",
    '"': "in",
}


def pydantic_problems(exc: ValidationError, root: type[BaseModel], problems: Problems) -> None:
    """Record every pydantic error of a validation; where a plain union (``inertia``: a
    matrix or a number) reports one error per branch, only the most specific (deepest)."""
    chosen: dict[Any, tuple[int, FieldPath, ErrorDetails]] = {}
    for i, err in enumerate(exc.errors(include_url=False)):
        loc = tuple(err["loc"])
        path, _, union_at = _resolve(loc, root)
        key: Any = i if union_at is None else ("union", path[:union_at])
        if key not in chosen or len(loc) > chosen[key][0]:
            chosen[key] = (len(loc), path, err)
    # A misspelt required key is said once, as the unknown key with its "did you mean", not
    # also as the required key missing.
    meant = set()
    for _, path, err in chosen.values():
        if err["type"] == "extra_forbidden" and path:
            _, (_, parents), _ = _resolve(tuple(err["loc"][:-1]), root)
            allowed = sorted({n for m in parents for n in m.model_fields})
            import difflib  # only for a bad key: not on the start-up path

            close = difflib.get_close_matches(str(path[-1]), allowed, n=1, cutoff=0.6)
            if close:
                meant.add((*path[:-1], close[0]))
    # A value the plain-value checks refused already (a non-finite number, a surrogate in a
    # text) is said once, in their words.
    said = {e.where for e in problems.errors}
    for _, path, err in chosen.values():
        if (err["type"] == "missing" and path in meant) or path in said:
            continue
        if err["type"] in ("union_tag_invalid", "union_tag_not_found"):
            path = (*path, "type")
        problems.add(path, describe_pydantic(err, root))


# --- every mistake in one run ---------------------------------------------------------------

#: Stand-ins for required top-level fields whose value is wrong: the file's other fields are
#: still checked with it, and its own error is already recorded.
_STAND_INS: dict[str, Any] = {"version": 1}
#: Rounds of salvaging: each drops at least one field, and a file has a bounded depth.
_SALVAGE_ROUNDS = 64


def _at(data: Any, path: FieldPath) -> tuple[bool, Any]:
    """Whether ``path`` exists in nested mappings and lists, and what is there."""
    here = data
    for part in path:
        if isinstance(here, dict) and part in here:
            here = here[part]
        elif isinstance(here, list) and isinstance(part, int) and 0 <= part < len(here):
            here = here[part]
        else:
            return False, None
    return True, here


def _existing(data: Any, path: FieldPath) -> FieldPath:
    """The longest prefix of ``path`` present in ``data``."""
    for n in range(len(path), 0, -1):
        if _at(data, path[:n])[0]:
            return path[:n]
    return ()


def _under(path: FieldPath, prefixes: set[FieldPath]) -> bool:
    return any(path[: len(p)] == p for p in prefixes)


def _drop(data: Any, path: FieldPath, bad: set[FieldPath], dropped: set[FieldPath]) -> bool:
    """Take a wrong field out of ``data``: a mapping's key goes (back to its default), a list
    item becomes a copy of a sound sibling (so later items keep their index), a list with no
    sound item goes whole; a required top-level field gets its stand-in. False if nothing
    could be dropped (the root)."""
    import copy

    while path:
        _, parent = _at(data, path[:-1])
        key = path[-1]
        if isinstance(parent, dict):
            if len(path) == 1 and key in _STAND_INS:
                if parent.get(key) == _STAND_INS[key] and path in dropped:
                    return False
                parent[key] = _STAND_INS[key]
            else:
                parent.pop(key, None)
            dropped.add(path)
            return True
        if isinstance(parent, list) and isinstance(key, int):
            sound = [
                i
                for i in range(len(parent))
                if i != key and not _under((*path[:-1], i), bad | dropped)
            ]
            if sound:
                stand_in = copy.deepcopy(parent[sound[0]])
                if isinstance(stand_in, dict) and isinstance(stand_in.get("name"), str):
                    stand_in["name"] = f"<left out {key}>"  # no duplicate name of its own
                parent[key] = stand_in
                dropped.add(path)
                return True
        path = path[:-1]
    return False


def record_of(value: Any) -> Any:
    """A validated pydantic model as :class:`~kcheck.scene.accept.Record` values (what the
    acceptor builds for a valid file), so the loader reads one kind of value."""
    from pydantic import BaseModel

    if isinstance(value, BaseModel):
        fields = {k: record_of(getattr(value, k)) for k in type(value).model_fields}
        return Record(type(value).__name__, fields, set(value.model_fields_set))
    if isinstance(value, list):
        return [record_of(v) for v in value]
    if isinstance(value, dict):
        return {k: record_of(v) for k, v in value.items()}
    return value


def salvage(
    data: Any, problems: Problems, root: type[BaseModel] | None = None
) -> tuple[Record | None, set[FieldPath]]:
    """Validate ``data`` against ``root`` (the scene's model by default), recording every
    pydantic error; then, so that the checks of values run on the rest of the file too
    (every mistake of a file in one run), drop each wrong field and validate again until what
    is left validates. Returns the records of what is left (None if nothing could be kept)
    and the fields dropped or replaced: errors at, under or above them are consequences of
    the dropping, not mistakes (:func:`consequence_of`)."""
    import copy

    from pydantic import ValidationError

    if root is None:
        from kcheck.scene.models import SceneModel

        root = SceneModel
    work = copy.deepcopy(data)
    dropped: set[FieldPath] = set()
    said = {e.where for e in problems.errors if e.where}  # plain-value errors
    for path in sorted(said, key=len):
        if not _under(path, dropped):
            _drop(work, _existing(work, path), said, dropped)
    first = True
    for _ in range(_SALVAGE_ROUNDS):
        try:
            return record_of(root.model_validate(work)), dropped
        except ValidationError as exc:
            if first:
                pydantic_problems(exc, root, problems)
            first = False
            paths = [
                _existing(work, _resolve(tuple(e["loc"]), root)[0])
                for e in exc.errors(include_url=False)
            ]
        bad = set(paths)
        changed = False
        for path in sorted(bad, key=len):
            if path and _under(path, dropped) and path not in dropped:
                continue  # an item replaced this round already
            changed |= _drop(work, path, bad, dropped)
        if not changed:
            return None, dropped
    return None, dropped


def consequence_of(where: FieldPath | None, dropped: set[FieldPath]) -> bool:
    """Whether an error at ``where`` may only follow from dropping the fields ``dropped``
    (:func:`salvage`): it sits at, under or above one of them; the supports' and couplings'
    counts and layout are one thing, so dropping either's item touches both."""
    if not dropped or where is None:
        return False
    if _under(where, dropped) or any(d[: len(where)] == where for d in dropped):
        return True
    layout = {("supports",), ("couplings",)}
    return where in layout and any(d[:1] in layout for d in dropped)
