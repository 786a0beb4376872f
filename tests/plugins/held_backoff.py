"""Held uniquely, slow back-off: do the compared cases `jamming` says friction holds uniquely
stay held when the retracted support backs off slowly (option ``retraction_time_ms``, a
half-cosine) instead of jumping? (docs/validation.md, "Held uniquely, slow back-off" and
"Held uniquely, a reading for slow back-offs": each run is also read as before that reading,
``from_seat``.)

The cases are selected as the agreement test selects them (tests/plugins/test_reseat.py:
``premise`` on the jump's first-motion run, ``held_at`` and ``held_alternatives`` as in
``compare_scene``), without that comparison's extra runs (stiffer contacts, ``rigid_motion``),
which only explain cases that move. Each selected case is then simulated once per back-off
time at the first-motion settings (``first_motion_settings``: its window opens when the support
has backed off).

Run (niced; the whole in-sample set takes minutes of CPU)::

    PYTHONPATH=.:plugins nice -n 10 python -m tests.plugins.held_backoff sample
    PYTHONPATH=.:plugins nice -n 10 python -m tests.plugins.held_backoff 27
    PYTHONPATH=.:plugins nice -n 10 python -m tests.plugins.held_backoff 28 0.175 0.25  # times, s
    PYTHONPATH=.:plugins nice -n 10 python -m tests.plugins.held_backoff sample half 0.1 0.2
"""

from __future__ import annotations

import json
import math
import sys
import tempfile
from collections.abc import Iterator, Sequence
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
from kcheck.numerics.thresholds import (
    RESEAT_BACKOFF_SHARE,
    RESEAT_JAM_FACTOR,
    RESEAT_WINDOW_SHARE,
)
from kcheck.result import MassProperties
from kcheck.scene import Scene, load_scene
from tests.conftest import FIXTURES
from tests.plugins.reseat_agreement import FIRST_MOTION, Compared, _pressed, generated, unresolved

#: Back-off times (s) measured beside the jump (0).
BACK_OFFS = (0.0, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 1.5, 2.0)
#: The agreement test's fixtures (tests/plugins/test_reseat.py), before its generated scenes.
SAMPLE_FIXTURES = (
    FIXTURES / "planar-block" / "block.kcheck.yaml",
    FIXTURES / "thesis-appendix-a" / "block.kcheck.yaml",
    FIXTURES / "maxwell-three-vee" / "coupling.kcheck.yaml",
)


@dataclass(frozen=True)
class HeldCase:
    scene: str
    retracted: str
    analytical: str
    # the simulated first-motion class at each back-off time (BACK_OFFS order)
    simulated: tuple[str, ...]
    # the same runs read as before the slow back-off's own reading: held when no contact point
    # moved RESEAT_WINDOW_SHARE of the retraction from the seat within the window + back-off
    from_seat: tuple[str, ...] = ()


#: The time step's divisor for a convergence set (``half`` on the command line: 2).
STEP_DIVISOR = [1]


def back_off_settings(seconds: float) -> ReseatSettings:
    """The first-motion run's settings with the support backing off over ``seconds`` (the
    phase at least twice as long, as the check's options require: RESEAT_BACKOFF_SHARE)."""
    if seconds == 0.0:
        settings = FIRST_MOTION
    else:
        duration = max(ReseatSettings().duration, seconds / RESEAT_BACKOFF_SHARE)
        settings = first_motion_settings(
            replace(ReseatSettings(), retraction_time=seconds, duration=duration)
        )
    return replace(settings, time_step=settings.time_step / STEP_DIVISOR[0])


def held_from_seat(run: ReseatRun, scene: Scene, mass: MassProperties, seconds: float) -> bool:
    """The former reading of a slow back-off: no contact point moved RESEAT_WINDOW_SHARE of the
    retraction from the seat within RESEAT_JAM_FACTOR free-body times plus the back-off time
    (the creep during the back-off counted against the window's distance)."""
    settings = back_off_settings(seconds)
    phase1 = run.trace.time >= 0.0
    time, contact = run.trace.time[phase1], run.trace.contacts[phase1]
    accel = np.linalg.norm(_wrench(scene, mass.center_of_mass, 1.0)[:3]) / mass.mass
    accel += np.linalg.norm(scene.gravity[: scene.dim])
    reach = RESEAT_WINDOW_SHARE * settings.retraction
    limit = RESEAT_JAM_FACTOR * math.sqrt(2 * reach / accel) + seconds
    moved = np.max(np.linalg.norm(contact - contact[0], axis=2), axis=1)
    return not bool(np.any((moved >= reach) & (time - time[0] <= limit)))


