"""Pictures a reader can read (issue 22): support names beside their own supports and inside
the frame, legends and titles clear of the panels' titles and tick labels, the design
direction drawn whether the check passes or fails, and empty pictures saying why.

The bundled fixtures are checked with every check that draws (the friction pictures, which
repeat each check at 41 to 121 coefficients, are drawn for two fixtures only).
Each figure is drawn on the Agg canvas where it would be written, and measured in display
coordinates (pixels).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from kcheck.gate.runner import Settings, check_scene  # noqa: E402
from kcheck.pictures import colours as palette  # noqa: E402
from kcheck.pictures.labels import EMPTY_GID, GID_PREFIX  # noqa: E402
from kcheck.plugin import load_checks  # noqa: E402
from kcheck.scene import load_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = sorted((ROOT / "fixtures").glob("*/*.kcheck.yaml"))
DRAWN = ("analytical-2d", "analytical-3d", "graphical-2d", "hertz", "jamming")
#: Largest gap between a support's point and its name's box, pixels at 100 dpi (the name is
#: set 6 pt = 8.3 px away; 4 px for the box's padding and rounding).
BESIDE_PX = 12.5


def _draw(fig: Any) -> Any:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = fig.canvas if hasattr(fig.canvas, "get_renderer") else FigureCanvasAgg(fig)
    canvas.draw()
    return canvas.get_renderer()


def _views(name: str) -> list[tuple[int, int]]:
    """The scene coordinates each axes of a picture shows, in the order the axes are made."""
    return [(0, 1), (0, 2)] if name.endswith("-scene.png") else [(0, 1)]


def _measure(fig: Any, name: str) -> dict[str, Any]:
    """What the tests read off a drawn figure: support labels (names, anchor and box in
    pixels, the axes' box), title/legend/tick boxes, design-coloured artists, empty notes."""
    from matplotlib.colors import to_rgba

    renderer = _draw(fig)
    design = to_rgba(palette.DESIGN)[:3]
    labels, titles, ticks, legends = [], [], [], []
    design_marks = 0
    empty, others = [], []
    for index, ax in enumerate(fig.axes):
        frame = ax.get_window_extent(renderer)
        for text in ax.texts:
            gid = text.get_gid() or ""
            if gid.startswith(GID_PREFIX):
                anchor = ax.transData.transform(text.xy)
                labels.append((gid[len(GID_PREFIX) :].split(","), text.xy, anchor,
                               text.get_window_extent(renderer), frame, index,
                               ax.transData.frozen()))  # fmt: skip
            elif text.get_text() and text.get_visible():
                others.append((index, text.get_window_extent(renderer), text.get_text()))
            if gid == EMPTY_GID:
                empty.append(text.get_text())
            arrow = getattr(text, "arrow_patch", None)
            if arrow is not None and to_rgba(arrow.get_edgecolor())[:3] == design:
                design_marks += 1
        for line in ax.lines:
            colours = {to_rgba(line.get_color())[:3], to_rgba(line.get_markerfacecolor())[:3]}
            if design in colours and len(line.get_xdata()):
                design_marks += 1
        for loc in ("left", "center", "right"):
            title = ax._left_title if loc == "left" else ax.title if loc == "center" else None
            if title is not None and title.get_text():
                titles.append(title.get_window_extent(renderer))
        for tick in [*ax.get_xticklabels(), *ax.get_yticklabels()] if ax.axison else []:
            if tick.get_visible() and tick.get_text():
                ticks.append(tick.get_window_extent(renderer))
        if ax.get_legend() is not None:
            legends.append(ax.get_legend().get_window_extent(renderer))
    legends += [leg.get_window_extent(renderer) for leg in fig.legends]
    suptitle = fig._suptitle.get_window_extent(renderer) if fig._suptitle is not None else None
    return {
        "name": name,
        "labels": labels,
        "others": others,
        "titles": titles,
        "ticks": ticks,
        "legends": legends,
        "suptitle": suptitle,
        "figure": fig.bbox,
        "design_marks": design_marks,
        "empty": empty,
        "views": _views(name),
    }


def _run(path: Path, tmp: Path, friction: bool = False) -> tuple[Any, list[dict[str, Any]]]:
    from matplotlib.figure import Figure

    seen: list[dict[str, Any]] = []

    def record(fig: Figure, target: Any, *args: Any, **kwargs: Any) -> None:
        seen.append(_measure(fig, Path(target).name))

    checks = [c for c in load_checks() if c.spec.name in DRAWN]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Figure, "savefig", record)
        if not friction:
            mp.setattr("kcheck_checks.pictures.friction.plot_friction", lambda *a, **k: ())
        result = check_scene(path, checks, settings=Settings(plots=tmp))
    return result, seen


