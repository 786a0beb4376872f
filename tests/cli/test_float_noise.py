"""`kcheck mass`, `init` and `expand` print the digits their input justifies (issue 22): values
like 0.1 + 0.2 (0.30000000000000004 in binary) come out as 0.3. Reference values are closed
forms: a cube of side a has volume a³, its centre in the middle, inertia m a²/6 about it."""

from __future__ import annotations

import itertools
import json
import re
from pathlib import Path

import pytest

from kcheck.fmt import COMPUTED_DIGITS, MESH_DIGITS, justified

LOW, HIGH = 0.1, 0.1 + 0.2  # HIGH is 0.30000000000000004
NUMBER = re.compile(r"-?\d+\.\d+(?:e-?\d+)?")


def _digits(number: str) -> int:
    """Significant digits of a written number."""
    mantissa = number.lstrip("-").split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) or 1


def _cube(path: Path) -> Path:
    """An ASCII STL cube from LOW to HIGH on every axis (its coordinates written in full)."""
    corners = list(itertools.product((LOW, HIGH), repeat=3))
    middle = (LOW + HIGH) / 2
    faces = []
    for axis in range(3):
        for side in (LOW, HIGH):
            a, b, c, d = sorted(
                (p for p in corners if p[axis] == side),
                key=lambda p: (p[(axis + 1) % 3], p[(axis + 2) % 3]),
            )
            for tri in ((a, b, d), (a, d, c)):
                # Wound outwards: the normal (right-hand rule) points away from the middle.
                u = [tri[1][k] - tri[0][k] for k in range(3)]
                v = [tri[2][k] - tri[0][k] for k in range(3)]
                normal = [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ]
                outwards = normal[axis] * (side - middle) > 0
                faces.append(tri if outwards else (tri[0], tri[2], tri[1]))
    lines = ["solid cube"]
    for tri in faces:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {x!r} {y!r} {z!r}" for x, y, z in tri]
        lines += ["endloop", "endfacet"]
    path.write_text("\n".join([*lines, "endsolid cube", ""]), encoding="utf-8")
    assert "0.30000000000000004" in path.read_text(encoding="utf-8")
    return path


def test_justified_drops_the_noise_and_keeps_the_digits() -> None:
    assert justified(0.1 + 0.2) == 0.3 and repr(justified(0.1 + 0.2)) == "0.3"
    assert justified([0.3 - 0.1, 2.9931e-08], 140.0, MESH_DIGITS) == [0.2, 0.0]
    assert justified(-1e-17, 1.0) == 0.0 and str(justified(-1e-17, 1.0)) == "0.0"
    assert justified(43.30127, 50.0) == 43.30127  # typed digits stay
    assert justified(1 / 3, 1.0) == round(1 / 3, COMPUTED_DIGITS - 1)


def test_mass_prints_the_digits_of_the_mesh(cli, tmp_path: Path) -> None:
    cube = _cube(tmp_path / "cube.stl")
    code, out, err = cli("mass", f"{cube}:steel", "--units", "mm", "--format", "json")
    assert code == 0, err
    (mesh,) = json.loads(out)["meshes"]
    side = HIGH - LOW
    mass = 7850 * (side * 1e-3) ** 3
    assert mesh["bounds"] == [[0.1, 0.1, 0.1], [0.3, 0.3, 0.3]]
    assert mesh["center_of_mass"] == [0.2, 0.2, 0.2]
    assert mesh["volume"] == pytest.approx(side**3, rel=1e-6)
    assert mesh["mass"] == pytest.approx(mass, rel=1e-6)
    assert mesh["inertia"][0][0] == pytest.approx(mass * side**2 / 6, rel=1e-6)
    numbers = NUMBER.findall(out)
    assert numbers and max(_digits(n) for n in numbers) <= MESH_DIGITS, numbers
    code, text, _ = cli("mass", f"{cube}:steel", "--units", "mm")
    assert "x 0.1 … 0.3" in text and "(0.2, 0.2, 0.2)" in text
    assert "0.3000" not in text and "1.4901" not in text  # float32 0.1 is 0.10000000149011612


def test_init_prints_the_digits_of_the_mesh(cli, tmp_path: Path) -> None:
    cube = _cube(tmp_path / "cube.stl")
    code, out, err = cli("init", "--mesh", str(cube), "--output", "-")
    assert code == 0, err
    assert re.search(r"spans x 0\.1 … 0\.3, y 0\.1 … 0\.3, z 0\.1 … 0\.3 (\w+)", out)
    assert "centre of mass is [0.2, 0.2, 0.2]" in out
    numbers = NUMBER.findall(out)
    assert numbers and max(_digits(n) for n in numbers) <= MESH_DIGITS, numbers


def test_expand_prints_the_digits_of_the_scene(cli, write_scene) -> None:
    # The Kelvin fixture with its flat's ball (radius 0.1) at x = 0.1, z = 0.1 + 0.2: the
    # contact is at z = 0.3 - 0.1 = 0.2 (not 0.20000000000000004), the normal straight up.
    scene = write_scene(
        f"""
        version: 1
        units: mm
        body:
          mass: 1.5
          center_of_mass: [0, 0, 12]
          inertia: [[0.002, 0, 0], [0, 0.002, 0], [0, 0, 0.004]]
        couplings:
          - {{name: socket, type: ball-trihedral, ball: {{center: [0, 50, 0], radius: 6}},
             up: [0, 0, 1], half_angle: 54.7356, reference: [0, 1, 0]}}
          - {{name: vee, type: ball-vee, ball: {{center: [-43.30127, -25, 0], radius: 6}},
             groove: {{axis: [43.30127, 75, 0], up: [0, 0, 1], half_angle: 45}}}}
          - {{name: flat, type: ball-flat, ball: {{center: [{LOW!r}, -25, {HIGH!r}], radius: 0.1}},
             normal: [0, 0, 1]}}
        friction: 0.1
        gravity: [0, 0, -9.81]
        load: {{point: [0, 0, 18.5], magnitude: 100, direction: [0, 0, -1]}}
        """
    )
    code, out, err = cli("expand", str(scene))
    assert code == 0, err
    flat = out[out.index("{name: flat.1, ") :].split("\n  - ", 1)[0]  # its list item (and contact)
    assert "position: [0.1, -25.0, 0.2], normal: [0.0, 0.0, 1.0]" in flat, flat
    numbers = NUMBER.findall(out.split("supports:", 1)[1])
    assert numbers and max(_digits(n) for n in numbers) <= COMPUTED_DIGITS, numbers


def test_a_value_that_rounds_to_zero_has_no_minus_sign():
    """A symmetric body's centre of mass comes out as -1e-17 or so from the mesh sums:
    printed with its column's decimals it is zero, not "-0.0000" (seen on the ASPE
    fixture's `kcheck check -v`)."""
    from kcheck.report.tables import fixed

    assert fixed([-1e-17, 2e-18, 0.0]) == ["0.0000", "0.0000", "0.0000"]
    assert fixed([-0.004, 12.0]) == ["0.00", "12.00"]  # -0.004 at two decimals
    assert fixed([-3.2, 1.0]) == ["-3.200", "1.000"]  # a real negative keeps its sign
