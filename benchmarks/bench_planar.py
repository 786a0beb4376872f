"""Numerical error against run time for planar scenes and mass properties.

Run: ``python benchmarks/bench_planar.py``. Prints two tables (results in docs/performance.md):

1. safe-range ends from kcheck's closed form against the thesis's way — sweeping the force
   angle in fixed steps and reading the range off the samples — for several step sizes: the
   error of the range ends (degrees, against the closed form) and the time per scene;
2. mass properties of a cylinder mesh at several tessellations: the relative error of mass and
   I_zz against the smooth cylinder's closed form, and the time for load + gate + integrate.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import trimesh

from kcheck.analysis import analyse
from kcheck.body.mass import body_mass_properties, load_mesh, mesh_mass_properties
from kcheck.mechanics.arcs import boundary_angles, intersect
from kcheck.mechanics.outcomes import outcome
from kcheck.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "fixtures" / "planar-block" / "block.kcheck.yaml"


def timed(fn: Callable[[], object], repeat: int = 7) -> tuple[float, object]:
    """Median wall time (s) of ``fn`` over ``repeat`` runs, and its last value."""
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), value


def sweep_ends(analysis, step_deg: float) -> np.ndarray:
    """Range ends read off a fixed-step sweep of the outcome (the thesis's method)."""
    angles = np.arange(0.0, 360.0, step_deg)
    dirs = np.column_stack([np.cos(np.radians(angles)), np.sin(np.radians(angles))])
    safe = np.array([all(outcome(case, d)[0] == "closes" for case in analysis.cases) for d in dirs])
    change = np.flatnonzero(safe != np.roll(safe, 1))
    # The boundary lies somewhere in the step before the change: take its middle.
    return np.sort((angles[change] - step_deg / 2) % 360.0)


def planar_table() -> None:
    """Closed form versus fixed-step sweeps on the planar block fixture."""
    scene = load_scene(SCENE)
    mass = body_mass_properties(scene.body, scene.scale)
    t_exact, analysis = timed(lambda: analyse(scene, mass))
    exact = np.degrees(boundary_angles(intersect(*analysis.arcs)))
    print("planar block (fixtures/planar-block), 3 cases")
    print(f"{'method':<34}{'time per scene':>16}{'max error of range ends':>26}")
    print(
        f"{'closed form (kcheck)':<34}{t_exact * 1e3:>13.2f} ms{analysis.error_deg:>22.1e} deg"
        "  (estimate)"
    )
    for label, step in (
        ("sweep 0.1 rad (thesis)", np.degrees(0.1)),
        ("sweep 1 deg", 1.0),
        ("sweep 0.1 deg", 0.1),
        ("sweep 0.01 deg", 0.01),
    ):
        t, ends = timed(lambda s=step: sweep_ends(analysis, s), repeat=3)
        err = (
            np.max(np.abs((ends - exact + 180) % 360 - 180))
            if len(ends) == len(exact)
            else float("nan")
        )
        print(f"{label:<34}{t * 1e3:>13.2f} ms{err:>22.2e} deg")


def mass_table() -> None:
    """Mesh tessellation error against time for mass properties."""
    r, h, rho = 0.05, 0.12, 2700.0
    mass = rho * np.pi * r * r * h
    print("\ncylinder r = 50 mm, h = 120 mm, aluminium: mesh versus closed form")
    print(f"{'sections':>9}{'faces':>9}{'time':>12}{'mass rel. error':>18}{'I_zz rel. error':>18}")
    with tempfile.TemporaryDirectory() as tmp:
        for sections in (16, 64, 256, 1024, 4096):
            path = Path(tmp) / f"c{sections}.stl"
            mesh = trimesh.creation.cylinder(radius=r, height=h, sections=sections)
            mesh.export(path)

            def run(p: Path = path) -> object:
                return mesh_mass_properties(load_mesh(p, 1.0, "mesh"), rho, p, "mesh")

            t, props = timed(run, repeat=5)
            e_m = abs(props.mass / mass - 1)
            e_i = abs(props.inertia[2, 2] / (mass * r * r / 2) - 1)
            print(f"{sections:>9}{len(mesh.faces):>9}{t * 1e3:>9.2f} ms{e_m:>18.2e}{e_i:>18.2e}")


if __name__ == "__main__":
    planar_table()
    mass_table()
