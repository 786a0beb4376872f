"""The `reseat` check (MuJoCo): known answers, convergence, the picture, agreement of the
first motion with analytical-2d/3d. Skipped, saying why, only where the `sim` extra is absent."""

from __future__ import annotations

import dataclasses
import json
import shutil
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip(
    "mujoco", reason="the reseat check needs the optional `sim` extra: pip install 'kcheck[sim]'"
)

from kcheck.analysis.reseat import ReseatSettings, rotation_angle, simulate  # noqa: E402
from kcheck.body.mass import body_mass_properties  # noqa: E402
from kcheck.numerics.thresholds import RESEAT_REST_SPEED  # noqa: E402
from kcheck.scene import load_scene  # noqa: E402
from tests.conftest import FIXTURES  # noqa: E402
from tests.plugins.held_backoff import back_off_class  # noqa: E402
from tests.plugins.reseat_agreement import (  # noqa: E402
    HELD_UNIQUELY_MOVES,
    OR_HELD_MOTION,
    SECOND_ANSWER,
    UNLOADING,
    Compared,
    compare_scene,
    generated,
    reason,
)

#: Short phases keep each test to a few seconds; every case here settles within 0.1 s.
SHORT = ReseatSettings(duration=0.2)
DISAGREEMENTS = Path(__file__).parent / "data" / "reseat_disagreements.json"


def _fixture_copy(tmp_path: Path, name: str, old: str, new: str) -> Path:
    """A fixture folder copied with one line of its scene replaced."""
    folder = shutil.copytree(FIXTURES / name, tmp_path / name)
    scene = next(folder.glob("*.kcheck.yaml"))
    text = scene.read_text(encoding="utf-8")
    assert old in text
    scene.write_text(text.replace(old, new), encoding="utf-8")
    return scene


def test_rotation_angle_of_small_turns() -> None:
    """2 atan2(|v|, w) of the relative quaternion: a turn of 1e-7 rad about z is 1e-7 rad
    (acos of the dot product would round it to zero)."""
    theta = 1e-7
    q0 = np.array([1.0, 0.0, 0.0, 0.0])
    q1 = np.array([np.cos(theta / 2), 0.0, 0.0, np.sin(theta / 2)])
    assert rotation_angle(q0, q1) == pytest.approx(theta, rel=1e-9)


def test_frictionless_three_vee_reseats_within_a_micrometre(tmp_path: Path) -> None:
    """Known answer: without friction an exactly constrained seat is unique (Maxwell), so
    after every retraction and return the plate is back within 1 µm and 1 µrad."""
    path = _fixture_copy(tmp_path, "maxwell-three-vee", "friction: 0.1", "friction: 0")
    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    for r in range(len(scene.supports)):
        run = simulate(scene, mass, r, np.zeros(len(scene.supports)), SHORT)
        assert run.first == "closes"
        assert run.closing_gap < 1e-6
        assert run.seat_error < 1e-6, scene.supports[r].name
        assert run.rotation < 1e-6
        assert run.reseated_after is not None


