"""The one colour language of every picture (issue 22): each colour is written here once, with
its meaning, and every picture module takes its colours from here (``tests/kcheck/
test_picture_colours.py`` fails on a colour written anywhere else among the pictures).

A reader learns it once, from the legend picture (:func:`kcheck.pictures.legend.draw_legend`,
shown in ``docs/report.md``), and carries it from one picture to the next:

* green: safe (force directions, bands, closing outcomes, contact stress within its allowable);
* amber: marginal (passes, but closer to its limit than the marginal threshold);
* red: failing (the body opens or turns the wrong way, a forbidden direction, a stress over
  its allowable, the value that decides a failure);
* orange: jamming (friction can hold the body);
* magenta: a support loses contact;
* navy: the design direction (the load's direction: arrow, line or star), always drawn;
* dark grey: the supports (arrows along their normals, their names); where supports must be
  told apart (curves, bars, boundaries), each keeps its own colour of :data:`SUPPORT_CYCLE`
  in every picture.

This module imports nothing heavy: colours are matplotlib colour strings.
"""

from __future__ import annotations

__all__ = [
    "SAFE",
    "MARGINAL",
    "FAILING",
    "JAMMING",
    "LOST_CONTACT",
    "DESIGN",
    "SUPPORT",
    "LANGUAGE",
    "OUTCOME_COLOURS",
    "VERDICT_COLOURS",
    "SUPPORT_CYCLE",
    "outcome_colour",
    "support_colour",
    "status_colour",
]

# --- The language: what a reader must be able to tell apart in every picture. ---
#: Safe: closes, a safe direction or band, within the allowable.
SAFE = "#2ca02c"
#: Marginal: passes, closer to the limit than the marginal threshold.
MARGINAL = "#e6ab02"
#: Failing: opens, wrong sense, forbidden, over the allowable.
FAILING = "#d62728"
#: Jamming: friction can hold the body.
JAMMING = "#ff7f0e"
#: A support loses contact.
LOST_CONTACT = "#c51b8a"
#: The design direction (the load's).
DESIGN = "#1f3b73"
#: Supports: their arrows, points and names.
SUPPORT = "#404040"

#: The language as (colour, name, meaning), in the legend's order.
LANGUAGE: tuple[tuple[str, str, str], ...] = (
    (SAFE, "green", "safe: closes, a safe direction, within the allowable"),
    (MARGINAL, "amber", "marginal: passes, near its limit"),
    (FAILING, "red", "failing: opens, wrong sense, forbidden, over the allowable"),
    (JAMMING, "orange", "jamming: friction can hold the body"),
    (LOST_CONTACT, "magenta", "lost contact: a support would have to pull"),
    (DESIGN, "navy", "design direction (arrow, line or star), pass or fail"),
    (SUPPORT, "dark grey", "supports: arrows along their normals, names"),
)

# --- Shades of the language. ---
#: Pale safe (a ring or band behind stronger marks).
SAFE_PALE = "#cfe8cf"
#: Dark safe (text on a safe area).
SAFE_DARK = "#1a6e1a"
#: Pale jamming: friction holds an opening load.
JAMMING_PALE = "#fdc086"
#: Jamming shade map (how many cases friction can hold), safe shade map (margin).
JAMMING_MAP = "Oranges"
SAFE_MAP = "Greens"
#: A margin from failing (red) through marginal (amber) to safe (green).
MARGIN_MAP = "RdYlGn"
#: Time along a simulated path (the reseat check), early dark to late light.
TIME_MAP = "viridis"

#: Verdict words' colours in titles (the text and HTML reports use the same hues, darker than
#: the fills so that text on white stays legible).
VERDICT_COLOURS = {
    "pass": "#1a7f37",
    "marginal": "#9a7b00",
    "warn": "#9a6700",
    "fail": "#cf222e",
    "error": "#8250df",
}

#: Colours of case outcomes, the same in every picture; any other outcome gets UNKNOWN.
OUTCOME_COLOURS = {
    "closes": SAFE,
    "ok": SAFE,
    "swept": SAFE,
    "marginal": MARGINAL,
    "loses_contact": LOST_CONTACT,
    "opens": FAILING,
    "wrong_sense": FAILING,
    "opens_loses_contact": FAILING,
    "jams": JAMMING,
    "ambiguous": "#8c564b",
}
UNKNOWN_OUTCOME = "#8c564b"

# --- Identity colours: telling supports (and the cases named after them) apart. They avoid
# the language's hues, so that no support's curve reads as safe or failing. ---
SUPPORT_CYCLE = ("#1f77b4", "#9467bd", "#8c564b", "#17becf", "#7f7f7f", "#aec7e8")

# --- Other things drawn. ---
#: A rotation sense a pole needs (Koster's construction).
SENSE_COLOURS = {"ccw": "#1f77b4", "cw": "#9467bd", "translation": "#7f7f7f"}
#: Planes of a direction plot (the stiffness at a point in the xy, xz and yz planes).
PLANE_COLOURS = ("#1f77b4", "#9467bd", "#8c564b")
#: Free motion: screw axis and rotation sense.
MOTION = "#7b2cbf"
#: Gravity's arrow.
GRAVITY = "#6b4226"
#: The scene's friction coefficient or range.
FRICTION_RANGE = "#1f77b4"
#: Best candidate of kcheck suggest (the design is DESIGN).
CANDIDATE = "#1f77b4"
#: The retracted support.
RETRACTED = "#7f7f7f"

# --- Neutrals. ---
INK = "black"
PAPER = "white"
#: The body (fill and outline).
BODY = "0.9"
BODY_EDGE = "0.35"
#: Dark marks: coordinate axes, the hemisphere's rim, the compass.
DARK = "0.2"
#: Muted text and marks (captions, angle rings).
MUTED = "0.35"
#: Faint lines (normal lines, grid-like marks).
FAINT = "0.6"
#: Where nothing is safe or there is no value.
NOTHING = "0.88"
#: Koster's jamming area a support would have to pull in (hatched).
PULL = "0.55"
#: Light grey of points without a value (kcheck suggest).
NO_VALUE = "0.8"
#: Transparent (no fill or no edge).
NONE = "none"


def outcome_colour(outcome: str) -> str:
    """The colour of a case outcome (a colour for any outcome, known or not)."""
    return OUTCOME_COLOURS.get(outcome, UNKNOWN_OUTCOME)


def support_colour(j: int) -> str:
    """Support ``j``'s own colour (by its index in the scene), the same in every picture."""
    return SUPPORT_CYCLE[j % len(SUPPORT_CYCLE)]


def status_colour(word: str) -> str:
    """The colour of a status drawn as a mark or fill: safe, marginal or failing (a warning in
    its title's amber)."""
    return {"pass": SAFE, "marginal": MARGINAL, "fail": FAILING}.get(word, VERDICT_COLOURS["warn"])
