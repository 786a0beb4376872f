"""Pictures of the spatial check: plan and elevation of the scene with each case's free motion,
the map of safe directions (:mod:`kcheck_checks.pictures.sphere`), and the normal forces per
retracted support (:mod:`kcheck_checks.pictures.forces`). matplotlib comes in through
:mod:`kcheck.pictures.plotting`.

The scene is drawn as an engineering drawing: for every retracted support a plan (x–y, seen
from +z) above an elevation (x–z, seen from −y) sharing the x axis. A screw axis is a dashed
line with its rotation sense: a circular arrow where the axis points at the viewer, or ⊙
(towards the viewer) and ⊗ (away) either side of an axis lying in the drawing plane.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.analysis.cases import Analysis
from kcheck.pictures import colours as palette
from kcheck.pictures.colours import outcome_colour
from kcheck.pictures.plotting import figure, save, slug
from kcheck.plugin import Check, Inputs
from kcheck.records import dataclass
from kcheck.report.tables import motion_text
from kcheck.result import CaseResult, CheckResult
from kcheck.scene import Scene
from kcheck_checks.pictures.titles import verdict_colour, verdict_title

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from kcheck_checks.analytical_3d import SphereMap

__all__ = ["plot_spatial", "scene_views", "clip_segment"]

# Largest number of mesh triangles drawn (the body is a rasterised silhouette anyway).
MAX_TRIANGLES = 6000
SUPPORT = palette.SUPPORT
RETRACTED = palette.RETRACTED
LOAD = palette.DESIGN
# Characters of a 9.5 pt panel title that fit a panel 3.8 inches wide.
TITLE_CHARACTERS = 58
GRAVITY = palette.GRAVITY
MOTION = palette.MOTION


@dataclass(frozen=True)
class View:
    """An orthographic view: which coordinates go right and up, and from where it is seen."""

    name: str
    axes: tuple[int, int]
    towards_viewer: np.ndarray  # right × up


VIEWS = (
    View("plan", (0, 1), np.array([0.0, 0.0, 1.0])),
    View("elevation", (0, 2), np.array([0.0, -1.0, 0.0])),
)
AXIS_NAMES = "xyz"


#: Tallest a panel of the scene views may be, as a multiple of its width.
MAX_PANEL_RATIO = 3.0


def plot_spatial(
    scene: Scene,
    analysis: Analysis,
    smap: SphereMap | None,
    result: CheckResult,
    directory: Path,
) -> list[Path]:
    """Write ``<scene>-analytical-3d-{scene,sphere,forces}`` pictures; return the paths."""
    from kcheck_checks.pictures.forces import forces_panel
    from kcheck_checks.pictures.sphere import sphere_figure

    stem = f"{slug(scene.name)}-analytical-3d"
    written: list[Path] = list(
        save(scene_views(scene, analysis, result), directory, f"{stem}-scene")
    )
    if smap is not None:
        written.extend(
            save(sphere_figure(scene, analysis, smap, result), directory, f"{stem}-sphere")
        )
    written.extend(save(forces_panel(scene, result), directory, f"{stem}-forces"))
    return written


def _mesh_triangles(scene: Scene) -> np.ndarray | None:
    """About MAX_TRIANGLES triangles (t, 3, 3) of the body's meshes in scene units, each part
    placed by its units and transform; None without a mesh (or one that cannot be read)."""
    from kcheck.body.mass import place
    from kcheck.body.meshio import load_triangles
    from kcheck.errors import KcheckError

    if scene.body is None or not scene.body.parts:
        return None
    parts = scene.body.parts
    tris = []
    for p in parts:
        try:
            t = load_triangles(p.mesh, p.scale, (*p.field, "mesh"), MAX_TRIANGLES // len(parts))
        except KcheckError:
            continue
        tris.append(place(t, p))
    if not tris:
        return None
    triangles = np.concatenate(tris) / scene.scale
    return triangles if np.all(np.isfinite(triangles)) else None


def clip_segment(
    point: np.ndarray, direction: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray | None:
    """Ends of the part of the line ``point + t direction`` inside the box [lo, hi] (any
    dimension), or None when the line misses it."""
    t0, t1 = -np.inf, np.inf
    for k in range(len(point)):
        # Cosmetic: a line this nearly parallel to a pair of the box's faces is taken as parallel.
        if abs(direction[k]) < 1e-12:
            if not lo[k] <= point[k] <= hi[k]:
                return None
            continue
        a, b = sorted(((lo[k] - point[k]) / direction[k], (hi[k] - point[k]) / direction[k]))
        t0, t1 = max(t0, a), min(t1, b)
    if not t1 > t0:
        return None
    return np.array([point + t0 * direction, point + t1 * direction])


@dataclass(frozen=True)
class Drawing:
    """Everything a view needs, in scene units."""

    points: np.ndarray
    normals: np.ndarray
    names: list[str]
    triangles: np.ndarray | None
    forces: list[tuple[np.ndarray, np.ndarray, str, str]]  # point, unit direction, label, colour
    lo: np.ndarray
    hi: np.ndarray
    arrow: float


def _drawing(scene: Scene, analysis: Analysis) -> Drawing:
    s = scene.scale
    points = np.array([sp.position for sp in scene.supports]) / s
    normals = np.array([sp.normal for sp in scene.supports], float)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    triangles = _mesh_triangles(scene)
    cloud = points if triangles is None else np.vstack([points, triangles.reshape(-1, 3)])
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    size = float(np.max(hi - lo)) or 1.0
    arrow = 0.16 * size
    frame, problem = analysis.problem.frame, analysis.problem
    forces = []
    load = scene.load
    if load is not None and load.magnitude > 0 and load.direction is not None:
        q = (frame.origin + frame.length * problem.load_point) / s
        forces.append((q, np.asarray(load.direction, float), "load", LOAD))
    if np.any(scene.gravity):
        com = (frame.origin + frame.length * problem.com) / s
        g = np.asarray(scene.gravity, float)
        forces.append((com, g / np.linalg.norm(g), "gravity", GRAVITY))
    for p in scene.preloads:
        f = np.asarray(p.force, float)
        if np.any(f):
            big = float(np.abs(f).max())
            unit = (f / big) / np.linalg.norm(f / big)
            forces.append((np.asarray(p.point, float) / s, unit, p.name, LOAD))
    ends = [points - 1.3 * arrow * normals, points]
    ends += [np.array([q - 1.5 * arrow * d, q]) for q, d, _, _ in forces]
    every = np.vstack([cloud, *ends])
    pad = 0.1 * size  # room for the support names
    return Drawing(
        points,
        normals,
        [sp.name for sp in scene.supports],
        triangles,
        forces,
        every.min(axis=0) - pad,
        every.max(axis=0) + pad,
        arrow,
    )


def _labels(ax: Axes, d: Drawing, view: View) -> None:
    """Every support's name beside its point (:func:`kcheck.pictures.labels.label_supports`);
    an arrow seen nearly end-on (under 0.3 of its length) counts as none."""
    from kcheck.pictures.labels import label_supports

    k = list(view.axes)
    arrows = -d.normals[:, k]
    arrows[np.linalg.norm(arrows, axis=1) < 0.3] = 0.0
    label_supports(
        ax, d.points[:, k], arrows, d.names, float(np.max(d.hi - d.lo)),
        fontsize=8, color=SUPPORT, weight="bold",
    )  # fmt: skip


def _rotation_sense(ax: Axes, centre: np.ndarray, axis: np.ndarray, view: View, r: float) -> None:
    """The rotation's sense about ``axis`` (right-handed) drawn around ``centre`` (3D)."""
    k = list(view.axes)
    facing = float(axis @ view.towards_viewer)
    if abs(facing) >= 0.35:
        u = np.cross(axis, view.towards_viewer if abs(facing) < 0.99 else [1.0, 0, 0])
        u = np.cross(axis, u)
        u /= np.linalg.norm(u)
        v = np.cross(axis, u)
        t = np.linspace(0.0, 1.6 * np.pi, 60)
        arc = centre + r * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)
        ax.plot(*arc[:-2, k].T, color=MOTION, lw=1.6, zorder=7)
        ax.annotate(
            "", xy=tuple(arc[-1, k]), xytext=tuple(arc[-4, k]),
            arrowprops={"arrowstyle": "-|>", "color": MOTION, "lw": 1.6}, zorder=7,
        )  # fmt: skip
        return
    # The axis lies (nearly) in the drawing plane: ⊙ where the body comes towards the viewer.
    side = np.cross(view.towards_viewer, axis)
    side /= np.linalg.norm(side)
    for sign in (1.0, -1.0):
        at = centre + sign * r * side
        towards = float(np.cross(axis, sign * side) @ view.towards_viewer) > 0
        ax.text(
            at[k[0]], at[k[1]], "⊙" if towards else "⊗", fontsize=12, color=MOTION,
            ha="center", va="center", zorder=7,
        )  # fmt: skip


