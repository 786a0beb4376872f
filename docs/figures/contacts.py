"""Draws docs/figures/contacts.png: the contacts `kcheck contacts` finds on the three-vee
assembly of tests/contact_assemblies.py (balls on the body, vees of two flat blocks each on
the base): contact points, normals (from the base into the body) and the fitted balls, in the
pictures' colours (:mod:`kcheck.pictures.colours`: supports dark grey).

Run: ``python docs/figures/contacts.py`` (needs matplotlib).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))

from contact_assemblies import three_vee  # noqa: E402

from kcheck.body.contact_regions import contact_regions  # noqa: E402
from kcheck.body.coupling_elements import recognise  # noqa: E402
from kcheck.pictures import colours  # noqa: E402


def main() -> None:
    base, body = three_vee()
    gap = 1e-3 * float(np.linalg.norm(np.ptp(np.vstack([base.bounds, body.bounds]), axis=0)))
    found = recognise(contact_regions(base, body, gap)[0], gap)
    fig = plt.figure(figsize=(11, 5))
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 24), np.linspace(0, np.pi, 12))
    for panel, (half, zoom) in enumerate(((60.0, None), (12.0, found.elements[1]))):
        ax = fig.add_subplot(1, 2, panel + 1, projection="3d")
        ax.add_collection3d(
            Poly3DCollection(
                base.triangles, facecolor=colours.NO_VALUE, edgecolor=colours.FAINT, alpha=0.4
            )
        )
        # the closer panel draws its own element only: 3-d text is not clipped to the axes
        for e in found.elements if zoom is None else (zoom,):
            assert e.ball is not None, f"{e.name}: a ball-vee has a fitted ball"
            c, r = e.ball.point, e.ball.radius
            ax.plot_wireframe(
                c[0] + r * np.cos(u) * np.sin(v),
                c[1] + r * np.sin(u) * np.sin(v),
                c[2] + r * np.cos(v),
                color=colours.BODY_EDGE,
                linewidth=0.3,
            )
            ax.text(c[0], c[1], c[2] + 1.5 * r, f"{e.name}: {e.kind}", fontsize=8, ha="center")
            for k in e.contacts:
                ax.scatter(*k.point, color=colours.SUPPORT, s=16, depthshade=False)
                ax.quiver(*k.point, *(0.4 * half * k.normal), color=colours.SUPPORT, linewidth=1.4)
        centre = np.zeros(3) if zoom is None or zoom.ball is None else zoom.ball.point
        for setter, x in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
            setter(x - half, x + half)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel("x, mm")
        ax.set_ylabel("y, mm")
        ax.set_zlabel("z, mm")
        ax.view_init(elev=20, azim=-75)
        ax.set_title("the assembly" if zoom is None else f"{zoom.name}, closer", fontsize=9)
    fig.suptitle(
        "kcheck contacts on a three-vee assembly: fitted balls (grey wire), contact points and\n"
        "normals from the base into the body (dark grey: supports); the base's blocks light "
        "grey, the body's plate not drawn",
        fontsize=9,
        y=1.0,
    )
    fig.savefig(Path(__file__).with_name("contacts.png"), dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    main()
