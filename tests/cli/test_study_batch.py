"""A study's chunk checked in one batch (``check_scenes``: each check given every variant at
once, ``analytical-3d`` stacking their algebra) gives exactly what each variant gives alone
(``check_scene``, the path of ``kcheck check``): the same rows, and the same whole results
bit for bit (floats compared through their exact JSON text), with and without the way-out
hints. The reference is computed in the test, one variant at a time."""

from __future__ import annotations

import dataclasses
import json
import math
import textwrap
from typing import Any

from kcheck.gate import study as engine
from kcheck.gate.runner import Settings, check_scene, check_scenes
from kcheck.plugin import load_checks
from kcheck.scene.load import scene_from_document
from kcheck.scene.study import load_study, variant_document
from tests.conftest import FIXTURES

SCENE = FIXTURES / "maxwell-three-vee" / "coupling.kcheck.yaml"

# The benchmark's study (benchmarks/bench_study.py): groove angle, μ and the load's point,
# wide enough that passing, marginal and failing variants all occur.
STUDY = """\
version: 1
scene: SCENE
design: {type: monte-carlo, samples: 24, seed: 3}
parameters:
  - {name: half_angle, path: couplings.*.groove.half_angle, range: [25, 60], unit: deg}
  - {name: mu, path: friction, distribution: {type: uniform, min: 0.02, max: 0.5}}
  - {name: load_x, path: load.point.0, distribution: {type: normal, mean: 0, sd: 20}, unit: mm}
checks: [analytical-3d]
figures: [analytical-3d.design_margin_deg, analytical-3d.limiting_friction,
  analytical-3d.robust_margin_deg, analytical-3d.safe_solid_angle_fraction]
"""


def _plain(result: Any) -> str:
    """A scene result as exact JSON text, without its run times."""

    def strip(x: Any) -> Any:
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if k != "runtime_s"}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x

    return json.dumps(strip(result.to_json()), sort_keys=True)


def _same_row(a: dict[str, Any], b: dict[str, Any]) -> bool:
    return a.keys() == b.keys() and all(
        a[k] == b[k]
        or (
            isinstance(a[k], float)
            and isinstance(b[k], float)
            and math.isnan(a[k])
            and math.isnan(b[k])
        )
        for k in a
    )


def _study(tmp_path):
    path = tmp_path / "b.kcheck-study.yaml"
    path.write_text(textwrap.dedent(STUDY).replace("SCENE", str(SCENE)), encoding="utf-8")
    return load_study(path)


def test_batched_chunk_gives_the_rows_of_one_variant_at_a_time(tmp_path):
    study = _study(tmp_path)
    checks = load_checks()
    settings = Settings(
        selected=frozenset(study.checks or ()), allow_outside=True, memo_mass=True, hints=False
    )
    n = engine.variant_count(study)
    together = engine.run_variants(study, checks, settings, 0, n)
    check_ids = [c.spec.name for c in checks if c.spec.name in settings.selected]
    alone = []
    for i in range(n):
        v = [col[i] for col in study.values()]
        doc = variant_document(study, v)
        result = check_scene(
            study.scene_path,
            checks,
            settings=settings,
            load=lambda doc=doc: scene_from_document(study.scene_path, doc, allow_outside=True),
        )
        alone.append(engine._row(study, i, v, result, check_ids))
    assert len(together) == len(alone) == n
    assert [
        i for i, (a, b) in enumerate(zip(together, alone, strict=True)) if not _same_row(a, b)
    ] == []
    # A study reads no hint: without them (the way-out searches and the ranges in a plane the
    # check does not report skipped) its rows are those of `kcheck check`'s full results.
    hinted = dataclasses.replace(settings, hints=True)
    assert engine.run_variants(study, checks, hinted, 0, 8) == together[:8]
    # Not vacuous: passing and failing variants, and figures with values.
    statuses = {r["status"] for r in together}
    assert "fail" in statuses and statuses & {"pass", "marginal"}
    assert sum(r["analytical-3d.design_margin_deg"] is not None for r in together) >= n // 4


def test_batched_results_equal_one_scene_at_a_time_with_hints(tmp_path):
    """The whole results (messages, findings with their hints, cases, details), as
    ``kcheck check`` would report each variant."""
    study = _study(tmp_path)
    checks = load_checks()
    settings = Settings(selected=frozenset(study.checks or ()), allow_outside=True)
    docs = [variant_document(study, [col[i] for col in study.values()]) for i in range(8)]

    def load(doc):
        return lambda: scene_from_document(study.scene_path, doc, allow_outside=True)

    together = check_scenes(study.scene_path, checks, settings, [load(d) for d in docs])
    alone = [check_scene(study.scene_path, checks, settings=settings, load=load(d)) for d in docs]
    assert [_plain(r) for r in together] == [_plain(r) for r in alone]
    assert {r.status.value for r in together} >= {"fail"}
