"""Default minimum margins: below them a passing check is ``marginal`` (issue 21).

A check with a continuous margin passes when the margin is above its failure line; a pass
closer to that line than the minimum margin here is reported as ``marginal``, a status of its
own that fails the run only with ``--strict``. These are design rules, not numerical
thresholds (those are in :mod:`kcheck.numerics.thresholds`): each is the default of a check
option (settable per scene under ``checks:`` and in ``[tool.kcheck.checks.<id>]``) and its
engineering reason is written here and in docs/checks.md ("Marginal results"). Setting an
option to its neutral value (0 for angles and probabilities, 1 for ratios, 1 for the
utilisation, 0 for cos θ) switches the band off.

Like :mod:`kcheck.numerics.thresholds`, this module imports nothing.
"""

from __future__ import annotations

__all__ = [
    "MARGINAL_ANGLE_DEG",
    "MARGINAL_FRICTION_RATIO",
    "MARGINAL_UTILISATION",
    "MARGINAL_PASS_PROBABILITY",
    "MARGINAL_COS",
]

#: Force-angle margin (degrees) below which a passing design direction is marginal
#: (``analytical-2d``, ``analytical-3d``, ``graphical-2d``: ``marginal_deg``). Load-direction
#: scatter: a hand, a spring or an actuator mounted to drawing tolerances puts the closing force
#: a few degrees off its design line; friction scatter moves every range end by about
#: ``arctan(Δμ)`` (Δμ = 0.05 is 2.9°). 5° covers both together.
MARGINAL_ANGLE_DEG: float = 5.0

#: Least holding friction over the design friction below which a jam-free design direction is
#: marginal (``jamming``: ``marginal_friction_ratio``, nondimensional). Friction scatter:
#: nominally equal dry contacts differ by ±20–30 % with humidity, surface films and run-in, and
#: friction often rises as seats wear; 1.3 covers a 30 % rise of the design coefficient.
MARGINAL_FRICTION_RATIO: float = 1.3

#: Contact-stress utilisation (peak pressure over the allowable, after the safety factor)
#: above which a passing contact is marginal (``hertz``: ``marginal_utilisation``). Wear and
#: surface roughness concentrate pressure, and seating loads are rarely known better than a
#: factor of two; since the peak pressure grows as the cube root of the force, 0.8 leaves
#: room for 0.8⁻³ ≈ 1.95 times the load.
MARGINAL_UTILISATION: float = 0.8

#: Lower confidence bound of the tolerance pass probability below which a passing
#: ``tolerances`` result is marginal (``marginal_pass_probability``). A coupling made in
#: hundreds should fail in fewer than one in a hundred; a bound below 0.99 also says the
#: sample was too small to show that (100 passing samples bound it only to 0.97 at 95 %).
MARGINAL_PASS_PROBABILITY: float = 0.99

#: Maxwell's cos θ below which a passing layout is marginal (``maxwell``: ``marginal_cos``,
#: default failure line 0.7). Wear and seat misalignment tilt contact normals by a few degrees:
#: arccos 0.75 = 41.4° and arccos 0.7 = 45.6°, so 0.75 leaves about 4° of normal tilt before
#: the criterion fails. (Not higher: common 3-2-1 layouts, kcheck init's among them, sit at
#: cos θ ≈ 0.77 and are sound; Maxwell's criterion is a rule of thumb, severity warning.)
MARGINAL_COS: float = 0.75
