"""The marginal band shared by every check with a continuous margin (docs/checks.md,
"Marginal results"): a pass closer to its failure line than the check's minimum margin is
``marginal``, with one finding saying which margin, how large, and what it needs.

Each result that has such a margin reports it under ``details["margin"]``: the quantity, its
value, the limit and whether the value must be ``at least`` or ``at most`` the limit.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Literal

from kcheck.errors import FieldPath
from kcheck.result import CheckResult, Finding, Status

__all__ = ["MARGINAL_CODE", "with_margin", "with_angle_margin"]

#: The code of a marginal finding (SARIF rule ``<check>/marginal``).
MARGINAL_CODE = "marginal"


def with_margin(
    result: CheckResult,
    quantity: str,
    value: float,
    limit: float,
    sense: Literal["at least", "at most"],
    message: str,
    *,
    hint: str | None = None,
    field: FieldPath | None = None,
) -> CheckResult:
    """``result`` with its margin recorded, and, when it passes with ``value`` on the wrong
    side of ``limit``, made ``marginal`` with a finding ``message``.

    ``quantity`` names the margin (``force-angle margin``); ``sense`` says which side of the
    limit is comfortable. A non-finite value (no case can be held, no force) is comfortable.
    """
    details = dict(result.details)
    details["margin"] = {
        "quantity": quantity,
        "value": value,
        "limit": limit,
        "sense": sense,
    }
    short = (value < limit) if sense == "at least" else (value > limit)
    if result.status is not Status.PASS or not math.isfinite(value) or not short:
        return dataclasses.replace(result, details=details)
    finding = Finding(message, code=MARGINAL_CODE, field=field, hint=hint)
    return dataclasses.replace(
        result,
        status=Status.MARGINAL,
        message=f"{result.message}; marginal: {message}",
        details=details,
        findings=(*result.findings, finding),
    )


def with_angle_margin(
    result: CheckResult,
    marginal_deg: float,
    field: FieldPath | None = None,
    *,
    gravity: bool = False,
) -> CheckResult:
    """The force-angle band of the analytical and graphical checks: the design direction's
    margin (``design_margin_deg``), or, with no design direction, the most robust direction's
    (``robust_margin_deg``), against ``marginal_deg``; the result unchanged without either.
    ``gravity``: the swept direction is gravity's (the advice then cannot be to turn it)."""
    from kcheck.fmt import format_angle

    details = result.details
    if isinstance(details.get("design_margin_deg"), (int, float)):
        value, what = float(details["design_margin_deg"]), "the design direction"
    elif isinstance(details.get("robust_margin_deg"), (int, float)):
        value, what = float(details["robust_margin_deg"]), "even the most robust direction"
    else:
        return result
    message = (
        f"{what} is only {format_angle(value)} from the edge of the safe directions, less than "
        f"the {marginal_deg:g}° minimum margin (load-direction and friction scatter)"
    )
    change = (
        "move the supports to widen the safe gravity directions around the installed one"
        if gravity
        else "turn the force further into the safe directions, or move the supports to widen them"
    )
    hint = f"{change} (the option `marginal_deg` sets the band)"
    return with_margin(
        result,
        "force-angle margin",
        value,
        marginal_deg,
        "at least",
        message,
        hint=hint,
        field=field,
    )
