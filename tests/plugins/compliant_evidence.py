"""Evidence for issue 26 (not the check): the compliant-contact test
(tests.plugins.compliant_hold) on every case `jamming` says friction holds, beside the
`reseat` simulation's first motion (tests/plugins/reseat_agreement.py's comparison).

For each held case, the largest friction usage ``|T| / (mu N)`` over the remaining contacts
after the release, per contact-stiffness assumption and tangential/normal ratio:

* ``equal``: the same normal stiffness at every contact (linear springs);
* ``hertz``: identical Hertzian contacts, stiffness ~ seated force^(1/3);
* ``mass``: MuJoCo's soft contacts, whose stiffness per constraint row scales with the row's
  effective mass ``1 / (w M^-1 w)`` (one time constant for every contact).

Run: PYTHONPATH=.:plugins python tests/plugins/compliant_evidence.py SEED OUT.json
(seed 26: the agreement test's scenes and its three fixtures; 4-10 min a seed), then
``... compliant_evidence.py table OUT.json SEED`` for docs/validation.md's table rows (the
compliant tests computed again, the simulated classes from OUT.json).
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np

from kcheck.mechanics.kinematics import wrenches
from kcheck.mechanics.seat import contact_forces, external_wrench, seat_layout, seated_loads
from kcheck.result import MassProperties
from kcheck.scene import Scene
from tests.plugins.compliant_hold import compliant_hold, hertz_stiffness, slip_hold

RATIOS = np.array([0.5, 2 / 3, 0.8, 1.0, 2.0, 10.0])
ASSUMPTIONS = ("equal", "hertz", "mass")


def compliant_usage(scene: Scene, mass: MassProperties, retracted: int, mu: np.ndarray) -> dict:
    """Largest friction usage after the release per assumption (RATIOS order), and which
    contact takes it."""
    dim = scene.dim
    points = np.array([s.position for s in scene.supports])[:, :dim]
    normals = np.array([s.normal / np.linalg.norm(s.normal) for s in scene.supports])[:, :dim]
    com = mass.center_of_mass[:dim]
    lever = points - com
    positions = np.array([s.position for s in scene.supports])
    seat = seat_layout(positions, np.array([s.normal for s in scene.supports]), dim, 1.0)
    loads, torque, _ = seated_loads(scene, mass)
    seated = contact_forces(seat, external_wrench(seat, loads, torque)).value
    assert seated is not None
    inertia = np.array([[mass.inertia[2, 2]]]) if dim == 2 else mass.inertia
    nw = inertia.shape[0]
    m = np.eye(nw + dim) * mass.mass
    m[:nw, :nw] = inertia
    rows = wrenches(lever, normals)
    stiffness = {
        "equal": np.ones(len(points)),
        "hertz": hertz_stiffness(seated),
        "mass": 1.0 / np.einsum("ia,ab,ib->i", rows, np.linalg.inv(m), rows),
    }
    names = [s.name for s in scene.supports]
    out: dict = {"seated": seated.round(4).tolist()}
    for key in ASSUMPTIONS:
        hold = compliant_hold(lever, normals, mu, seated, retracted, stiffness[key], RATIOS)
        worst = np.argmax(hold.usage, axis=1)
        slips = [
            slip_hold(lever, normals, mu, seated, retracted, stiffness[key], float(ratio))
            for ratio in RATIOS
        ]
        out[key] = {
            "slip_holds": [s.holds for s in slips],
            "slip_why": [s.why for s in slips],
            "slipped": [[names[i] for i in np.flatnonzero(s.slipping)] for s in slips],
            "usage": [round(float(u), 4) for u in hold.usage.max(axis=1)],
            "at": [names[int(i)] for i in worst],
            "separated": [[names[i] for i in np.flatnonzero(s)] for s in hold.separated],
        }
    return out


def main() -> None:
    from kcheck.analysis.jamming_cases import analyse_jamming, held_at, jam_statics
    from kcheck.body.mass import body_mass_properties
    from kcheck.scene import load_scene
    from tests.conftest import FIXTURES
    from tests.plugins.reseat_agreement import compare_scene, generated
    from tests.plugins.test_reseat import premise

    seed = int(sys.argv[1])
    rows = []
    with tempfile.TemporaryDirectory() as d:
        paths = generated(Path(d), 100, seed=seed)
        if seed == 26:
            paths = [
                FIXTURES / "planar-block" / "block.kcheck.yaml",
                FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml",
                FIXTURES / "maxwell-three-vee" / "coupling.kcheck.yaml",
                *paths,
            ]
        for path in paths:
            scene = load_scene(path)
            assert scene.body is not None
            mass = body_mass_properties(scene.body, scene.scale)
            statics, swept, design = jam_statics(scene, mass)
            if design is None:
                continue
            jams = analyse_jamming(statics, swept, design)
            held = [
                r
                for r in range(len(scene.supports))
                if held_at(jams, jams.cases[r], design, statics.friction)
            ]
            if not held:
                continue
            mu = np.asarray(scene.friction_range("kinetic")[1], float)
            for c in compare_scene(path):
                if not c.held or premise(c) is not None:
                    continue
                r = [s.name for s in scene.supports].index(c.retracted)
                rows.append(
                    {
                        "scene": c.scene,
                        "retracted": c.retracted,
                        "unique": c.unique,
                        "simulated": c.simulated,
                        "analytical": c.analytical,
                        **compliant_usage(scene, mass, r, mu),
                    }
                )
            print(path.name, len(rows), flush=True)
    Path(sys.argv[2]).write_text(json.dumps({"ratios": RATIOS.tolist(), "rows": rows}, indent=1))


def recompute(path: Path, seed: int) -> list[dict]:
    """The rows of an earlier run with the compliant usage computed again (the simulation's
    class kept): the scenes are drawn again from the seed. Two fixtures share a file name;
    the one whose seated forces the row recorded is taken."""
    from kcheck.body.mass import body_mass_properties
    from kcheck.scene import load_scene
    from tests.conftest import FIXTURES
    from tests.plugins.reseat_agreement import generated

    rows = json.loads(path.read_text())["rows"]
    with tempfile.TemporaryDirectory() as d:
        paths = {p.name: [p] for p in generated(Path(d), 100, seed=seed)}
        for folder in ("planar-block", "thesis-appendix-a", "maxwell-three-vee"):
            for file in (FIXTURES / folder).glob("*.kcheck.yaml"):
                paths.setdefault(file.name, []).append(file)
        out = []
        for row in rows:
            for candidate in paths[row["scene"]]:
                scene = load_scene(candidate)
                assert scene.body is not None
                mass = body_mass_properties(scene.body, scene.scale)
                names = [s.name for s in scene.supports]
                if row["retracted"] not in names:
                    continue
                mu = np.asarray(scene.friction_range("kinetic")[1], float)
                usage = compliant_usage(scene, mass, names.index(row["retracted"]), mu)
                if np.allclose(usage["seated"], row.get("seated", usage["seated"]), atol=1e-3):
                    out.append({**row, **usage})
                    break
    return out


def table(rows: list[dict], label: str) -> list[str]:
    """docs/validation.md's table rows: per test (elastic: a contact leaves its cone; through
    local slip: the slip does not stop), assumption and ratio, how many held cases are flagged,
    split by `jamming`'s uniqueness and by whether the simulation keeps them held, and
    random-3d-1667 s1."""
    lines = []
    groups = [(u, held) for u in (True, False) for held in (True, False)]
    for test, field in (("elastic", "usage"), ("through slip", "slip_holds")):
        for key in ASSUMPTIONS:
            for i in (1, 3, 5):

                def flag(r: dict, key: str = key, i: int = i, field: str = field) -> bool:
                    v = r[key][field][i]
                    return v > 1 if field == "usage" else not v

                cells = []
                for u, held in groups:
                    group = [
                        r for r in rows if r["unique"] == u and (r["simulated"] == "jams") == held
                    ]
                    cells.append(f"{sum(map(flag, group))} of {len(group)}")
                target = [
                    r
                    for r in rows
                    if r["scene"].startswith("random-3d-1667.") and r["retracted"] == "s1"
                ]
                hit = ("flagged" if flag(target[0]) else "not flagged") if target else "—"
                lines.append(
                    f"| {label} | {test} | {key} | {RATIOS[i]:.2f} | {cells[0]} | {cells[1]} | "
                    f"{hit} | {cells[2]} | {cells[3]} |"
                )
    return lines


if __name__ == "__main__":
    if sys.argv[1] == "table":  # table RUN.json SEED: the usage again, the simulation kept
        rows = recompute(Path(sys.argv[2]), int(sys.argv[3]))
        print("\n".join(table(rows, f"seed {sys.argv[3]}")))
    else:
        main()
