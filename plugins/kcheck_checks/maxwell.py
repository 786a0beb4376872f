"""Maxwell's criterion and the determinacy of the support layout (methods.md §2).

Maxwell's criterion is a rule of thumb: a low cos(theta) does not stop a coupling from
closing (the analytical checks decide that). So the check's default severity is ``warning``:
it is shown, and fails a run only with ``--strict`` (or a severity set to ``error``).
"""

from __future__ import annotations

import numpy as np

from kcheck.analysis.cases import support_layout
from kcheck.fmt import format_angle, format_number
from kcheck.mechanics.kinematics import (
    RANK_RTOL,
    free_twist,
    layout_singular_values,
    maxwell_angle,
    maxwell_cos,
    point_velocity,
)
from kcheck.numerics.margins import MARGINAL_COS
from kcheck.numerics.thresholds import EPS, NEARLY_SINGULAR, NOISE_RTOL
from kcheck.plugin import Check, Field, Inputs, Options
from kcheck.result import CaseResult, CheckResult, Finding, Status
from kcheck_checks.marginal import with_margin

__all__ = ["Maxwell", "MaxwellOptions"]


class MaxwellOptions(Options):
    """Options of the ``maxwell`` check."""

    min_cos: float = Field(0.7, ge=0, le=1, description="Smallest acceptable cos(theta)")
    marginal_cos: float = Field(
        MARGINAL_COS,
        ge=0,
        le=1,
        description="A pass whose smallest cos(theta) is below this is marginal (0: no "
        "marginal band)",
    )


#: Added to the turn a hint names (degrees), so that the normal written with four decimals still
#: reaches the limit: a unit vector rounded to 1e-4 per component is off by < 0.01°.
TURN_SLACK_DEG = 0.05


def turned_normal(velocity: np.ndarray, normal: np.ndarray, min_cos: float) -> dict | None:
    """The least turn of a support's normal, towards its freed motion ``velocity``, that makes
    cos θ reach ``min_cos`` in its own case: ``{"by_deg", "normal"}`` (the turn, rounded up to
    0.01° after ``TURN_SLACK_DEG``, and the new unit normal), None when no turn is needed or
    the motion has no speed.

    The freed motion of a retracted support depends only on the *other* supports, so turning
    this normal by Δ in the plane of the normal and the motion makes θ' = θ − Δ exactly (the
    other cases, where this support stays, change with it)."""
    speed = float(np.linalg.norm(velocity))
    if not speed > 0:
        return None
    along = float(normal @ velocity)
    across = velocity - along * normal
    size = float(np.linalg.norm(across))
    theta = float(np.arctan2(size, abs(along)))
    target = float(np.arccos(np.clip(min_cos, 0.0, 1.0)))
    if theta <= target or not size > 0:
        return None
    by = min(np.ceil((np.degrees(theta - target) + TURN_SLACK_DEG) * 100) / 100, np.degrees(theta))
    delta = np.radians(by)
    sign = 1.0 if along >= 0 else -1.0
    turned = np.cos(delta) * normal + np.sin(delta) * sign * across / size
    turned = np.zeros(3) + np.pad(turned, (0, 3 - len(turned)))
    return {"by_deg": float(by), "normal": (turned / np.linalg.norm(turned)).tolist()}


def _turn_hint(case: CaseResult, min_cos: float, geometry: object = None) -> str:
    """ "turn y1's normal 12.35° towards its freed motion, to (0.2139, 0.9769, 0): cos θ ≥ 0.7
    in this case; ..." or, without a number, the advice to tilt the neighbours. A coupling's
    contact (``geometry``) has its normal from its seat: the hint says so."""
    turn = case.details.get("turn_normal")
    if not isinstance(turn, dict):
        return "tilt the neighbouring contacts so the freed motion meets this normal more squarely"
    vector = ", ".join(format_number(round(float(x), 4) + 0.0, 4) for x in turn["normal"][:3])
    coupling = getattr(geometry, "coupling", None)
    seat = "" if coupling is None else f" (by turning coupling {coupling}'s seat or flank)"
    return (
        f"turn {case.retracted}'s normal {format_angle(turn['by_deg'])} towards its freed motion, "
        f"to ({vector}){seat}: cos θ ≥ {min_cos:g} in this case (the cases where {case.retracted} "
        "stays change with it: run again); or tilt the neighbouring contacts so the freed motion "
        "meets this normal more squarely"
    )