def _motion(ax: Axes, d: Drawing, view: View, case: CaseResult, retracted: int, s: float) -> None:
    k = list(view.axes)
    size = float(np.max(d.hi - d.lo))
    motion = case.details.get("motion")
    if motion in ("screw", "rotation") and "axis" in case.details:  # rotation: no pitch
        axis = np.asarray(case.details["axis"], float)
        foot = np.asarray(case.details["axis_point"], float) / s
        centre3 = 0.5 * (d.lo + d.hi)
        nearest = foot + ((centre3 - foot) @ axis) * axis
        seg = (
            clip_segment(nearest[k], axis[k], d.lo[k], d.hi[k])
            # Cosmetic: an axis seen end-on (shorter than 1e-9 in the view) gets no segment.
            if np.linalg.norm(axis[k]) > 1e-9
            else None
        )
        if seg is not None:
            ax.plot(*seg.T, color=MOTION, ls="--", lw=1.6, zorder=5)
        inside = np.all((nearest[k] >= d.lo[k]) & (nearest[k] <= d.hi[k]))
        if inside:
            _rotation_sense(ax, nearest, axis, view, 0.07 * size)
    elif motion == "translation":
        direction = np.asarray(case.details["direction"], float)
        p = d.points[retracted]
        # Cosmetic: an arrow seen end-on (under 1e-6 of its length in the view) is not drawn.
        if np.linalg.norm(direction[k]) > 1e-6:
            ax.annotate(
                "", xy=tuple(p[k] + 1.3 * d.arrow * direction[k]), xytext=tuple(p[k]),
                arrowprops={"arrowstyle": "-|>", "color": MOTION, "lw": 2.0}, zorder=7,
            )  # fmt: skip
        else:
            towards = float(direction @ view.towards_viewer) > 0
            ax.text(
                p[k[0]], p[k[1]], "⊙" if towards else "⊗", fontsize=12, color=MOTION,
                ha="center", va="center",
            )  # fmt: skip