@pytest.fixture(scope="module")
def drawn(tmp_path_factory: pytest.TempPathFactory) -> list[tuple[Path, Any, dict[str, Any]]]:
    out = []
    for path in FIXTURES:
        result, seen = _run(path, tmp_path_factory.mktemp("plots"))
        out += [(path, result, fig) for fig in seen]
    return out


def _gap(box: Any, point: np.ndarray) -> float:
    """Distance (pixels) from a point to a box, 0 inside it."""
    gap_x = max(box.x0 - point[0], point[0] - box.x1, 0.0)
    gap_y = max(box.y0 - point[1], point[1] - box.y1, 0.0)
    return float(np.hypot(gap_x, gap_y))


@pytest.mark.slow
def test_support_names_sit_beside_their_own_supports(
    drawn: list[tuple[Path, Any, dict[str, Any]]],
) -> None:
    """Each name is anchored at its own support's point as the scene gives it (scene units,
    projected on the view), its box within BESIDE_PX of that point, inside the axes."""
    checked = 0
    for path, _, fig in drawn:
        if not fig["labels"]:
            continue
        scene = load_scene(path)
        where = {s.name: np.asarray(s.position) / scene.scale for s in scene.supports}
        size = float(np.ptp(np.array(list(where.values())), axis=0).max())
        axes_order: list[Any] = []
        for names, xy, anchor, box, frame, index, transform in fig["labels"]:
            if index not in axes_order:
                axes_order.append(index)
            view = fig["views"][axes_order.index(index) % len(fig["views"])]
            own = np.array([where[n][list(view)] for n in names])
            # the anchor is its supports' point (their middle when several coincide)
            assert np.allclose(xy, own.mean(axis=0), atol=1e-9 * size), (fig["name"], names)
            assert _gap(box, anchor) <= BESIDE_PX, (fig["name"], names, _gap(box, anchor))
            # supports sharing a name coincide to a few pixels: each is beside it too
            for point in transform.transform(own):
                assert _gap(box, point) <= 2.5 * BESIDE_PX, (fig["name"], names)
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1, (fig["name"], names)
            assert frame.y0 <= box.y0 and box.y1 <= frame.y1, (fig["name"], names)
            checked += 1
        # every support is named in every view of it
        named = {n for names, *_ in fig["labels"] for n in names}
        assert named == set(where), (fig["name"], set(where) - named)
    assert checked > 100  # the 3D fixtures' plan and elevation views and the planar ones


@pytest.mark.slow
def test_support_names_do_not_cover_each_other(
    drawn: list[tuple[Path, Any, dict[str, Any]]],
) -> None:
    """...nor any other text in their panel (a pole's name, an angle, the load's name)."""
    for _, _, fig in drawn:
        boxes = [(names, box, ax) for names, _, _, box, _, ax, _ in fig["labels"]]
        for i, (a, box_a, ax_a) in enumerate(boxes):
            for b, box_b, ax_b in boxes[:i]:
                if ax_a == ax_b:
                    assert not box_a.overlaps(box_b), (fig["name"], a, b)
            for ax, box, text in fig["others"]:
                if ax == ax_a:
                    assert not box_a.overlaps(box), (fig["name"], a, text)


@pytest.mark.slow
def test_legends_and_titles_clear_the_panels(
    drawn: list[tuple[Path, Any, dict[str, Any]]],
) -> None:
    """The figure's title and legends cover no panel title or tick label; all inside the
    figure."""
    for _, _, fig in drawn:
        _assert_clear(fig)


