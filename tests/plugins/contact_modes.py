"""Evidence for issue 26 (not the check): every contact mode of a spatial body's first motion
from rest, enumerated, to tell whether the rigid model admits a motion beside rest that
Lemke's method (kcheck.mechanics.second_answer) did not return.

Each remaining contact separates (S: no force, non-negative normal acceleration), sticks (T:
no acceleration, force in its friction pyramid), slides along one edge of the pyramid (E_k:
force on edge k, the tangential acceleration in the sector where edge k opposes it most) or
between two neighbouring edges (F_k: force on facet k, the tangential acceleration opposite
the facet's bisector). The pyramids are kcheck.mechanics.lift_off's (LIFT_EDGES inscribed
edges, the same tangent basis). Each mode is a square linear system in the acceleration
twist ``a`` and the mode's force unknowns ``x``: ``M a = w + B x``, ``C a = 0`` (B the force
columns, C the kinematic rows of the mode), solved as ``C M^-1 B x = -C M^-1 w``.

A mode with ``m`` kinematic rows, ``m`` >= 6 and C of full rank, forces ``a = 0``: rest.
So motions live in the modes with m <= 5 (vectorised, every edge choice at once) and in the
one structural exception, two sticking contacts (C of rank 5: the body may turn about the
line through them) with every other contact separating, solved with its one-parameter
family of internal forces. Generic geometry is assumed beyond that (the two scenes here
are random draws).

Run: PYTHONPATH=.:plugins python tests/plugins/contact_modes.py [EDGES] (16: about 30 s CPU)
"""

from __future__ import annotations

import itertools
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from kcheck.mechanics.kinematics import wrenches
from kcheck.mechanics.lift_off import LIFT_EDGES

S, T, E, F = 0, 1, 2, 3
SIZE = {S: 0, T: 3, E: 1, F: 2}
NAMES = {S: "separates", T: "sticks", E: "slides on edge", F: "slides on facet"}
#: Constraint slack, and the smallest acceleration counted as motion, over the free body's
#: acceleration scale (as kcheck.numerics.thresholds.LIFT_SHARE).
TOL = 1e-9
#: The nearest inconsistent mode is reported among motions at least this share of the scale.
NEAR = 1e-3


@dataclass(frozen=True)
class Mode:
    """One consistent mode: the per-contact types and edge indices, the acceleration twist."""

    types: tuple[int, ...]
    edges: tuple[int, ...]
    acceleration: np.ndarray

    def describe(self, names: list[str]) -> str:
        return ", ".join(
            f"{n} {NAMES[t]}" + (f" {k}" if t in (E, F) else "")
            for n, t, k in zip(names, self.types, self.edges, strict=True)
        )


