"""Analytical 3D: Newton–Euler of a six-support coupling with the full inertia tensor."""

from __future__ import annotations

from kcheck.analysis import analyse, closing_force_reason
from kcheck.plugin import Check, Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene
from kcheck_checks.analytical_2d import AnalyticalOptions, analytical_result

__all__ = ["Analytical3D"]


class Analytical3D(Check):
    """Every retracted support of a spatial scene: free screw, outcome, forces, ranges."""

    id = "analytical-3d"
    summary = (
        "Newton–Euler per retracted support with the full inertia tensor: outcome, normal "
        "forces, limiting friction, exact safe ranges in the sweep plane"
    )
    applies_to = "spatial scenes (6 supports) with a body and a closing force"
    needs_mass = True
    options = AnalyticalOptions

    def skip_reason(self, scene: Scene) -> str | None:
        """Spatial scenes with mass properties and a closing force only."""
        if scene.kind != "spatial":
            return "applies to spatial (6-support) scenes; this one is planar"
        return closing_force_reason(scene)

    def run(self, inputs: Inputs) -> CheckResult:
        """Analyse every retracted case."""
        assert inputs.mass is not None and isinstance(inputs.options, AnalyticalOptions)
        analysis = analyse(inputs.scene, inputs.mass)
        return analytical_result(self.id, analysis, inputs.options.min_margin_deg)
