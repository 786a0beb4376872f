"""An example third-party kcheck check: every friction coefficient at most ``max_mu``."""

from __future__ import annotations

from pydantic import Field

from kcheck.plugin import Check, Inputs, Options
from kcheck.result import CaseResult, CheckResult, Status


class CeilingOptions(Options):
    """Options of ``friction-ceiling``."""

    max_mu: float = Field(0.2, ge=0)


class FrictionCeiling(Check):
    """Fails when a support's Coulomb coefficient exceeds ``max_mu``."""

    id = "friction-ceiling"
    summary = "every support's friction coefficient is at most max_mu"
    applies_to = "every scene"
    options = CeilingOptions

    def run(self, inputs: Inputs) -> CheckResult:
        """Compare each support's coefficient with the ceiling."""
        limit = inputs.options.max_mu  # type: ignore[attr-defined]
        cases = tuple(
            CaseResult(
                s.name,
                "ok" if s.friction <= limit else "too_high",
                details={"friction": s.friction},
            )
            for s in inputs.scene.supports
        )
        bad = [c.retracted for c in cases if c.outcome != "ok"]
        status = Status.FAIL if bad else Status.PASS
        return CheckResult(self.id, status, f"above {limit}: {bad}" if bad else "ok", cases=cases)
