"""Tolerances: does the coupling still close as it may be made?

The scene's ``tolerances:`` give a box of made couplings — support positions, support normals,
the load direction — and its ``friction`` ranges the coefficients. This check samples the box
(seeded Monte Carlo, :mod:`kcheck.mechanics.tolerance`: positions, normals and the kinetic
coefficients drawn uniformly — the coefficients along their ranges together, as the analytical
checks take them, unless ``independent_friction``) and treats the load direction exactly (a sample
passes for every load direction within ``±δ`` iff its design margin is at least ``δ``). It
reports the worst design margin over the box — the worst sample, and the nominal coupling over
its friction range exactly (:mod:`kcheck.analysis.friction_ranges`) — and the probability that the
coupling passes, with Clopper–Pearson bounds.

A separate check (not part of the analytical ones) because it answers another question — how
likely, not whether — at a cost the analytical checks should not pay on every scene, and only
when the scene asks for it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from kcheck.analysis import analyse
from kcheck.analysis.cases import closing_force_reason, problem_for
from kcheck.analysis.friction_ranges import RangeInfo
from kcheck.fmt import format_angle, format_length, format_number
from kcheck.numerics.margins import MARGINAL_PASS_PROBABILITY
from kcheck.plugin import Check, Field, Inputs, Options
from kcheck.result import CheckResult, Finding, Status
from kcheck.scene import Scene
from kcheck_checks.marginal import with_margin
from kcheck_checks.wording import verdict

if TYPE_CHECKING:  # the sampling is imported when the check runs, not when it is found
    from kcheck.mechanics.tolerance import Perturbed

__all__ = ["Tolerances", "TolerancesOptions"]


class TolerancesOptions(Options):
    """Options of the ``tolerances`` check."""

    samples: int = Field(10_000, ge=100, le=1_000_000, description="Monte Carlo samples")
    seed: int = Field(0, ge=0, description="Seed of the random numbers (results repeat)")
    design: Literal["monte-carlo", "latin-hypercube", "sobol"] = Field(
        "monte-carlo",
        description="How the box is sampled: independent draws, or a Latin hypercube or "
        "Sobol design (kcheck.numerics.design, as `kcheck study` samples)",
    )
    confidence: float = Field(
        0.95, gt=0.5, lt=1.0, description="Confidence of the pass probability's bounds"
    )
    min_margin_deg: float = Field(
        0.0, ge=0, description="Least design margin every made coupling must keep"
    )
    independent_friction: bool = Field(
        False,
        description="Draw each support's coefficient on its own (default: all move together "
        "along their ranges, as the analytical checks take them)",
    )
    min_pass_probability: float | None = Field(
        None,
        gt=0.0,
        le=1.0,
        description="Pass when the lower confidence bound reaches this; default: every "
        "sample (and the nominal coupling over its friction range) must pass",
    )
    marginal_pass_probability: float = Field(
        MARGINAL_PASS_PROBABILITY,
        ge=0.0,
        le=1.0,
        description="A pass whose pass probability's lower confidence bound is below this is "
        "marginal (0: no marginal band)",
    )


def _nominal_worst(scene: Scene, inputs: Inputs, design: np.ndarray | None) -> float:
    """The nominal coupling's least design margin (rad) over its kinetic friction range,
    exactly (one coefficient: its design margin)."""
    from kcheck.mechanics.tolerance import Perturbed, sample_margins

    assert inputs.mass is not None
    analysis = analyse(scene, inputs.mass)
    info = analysis.friction_range
    if isinstance(info, RangeInfo):
        worst = [w[1] for w in info.worst if w is not None]
        if worst:
            return float(min(worst))
    problem = analysis.problem
    k, dim = problem.points.shape
    nominal = Perturbed(problem.points[None], problem.normals[None], problem.friction[None])
    return float(sample_margins(problem, nominal, design)[0])


class Tolerances(Check):
    """Monte Carlo over the scene's tolerance box: worst design margin, pass probability."""

    id = "tolerances"
    summary = (
        "the coupling as it may be made (support positions, normals, friction ranges; the load "
        "direction's tolerance exactly): worst design margin and the probability that it passes"
    )
    applies_to = "scenes with `tolerances:`, a body and a closing force with a design direction"
    needs_mass = True
    options = TolerancesOptions

    def skip_reason(self, scene: Scene) -> str | None:
        """Scenes with tolerances, mass properties and something to close them."""
        if scene.tolerances is None:
            return "the scene gives no `tolerances:`"
        reason = closing_force_reason(scene)
        if reason is not None:
            return reason
        load = scene.load
        if load is not None and load.magnitude > 0 and load.direction is None:
            return "needs the load's design direction (`load.direction` or `load.angle`)"
        return None

    def run(self, inputs: Inputs) -> CheckResult:
        """Sample the box, count the passes, find the worst."""
        from kcheck.mechanics.tolerance import Box, chunk_layouts, chunk_margins, margin_chunks
        from kcheck.numerics.stats import clopper_pearson

        scene, opts = inputs.scene, inputs.options
        assert inputs.mass is not None and isinstance(opts, TolerancesOptions)
        assert scene.tolerances is not None
        tol = scene.tolerances
        problem = problem_for(scene, inputs.mass)
        load = scene.load
        design = None
        if load is not None and load.magnitude > 0 and load.direction is not None:
            design = load.direction[: scene.dim]
        low, high = scene.friction_range("kinetic")
        unit = None
        if opts.design != "monte-carlo":
            from kcheck.mechanics.tolerance import unit_dimensions
            from kcheck.numerics.design import unit_points

            k, dim = problem.points.shape
            d = unit_dimensions(k, dim, opts.independent_friction)
            unit = unit_points(opts.design, opts.samples, d, opts.seed)
        box = Box(
            tol.position, float(np.radians(tol.normal_deg)), low, high, opts.independent_friction
        )
        # Chunks of fixed size, each drawn from its own stream: the same margins on whichever
        # executor the sample map runs them (kcheck check --sample-jobs, --dask-local, ...).
        chunks = margin_chunks(problem, box, design, opts.samples, opts.seed, unit)
        margins = np.concatenate(inputs.sample_map(chunk_margins, chunks))
        spread = float(np.radians(tol.load_direction_deg)) if design is not None else 0.0
        need = float(np.radians(opts.min_margin_deg))
        passes = (margins > 0) & (margins - spread >= need)
        count = int(np.count_nonzero(passes))
        low_p, high_p = clopper_pearson(count, opts.samples, opts.confidence)
        nominal = _nominal_worst(scene, inputs, design)
        worst_index = int(np.argmin(margins))
        details: dict[str, Any] = {
            "samples": opts.samples,
            "seed": opts.seed,
            "tolerances": {
                "position": tol.position,
                "normal_deg": tol.normal_deg,
                "load_direction_deg": tol.load_direction_deg,
            },
            "passed": count,
            "pass_probability": count / opts.samples,
            "pass_probability_bounds": [low_p, high_p],
            "confidence": opts.confidence,
        }
        if unit is not None:  # named only when not the default, so recorded results stay
            details["design"] = opts.design
        size = chunks[0].count  # every chunk but the last has this size
        worst_chunk = chunks[worst_index // size]
        sample = _describe_sample(
            scene, problem.frame.length, chunk_layouts(worst_chunk), problem, worst_index % size
        )
        sample["index"] = worst_index
        findings: list[Finding] = []
        if design is not None:
            worst = min(float(margins[worst_index]), nominal) - spread
            details["worst_margin_deg"] = float(np.degrees(worst))
            details["worst_sample"] = {
                **sample,
                "margin_deg": float(np.degrees(margins[worst_index] - spread)),
            }
            details["nominal_worst_margin_deg"] = float(np.degrees(nominal - spread))
            everything = worst > 0 and worst >= need
        else:
            details["worst_sample"] = sample
            everything = count == opts.samples and nominal > 0
        ok = everything if opts.min_pass_probability is None else low_p >= opts.min_pass_probability
        percent = f"{100 * count / opts.samples:.2f}%"
        bounds = f"{100 * opts.confidence:g}% confidence: {100 * low_p:.2f}–{100 * high_p:.2f}%"
        parts = [f"passes in {percent} of {opts.samples} made couplings ({bounds})"]
        if design is not None:
            drawn = format_angle(float(np.degrees(margins[worst_index] - spread)))
            at_worst = format_angle(float(np.degrees(nominal - spread)))
            parts.append(
                f"worst design margin {drawn} over the samples ({at_worst} for the nominal "
                "coupling at its worst friction)"
            )
        if not ok:
            findings.append(_finding(scene, details, opts, design is not None))
        result = CheckResult(
            self.id,
            Status.PASS if ok else Status.FAIL,
            verdict(parts, findings),
            # The pass probability's statistical error (a fraction): half its confidence
            # interval. Sampling dominates: each sample's margin is exact to ~1e-12 rad.
            error_estimate=(high_p - low_p) / 2.0,
            details=details,
            findings=tuple(findings),
        )
        band = opts.marginal_pass_probability
        return with_margin(
            result,
            "tolerance pass probability (lower confidence bound)",
            low_p,
            band,
            "at least",
            f"the pass probability is at least {100 * low_p:.2f}% "
            f"({100 * opts.confidence:g}% confidence), below the {100 * band:g}% minimum margin",
            hint="tighten the tolerances, or take more samples if every sample passed "
            "(the option `marginal_pass_probability` sets the band)",
            field=("tolerances",),
        )


def _describe_sample(
    scene: Scene, length: float, layouts: Perturbed, problem: Any, i: int
) -> dict[str, Any]:
    """How sample ``i`` differs from the scene: each support's displacement (m), tilt (deg)
    and coefficient."""
    moved = np.linalg.norm(layouts.points[i] - problem.points, axis=1) * length
    cos = np.clip(np.sum(layouts.normals[i] * problem.normals, axis=1), -1.0, 1.0)
    tilt = np.degrees(np.arccos(cos))
    return {
        "index": i,
        "supports": {
            s.name: {
                "displacement": float(moved[j]),
                "tilt_deg": float(tilt[j]),
                "friction": float(layouts.friction[i][j]),
            }
            for j, s in enumerate(scene.supports)
        },
    }


def _finding(
    scene: Scene, details: dict[str, Any], opts: TolerancesOptions, angular: bool
) -> Finding:
    """Why the made coupling may fail: how often, and the worst sample's largest deviations."""
    sample = details["worst_sample"]["supports"]
    moved = max(sample.items(), key=lambda kv: kv[1]["displacement"])
    tilted = max(sample.items(), key=lambda kv: kv[1]["tilt_deg"])
    failed = details["samples"] - details["passed"]
    what = "" if angular else ", it does not close"
    message = (
        f"{failed} of {details['samples']} made couplings fail (the worst{what}: "
        f"{moved[0]} moved {format_length(moved[1]['displacement'], scene.scale, scene.units)}, "
        f"{tilted[0]} tilted {format_angle(tilted[1]['tilt_deg'])}, μ up to "
        f"{format_number(max(v['friction'] for v in sample.values()), 3)})"
    )
    if failed == 0 and angular:
        message = (
            "every made coupling passes as drawn, but the nominal coupling at its worst "
            f"friction keeps only {format_angle(details['nominal_worst_margin_deg'])}"
        )
    if opts.min_pass_probability is not None:
        message += (
            f"; the pass probability is at least {100 * details['pass_probability_bounds'][0]:.2f}%"
            f", below the required {100 * opts.min_pass_probability:g}%"
        )
    hint = "tighten the tolerances, or turn the load towards the most robust direction"
    if scene.load is None or not scene.load.magnitude > 0:
        hint = "tighten the tolerances, or lower the friction"  # nobody turns gravity
    return Finding(message, code="tolerance", field=("tolerances",), hint=hint)
