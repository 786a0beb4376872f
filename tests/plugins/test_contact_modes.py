"""The contact-mode enumeration of the issue 26 evidence (tests/plugins/contact_modes.py) on
the agreement test's two "held, yet the simulation moves" cases: it must find random-3d-3391
s4's known second answer (docs/validation.md; the same motion as
kcheck.mechanics.second_answer's, checked here independently), and it finds no motion
beside rest for random-3d-1667 s1."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.plugins.contact_modes import S, T, case, enumerate_modes
from tests.plugins.reseat_agreement import generated


@pytest.mark.slow
def test_enumerated_modes_of_the_two_held_cases_that_move(tmp_path: Path) -> None:
    paths = {p.name: p for p in generated(tmp_path, 100)}
    names, g = case(paths, "random-3d-3391.kcheck.yaml", "s4")
    found, solved, _ = enumerate_modes(g)
    assert solved > 10**6
    # s1 and s6 stick (remaining order s1 s2 s3 s5 s6), the others separate
    sticking = [m for m in found if m.types == (T, S, S, S, T)]
    assert len(sticking) == 1
    a = sticking[0].acceleration
    # independently: s1 and s6 do not accelerate, s2, s3 and s5 separate
    normal = g.rows_n @ a
    assert np.abs(normal[[0, 4]]).max() <= 1e-9 * g.scale
    assert np.abs(g.rows_t[[0, 4]] @ a).max() <= 1e-9 * g.scale
    assert np.all(normal[1:4] > 0)
    # every other mode found is the same motion
    assert all(np.allclose(m.acceleration, a, atol=1e-9 * g.scale) for m in found)
    _, g = case(paths, "random-3d-1667.kcheck.yaml", "s1")
    found, _, _ = enumerate_modes(g)
    assert found == []
