"""The scene acceptor (issue 24: a valid file is read without pydantic) against pydantic.

The acceptor must never accept what the pydantic models refuse (their error records are
kcheck's only source of error wording), and must build the values they build where both
accept. Compared on every scene file of the repository, the error-location corpus, and
seeded random mutations of them; and its table must still be the one the models give.
"""

from __future__ import annotations

import copy
import random
from pathlib import Path
from typing import Any

import pytest
from pydantic import ValidationError

from kcheck.scene.accept import FIELDS, Record, accept
from kcheck.scene.models import SceneModel
from kcheck.scene.validate import record_of
from kcheck.scene.yamlio import read_yaml
from tests.kcheck.scene_fields import derive

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted(
    p
    for folder in ("fixtures", "docs", "tests")
    for p in (ROOT / folder).rglob("*.kcheck.yaml")
    if "golden" not in p.parts
)


def pydantic_records(data: Any) -> Record | None:
    """What the models make of a document, as records; None when they refuse it."""
    try:
        return record_of(SceneModel.model_validate(data))
    except ValidationError:
        return None


def agree(data: Any) -> None:
    ours = accept(copy.deepcopy(data))
    theirs = pydantic_records(copy.deepcopy(data))
    if theirs is None:
        assert ours is None, data
    elif ours is not None:  # the acceptor may leave a valid document to pydantic, never more
        assert ours == theirs, data
        assert _types(ours) == _types(theirs), data


def _types(value: Any) -> Any:
    """The value with every leaf replaced by its type (1 and 1.0 are equal, not the same)."""
    if isinstance(value, Record):
        return (value.model_name, {k: _types(v) for k, v in vars(value).items()})
    if isinstance(value, list):
        return [_types(v) for v in value]
    if isinstance(value, dict):
        return {k: _types(v) for k, v in value.items()}
    return type(value)


def test_the_table_is_the_models():
    assert derive() == FIELDS


def test_every_scene_file_is_accepted_as_pydantic_reads_it():
    assert len(SCENES) >= 10
    accepted = 0
    for path in SCENES:
        data = read_yaml(path).data
        agree(data)
        accepted += accept(data) is not None and pydantic_records(data) is not None
    # The acceptor is the common path: it reads every valid file the repository has.
    valid = sum(pydantic_records(read_yaml(p).data) is not None for p in SCENES)
    assert accepted == valid > 0


def test_the_error_corpus_is_refused_where_pydantic_refuses_it():
    import yaml

    from tests.kcheck import test_error_locations as corpus

    for base, edit, _, _ in corpus.CORPUS.values():
        if isinstance(edit, str):
            data = yaml.safe_load(edit)
        else:
            data = copy.deepcopy(base) or {}
            edit(data)
        agree(data)


# Values a mutation puts anywhere: each kind the models tell apart, at and past their limits.
VALUES: list[Any] = [
    None,
    True,
    False,
    0,
    1,
    -1,
    2,
    0.5,
    1.0,
    -0.0,
    1e9,
    -400.0,
    90.0,
    100.0,
    100.5,
    float("inf"),
    float("nan"),
    10**400,
    52100,
    "52100",
    "",
    "x" * 201,
    "steel",
    "mm",
    "metre",
    "ball-vee",
    "ball-flat",
    "body",
    "base",
    [],
    [1, 2],
    [1, 2, 3],
    [1.0, 0.0, 0.0],
    [None, 1.0],
    [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
    [1, "2", 3],
    {},
    {"min": 0.1, "max": 0.2},
    {"static": 0.2, "kinetic": 0.1},
    {"static": {"min": 0.1, "max": 0.2}, "kinetic": 0.1},
    {"axis": [0, 0, 1], "angle": 30},
    {1: 2},
    ("tuple", 1),
]


def _paths(value: Any, path: tuple = ()) -> list[tuple]:
    out = [path]
    if isinstance(value, dict):
        for k, v in value.items():
            out += _paths(v, (*path, k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            out += _paths(v, (*path, i))
    return out


def _mutate(data: Any, rng: random.Random) -> Any:
    data = copy.deepcopy(data)
    path = rng.choice(_paths(data)[1:])
    parent = data
    for part in path[:-1]:
        parent = parent[part]
    key = path[-1]
    move = rng.random()
    if move < 0.15 and isinstance(parent, dict):
        del parent[key]
    elif move < 0.25 and isinstance(parent, dict):
        parent[rng.choice(["fricton", "extra", "type", "min", "static", "units"])] = rng.choice(
            VALUES
        )
    elif move < 0.3 and isinstance(parent, list):
        parent.append(copy.deepcopy(parent[key]))
    else:
        parent[key] = copy.deepcopy(rng.choice(VALUES))
    return data


@pytest.mark.parametrize("seed", range(4))
def test_mutated_scenes_are_never_accepted_where_pydantic_refuses(seed):
    rng = random.Random(seed)
    bases = [read_yaml(p).data for p in SCENES]
    bases = [b for b in bases if isinstance(b, dict) and pydantic_records(b) is not None]
    for _ in range(600):
        data = rng.choice(bases)
        for _ in range(rng.choice([1, 1, 2, 3])):
            data = _mutate(data, rng)
        agree(data)


def test_non_finite_numbers_are_refused_whatever_their_float_type():
    import numpy as np

    for bad in (float("inf"), float("nan"), np.float64("inf"), np.float64("nan")):
        assert accept({"version": 1, "gravity": [bad, 0.0, 0.0]}) is None
    assert accept({"version": 1, "gravity": [np.float64(1.5), 0, 0]}) is not None
    agree({"version": 1, "gravity": [np.float64(1.5), 0, 0], "friction": np.float64(0.2)})
