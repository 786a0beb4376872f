"""Mutated fixture scenes (kinds ``mutation`` and ``extreme``), each with what the documented
contract says must come of it."""

from __future__ import annotations

import copy
import math
import random
from typing import Any

from tests.fuzz.contract import MATERIALS, fmt_path, judge_number_field
from tests.fuzz.model import ANY, Case, Claim, Expect
from tests.fuzz.scenes import dump, encode, equivalent, fixtures, get, put, walk

__all__ = ["mutation_case", "extreme_case", "valid_case", "fixture_copy", "mutate", "EXTREMES"]

EXTREMES: tuple[Any, ...] = (
    math.inf,
    -math.inf,
    math.nan,
    1e308,
    -1e308,
    1.7976931348623157e308,
    5e-324,
    -5e-324,
    2.2250738585072014e-308,
    1e-300,
    1e300,
    1e200,
    1e155,
    1e150,
    1e-150,
    1e-155,
    1e16,
    1e-16,
    1e-9,
    1e-10,
    1e6,
    1e7,
    1e9,
    3e4,
    100.0,
    -1.0,
    0.0,
    -0.0,
    2**63,
    -(2**63),
    10**301,
    10**400,
)
STRINGS = (
    "",
    " ",
    "x",
    "\x00",
    "a\x00b",
    "\ud800",
    "\udcff\ud800",
    "\u202eevil",
    "\n",
    "\t",
    "x" * 201,
    "x" * 10000,
    "../../etc/passwd",
    "/etc/passwd",
    "/dev/zero",
    "1e3",
    "yes",
    "null",
    "10",
    "\x7f\x01\x1b[31m",
)
Path = tuple[Any, ...]
#: What a mutation did, what must come of it, and the field its claims are about.
Op = tuple[str, Expect, "Path | None"]
TYPOS = ("frictoin", "normals", "positon", "Mass", "center-of-mass", "loads", "xyz", "__class__")


def _scalar_paths(data: dict) -> list[tuple[Any, ...]]:
    return [p for p, v in walk(data) if p and not isinstance(v, (dict, list))]


def _number_paths(data: dict) -> list[tuple[Any, ...]]:
    return [
        p
        for p, v in walk(data)
        if p and isinstance(v, (int, float)) and not isinstance(v, bool) and p != ("version",)
    ]


def _vector_paths(data: dict) -> list[tuple[Any, ...]]:
    return [
        p
        for p, v in walk(data)
        if p and isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v)
    ]


def _retype(data: dict, rng: random.Random) -> Op:
    """A value of another type (or an odd string) where a scalar or vector was."""
    paths = _scalar_paths(data) + _vector_paths(data)
    path = rng.choice(paths)
    old = get(data, path)
    new: Any = rng.choice(
        (
            rng.choice(STRINGS),
            True,
            None,
            [],
            [1, 2],
            {"a": 1},
            rng.choice(EXTREMES),
            "10",
        )
    )
    put(data, path, new)
    where = fmt_path(path)
    what = f"{where}: {old!r} -> {new!r}"
    return what, _retype_expect(data, path, old, new), path


def _retype_expect(data: dict, path: tuple[Any, ...], old: Any, new: Any) -> Expect:
    where = fmt_path(path)
    if path[0] == "checks":
        if isinstance(new, str) and _surrogate(new):
            return _invalid(None, "strings are valid Unicode text")
        bad = isinstance(new, str) and "\x00" in new
        return _invalid(where, "a NUL character") if bad else ANY
    if isinstance(new, str) and "\x00" in new:
        return _invalid(where, "strings are valid text without NUL")
    if isinstance(new, str) and _surrogate(new):
        # Only writable as an escape, which the YAML parser itself refuses: anywhere located.
        return _invalid(None, "strings are valid Unicode text")
    if new is None:
        return ANY
    number = isinstance(old, (int, float)) and not isinstance(old, bool)
    if path == ("version",):
        return ANY if new == 1 and type(new) is int else _invalid(where, "version 1")
    if number and (isinstance(new, (str, bool, list, dict))):
        return _invalid(where, "a number")
    if isinstance(old, list) and not isinstance(new, list):
        return _invalid(where, "a list of 3 numbers")
    if isinstance(old, list) and isinstance(new, list) and len(new) != 3:
        return _invalid(where, "a list of 3 numbers")
    if isinstance(old, str) and not isinstance(new, str):
        return _invalid(where, "a string")
    if isinstance(old, bool) and not isinstance(new, bool):
        return _invalid(where, "true or false")
    if number and isinstance(new, (int, float)):
        return judge_number_field(data, path)
    if isinstance(old, str) and isinstance(new, str):
        return _judge_string(path, new)
    return ANY


