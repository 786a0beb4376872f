"""Reseating in time: the body, its supports as ball-on-plane contacts, simulated in MuJoCo.

For one retracted support a case runs three stretches of time:

0. *settle*: the body, placed on its supports, comes to rest under its loads (the seat every
   error is measured from, so the contacts' small soft-contact overlap cancels);
1. *retract*: the support jumps back by the retraction distance along its normal, and the
   body moves under the closing force, its weight and its preloads (with ``retraction_time``
   set, the support backs off on a half-cosine over that time instead of jumping);
2. *return*: the support comes back to its place (a smooth half-cosine over a quarter of the
   phase), and the body must come back to its seat.

Everything is SI. Each support is a small sphere fixed on the body, touching a plane through
the support point normal to it (a mocap body, so the retracted one can move), with Coulomb
friction at the support's coefficient (elliptic cones). Planar scenes move in the xy-plane
only (two slide joints and a hinge about z). MuJoCo is imported by :func:`simulate` only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import field

import numpy as np

from kcheck.numerics.thresholds import (
    RESEAT_BACKOFF_MOTION_SHARE,
    RESEAT_JAM_FACTOR,
    RESEAT_LOST_SHARE,
    RESEAT_RELEASE_TIME_CONSTANTS,
    RESEAT_REST_SPEED,
    RESEAT_STICK_SHARE,
    RESEAT_WINDOW_SHARE,
)
from kcheck.records import dataclass
from kcheck.result import MassProperties
from kcheck.scene import Scene

__all__ = [
    "FIRST_MOTIONS",
    "first_motion_settings",
    "ReseatSettings",
    "Trace",
    "ReseatRun",
    "scene_xml",
    "simulate",
    "first_motion",
    "first_motion_end",
    "kept_contacts",
    "seat_errors",
    "ball_radius",
    "rotation_angle",
    "inertia_missing",
]

#: First-motion classes, in analytical-2d/3d's words (``jams``: friction holds the body).
FIRST_MOTIONS = ("closes", "loses_contact", "opens", "opens_loses_contact", "jams")

#: Settle time as a share of one phase ...
SETTLE_SHARE = 0.2
#: ... and at least this many contact time constants (a short phase still settles).
SETTLE_TIME_CONSTANTS = 50
#: A seat still moving after the settle settles on, in blocks of the settle, up to this (s).
SETTLE_LIMIT = 1.0
#: Return time of the support as a share of phase 2.
RETURN_SHARE = 0.25
#: Ball radius as a share of the supports' size (largest distance from their centroid).
BALL_SHARE = 0.01
#: Samples of the trace per phase.
SAMPLES = 400


@dataclass(frozen=True)
class ReseatSettings:
    """How a case is simulated: retraction distance (m), closing-force profile (``step``:
    constant; ``ramp``: the load falls to zero when the support backs off and rises linearly to
    full over the first half of phase 1), duration of each phase (s), time step (s), contact
    time constant (s) and damping ratio (MuJoCo ``solref``), impedance (``solimp``), seat
    tolerance (m, on the largest contact-point displacement), and MuJoCo's noslip iterations
    (0: off; on, a sticking contact does not creep in the soft friction cone). ``window``
    shortens phase 1 (and the settle with it) for a run that only reads the first motion; the
    load's ramp keeps ``duration``."""

    retraction: float = 1e-4
    profile: str = "step"
    duration: float = 0.5
    time_step: float = 1e-4
    time_constant: float = 2e-3
    damping_ratio: float = 1.0
    impedance: float = 0.99
    tolerance: float = 1e-6
    noslip_iterations: int = 0
    retraction_time: float = 0.0  # s, the support backs off on a half-cosine over it (0: jumps)
    window: float | None = None  # s, phase 1 alone when shorter than ``duration`` (first motion)


