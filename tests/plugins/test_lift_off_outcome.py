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
    lifted = 0
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
            lifts = result.details.get("lifts_off")
            if lifts:
                lifted += 1
                assert not held and result.outcome in ("loses_contact", "opens_loses_contact")
                assert result.retracted not in lifts
                assert result.normal_forces is not None
                assert all(result.normal_forces[n] == 0.0 for n in lifts)
                assert all(np.isfinite(f) and f >= 0 for f in result.normal_forces.values())
    assert lifted >= 14