def _surrogate(text: str) -> bool:
    return any(0xD800 <= ord(c) <= 0xDFFF for c in text)


def _judge_string(path: tuple[Any, ...], new: str) -> Expect:
    where = fmt_path(path)
    name = path[-1]
    if name == "units" and new not in ("m", "cm", "mm", "um", "in"):
        return _invalid(where, "a known unit")
    if name == "type" and path[0] == "couplings":
        known = (
            "ball-vee",
            "ball-cylinders",
            "ball-sphere",
            "ball-trihedral",
            "ball-cone",
            "ball-flat",
        )
        return ANY if new in known else _invalid(where, "a coupling type")
    if name == "ball_on" and new not in ("body", "base"):
        return _invalid(where, "body or base")
    if name == "material" and new not in MATERIALS:
        return _invalid(where, "a name of the material table")
    if name == "mesh":
        return _invalid(where, "an existing mesh file in the scene's folder")
    if name == "name" and len(new) > 200:
        return _invalid(where, "a name of at most 200 characters")
    if name == "name" and new == "":
        return _invalid(where, "a non-empty name")
    return ANY


def _invalid(field: str | None, why: str) -> Expect:
    return Expect("invalid", (Claim(field, why),))


def _delete(data: dict, rng: random.Random) -> Op:
    paths = [p for p, v in walk(data) if p and isinstance(p[-1], str)]
    path = rng.choice(paths)
    del get(data, path[:-1])[path[-1]]
    return f"{fmt_path(path)} deleted", ANY, None


def _unknown_key(data: dict, rng: random.Random) -> Op:
    maps = [p for p, v in walk(data) if isinstance(v, dict) and (not p or p[0] != "checks")]
    path = rng.choice(maps)
    key = rng.choice(TYPOS)
    holder = get(data, path)
    if key in holder:
        return "nothing", ANY, None
    holder[key] = rng.choice((1, "x", [1, 2, 3], None, {"a": 1}))
    where = (*path, key)
    return f"unknown key {fmt_path(where)}", _invalid(fmt_path(where), "known keys"), where


def _unknown_check(data: dict, rng: random.Random) -> Op:
    key = rng.choice(("maxwel", "analytical2d", "nope", "MAXWELL", ""))
    data.setdefault("checks", {})
    if not isinstance(data["checks"], dict):
        return "nothing", ANY, None
    data["checks"][key] = rng.choice(({}, None, {"severity": "warning"}))
    where = ("checks", key)
    return f"options of unknown check {key!r}", _invalid(fmt_path(where), "a check id"), where


def _list_edit(data: dict, rng: random.Random) -> Op:
    lists = [p for p, v in walk(data) if p and isinstance(v, list) and v]
    if not lists:  # an earlier edit deleted or retyped every list
        return "nothing", ANY, None
    path = rng.choice(lists)
    items = get(data, path)
    vector = _is_vector(items)
    op = rng.randrange(3)
    if op == 0:
        items.append(copy.deepcopy(rng.choice(items)))
    elif op == 1:
        items.pop(rng.randrange(len(items)))
    else:
        items.insert(rng.randrange(len(items) + 1), copy.deepcopy(rng.choice(items)))
    what = f"{fmt_path(path)}: {('append', 'pop', 'insert')[op]}"
    if vector and path[0] != "checks":
        return what, _invalid(fmt_path(path), VECTOR), path
    return what, ANY, None