@pytest.mark.slow
def test_friction_pictures_are_clear_and_draw_the_design(tmp_path: Path) -> None:
    """The pictures against friction of a failing planar scene and a passing spatial one."""
    names = []
    for fixture in ("thesis-appendix-a/block", "kelvin/coupling"):
        path = ROOT / "fixtures" / f"{fixture}.kcheck.yaml"
        _, seen = _run(path, tmp_path / fixture.split("/")[0], friction=True)
        for fig in seen:
            if fig["name"].endswith("-friction.png"):
                names.append(fig["name"])
                _assert_clear(fig)
                assert fig["design_marks"] >= 1, fig["name"]
    assert len(names) == 4  # analytical-2d, graphical-2d, jamming; analytical-3d


def _assert_clear(fig: dict[str, Any]) -> None:
    """The figure's title, legends and panel titles inside the figure; its title and legends
    over no panel title or tick label (pixels, after drawing)."""
    inside = fig["figure"]
    for box in [*fig["legends"], *fig["titles"]] + (
        [fig["suptitle"]] if fig["suptitle"] is not None else []
    ):
        assert inside.x0 - 1 <= box.x0 and box.x1 <= inside.x1 + 1, fig["name"]
        assert inside.y0 - 1 <= box.y0 and box.y1 <= inside.y1 + 1, fig["name"]
    for legend in fig["legends"]:
        for other in [*fig["titles"], *fig["ticks"]]:
            assert not legend.overlaps(other), (fig["name"], "legend", other)
    if fig["suptitle"] is not None:
        for other in [*fig["titles"], *fig["ticks"]]:
            assert not fig["suptitle"].overlaps(other), (fig["name"], "suptitle")


@pytest.mark.slow
def test_the_design_direction_is_drawn_pass_or_fail(
    drawn: list[tuple[Path, Any, dict[str, Any]]], tmp_path: Path
) -> None:
    """In every picture showing directions (not the forces bars), the design direction is
    drawn in its colour: for the fixtures (thesis appendix A fails) and for the 3-2-1 block
    pushed the wrong way, whose analytical-3d and jamming checks fail."""
    source = ROOT / "fixtures" / "block-321"
    (tmp_path / "block.stl").write_bytes((source / "block.stl").read_bytes())
    text = (source / "block.kcheck.yaml").read_text()
    scene = tmp_path / "block.kcheck.yaml"
    scene.write_text(
        text.replace("direction: [-0.57, -0.82, 0.04]", "direction: [0.57, 0.82, 0.3]")
    )
    result, seen = _run(scene, tmp_path / "plots")
    assert {c.status.value for c in result.checks} >= {"fail"}
    statuses = set()
    for path, scene_result, fig in [*drawn, *((scene, result, f) for f in seen)]:
        if fig["name"].endswith(("-forces.png", "-hertz.png")):
            continue  # bars of forces and stresses: no direction drawn
        load = load_scene(path).load
        if load is None or load.direction is None or not load.magnitude > 0:
            continue  # no design direction to draw (a load swept over every angle)
        statuses.add(scene_result.status.value)
        assert fig["design_marks"] >= 1, fig["name"]
    assert {"pass", "fail"} <= statuses


def test_an_empty_friction_picture_says_why(tmp_path: Path) -> None:
    """A friction picture where no angle is safe at any coefficient writes why in its axes."""
    from kcheck_checks.pictures.friction import _band_picture
    from matplotlib.figure import Figure

    path = ROOT / "fixtures" / "thesis-appendix-a" / "block.kcheck.yaml"
    checks = [c for c in load_checks() if c.spec.name == "analytical-2d"]
    result = check_scene(path, checks).checks[0]
    notes: list[str] = []

    def record(fig: Figure, target: Any, *args: Any, **kwargs: Any) -> None:
        notes.extend(t.get_text() for ax in fig.axes for t in ax.texts if t.get_gid() == EMPTY_GID)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Figure, "savefig", record)
        _band_picture(
            load_scene(path), result, "analytical-2d", "kinetic", lambda at: [], "safe angles",
            tmp_path,
        )  # fmt: skip
    assert len(notes) == 1 and notes[0].startswith("no safe angles at any kinetic μ from 0")
