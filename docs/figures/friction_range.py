"""Draws docs/figures/friction-range.png: analytical-2d's safe force angles against μ.

Run: ``python docs/figures/friction_range.py`` (needs the `plot` extra). The planar block
fixture with its friction made a range, ``friction: {min: 0.05, max: 0.3}``, drawn by the same
code (and so in the same colours) as ``kcheck check --plots``
(:mod:`kcheck_checks.pictures.friction`).
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from kcheck_checks.analytical_2d import Analytical2D
from kcheck_checks.pictures.friction import plot_friction

from kcheck.body.mass import body_mass_properties
from kcheck.plugin import Inputs
from kcheck.scene import load_scene

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "fixtures" / "planar-block" / "block.kcheck.yaml"
OUT = Path(__file__).with_name("friction-range.png")
FIXED, RANGE = "friction: 0.1\n", "friction: {min: 0.05, max: 0.3}\n"


def main() -> None:
    text = SCENE.read_text(encoding="utf-8")
    if FIXED not in text:
        raise SystemExit(f"{SCENE}: expected a line {FIXED.strip()!r} to make a range of")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / SCENE.name
        path.write_text(text.replace(FIXED, RANGE), encoding="utf-8")
        shutil.copy(SCENE.with_name("block.stl"), Path(tmp) / "block.stl")
        scene = load_scene(path)
        assert scene.body is not None, f"{SCENE}: the fixture has a body"
        check = Analytical2D()
        inputs = Inputs(scene, body_mass_properties(scene.body, scene.scale), check.options())
        written = plot_friction(check.id, inputs, check.run(inputs), Path(tmp))
        shutil.copy(next(p for p in written if p.suffix == ".png"), OUT)
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