VECTOR = "a list of 3 numbers"


def _is_vector(items: Any) -> bool:
    return (
        isinstance(items, list)
        and len(items) == 3
        and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in items)
    )


def _swap(data: dict, rng: random.Random) -> Op:
    paths = _number_paths(data)
    if len(paths) < 2:
        return "nothing", ANY, None
    a, b = rng.sample(paths, 2)
    va, vb = get(data, a), get(data, b)
    put(data, a, vb)
    put(data, b, va)
    # Judged on the final data (mutation_case): both fields are watched.
    return f"{fmt_path(a)} <-> {fmt_path(b)}", ANY, None


def _renumber(data: dict, rng: random.Random) -> Op:
    """A plausible wrong number: negated, zero, scaled by a power of ten."""
    path = rng.choice(_number_paths(data))
    old = get(data, path)
    power = rng.randint(-12, 12)  # drawn first, as before: seeds reproduce earlier campaigns
    which = rng.choice(range(5))
    try:
        new = (-old, 0, old * 10**power, old + 1, abs(old) * 1e3 + 1)[which]
    except OverflowError:  # an integer too large for a float (seed 4244): negate it instead
        new = -old
    put(data, path, new)
    return f"{fmt_path(path)}: {old!r} -> {new!r}", judge_number_field(data, path), path


STRUCTURAL = (_retype, _retype, _delete, _unknown_key, _unknown_check, _list_edit, _swap, _renumber)


def _combine(expects: list[Expect]) -> Expect:
    claims = tuple(c for e in expects if e.outcome == "invalid" for c in e.claims)
    return Expect("invalid", claims) if claims else ANY


def _text_damage(text: str, rng: random.Random) -> tuple[str, str]:
    lines = text.splitlines()
    op = rng.randrange(6)
    i = rng.randrange(len(lines))
    if op == 0:
        del lines[i]
        what = f"line {i + 1} deleted"
    elif op == 1:
        lines.insert(i, lines[rng.randrange(len(lines))])
        what = f"a line duplicated at {i + 1}"
    elif op == 2:
        lines[i] = " " * rng.randrange(1, 5) + lines[i]
        what = f"line {i + 1} indented"
    elif op == 3:
        cut = rng.randrange(len(text) + 1)
        return text[:cut], f"truncated at character {cut}"
    elif op == 4:
        pos = rng.randrange(len(text) + 1)
        token = rng.choice(("[", "]", "{", "}", ":", "- ", "&a ", "*a", "!!", "'", '"', "\t", "%"))
        return text[:pos] + token + text[pos:], f"{token!r} inserted at character {pos}"
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
        what = f"lines {i + 1} and {j + 1} swapped"
    return "\n".join(lines) + "\n", what


def _case_files(fixture_files: dict[str, bytes], scene: str, raw: bytes) -> dict[str, Any]:
    return {**fixture_files, scene: raw}


def mutation_case(seed: int, index: int) -> Case:
    """A fixture scene mutated on its data (1-3 changes), sometimes damaged as text after."""
    rng = random.Random(f"{seed}:mutation:{index}")
    fx = rng.choice(fixtures())
    if rng.random() < 0.12:
        raw, what = equivalent(fx, rng)
        return Case(
            "mutation",
            seed,
            index,
            f"{fx.name}: {what}",
            _case_files(fx.files, fx.scene, raw),
            (fx.scene,),
            {fx.scene: Expect("valid", baseline=fx.name)},
        )
    data = copy.deepcopy(fx.data)
    done, expect = mutate(data, rng)
    text = dump(data, rng)
    if rng.random() < 0.15:
        text, what = _text_damage(text, rng)
        done.append(what)
        expect = ANY
    raw, encoding = (
        encode(text, rng) if rng.random() < 0.2 else (text.encode("utf-8", "surrogatepass"), "")
    )
    if encoding and encoding != "UTF-8":
        done.append(encoding)
    return Case(
        "mutation",
        seed,
        index,
        f"{fx.name}: " + "; ".join(done),
        _case_files(fx.files, fx.scene, raw),
        (fx.scene,),
        {fx.scene: expect},
    )


