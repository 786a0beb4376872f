"""Generated scenes for the `reseat` check's agreement test: seated bodies (every seated
normal force positive without friction) on three planar or six spatial point supports, with
explicit mass properties, a load at a point and sometimes gravity."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

__all__ = ["random_scene", "seated_forces"]


def _wrench_rows(points: np.ndarray, normals: np.ndarray, dim: int) -> np.ndarray:
    """Columns: the wrench of a unit normal force at each support (planar: fx, fy, mz)."""
    if dim == 2:
        moment = points[:, 0] * normals[:, 1] - points[:, 1] * normals[:, 0]
        return np.vstack([normals[:, 0], normals[:, 1], moment])
    return np.vstack([normals.T, np.cross(points, normals).T])


def seated_forces(
    points: np.ndarray, normals: np.ndarray, force: np.ndarray, at: np.ndarray, dim: int
) -> np.ndarray | None:
    """Frictionless seated normal forces balancing a force at a point (None: singular)."""
    a = _wrench_rows(points, normals, dim)
    if dim == 2:
        w = np.array([force[0], force[1], at[0] * force[1] - at[1] * force[0]])
    else:
        w = np.concatenate([force, np.cross(at, force)])
    if np.linalg.cond(a) > 1e6:
        return None
    return np.linalg.solve(a, -w)


def random_scene(rng: np.random.Generator, folder: Path, index: int, dim: int) -> Path | None:
    """One random seated scene file (mm, explicit mass), or None when the draw does not sit
    (a seated normal force below 5 % of the load: too near losing contact when seated)."""
    k = 3 if dim == 2 else 6
    points = rng.uniform(-50, 50, (k, 3))
    if dim == 2:
        points[:, 2] = 0.0
    com = rng.uniform(-20, 20, 3)
    if dim == 2:
        com[2] = 0.0
    inward = com - points + rng.normal(0, 25, (k, 3))
    if dim == 2:
        inward[:, 2] = 0.0
    normals = inward / np.linalg.norm(inward, axis=1, keepdims=True)
    direction = rng.normal(size=3)
    if dim == 2:
        direction[2] = 0.0
    direction /= np.linalg.norm(direction)
    mu = float(rng.choice([0.0, 0.05, 0.1, 0.2, 0.3]))
    magnitude = 10.0
    forces = seated_forces(points * 1e-3, normals, magnitude * direction, com * 1e-3, dim)
    if forces is None or np.any(forces < 0.05 * magnitude):
        return None
    inertia: float | list[list[float]] = float(rng.uniform(2e-4, 2e-3))
    if dim == 3:
        # ten 0.1 kg points about the centre of mass: a physical (triangle-inequality) tensor
        cloud = rng.normal(0, 0.03, (10, 3))
        tensor = 0.1 * (np.sum(cloud**2) * np.eye(3) - cloud.T @ cloud)
        inertia = tensor.round(12).tolist()
    supports = "\n".join(
        f"  - {{name: s{i + 1}, position: {p.round(6).tolist()}, normal: {n.round(9).tolist()}}}"
        for i, (p, n) in enumerate(zip(points, normals, strict=True))
    )
    text = f"""\
    version: 1
    name: random {index}
    units: mm
    body:
      mass: 1
      center_of_mass: {com.round(6).tolist()}
      inertia: {inertia}
    supports:
    SUPPORTS
    friction: {mu}
    load:
      magnitude: {magnitude}
      direction: {direction.round(9).tolist()}
    """
    path = folder / f"random-{dim}d-{index}.kcheck.yaml"
    path.write_text(textwrap.dedent(text).replace("SUPPORTS", supports), encoding="utf-8")
    return path