def _basis(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """kcheck.mechanics.lift_off._edges's tangent basis."""
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return t1, np.cross(normals, t1)


@dataclass(frozen=True)
class Geometry:
    rows_n: np.ndarray  # (c, 6) normal wrench rows
    rows_t: np.ndarray  # (c, 2, 6) tangent rows (t1, t2)
    rows_d: np.ndarray  # (c, m, 6) edge rows
    rows_p: np.ndarray  # (c, m, 6) in-plane perpendiculars of each facet's bisector
    rows_b: np.ndarray  # (c, m, 6) facet bisectors
    cos_d: np.ndarray  # (m, 2) edge directions in the (t1, t2) basis
    cos_b: np.ndarray  # (m, 2) facet bisectors in the (t1, t2) basis
    mu: np.ndarray
    inv: np.ndarray
    wrench: np.ndarray
    scale: float


def geometry(points, normals, mu, com, inertia, wrench, edges=LIFT_EDGES) -> Geometry:
    lever = points - com
    t1, t2 = _basis(normals)
    theta = 2 * np.pi * np.arange(edges) / edges
    phi = theta + np.pi / edges
    cos_d = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    cos_b = np.stack([np.cos(phi), np.sin(phi)], axis=1)

    def rows(coef: np.ndarray) -> np.ndarray:  # (m, 2) tangent-plane directions -> (c, m, 6)
        d = coef[None, :, :1] * t1[:, None] + coef[None, :, 1:] * t2[:, None]
        return wrenches(np.repeat(lever[:, None], len(coef), axis=1), d)

    mass = np.eye(6)
    mass[:3, :3] = inertia
    inv = np.linalg.inv(mass)
    free = inv @ wrench
    scale = float(np.abs(free).max()) + float(np.abs(free[3:] + np.cross(free[:3], lever)).max())
    perp = np.stack([-cos_b[:, 1], cos_b[:, 0]], axis=1)
    return Geometry(
        wrenches(lever, normals),
        np.stack([wrenches(lever, t1), wrenches(lever, t2)], axis=1),
        rows(cos_d),
        rows(perp),
        rows(cos_b),
        cos_d,
        cos_b,
        np.asarray(mu, float),
        inv,
        np.asarray(wrench, float),
        scale,
    )


def _columns(g: Geometry, types, idx):
    """Force columns B (N, 6, m) and kinematic rows C (N, m, 6) of one type pattern with the
    edge indices ``idx`` (N, q) of its E/F contacts, in contact order."""
    n = idx.shape[0]
    cols, rows = [], []
    q = 0
    m_edges = len(g.cos_d)
    for j, t in enumerate(types):
        if t == S:
            continue
        wn = np.broadcast_to(g.rows_n[j], (n, 6))
        if t == T:
            for r in (
                wn,
                np.broadcast_to(g.rows_t[j, 0], (n, 6)),
                np.broadcast_to(g.rows_t[j, 1], (n, 6)),
            ):
                cols.append(r)
                rows.append(r)
            continue
        k = idx[:, q]
        q += 1
        if t == E:
            cols.append(wn + g.mu[j] * g.rows_d[j, k])
            rows.append(wn)
        else:
            cols.append(wn + g.mu[j] * g.rows_d[j, k])
            cols.append(wn + g.mu[j] * g.rows_d[j, (k + 1) % m_edges])
            rows.append(wn)
            rows.append(g.rows_p[j, k])
    return np.stack(cols, axis=2), np.stack(rows, axis=1)


def _slacks(g: Geometry, types, idx, a, x):
    """Every inequality of the mode as a value that must be >= 0 (N, k), homogeneous in
    (a, x)."""
    out = []
    col = q = 0
    cos_half = np.cos(np.pi / len(g.cos_d))
    for j, t in enumerate(types):
        if t == S:
            out.append(a @ g.rows_n[j])
            continue
        if t == T:
            big_n, ft = x[:, col], x[:, col + 1 : col + 3]
            col += 3
            out.append(big_n)
            out.append(g.mu[j] * cos_half * big_n[:, None] - ft @ g.cos_b.T)
            continue
        k = idx[:, q]
        q += 1
        at = a @ g.rows_t[j].T  # (N, 2) tangential acceleration in (t1, t2)
        if t == E:
            out.append(x[:, col])
            col += 1
            # edge k opposes the sliding most: at . (d_i - d_k) >= 0 for every edge i
            out.append(at @ g.cos_d.T - np.sum(at * g.cos_d[k], axis=1)[:, None])
        else:
            out.append(x[:, col])
            out.append(x[:, col + 1])
            col += 2
            out.append(-np.sum(at * g.cos_b[k], axis=1))
    return np.column_stack([o if o.ndim == 2 else o[:, None] for o in out])


def _scaled(g: Geometry, types, s: np.ndarray) -> np.ndarray:
    """Slacks over their scale: accelerations over g.scale, forces over the wrench's size."""
    force = float(np.abs(g.wrench).max())
    widths = []
    for t in types:
        widths += {
            S: ["a"],
            T: ["f"] * (1 + len(g.cos_b)),
            E: ["f"] + ["a"] * len(g.cos_d),
            F: ["f", "f", "a"],
        }[t]
    div = np.array([g.scale if w == "a" else force for w in widths])
    return s / div


def enumerate_modes(g: Geometry, chunk: int = 200_000):
    """Every consistent moving mode, the number of systems solved, and the smallest largest
    violation among clearly moving modes (how near the nearest motion comes to consistency)."""
    c = len(g.mu)
    m_edges = len(g.cos_d)
    found: list[Mode] = []
    solved = 0
    nearest = (np.inf, None)
    for types in itertools.product((S, T, E, F), repeat=c):
        m = sum(SIZE[t] for t in types)
        q = sum(t in (E, F) for t in types)
        if m == 0:
            combos = [np.zeros((1, 0), dtype=int)]
        elif m <= 5:
            total = m_edges**q
            combos = (
                np.stack(
                    np.unravel_index(np.arange(s, min(s + chunk, total)), (m_edges,) * q), axis=1
                )
                if q
                else np.zeros((1, 0), dtype=int)
                for s in range(0, total, chunk)
            )
        else:
            continue
        for idx in combos:
            if m == 0:
                a = np.broadcast_to(g.inv @ g.wrench, (1, 6))
                x = np.zeros((1, 0))
            else:
                b, cr = _columns(g, types, idx)
                k = cr @ g.inv @ b
                rhs = -(cr @ (g.inv @ g.wrench))
                good = np.abs(np.linalg.det(k)) > 1e-14 * np.abs(k).max(axis=(1, 2)) ** m
                x = np.full((len(idx), m), np.nan)
                x[good] = np.linalg.solve(k[good], rhs[good][..., None])[..., 0]
                a = (g.wrench[None] + np.einsum("nij,nj->ni", b, np.nan_to_num(x))) @ g.inv.T
                a[~good] = np.nan
            solved += len(idx)
            s = _scaled(g, types, _slacks(g, types, idx, a, x))
            worst = -np.min(s, axis=1)
            moving = np.abs(a).max(axis=1) > TOL * g.scale
            ok = (worst <= TOL) & moving
            # the nearest miss among clear motions (near rest every sector test is noise)
            clear = np.abs(a).max(axis=1) > NEAR * g.scale
            cand = np.where(clear & np.isfinite(worst), worst, np.inf)
            if cand.size and cand.min() < nearest[0]:
                i = int(np.argmin(cand))
                nearest = (float(cand[i]), Mode(types, _edges_of(types, idx[i]), a[i]))
            for i in np.flatnonzero(ok):
                found.append(Mode(types, _edges_of(types, idx[i]), a[i]))
    for i, j in itertools.combinations(range(c), 2):
        mode = _two_sticking(g, i, j)
        solved += 1
        if mode is not None:
            found.append(mode)
    return found, solved, nearest


def _edges_of(types, idx) -> tuple[int, ...]:
    it = iter(idx.tolist())
    return tuple(next(it) if t in (E, F) else -1 for t in types)


def _two_sticking(g: Geometry, i: int, j: int) -> Mode | None:
    """Contacts i and j stick, every other separates: the body turns about the line through
    them (a = s z), the forces' part along that line is internal (one free parameter)."""
    c = len(g.mu)
    types = tuple(T if k in (i, j) else S for k in range(c))
    b, cr = _columns(g, types, np.zeros((1, 0), dtype=int))
    b, cr = b[0], cr[0]
    mass = np.linalg.inv(g.inv)
    # Unknowns (a, x): M a - B x = w, C a = 0.
    system = np.block([[mass, -b], [cr, np.zeros((6, 6))]])
    rhs = np.r_[g.wrench, np.zeros(6)]
    u, sv, vt = np.linalg.svd(system)
    rank = int(np.sum(sv > 1e-12 * sv[0]))
    sol = vt[:rank].T @ ((u[:, :rank].T @ rhs) / sv[:rank])
    if np.linalg.norm(system @ sol - rhs) > 1e-9 * (1 + np.linalg.norm(rhs)):
        return None  # inconsistent (the turn's axial moment does not balance)
    null = vt[rank:]
    idx = np.zeros((1, 0), dtype=int)
    s0 = _scaled(g, types, _slacks(g, types, idx, sol[None, :6], sol[None, 6:]))[0]
    if len(null) == 0:
        lo, hi = 0.0, 0.0
        ok = s0.min() >= -TOL
        t = 0.0
    else:
        z = null[0]
        s1 = _scaled(g, types, _slacks(g, types, idx, z[None, :6], z[None, 6:]))[0]
        lo, hi = -np.inf, np.inf
        for v0, v1 in zip(s0, s1, strict=True):
            if abs(v1) < 1e-15:
                if v0 < -TOL:
                    return None
            elif v1 > 0:
                lo = max(lo, (-TOL - v0) / v1)
            else:
                hi = min(hi, (-TOL - v0) / v1)
        ok = lo <= hi
        t = 0.0 if lo <= 0 <= hi else (lo if np.isfinite(lo) else hi)
        sol = sol + t * z
    a = sol[:6]
    if ok and np.abs(a).max() > TOL * g.scale:
        return Mode(types, (-1,) * c, a)
    return None


class RetractionCase(NamedTuple):
    """One retraction case of a scene, as the rigid model's first-motion problem sees it."""

    names: list[str]  # every support's name
    retracted: int  # index of the retracted support
    rest: list[int]  # indices of the supports kept
    points: np.ndarray  # (n, 3) every support's contact point, m
    normals: np.ndarray  # (n, 3) unit normals
    center_of_mass: np.ndarray  # (3,) m
    # The kept supports' points, normals and kinetic mu; the centre of mass, inertia / mass
    # (m^2) and load (moment, force) / mass: Body's and geometry's first six arguments.
    arrays: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def retraction_case(paths: dict[str, Path], name: str, retracted: str) -> RetractionCase:
    """The retraction case of scene ``paths[name]`` retracting support ``retracted``, its
    load per unit mass (shared by this module's :func:`case` and
    tests/kcheck/test_second_answer.py)."""
    from kcheck.analysis.reseat import _wrench
    from kcheck.body.mass import body_mass_properties
    from kcheck.scene import load_scene

    scene = load_scene(paths[name])
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    names = [s.name for s in scene.supports]
    r = names.index(retracted)
    rest = [i for i in range(len(names)) if i != r]
    points = np.array([s.position for s in scene.supports])
    normals = np.array([s.normal / np.linalg.norm(s.normal) for s in scene.supports])
    load = _wrench(scene, mass.center_of_mass, 1.0) + np.r_[mass.mass * scene.gravity, 0, 0, 0]
    arrays = (
        points[rest],
        normals[rest],
        np.asarray(scene.friction_range("kinetic")[1])[rest],
        mass.center_of_mass,
        mass.inertia / mass.mass,
        np.r_[load[3:], load[:3]] / mass.mass,
    )
    return RetractionCase(names, r, rest, points, normals, mass.center_of_mass, arrays)


def case(paths: dict[str, Path], name: str, retracted: str, edges: int = LIFT_EDGES):
    """The nondimensional first-motion problem of one retraction case."""
    c = retraction_case(paths, name, retracted)
    return [c.names[i] for i in c.rest], geometry(*c.arrays, edges)


def main() -> None:
    import tempfile
    import time

    from tests.plugins.reseat_agreement import generated

    edges = int(sys.argv[1]) if len(sys.argv) > 1 else LIFT_EDGES

    with tempfile.TemporaryDirectory() as d:
        paths = {p.name: p for p in generated(Path(d), 100)}
        for name, retracted in (
            ("random-3d-3391.kcheck.yaml", "s4"),
            ("random-3d-1667.kcheck.yaml", "s1"),
        ):
            names, g = case(paths, name, retracted, edges)
            start = time.process_time()
            found, solved, nearest = enumerate_modes(g)
            cpu = time.process_time() - start
            print(
                f"{name} retracting {retracted}, {edges}-edge pyramids:",
                f"{solved} mode systems, {cpu:.1f} s CPU",
            )
            print(f"  consistent moving modes: {len(found)}")
            for mode in found[:10]:
                print(
                    "   ",
                    mode.describe(names),
                    "|a|/scale =",
                    np.abs(mode.acceleration).max() / g.scale,
                )
            if nearest[1] is not None:
                print(
                    f"  nearest moving mode violates by {nearest[0]:.3g} (scaled):",
                    nearest[1].describe(names),
                )
    sys.stdout.flush()


if __name__ == "__main__":
    main()
