"""The reseat check's reading of the first motion (``first_motion_end``, ``first_motion``) on
synthetic traces: no MuJoCo, every reference from a closed form of the trace drawn here.

The traces: every contact point of a body moves alike, sampled every 0.7 ms; the
retraction is 100 µm, so the window's distance is RESEAT_WINDOW_SHARE x 100 µm = 10 µm and a
slow back-off's bound on the motion while the support backs off is
RESEAT_BACKOFF_MOTION_SHARE x 100 µm = 50 µm."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kcheck.analysis.reseat import ReseatSettings, first_motion, first_motion_end
from kcheck.numerics.thresholds import (
    RESEAT_BACKOFF_MOTION_SHARE,
    RESEAT_JAM_FACTOR,
    RESEAT_RELEASE_TIME_CONSTANTS,
    RESEAT_WINDOW_SHARE,
)

RETRACTION = 1e-4  # m
TIME_CONSTANT = 5e-4  # s, the first-motion run's contacts
ACCEL = 1.0  # m/s², the acceleration scale
DT = 7e-4  # s between samples
WINDOW = 0.05  # s after the back-off
#: Three contact points; the retracted one (0) has its support's normal along +z.
NORMALS = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
REACH = RESEAT_WINDOW_SHARE * RETRACTION
#: The free-body window: RESEAT_JAM_FACTOR x the time to move REACH at ACCEL from rest.
LIMIT = RESEAT_JAM_FACTOR * math.sqrt(2 * REACH / ACCEL)


def _settings(back_off: float) -> ReseatSettings:
    return ReseatSettings(
        retraction=RETRACTION, retraction_time=back_off, time_constant=TIME_CONSTANT
    )


def _trace(back_off: float, path) -> tuple[np.ndarray, np.ndarray]:
    """Sample times (s) over the back-off and the window after it, and contact points (n, 3, 3)
    m all displaced by ``path(t)`` (m) along -z, towards the retracted support."""
    time = np.arange(0.0, back_off + WINDOW + DT / 2, DT)
    shift = np.asarray(path(time), dtype=float)
    contact = np.zeros((len(time), 3, 3))
    contact[:, :, 2] = -shift[:, None]
    return time, contact


def _read(back_off: float, path) -> int | None:
    time, contact = _trace(back_off, path)
    return first_motion_end(time, contact, _settings(back_off), ACCEL)


def _index(t: float) -> int:
    """The first sample at or after ``t`` (s; DT is chosen so that no reference falls on a
    sample)."""
    return math.ceil(t / DT)


def test_the_jump_reads_the_window_from_the_seat() -> None:
    """No back-off (unchanged by the slow back-off's reading): a body creeping at v reaches
    10 µm at 10 µm / v; within the free-body window (LIMIT = 20 x sqrt(2 x 10 µm / 1 m/s²) =
    89 ms) it moves, read there; at half that speed it is held."""
    assert LIMIT == pytest.approx(0.0894, abs=1e-4)
    time = np.arange(0.0, LIMIT + DT / 2, DT)
    contact = np.zeros((len(time), 3, 3))
    for v, expected in ((2 * REACH / LIMIT, _index(LIMIT / 2)), (0.5 * REACH / LIMIT, None)):
        contact[:, :, 2] = -v * time[:, None]
        assert first_motion_end(time, contact, _settings(0.0), ACCEL) == expected


def test_creep_while_the_support_backs_off_slowly_is_held() -> None:
    """A held body creeping at 40 µm/s (soft friction at its limit, random-2d-6567 s1's
    speed) through a 1 s back-off: 40 µm by its end, under the 50 µm bound, and 2 µm in the
    50 ms after it, under the window's 10 µm: held. Read from the seat (the creep of the whole
    back-off counted against the 10 µm) it would move."""
    creep = 40e-6  # m/s
    assert creep * 1.0 < RESEAT_BACKOFF_MOTION_SHARE * RETRACTION
    assert creep * WINDOW < REACH
    assert _read(1.0, lambda t: creep * t) is None
    time, contact = _trace(1.0, lambda t: creep * t)
    moved = np.max(np.linalg.norm(contact - contact[0], axis=2), axis=1)
    assert np.any((moved >= REACH) & (time <= LIMIT + 1.0))  # the former reading


def test_creep_beyond_the_bound_moves() -> None:
    """The same creep through a 2 s back-off: 80 µm, beyond the 50 µm bound, so it moves, read
    where it passed 10 µm (at 0.25 s) but no earlier than the release (2 s + 4 ms)."""
    creep = 40e-6
    release = 2.0 + RESEAT_RELEASE_TIME_CONSTANTS * TIME_CONSTANT
    assert _read(2.0, lambda t: creep * t) == _index(release)


def test_a_body_following_the_support_moves() -> None:
    """A body that follows its support on the half-cosine, d/2 (1 - cos(pi t / T)) over
    T = 0.5 s, and stops with it: it has moved the whole 100 µm while the support backs off
    and nothing after, yet it moves, read at the release (0.5 s + 4 ms); its retracted
    contact point went towards the support with every contact kept: `closes`."""
    back_off = 0.5

    def follow(t: np.ndarray) -> np.ndarray:
        share = np.minimum(t / back_off, 1.0)
        return RETRACTION * 0.5 * (1 - np.cos(np.pi * share))

    release = back_off + RESEAT_RELEASE_TIME_CONSTANTS * TIME_CONSTANT
    end = _read(back_off, follow)
    assert end == _index(release)
    time, contact = _trace(back_off, follow)
    gaps = np.zeros((len(time), 3))
    forces = np.ones((len(time), 3))
    settings = _settings(back_off)
    assert first_motion(time, contact, gaps, forces, NORMALS, 0, settings, ACCEL) == "closes"


def test_a_body_released_at_the_end_of_the_back_off_moves() -> None:
    """A body at rest through a 0.2 s back-off that then accelerates at 1 m/s²: it moves the
    window's 10 µm from where it was at 0.2 s after sqrt(2 x 10 µm / 1 m/s²) = 4.5 ms, read at
    the first sample past that."""
    back_off = 0.2
    start = np.sqrt(2 * REACH / ACCEL)
    end = _read(back_off, lambda t: 0.5 * ACCEL * np.maximum(t - back_off, 0.0) ** 2)
    assert end == _index(back_off + start)