@dataclass(frozen=True)
class Trace:
    """Sampled history of one run: ``time`` (n,) s from the start of phase 1 (negative while
    settling); ``gaps`` (n, k) m, each support's gap from its settled value (positive: open);
    ``forces`` (n, k) N normal force; ``slip`` (n, k) m/s tangential speed of the body's
    contact point; ``reference`` (n, 3) m the centre of mass; ``displacement`` (n,) m the
    largest contact-point displacement from the seat; ``contacts`` (n, k, 3) m the body's
    contact points."""

    time: np.ndarray
    gaps: np.ndarray
    forces: np.ndarray
    slip: np.ndarray
    reference: np.ndarray
    displacement: np.ndarray
    contacts: np.ndarray  # (n, k, 3) m, the body's contact points


@dataclass(frozen=True)
class ReseatRun:
    """One simulated case and what it shows (SI)."""

    retracted: int
    friction: np.ndarray
    trace: Trace
    translation: float  # m, centre of mass, end of phase 2 from the seat
    rotation: float  # rad, end of phase 2
    seat_error: float  # m, largest contact-point displacement at the end of phase 2
    closing_gap: float  # m, largest gap at the end of phase 1 (the retracted seat)
    closed_after: float | None  # s into phase 1 from which every gap stays within tolerance
    reseated_after: float | None  # s into phase 2 from which the error stays within tolerance
    largest_gaps: np.ndarray  # (k,) m
    losses: np.ndarray  # (k,) contact-loss events
    sticks: np.ndarray  # (k,) slide-to-stick events
    first: str
    settle_speed: float = 0.0  # m/s, largest contact-point speed at the end of the settle
    seat_forces: np.ndarray | None = None  # (k,) N, normal forces at the end of the settle
    steps: int = 0
    notes: tuple[str, ...] = field(default=())
    # (k,) the supports pressed where the first motion is read; None when friction holds
    kept: np.ndarray | None = None


#: The first-motion run's phase 1 (s): the window ends within a few ms.
FIRST_MOTION_WINDOW = 0.05
#: Its contact time constant at most (s): at 2 ms a contact the analysis says is lost takes as
#: long to unload out of its seated overlap as the body takes to move the window's 10 µm.
FIRST_MOTION_TIME_CONSTANT = 5e-4
#: Its time step at most (s): a tenth of the time constant (at a fifth the stiff contacts
#: chatter after the sudden release).
FIRST_MOTION_TIME_STEP = 5e-5
#: Its noslip iterations: a body friction holds stays held instead of creeping.
FIRST_MOTION_NOSLIP = 10


def first_motion_settings(settings: ReseatSettings) -> ReseatSettings:
    """The settings of the run the first motion is read from: the case's, with phase 1
    shortened to FIRST_MOTION_WINDOW, contacts at least as stiff as FIRST_MOTION_TIME_CONSTANT,
    half the time step (at most FIRST_MOTION_TIME_STEP) and noslip on (docs/validation.md:
    the settings the agreement with analytical-2d/3d is measured at)."""
    from dataclasses import replace

    return replace(
        settings,
        # The window opens when the support has backed off (retraction_time after the start).
        window=min(settings.duration, FIRST_MOTION_WINDOW + settings.retraction_time),
        time_constant=min(settings.time_constant, FIRST_MOTION_TIME_CONSTANT),
        time_step=min(settings.time_step / 2, FIRST_MOTION_TIME_STEP),
        noslip_iterations=max(settings.noslip_iterations, FIRST_MOTION_NOSLIP),
    )


def inertia_missing(scene: Scene, mass: MassProperties) -> bool:
    """Whether the inertia the simulation needs is unknown (Izz for a planar scene)."""
    needed = mass.inertia[2, 2] if scene.kind == "planar" else mass.inertia
    return not bool(np.all(np.isfinite(needed)))


