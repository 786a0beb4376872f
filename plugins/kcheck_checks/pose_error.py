"""Pose error: where the seated body ends up, as the coupling may be made.

Seeded Monte Carlo over stated manufacturing errors — ball positions and radii, seat (groove)
positions and angles, and correlated groups (one machine setup moves a declared group of seats
together) — mapped to the body's pose error at a point of interest by the small-displacement
kinematics of :mod:`kcheck.mechanics.pose_error` (one matrix product per chunk of samples;
the chunks run where the inputs' sample map sends them, with the same answer anywhere). It
reports the mean, spread and a chosen quantile of the translation (µm) and rotation (µrad)
there, with Monte Carlo confidence bounds, and judges them against an allowed pose error when
one is given — without one it reports the numbers and says it did not judge them.

Opt-in (``default_selected = False``): it runs only on scenes whose ``checks:`` give
``pose-error:`` options, when the configuration's ``[tool.kcheck.checks.pose-error]`` gives
options, or when ``--select`` names it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from kcheck.fmt import format_number
from kcheck.plugin import Check, Field, Inputs, Options
from kcheck.result import CheckResult, Finding, Status
from kcheck.scene import Scene
from kcheck_checks.wording import verdict

if TYPE_CHECKING:  # read by the options' pydantic model when options are given
    from kcheck.scene.models import MaterialName

__all__ = ["PoseError", "PoseErrorOptions", "PoseGroup"]

UM = 1e-6  # m per µm, rad per µrad


class PoseGroup(Options):
    """Seats made in one machine setup: one shared error moves them together."""

    name: str = Field(description="The group's name (for the report)")
    couplings: list[str] = Field(
        min_length=1, description="Coupling entries (or explicit supports) whose seats it moves"
    )
    position_um: float = Field(0.0, ge=0, description="Shared seat translation, per axis (µm)")
    angle_urad: float = Field(
        0.0, ge=0, description="Shared seat rotation about the group's centroid, per axis (µrad)"
    )


class PoseErrorOptions(Options):
    """Options of the ``pose-error`` check (the scene's ``checks: {pose-error: {...}}``)."""

    point: list[float] | None = Field(
        None,
        min_length=3,
        max_length=3,
        description="Point of interest on the body, scene coordinates and units",
    )
    distribution: Literal["normal", "uniform"] = Field(
        "normal",
        description="normal: each tolerance is a standard deviation; uniform: a half-width",
    )
    ball_position_um: float = Field(0.0, ge=0, description="Ball centre, per axis (µm)")
    ball_radius_um: float = Field(0.0, ge=0, description="Ball radius (µm)")
    seat_position_um: float = Field(0.0, ge=0, description="Seat (groove) position, per axis (µm)")
    seat_angle_urad: float = Field(
        0.0, ge=0, description="Seat rotation about its root (vee) or apex, per axis (µrad)"
    )
    # pydantic copies mutable defaults per instance (and `kcheck plugins` shows this one)
    groups: list[PoseGroup] = Field([], description="Correlated seat groups")
    load_percent: float = Field(
        0.0,
        ge=0,
        lt=100,
        description="The load's magnitude, relative (%); the contacts' "
        "Hertz compliance turns it into a pose change",
    )
    mass_percent: float = Field(
        0.0, ge=0, lt=100, description="The body's mass (its weight), relative (%)"
    )
    ball_material: MaterialName | None = Field(
        None, description="Every ball's material the scene gives none for (load and mass)"
    )
    seat_material: MaterialName | None = Field(
        None, description="Every seat's material the scene gives none for (load and mass)"
    )
    samples: int = Field(100_000, ge=100, le=10_000_000, description="Monte Carlo samples")
    sampler: Literal["random", "sobol"] = Field(
        "random",
        description="random: independent draws; sobol: scrambled Sobol points (samples rounded "
        "up to a power of two; the bounds are those of independent draws)",
    )
    seed: int = Field(0, ge=0, description="Seed of the random numbers (results repeat)")
    quantile: float = Field(0.95, gt=0.0, lt=1.0, description="Quantile reported and judged")
    confidence: float = Field(0.95, gt=0.5, lt=1.0, description="Confidence of the bounds")
    allowed_translation_um: float | None = Field(
        None, gt=0, description="Largest allowed translation at the point (at the quantile)"
    )
    allowed_rotation_urad: float | None = Field(
        None, gt=0, description="Largest allowed rotation (at the quantile)"
    )


def _parts(scene: Scene) -> dict[str, Any]:
    """Per contact: its ball and seat (indices into the coupling entries), their sides' signs
    (+1 base, -1 body), the ball centres; explicit supports are a seat on the base, no ball."""
    names: list[str] = []
    ball, seat, ball_sign, seat_sign = [], [], [], []
    centres = []
    for s in scene.supports:
        g = s.contact_geometry
        entry = s.name if g is None else g.coupling
        if entry not in names:
            names.append(entry)
        j = names.index(entry)
        seat.append(j)
        if g is None:
            ball.append(-1)
            ball_sign.append(0.0)
            seat_sign.append(1.0)
            centres.append(np.asarray(s.position, float))
        else:
            ball.append(j)
            ball_sign.append(1.0 if g.ball_on == "base" else -1.0)
            seat_sign.append(1.0 if g.seat_on == "base" else -1.0)
            centres.append(np.asarray(g.ball_center, float))
    return {
        "names": names,
        "ball": np.array(ball),
        "seat": np.array(seat),
        "ball_sign": np.array(ball_sign),
        "seat_sign": np.array(seat_sign),
        "centres": np.array(centres),
    }


def sensitivities(scene: Scene, opts: PoseErrorOptions) -> list[tuple[str, np.ndarray, float]]:
    """Every error source as (name, sensitivity (k, m) of the contact separations, its
    tolerance in SI): ``delta = S x`` with ``x`` drawn at that tolerance."""
    from kcheck.mechanics.pose_error import part_rows, radius_rows, seat_pivots

    p = np.array([s.position for s in scene.supports], float)
    n = np.array([s.normal for s in scene.supports], float)
    parts = _parts(scene)
    count = len(parts["names"])
    sources: list[tuple[str, np.ndarray, float]] = []
    translation = np.r_[3:6]
    rotation = np.r_[0:3]

    def columns(matrix: np.ndarray, which: np.ndarray) -> np.ndarray:
        keep = (np.arange(matrix.shape[1]) % 6)[None, :] == which[:, None]
        return matrix[:, keep.any(axis=0)]

    if opts.ball_position_um > 0:
        rows = part_rows(p, n, parts["ball"], count, parts["ball_sign"], parts["centres"])
        sources.append(("ball position", columns(rows, translation), opts.ball_position_um * UM))
    if opts.ball_radius_um > 0:
        sources.append(("ball radius", radius_rows(parts["ball"], count), opts.ball_radius_um * UM))
    if opts.seat_position_um > 0 or opts.seat_angle_urad > 0:
        pivots = seat_pivots(p, n, parts["seat"])
        rows = part_rows(p, n, parts["seat"], count, parts["seat_sign"], pivots)
        if opts.seat_position_um > 0:
            sources.append(
                ("seat position", columns(rows, translation), opts.seat_position_um * UM)
            )
        if opts.seat_angle_urad > 0:
            sources.append(("seat angle", columns(rows, rotation), opts.seat_angle_urad * UM))
    for group in opts.groups:
        member = np.isin(np.array(parts["names"])[parts["seat"]], group.couplings)
        part = np.where(member, 0, -1)
        centre = np.broadcast_to(p[member].mean(axis=0), p.shape)
        rows = part_rows(p, n, part, 1, parts["seat_sign"], centre)
        if group.position_um > 0:
            sources.append((f"group {group.name} position", rows[:, 3:], group.position_um * UM))
        if group.angle_urad > 0:
            sources.append((f"group {group.name} angle", rows[:, :3], group.angle_urad * UM))
    return sources


def load_sensitivities(
    scene: Scene, mass: Any, opts: PoseErrorOptions
) -> tuple[list[tuple[str, np.ndarray, float]], str | None]:
    """The load's and the mass's sources: a relative change ``e`` of the load (of the weight)
    changes the seated contact forces by ``e dN`` (statics), and each contact's Hertz approach
    by ``e dN_i / k_i`` (its tangent stiffness at the seated force): the separations by
    ``-e dN_i / k_i``. Returns the sources and why they cannot be given (None: they can)."""
    if opts.load_percent <= 0 and opts.mass_percent <= 0:
        return [], None
    from kcheck.mechanics.hertz import hertz
    from kcheck.mechanics.seat import contact_forces, external_wrench, seat_layout, seated_loads
    from kcheck.numerics.thresholds import ZERO_GUARD
    from kcheck_checks.hertz_materials import Contacts, HertzOptions, contacts_of

    how = "(give `load_percent`/`mass_percent` only with them)"
    if any(s.contact_geometry is None for s in scene.supports):
        return [], f"load and mass need the contact geometry of every support {how}"
    if any(g.line_contact for s in scene.supports if (g := s.contact_geometry) is not None):
        return [], f"load and mass need point contacts (no ball-cone) {how}"
    loads, torque, _ = seated_loads(scene, mass)
    p = np.array([s.position for s in scene.supports], float)
    n = np.array([s.normal for s in scene.supports], float)
    scale = max([float(np.linalg.norm(x.force)) for x in loads] + [ZERO_GUARD])
    seat = seat_layout(p, n, 3, scale)
    seated = contact_forces(seat, external_wrench(seat, loads, torque)).value
    if seated is None or not np.all(seated > 0):
        return [], f"the body is not seated on every contact under its loads {how}"
    named = {"ball_material": opts.ball_material, "seat_material": opts.seat_material}
    materials = HertzOptions.model_validate({k: v for k, v in named.items() if v is not None})
    contacts = contacts_of(scene, materials)
    if not isinstance(contacts, Contacts):
        return [], (
            "the contacts' materials are not known (give `ball_material` and `seat_material` "
            "under `checks: {pose-error: ...}`, or on the couplings)"
        )
    k = hertz(seated, contacts.sum_a, contacts.sum_b, contacts.modulus).stiffness
    sources: list[tuple[str, np.ndarray, float]] = []
    for name, percent, picked, moment in (
        ("load", opts.load_percent, [x for x in loads if x.name == "load"], torque),
        ("mass", opts.mass_percent, [x for x in loads if x.name == "weight"], np.zeros(3)),
    ):
        if percent <= 0:
            continue
        if not picked:
            what = "load with a design direction" if name == "load" else "weight (body, gravity)"
            return [], f"`{name}_percent` is given but the scene has no {what}"
        change = contact_forces(seat, external_wrench(seat, picked, moment)).value
        assert change is not None  # the same matrix as the seated solve
        sources.append((name, (-change / k)[:, None], percent / 100.0))
    return sources, None


class PoseError(Check):
    """Monte Carlo of the seated pose error at a point from manufacturing tolerances."""

    id = "pose-error"
    summary = (
        "the seated body's pose error at a point of interest from manufacturing tolerances "
        "(balls, seats, correlated groups): mean, spread and a quantile with Monte Carlo bounds"
    )
    applies_to = (
        "spatial scenes of six contacts; opt-in: where the scene's `checks:` or the "
        "configuration give `pose-error` options, or `--select` names it"
    )
    options = PoseErrorOptions
    default_selected = False  # opt-in: runs where a scene, the configuration or --select asks

    def needs_mass_for(self, scene: Scene) -> bool:
        """The weight and the centre of mass, when there is a body (for load and mass)."""
        return scene.body is not None

    def skip_reason(self, scene: Scene) -> str | None:
        """Spatial, six contacts."""
        if scene.dim != 3:
            return "pose error is modelled for spatial couplings only"
        if len(scene.supports) != 6:
            return (
                f"the seated pose needs exactly six contacts (a determinate coupling); the "
                f"scene has {len(scene.supports)}"
            )
        return None

    def run(self, inputs: Inputs) -> CheckResult:
        """Draw the errors, map them to the pose at the point, summarise with bounds."""
        from kcheck.mechanics.pose_error import (
            mean_bounds,
            pose_chunk,
            pose_chunks,
            pose_map,
            quantile_bounds,
        )

        scene, opts = inputs.scene, inputs.options
        assert isinstance(opts, PoseErrorOptions)
        if opts.point is None:
            return CheckResult(
                self.id,
                Status.SKIPPED,
                "not checked, because no point of interest is given (give `checks: "
                "{pose-error: {point: [x, y, z]}}` in scene units)",
            )
        known = {s.name for s in scene.supports} | {
            g.coupling for s in scene.supports if (g := s.contact_geometry) is not None
        }
        for group in opts.groups:
            unknown = [c for c in group.couplings if c not in known]
            if unknown:
                return CheckResult(
                    self.id,
                    Status.SKIPPED,
                    f"not checked, because group {group.name} names unknown coupling(s) "
                    f"{', '.join(unknown)} (known: {', '.join(sorted(known))})",
                )
        point = np.asarray(opts.point, float) * scene.scale
        p = np.array([s.position for s in scene.supports], float)
        n = np.array([s.normal for s in scene.supports], float)
        pose = pose_map(p, n, point)
        if pose is None:
            return CheckResult(
                self.id,
                Status.FAIL,
                "the six contacts do not fix the body (their contact matrix is singular): "
                "no seated pose to perturb",
                findings=(
                    Finding(
                        "the contacts do not fix the body",
                        code="not-determinate",
                        field=("supports",),
                        hint="check the supports' normals (the `maxwell` check says which motion "
                        "is free)",
                    ),
                ),
            )
        sources = sensitivities(scene, opts)
        extra, why = load_sensitivities(scene, inputs.mass, opts)
        if why is not None:
            return CheckResult(self.id, Status.SKIPPED, f"not checked, because {why}")
        sources += extra
        if not sources:
            return CheckResult(
                self.id,
                Status.SKIPPED,
                "not checked, because no tolerance is given (give e.g. `ball_radius_um`, "
                "`seat_position_um` or `groups` in `checks: {pose-error: ...}`)",
                details={"condition": pose.condition},
            )
        scale = np.concatenate([np.full(m.shape[1], tol) for _, m, tol in sources])
        # Chunks of fixed size, each drawn from its own stream (Sobol: its own stretch of one
        # sequence): the same numbers on whichever executor the sample map runs them.
        chunks, samples = pose_chunks(
            pose,
            np.hstack([m for _, m, _ in sources]),
            scale,
            opts.distribution,
            opts.sampler,
            opts.seed,
            opts.samples,
        )
        mapped = inputs.sample_map(pose_chunk, chunks)
        t_norm = np.concatenate([m[0] for m in mapped])
        r_norm = np.concatenate([m[1] for m in mapped])
        t_mean = np.sum([m[2] for m in mapped], axis=0) / samples
        r_mean = np.sum([m[3] for m in mapped], axis=0) / samples
        from scipy.stats import norm

        z = float(norm.ppf(0.5 + opts.confidence / 2))
        summary: dict[str, Any] = {}
        for key, values, unit in (
            ("translation_um", t_norm, UM),
            ("rotation_urad", r_norm, UM),
        ):
            mean, std, lo, hi = mean_bounds(values, z)
            q, qlo, qhi = quantile_bounds(values, opts.quantile, opts.confidence)
            summary[key] = {
                "mean": mean / unit,
                "mean_bounds": [lo / unit, hi / unit],
                "std": std / unit,
                "quantile": q / unit,
                "quantile_bounds": [qlo / unit, qhi / unit],
            }
        # Each source's share: the same map on its own (exact for independent sources).
        details: dict[str, Any] = {
            "point": [float(v) for v in opts.point],
            "samples": samples,
            "sampler": opts.sampler,
            "seed": opts.seed,
            "distribution": opts.distribution,
            "quantile": opts.quantile,
            "confidence": opts.confidence,
            "condition": pose.condition,
            "sources": [name for name, *_ in sources],
            **summary,
            "mean_translation_um": [float(v) for v in t_mean / UM],
            "mean_rotation_urad": [float(v) for v in r_mean / UM],
        }
        t, r = summary["translation_um"], summary["rotation_urad"]
        qname = f"{format_number(100 * opts.quantile)}%"

        def num(x: float) -> str:
            return format_number(x, 3)

        t_bounds = f"{num(t['quantile_bounds'][0])}–{num(t['quantile_bounds'][1])}"
        r_bounds = f"{num(r['quantile_bounds'][0])}–{num(r['quantile_bounds'][1])}"
        parts = [
            f"at {_point_text(opts.point, scene.units)}: translation {qname} quantile "
            f"{num(t['quantile'])} µm ({t_bounds}), mean {num(t['mean'])} ± {num(t['std'])} µm; "
            f"rotation {qname} quantile {num(r['quantile'])} µrad ({r_bounds}), mean "
            f"{num(r['mean'])} ± {num(r['std'])} µrad ({samples} samples, "
            f"{format_number(100 * opts.confidence)}% bounds)"
        ]
        # The numbers' error is the Monte Carlo's: the quantile bounds' half-width (µm).
        error = 0.5 * (t["quantile_bounds"][1] - t["quantile_bounds"][0])
        allowed_t, allowed_r = opts.allowed_translation_um, opts.allowed_rotation_urad
        if allowed_t is None and allowed_r is None:
            parts.append(
                "not judged, because no allowed pose error is given (`allowed_translation_um`, "
                "`allowed_rotation_urad`)"
            )
            return CheckResult(
                self.id, Status.SKIPPED, "; ".join(parts), error_estimate=error, details=details
            )
        findings: list[Finding] = []
        # Judged on the upper confidence bound of the quantile: a pass is a pass with confidence.
        for what, value, allowed, label in (
            ("translation", t, allowed_t, "µm"),
            ("rotation", r, allowed_r, "µrad"),
        ):
            if allowed is not None and value["quantile_bounds"][1] > allowed:
                findings.append(
                    Finding(
                        f"the {what}'s {qname} quantile may reach "
                        f"{format_number(value['quantile_bounds'][1], 3)} {label} (upper bound), "
                        f"above the allowed {format_number(allowed, 3)} {label}",
                        code="pose-error",
                        field=("checks", self.id),
                        hint="tighten the largest tolerance sources, or move the point of "
                        "interest nearer the coupling's centre",
                    )
                )
        details["allowed_translation_um"] = allowed_t
        details["allowed_rotation_urad"] = allowed_r
        return CheckResult(
            self.id,
            Status.FAIL if findings else Status.PASS,
            verdict(parts, findings),
            error_estimate=error,
            details=details,
            findings=tuple(findings),
        )


def _point_text(point: list[float], units: str) -> str:
    return "(" + ", ".join(format_number(v) for v in point) + f") {units}"