def _view(
    ax: Axes, d: Drawing, view: View, retracted: int, case: CaseResult | None, s: float
) -> None:
    """One orthographic view of the scene with the free motion of one retracted support."""
    from matplotlib.collections import PolyCollection

    k = list(view.axes)
    size = float(np.max(d.hi - d.lo))
    if d.triangles is not None:
        body = PolyCollection(
            # matplotlib's stubs say a sequence of polygons; it takes an (N, 3, 2) array too.
            d.triangles[:, :, k],  # type: ignore[arg-type]
            facecolor=palette.BODY,
            edgecolor="none",
            zorder=0,
            rasterized=True,
        )
        ax.add_collection(body)
    keep = np.arange(len(d.points)) != retracted
    tails = d.points - d.arrow * d.normals
    ax.quiver(
        *tails[keep][:, k].T, *(d.arrow * d.normals[keep][:, k]).T,
        angles="xy", scale_units="xy", scale=1, color=SUPPORT, width=0.006, zorder=4,
    )  # fmt: skip
    ax.plot(*d.points[keep][:, k].T, "o", color=SUPPORT, ms=3.5, zorder=5)
    ax.plot(*d.points[retracted, k], "X", color=RETRACTED, ms=9, mec=palette.PAPER, zorder=6)
    ax.plot(
        *np.array([tails[retracted], d.points[retracted]])[:, k].T, ":", color=RETRACTED, lw=1.5
    )
    # Labels placed so far: a second one at the same place goes a line below.
    placed: list[np.ndarray] = []
    for q, direction, label, colour in d.forces:
        tail = q - 1.5 * d.arrow * direction
        # Cosmetic: an arrow seen end-on (under 1e-6 of its length in the view) is not drawn.
        if np.linalg.norm(direction[k]) > 1e-6:
            ax.annotate(
                "", xy=tuple(q[k]), xytext=tuple(tail[k]),
                arrowprops={"arrowstyle": "-|>", "color": colour, "lw": 2.2}, zorder=6,
            )  # fmt: skip
            near = int(sum(np.linalg.norm(p - tail[k]) < 0.05 * size for p in placed))
            placed.append(tail[k])
            ax.annotate(
                f" {label}", xy=tuple(tail[k]), xytext=(0, -10 * near),
                textcoords="offset points", color=colour, fontsize=8, va="center", zorder=6,
            )  # fmt: skip
        else:
            towards = float(direction @ view.towards_viewer) > 0
            near = int(sum(np.linalg.norm(p - q[k]) < 0.05 * size for p in placed))
            placed.append(q[k])
            ax.annotate(
                ("⊙ " if towards else "⊗ ") + label, xy=tuple(q[k]), xytext=(0, -11 * near),
                textcoords="offset points", color=colour, fontsize=9, zorder=6, va="top",
            )  # fmt: skip
    if case is not None:
        _motion(ax, d, view, case, retracted, s)
    ax.set_xlim(d.lo[k[0]], d.hi[k[0]])
    ax.set_ylim(d.lo[k[1]], d.hi[k[1]])
    ax.set_aspect("equal")
    ax.locator_params(nbins=5)  # fewer tick labels: text is most of the drawing time
    ax.tick_params(labelsize=7)
    ax.set_ylabel(f"{AXIS_NAMES[k[1]]}", fontsize=8, rotation=0, labelpad=6)
    ax.grid(True, lw=0.3, alpha=0.5)


