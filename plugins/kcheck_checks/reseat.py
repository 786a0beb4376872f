"""Reseat: watch the body come back to its seat in time (MuJoCo, the ``sim`` extra).

For every retracted support (at both ends of a friction range) the body is simulated through
a retraction and a return (:mod:`kcheck.analysis.reseat`): does it close onto the retracted
support, does it come back to its seat, how far off does it stop, how long does it take, does
it lose a contact or stick on the way. MuJoCo is imported only when the check runs.
"""

from __future__ import annotations

import importlib.util
import time
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from kcheck.analysis import analyse
from kcheck.analysis.cases import closing_force_reason
from kcheck.fmt import format_number
from kcheck.numerics.thresholds import (
    RESEAT_BACKOFF_SHARE,
    RESEAT_ESTIMATE_FACTOR,
    RESEAT_SEAT_RESOLUTION,
)
from kcheck.plugin import Check, Field, Inputs, Options, model_validator
from kcheck.result import CaseResult, CheckResult, Finding, MassProperties, Status
from kcheck.scene import Scene

if TYPE_CHECKING:  # the simulation is imported when the opt-in check runs (issue 24)
    from kcheck.analysis.reseat import ReseatRun, ReseatSettings

__all__ = ["Reseat", "ReseatOptions", "SIM_INSTALL", "settings_of", "friction_ends"]

#: How to get the simulator.
SIM_INSTALL = "pip install 'kcheck[sim]'"


class ReseatOptions(Options):
    """Options of the ``reseat`` check (lengths in µm, times in s)."""

    retraction_um: float = Field(
        100.0, gt=0, le=1e5, description="How far the retracted support backs off (µm)"
    )
    retraction_time_ms: float = Field(
        0.0,
        ge=0,
        le=6e4,
        description="Time the support takes to back off (ms, half-cosine); 0: it jumps back",
    )
    profile: Literal["step", "ramp"] = Field(
        "step",
        description="Closing force in phases 1-2: step (constant) or ramp (let go when the "
        "support backs off, back to full linearly over the first half of phase 1)",
    )
    duration_s: float = Field(
        0.5, gt=0, le=60, description="Simulated time of each phase (retract, return), s"
    )
    time_step_s: float = Field(1e-4, gt=0, le=1e-2, description="Integration time step (s)")
    tolerance_um: float = Field(
        1.0, gt=0, description="Seat tolerance: largest contact-point displacement (µm)"
    )
    contact_time_constant_s: float = Field(
        2e-3, gt=0, le=1.0, description="Contact stiffness as a time constant (MuJoCo solref, s)"
    )
    contact_damping_ratio: float = Field(
        1.0, gt=0, le=10, description="Contact damping ratio (MuJoCo solref)"
    )
    contact_impedance: float = Field(
        0.99, ge=0.9, lt=1.0, description="Constraint impedance (MuJoCo solimp, 1 = hard)"
    )

    @model_validator(mode="after")
    def _backs_off_within_a_phase(self) -> ReseatOptions:
        # A support still backing off when phase 1 ends would be read (and returned) part-way:
        # the body needs the rest of the phase to move.
        longest_ms = RESEAT_BACKOFF_SHARE * self.duration_s * 1e3
        if self.retraction_time_ms > longest_ms:
            raise ValueError(
                f"retraction_time_ms {format_number(self.retraction_time_ms, 4)} is longer than "
                f"{RESEAT_BACKOFF_SHARE:g} of a phase (duration_s "
                f"{format_number(self.duration_s, 4)} s): at most "
                f"{format_number(longest_ms, 4)} ms, or raise duration_s"
            )
        return self


def settings_of(options: ReseatOptions) -> ReseatSettings:
    """The simulation settings (SI) of the check's options."""
    from kcheck.analysis.reseat import ReseatSettings

    return ReseatSettings(
        retraction=options.retraction_um * 1e-6,
        retraction_time=options.retraction_time_ms * 1e-3,
        profile=options.profile,
        duration=options.duration_s,
        time_step=options.time_step_s,
        time_constant=options.contact_time_constant_s,
        damping_ratio=options.contact_damping_ratio,
        impedance=options.contact_impedance,
        tolerance=options.tolerance_um * 1e-6,
    )


def friction_ends(scene: Scene) -> list[tuple[str, np.ndarray]]:
    """The friction coefficients to simulate: the kinetic one, or both ends of ranges."""
    low, high = scene.friction_range("kinetic")
    if np.array_equal(low, high):
        return [("", high)]
    return [("μ low", low), ("μ high", high)]