class Maxwell(Check):
    """Rank of the constraint matrix and, per support, how squarely its free motion meets it."""

    id = "maxwell"
    summary = "layout determinacy and Maxwell's criterion: cos(theta) of each support's free motion"
    applies_to = "planar (3 supports) and spatial (6 supports) scenes"
    needs_mass = False
    options = MaxwellOptions
    severity = "warning"

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
            turn = turned_normal(point_velocity(free.twist, points[r]), normals[r], opts.min_cos)
            # The null vector is perturbed by about eps / (its singular-value gap).
            worst_error = max(worst_error, EPS / free.determinacy)
            outcome = "ok" if cos >= opts.min_cos else "poor"
            cases.append(
                CaseResult(
                    support.name,
                    outcome,
                    cos_maxwell=cos,
                    details={
                        "theta_deg": float(np.degrees(maxwell_angle(free, points[r], normals[r]))),
                        **({} if turn is None else {"turn_normal": turn}),
                    },
                )
            )
        details = {"rank": rank, "smallest_scaled_singular_value": sigma, "min_cos": opts.min_cos}
        if not deterministic:
            motions = len(points) - rank
            return CheckResult(
                self.id,
                Status.FAIL,
                f"not deterministic: constraint matrix rank {rank} of {len(points)}, so "
                f"{motions} motion(s) stay free with every support in place "
                "(e.g. all normals through one point)",
                error_estimate=None,
                cases=tuple(cases),
                details=details,
                findings=(
                    Finding(
                        f"the supports leave {motions} motion(s) free with every support in place "
                        f"(constraint matrix rank {rank} of {len(points)})",
                        code="not-deterministic",
                        field=("supports",),
                        hint="turn or move a support so the normals no longer meet in one "
                        "point (planar) or one line (spatial)",
                    ),
                ),
            )
        poor = [c for c in cases if c.outcome != "ok"]
        # The first of the worst: supports tied in cos θ (a symmetric coupling) within rounding
        # noise are one tie, so the name does not depend on the last digits of the input.
        cosines = [c.cos_maxwell if c.cos_maxwell is not None else -1.0 for c in cases]
        worst = cases[next(k for k, v in enumerate(cosines) if v <= min(cosines) + NOISE_RTOL)]
        near = sigma < NEARLY_SINGULAR
        findings = tuple(
            Finding(
                f"retracting {c.retracted} frees a motion at "
                f"{format_angle(c.details['theta_deg'])} from its normal "
                f"(cos θ = {c.cos_maxwell:.3f}, below {opts.min_cos:g})",
                code="maxwell",
                field=scene.support_field(i),
                hint=_turn_hint(c, opts.min_cos, scene.supports[i].geometry),
            )
            for i, c in enumerate(cases)
            if c in poor and c.cos_maxwell is not None
        )
        if poor:
            names = ", ".join(c.retracted for c in poor)
            status = Status.FAIL
            message = (
                f"cos θ below {opts.min_cos:g} at {names}; worst {worst.retracted} "
                f"cos θ = {worst.cos_maxwell:.3f}"
            )
        else:
            status = Status.PASS
            message = (
                f"deterministic; every cos θ ≥ {opts.min_cos:g} "
                f"(worst {worst.retracted}: {worst.cos_maxwell:.3f})"
            )
        if near:
            message += f"; nearly singular layout (scaled σ_min {sigma:.1e})"
        result = CheckResult(
            self.id,
            status,
            message,
            error_estimate=worst_error,
            cases=tuple(cases),
            details=details,
            findings=findings,
        )
        if worst.cos_maxwell is None:
            return result
        band = opts.marginal_cos
        return with_margin(
            result,
            "Maxwell cos θ",
            min(cosines),  # the margin is the least cos θ itself; the name the first tied
            band,
            "at least",
            f"retracting {worst.retracted} frees a motion with cos θ = {worst.cos_maxwell:.3f}, "
            f"below the {band:g} minimum margin (wear and seat misalignment tilt normals)",
            hint="tilt the neighbouring contacts so the freed motion meets this normal more "
            "squarely (the option `marginal_cos` sets the band)",
            field=scene.support_field(cases.index(worst)),
        )
