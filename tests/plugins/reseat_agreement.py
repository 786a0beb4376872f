"""First motion of the `reseat` simulation against analytical-2d/3d's outcome class, on
generated scenes and the fixtures (tests/plugins/test_reseat.py; the disagreements and their
reasons are written to tests/plugins/data/reseat_disagreements.json)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from kcheck.analysis import analyse
from kcheck.analysis.held_alternatives import held_alternatives
from kcheck.analysis.jamming_cases import analyse_jamming, held_at, jam_statics
from kcheck.analysis.reseat import (
    ReseatRun,
    ReseatSettings,
    _wrench,
    first_motion_settings,
    simulate,
)
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.kinematics import wrenches
from kcheck.mechanics.lift_off import lift_off
from kcheck.numerics.thresholds import RESEAT_JAM_FACTOR
from kcheck.result import CaseResult, MassProperties
from kcheck.scene import Scene, load_scene
from tests.plugins.reseat_scenes import random_scene

__all__ = [
    "Compared",
    "compare_scene",
    "generated",
    "reason",
    "rigid_motion",
    "unresolved",
    "SECOND_ANSWER",
    "HELD_UNIQUELY_MOVES",
    "UNLOADING",
    "OR_HELD_MOTION",
    "STIFFER",
]

#: The check's own first-motion run (kcheck.analysis.reseat.first_motion_settings) at the
#: default options: phase 1 of 50 ms, contacts 0.5 ms stiff (four times the check's default:
#: at 2 ms a contact the analysis says is lost takes as long to unload out of its seated
#: overlap as the body takes to move the window's 10 µm, so the window closed before the lost
#: contact let go), MuJoCo's noslip pass on (a body friction holds stays held instead of
#: creeping through the soft friction cone), time step 0.05 ms (at 0.1 ms, a fifth of the
#: contact time constant, the stiff contacts chattered after the sudden release, a light
#: contact dropping to zero force and back every step or two: random-2d-2430, s1).
FIRST_MOTION = first_motion_settings(ReseatSettings())
#: Contact stiffness factors a disagreeing case is run at again (time constant and time step
#: divided by each): does the simulation's class converge to the analysis's?
STIFFER = (2, 4)
#: A seated-case normal force within this share of the largest is "at the resolution limit".
NEAR_ZERO = 0.05
#: A remaining contact below this share of the largest normal force is lightly pressed.
LIGHT = 0.2


@dataclass(frozen=True)
class Compared:
    scene: str
    retracted: str
    analytical: str
    simulated: str
    held: bool | None
    smallest_force_share: float | None
    mu: float
    settle_speed: float
    seat_pressed: float  # the smallest seated normal force over the largest, simulated
    unresolved: bool = False  # the analysis itself reports the case unresolved
    may_hold: bool = False  # the analysis reports that friction can hold the body as well
    slow: bool = False  # the rigid first motion too slow for the window to tell from holding
    # whether the simulation's first motion (the contacts it keeps, the others free) is a
    # consistent rigid first motion too; None when the simulation jams
    rigid_motion: bool | None = None
    stiffer: tuple[str, ...] = ()  # the simulated class with contacts STIFFER times stiffer
    # for a case `jamming` says friction holds: whether the rigid model admits no motion
    # beside rest (not "or held", and no second answer, kcheck.analysis.held_alternatives)
    unique: bool | None = None

    @property
    def agrees(self) -> bool:
        """The simulation does what the analysis says: its class, or, where the analysis says
        friction can also hold the body (the rigid model's second answer), stays held."""
        return self.analytical == self.simulated or (self.may_hold and self.simulated == "jams")


#: A held case the analysis also says moves ("or held"), moving in the analysis's class.
OR_HELD_MOTION = (
    "the analysis's motion and jamming's equilibrium are both consistent (the analysis says "
    "'or held'); from the released seat the body takes the motion"
)
#: Rest and the simulation's motion are both rigid solutions.
SECOND_ANSWER = (
    "second rigid answer: friction can hold the body (jamming: an equilibrium exists), and the "
    "simulation's first motion is a rigid solution too (the lift-off LCP on the contacts the "
    "simulation keeps lifts none of them, and every other contact separates); the rigid model "
    "does not choose between rest and this motion, the soft one moves"
)
#: Friction holds the body uniquely in the rigid model, and the soft one moves anyway.
HELD_UNIQUELY_MOVES = (
    "held uniquely in the rigid model as far as kcheck finds (jamming: an equilibrium exists; "
    "no second answer on any subset of the remaining contacts, and the lift-off LCP on the "
    "contacts the simulation keeps gives rest), but the simulation moves, its class changing "
    "with the contact stiffness: the soft model's answer, not converged to a rigid one"
)
#: The simulation reads a contact as kept that is still coming out of its seated overlap.
UNLOADING = (
    "soft contact still unloading: the contacts the simulation keeps where it reads the first "
    "motion are no rigid motion (the lift-off LCP on them lifts one), and with contacts 2 or 4 "
    "times stiffer (time constant and step divided alike) the simulation gives the analysis's "
    "class"
)


def reason(c: Compared) -> str:
    """Why a first motion differs from the analytical outcome class."""
    if c.analytical == "ambiguous":
        return "Painlevé: the rigid-body equations have no unique sliding answer"
    if c.analytical == "jams" and c.held is False:
        return (
            "analytical jams, but no equilibrium holds the body (jamming: moves) and the "
            "first motion with contacts free to lift off found none lifting"
        )
    if c.held and c.simulated == "jams":
        return (
            "friction can hold the body as well (jamming: an equilibrium exists, the rigid "
            "model's second consistent answer), and the simulation stays held; the analysis "
            "does not say so"
        )
    if c.held and c.rigid_motion:
        return SECOND_ANSWER
    if c.rigid_motion is False and c.analytical in c.stiffer:
        return UNLOADING
    if c.held and c.unique and c.simulated != "jams":
        return HELD_UNIQUELY_MOVES
    if c.may_hold:
        return (
            "unexplained: the analysis says the body moves, or friction holds it (both "
            "consistent in the rigid model); the simulation moves in another class"
        )
    if c.analytical == "jams" and c.held:
        return (
            "held by friction in the rigid model (jamming: an equilibrium exists), but the "
            "force distribution the soft contacts' compliance sets leaves a contact outside "
            "its friction cone, and the body slides (noslip on: not creep)"
        )
    if c.slow and c.simulated == "jams":
        return (
            "slow first motion: the rigid motion (contacts lifting off) accelerates the "
            "retracted contact at under 1/RESEAT_JAM_FACTOR² of the load's acceleration, too "
            "slowly for the simulation's window to tell it from holding"
        )
    if c.smallest_force_share is not None and c.smallest_force_share < NEAR_ZERO:
        return "at the resolution limit: a normal force within 5 % of zero"
    if (
        c.analytical == "closes"
        and c.simulated == "loses_contact"
        and c.smallest_force_share is not None
        and c.smallest_force_share < LIGHT
    ):
        return (
            "release transient: a lightly pressed contact (under 20 % of the largest normal "
            "force) opens in the contact vibration the sudden retraction starts"
        )
    return "unexplained"


def compare_scene(path: Path, settings: ReseatSettings = FIRST_MOTION) -> Iterator[Compared]:
    """Every retracted case of one scene, analytical outcome beside simulated first motion."""
    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    analysis = analyse(scene, mass)
    statics, swept, design = jam_statics(scene, mass)
    jams = analyse_jamming(statics, swept, design) if design is not None else None
    mu = scene.friction_range("kinetic")[1]
    # The acceleration scale the simulation's jams limit is set by (kcheck.analysis.reseat).
    load = 0.0 if scene.load is None else scene.load.magnitude
    scale = load / mass.mass + float(np.linalg.norm(scene.gravity[: scene.dim]))
    for r, result in enumerate(analysis.results):
        run = simulate(scene, mass, r, mu, settings, returns=False)
        held = None
        if jams is not None and design is not None:
            held = held_at(jams, jams.cases[r], design, statics.friction)
        may_hold = bool(result.details.get("friction_may_hold"))
        unique = None
        if held:
            assert jams is not None
            unique = not may_hold and (
                held_alternatives(scene, mass, [(r, jams.cases[r].keep)])[r] is None
            )
        agrees = result.outcome == run.first or (may_hold and run.first == "jams")
        stiffer: tuple[str, ...] = ()
        if result.outcome != "ambiguous" and (not agrees or (held and run.first != "jams")):
            stiffer = tuple(
                simulate(
                    scene,
                    mass,
                    r,
                    mu,
                    replace(
                        settings,
                        time_constant=settings.time_constant / f,
                        time_step=settings.time_step / f,
                    ),
                    returns=False,
                ).first
                for f in STIFFER
            )
        share = None
        lifted = result.details.get("lifts_off") or []
        if result.normal_forces:  # lifted contacts carry nothing by construction
            forces = np.array([f for n, f in result.normal_forces.items() if n not in lifted])
            share = float(np.min(np.abs(forces)) / max(np.max(np.abs(forces)), 1e-300))
        yield Compared(
            path.name,
            result.retracted,
            result.outcome,
            run.first,
            held,
            share,
            float(mu.max()),
            run.settle_speed,
            _pressed(run.seat_forces),
            unresolved(result),
            may_hold,
            bool(lifted)
            and result.acceleration is not None
            and abs(result.acceleration) < scale / RESEAT_JAM_FACTOR**2,
            rigid_motion(scene, mass, r, run),
            stiffer,
            unique,
        )


def rigid_motion(scene: Scene, mass: MassProperties, retracted: int, run: ReseatRun) -> bool | None:
    """Whether the simulation's first motion is a rigid solution too: the first motion from
    rest on the contacts the simulation keeps (the lift-off LCP, kcheck.mechanics.lift_off)
    moves the body and lifts none of them, and every other remaining contact's normal
    acceleration separates it (rest on the kept contacts is no motion: False). None when the
    simulation holds the body."""
    if run.kept is None:
        return None
    dim = scene.dim
    points = np.array([s.position for s in scene.supports])[:, :dim]
    normals = np.array([s.normal / np.linalg.norm(s.normal) for s in scene.supports])[:, :dim]
    com = mass.center_of_mass[:dim]
    inertia = np.array([[mass.inertia[2, 2]]]) if dim == 2 else mass.inertia
    gravity = np.concatenate([mass.mass * scene.gravity, np.zeros(3)])
    load = _wrench(scene, mass.center_of_mass, 1.0) + gravity  # force, torque about the com
    wrench = np.array([load[5], load[0], load[1]]) if dim == 2 else np.r_[load[3:], load[:3]]
    kept = [i for i in range(len(points)) if run.kept[i] and i != retracted]
    others = [i for i in range(len(points)) if i not in kept and i != retracted]
    if not kept:  # the body leaves every support: not judged here
        return None
    mu = np.asarray(run.friction)
    motion = lift_off(
        points[kept],
        normals[kept],
        mu[kept],
        com,
        inertia / mass.mass,
        wrench / mass.mass,
        (points[retracted], normals[retracted]),
    )
    if motion is None or not motion.moves or np.any(motion.lifted):
        return False
    separating = wrenches(points[others] - com, normals[others]) @ motion.acceleration
    return bool(np.all(separating >= -1e-9 * np.linalg.norm(wrench) / mass.mass))


def unresolved(result: CaseResult) -> bool:
    """Whether analytical-2d/3d itself reports the case unresolved: its outcome undetermined or
    ill-conditioned, a friction interval it could not resolve, or a kept contact whose friction
    direction it could not determine."""
    return result.outcome in ("undetermined", "ill_conditioned") or any(
        key in result.details for key in ("friction_intervals_unresolved", "friction_undetermined")
    )


def _pressed(forces: np.ndarray | None) -> float:
    if forces is None or np.max(forces) <= 0:
        return 0.0
    return float(np.min(forces) / np.max(forces))


def generated(folder: Path, count: int, seed: int = 26) -> list[Path]:
    """``count`` seated random scenes, planar and spatial alternately."""
    rng = np.random.default_rng(seed)
    paths: list[Path] = []
    index = 0
    while len(paths) < count:
        index += 1
        path = random_scene(rng, folder, index, 2 if len(paths) % 2 == 0 else 3)
        if path is not None:
            paths.append(path)
    return paths