def missing_simulator() -> str | None:
    """Why the check cannot run here (MuJoCo absent), or None."""
    if importlib.util.find_spec("mujoco") is None:
        return f"the reseat check needs the optional `sim` extra (MuJoCo): {SIM_INSTALL}"
    return None


def _um(x: float) -> str:
    return format_number(x * 1e6)


def _estimate(coarse: ReseatRun, fine: ReseatRun) -> float:
    """Error estimate (m) of the fine run's seat error: twice its difference from the coarse
    run's, at least the simulation's seat resolution."""
    return max(
        RESEAT_ESTIMATE_FACTOR * abs(fine.seat_error - coarse.seat_error), RESEAT_SEAT_RESOLUTION
    )


def _case(
    scene: Scene, run: ReseatRun, fine: ReseatRun, first: str, label: str, tol: float
) -> CaseResult:
    """One case's result: the fine run's numbers, the coarse run's difference as estimate,
    and the first motion ``first`` of the stiff first-motion run."""
    names = [s.name for s in scene.supports]
    reseats = fine.seat_error <= tol and fine.closing_gap <= tol
    details: dict[str, Any] = {
        "first_motion": first,
        "verdict": "reseats" if reseats else "stops off-seat",
        "seat_error_um": fine.seat_error * 1e6,
        "translation_um": fine.translation * 1e6,
        "rotation_urad": fine.rotation * 1e6,
        "closing_gap_um": fine.closing_gap * 1e6,
        "time_to_close_s": fine.closed_after,
        "time_to_reseat_s": fine.reseated_after,
        "largest_gap_um": {
            n: float(g) * 1e6 for n, g in zip(names, fine.largest_gaps, strict=True)
        },
        "contact_losses": {n: int(c) for n, c in zip(names, fine.losses, strict=True)},
        "stick_events": {n: int(c) for n, c in zip(names, fine.sticks, strict=True)},
        "error_estimate_um": _estimate(run, fine) * 1e6,
    }
    if label:
        details["friction"] = label
    retracted = names[fine.retracted] + (f" ({label})" if label else "")
    return CaseResult(retracted, "reseats" if reseats else "off_seat", details=details)


class Reseat(Check):
    """Time-domain retraction and return of every support, simulated in MuJoCo."""

    id = "reseat"
    pictures = "kcheck_checks.pictures.reseat:draw"
    summary = (
        "simulates each retraction and return in time (MuJoCo): seat error, time to reseat, "
        "gaps, contact losses and sticking"
    )
    applies_to = "planar and spatial scenes with a body and a closing force or gravity"
    needs_mass = True
    options = ReseatOptions
    #: Not run unless selected: it takes about a second of CPU per case (docs/checks.md).
    default_selected = False

    def missing_extra(self) -> str | None:
        """The extra to install when MuJoCo is absent."""
        return missing_simulator()

    def skip_reason(self, scene: Scene) -> str | None:
        """A body and a closing force; a load with a design direction when there is a load."""
        reason = closing_force_reason(scene)
        if reason is not None:
            return reason
        load = scene.load
        if load is not None and load.magnitude > 0 and load.direction is None:
            return (
                "the load has no design direction, so there is no one motion to simulate "
                "(give `load.direction` or `load.angle`)"
            )
        return None

    def run(self, inputs: Inputs) -> CheckResult:
        """Simulate every case at the time step and at half of it, and its first motion in a
        short run with stiff contacts (:func:`kcheck.analysis.reseat.first_motion_settings`)."""
        from kcheck.analysis.reseat import first_motion_settings, inertia_missing, simulate

        assert inputs.mass is not None and isinstance(inputs.options, ReseatOptions)
        mass = inputs.mass
        if inertia_missing(inputs.scene, mass):
            return CheckResult(
                self.id,
                Status.SKIPPED,
                "not checked, because the body's inertia is not finite (give `body` a mesh or "
                "explicit inertia)",
            )
        scene, settings = inputs.scene, settings_of(inputs.options)
        first_settings = first_motion_settings(settings)
        started = time.process_time()
        cases: list[CaseResult] = []
        runs: list[tuple[ReseatRun, ReseatRun]] = []
        links: list[str] = []
        for label, mu in friction_ends(scene):
            lost = predicted_losses(scene, mass, mu)
            for r in range(len(scene.supports)):
                coarse = simulate(scene, mass, r, mu, settings)
                fine = simulate(scene, mass, r, mu, settings, dt=settings.time_step / 2)
                first = simulate(scene, mass, r, mu, first_settings, returns=False).first
                runs.append((coarse, fine))
                case = _case(scene, coarse, fine, first, label, settings.tolerance)
                cases.append(case)
                link = _lift_link(scene, fine, case, lost.get(r, ()), settings.tolerance)
                if link is not None:
                    links.append(link)
        found = [_finding(scene, c, settings.tolerance) for c in cases]
        failing = [f for f in found if f is not None]
        estimate = 1e6 * max(_estimate(c, f) for c, f in runs)
        worst = max(f.seat_error for _, f in runs)
        parts = [
            f"{sum(c.outcome == 'reseats' for c in cases)} of {len(cases)} cases reseat "
            f"within {_um(settings.tolerance)} µm; largest seat error {_um(worst)} µm"
        ]
        if failing:
            more = f" (and {len(failing) - 1} more)" if len(failing) > 1 else ""
            parts.append(failing[0].message + more)
        parts.extend(links)
        return CheckResult(
            self.id,
            Status.FAIL if failing else Status.PASS,
            "; ".join(parts),
            error_estimate=estimate,
            cases=tuple(cases),
            details={
                "seat_error_um": worst * 1e6,
                "error_estimate_unit": "µm of seat error",
                "simulated_s": sum(f.steps * settings.time_step / 2 for _, f in runs),
                "cpu_s": time.process_time() - started,
                "time_step_s": settings.time_step / 2,
            },
            findings=tuple(failing),
        )


