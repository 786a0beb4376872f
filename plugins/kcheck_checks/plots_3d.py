"""Pictures of the spatial check: the scene with screw axes, the safe-direction map, and the
normal forces per retracted support. matplotlib comes in through :mod:`kcheck.plotting`."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.analysis import Analysis
from kcheck.arcs import cap_margins
from kcheck.plotting import figure, save, slug
from kcheck.result import CheckResult
from kcheck.scene import Scene

if TYPE_CHECKING:
    from kcheck_checks.analytical_3d import SphereMap

__all__ = ["plot_spatial", "scene_panel", "sphere_panel", "forces_panel"]

OUTCOME_COLOURS = {
    "closes": "tab:green",
    "loses_contact": "tab:orange",
    "opens": "tab:red",
    "opens_loses_contact": "tab:red",
    "jams": "tab:red",
    "ambiguous": "tab:purple",
}
# Largest number of mesh triangles drawn; more only slows matplotlib's 3D sorting down.
MAX_TRIANGLES = 4000


def plot_spatial(
    scene: Scene,
    analysis: Analysis,
    smap: SphereMap | None,
    result: CheckResult,
    directory: Path,
) -> list[Path]:
    """Write ``<scene>-analytical-3d-{scene,sphere,forces}.png/.svg``; return the paths."""
    stem = f"{slug(scene.name)}-analytical-3d"
    written: list[Path] = []
    fig = figure(figsize=(15, 9.5))
    scene_panel(fig, scene, analysis, result)
    written.extend(save(fig, directory, f"{stem}-scene"))
    if smap is not None:
        fig = figure(figsize=(12, 6.8))
        sphere_panel(fig, scene, analysis, smap)
        written.extend(save(fig, directory, f"{stem}-sphere"))
    fig = figure(figsize=(12, 5.5))
    forces_panel(fig, scene, analysis, result)
    written.extend(save(fig, directory, f"{stem}-forces"))
    return written


def _mesh_triangles(scene: Scene) -> np.ndarray | None:
    """Triangles (t, 3, 3) of the body's meshes in scene units, thinned to MAX_TRIANGLES."""
    from kcheck.mass import load_mesh

    if scene.body is None or not scene.body.parts:
        return None
    tris = [load_mesh(p.mesh, scene.scale, (*p.field, "mesh")).triangles for p in scene.body.parts]
    triangles = np.concatenate(tris) / scene.scale
    if len(triangles) > MAX_TRIANGLES:
        triangles = triangles[:: int(np.ceil(len(triangles) / MAX_TRIANGLES))]
    return triangles