def ball_radius(scene: Scene) -> float:
    """Radius (m) of the small contact spheres: BALL_SHARE of the supports' size."""
    points = np.array([s.position for s in scene.supports])
    size = float(np.max(np.linalg.norm(points - points.mean(axis=0), axis=1)))
    return BALL_SHARE * size


def _quat_z_to(n: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) turning +z onto the unit vector ``n``."""
    z = np.array([0.0, 0.0, 1.0])
    c = float(z @ n)
    if c < -1 + 1e-12:
        return np.array([0.0, 1.0, 0.0, 0.0])
    axis = np.cross(z, n)
    q = np.array([1.0 + c, *axis])
    return q / np.linalg.norm(q)


def _fmt(values: Sequence[float] | np.ndarray) -> str:
    return " ".join(repr(float(v)) for v in values)


def scene_xml(
    scene: Scene, mass: MassProperties, friction: np.ndarray, settings: ReseatSettings, dt: float
) -> str:
    """The MJCF model of a scene: a rigid body with the scene's mass properties and one
    sphere-on-plane pair per support, friction ``friction`` (k,)."""
    r = ball_radius(scene)
    inertia = mass.inertia
    planar = scene.kind == "planar"
    if planar:  # a hinge about z feels Izz alone (the scene may give no other component)
        full = [inertia[2, 2]] * 3 + [0.0] * 3
    else:
        full = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2]]
        full.append(inertia[1, 2])
    if planar:
        joints = (
            '<joint name="x" type="slide" axis="1 0 0"/>'
            '<joint name="y" type="slide" axis="0 1 0"/>'
            '<joint name="rz" type="hinge" axis="0 0 1"/>'
        )
    else:
        joints = '<freejoint name="free"/>'
    planes, balls, pairs = [], [], []
    solref = f"{settings.time_constant!r} {settings.damping_ratio!r}"
    d = settings.impedance
    solimp = f"{d!r} {d!r} 0.001 0.5 2"
    for i, s in enumerate(scene.supports):
        n = s.normal / np.linalg.norm(s.normal)
        planes.append(
            f'<body name="support{i}" mocap="true" pos="{_fmt(s.position)}" '
            f'quat="{_fmt(_quat_z_to(n))}"><geom name="plane{i}" type="plane" size="0 0 1"/></body>'
        )
        balls.append(
            f'<geom name="ball{i}" type="sphere" size="{r!r}" pos="{_fmt(s.position + r * n)}"/>'
        )
        mu = float(friction[i])
        pairs.append(
            f'<pair geom1="ball{i}" geom2="plane{i}" condim="3" '
            f'friction="{mu!r} {mu!r} 0.005 0.0001 0.0001" solref="{solref}" solimp="{solimp}"/>'
        )
    gravity = scene.gravity
    return (
        "<mujoco>"
        f'<option timestep="{dt!r}" gravity="{_fmt(gravity)}" cone="elliptic" '
        f'noslip_iterations="{settings.noslip_iterations}" '
        'integrator="implicitfast" iterations="100" tolerance="1e-12">'
        '<flag refsafe="disable"/></option>'
        '<default><geom contype="0" conaffinity="0"/></default>'
        "<worldbody>"
        + "".join(planes)
        + '<body name="body" pos="0 0 0">'
        + joints
        + f'<inertial pos="{_fmt(mass.center_of_mass)}" mass="{mass.mass!r}" '
        f'fullinertia="{_fmt(full)}"/>'
        + "".join(balls)
        + "</body></worldbody><contact>"
        + "".join(pairs)
        + "</contact></mujoco>"
    )


def _wrench(scene: Scene, com: np.ndarray, load_scale: float) -> np.ndarray:
    """Force (3) and torque about the current centre of mass ``com`` (3) of the closing load
    (times ``load_scale``) and the preloads, in N and N m (gravity is MuJoCo's)."""
    force = np.zeros(3)
    torque = np.zeros(3)
    load = scene.load
    if load is not None and load.magnitude > 0 and load.direction is not None:
        f = load.magnitude * load.direction * load_scale
        point = com if load.point is None else load.point
        force += f
        torque += np.cross(point - com, f) + load.torque * load_scale
    elif load is not None:
        torque += load.torque * load_scale
    for p in scene.preloads:
        force += p.force
        torque += np.cross(p.point - com, p.force)
    if scene.kind == "planar":
        force[2] = 0.0
        torque[:2] = 0.0
    return np.concatenate([force, torque])


def simulate(
    scene: Scene,
    mass: MassProperties,
    retracted: int,
    friction: np.ndarray,
    settings: ReseatSettings,
    dt: float | None = None,
    returns: bool = True,
) -> ReseatRun:
    """Simulate one retraction case (settle, retract, return) and measure it. With
    ``returns`` False the return is not simulated (the first motion alone: the seat error and
    times then describe the end of phase 1)."""
    import mujoco

    dt = settings.time_step if dt is None else dt
    model = mujoco.MjModel.from_xml_string(scene_xml(scene, mass, friction, settings, dt))
    data = mujoco.MjData(model)
    body = model.body("body").id
    k = len(scene.supports)
    normals = np.array([s.normal / np.linalg.norm(s.normal) for s in scene.supports])
    points = np.array([s.position for s in scene.supports])
    r = ball_radius(scene)
    ball_local = points + r * normals  # body frame = world frame at the start
    seats = points.copy()
    pair_of = {int(model.geom(f"ball{i}").id): i for i in range(k)}
    phase = settings.duration if settings.window is None else settings.window
    n_phase = max(1, round(phase / dt))
    settle = max(SETTLE_SHARE * phase, SETTLE_TIME_CONSTANTS * settings.time_constant)
    n_settle = max(1, round(settle / dt))
    chunk = max(1, n_phase // SAMPLES)
    force6 = np.zeros(6)

    rows: list[tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []

    def sample(t: float) -> None:
        rot = data.xmat[body].reshape(3, 3)
        pos = data.xpos[body]
        centres = ball_local @ rot.T + pos
        gaps = np.einsum("ij,ij->i", centres - data.mocap_pos, normals) - r
        forces = np.zeros(k)
        for c in range(data.ncon):
            i = pair_of.get(int(data.contact[c].geom1), pair_of.get(int(data.contact[c].geom2)))
            if i is None:
                continue
            mujoco.mj_contactForce(model, data, c, force6)
            forces[i] += force6[0]
        rows.append((t, centres.copy(), gaps, forces, data.xipos[body].copy()))

    def load_scale(t: float) -> float:
        if settings.profile == "ramp" and t >= 0:
            return min(1.0, t / (0.5 * settings.duration))
        return 1.0

    def run(
        steps: int,
        t0: float,
        start: np.ndarray | None = None,
        end: np.ndarray | None = None,
        over: float = 0.0,
        every_step: bool = False,
    ) -> None:
        """``steps`` steps from ``t0``; with ``start`` and ``end`` the retracted support moves
        between them on a half-cosine over ``over`` seconds, once per stored sample, or with
        ``every_step`` at every step until it gets there (a slow back-off: a staircase of one
        move per sample releases a seat's µm-small overlap in sudden steps)."""

        def place(share: float) -> None:
            assert start is not None and end is not None
            data.mocap_pos[retracted] = start + (end - start) * 0.5 * (
                1 - math.cos(math.pi * share)
            )

        done = 0
        while done < steps:
            n = min(chunk, steps - done)
            t = t0 + done * dt
            if start is not None and end is not None:
                place(min(1.0, (done * dt) / over) if over > 0 else 1.0)
            data.xfrc_applied[body] = _wrench(scene, data.xipos[body], load_scale(t))
            if every_step and over > 0 and done * dt < over:
                for j in range(n):
                    place(min(1.0, ((done + j) * dt) / over))
                    mujoco.mj_step(model, data)
            else:
                mujoco.mj_step(model, data, n)
            done += n
            sample(t0 + done * dt)

    # The settle is frictionless: with friction the body would stop wherever its sinking into
    # the soft contacts first sticks, on forces the rigid seat does not have (often a support
    # unloaded); frictionless it settles on the seat's determinate normal forces.
    rough = model.pair_friction[:, :2].copy()
    model.pair_friction[:, :2] = 0.0
    mujoco.mj_forward(model, data)
    data.xfrc_applied[body] = _wrench(scene, data.xipos[body], 1.0)
    accel = float(np.linalg.norm(data.xfrc_applied[body][:3])) / mass.mass
    accel += float(np.linalg.norm(scene.gravity[: scene.dim]))
    sample(-n_settle * dt)
    starts = [0]
    while True:
        run(n_settle, -n_settle * dt)
        settle_speed = float(
            np.max(np.linalg.norm(rows[-1][1] - rows[-2][1], axis=1)) / (rows[-1][0] - rows[-2][0])
        )
        if settle_speed <= RESEAT_REST_SPEED or len(starts) * n_settle * dt >= SETTLE_LIMIT:
            break
        starts.append(len(rows))
    for b, first_row in enumerate(starts):  # blocks one after the other, the last ending at 0
        shift = -(len(starts) - 1 - b) * n_settle * dt
        last_row = starts[b + 1] if b + 1 < len(starts) else len(rows)
        for j in range(first_row, last_row):
            rows[j] = (rows[j][0] + shift, *rows[j][1:])
    seated_centres = rows[-1][1].copy()
    seated_gaps = rows[-1][2].copy()
    seated_forces = rows[-1][3].copy()
    seated_com = rows[-1][4].copy()
    seated_quat = data.xquat[body].copy()
    model.pair_friction[:, :2] = rough
    backed = seats[retracted] - settings.retraction * normals[retracted]
    if settings.retraction_time > 0:
        sample(0.0)
        start = len(rows) - 1
        run(n_phase, 0.0, seats[retracted], backed, settings.retraction_time, every_step=True)
    else:
        data.mocap_pos[retracted] = backed
        mujoco.mj_forward(model, data)
        sample(0.0)
        start = len(rows) - 1
        run(n_phase, 0.0)
    end1 = len(rows) - 1
    if returns:
        # From where the support got to (a back-off longer than phase 1 stops part-way).
        reached = data.mocap_pos[retracted].copy()
        run(n_phase, n_phase * dt, reached, seats[retracted], RETURN_SHARE * settings.duration)

    time = np.array([row[0] for row in rows])
    centres = np.array([row[1] for row in rows])
    gaps = np.array([row[2] for row in rows]) - seated_gaps
    forces = np.array([row[3] for row in rows])
    com = np.array([row[4] for row in rows])
    contact = centres - r * normals  # the body's contact points (ball bottoms)
    seated_contact = seated_centres - r * normals
    displacement = np.max(np.linalg.norm(contact - seated_contact, axis=2), axis=1)
    # Backward differences; the retraction's jump (two samples at t = 0) counts as at rest.
    step = np.diff(time)[:, None, None]
    velocity = np.zeros_like(contact)
    velocity[1:] = np.diff(contact, axis=0) / np.where(step > 0, step, np.inf)
    tangential = velocity - np.einsum("tij,ij->ti", velocity, normals)[..., None] * normals
    slip = np.linalg.norm(tangential, axis=2)
    rotation = rotation_angle(seated_quat, data.xquat[body])
    trace = Trace(
        time=time,
        gaps=gaps,
        forces=forces,
        slip=slip,
        reference=com,
        displacement=displacement,
        contacts=contact,
    )
    tol = settings.tolerance
    phase1 = slice(start, end1 + 1)
    phase2 = slice(end1, len(rows))
    closing_gap = float(np.max(np.abs(gaps[end1])))
    seat_error = float(displacement[-1])
    read_at = first_motion_end(time[phase1], contact[phase1], settings, accel)
    kept = None if read_at is None else kept_contacts(forces[phase1], read_at)
    losses, sticks = _events(
        gaps[start:], forces[start:], slip[start:], np.asarray(friction), settings, retracted
    )
    return ReseatRun(
        retracted=retracted,
        friction=np.asarray(friction, dtype=float),
        trace=trace,
        translation=float(np.linalg.norm(com[-1] - seated_com)),
        rotation=rotation,
        seat_error=seat_error,
        closing_gap=closing_gap,
        closed_after=_settled_after(time[phase1], np.max(np.abs(gaps[phase1]), axis=1), tol),
        reseated_after=_settled_after(time[phase2] - time[end1], displacement[phase2], tol),
        largest_gaps=np.max(gaps[start:], axis=0),
        losses=losses,
        sticks=sticks,
        first=first_motion(
            time[phase1],
            contact[phase1],
            gaps[phase1],
            forces[phase1],
            normals,
            retracted,
            settings,
            accel,
        ),
        steps=int(len(starts) * n_settle + (2 if returns else 1) * n_phase),
        settle_speed=settle_speed,
        seat_forces=seated_forces,
        kept=kept,
    )


def rotation_angle(q0: np.ndarray, q1: np.ndarray) -> float:
    """Angle (rad) of the rotation from unit quaternion ``q0`` to ``q1`` (w, x, y, z), from the
    vector part of ``conj(q0) q1`` (accurate for the µrad angles ``acos`` rounds to zero)."""
    w0, v0 = q0[0], -np.asarray(q0[1:])
    w1, v1 = q1[0], np.asarray(q1[1:])
    w = w0 * w1 - float(v0 @ v1)
    v = w0 * v1 + w1 * v0 + np.cross(v0, v1)
    return 2 * math.atan2(float(np.linalg.norm(v)), abs(float(w)))


def _settled_after(time: np.ndarray, error: np.ndarray, tol: float) -> float | None:
    """The first time from which ``error`` stays within ``tol``; None if it ends outside."""
    outside = np.nonzero(error > tol)[0]
    if len(outside) == 0:
        return float(time[0])
    last = int(outside[-1])
    return None if last == len(time) - 1 else float(time[last + 1])


def _events(
    gaps: np.ndarray,
    forces: np.ndarray,
    slip: np.ndarray,
    friction: np.ndarray,
    settings: ReseatSettings,
    retracted: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Contact-loss events (a touching support's gap opening beyond the tolerance) and stick
    events (a pressed contact's slip speed falling from above to below the stick speed) per
    support, from phase 1 on. The retracted support starts open."""
    open_ = gaps > settings.tolerance
    touching = ~open_
    touching[0, retracted] = False
    lost = touching[:-1] & open_[1:]
    lost[0, retracted] = False
    stick_speed = RESEAT_STICK_SHARE * settings.retraction / settings.duration
    rough = friction > 0
    sliding = (slip > stick_speed) & (forces > 0) & rough
    stuck = (slip <= stick_speed) & (forces > 0) & rough
    sticks = sliding[:-1] & stuck[1:]
    return lost.sum(axis=0), sticks.sum(axis=0)


def first_motion_end(
    time: np.ndarray, contact: np.ndarray, settings: ReseatSettings, accel: float
) -> int | None:
    """Index of phase 1's sample the first motion is read at, or None when friction holds the
    body (see :func:`first_motion`).

    The body moves when, within RESEAT_JAM_FACTOR free-body times after the support has got
    to its backed-off place, a contact point moves RESEAT_WINDOW_SHARE of the retraction from
    where it was then; or, with a slow back-off, when a contact point moves
    RESEAT_BACKOFF_MOTION_SHARE of it from the seat while the support backs off (it follows or
    leaves the support). The creep of a held body during the back-off is not counted against
    the window's distance. The jump (no back-off) reads the window from the seat alone."""
    reach = RESEAT_WINDOW_SHARE * settings.retraction
    limit = RESEAT_JAM_FACTOR * math.sqrt(2 * reach / max(accel, 1e-300))
    elapsed = time - time[0]
    backed = settings.retraction_time
    # The first sample once the support has backed off (0 for the jump). The 1e-9 is a
    # relative tolerance on the sample times: the sample whose time rounds a few ulps below
    # the back-off time (time steps summed in floating point) counts as at it.
    b = min(int(np.searchsorted(elapsed, backed * (1 - 1e-9))), len(time) - 1) if backed else 0
    after = np.max(np.linalg.norm(contact[b:] - contact[b], axis=2), axis=1)
    inside = b + np.nonzero((after >= reach) & (elapsed[b:] - elapsed[b] <= limit))[0]
    if backed > 0:
        during = np.max(np.linalg.norm(contact[: b + 1] - contact[0], axis=2), axis=1)
        if float(during.max()) >= RESEAT_BACKOFF_MOTION_SHARE * settings.retraction:
            # Followed or left: read from the seat, where the motion passed the window's distance.
            inside = np.nonzero(during >= reach)[0]
    if len(inside) == 0:
        return None
    # A contact the rigid motion unloads at once comes out of its seated overlap only as the
    # body moves: the class is read no earlier than RESEAT_RELEASE_TIME_CONSTANTS after the
    # release (the support's back-off included).
    release = backed + RESEAT_RELEASE_TIME_CONSTANTS * settings.time_constant
    return max(int(inside[0]), int(np.searchsorted(elapsed, min(release, elapsed[-1]))))


def kept_contacts(forces: np.ndarray, end: int) -> np.ndarray:
    """Which supports (k,) carry at least RESEAT_LOST_SHARE of the normal force over the second
    half of phase 1's samples up to ``end`` (forces (n, k) N)."""
    late = slice(max(1, end // 2), end + 1)
    share = forces[late].mean(axis=0) / max(float(forces[late].sum(axis=1).mean()), 1e-300)
    return np.asarray(share >= RESEAT_LOST_SHARE)


def first_motion(
    time: np.ndarray,
    contact: np.ndarray,
    gaps: np.ndarray,
    forces: np.ndarray,
    normals: np.ndarray,
    retracted: int,
    settings: ReseatSettings,
    accel: float,
) -> str:
    """The class of the body's first motion in phase 1, in analytical-2d/3d's words.

    The window ends when a contact point has moved RESEAT_WINDOW_SHARE of the retraction
    distance, and no earlier than RESEAT_RELEASE_TIME_CONSTANTS contact time constants after
    the release. If moving that far takes longer than RESEAT_JAM_FACTOR times the time a free
    body would need under the acceleration scale ``accel`` (m/s^2: loads over mass, plus
    gravity), friction holds it (jams: soft friction only creeps). Otherwise: does the
    retracted contact point move towards its support (closes) or away (opens), and is a
    remaining contact open while carrying less than RESEAT_LOST_SHARE of the normal force over
    the window's second half (loses contact)."""
    end = first_motion_end(time, contact, settings, accel)
    if end is None:
        return "jams"
    towards = -float((contact[end, retracted] - contact[0, retracted]) @ normals[retracted])
    others = np.delete(np.arange(gaps.shape[1]), retracted)
    opened = gaps[end, others] > 0
    lost = bool(np.any(~kept_contacts(forces, end)[others] & opened))
    if towards > 0:
        return "loses_contact" if lost else "closes"
    return "opens_loses_contact" if lost else "opens"


def seat_errors(runs: Sequence[ReseatRun]) -> np.ndarray:
    """Final seat errors (m) of runs."""
    return np.array([run.seat_error for run in runs])
