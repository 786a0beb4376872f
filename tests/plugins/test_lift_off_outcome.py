"""analytical-2d/3d say ``jams`` only where friction can hold the body: where no equilibrium
exists (the `jamming` check's exact test, an independent computation: a cone's facets
planar, a conic programme spatial) a case neither sliding assumption fits lifts a kept contact
off (kcheck.mechanics.lift_off), as the `reseat` simulation shows (docs/validation.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from kcheck.analysis import analyse
from kcheck.analysis.jamming_cases import analyse_jamming, held_at, jam_statics
from kcheck.body.mass import body_mass_properties
from kcheck.scene import load_scene
from tests.plugins.reseat_agreement import generated


def test_jams_only_where_an_equilibrium_exists(tmp_path: Path) -> None:
    """On the reseat agreement's 100 generated scenes: every ``jams`` is held by `jamming`;
    every case that lifts off is one `jamming` finds no equilibrium for, and its lifted
    supports are kept ones with zero normal force. Before, 14 of these cases said ``jams``
    where no equilibrium exists (the simulation shows all 13 compared ones losing contact)."""
    lifted = may_hold = 0
    for path in generated(tmp_path, 100):
        scene = load_scene(path)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        analysis = analyse(scene, mass)
        statics, swept, design = jam_statics(scene, mass)
        assert design is not None
        jams = analyse_jamming(statics, swept, design)
        for r, result in enumerate(analysis.results):
            held = held_at(jams, jams.cases[r], design, statics.friction)
            if result.outcome == "jams":
                assert held, (path.name, result.retracted)
            if result.outcome in ("closes", "loses_contact", "opens", "opens_loses_contact"):
                # A moving case says "or held" exactly where jamming finds an equilibrium.
                assert bool(result.details.get("friction_may_hold")) == held, path.name
                may_hold += held
            lifts = result.details.get("lifts_off")
            if lifts:
                lifted += 1
                assert not held and result.outcome in ("loses_contact", "opens_loses_contact")
                assert result.retracted not in lifts
                assert result.normal_forces is not None
                assert all(result.normal_forces[n] == 0.0 for n in lifts)
                assert all(np.isfinite(f) and f >= 0 for f in result.normal_forces.values())
    assert lifted >= 14 and may_hold >= 11


def test_a_case_friction_can_also_hold_says_so(tmp_path: Path, cli_json) -> None:
    """random-3d-1962, s5 retracted: analytical-3d's forward sliding loses s6 (a negative
    normal force), and `jamming` finds an equilibrium there too: the finding says both."""
    (path,) = [p for p in generated(tmp_path, 30) if p.name == "random-3d-1962.kcheck.yaml"]
    _, doc = cli_json(str(path), "--select", "analytical-3d,jamming")
    checks = {c["id"]: c for c in doc["scenes"][0]["checks"]}
    (s5,) = [c for c in checks["analytical-3d"]["cases"] if c["retracted"] == "s5"]
    (j5,) = [c for c in checks["jamming"]["cases"] if c["retracted"] == "s5"]
    assert s5["outcome"] == "loses_contact" and s5["friction_may_hold"] is True
    assert j5["outcome"] in ("jams", "holds")
    messages = [f["message"] for f in checks["analytical-3d"]["findings"]]
    (line,) = [m for m in messages if m.startswith("retract s5")]
    assert "or friction holds the body (an equilibrium exists too" in line


def test_a_jam_without_equilibrium_does_not_claim_friction_holds() -> None:
    """Where Lemke's method finds no lift-off motion either (``no_equilibrium``), the finding
    does not say friction holds the body: `jamming` finds no equilibrium."""
    from kcheck_checks.wording import _why

    from kcheck.result import CaseResult

    held = _why(CaseResult("s1", "jams", details={}), None)
    unheld = _why(CaseResult("s1", "jams", details={"no_equilibrium": True}), None)
    assert held is not None and unheld is not None
    assert "friction holds the body" in held[1]
    assert "friction holds the body" not in unheld[1] and "nor be held" in unheld[1]