def clip_line(
    point: np.ndarray, axis: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray | None:
    """Ends of the part of the line ``point + t axis`` inside the box [lo, hi], or None."""
    t0, t1 = -np.inf, np.inf
    for k in range(3):
        if abs(axis[k]) < 1e-12:
            if not lo[k] <= point[k] <= hi[k]:
                return None
            continue
        a, b = sorted(((lo[k] - point[k]) / axis[k], (hi[k] - point[k]) / axis[k]))
        t0, t1 = max(t0, a), min(t1, b)
    if not t1 > t0:
        return None
    return np.array([point + t0 * axis, point + t1 * axis])


def scene_panel(fig: Any, scene: Scene, analysis: Analysis, result: CheckResult) -> None:
    """One 3D panel per retracted support: body, supports and normals, load, screw axis."""
    unit = scene.units
    s = scene.scale
    points = np.array([sp.position for sp in scene.supports]) / s
    normals = np.array([sp.normal for sp in scene.supports])
    triangles = _mesh_triangles(scene)
    cloud = points if triangles is None else np.vstack([points, triangles.reshape(-1, 3)])
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    centre, size = 0.5 * (lo + hi), float(np.max(hi - lo))
    arrow = 0.18 * size
    # The view box: the scene plus room for arrows, no axis thinner than 40 % of the largest.
    half = np.maximum(0.5 * (hi - lo) + 0.25 * size, 0.2 * size)
    box_lo, box_hi = centre - half, centre + half
    load = scene.load
    load_point = None
    if load is not None and load.magnitude > 0 and load.direction is not None:
        frame = analysis.problem.frame
        load_point = (frame.origin + frame.length * analysis.problem.load_point) / s
        load_dir = load.direction
    elif np.any(scene.gravity):
        com = analysis.problem.frame.origin + analysis.problem.frame.length * analysis.problem.com
        load_point = com / s
        load_dir = scene.gravity / np.linalg.norm(scene.gravity)
    cases = {r.retracted: r for r in result.cases}
    n = len(scene.supports)
    cols = 3
    rows = int(np.ceil(n / cols))
    for i, support in enumerate(scene.supports):
        ax = fig.add_subplot(rows, cols, i + 1, projection="3d")
        if triangles is not None:
            from mpl_toolkits.mplot3d.art3d import Poly3DCollection

            ax.add_collection3d(
                Poly3DCollection(
                    triangles, facecolor="0.8", edgecolor="0.65", linewidth=0.1, alpha=0.18
                )
            )
        keep = np.arange(n) != i
        ax.quiver(
            *points[keep].T,
            *(arrow * normals[keep]).T,
            color="tab:blue",
            linewidth=1.2,
            arrow_length_ratio=0.25,
        )
        ax.scatter(*points[keep].T, color="tab:blue", s=12, depthshade=False)
        ax.scatter(*points[i], color="tab:red", marker="X", s=70, depthshade=False)
        ax.quiver(*points[i], *(arrow * normals[i]), color="tab:red", linestyle=":")
        for j in np.flatnonzero(keep):
            ax.text(*(points[j] + 0.06 * size * normals[j]), scene.supports[j].name, fontsize=7)
        if load_point is not None:
            ax.quiver(
                *(load_point - 1.6 * arrow * load_dir),
                *(1.6 * arrow * load_dir),
                color="tab:orange",
                linewidth=2.0,
                arrow_length_ratio=0.2,
            )
        case = cases.get(support.name)
        title = f"{support.name} retracted"
        colour = "black"
        if case is not None:
            title += f": {case.outcome.replace('_', ' ')}"
            colour = OUTCOME_COLOURS.get(case.outcome, "black")
            segment = None
            if "axis" in case.details:  # a screw, or a pure rotation
                foot = np.asarray(case.details["axis_point"]) / s
                segment = clip_line(foot, np.asarray(case.details["axis"]), box_lo, box_hi)
            if case.details.get("motion") == "rotation":  # a screw without pitch
                if segment is not None:
                    ax.plot(*segment.T, color="tab:purple", linestyle="--", linewidth=1.8)
                title += "\nrotation axis (purple)" if segment is not None else ""
            elif case.details.get("motion") == "screw":
                pitch = case.details["pitch_m"] / s
                if segment is not None:
                    ax.plot(*segment.T, color="tab:purple", linestyle="--", linewidth=1.8)
                    title += f"\nscrew axis (purple), pitch {pitch:.3g} {unit}"
                else:
                    title += f"\nscrew axis outside the view, pitch {pitch:.3g} {unit}"
            elif case.details.get("motion") == "translation":
                d = np.asarray(case.details["direction"])
                ax.quiver(*points[i], *(1.5 * arrow * d), color="tab:purple", linewidth=1.5)
                title += "\ntranslation (purple arrow)"
        ax.set_title(title, fontsize=9, color=colour)
        ax.set_xlim(box_lo[0], box_hi[0])
        ax.set_ylim(box_lo[1], box_hi[1])
        ax.set_zlim(box_lo[2], box_hi[2])
        ax.set_box_aspect(tuple(box_hi - box_lo))
        ax.set_xlabel(f"x ({unit})", fontsize=7)
        ax.set_ylabel(f"y ({unit})", fontsize=7)
        ax.set_zlabel(f"z ({unit})", fontsize=7)
        ax.tick_params(labelsize=6)
        ax.view_init(elev=28, azim=-60)
    what = "load (orange)" if load is not None and load.magnitude > 0 else "gravity (orange)"
    fig.suptitle(
        f"{scene.name}: free motion when each support is retracted — supports and normals "
        f"(blue), retracted support (red ×), {what}",
        fontsize=11,
    )


def _tangent_basis(centre: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors e1, e2 completing ``centre`` to a right-handed frame (e1 ~ world x or z)."""
    helper = np.array([0.0, 0.0, 1.0]) if abs(centre[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = helper - (helper @ centre) * centre
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(centre, e1)


def lambert_inverse(x: np.ndarray, y: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Directions (..., 3) of points of a Lambert azimuthal equal-area disc about ``centre``.

    The disc radius ``r = 2 sin(theta / 2)`` (theta from the centre) keeps areas; the
    hemisphere around the centre fills ``r <= sqrt(2)``.
    """
    e1, e2 = _tangent_basis(centre)
    r = np.hypot(x, y)
    theta = 2.0 * np.arcsin(np.clip(r / 2.0, 0.0, 1.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        ux, uy = np.where(r > 0, x / r, 1.0), np.where(r > 0, y / r, 0.0)
    s = np.sin(theta)[..., None]
    return np.cos(theta)[..., None] * centre + s * ux[..., None] * e1 + s * uy[..., None] * e2


def lambert_forward(d: np.ndarray, centre: np.ndarray) -> tuple[float, float]:
    """Disc coordinates of a direction in the Lambert map about ``centre``."""
    e1, e2 = _tangent_basis(centre)
    theta = float(np.arccos(np.clip(d @ centre, -1.0, 1.0)))
    psi = float(np.arctan2(d @ e2, d @ e1))
    r = 2.0 * np.sin(theta / 2.0)
    return r * np.cos(psi), r * np.sin(psi)


def sphere_panel(fig: Any, scene: Scene, analysis: Analysis, smap: SphereMap) -> None:
    """Equal-area map of the safe directions: the hemisphere about the design (or most robust)
    direction and the opposite hemisphere, side by side (Lambert azimuthal projections)."""
    deg = float(np.degrees(1.0))
    centre = smap.design if smap.design is not None else smap.robust
    named = "design" if smap.design is not None else "most robust"
    edge = np.sqrt(2.0)
    t = np.linspace(-edge, edge, 301)
    x, y = np.meshgrid(t, t)
    inside = np.hypot(x, y) <= edge * (1 + 1e-9)
    axes = fig.subplots(1, 2)
    top = max(smap.robust_margin * deg, 1.0)
    levels = np.concatenate([[-181.0, 0.0], np.linspace(0, top, 8)[1:]])
    colours = [(0.9, 0.9, 0.9)] + [tuple(c) for c in _greens(np.linspace(0.3, 0.95, 7))]
    filled = None
    for k, (ax, sign) in enumerate(zip(axes, (1.0, -1.0), strict=True)):
        c0 = sign * centre
        dirs = lambert_inverse(x, y, c0)
        margin = np.degrees(cap_margins(smap.a, smap.c, dirs.reshape(-1, 3))).reshape(x.shape)
        margin = np.where(inside, margin, np.nan)
        filled = ax.contourf(x, y, margin, levels=levels, colors=colours)
        for i, result in enumerate(analysis.results):
            mine = smap.owner == i
            if not np.any(mine):
                continue
            m = cap_margins(smap.a[mine], smap.c[mine], dirs.reshape(-1, 3)).reshape(x.shape)
            m = np.where(inside, m, np.nan)
            if np.nanmin(m) < 0 < np.nanmax(m):
                ax.contour(x, y, m, levels=[0.0], colors=[f"C{i}"], linewidths=0.8)
            if k == 0:
                ax.plot([], [], color=f"C{i}", lw=0.8, label=f"{result.retracted} closes inside")
        if np.nanmin(margin) < 0 < np.nanmax(margin):
            ax.contour(x, y, margin, levels=[0.0], colors="black", linewidths=1.8)
        # Rings of equal angle from the centre direction.
        for ring in (30, 60, 90):
            theta = np.radians(ring if sign > 0 else 180 - ring)
            r = 2 * np.sin(theta / 2)
            if sign < 0:
                r = 2 * np.sin((np.pi - theta) / 2)
            ax.add_patch(_circle(r, ring == 90))
            label = f"{ring}°" if sign > 0 else f"{180 - ring}°"
            ax.text(0.71 * r, 0.71 * r, label, fontsize=7, color="0.35", ha="left", va="bottom")
        for label, vec in {
            "+x": (1, 0, 0), "−x": (-1, 0, 0), "+y": (0, 1, 0),
            "−y": (0, -1, 0), "+z": (0, 0, 1), "−z": (0, 0, -1),
        }.items():  # fmt: skip
            v = np.array(vec, float)
            if v @ c0 >= -1e-9:
                px, py = lambert_forward(v, c0)
                ax.plot(px, py, "+", color="0.25", ms=8)
                ax.text(px, py, f" {label}", fontsize=9, color="0.25", va="bottom")
        for d, marker, kw, text in (
            (smap.robust, "o", {"mfc": "white", "mec": "black", "mew": 2, "ms": 10},
             f"most robust {_v(smap.robust)}: margin {smap.robust_margin * deg:.1f}°"),
            (smap.design, "*", {"mfc": "tab:orange", "mec": "black", "ms": 16},
             None if smap.design_margin is None
             else f"design {_v(smap.design)}: margin {smap.design_margin * deg:.1f}°"),
        ):  # fmt: skip
            if d is None:
                continue
            if d @ c0 >= 0:
                ax.plot(*lambert_forward(d, c0), marker, label=text if k == 0 else None, **kw)
            elif k == 0:
                ax.plot([], [], marker, label=text, **kw)
        ax.set_aspect("equal")
        ax.set_xlim(-edge * 1.05, edge * 1.05)
        ax.set_ylim(-edge * 1.05, edge * 1.05)
        ax.axis("off")
        ax.set_title(
            f"within 90° of the {named} direction {_v(centre)}"
            if sign > 0
            else f"the opposite hemisphere, about {_v(-centre)}",
            fontsize=10,
        )
    assert filled is not None
    bar = fig.colorbar(filled, ax=list(axes), shrink=0.7, pad=0.02)
    bar.set_ticks(levels[1:])
    bar.set_ticklabels([f"{v:.1f}" for v in levels[1:]])
    bar.set_label("margin to the nearest boundary (°); grey: not safe")
    fig.legend(loc="lower center", ncol=4, fontsize=8, frameon=False)
    what = "force" if smap.swept == "load" else "gravity"
    frac = smap.fraction
    fig.suptitle(
        f"{scene.name}: {what} directions safe for every retracted support (green): "
        f"{100 * frac.fraction:.1f}% ± {100 * frac.error:.1f}% of the sphere\n"
        "equal-area (Lambert azimuthal) views; black: boundary of the safe region, "
        "colours: where each case alone closes",
        fontsize=11,
    )


def _circle(r: float, solid: bool) -> Any:
    from matplotlib.patches import Circle

    return Circle(
        (0, 0), r, fill=False, color="0.2" if solid else "0.55",
        linewidth=1.2 if solid else 0.5, linestyle="-" if solid else ":",
    )  # fmt: skip


def _greens(x: np.ndarray) -> np.ndarray:
    import matplotlib

    return matplotlib.colormaps["Greens"](x)


def _v(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.2f}" for x in v) + ")"


def forces_panel(fig: Any, scene: Scene, analysis: Analysis, result: CheckResult) -> None:
    """Grouped bars: the normal forces of the remaining supports per retracted support."""
    ax = fig.add_subplot(1, 1, 1)
    names = [s.name for s in scene.supports]
    width = 0.8 / (len(names) - 1)
    drawn: set[str] = set()
    for g, case in enumerate(result.cases):
        forces = case.normal_forces or {}
        for k, name in enumerate(n for n in names if n in forces):
            x = g - 0.4 + width * (k + 0.5)
            value = forces[name]
            colour = f"C{names.index(name)}"
            ax.bar(
                x,
                value,
                width,
                color=colour,
                edgecolor="black" if value <= 0 else colour,
                label=None if name in drawn else name,
            )
            drawn.add(name)
            ax.text(x, value, f"{value:.3g}", ha="center", va="bottom" if value >= 0 else "top",
                    fontsize=6.5)  # fmt: skip
        ax.text(
            g, 1.0, case.outcome.replace("_", " "), transform=ax.get_xaxis_transform(),
            ha="center", va="bottom", fontsize=9,
            color=OUTCOME_COLOURS.get(case.outcome, "black"),
        )  # fmt: skip
    ax.axhline(0, color="black", linewidth=0.8)
    ax.set_xticks(range(len(result.cases)))
    ax.set_xticklabels([f"{c.retracted}\nretracted" for c in result.cases])
    ax.set_ylabel("normal force (N)")
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda k: names.index(labels[k]))
    ax.legend(
        [handles[k] for k in order], [labels[k] for k in order], title="support",
        fontsize=8, loc="upper left", bbox_to_anchor=(1.005, 1.0),
    )  # fmt: skip
    ax.grid(True, axis="y", linewidth=0.4, alpha=0.6)
    load = scene.load
    at = (
        "at the design direction"
        if load is not None and load.magnitude > 0 and load.direction is not None
        else "under gravity"
    )
    ax.set_title(f"{scene.name}: normal forces of the remaining supports {at}", pad=22)
