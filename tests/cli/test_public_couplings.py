"""`kcheck contacts` on public coupling designs not written here (fixtures/<design>/, each with
its ATTRIBUTION.md and derivation.py): it finds every hand-derived contact within 0.01 mm and
every normal within 0.1 deg, and the scene it writes gets the same verdicts and friction
limits as the hand-written fixture. The reference contacts are geometry.json, written by the
fixture's derivation.py with numpy/scipy/trimesh alone, from what the design publishes: its
meshes (the probe), its cutting files (the Voron bed mounts) or its parameters (the ASPE design
script's sample coupling)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

pytest.importorskip("trimesh")

from kcheck.cli import main  # noqa: E402
from kcheck.scene.load import load_scene  # noqa: E402

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
POINT_TOL_MM = 0.01
NORMAL_TOL_DEG = 0.1


def _supports(scene_path):
    """The scene's point contacts (mm, unit normals), shorthands expanded as kcheck loads them."""
    scene = load_scene(scene_path)
    return [(s.position / scene.scale, s.normal / np.linalg.norm(s.normal)) for s in scene.supports]


def _matched(found, reference):
    """Each reference contact paired with the nearest found one: (distance mm, angle deg)."""
    out = []
    for p, n in reference:
        k = int(np.argmin([np.linalg.norm(q - p) for q, _ in found]))
        q, m = found[k]
        out.append(
            (float(np.linalg.norm(q - p)), float(np.degrees(np.arccos(np.clip(m @ n, -1.0, 1.0)))))
        )
    return out


def _checks(path, capsys):
    assert main(["check", str(path), "--format", "json", "-j", "1"]) in (0, 1)
    scene = json.loads(capsys.readouterr().out)["scenes"][0]
    return {c["id"]: c for c in scene["checks"]}


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
        found = _supports(out)
        derived = json.loads((folder / "geometry.json").read_text())["contacts"]
        reference = [(np.array(c["point"]), np.array(c["normal"])) for c in derived]
        assert len(found) == len(reference) == 6
        # Every hand-derived contact is found, one to one.
        pairs = _matched(found, reference)
        assert (
            len({int(np.argmin([np.linalg.norm(q - p) for q, _ in found])) for p, _ in reference})
            == 6
        )
        assert max(d for d, _ in pairs) <= POINT_TOL_MM, pairs
        assert max(a for _, a in pairs) <= NORMAL_TOL_DEG, pairs
        # The hand-written scene (rounded to 1e-4 mm) is the derivation's.
        written = _matched(_supports(folder / hand), reference)
        assert max(d for d, _ in written) <= 1e-4 and max(a for _, a in written) <= 1e-3
        # The scene kcheck writes checks as the hand-written one: same verdicts, same limits.
        # Its closing load and preloads are the designer's: set to the hand-written one's.
        hand_doc = yaml.safe_load((folder / hand).read_text())
        found_doc = yaml.safe_load(out.read_text())
        found_doc["load"] = hand_doc["load"]
        if "preloads" in hand_doc:
            found_doc["preloads"] = hand_doc["preloads"]
        out.write_text(yaml.safe_dump(found_doc))
        got, want = _checks(out, capsys), _checks(folder / hand, capsys)
    finally:
        out.unlink(missing_ok=True)
    assert got.keys() == want.keys()
    for check_id in want:
        assert got[check_id]["status"] == want[check_id]["status"], check_id
        # Each margin: the force-angle margin (deg), the least holding friction over the
        # design friction (jamming: the friction limit), Maxwell's least cos.
        if "margin" in want[check_id]:
            assert got[check_id]["margin"]["value"] == pytest.approx(
                want[check_id]["margin"]["value"], rel=1e-3
            ), check_id
    # analytical-3d's margins (deg), whichever the scene's load reports.
    margins = ("design_margin_deg", "robust_margin_deg", "sweep_design_margin_deg")
    reported = [k for k in margins if want["analytical-3d"].get(k) is not None]
    assert reported == [k for k in margins if got["analytical-3d"].get(k) is not None]
    assert reported, want["analytical-3d"]
    for key in reported:
        assert got["analytical-3d"][key] == pytest.approx(want["analytical-3d"][key], abs=0.05)
