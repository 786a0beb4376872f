"""The pictures of ``kcheck study``: each figure against each parameter, and the verdicts
over the first two parameters (the pass map). They take the table as plain columns, so the
study engine stays above them."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from kcheck.pictures import colours as palette
from kcheck.pictures.plotting import figure, save, slug

__all__ = ["draw_study"]


def _numbers(values: Sequence[Any]) -> np.ndarray:
    out = np.full(len(values), math.nan)
    for i, v in enumerate(values):
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out[i] = float(v)
    return out


def _status_colours(status: Sequence[Any]) -> list[str]:
    return [palette.status_colour(str(s)) if s != "error" else palette.NO_VALUE for s in status]


def draw_study(
    title: str,
    table: Mapping[str, Sequence[Any]],
    parameters: Sequence[str],
    figures: Sequence[str],
    directory: Path,
) -> list[Path]:
    """Write ``figure-vs-parameter`` pictures (points coloured by verdict: green pass, the
    report's amber for marginal, red fail, grey error) and, with two numeric parameters
    or more, the pass map of the first two. Return the files written."""
    written: list[Path] = []
    status = list(table["status"])
    colours = _status_colours(status)
    numeric = [p for p in parameters if np.isfinite(_numbers(table[p])).any()]
    for f in figures:
        y = _numbers(table[f])
        if not np.isfinite(y).any() or not numeric:
            continue
        fig = figure(figsize=(4.2 * len(numeric), 3.8))
        for k, p in enumerate(numeric):
            ax = fig.add_subplot(1, len(numeric), k + 1)
            x = _numbers(table[p])
            ok = np.isfinite(x) & np.isfinite(y)
            ax.scatter(x[ok], y[ok], s=10, c=[c for c, o in zip(colours, ok, strict=True) if o])
            ax.set_xlabel(p)
            ax.set_ylabel(f)
            ax.grid(True, alpha=0.3)
        fig.suptitle(f"{title}: {f} against each parameter (colour: verdict)", fontsize=10)
        written.extend(save(fig, directory, slug(f"study-{f}")))
    if len(numeric) >= 2:
        p, q = numeric[:2]
        fig = figure(figsize=(6.0, 5.0))
        ax = fig.add_subplot(1, 1, 1)
        ax.scatter(_numbers(table[p]), _numbers(table[q]), s=40, c=colours, marker="s")
        ax.set_xlabel(p)
        ax.set_ylabel(q)
        n = len(status)
        passed = sum(s in ("pass", "marginal") for s in status)
        ax.set_title(
            f"{title}: pass map, {passed}/{n} pass or marginal\n"
            "(green pass, amber marginal, red fail, grey error)",
            fontsize=10,
        )
        written.extend(save(fig, directory, slug(f"study-pass-map-{p}-{q}")))
    return written