def predicted_losses(
    scene: Scene, mass: MassProperties, mu: np.ndarray
) -> dict[int, tuple[int, ...]]:
    """Per retracted support, the remaining supports analytical-2d/3d says lose contact in
    the first motion (those with a negative normal force) at the coefficients ``mu`` (k,)."""
    names = [s.name for s in scene.supports]
    out: dict[int, tuple[int, ...]] = {}
    for r, result in enumerate(analyse(scene, mass, friction=mu).results):
        lifts = result.details.get("lifts_off")
        if isinstance(lifts, list) and lifts:  # lifted in the first motion from rest
            out[r] = tuple(names.index(n) for n in lifts)
        elif result.outcome in ("loses_contact", "opens_loses_contact") and result.normal_forces:
            out[r] = tuple(names.index(n) for n, f in result.normal_forces.items() if f < 0)
    return out


def _lift_link(
    scene: Scene, run: ReseatRun, case: CaseResult, lost: tuple[int, ...], tol: float
) -> str | None:
    """The sentence linking analytical-2d/3d's lost contact to the simulated reseat, when a
    contact the analysis says is lost lifts in the simulation and the body still reseats."""
    lifted = [i for i in lost if run.largest_gaps[i] > tol]
    if case.outcome != "reseats" or not lifted:
        return None
    analysis = "analytical-2d" if scene.kind == "planar" else "analytical-3d"
    lifts = " and ".join(
        f"{scene.supports[i].name} lifts {_um(float(run.largest_gaps[i]))} µm" for i in lifted
    )
    return (
        f"retract {case.retracted}: {lifts} as {analysis} predicts, then the body reseats "
        f"within {format_number(case.details['seat_error_um'])} µm"
    )


def _finding(scene: Scene, case: CaseResult, tol: float) -> Finding | None:
    """Why a case fails: it did not close onto the backed-off support, or did not reseat."""
    if case.outcome == "reseats":
        return None
    d = case.details
    name = case.retracted
    index = [s.name for s in scene.supports].index(name.split(" (")[0])
    if d["closing_gap_um"] * 1e-6 > tol:
        message = (
            f"retract {name} → the body stops {format_number(d['closing_gap_um'])} µm short of "
            f"the backed-off support ({d['first_motion'].replace('_', ' ')})"
        )
        hint = "lower the friction at the remaining supports, or turn the load towards the seat"
    else:
        message = (
            f"retract {name} and return → stops off-seat by {format_number(d['seat_error_um'])} µm "
            f"({format_number(d['rotation_urad'])} µrad)"
        )
        hint = "lower the friction, or raise the closing force"
    return Finding(message, code="off-seat", field=scene.support_field(index), hint=hint)