def test_friction_above_the_least_holding_friction_stops_off_seat(tmp_path: Path, cli_json) -> None:
    """Appendix A block, y1 retracted: jamming's least holding friction is 0.124. At μ = 0.1
    the block closes onto the backed-off support and reseats; at μ = 0.3 friction holds it:
    it stops off its (retracted) seat by nearly the whole retraction, 100 µm."""
    _, doc = cli_json(str(FIXTURES / "thesis-appendix-a"), "--select", "jamming")
    (y1,) = [c for c in doc["scenes"][0]["checks"][0]["cases"] if c["retracted"] == "y1"]
    least = y1["holding_friction"]
    assert 0.1 < least < 0.3
    scene = load_scene(FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml")
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    below = simulate(scene, mass, 0, np.full(3, 0.1), SHORT)
    above = simulate(scene, mass, 0, np.full(3, 0.3), SHORT)
    assert below.closing_gap < 1e-6 and below.seat_error < 1e-6
    assert above.first == "jams"
    assert above.closing_gap > 0.9e-4  # held: the gap stays nearly the retraction distance
    assert above.seat_error < 1e-6  # the returning support comes back to it


def test_appendix_a_closes_after_tipping(cli_json) -> None:
    """The thesis's open question (Appendix A): x3 retracted, the block tips about y2 and
    lifts off y1 (first motion `loses_contact`, as analytical-2d says), then comes back onto
    y1 and x3 and reseats (docs/validation.md)."""
    code, doc = cli_json(str(FIXTURES / "thesis-appendix-a"), "--select", "reseat,analytical-2d")
    checks = {c["id"]: c for c in doc["scenes"][0]["checks"]}
    reseat = checks["reseat"]
    (x3,) = [c for c in reseat["cases"] if c["retracted"] == "x3"]
    (ax3,) = [c for c in checks["analytical-2d"]["cases"] if c["retracted"] == "x3"]
    assert ax3["outcome"] == x3["first_motion"] == "loses_contact"
    assert x3["contact_losses"]["y1"] >= 1 and x3["largest_gap_um"]["y1"] > 1
    assert x3["closing_gap_um"] < 1 and x3["seat_error_um"] < 1
    assert reseat["status"] == "pass" and reseat["error_estimate"] >= 0


def test_halving_the_time_step_changes_the_seat_error_less_than_the_estimate(
    tmp_path: Path, cli_json
) -> None:
    """Convergence on the Appendix A fixture: the result at half the time step differs from
    the default's by less than the default run's error_estimate (the difference of its own
    two time steps), case by case."""
    results = []
    for step in ("1.0e-4", "5.0e-5"):
        folder = tmp_path / step
        folder.mkdir()
        path = _fixture_copy(folder, "thesis-appendix-a", "version: 1", "version: 1")
        with path.open("a", encoding="utf-8") as f:
            f.write(f"checks:\n  reseat: {{time_step_s: {step}, duration_s: 0.2}}\n")
        _, doc = cli_json(str(path), "--select", "reseat")
        results.append(doc["scenes"][0]["checks"][0])
    a, b = results
    for x, y in zip(a["cases"], b["cases"], strict=True):
        assert abs(x["seat_error_um"] - y["seat_error_um"]) <= a["error_estimate"] + 1e-9


@pytest.mark.slow
def test_convergence_on_every_fixture(tmp_path: Path) -> None:
    """Every fixture the check applies to: the whole check at half the default time step
    changes no case's seat error by more than the default run's error_estimate."""
    from kcheck_checks.reseat import Reseat, ReseatOptions

    from kcheck.plugin import Inputs

    checked = 0
    for path in sorted(FIXTURES.glob("*/*.kcheck.yaml")):
        scene = load_scene(path)
        check = Reseat()
        if check.skip_reason(scene) is not None:
            continue
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        coarse = check.run(Inputs(scene, mass, ReseatOptions(duration_s=0.2)))
        fine = check.run(Inputs(scene, mass, ReseatOptions(duration_s=0.2, time_step_s=5e-5)))
        assert coarse.error_estimate is not None
        for x, y in zip(coarse.cases, fine.cases, strict=True):
            change = abs(x.details["seat_error_um"] - y.details["seat_error_um"])
            assert change <= coarse.error_estimate + 1e-9, (path.parent.name, x.retracted)
        checked += 1
    assert checked >= 10


def test_picture_is_written(tmp_path: Path) -> None:
    """--plots writes the gaps, forces and path picture of the worst case, and with SVG the
    animation of the contact points."""
    from kcheck.cli import main

    code = main(
        ["check", str(FIXTURES / "thesis-appendix-a"), "--select", "reseat", "--plots",
         str(tmp_path), "--plot-format", "png,svg"]
    )  # fmt: skip
    assert code == 0
    (png,) = tmp_path.glob("*-reseat.png")
    assert png.stat().st_size > 10_000
    # The animation the HTML report inlines: one moving dot per support (two <animate> each).
    motion = (tmp_path / "thesis-appendix-a-block-reseat-motion.svg").read_text(encoding="utf-8")
    assert motion.count("<animate ") == 2 * 3


def test_a_lost_contact_is_linked_to_the_analysis(tmp_path: Path, cli_json) -> None:
    """Appendix A, x3 retracted: analytical-2d says y1 loses contact (its normal force
    -0.087 N, negative); the simulation shows y1 lift and the body reseat, and the message
    links the two."""
    path = _fixture_copy(tmp_path, "thesis-appendix-a", "friction: 0.1", "friction: 0.1")
    with path.open("a", encoding="utf-8") as f:
        f.write("checks:\n  reseat: {duration_s: 0.2}\n")
    _, doc = cli_json(str(path), "--select", "reseat")
    check = doc["scenes"][0]["checks"][0]
    x3 = next(c for c in check["cases"] if c["retracted"] == "x3")
    assert x3["outcome"] == "reseats"
    assert x3["largest_gap_um"]["y1"] > 1.0
    assert "retract x3: y1 lifts" in check["message"]
    assert "as analytical-2d predicts, then the body reseats" in check["message"]


@pytest.mark.parametrize(
    ("option", "name"),
    [
        ("profile: sine", "profile"),
        ("retraction_time_ms: -1", "retraction_time_ms"),
        # Longer than half of the default 0.5 s phase: the body would have no time to move.
        ("retraction_time_ms: 300", "retraction_time_ms"),
    ],
)
def test_bad_option_is_a_located_input_error(cli, write_scene, option: str, name: str) -> None:
    """Options are validated like every check's: an unknown profile or a negative back-off
    time is exit 2, no traceback, naming the option."""
    path = write_scene(
        """
        version: 1
        name: bad profile
        body: {mass: 1, center_of_mass: [0, 0, 0], inertia: 0.001}
        supports:
          - {name: y1, position: [-0.02, -0.03, 0], normal: [0, 1, 0]}
          - {name: y2, position: [0.02, -0.03, 0], normal: [0, 1, 0]}
          - {name: x1, position: [-0.05, 0, 0], normal: [1, 0, 0]}
        load: {magnitude: 1, angle: 225}
        checks:
          reseat: {OPTION}
        """.replace("OPTION", option)
    )
    code, out, err = cli("check", str(path), "--select", "reseat")
    assert code == 2
    assert "Traceback" not in out + err
    assert name in out + err


@pytest.mark.slow
def test_first_motion_agrees_with_the_analytical_outcome(tmp_path: Path) -> None:
    """On three fixtures and 100 generated seated scenes (50 planar, 50 spatial), the
    simulation's first motion against analytical-2d/3d's outcome class.

    Compared are the cases where the analysis's premise holds in the simulation: not
    Painlevé (the rigid equations have no unique answer), and a settled seat at rest that
    presses every support. A case at the resolution limit is left out only when the analysis
    itself reports it unresolved (outcome undetermined or ill-conditioned, a friction interval
    or direction it could not resolve); every other case counts. A case the analysis reports
    as moving "or held" (friction_may_hold: an equilibrium exists too, the rigid model's second
    answer, which it tells the user) agrees when the simulation moves in its class or stays
    held; `agree_by_class_alone` counts the named class only. Every disagreement, and every
    case `jamming` says friction holds that moves, is written with its reason to
    tests/plugins/data/reseat_disagreements.json (checked against the recording; rewritten
    with KCHECK_RECORD_RESEAT=1), with the evidence the reason rests on: whether the
    simulation's motion is a rigid solution too (`rigid_motion`, the lift-off LCP on the
    contacts it keeps) and its class at contacts 2 and 4 times stiffer (`stiffer`). None may
    be unexplained, and each reason a held case moves for is bounded by its measured count.
    Measured: docs/validation.md."""
    import os

    paths = [
        FIXTURES / "planar-block" / "block.kcheck.yaml",
        FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml",
        FIXTURES / "maxwell-three-vee" / "coupling.kcheck.yaml",
        *generated(tmp_path, 100),
    ]
    rows = [c for p in paths for c in compare_scene(p)]
    compared = [c for c in rows if premise(c) is None]
    share = sum(c.agrees for c in compared) / len(compared)
    # Disagreements with a physical reason (the rigid model has a second consistent answer, or
    # a force at the resolution limit) are left out of the share; the soft model's
    # artefacts (creep, release transients) and unexplained ones stay in it as disagreements.
    judged = [c for c in compared if c.agrees or not physical(reason(c))]
    judged_share = sum(c.agrees for c in judged) / len(judged)
    listed = [
        {
            "scene": c.scene,
            "retracted": c.retracted,
            "analytical": c.analytical,
            "simulated": c.simulated,
            "compared": premise(c) is None,
            "reason": premise(c) or reason(c),
            "rigid_motion": c.rigid_motion,
            "stiffer": list(c.stiffer),
        }
        for c in rows
        if not c.agrees
    ]
    moving = [c for c in rows if c.analytical != "ambiguous"]
    held = [c for c in compared if c.held]
    # Every compared case `jamming` says friction can hold that moves in the simulation, why.
    held_moving = [
        {
            "scene": c.scene,
            "retracted": c.retracted,
            "analytical": c.analytical + (" or held" if c.may_hold else ""),
            "simulated": c.simulated,
            "reason": OR_HELD_MOTION if c.agrees else reason(c),
            "rigid_motion": c.rigid_motion,
            "stiffer": list(c.stiffer),
            "unique": c.unique,
        }
        for c in held
        if c.simulated != "jams"
    ]
    uniquely = [c for c in held if c.unique]
    document = {
        "cases": len(rows),
        "compared": len(compared),
        "agree": sum(c.agrees for c in compared),
        # The same without the analysis's "or held": the simulation's class must be the one
        # the analysis names first.
        "agree_by_class_alone": sum(c.analytical == c.simulated for c in compared),
        "share": round(share, 4),
        "judged_without_a_physical_reason": len(judged),
        "share_without_a_physical_reason": round(judged_share, 4),
        "disagreements_by_reason": dict(
            Counter(premise(c) or reason(c) for c in rows if not c.agrees)
        ),
        "not_compared": dict(
            Counter((premise(c) or "").split(":")[1] for c in rows if premise(c) is not None)
        ),
        "share_of_every_non_painleve_case": round(sum(c.agrees for c in moving) / len(moving), 4),
        "held_by_jamming_compared": len(held),
        "held_by_jamming_and_simulated_jams": sum(c.simulated == "jams" for c in held),
        "held_uniquely_compared": len(uniquely),
        "held_uniquely_and_simulated_jams": sum(c.simulated == "jams" for c in uniquely),
        "held_by_jamming_and_simulated_moving_by_reason": dict(
            Counter(d["reason"] for d in held_moving)
        ),
        "held_by_jamming_and_simulated_moving": held_moving,
        "disagreements": listed,
    }
    if os.environ.get("KCHECK_RECORD_RESEAT"):
        DISAGREEMENTS.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    recorded = json.loads(DISAGREEMENTS.read_text(encoding="utf-8"))
    assert share >= MEASURED_SHARE
    assert judged_share >= 0.95
    # Held stays held: measured 137 of 148 (not all, the aim; every one that moves is
    # listed with its reason, docs/validation.md).
    assert sum(c.simulated == "jams" for c in held) >= MEASURED_HELD
    # Every held case either stays held or moves for one of the specific reasons, each class
    # bounded by its measured count (docs/validation.md); none is unexplained.
    # (Another platform's MuJoCo build may move one case more: MEASURED_HELD's margin.)
    by_class = Counter(HELD_MOVING_CLASS.get(d["reason"], "unexplained") for d in held_moving)
    assert "unexplained" not in by_class
    excess = sum(max(0, n - HELD_MOVING_BOUND[k]) for k, n in by_class.items())
    assert excess <= HELD_MEASURED - MEASURED_HELD
    # Held uniquely stays held: every held case that moves is one `jamming` reports as "held or
    # moves" but those bounded by HELD_UNIQUELY_MOVING (measured 124 of 125 held uniquely stay
    # held; 81 of 81 and 91 of 91 on seeds 27 and 28, docs/validation.md).
    assert sum(c.simulated == "jams" for c in uniquely) >= len(uniquely) - HELD_UNIQUELY_MOVING
    # The static claim tested by a quasi-static withdrawal: with the support backing off over
    # each of HELD_BACK_OFFS_S every held-uniquely case stays held (measured 125 of 125,
    # 81 of 81 and 91 of 91 on seeds 26, 27 and 28 at every back-off from 50 ms to 1 s;
    # docs/validation.md, "Held uniquely, a reading for slow back-offs").
    by_name = Counter(p.name for p in paths)
    path_of = {p.name: p for p in paths}
    assert all(by_name[c.scene] == 1 for c in uniquely)  # each case's scene file is known
    moving_slowly = [
        (c.scene, c.retracted, seconds, simulated)
        for seconds in HELD_BACK_OFFS_S
        for c in uniquely
        if (simulated := back_off_class(path_of[c.scene], c.retracted, seconds)) != "jams"
    ]
    assert not moving_slowly
    # No disagreement is unexplained.
    assert not [d for d in listed if d["reason"].startswith("unexplained")]
    # Every held case that moves is one the file lists with its reason.
    listed_moving = {
        (d["scene"], d["retracted"]) for d in recorded["held_by_jamming_and_simulated_moving"]
    }
    assert {(d["scene"], d["retracted"]) for d in held_moving} <= listed_moving
    # Every disagreement now is one the file lists with its reason.
    known = {(d["scene"], d["retracted"]) for d in recorded["disagreements"]}
    assert {(d["scene"], d["retracted"]) for d in listed} <= known


#: The reason classes a case `jamming` says friction holds may move for in the simulation ...
HELD_MOVING_CLASS = {
    OR_HELD_MOTION: "or held: the analysis's motion",
    SECOND_ANSWER: "second rigid answer",
    UNLOADING: "soft contact still unloading",
    HELD_UNIQUELY_MOVES: "held uniquely, the soft model moves",
}
#: ... and how many of the 148 compared held cases each may take (measured: docs/validation.md).
HELD_MOVING_BOUND = {
    "or held: the analysis's motion": 6,
    "second rigid answer": 1,
    "soft contact still unloading": 3,
    "held uniquely, the soft model moves": 1,
}
#: Compared cases `jamming` says friction holds uniquely that move in the simulation
#: (measured: random-3d-1667 retracting s1, whose simulated class changes with the contact
#: stiffness; its recorded rigid_motion was rest on the contacts kept before rigid_motion
#: required a motion).
HELD_UNIQUELY_MOVING = 1
#: Back-offs (s, retraction_time_ms) at which every held-uniquely case stays held: the
#: recommended 250 ms and 500 ms, inside the part of the window that holds at the check's
#: first-motion step and at half of it (200 ms to about 0.7 s; docs/validation.md, "Held
#: uniquely, a reading for slow back-offs"). At the check's step the window is 50 ms to 1 s,
#: but both of its ends are the soft model's and move with the time step (so, likely, with
#: MuJoCo's build): below, random-3d-1667 s1's 0.05 um seat overlap is released within about
#: one contact time constant (0.014 x the back-off) and the ringing contacts walk the body off
#: (it moves at 20 ms at the check's step, up to 150 ms at half of it); above,
#: random-2d-6567 s1 (seed 27) creeps 42-70 um/s (growing as the step shrinks) and passes the
#: 50 um the body may move while the support backs off (RESEAT_BACKOFF_MOTION_SHARE) at
#: 0.7-1.2 s. The test pins the robust middle, not those ends.
HELD_BACK_OFFS_S = (0.25, 0.5)


def premise(c: Compared) -> str | None:
    """Why a case is not compared, or None: the analysis's premise fails in the simulation."""
    if c.analytical == "ambiguous":
        return "not compared: Painlevé, the rigid-body equations have no unique sliding answer"
    if c.unresolved:
        return (
            "not compared: the analysis itself reports the case unresolved (undetermined, "
            "ill-conditioned, or a friction interval or direction it could not resolve)"
        )
    if c.settle_speed > RESEAT_REST_SPEED:
        return (
            "not compared: the simulated seat is not at rest after settling for 1 s (a "
            "near-singular seat, its seated normal forces 7 to 1100 times the load, out of "
            "which the body slides in the soft model)"
        )
    if c.seat_pressed < SEAT_PRESSED:
        return (
            "not compared: a support carries no force in the settled seat (the seat is not "
            "stable to second order, or friction holds the body on fewer supports)"
        )
    return None


#: Every support must carry at least this share of the largest seated normal force.
SEAT_PRESSED = 0.01
#: The share of compared cases measured on these scenes, every disagreement counted: 0.983
#: (0.969 before the first motion was read at least 8 contact time constants after the release,
#: RESEAT_RELEASE_TIME_CONSTANTS; 0.914 before analytical-2d/3d solved the lift-off of a case
#: no sliding fits and said when friction can also hold the body; 0.892 before the stiffer
#: first-motion contacts, noslip and the halved step). By the analysis's first-named class
#: alone: 0.957. Three cases of margin for another platform's MuJoCo build.
MEASURED_SHARE = 0.975
#: Compared cases `jamming` says friction holds that stay held in the simulation: 137 of 148
#: measured, one case of margin for another platform's MuJoCo build.
HELD_MEASURED = 137
MEASURED_HELD = 136

#: Reasons a first motion may differ from the rigid analysis's class for physical reasons: the
#: rigid model has no or a second consistent answer. A force near zero ("at the resolution
#: limit") is not among them: a case is left out for resolution only when the analysis itself
#: reports it unresolved (premise), and none of these scenes' cases is.
PHYSICAL = ("Painlevé", "friction can hold", "second rigid answer")


def physical(why: str) -> bool:
    """Whether a disagreement's reason is physical (not the soft model's, not unexplained)."""
    return why.startswith(PHYSICAL)


def test_a_ramped_load_closes_later_than_a_step() -> None:
    """`profile: ramp` lets the load go when the support backs off and raises it over half a
    phase: the block needs longer to close onto the backed-off support than under the
    constant load (it starts with no push), and still reseats."""
    scene = load_scene(FIXTURES / "planar-block" / "block.kcheck.yaml")
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    mu = scene.friction_range("kinetic")[1]
    step = simulate(scene, mass, 2, mu, SHORT)
    ramp = simulate(scene, mass, 2, mu, ReseatSettings(duration=0.2, profile="ramp"))
    assert step.closed_after is not None and ramp.closed_after is not None
    assert ramp.closed_after > step.closed_after
    assert ramp.seat_error < 1e-6 and step.seat_error < 1e-6


def test_a_block_follows_a_support_backing_off_slowly() -> None:
    """`retraction_time_ms`: the support backs off on a half-cosine over 20 ms instead of
    jumping. The support's largest acceleration, pi² x 100 µm / (2 x (20 ms)²) = 1.2 m/s², is
    below the planar block's towards it, (0.707 N - 0.1 x 0.707 N of friction) / 0.324 kg =
    2.0 m/s², so the block keeps up: its gap there stays within the 1 µm tolerance, where after
    a jump it opens the whole 100 µm. Both reseat; the first motion is `closes` either way."""
    from dataclasses import replace

    scene = load_scene(FIXTURES / "planar-block" / "block.kcheck.yaml")
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    mu = scene.friction_range("kinetic")[1]
    jump = simulate(scene, mass, 2, mu, SHORT)
    slow = simulate(scene, mass, 2, mu, replace(SHORT, retraction_time=0.02))
    assert jump.largest_gaps[2] == pytest.approx(SHORT.retraction, rel=1e-3)
    assert slow.largest_gaps[2] < SHORT.tolerance
    assert slow.closed_after == 0.0  # no gap ever beyond the tolerance in phase 1
    assert jump.first == slow.first == "closes"
    assert slow.seat_error < 1e-6 and jump.seat_error < 1e-6


def test_the_first_motion_is_read_after_a_slow_back_off() -> None:
    """A back-off of 300 ms, longer than the first-motion run's 50 ms window: the window
    grows by the back-off time, so the block's first motion is read once the support has
    backed off and is `closes`, as after a jump (the same block as above: it keeps up with
    the support)."""
    from dataclasses import replace

    from kcheck.analysis.reseat import first_motion_settings

    scene = load_scene(FIXTURES / "planar-block" / "block.kcheck.yaml")
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    mu = scene.friction_range("kinetic")[1]
    slow = first_motion_settings(replace(SHORT, duration=1.0, retraction_time=0.3))
    assert slow.window is not None and slow.window > 0.3
    assert simulate(scene, mass, 2, mu, slow, returns=False).first == "closes"


def test_a_friction_range_is_simulated_at_both_ends(tmp_path: Path, cli_json) -> None:
    """Appendix A with μ from 0.05 to 0.3: every case at both ends; at the high end friction
    holds y1's case (least holding μ 0.124), at the low end every case reseats."""
    path = _fixture_copy(
        tmp_path, "thesis-appendix-a", "friction: 0.1", "friction: {min: 0.05, max: 0.3}"
    )
    with path.open("a", encoding="utf-8") as f:
        f.write("checks:\n  reseat: {duration_s: 0.2}\n")
    code, doc = cli_json(str(path), "--select", "reseat")
    check = doc["scenes"][0]["checks"][0]
    outcomes = {c["retracted"]: c["outcome"] for c in check["cases"]}
    assert set(outcomes) == {f"{s} (μ {e})" for s in ("y1", "y2", "x3") for e in ("low", "high")}
    assert all(outcomes[f"{s} (μ low)"] == "reseats" for s in ("y1", "y2", "x3"))
    assert outcomes["y1 (μ high)"] == "off_seat"
    assert code == 1 and check["status"] == "fail"
    assert check["findings"][0]["field"] == "supports[0]"


def test_a_load_without_a_design_direction_is_skipped_saying_why(cli_json) -> None:
    """Nothing is simulated on a default: a swept load has no one motion (thesis block 4.2)."""
    _, doc = cli_json(str(FIXTURES / "thesis-block-4-2"), "--select", "reseat")
    check = doc["scenes"][0]["checks"][0]
    assert check["status"] == "skipped"
    assert "design direction" in check["message"]


def test_the_first_motion_is_read_with_stiff_contacts(tmp_path: Path) -> None:
    """random-3d-1962 of the agreement scenes, s1 retracted: analytical-3d says s6 loses
    contact. With the check's default 2 ms contacts the lost contact unloads out of its seated
    overlap as slowly as the body moves the window's 10 µm, and that run reads "closes"; the
    check reads the first motion from its stiff run (first_motion_settings: 0.5 ms contacts,
    0.05 ms step, noslip), which sees the loss (docs/validation.md)."""
    from kcheck_checks.reseat import ReseatOptions, settings_of

    from kcheck.analysis import analyse
    from kcheck.analysis.reseat import first_motion_settings

    (path,) = [p for p in generated(tmp_path, 30) if p.name == "random-3d-1962.kcheck.yaml"]
    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    assert analyse(scene, mass).results[0].outcome == "loses_contact"
    settings = settings_of(ReseatOptions())
    mu = scene.friction_range("kinetic")[1]
    soft = simulate(scene, mass, 0, mu, dataclasses.replace(settings, duration=0.05), returns=False)
    stiff = simulate(scene, mass, 0, mu, first_motion_settings(settings), returns=False)
    assert soft.first == "closes"
    assert stiff.first == "loses_contact"
