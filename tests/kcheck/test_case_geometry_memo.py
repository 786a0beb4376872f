"""The cases of a problem whose geometry was met before (a way-out search's trial scenes:
the scene with another closing force) reuse it (:data:`kcheck.mechanics.dynamics._GEOMETRIES`)
and are bit for bit the cases computed afresh: the free twists, systems, conditioning and
effective masses do not depend on the load, only the solved unknowns do."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np

from kcheck.analysis.cases import problem_for
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics import dynamics
from kcheck.scene import load_scene

TESTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(TESTS))

from spatial_scenes import write_spatial_scenes  # noqa: E402


def _same(a: object, b: object, where: str = "") -> list[str]:
    """Where ``a`` and ``b`` differ, bit for bit (NaN equals NaN), through dataclasses."""
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        return [
            d
            for f in dataclasses.fields(a)
            for d in _same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
        ]
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        nan = a.dtype.kind in "fc"
        ok = a.shape == b.shape and np.array_equal(a, b, equal_nan=nan)
        return [] if ok else [where]
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)) and len(a) == len(b):
        return [
            d
            for n, (x, y) in enumerate(zip(a, b, strict=True))
            for d in _same(x, y, f"{where}[{n}]")
        ]
    same = a == b or (isinstance(a, float) and np.isnan(a) and np.isnan(b))  # type: ignore[arg-type]
    return [] if same else [where]


def test_cases_from_a_remembered_geometry_are_computed_afresh(tmp_path, monkeypatch) -> None:
    scenes = [load_scene(p) for p in write_spatial_scenes(tmp_path, range(12))]
    hits = 0
    for scene in scenes:
        mass = body_mass_properties(scene.body, scene.scale)
        assert scene.load is not None
        for factor in (0.5, 3.0):
            trial = dataclasses.replace(
                scene, load=dataclasses.replace(scene.load, magnitude=scene.load.magnitude * factor)
            )
            dynamics._GEOMETRIES.clear()
            fresh = dynamics.analyse_cases(problem_for(trial, mass))
            dynamics.analyse_cases(problem_for(scene, mass))  # remembers the geometry
            assert len(dynamics._GEOMETRIES) == 1
            remembered = dynamics.analyse_cases(problem_for(trial, mass))
            hits += len(dynamics._GEOMETRIES) == 1  # the trial found the scene's geometry
            assert _same(remembered, fresh) == []
            # ... and the load did change the unknowns (the test compares something).
            scene_cases = dynamics.analyse_cases(problem_for(scene, mass))
            solved = [c for c in fresh if c.forward is not None]
            assert solved and any(
                not np.array_equal(a.forward.a, b.forward.a)  # type: ignore[union-attr]
                for a, b in zip(scene_cases, fresh, strict=True)
                if a.forward is not None
            )
    assert hits == 24


def test_remembered_arrays_are_read_only(tmp_path) -> None:
    """A caller cannot change a remembered geometry through a case's arrays (the solved
    systems are stacked anew for each problem)."""
    (path,) = write_spatial_scenes(tmp_path, range(1))
    scene = load_scene(path)
    mass = body_mass_properties(scene.body, scene.scale)
    dynamics._GEOMETRIES.clear()
    case = dynamics.analyse_cases(problem_for(scene, mass))[0]
    assert case.k0 is not None and case.k_friction is not None
    for array in (case.free.twist, case.k0, case.k_friction):
        assert not array.flags.writeable


def test_a_batch_larger_than_the_memory_mixing_known_and_new_problems(tmp_path) -> None:
    """A batch of more problems than are remembered, some of them remembered already: each
    problem's cases are those it gets afresh (none lost to the memory's turnover)."""
    count = dynamics.RECENT_GEOMETRIES + 6
    scenes = [load_scene(p) for p in write_spatial_scenes(tmp_path, range(count))]
    problems = [problem_for(s, body_mass_properties(s.body, s.scale)) for s in scenes]
    dynamics._GEOMETRIES.clear()
    fresh = dynamics.analyse_cases_many(problems)
    dynamics._GEOMETRIES.clear()
    dynamics.analyse_cases_many(problems[:3])  # remembered, then the first to be dropped
    again = dynamics.analyse_cases_many(problems[::-1])[::-1]
    assert _same(again, fresh) == []
    assert len(dynamics._GEOMETRIES) == dynamics.RECENT_GEOMETRIES
