"""Draws docs/figures/tool-changer.png: the tool changer fixture as kcheck reads it.

Run: ``python docs/figures/tool_changer.py`` (needs the `plot` extra). Top and side views of
the plate outline, the balls, the dowel pins and every expanded contact with its normal, all
taken from the loaded scene (the picture shows what the shorthands expand to, not a drawing).
Colours are the pictures' own language (:mod:`kcheck.pictures.colours`): supports dark grey,
the closing force (the magnet's preload) navy, the body in the body's greys.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle, Rectangle  # noqa: E402

from kcheck.body.mass import body_mass_properties  # noqa: E402
from kcheck.pictures import colours  # noqa: E402
from kcheck.scene import ContactGeometry, load_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "fixtures" / "tool-changer" / "tool.kcheck.yaml"
OUT = Path(__file__).with_name("tool-changer.png")
PIN_LENGTH_MM = 14.0
MM = 1e3
BALL: dict[str, Any] = {"fc": colours.PAPER, "ec": colours.BODY_EDGE, "lw": 1.2}
PLATE: dict[str, Any] = {"fc": colours.BODY, "ec": colours.BODY_EDGE, "lw": 1.0}
PIN: dict[str, Any] = {"fc": colours.NO_VALUE, "ec": colours.MUTED, "lw": 1.0}


def _xy(p: np.ndarray) -> tuple[float, float]:
    """A point of the picture from a 2-vector."""
    return float(p[0]), float(p[1])


def main() -> None:
    scene = load_scene(SCENE)
    assert scene.body is not None, f"{SCENE}: the fixture has a body"
    mass = body_mass_properties(scene.body, scene.scale)
    fig, (top, side) = plt.subplots(
        1, 2, figsize=(11, 5.2), gridspec_kw={"width_ratios": [1, 1.25]}
    )
    for ax in (top, side):
        ax.set_aspect("equal")
        ax.grid(True, lw=0.6, alpha=0.3)
    # The plate (turned over from its print orientation) as the loader placed it.
    lo, hi = mass.part_bounds[0] * MM
    top.add_patch(Circle((0, 0), (hi[0] - lo[0]) / 2, label="plate (body)", **PLATE))
    side.add_patch(Rectangle(_xy(lo[[0, 2]]), hi[0] - lo[0], hi[2] - lo[2], **PLATE))
    seen: set[str] = set()
    for s in scene.supports:
        g = s.geometry
        assert isinstance(g, ContactGeometry), f"{s.name} comes from a coupling shorthand"
        c, r = g.ball_center * MM, g.ball_radius * MM
        if g.coupling not in seen:
            seen.add(g.coupling)
            top.add_patch(Circle(_xy(c[:2]), r, **BALL))
            side.add_patch(Circle(_xy(c[[0, 2]]), r, **BALL))
            top.annotate(g.coupling, c[:2] + [0, r + 2.5], ha="center", fontsize=9)
        # The pin: its axis through the contact's foot, along the surface's first direction.
        pin_r = g.base.radii[1] * MM
        axis = g.base.direction
        assert axis is not None, f"{s.name}: a pin has an axis"
        centre = s.position * MM - s.normal * pin_r  # from the contact to the pin's axis
        ends = np.array([centre - axis * PIN_LENGTH_MM / 2, centre + axis * PIN_LENGTH_MM / 2])
        top.plot(*ends[:, :2].T, color=PIN["fc"], lw=2 * pin_r * 1.1, solid_capstyle="butt")
        top.plot(*ends[:, :2].T, color=PIN["ec"], lw=0.8)
        if abs(axis[1]) > 0.99:  # the pins of b1 run along y: circles in the side view
            side.add_patch(Circle(_xy(centre[[0, 2]]), pin_r, **PIN))
        p, n = s.position * MM, s.normal
        for ax, idx in ((top, [0, 1]), (side, [0, 2])):
            ax.plot(*p[idx], "o", color=colours.SUPPORT, ms=4)
            ax.annotate(
                "",
                p[idx] + 6 * n[idx],
                p[idx],
                arrowprops={"arrowstyle": "-|>", "color": colours.SUPPORT, "lw": 1.2},
            )
    com = mass.center_of_mass * MM
    for ax, idx in ((top, [0, 1]), (side, [0, 2])):
        ax.plot(*com[idx], marker="+", color=colours.INK, ms=10, mew=1.5)
    # The magnet's preload along its line of action (drawn above the plate, not through b1).
    magnet = scene.preloads[0]
    x = magnet.point[0] * MM
    down = np.sign(magnet.force[2])
    side.annotate(
        "",
        (x, hi[2] + 0.3),
        (x, hi[2] + 0.3 - 4.5 * down),
        arrowprops={"arrowstyle": "-|>", "color": colours.DESIGN, "lw": 2},
    )
    side.text(
        x + 1.5,
        hi[2] + 2.2,
        f"magnet preload {abs(magnet.force[2]):g} N",
        color=colours.DESIGN,
        fontsize=9,
    )
    top.set(title="top view (x, y in mm)", xlim=(-45, 45), ylim=(-45, 45))
    side.set(title="side view (x, z in mm): b1's pins end-on", xlim=(-45, 45), ylim=(-14, 18))
    top.plot([], [], "o", color=colours.SUPPORT, ms=4, label="contact, normal into the body")
    top.plot([], [], color=PIN["fc"], lw=3, label="dowel pin (base)")
    com_label = f"centre of mass ({com[0]:.1f}, {com[1]:.1f}, {com[2]:.1f}) mm"
    top.plot([], [], "+", color=colours.INK, ms=8, label=com_label)
    top.legend(loc="lower left", fontsize=8, framealpha=0.9)
    fig.suptitle(
        "fixtures/tool-changer: three `ball-cylinders` couplings expanded into six supports"
    )
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
