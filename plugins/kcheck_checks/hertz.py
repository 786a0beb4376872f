"""Hertz: contact stress and stiffness of each ball contact, the coupling's stiffness at the
seat and the body's error motion under a disturbing load (docs/checks.md, `hertz`).

Needs the contact geometry of every support (ball radius, the mating surface's radii), which
the coupling shorthands (`couplings:`) give and an explicit support gives in its `contact`
field; without it the check is skipped with that reason. Materials come from the scene (each
coupling's or contact's ball and seat material, the body's material for seats cut into it),
then from the check's options (hertz_materials); a contact whose material is unknown is not
checked, and says how to give it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.fmt import format_number, format_percent, format_vector
from kcheck.numerics.thresholds import CURVATURE_RTOL, LIFTED_RTOL, ZERO_GUARD
from kcheck.plugin import Check, Inputs
from kcheck.records import dataclass
from kcheck.result import CheckResult, Finding, Status
from kcheck.scene import Preload, Scene, Support
from kcheck_checks.hertz_materials import (
    Contacts,
    HertzOptions,
    Unknown,
    contacts_of,
    unknown_hint,
)
from kcheck_checks.marginal import with_margin

if TYPE_CHECKING:  # the computation is imported when the check runs, not when it is found
    from kcheck.mechanics.hertz import HertzContact
    from kcheck.mechanics.seat import Seat

__all__ = ["Hertz", "hertz_result"]


def _support_field(scene: Scene, index: int) -> tuple[str | int, ...]:
    """The scene field of a support: its coupling entry, or its item under `supports`."""
    return scene.support_field(index)


# --- the check ------------------------------------------------------------------------------


def _pressure(p: float) -> str:
    """A pressure in Pa for people: GPa above 1 GPa, else MPa."""
    return f"{p / 1e9:.3g} GPa" if p >= 1e9 else f"{p / 1e6:.3g} MPa"


def _stiffness_text(k: float) -> str:
    return format_number(k / 1e6, 3)


class Hertz(Check):
    """Hertz contact stress and stiffness per ball contact; coupling stiffness; error motion."""

    id = "hertz"
    pictures = "kcheck_checks.pictures.hertz:draw"
    summary = (
        "Hertz contact of every ball contact under the seated load: peak pressure against the "
        "materials' allowable, contact stiffness; the coupling's stiffness matrix and the "
        "error motion of a body point under a disturbing load"
    )
    applies_to = (
        "scenes whose supports carry contact geometry (coupling shorthands) and some seating "
        "force (weight, preloads or a load with a design direction)"
    )
    options = HertzOptions

    def skip_reason(self, scene: Scene) -> str | None:
        """Every support needs its contact geometry (a ball-cone's ring contact has its own
        model, :mod:`kcheck.mechanics.ring_contact`)."""
        bare = [s.name for s in scene.supports if s.contact_geometry is None]
        if bare:
            shown = ", ".join(bare[:4]) + (", ..." if len(bare) > 4 else "")
            return (
                f"not checked: needs the contact geometry of every support; {shown} "
                f"{'is an explicit support' if len(bare) == 1 else 'are explicit supports'} "
                "with no `contact` (give each `contact: {ball_radius, seat_radii}`, or write "
                "the coupling with `couplings:` shorthands)"
            )
        seating = scene.preloads or (scene.body is not None and np.any(scene.gravity[: scene.dim]))
        load = scene.load
        designed = load is not None and load.magnitude > 0 and load.direction is not None
        if not seating and not designed:
            return (
                "nothing seats the coupling (no weight, no preloads, no load with a design "
                "direction): contact forces and contact stiffness are zero"
            )
        return None

    def needs_mass_for(self, scene: Scene) -> bool:
        """Mass properties for the weight, or for a load acting at the centre of mass."""
        if scene.body is None:
            return False
        load = scene.load
        at_com = load is not None and load.point is None and load.direction is not None
        return bool(np.any(scene.gravity[: scene.dim])) or at_com

    def run(self, inputs: Inputs) -> CheckResult:
        """Seated forces, Hertz contacts, stiffness matrix, error motion, verdict."""
        assert isinstance(inputs.options, HertzOptions)
        return hertz_result(self.id, inputs.scene, inputs.mass, inputs.options)


def _unknown_couplings(scene: Scene, options: HertzOptions) -> CheckResult | None:
    known = {g.coupling for s in scene.supports if (g := s.contact_geometry) is not None}
    unknown = sorted(set(options.couplings) - known)
    if not unknown:
        return None
    message = (
        f"materials given for unknown coupling(s) {', '.join(unknown)}; "
        f"the scene's couplings: {', '.join(sorted(known))}"
    )
    return CheckResult(
        "hertz",
        Status.ERROR,
        message,
        findings=(Finding(message, "unknown-coupling", ("checks", "hertz", "couplings")),),
    )


def _contact_json(
    support: Support, contacts: Contacts, i: int, seated: HertzContact, worst: HertzContact
) -> dict[str, Any]:
    g = support.contact_geometry
    assert g is not None
    ball, seat = contacts.ball[i], contacts.seat[i]
    return {
        "support": support.name,
        "coupling": g.coupling,
        "ball_material": ball.name,
        "ball_material_grade": ball.grade or ball.name,
        "ball_material_from": contacts.ball_from[i],
        "seat_material": seat.name,
        "seat_material_grade": seat.grade or seat.name,
        "seat_material_from": contacts.seat_from[i],
        "contact_modulus": float(contacts.modulus[i]),
        "curvature_sums": [float(contacts.sum_a[i]), float(contacts.sum_b[i])],
        # a circle has no major axis
        "major_axis": None
        if contacts.sum_b[i] - contacts.sum_a[i] <= CURVATURE_RTOL * contacts.sum_b[i]
        else contacts.major_axis[i].tolist(),
        "normal_force": float(seated.force[i]),
        "semi_axes": [float(seated.a[i]), float(seated.b[i])],
        "max_pressure": float(seated.max_pressure[i]),
        "approach": float(seated.approach[i]),
        "stiffness": float(seated.stiffness[i]),
        "normal_force_worst": float(worst.force[i]),
        "max_pressure_worst": float(worst.max_pressure[i]),
        "allowable_pressure": float(contacts.allowable[i]),
    }


@dataclass(frozen=True)
class _Rings:
    """The ring contacts (ball-cone couplings) among the supports: ``line`` marks their
    supports; per support the arc it stands for (a third of the circle, m), the ball radius
    (m), the ring radius (m), the angle between its normal and the cone's axis (rad) and that
    axis (n, 3; zero for point contacts); ``groups`` the support indices of each ring,
    ``names`` their couplings."""

    line: np.ndarray
    arc: np.ndarray
    ball_radius: np.ndarray
    ring_radius: np.ndarray
    angle: np.ndarray
    axis: np.ndarray
    groups: tuple[np.ndarray, ...]
    names: tuple[str, ...]


def _rings(scene: Scene) -> _Rings:
    """Where the ball-cone rings are: the circle through each coupling's contact points (its
    centre their centroid, the axis along their mean normal)."""
    n = len(scene.supports)
    out = {k: np.zeros(n) for k in ("arc", "ball_radius", "ring_radius", "angle")}
    line = np.zeros(n, bool)
    axes = np.zeros((n, 3))
    members: dict[str, list[int]] = {}
    for i, s in enumerate(scene.supports):
        g = s.contact_geometry
        if g is not None and g.line_contact:
            members.setdefault(g.coupling, []).append(i)
    for idx in members.values():
        points = np.array([scene.supports[i].position for i in idx])
        normals = np.array([scene.supports[i].normal for i in idx])
        axis = normals.mean(axis=0)
        axis /= np.linalg.norm(axis)
        radius = float(np.mean(np.linalg.norm(points - points.mean(axis=0), axis=1)))
        for i, normal in zip(idx, normals, strict=True):
            g = scene.supports[i].contact_geometry
            assert g is not None
            line[i] = True
            out["arc"][i] = 2.0 * np.pi * radius / len(idx)
            out["ball_radius"][i] = g.ball_radius
            out["ring_radius"][i] = radius
            out["angle"][i] = float(np.arccos(np.clip(normal @ axis, -1.0, 1.0)))
            axes[i] = axis
    return _Rings(
        line,
        out["arc"],
        out["ball_radius"],
        out["ring_radius"],
        out["angle"],
        axes,
        tuple(np.array(v) for v in members.values()),
        tuple(members),
    )


def _mechanics(
    force: np.ndarray, contacts: Contacts, rings: _Rings, peak: Sequence[np.ndarray] = ()
) -> HertzContact:
    """Every contact under normal forces (N): Hertz for points, the ring contact for
    ball-cone supports (``a`` half the arc a support stands for, ``b`` the half-width; the
    stiffness the arc's). ``peak``: load states (forces, N) whose largest ring peak line load
    (:func:`~kcheck.mechanics.ring_contact.ring_peak_load`) sets each ring's pressure, for
    stresses (each state's own distribution: supports' maxima from different states are no
    state of the ring)."""
    from kcheck.mechanics.hertz import HertzContact, hertz
    from kcheck.mechanics.ring_contact import line_contact, ring_peak_load

    n = len(force)
    fields = {k: np.zeros(n) for k in ("a", "b", "p0", "delta", "k")}
    point = ~rings.line
    if np.any(point):
        h = hertz(force[point], contacts.sum_a[point], contacts.sum_b[point],
                  contacts.modulus[point])  # fmt: skip
        for key, v in zip(fields, (h.a, h.b, h.max_pressure, h.approach, h.stiffness), strict=True):
            fields[key][point] = v
    if np.any(rings.line):
        w = np.where(rings.line, force / np.where(rings.line, rings.arc, 1.0), 0.0)
        line = line_contact(w, np.where(rings.line, rings.ball_radius, 1.0), contacts.modulus)
        shown = line
        if len(peak):
            w_peak = w.copy()
            for group in rings.groups:
                states = [np.clip(f[group], 0.0, None) / rings.arc[group] for f in peak]
                w_peak[group] = max(
                    float(ring_peak_load(s)) if len(group) == 3 else float(s.max()) for s in states
                )
            shown = line_contact(w_peak, np.where(rings.line, rings.ball_radius, 1.0),
                                 contacts.modulus)  # fmt: skip
        m = rings.line
        fields["a"][m] = 0.5 * rings.arc[m]
        fields["b"][m] = shown.half_width[m]
        fields["p0"][m] = shown.max_pressure[m]
        fields["delta"][m] = line.approach[m]
        fields["k"][m] = line.stiffness[m] * rings.arc[m]
    return HertzContact(force, *fields.values())


def _point(value: Sequence[float] | None, scene: Scene, default: np.ndarray) -> np.ndarray:
    return default if value is None else np.asarray(value, float) * scene.scale


@dataclass(frozen=True)
class _Forces:
    """Contact forces (N): seated, with the disturbance, and which contacts lift or open."""

    seated: np.ndarray
    disturbed: np.ndarray
    error: np.ndarray
    lifted: np.ndarray
    opened: np.ndarray


def _forces(
    scene: Scene, seat: Seat, loads: Sequence[Preload], torque: np.ndarray, options: HertzOptions
) -> tuple[_Forces | None, float, dict[str, Any]]:
    """Seated and disturbed contact forces, or None on a singular layout; the condition."""
    from kcheck.mechanics.seat import contact_forces, external_wrench

    seated = contact_forces(seat, external_wrench(seat, loads, torque))
    if seated.value is None or seated.error is None:
        return None, seated.condition, {}
    extra: dict[str, Any] = {}
    change = np.zeros_like(seated.value)
    if options.disturbed:
        origin = seat.frame.origin
        error_point = _point(options.error_point, scene, origin)
        point = _point(options.disturbing_point, scene, error_point)
        dist = Preload("disturbance", point, np.asarray(options.disturbing_force, float))
        wrench = external_wrench(seat, [dist], np.asarray(options.disturbing_torque, float))
        # The same matrix as the seated solve, so not singular either.
        change = contact_forces(seat, wrench).value  # type: ignore[assignment]
        extra["disturbing_load"] = {
            "point": point.tolist(),
            "force": list(options.disturbing_force),
            "torque": list(options.disturbing_torque),
        }
    tol = LIFTED_RTOL * seat.frame.force
    lifted = seated.value <= tol
    total = seated.value + change
    return (
        _Forces(seated.value, total, seated.error, lifted, (total <= tol) & ~lifted),
        seated.condition,
        extra,
    )


def _contact_findings(scene: Scene, forces: _Forces) -> list[Finding]:
    names = [s.name for s in scene.supports]
    out = []
    for i in map(int, np.flatnonzero(forces.lifted)):
        out.append(
            Finding(
                f"{names[i]} would have to pull ({format_number(forces.seated[i], 3)} N) under "
                "the seated load: the body lifts off there",
                "lifts-off",
                _support_field(scene, i),
                "add preload (springs, a magnet) or move the closing force so every contact "
                "carries load",
            )
        )
    for i in map(int, np.flatnonzero(forces.opened)):
        out.append(
            Finding(
                f"{names[i]} opens under the disturbing load "
                f"({format_number(forces.seated[i], 3)} N seated, "
                f"{format_number(forces.disturbed[i], 3)} N disturbed)",
                "opens-under-disturbance",
                _support_field(scene, i),
                "raise the preload above the disturbance's share at this contact",
            )
        )
    return out


def _stress_findings(
    scene: Scene,
    contacts: Contacts,
    worst: HertzContact,
    utilisation: np.ndarray,
    sf: float,
    line: np.ndarray,
) -> list[Finding]:
    out = []
    for i in map(int, np.flatnonzero(utilisation > 1.0)):
        weak = contacts.weaker(i)
        assert weak.allowable_pressure is not None
        factor = f" / safety factor {sf:g}" if sf != 1 else ""
        u = utilisation[i]
        # p0 ~ (P / R^2)^(1/3) at a point: radii u^(3/2) larger or force u^3 smaller; on a
        # ring p0 ~ sqrt(w / R) with w ~ P / R: ~ sqrt(P) / R, the ball u larger (its ring
        # with it) or the force u^2 smaller
        hint = (
            f"to get below it: a ball {u:.2g}x larger, {u**2:.2g}x less force, or a harder material"
            if line[i]
            else f"to get below it: contact radii {u**1.5:.2g}x larger (a larger ball, a "
            f"conformal groove or cylinder), {u**3:.2g}x less force, or a harder material"
        )
        out.append(
            Finding(
                f"{scene.supports[i].name} ({contacts.ball[i].label} ball on "
                f"{contacts.seat[i].label} seat): peak pressure "
                f"{_pressure(worst.max_pressure[i])} exceeds {weak.label}'s allowable "
                f"{_pressure(weak.allowable_pressure)}{factor} "
                f"({format_percent(utilisation[i])})",
                "contact-stress",
                _support_field(scene, i),
                hint,
            )
        )
    return out


def _subsurface(
    contacts: Contacts, worst: HertzContact, line: np.ndarray
) -> list[dict[str, dict[str, Any]]]:
    """Per contact and side (ball, seat): the largest shear and von Mises stresses below the
    surface under the heavier load, their depths, and von Mises over the side's yield; a
    ring (``line``) contact's from the 2D line contact."""
    from kcheck.mechanics.subsurface import (
        SubsurfaceStress,
        line_subsurface_stress,
        subsurface_stress,
    )

    n = len(contacts.ball)
    sides = {"ball": contacts.ball, "seat": contacts.seat}
    nu = np.array([m.poisson for ms in sides.values() for m in ms], float)
    a, b, p0, lines = (np.tile(v, 2) for v in (worst.a, worst.b, worst.max_pressure, line))
    both = SubsurfaceStress(*(np.zeros(2 * n) for _ in range(4)))
    for group, solve in ((~lines, subsurface_stress), (lines, None)):
        if not np.any(group):
            continue
        found = (
            subsurface_stress(a[group], b[group], p0[group], nu[group])
            if solve is not None
            else line_subsurface_stress(b[group], p0[group], nu[group])
        )
        for name in ("max_shear", "max_shear_depth", "von_mises", "von_mises_depth"):
            getattr(both, name)[group] = getattr(found, name)
    out: list[dict[str, dict[str, Any]]] = [{} for _ in range(n)]
    for k, (side, materials) in enumerate(sides.items()):
        for i, m in enumerate(materials):
            j = k * n + i
            mises = float(both.von_mises[j])
            out[i][side] = {
                "max_shear": float(both.max_shear[j]),
                "max_shear_depth": float(both.max_shear_depth[j]),
                "von_mises": mises,
                "von_mises_depth": float(both.von_mises_depth[j]),
                "yield_strength": m.yield_strength,
                "yield_utilisation": None if not m.yield_strength else mises / m.yield_strength,
            }
    return out


def _ring_details(
    scene: Scene,
    contacts: Contacts,
    rings: _Rings,
    forces: _Forces,
    seated: HertzContact,
    worst: HertzContact,
    details: dict[str, Any],
) -> None:
    """details["rings"]: per ball-cone coupling the ring's line loads, half-width, peak
    pressure, its stiffness along and across the cone's axis and their uncertainty."""
    from kcheck.mechanics.ring_contact import cone_stiffness, line_uncertainty, ring_peak_load

    out = []
    notes = details.setdefault("notes", [])
    for name, group in zip(rings.names, rings.groups, strict=True):
        i = int(group[0])
        arc, radius, ring = rings.arc[group], rings.ball_radius[i], rings.ring_radius[i]
        k_line = seated.stiffness[group] / arc
        axial, radial = cone_stiffness(float(np.mean(k_line)), ring, float(rings.angle[i]))
        j = int(group[np.argmax(worst.max_pressure[group])])
        uncertainty = line_uncertainty(seated.b[group], radius)
        states = [np.clip(f[group], 0.0, None) / arc for f in (forces.seated, forces.disturbed)]
        if len(group) == 3 and any(2.0 * np.mean(w) - ring_peak_load(w) < 0 for w in states):
            # the first harmonic dips below zero: part of the ring lifts
            notes.append(
                f"ring contact {name} is unloaded along part of its circle under the seated or "
                "disturbed load: its peak line load (a first harmonic through three points) is "
                "approximate"
            )
        out.append(
            {
                "coupling": name,
                "ball_radius": float(radius),
                "ring_radius": float(ring),
                "normal_angle_deg": float(np.degrees(rings.angle[i])),
                "normal_force": float(seated.force[group].sum()),
                "line_load": (seated.force[group] / arc).tolist(),
                "half_width": seated.b[group].tolist(),
                "line_stiffness": k_line.tolist(),
                "axial_stiffness": float(axial),
                "radial_stiffness": float(radial),
                "stiffness_uncertainty": float(np.max(uncertainty)),
                # p0 = 2 w / (pi b)
                "peak_line_load_worst": float(np.pi * worst.max_pressure[j] * worst.b[j] / 2.0),
                "max_pressure_worst": float(worst.max_pressure[j]),
                "contact_modulus": float(contacts.modulus[i]),
            }
        )
    details["rings"] = out
    notes.append(
        "ball-cone: a ring (line) contact; its stiffness assumes a datum about one ball radius "
        "deep in both bodies (docs/checks.md, hertz), as does its tangential (no-slip) stiffness"
    )


def _ring_tangential(
    contacts: Contacts, rings: _Rings, seated: HertzContact, normals: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Each ring support's no-slip tangential stiffness (N/m, its arc's) across the line
    (meridional tangent) and along it (circumferential tangent), with those unit tangents
    (n, 3); zeros for point contacts (:func:`~kcheck.mechanics.ring_contact.
    line_tangential_stiffness`)."""
    from kcheck.mechanics.ring_contact import line_tangential_stiffness

    n = len(normals)
    across, along = np.zeros(n), np.zeros(n)
    t_m, t_c = np.zeros((n, 3)), np.zeros((n, 3))
    m = rings.line
    if np.any(m):
        km, kc = line_tangential_stiffness(
            seated.b[m],
            rings.ball_radius[m],
            np.array([c.youngs_modulus for c in contacts.ball], float)[m],
            np.array([c.poisson for c in contacts.ball], float)[m],
            np.array([c.youngs_modulus for c in contacts.seat], float)[m],
            np.array([c.poisson for c in contacts.seat], float)[m],
        )
        across[m], along[m] = km * rings.arc[m], kc * rings.arc[m]
        c = np.cross(rings.axis[m], normals[m])
        t_c[m] = c / np.linalg.norm(c, axis=1)[:, None]
        t_m[m] = np.cross(normals[m], t_c[m])
    return t_m, across, t_c, along


def _ring_text(scene: Scene, rings: list[dict[str, Any]]) -> str:
    """The rings' stiffness in a designer's words."""
    return "; ".join(
        f"ring contact {r['coupling']} (r = {format_number(r['ring_radius'] / scene.scale, 3)} "
        f"{scene.units}): axial/radial stiffness {_stiffness_text(r['axial_stiffness'])}/"
        f"{_stiffness_text(r['radial_stiffness'])} N/µm "
        f"(±{r['stiffness_uncertainty']:.0%}, line contact)"
        for r in rings
    )


def _thermal(
    scene: Scene,
    seat: Seat,
    contacts: Contacts,
    options: HertzOptions,
    point: np.ndarray,
    details: dict[str, Any],
) -> str:
    """The thermal pose shift at ``point`` and the thermal centre (details["thermal"]); the
    message's words. Every expansion coefficient must be known: none is assumed."""
    from kcheck.mechanics.thermal import thermal_approach, thermal_shift

    d_t = options.temperature_change
    body_name = options.body_material
    if body_name is None and scene.body is not None and len(scene.body.materials) == 1:
        body_name = scene.body.materials[0]
    body = None if body_name is None else options.lookup(body_name)
    base = None if options.base_material is None else options.lookup(options.base_material)
    missing = []
    if body is None or body.thermal_expansion is None:
        missing.append(
            "the body's expansion (set the body's `material` or `body_material` under checks: "
            "hertz)"
            if body is None
            else f"{body.label}'s expansion coefficient"
        )
    if base is None or base.thermal_expansion is None:
        missing.append(
            "the base's expansion (set `base_material` under checks: hertz)"
            if base is None
            else f"{base.label}'s expansion coefficient"
        )
    balls = [m.thermal_expansion for m in contacts.ball]
    if any(a is None for a in balls):
        missing.append("a ball's expansion coefficient")
    if missing:
        details["thermal"] = {"temperature_change": d_t, "not_computed": missing}
        return f"thermal shift not computed: {'; '.join(missing)} unknown"
    assert body is not None and base is not None
    assert body.thermal_expansion is not None and base.thermal_expansion is not None
    geometry = [s.contact_geometry for s in scene.supports]
    approach = thermal_approach(
        np.array([s.position for s in scene.supports]),
        np.array([s.normal for s in scene.supports]),
        np.array([g.ball_center for g in geometry if g is not None]),
        np.array([g.ball_radius for g in geometry if g is not None]),
        np.array([g is not None and g.ball_on == "body" for g in geometry]),
        seat.frame.origin,
        body.thermal_expansion,
        base.thermal_expansion,
        np.array(balls, float),
        d_t,
    )
    beta = (body.thermal_expansion - base.thermal_expansion) * d_t
    found = thermal_shift(seat, approach, beta, point)
    if found is None:  # the seated solve succeeded with the same matrix: not reached
        return "thermal shift not computed: singular layout"
    nw = seat.rotations
    rotation = found.twist[:nw] if nw == 3 else np.array([0.0, 0.0, found.twist[0]])
    details["thermal"] = {
        "temperature_change": d_t,
        "alpha_body": body.thermal_expansion,
        "alpha_base": base.thermal_expansion,
        "point": point.tolist(),
        "shift": found.shift.tolist(),
        "rotation": rotation.tolist(),
        "centre": None if found.centre is None else found.centre.tolist(),
    }
    centre = (
        "no thermal centre (body and base expand alike)"
        if found.centre is None
        else f"thermal centre {format_vector(found.centre / scene.scale)} {scene.units}"
    )
    return (
        f"thermal shift ({d_t:+g} K) {format_number(float(np.linalg.norm(found.shift)) * 1e6, 3)}"
        f" µm, {format_number(float(np.linalg.norm(rotation)) * 1e6, 3)} µrad at "
        f"{format_vector(point / scene.scale)} {scene.units}; {centre}"
    )


def _materials_text(scene: Scene, contacts: Contacts) -> str:
    """The materials of every contact, in a designer's words: ``materials: 52100 balls on
    aluminium (as 6061-t6) seats`` (one pair) or per group of couplings."""
    groups: dict[tuple[str, str], list[str]] = {}
    for i, s in enumerate(scene.supports):
        g = s.contact_geometry
        assert g is not None
        names = groups.setdefault((contacts.ball[i].label, contacts.seat[i].label), [])
        if g.coupling not in names:
            names.append(g.coupling)
    if len(groups) == 1:
        (ball, seat), _ = next(iter(groups.items()))
        return f"materials: {ball} balls on {seat} seats"
    return "materials: " + ", ".join(
        f"{ball} on {seat} ({', '.join(names)})" for (ball, seat), names in groups.items()
    )


def _lift_off_result(
    check_id: str, scene: Scene, forces: _Forces, details: dict[str, Any]
) -> CheckResult:
    """A contact would have to pull under the seated load: the coupling does not seat, and the
    solution's stresses (with a pulling contact) describe no real state; none are shown."""
    names = [scene.supports[i].name for i in map(int, np.flatnonzero(forces.lifted))]
    details["lifted"] = names
    details["seated_forces"] = {
        s.name: float(f) for s, f in zip(scene.supports, forces.seated, strict=True)
    }
    return CheckResult(
        check_id,
        Status.FAIL,
        f"the body lifts off at {', '.join(names)} under the seated load: the coupling does "
        "not seat, so no contact stress is reported",
        details=details,
        findings=tuple(f for f in _contact_findings(scene, forces) if f.code == "lifts-off"),
    )


def _unknown_materials_result(
    check_id: str, scene: Scene, unknown: list[Unknown], details: dict[str, Any]
) -> CheckResult:
    """Some contact's material is not known: not checked, and how to give it (no default)."""
    findings = []
    seen: dict[tuple[str, str], None] = {}
    for u in unknown:
        g = scene.supports[u.index].contact_geometry
        assert g is not None
        key = (g.coupling, u.side)
        if key in seen:
            continue
        seen[key] = None
        what = f"material of {g.coupling}'s {u.side}"
        text = (
            f"not checked: {what} unknown"
            if u.name is None
            else (f"not checked: {what} ({u.name}) has no elastic constants")
        )
        findings.append(
            Finding(
                text, "material-unknown", _support_field(scene, u.index), unknown_hint(scene, u)
            )
        )
    first = findings[0].message
    more = (
        f" (and {len(findings) - 1} more: "
        + ", ".join(f"{c}'s {side}" for c, side in list(seen)[1:])
        + ")"
        if len(findings) > 1
        else ""
    )
    details["unknown_materials"] = [{"coupling": c, "side": side} for c, side in seen]
    # the headline's way out covers every side that is unknown (balls and seats both)
    sides = [side for _, side in seen]
    hint = findings[0].hint or ""
    other = next((s for s in ("ball", "seat") if s in sides and s != sides[0]), None)
    if other is not None:
        hint += f" (and likewise `{other}_material` for the {other}s)"
    return CheckResult(
        check_id,
        Status.SKIPPED,
        f"{first}{more}; {hint}",
        details=details,
        findings=tuple(findings),
    )


def hertz_result(check_id: str, scene: Scene, mass: Any, options: HertzOptions) -> CheckResult:
    """The hertz check's result for a scene whose supports all carry contact geometry."""
    from kcheck.mechanics.hertz import contact_shear_modulus, tangential_stiffness
    from kcheck.mechanics.seat import (
        directed_stiffness_matrix,
        point_compliance,
        point_translation,
        seat_layout,
        seated_loads,
        stiffness_matrix,
        tangential_stiffness_matrix,
        twist_from_approach,
    )

    bad = _unknown_couplings(scene, options)
    if bad is not None:
        return bad
    positions = np.array([s.position for s in scene.supports])
    normals = np.array([s.normal for s in scene.supports])
    loads, torque, notes = seated_loads(scene, mass)
    scale = max([float(np.linalg.norm(p.force)) for p in loads] + [ZERO_GUARD])
    seat = seat_layout(positions, normals, scene.dim, scale)
    error_point = _point(options.error_point, scene, seat.frame.origin)
    details: dict[str, Any] = {
        "safety_factor": options.safety_factor,
        "reference_point": seat.frame.origin.tolist(),
        "seated_load": [
            {
                "name": p.name,
                "point": np.asarray(p.point).tolist(),
                "force": np.asarray(p.force).tolist(),
            }
            for p in loads
        ],
    }
    if notes:
        details["notes"] = notes
    forces, condition, extra = _forces(scene, seat, loads, torque, options)
    details["condition"] = condition
    details.update(extra)
    if forces is None:
        return CheckResult(
            check_id,
            Status.FAIL,
            f"the support layout is singular (condition {condition:.1e}): the seated contact "
            "forces are not determined; no contact stresses reported",
            details=details,
        )
    if np.any(forces.lifted):
        return _lift_off_result(check_id, scene, forces, details)
    contacts = contacts_of(scene, options)
    if not isinstance(contacts, Contacts):
        return _unknown_materials_result(check_id, scene, contacts, details)
    rings = _rings(scene)
    seated = _mechanics(forces.seated.clip(0.0), contacts, rings)
    heavier = np.maximum(forces.seated, forces.disturbed).clip(0.0)
    worst = _mechanics(heavier, contacts, rings, peak=(forces.seated, forces.disturbed))
    allowable = contacts.allowable / options.safety_factor
    utilisation = worst.max_pressure / allowable
    details["contacts"] = [
        _contact_json(s, contacts, i, seated, worst) | {"utilisation": float(utilisation[i])}
        for i, s in enumerate(scene.supports)
    ]
    details["max_utilisation"] = float(utilisation.max())
    details["materials"] = _materials_text(scene, contacts)
    below = _subsurface(contacts, worst, rings.line)
    for entry, sides in zip(details["contacts"], below, strict=True):
        entry["subsurface"] = sides
    used = [
        side["yield_utilisation"]
        for sides in below
        for side in sides.values()
        if side["yield_utilisation"] is not None
    ]
    details["max_yield_utilisation"] = max(used) if used else None
    # Hertz theory assumes contacts small against the radii (half-space, small strains).
    # (a ring's contact is long along its circle by design: its width against the ball's radius)
    size = float(np.max(np.where(rings.line, worst.b / np.where(rings.line, rings.ball_radius,
                                 1.0), worst.a * 2.0 * contacts.sum_b)))  # fmt: skip
    large = f"contacts large against their radii (a/R up to {size:.2g}): Hertz is approximate"
    if size > 0.1:
        details.setdefault("notes", []).append(large)
    findings = _contact_findings(scene, forces)
    findings += _stress_findings(
        scene, contacts, worst, utilisation, options.safety_factor, rings.line
    )
    i = int(np.argmax(utilisation))
    parts = [
        f"peak contact pressure {_pressure(worst.max_pressure[i])} at {scene.supports[i].name} "
        f"({format_percent(utilisation[i])} of {_pressure(allowable[i])} allowed)"
    ]
    if size > 0.1:
        parts.append(large)
    parts.append(details["materials"])
    big_k = stiffness_matrix(seat, seated.stiffness)
    details["stiffness_matrix"] = big_k.tolist()
    shear = contact_shear_modulus(
        np.array([m.youngs_modulus for m in contacts.ball], float),
        np.array([m.poisson for m in contacts.ball], float),
        np.array([m.youngs_modulus for m in contacts.seat], float),
        np.array([m.poisson for m in contacts.seat], float),
    )
    # A ring's tangential compliance is the line contact's (logarithmic like its normal one,
    # and different across and along the line): its own directions, not the point's circle.
    k_t = np.where(rings.line, 0.0, tangential_stiffness(seated, shear))
    ring_t = _ring_tangential(contacts, rings, seated, normals)
    for i, entry in enumerate(details["contacts"]):
        entry["tangential_stiffness"] = float(ring_t[1][i] if rings.line[i] else k_t[i])
        if rings.line[i]:
            entry["tangential_stiffness_along_line"] = float(ring_t[3][i])
    if np.any(rings.line):
        _ring_details(scene, contacts, rings, forces, seated, worst, details)
        from kcheck.mechanics.ring_contact import cone_tangential_stiffness

        for entry, group in zip(details["rings"], rings.groups, strict=True):
            arc = rings.arc[group]
            axial, radial = cone_tangential_stiffness(
                float(np.mean(ring_t[1][group] / arc)),
                float(np.mean(ring_t[3][group] / arc)),
                entry["ring_radius"],
                float(rings.angle[group[0]]),
            )
            entry["axial_tangential_stiffness"] = float(axial)
            entry["radial_tangential_stiffness"] = float(radial)
        parts.append(_ring_text(scene, details["rings"]))
    big_kt = big_k + tangential_stiffness_matrix(seat, positions, normals, k_t)
    for tangents, k in ((ring_t[0], ring_t[1]), (ring_t[2], ring_t[3])):
        big_kt = big_kt + directed_stiffness_matrix(seat, positions, tangents, k)
    details["stiffness_matrix_with_tangential"] = big_kt.tolist()
    compliance = None if np.any(forces.lifted) else point_compliance(seat, big_k, error_point)
    if compliance is not None:
        axis_k = 1.0 / np.diag(compliance)
        details["error_point"] = error_point.tolist()
        details["point_stiffness"] = axis_k.tolist()
        details["point_compliance"] = compliance.tolist()
        with_t = point_compliance(seat, big_kt, error_point)
        if with_t is not None:
            details["point_stiffness_with_tangential"] = (1.0 / np.diag(with_t)).tolist()
        parts.append(
            f"stiffness at {format_vector(error_point / scene.scale)} {scene.units}: "
            + "/".join(_stiffness_text(k) for k in axis_k)
            + f" N/µm ({'/'.join('xyz'[: scene.dim])})"
        )
    if options.disturbed and compliance is not None and not np.any(forces.opened):
        disturbed = _mechanics(forces.disturbed.clip(0.0), contacts, rings)
        motion = twist_from_approach(seat, disturbed.approach - seated.approach)
        assert motion.value is not None
        nw = seat.rotations
        translation = point_translation(seat, motion.value, error_point)
        rotation = motion.value[:nw] if nw == 3 else np.array([0.0, 0.0, motion.value[0]])
        details["error_motion"] = {
            "point": error_point.tolist(),
            "translation": translation.tolist(),
            "rotation": rotation.tolist(),
        }
        parts.append(
            f"error motion {format_number(float(np.linalg.norm(translation) * 1e6), 3)} µm, "
            f"{format_number(float(np.linalg.norm(rotation) * 1e6), 3)} µrad "
            "under the disturbing load"
        )
    if options.temperature_change:
        parts.append(_thermal(scene, seat, contacts, options, error_point, details))
    # Forces err by about the solve's estimate; p0 ~ N^(1/3) at a point, so utilisation by a
    # third of it; ~ N^(1/2) on a ring, by half.
    rel = float(np.max(forces.error / np.maximum(np.abs(forces.seated), ZERO_GUARD)))
    spread = np.where(rings.line, utilisation * rel / 2.0, utilisation * rel / 3.0)
    result = CheckResult(
        check_id,
        Status.PASS if not findings else Status.FAIL,
        "; ".join(parts),
        error_estimate=float(np.max(spread)),
        details=details,
        findings=tuple(findings),
    )
    band = options.marginal_utilisation
    return with_margin(
        result,
        "contact stress utilisation",
        float(utilisation[i]),
        band,
        "at most",
        f"{scene.supports[i].name} uses {format_percent(utilisation[i])} of its allowable "
        f"contact pressure, above the {format_percent(band)} limit (wear, roughness, load "
        "scatter)",
        hint="larger balls or seat radii, a harder material, or less seating force (the "
        "option `marginal_utilisation` sets the band)",
        field=_support_field(scene, i),
    )
