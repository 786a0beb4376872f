"""Draw docs/figures/tool-changer.png: the tool changer fixture as kcheck reads it.

``python docs/figures/tool_changer.py`` (needs the `plot` extra). Top and side views of the
plate outline, the balls, the dowel pins and every expanded contact with its normal, all taken
from the loaded scene (so the picture shows what the shorthands expand to, not a drawing).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, Rectangle

from kcheck.body.mass import body_mass_properties
from kcheck.scene import load_scene

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "fixtures" / "tool-changer" / "tool.kcheck.yaml"
OUT = Path(__file__).with_name("tool-changer.png")
PIN_LENGTH_MM = 14.0


def main() -> None:
    scene = load_scene(SCENE)
    mass = body_mass_properties(scene.body)
    mm = 1e3
    fig, (top, side) = plt.subplots(
        1, 2, figsize=(11, 5.2), gridspec_kw={"width_ratios": [1, 1.25]}
    )
    for ax in (top, side):
        ax.set_aspect("equal")
        ax.grid(True, color="0.9", lw=0.6)
    # The plate (rotated back from its print orientation) as the loader placed it.
    lo, hi = mass.part_bounds[0] * mm
    top.add_patch(Circle((0, 0), (hi[0] - lo[0]) / 2, fc="0.93", ec="0.6", lw=1, label="plate"))
    side.add_patch(Rectangle((lo[0], lo[2]), hi[0] - lo[0], hi[2] - lo[2], fc="0.93", ec="0.6"))
    seen: set[str] = set()
    for s in scene.supports:
        g = s.geometry
        c, r = g.ball_center * mm, g.ball_radius * mm
        if g.coupling not in seen:
            seen.add(g.coupling)
            top.add_patch(Circle(c[:2], r, fc="#c9d6e8", ec="#3b5b8c", lw=1.2))
            side.add_patch(Circle(c[[0, 2]], r, fc="#c9d6e8", ec="#3b5b8c", lw=1.2))
            top.annotate(g.coupling, c[:2] + [0, r + 2.5], ha="center", fontsize=9)
        # The pin: its axis through the contact's foot, along the surface's first direction.
        pin_r = g.base.radii[1] * mm
        axis = g.base.direction
        centre = s.position * mm - s.normal * pin_r  # from the contact to the pin's axis
        ends = np.array([centre - axis * PIN_LENGTH_MM / 2, centre + axis * PIN_LENGTH_MM / 2])
        top.plot(
            ends[:, 0],
            ends[:, 1],
            color="#8c5a3b",
            lw=2 * pin_r * 1.1,
            alpha=0.35,
            solid_capstyle="butt",
        )
        top.plot(ends[:, 0], ends[:, 1], color="#8c5a3b", lw=0.8)
        if abs(axis[1]) > 0.99:  # the pins of b1 run along y: circles in the side view
            side.add_patch(Circle(centre[[0, 2]], pin_r, fc="#e8d3c4", ec="#8c5a3b", lw=1))
        p, n = s.position * mm, s.normal
        for ax, idx in ((top, [0, 1]), (side, [0, 2])):
            ax.plot(*p[idx], "o", color="#b3261e", ms=4)
            ax.annotate(
                "",
                p[idx] + 6 * n[idx],
                p[idx],
                arrowprops={"arrowstyle": "-|>", "color": "#b3261e", "lw": 1.2},
            )
    com = mass.center_of_mass * mm
    for ax, idx in ((top, [0, 1]), (side, [0, 2])):
        ax.plot(*com[idx], marker="+", color="k", ms=10, mew=1.5)
    # The magnet's preload along its line of action (drawn above the plate, not through b1).
    magnet = scene.preloads[0]
    x = magnet.point[0] * mm
    down = np.sign(magnet.force[2])
    side.annotate(
        "",
        (x, hi[2] + 0.3),
        (x, hi[2] + 0.3 - 4.5 * down),
        arrowprops={"arrowstyle": "-|>", "color": "#1f7a3a", "lw": 2},
    )
    side.text(
        x + 1.5,
        hi[2] + 2.2,
        f"magnet preload {abs(magnet.force[2]):g} N",
        color="#1f7a3a",
        fontsize=9,
    )
    top.set(title="top view (x, y in mm)", xlim=(-45, 45), ylim=(-45, 45))
    side.set(title="side view (x, z in mm): b1's pins end-on", xlim=(-45, 45), ylim=(-14, 18))
    top.plot([], [], "o", color="#b3261e", ms=4, label="contact, normal into the body")
    top.plot([], [], color="#8c5a3b", lw=3, alpha=0.5, label="dowel pin (base)")
    top.plot([], [], "+", color="k", ms=8, label="centre of mass")
    top.legend(loc="lower left", fontsize=8, framealpha=0.9)
    fig.suptitle(
        "fixtures/tool-changer: three `ball-cylinders` couplings expanded into six supports"
    )
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