def _panel_title(name: str, case: CaseResult | None, units: str) -> tuple[str, str]:
    """ "B.1 retracted: closes — pure rotation about (...)" and its colour."""
    if case is None:
        return f"{name} retracted", palette.INK
    motion = motion_text(case.details, units)
    outcome = case.outcome.replace("_", " ")
    return f"{name} retracted: {outcome} — {motion}", outcome_colour(case.outcome)


def scene_views(scene: Scene, analysis: Analysis, result: CheckResult) -> Any:
    """Plan over elevation for every retracted support, three supports a row."""
    d = _drawing(scene, analysis)
    n = len(d.points)
    cols = min(3, n)
    rows = int(np.ceil(n / cols))
    extent = d.hi - d.lo
    # Panel heights per width, bounded: a load point 85 m above a 0.1 m block made a figure
    # of 386 million pixels (1.7 GB and a minute to encode; issue 13's fuzzer). Past the
    # bound the drawing keeps its true proportions and leaves the panel's width unused.
    plan_h = min(max(extent[1] / extent[0], 0.25), MAX_PANEL_RATIO)
    elev_h = min(max(extent[2] / extent[0], 0.25), MAX_PANEL_RATIO)
    width = 4.6
    # The drawing width of a panel (the figure's margins and gaps taken off), in inches.
    drawn = cols * width * 0.94 / (cols + 0.2 * (cols - 1))
    pair = drawn * (plan_h + elev_h) + 0.35  # one plan over its elevation, inches
    cases = {c.retracted: c for c in result.cases}
    titles = [_panel_title(name, cases.get(name), scene.units) for name in d.names]
    # A title too long for its panel (a rotation axis with three components) goes on two
    # lines, and every row gets the room for them.
    long = any(len(t) > TITLE_CHARACTERS * drawn / 3.8 for t, _ in titles)
    extra = 0.17 if long else 0.0
    status = verdict_title(result)
    lines = status.count("\n")
    head = 1.15 + 0.22 * lines  # room for the title and the caption, inches
    height = rows * (pair + 0.45 + extra) + head + extra
    fig = figure(figsize=(cols * width, height), layout=None)
    outer = fig.add_gridspec(
        rows, cols, left=0.05, right=0.99, bottom=0.35 / height,
        top=1 - (head + extra) / height, hspace=(0.4 + extra) / pair, wspace=0.2,
    )  # fmt: skip
    placed: list[tuple[Axes, Axes]] = []
    for i, name in enumerate(d.names):
        inner = outer[divmod(i, cols)].subgridspec(
            2, 1, height_ratios=[plan_h, elev_h], hspace=0.35 / pair
        )
        plan = fig.add_subplot(inner[0])
        elev = fig.add_subplot(inner[1], sharex=plan)
        case = cases.get(name)
        for ax, view in zip((plan, elev), VIEWS, strict=True):
            _view(ax, d, view, i, case, scene.scale)
        plan.set_anchor("S")  # the elevation sits right under its plan
        elev.set_anchor("N")
        placed.append((plan, elev))
        # Every panel has the same limits: numbers only on the outer edges (text is most of
        # the drawing time), grid lines everywhere.
        plan.tick_params(labelbottom=False)
        if i % cols:
            for ax in (plan, elev):
                ax.tick_params(labelleft=False)
                ax.set_ylabel("")
        if i + cols < n:
            elev.tick_params(labelbottom=False)
        else:
            elev.set_xlabel(f"x ({scene.units})", fontsize=8)
        title, colour = titles[i]
        if long:
            title = title.replace(" — ", "\n", 1)
        plan.set_title(title, fontsize=9.5, color=colour, loc="left")
    # Names last: placing them measures them in the panels as laid out.
    for pair in placed:
        for ax, view in zip(pair, VIEWS, strict=True):
            _labels(ax, d, view)
    fig.suptitle(
        f"{scene.name} — {status}", fontsize=12, color=verdict_colour(result),
        y=1 - 0.12 / height, va="top",
    )  # fmt: skip
    fig.text(
        0.5, 1 - (0.4 + 0.22 * lines) / height,
        f"free motion when each support is retracted ({scene.units}); each: plan (x–y, from +z)"
        " over elevation (x–z, from −y);\ndark grey: supports pushing along their normals, "
        "grey ×: the retracted one; purple: screw axis and rotation sense (⊙ towards you, "
        "⊗ away); navy: the load (design direction), preloads; brown: gravity",
        ha="center", va="top", fontsize=8.5, color=palette.MUTED,
    )  # fmt: skip
    return fig


def draw(check: Check, inputs: Inputs, result: CheckResult, directory: Path) -> list[Path]:
    """analytical-3d's pictures: the scene with screw axes, the safe-direction map, normal
    forces per case, and the safe set against friction."""
    from kcheck.analysis import analyse
    from kcheck_checks.analytical_3d import Analytical3DOptions, spatial_result
    from kcheck_checks.pictures.friction import plot_friction

    assert inputs.mass is not None and isinstance(inputs.options, Analytical3DOptions)
    analysis = analyse(inputs.scene, inputs.mass)
    _, smap, analysis = spatial_result(check.id, inputs.scene, analysis, inputs.options)
    paths = plot_spatial(inputs.scene, analysis, smap, result, directory)
    return [*paths, *plot_friction(check.id, inputs, result, directory)]
