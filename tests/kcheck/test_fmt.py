"""kcheck.fmt's shares: hand-written values, and for shares spread over twelve decades the
written number read back against the true one (two significant digits near 0 and 1)."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.fmt import format_share, format_share_bounds


@pytest.mark.parametrize(
    ("fraction", "text"),
    [
        (0.0, "0%"),
        (1.0, "100%"),
        (0.062, "6.20%"),
        (0.3324, "33.24%"),
        (5.6274704396466154e-05, "0.0056%"),  # the Kelvin clamp's safe share (was "0.01%")
        (0.0009, "0.090%"),
        (0.99999, "99.9990%"),
        (1e-20, "1.0e-18%"),
    ],
)
def test_share_by_hand(fraction: float, text: str) -> None:
    assert format_share(fraction) == text


def test_a_share_between_0_and_1_is_never_written_as_either() -> None:
    """Reading the text back gives the share to two significant digits of itself, or of what
    it lacks to the whole (relative error at most half a unit of the second digit: 5%)."""
    rng = np.random.default_rng(7)
    small = 10.0 ** rng.uniform(-12, 0, 400)
    for fraction in np.concatenate([small, 1.0 - small[small < 0.5]]):
        text = format_share(float(fraction))
        assert text not in ("0%", "0.00%", "100%", "100.00%")
        percent = float(text.rstrip("%"))
        gap = min(100 * fraction, 100 - 100 * fraction)
        read = min(percent, 100 - percent)
        assert abs(read - gap) <= 0.05 * gap + 1e-9, (fraction, text)


def test_share_bounds() -> None:
    assert format_share_bounds(0.0, 0.0009) == "0%–0.090%"
    assert format_share_bounds(0.59, 0.590001) == "59.00%"
    assert format_share_bounds(0.275, 0.35, 1) == "27.5%–35.0%"
