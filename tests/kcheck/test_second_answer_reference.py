"""The second answer's search (kcheck.analysis.held_alternatives) gives today the answers
recorded before it was made faster (tests/golden/second_answer_reference.json, written by
tests/record_second_answer_reference.py at the commit it names): on every held case of 300
generated spatial scenes, 100 random spatial and 100 random planar scenes and the fixtures, the
same supports lifted, or no second answer, as before."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from kcheck.analysis.held_alternatives import held_alternatives
from kcheck.body.mass import body_mass_properties
from kcheck.scene import load_scene
from tests.record_second_answer_reference import OUT, ROOT, scene_sets


def test_the_search_answers_as_recorded(tmp_path: Path) -> None:
    reference = json.loads(OUT.read_text(encoding="utf-8"))
    counts = reference["counts"]
    sets = scene_sets(tmp_path, counts["spatial"], counts["random-3d"], counts["random-2d"])
    compared = found = 0
    for name, paths in sets.items():
        recorded = reference["cases"][name]
        for path in paths:
            key = str(path.relative_to(ROOT)) if name == "fixtures" else path.name
            if key not in recorded:
                continue
            scene = load_scene(path)
            assert scene.body is not None
            mass = body_mass_properties(scene.body, scene.scale)
            cases = [(r, np.asarray(kept)) for r, kept, _ in recorded[key]]
            answers = held_alternatives(scene, mass, cases)
            for r, _, lifted in recorded[key]:
                assert answers[r] == lifted, (name, key, r)
                compared += 1
                found += lifted is not None
    # The reference's size (recorded: 756 held cases, 72 with a second answer).
    assert compared == 756 and found == 72
