"""Maxwell's criterion and the determinacy of the support layout (methods.md §2)."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from kcheck.analysis import support_layout
from kcheck.kinematics import RANK_RTOL, free_twist, layout_singular_values, maxwell_cos
from kcheck.plugin import Check, Inputs, Options
from kcheck.result import CaseResult, CheckResult, Status

__all__ = ["Maxwell", "MaxwellOptions"]

EPS = float(np.finfo(float).eps)


class MaxwellOptions(Options):
    """Options of the ``maxwell`` check."""

    min_cos: float = Field(0.7, ge=0, le=1, description="Smallest acceptable cos(theta)")


class Maxwell(Check):
    """Rank of the constraint matrix and, per support, how squarely its free motion meets it."""

    id = "maxwell"
    summary = "layout determinacy and Maxwell's criterion: cos(theta) of each support's free motion"
    applies_to = "planar (3 supports) and spatial (6 supports) scenes"
    needs_mass = False
    options = MaxwellOptions

    def run(self, inputs: Inputs) -> CheckResult:
        """Rank and smallest scaled singular value of the layout; cos(theta) per support."""
        scene, opts = inputs.scene, inputs.options
        assert isinstance(opts, MaxwellOptions)
        _, points, normals = support_layout(scene)
        singular = layout_singular_values(points, normals)
        rank = int(np.count_nonzero(singular > RANK_RTOL * singular[0]))
        sigma = float(singular[-1] / singular[0])
        deterministic = rank == len(points)
        cases = []
        worst_error = 0.0
        for r, support in enumerate(scene.supports):
            free = free_twist(points, normals, r)
            if not deterministic or free.determinacy <= RANK_RTOL:
                cases.append(CaseResult(support.name, "undetermined"))
                continue
            cos = maxwell_cos(free, points[r], normals[r])
            # The null vector is perturbed by about eps / (its singular-value gap).
            worst_error = max(worst_error, 8 * EPS / free.determinacy)
            outcome = "ok" if cos >= opts.min_cos else "poor"
            cases.append(
                CaseResult(
                    support.name,
                    outcome,
                    cos_maxwell=cos,
                    details={"theta_deg": float(np.degrees(np.arccos(min(cos, 1.0))))},
                )
            )
        details = {"rank": rank, "smallest_scaled_singular_value": sigma, "min_cos": opts.min_cos}
        if not deterministic:
            return CheckResult(
                self.id,
                Status.FAIL,
                f"not deterministic: constraint matrix rank {rank} of {len(points)}, so "
                f"{len(points) - rank} motion(s) stay free with every support in place "
                "(e.g. all normals through one point)",
                error_estimate=None,
                cases=tuple(cases),
                details=details,
            )
        poor = [c for c in cases if c.outcome != "ok"]
        worst = min(cases, key=lambda c: c.cos_maxwell if c.cos_maxwell is not None else -1)
        near = sigma < 1e-6
        if poor:
            names = ", ".join(c.retracted for c in poor)
            status, message = (
                Status.FAIL,
                (
                    f"cos(theta) below {opts.min_cos} at {names}; worst {worst.retracted} "
                    f"cos = {worst.cos_maxwell:.3f}"
                ),
            )
        else:
            status, message = (
                Status.PASS,
                (
                    f"deterministic; every cos(theta) >= {opts.min_cos} "
                    f"(worst {worst.retracted}: {worst.cos_maxwell:.3f})"
                ),
            )
        if near:
            message += f"; nearly singular layout (scaled sigma_min {sigma:.1e})"
        return CheckResult(
            self.id,
            status,
            message,
            error_estimate=worst_error,
            cases=tuple(cases),
            details=details,
        )
