"""The verdict words of every built-in picture's title, in one place.

Each title carries its check's verdict (``PASS``, ``MARGINAL``, ``WARN``, ``FAIL``) with its
margin, and, where the scene's verdict is worse, that verdict and why: the words come from
:func:`kcheck.report.views.status_text` and :func:`~kcheck.report.views.scene_status_text`, fed
the same result objects the text report uses; nothing is computed again.
"""

from __future__ import annotations

from kcheck.pictures.colours import INK, VERDICT_COLOURS
from kcheck.pictures.plotting import current_scene
from kcheck.report.views import scene_status_text, status_text, verdict, worse
from kcheck.result import CheckResult

__all__ = ["verdict_title", "verdict_colour"]


def verdict_title(result: CheckResult, qualifier: str = "") -> str:
    """``graphical-2d PASS (mass-free), margin 7.59°``, and on a second line, when the scene
    is worse, ``scene FAIL: analytical-2d FAIL — ...``."""
    text = status_text(result, qualifier)
    scene = current_scene()
    if scene is not None:
        worse_scene = scene_status_text(result, scene.word, scene.checks, scene.warnings)
        if worse_scene is not None:
            text += f"\n{worse_scene}"
    return text


def verdict_colour(result: CheckResult) -> str:
    """The title's colour: the worse of the check's verdict and the scene's."""
    word = verdict(result)
    scene = current_scene()
    if scene is not None and worse(scene.word, word):
        word = scene.word
    return VERDICT_COLOURS.get(word, INK)
