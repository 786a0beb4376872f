"""No input prints anything on stderr but kcheck's own lines (issue 25): every fixture with
every length multiplied by 1e-300, 1e-12, 1e-3, 1e3, 1e12 and 1e300 — the scene's lengths
alone (a units slip against the meshes), and the scene with its meshes (the whole design at
another scale) — checked by the command line with Python's warnings turned into errors
(``python -W error``), in one batch.

What must come out (docs/robustness.md, "Scaled layouts"): at 1e-300 and 1e-12 every scene is
an input error (a ball radius under 1 µm, a layout under 1 µm, a mesh whose mass is under
1e-9 kg), at 1e12 and 1e300 likewise (coordinates past 1000 m, radii past 10 m); at 1e-3 and
1e3 the scenes within the limits get verdicts and the others input errors. Never a
traceback, a check that crashed (a warning turned error inside a check would be one), an
internal error, or a stray line on stderr: there only ``kcheck: error:`` lines.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import trimesh

from tests.conftest import FIXTURES, ROOT
from tests.fuzz.harness import stray_stderr_lines

FACTORS = (1e-300, 1e-12, 1e-3, 1e3, 1e12, 1e300)
#: Scales at which no fixture is within the documented limits.
REFUSED = (1e-300, 1e-12, 1e12, 1e300)
POINTS = {"position", "point", "center", "center_of_mass", "translate"}


def scaled(value: Any, factor: float, name: str | None = None, parent: str | None = None) -> Any:
    """A scene's data with every length (coordinates, radii, the position tolerance) scaled."""
    if isinstance(value, dict):
        return {k: v if k == "checks" else scaled(v, factor, k, name) for k, v in value.items()}
    if isinstance(value, list):
        if name in POINTS and all(isinstance(x, (int, float)) for x in value):
            return [x * factor for x in value]
        return [scaled(v, factor, name, parent) for v in value]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if name == "radius" or (name == "position" and parent == "tolerances"):
            return value * factor
    return value


def ascii_stl(mesh: trimesh.Trimesh, factor: float) -> bytes:
    """The mesh scaled, as ASCII STL: its coordinates keep every digit of a float64 (a binary
    STL's float32 would round 1e-300 to 0 and 1e300 to infinity)."""
    lines = ["solid scaled"]
    for face in mesh.faces:
        lines += [" facet normal 0 0 0", "  outer loop"]
        for v in mesh.vertices[face]:
            lines.append("   vertex " + " ".join(repr(float(x) * factor) for x in v))
        lines += ["  endloop", " endfacet"]
    lines.append("endsolid scaled")
    return ("\n".join(lines) + "\n").encode()


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    import yaml

    from kcheck.scene.yamlio import load_yaml

    root = tmp_path_factory.mktemp("scaled")
    for factor in FACTORS:
        for what in ("scene", "whole"):
            for scene in sorted(FIXTURES.glob("*/*.kcheck.yaml")):
                folder = root / f"{factor:g}-{what}" / scene.parent.name
                folder.mkdir(parents=True)
                for other in scene.parent.iterdir():
                    if other == scene:
                        continue
                    if what == "whole" and other.suffix == ".stl":
                        mesh = trimesh.load_mesh(other, process=False)
                        (folder / other.name).write_bytes(ascii_stl(mesh, factor))
                    else:
                        (folder / other.name).write_bytes(other.read_bytes())
                data, _ = load_yaml(scene)
                (folder / scene.name).write_text(yaml.safe_dump(scaled(data, factor)))
    proc = subprocess.run(
        [sys.executable, "-W", "error", "-m", "kcheck", "check", "--format", "json"]
        + ["--no-cache", "-j", "2", "--isolated", str(root)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    return {"proc": proc, "doc": json.loads(proc.stdout) if proc.stdout else None}


def _factor(scene: dict[str, Any]) -> float:
    return float(Path(scene["path"]).parts[-3].rsplit("-", 1)[0])


def test_stderr_holds_only_kcheck_s_own_lines(run):
    proc, doc = run["proc"], run["doc"]
    assert doc is not None, proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr + proc.stdout
    stray = stray_stderr_lines(proc.stderr, doc)
    assert not stray, "\n".join(stray[:20])
    assert "Warning" not in proc.stderr
    assert proc.returncode == 2  # some scenes are input errors
    fixtures = len(list(FIXTURES.glob("*/*.kcheck.yaml")))
    assert len(doc["scenes"]) == fixtures * len(FACTORS) * 2


def test_no_check_crashes_and_no_internal_error(run):
    for scene in run["doc"]["scenes"]:
        crashed = [c["id"] for c in scene["checks"] if c["status"] == "error"]
        assert not crashed, (scene["path"], crashed)
        assert "internal error" not in json.dumps(scene), scene["path"]


def test_out_of_range_scales_are_located_input_errors(run):
    for scene in run["doc"]["scenes"]:
        if _factor(scene) not in REFUSED:
            continue
        assert scene["status"] == "error", scene["path"]
        for error in scene.get("errors", []):
            assert error.get("field") and error.get("line") and error.get("column"), error


def test_scales_within_the_limits_get_verdicts(run):
    verdicts = {factor: 0 for factor in FACTORS}
    for scene in run["doc"]["scenes"]:
        if scene["status"] != "error":
            verdicts[_factor(scene)] += 1
        else:
            assert scene.get("errors") and all(e.get("field") for e in scene["errors"]), scene[
                "path"
            ]
    # the algebra ran at a thousandth and a thousand times the fixtures' size
    assert verdicts[1e-3] >= 10 and verdicts[1e3] >= 10, verdicts
    assert all(verdicts[f] == 0 for f in REFUSED), verdicts