def mutate(data: dict, rng: random.Random) -> tuple[list[str], Expect]:
    """One to three structural mutations of a scene's data (in place): what was done, and
    what the documented contract says must come of it."""
    done: list[str] = []
    watched: list[tuple[Claim, Path, Any]] = []
    exact = True  # every change claims an error: the errors must be at the claims
    for _ in range(rng.choice((1, 1, 1, 2, 3))):
        what, expect, path = rng.choice(STRUCTURAL)(data, rng)
        done.append(what)
        exact &= bool(expect.claims)
        for claim in expect.claims:
            watched.append((claim, path, get(data, path)))
    expect = _still_claimed(data, watched)
    if expect.claims and not exact:
        expect = Expect("invalid", expect.claims, exact=False)
    return done, expect


def _still_claimed(data: dict, watched: list[tuple[Claim, Path, Any]]) -> Expect:
    """The claims true of the final data. A later change may have deleted, overwritten or
    moved (a list item removed) the field of an earlier one, so a claim about a value's type
    or shape is kept only if its field still holds the very value put there; numbers are
    judged afresh, every one of them (a swap may have moved a value out of its range)."""
    kept = []
    for claim, path, value in watched:
        try:
            now = get(data, path)
        except (KeyError, IndexError, TypeError):
            continue
        # A later edit of the same list (a pop, then an insert) may have made it whole again.
        if claim.why == VECTOR and _is_vector(now):
            continue
        if now is value and not claim.numeric:
            kept.append(claim)
    for path in _number_paths(data):
        kept.extend(judge_number_field(data, path).claims)
    unique = tuple(dict.fromkeys(kept))
    return Expect("invalid", unique) if unique else ANY


def extreme_case(seed: int, index: int) -> Case:
    """A fixture scene with one number (or a whole vector) at an extreme."""
    rng = random.Random(f"{seed}:extreme:{index}")
    fx = rng.choice(fixtures())
    data = copy.deepcopy(fx.data)
    if rng.random() < 0.3:
        path = rng.choice(_vector_paths(data))
        big = rng.choice(EXTREMES)
        vec = [rng.choice((big, 0.0, 1.0, -big)) for _ in range(3)]
        put(data, path, vec)
        checks = [judge_number_field(data, (*path, i)) for i in range(3)]
        expect = _combine(checks)
        what = f"{fmt_path(path)} = {vec!r}"
    else:
        path = rng.choice(_number_paths(data))
        value = rng.choice(EXTREMES)
        if rng.random() < 0.3 and isinstance(value, float) and math.isfinite(value):
            value *= rng.choice((0.5, 1.5, 1 - 1e-12, 1 + 1e-12))
        put(data, path, value)
        expect = judge_number_field(data, path)
        what = f"{fmt_path(path)} = {value!r}"
    raw = dump(data).encode()
    return Case(
        "extreme",
        seed,
        index,
        f"{fx.name}: {what}",
        _case_files(fx.files, fx.scene, raw),
        (fx.scene,),
        {fx.scene: expect},
    )


def valid_case(seed: int, index: int, kind: str = "valid") -> Case:
    """A rewrite of a fixture that must get the fixture's verdict."""
    rng = random.Random(f"{seed}:{kind}:{index}")
    fx = rng.choice(fixtures())
    raw, what = equivalent(fx, rng)
    return Case(
        kind,
        seed,
        index,
        f"{fx.name}: {what}",
        _case_files(fx.files, fx.scene, raw),
        (fx.scene,),
        {fx.scene: Expect("valid", baseline=fx.name)},
    )


def fixture_copy(name: str, index: int, seed: int = 0) -> Case:
    """A fixture as it is (the valid scenes mixed into every batch)."""
    fx = next(f for f in fixtures() if f.name == name)
    return Case(
        "fixture",
        seed,
        index,
        f"{fx.name} as it is",
        _case_files(fx.files, fx.scene, fx.text.encode()),
        (fx.scene,),
        {fx.scene: Expect("valid", baseline=fx.name)},
    )
