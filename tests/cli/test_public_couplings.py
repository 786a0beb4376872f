"""`kcheck contacts` on public coupling designs not written here (fixtures/<design>/, each with
its ATTRIBUTION.md and derivation.py): it finds every hand-derived contact within 0.01 mm and
every normal within 0.1 deg, and the scene it writes gets the same verdicts and friction
limits as the hand-written fixture. The reference contacts are geometry.json, written by the
fixture's derivation.py with numpy/scipy/trimesh alone, from what the design publishes: its
meshes (the probe), its cutting files (the Voron bed mounts) or its parameters (the ASPE design
script's sample coupling)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

pytest.importorskip("trimesh")

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact_comparison import (  # noqa: E402
    NORMAL_TOL_DEG,
    POINT_TOL_MM,
    assert_same_checks,
    checks,
    matched,
    one_to_one,
    supports,
)

from kcheck.cli import main  # noqa: E402

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures"
# (fixture folder, base mesh, body mesh, hand-written scene, material given to kcheck contacts)
DESIGNS = [
    (
        "mostly-printed-probe",
        "base_pins.stl",
        "spider_pins.stl",
        "probe.kcheck.yaml",
        "tungsten-carbide",
    ),
    (
        "aspe-kc-design-script",
        "base_vees.stl",
        "body_balls.stl",
        "coupling.kcheck.yaml",
        "52100",
    ),
    (
        "voron-kinematic-bed",
        "base_pins.stl",
        "bed_balls.stl",
        "bed.kcheck.yaml",
        "52100",
    ),
]


@pytest.mark.parametrize(("design", "base", "body", "hand", "material"), DESIGNS)
def test_contacts_found_on_a_public_design(design, base, body, hand, material, tmp_path, capsys):
    folder = FIXTURES / design
    assert (folder / "ATTRIBUTION.md").is_file() and (folder / "derivation.py").is_file()
    out = folder / "found.kcheck.yaml"  # beside the meshes, so its mesh path is theirs
    try:
        code = main(
            [
                "contacts",
                str(folder / base),
                str(folder / body),
                "--units",
                "mm",
                "--material",
                material,
                "-o",
                str(out),
            ]
        )
        assert code == 0, capsys.readouterr().err
        capsys.readouterr()
        found = supports(out)
        derived = json.loads((folder / "geometry.json").read_text())["contacts"]
        reference = [(np.array(c["point"]), np.array(c["normal"])) for c in derived]
        assert len(found) == len(reference) == 6
        # Every hand-derived contact is found, one to one.
        pairs = matched(found, reference)
        assert one_to_one(found, reference)
        assert max(d for d, _ in pairs) <= POINT_TOL_MM, pairs
        assert max(a for _, a in pairs) <= NORMAL_TOL_DEG, pairs
        # The hand-written scene (rounded to 1e-4 mm) is the derivation's.
        written = matched(supports(folder / hand), reference)
        assert max(d for d, _ in written) <= 1e-4 and max(a for _, a in written) <= 1e-3
        # The scene kcheck writes checks as the hand-written one: same verdicts, same limits.
        # Its closing load and preloads are the designer's: set to the hand-written one's.
        hand_doc = yaml.safe_load((folder / hand).read_text())
        found_doc = yaml.safe_load(out.read_text())
        found_doc["load"] = hand_doc["load"]
        if "preloads" in hand_doc:
            found_doc["preloads"] = hand_doc["preloads"]
        out.write_text(yaml.safe_dump(found_doc))
        got, want = checks(out, capsys), checks(folder / hand, capsys)
    finally:
        out.unlink(missing_ok=True)
    assert_same_checks(got, want)