def back_off_class(path: Path, retracted: str, seconds: float) -> str:
    """The simulated first-motion class of one case (the support named ``retracted``) with the
    support backing off over ``seconds``."""
    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    r = [s.name for s in scene.supports].index(retracted)
    mu = scene.friction_range("kinetic")[1]
    return simulate(scene, mass, r, mu, back_off_settings(seconds), returns=False).first


def held_uniquely(path: Path, times: Sequence[float] = BACK_OFFS) -> Iterator[HeldCase]:
    """Every compared case of one scene `jamming` says friction holds uniquely, simulated at
    each back-off time."""
    from tests.plugins.test_reseat import premise

    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    analysis = analyse(scene, mass)
    statics, swept, design = jam_statics(scene, mass)
    if design is None:
        return
    jams = analyse_jamming(statics, swept, design)
    mu = scene.friction_range("kinetic")[1]
    for r, result in enumerate(analysis.results):
        if not held_at(jams, jams.cases[r], design, statics.friction):
            continue
        may_hold = bool(result.details.get("friction_may_hold"))
        if may_hold or held_alternatives(scene, mass, [(r, jams.cases[r].keep)])[r] is not None:
            continue
        jump = simulate(scene, mass, r, mu, FIRST_MOTION, returns=False)  # selects the cases
        c = Compared(
            path.name,
            result.retracted,
            result.outcome,
            jump.first,
            True,
            None,
            float(mu.max()),
            jump.settle_speed,
            _pressed(jump.seat_forces),
            unresolved(result),
            may_hold,
        )
        if premise(c) is not None:
            continue
        runs = [
            jump
            if t == 0.0 and STEP_DIVISOR[0] == 1
            else simulate(scene, mass, r, mu, back_off_settings(t), returns=False)
            for t in times
        ]
        yield HeldCase(
            path.name,
            result.retracted,
            result.outcome,
            tuple(run.first for run in runs),
            tuple(
                "jams" if held_from_seat(run, scene, mass, t) else "moves"
                for run, t in zip(runs, times, strict=True)
            ),
        )


def scenes(which: str, folder: Path) -> list[Path]:
    """``sample``: the agreement test's scenes (3 fixtures, seed 26); a number: that seed's."""
    if which == "sample":
        return [*SAMPLE_FIXTURES, *generated(folder, 100)]
    return generated(folder, 100, seed=int(which))


def main(argv: Sequence[str]) -> None:
    which = argv[0]
    if argv[1:2] == ["half"]:  # the same cases at half the first-motion time step
        STEP_DIVISOR[0] = 2
        argv = [which, *argv[2:]]
    label = which if STEP_DIVISOR[0] == 1 else f"{which} (half step)"
    times = tuple(float(t) for t in argv[1:]) or BACK_OFFS
    rows: list[HeldCase] = []
    with tempfile.TemporaryDirectory() as d:
        for path in scenes(which, Path(d)):
            for row in held_uniquely(path, times):
                rows.append(row)
                print(json.dumps(row.__dict__), flush=True)
    for i, t in enumerate(times):
        held = sum(r.simulated[i] == "jams" for r in rows)
        moving = [
            f"{r.scene} {r.retracted}: {r.simulated[i]}" for r in rows if r.simulated[i] != "jams"
        ]
        agree = sum(r.simulated[i] == r.analytical for r in rows)
        seat = [f"{r.scene} {r.retracted}" for r in rows if r.from_seat[i] != "jams"]
        print(
            f"{label} back-off {t * 1e3:g} ms: held uniquely {len(rows)}, stay held {held}, "
            f"first motion = analytical class {agree}; moving: {moving}; "
            f"read from the seat, held {len(rows) - len(seat)}, moving: {seat}",
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:])
