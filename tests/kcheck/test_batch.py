"""The scenes of a chunk analysed in one batch (issue 24) give exactly what each gives alone.

:func:`kcheck.analysis.analyse_many` stacks the cases of every scene (free twists, both friction
systems, the friction-interval pencils) and solves them in one batch of numpy calls. Each
matrix of a stack is still equilibrated, factorised and decomposed on its own (numpy's
batched LAPACK calls loop over the matrices), and every other operation is elementwise or per
row, so the values are the same bits as one scene at a time: the tolerance is zero (NaN equal
to NaN). The values of one scene at a time against those recorded before the speed work
(1e-9 relative) are ``tests/kcheck/test_speed_reference.py``'s.

Scenes: the fixtures with mass properties (planar and spatial mixed in one batch: they are
grouped by system size) and 40 generated spatial scenes (``tests/spatial_scenes.py``).
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from kcheck.analysis import analyse, analyse_many
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.dynamics import analyse_cases, analyse_cases_many
from kcheck.mechanics.friction import friction_intervals_batch, friction_intervals_many
from kcheck.scene import load_scene

TESTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TESTS))

from spatial_scenes import write_spatial_scenes  # noqa: E402

FIXTURES = TESTS.parent / "fixtures"


def _same(a: object, b: object, where: str = "") -> list[str]:
    """Where ``a`` and ``b`` differ (bit for bit; NaN equals NaN), recursively."""
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        if type(a) is not type(b):
            return [f"{where}: {type(a).__name__} vs {type(b).__name__}"]
        return [
            d
            for f in dataclasses.fields(a)
            for d in _same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
        ]
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        ok = a.shape == b.shape and (
            np.array_equal(a, b, equal_nan=a.dtype.kind in "fc")
            if a.dtype.kind in "fc"
            else np.array_equal(a, b)
        )
        return [] if ok else [f"{where}: arrays differ"]
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        if a.keys() != b.keys():
            return [f"{where}: keys differ"]
        return [d for k in a for d in _same(a[k], b[k], f"{where}.{k}")]
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        if len(a) != len(b):
            return [f"{where}: lengths differ"]
        return [
            d
            for i, (x, y) in enumerate(zip(a, b, strict=True))
            for d in _same(x, y, f"{where}[{i}]")
        ]
    if isinstance(a, float) and isinstance(b, float) and np.isnan(a) and np.isnan(b):
        return []
    if hasattr(a, "__dict__") and type(a) is type(b):
        return _same(vars(a), vars(b), where)
    return [] if a == b else [f"{where}: {a!r} vs {b!r}"]


def _scenes(tmp_path: Path) -> list:
    paths = sorted(FIXTURES.glob("*/*.kcheck.yaml"))
    paths += write_spatial_scenes(tmp_path, range(40))
    scenes = [load_scene(p) for p in paths]
    return [s for s in scenes if s.body is not None]


def test_analyse_many_equals_one_scene_at_a_time(tmp_path: Path) -> None:
    scenes = _scenes(tmp_path)
    assert {s.dim for s in scenes} == {2, 3}  # both sizes of system in one batch
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]
    together = analyse_many(scenes, masses)
    alone = [analyse(s, m) for s, m in zip(scenes, masses, strict=True)]
    assert len(together) == len(alone) == len(scenes)
    differences = [
        d for s, x, y in zip(scenes, together, alone, strict=True) for d in _same(x, y, s.name)
    ]
    assert differences == []
    # Not vacuous: the batch holds closing cases with finite limiting friction.
    limits = [r.limiting_friction for a in together for r in a.results]
    assert sum(1 for v in limits if v is not None and np.isfinite(v)) > 50


def test_mechanics_batch_equals_one_problem_at_a_time(tmp_path: Path) -> None:
    from kcheck.analysis.cases import problem_for

    scenes = [s for s in _scenes(tmp_path) if s.load is not None]
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]
    problems = [problem_for(s, m) for s, m in zip(scenes, masses, strict=True)]
    directions = [
        None if s.load.direction is None else s.load.direction[: p.dim]
        for s, p in zip(scenes, problems, strict=True)
    ]
    cases = analyse_cases_many(problems)
    intervals = friction_intervals_batch(problems, cases, directions)
    for p, d, c, i in zip(problems, directions, cases, intervals, strict=True):
        one = analyse_cases(p)
        assert _same(c, one) == []
        assert _same(i, friction_intervals_many(p, one, d)) == []


def test_one_singular_matrix_does_not_spoil_its_stack() -> None:
    from kcheck.mechanics.dynamics import solve_each

    # Closed form: diag(2, 4) x = (2, 4) gives x = (1, 1); the zero matrix has no solution.
    stack = np.array([np.diag([2.0, 4.0]), np.zeros((2, 2)), np.diag([2.0, 4.0])])
    rhs = np.array([[[2.0], [4.0]]] * 3)
    x, ok = solve_each(stack, rhs)
    assert ok.tolist() == [True, False, True]
    assert x[0, :, 0].tolist() == [1.0, 1.0] and x[2, :, 0].tolist() == [1.0, 1.0]
    assert np.all(np.isnan(x[1]))
