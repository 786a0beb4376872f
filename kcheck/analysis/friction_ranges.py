"""The analytical checks over a range of kinetic friction: a case passes only if it closes for
every coefficient in the range (:mod:`kcheck.mechanics.friction_range` decides that exactly).

Per case at the design direction: whether it closes throughout, the coefficients of the range
where it does not (exact intervals: roots of the Cramer numerators and effective masses), and
the **worst** coefficient — where the design direction's angular margin at that coefficient
alone is smallest (inside: the distance to the nearest boundary; outside: minus the largest
violation of one condition). The margin is a closed form in ``t`` per condition; its minimum
is found on 257 Chebyshev–Lobatto points and refined by golden-section search between the
neighbours of the best one. The case is then reported (outcome, forces, acceleration,
friction intervals) as analysed at its worst coefficient.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import field, replace

import numpy as np

from kcheck.analysis.cases import Analysis, analyse_fixed, intervals_json, sweep_ranges
from kcheck.mechanics.arcs import ArcSet
from kcheck.mechanics.dynamics import Case, Problem
from kcheck.mechanics.friction_range import FrictionPath, RangeCase, range_arcs, range_cases
from kcheck.numerics import chebyshev as cheb
from kcheck.numerics.thresholds import GOLDEN_XTOL
from kcheck.records import dataclass
from kcheck.result import MassProperties
from kcheck.scene import Scene

__all__ = [
    "coefficients_used",
    "range_details",
    "RangeInfo",
    "analyse_range",
    "design_margins",
    "failing_intervals",
    "bounded_intervals",
    "Bounded",
    "worst_parameter",
]

GRID = 257
GOLDEN = 0.5 * (np.sqrt(5.0) - 1.0)


def design_margins(rc: RangeCase, direction: np.ndarray | None, x: np.ndarray) -> np.ndarray:
    """The design direction's angular margin (rad) at points ``x`` (m,) of the path, closed
    form per condition: ``arccos(-P / |Q|) - arccos(Q . d / |Q|)``, least over the unknowns;
    ``-pi`` where the case is Painlevé-type. Without a direction (the fixed wrench alone): the
    least unknown relative to its own size, a sign and not an angle."""
    if not rc.trusted:
        return np.full(len(x), -np.pi)
    p = cheb.values(rc.numerators[:, 0], x)  # (n, m)
    if direction is None:
        size = np.abs(rc.numerators[:, 0]).sum(axis=1, keepdims=True)
        value = (p / np.where(size > 0, size, 1.0)).min(axis=0)
    else:
        q = np.moveaxis(cheb.values(rc.numerators[:, 1:], x), 1, 2)  # (n, m, dim)
        norm = np.linalg.norm(q, axis=2)
        along = q @ direction
        with np.errstate(all="ignore"):
            radius = np.arccos(np.clip(-p / norm, -1.0, 1.0))
            off = np.arccos(np.clip(along / norm, -1.0, 1.0))
        flat = np.where(p > 0, np.pi, -np.pi)
        value = np.where(norm > 0, radius - off, flat).min(axis=0)
    return np.where(rc.painleve_at(x), -np.pi, value)


@dataclass(frozen=True)
class Bounded:
    """Where a case fails along the path, with how sure that is (``t`` in [0, 1]).

    ``failing``: resolved intervals ``(lo, hi, lo_error, hi_error)``, each end's error bound
    well inside the interval. ``unresolved``: intervals ``(lo, hi, lo_error, hi_error,
    condition)`` whose ends are uncertain by as much as the interval is wide, or where a
    condition comes within its own error bound of zero without crossing it (a sliver rounding
    may hide): neither closing nor failing. ``condition`` is how much the responsible
    condition amplifies rounding (its error bound over ``eps`` times its size).
    """

    failing: tuple[tuple[float, float, float, float], ...]
    unresolved: tuple[tuple[float, float, float, float, float], ...]


def _root_errors(p: np.ndarray, err: float, x: np.ndarray) -> np.ndarray:
    """Error bounds (in x) of roots ``x`` of the series ``p`` whose values err by up to
    ``err``: ``err / |p'|`` at a simple root, ``sqrt(2 err / |p''|)`` where the first-order
    bound is not small against the curvature (a near-double root); 2 (all of [-1, 1]) where
    neither bounds it."""
    d1 = cheb.values(cheb.derivative(p[None])[0], x)
    d2 = cheb.values(cheb.derivative(cheb.derivative(p[None]))[0], x)
    with np.errstate(all="ignore"):
        first = err / np.abs(d1)
        second = np.sqrt(2.0 * err / np.abs(d2))
        out = np.where(np.abs(d1) ** 2 > 4.0 * err * np.abs(d2), first, second)
    return np.where(np.isfinite(out), np.minimum(out, 2.0), 2.0)


def _near_misses(p: np.ndarray, err: float) -> list[tuple[float, float]]:
    """Regions (x) where the series ``p`` comes within ``err`` of zero at a local extremum
    without a root there: a sliver of the other sign may hide within the rounding."""
    critical = cheb.real_roots(cheb.derivative(p[None]))[0]
    critical = np.concatenate([critical[np.isfinite(critical)], [-1.0, 1.0]])
    at = cheb.values(p[None], critical)[0]
    d2 = cheb.values(cheb.derivative(cheb.derivative(p[None]))[0], critical)
    out = []
    for c, value, curve in zip(critical, at, d2, strict=True):
        if abs(value) > err:
            continue
        with np.errstate(all="ignore"):
            half = float(np.sqrt(2.0 * (err + abs(value)) / abs(curve))) if curve else 2.0
        half = min(half if np.isfinite(half) else 2.0, 2.0)
        out.append((max(-1.0, c - half), min(1.0, c + half)))
    return out


def bounded_intervals(rc: RangeCase, direction: np.ndarray | None) -> Bounded:
    """:func:`failing_intervals` with each end's error bound, and the unresolved intervals
    (:class:`Bounded`): the roots' errors come from the series' error bounds
    (:meth:`kcheck.mechanics.friction_range.RangeCase.condition_errors`)."""
    from kcheck.numerics.thresholds import EPS

    if not rc.trusted:
        return Bounded((), ((0.0, 1.0, 0.5, 0.5, float("inf")),))
    d = None if direction is None else np.atleast_2d(direction)
    series = np.concatenate([rc.conditions(d)[0], rc.effective])
    effective_error = np.zeros(2) if rc.effective_error is None else rc.effective_error
    errors = np.concatenate([rc.condition_errors(d)[0], effective_error])
    roots = cheb.real_roots(series)
    found: dict[float, tuple[float, float]] = {}  # root -> (error, condition)
    hidden: list[tuple[float, float, float]] = []  # near misses: lo, hi, condition
    for p, err, row in zip(series, errors, roots, strict=True):
        size = float(cheb.abs_bound(p))
        condition = float(err / (EPS * size)) if size > 0 else float("inf")
        row = row[np.isfinite(row)]
        for r, e in zip(row, _root_errors(p, float(err), row), strict=True):
            if r not in found or e > found[r][0]:
                found[float(r)] = (float(e), condition)
        # A double root (found, or split into a complex pair) is a near miss too.
        hidden += [(lo, hi, condition) for lo, hi in _near_misses(p, float(err))]
    edges = np.unique(np.concatenate([[-1.0, 1.0], list(found)]))
    mids = 0.5 * (edges[1:] + edges[:-1])
    ok = rc.closing_at(d, mids)[0]

    def error(x: float) -> tuple[float, float]:
        return found.get(float(x), (0.0, 0.0))

    pieces: list[list[float]] = []
    for lo, hi, good in zip(edges[:-1], edges[1:], ok, strict=True):
        if good:
            continue
        if pieces and pieces[-1][1] == lo:
            pieces[-1][1] = hi
        else:
            pieces.append([lo, hi])
    failing, unresolved = [], []
    for lo, hi in pieces:
        (elo, clo), (ehi, chi) = error(lo), error(hi)
        near = any(a <= hi + ehi and lo - elo <= b for a, b, _ in hidden)
        if hi - lo > elo + ehi and not near:
            failing.append((lo, hi, elo, ehi))
        else:
            unresolved.append((lo, hi, elo, ehi, max(clo, chi)))
    for lo, hi, condition in hidden:
        unresolved.append((lo, hi, 0.0, 0.0, condition))

    def to_t(x: float) -> float:
        return 0.5 * (x + 1.0)

    return Bounded(
        tuple((to_t(a), to_t(b), 0.5 * ea, 0.5 * eb) for a, b, ea, eb in failing),
        tuple((to_t(a), to_t(b), 0.5 * ea, 0.5 * eb, c) for a, b, ea, eb, c in sorted(unresolved)),
    )


def failing_intervals(rc: RangeCase, direction: np.ndarray | None) -> list[tuple[float, float]]:
    """The intervals of ``t`` in [0, 1] where the case does not close at the direction:
    pieces between the roots of every numerator and effective mass, one decision each; only
    the resolved ones (:func:`bounded_intervals` has the unresolved and the ends' errors)."""
    return [(lo, hi) for lo, hi, _, _ in bounded_intervals(rc, direction).failing]


def worst_parameter(
    rc: RangeCase, direction: np.ndarray | None, failing: Sequence[tuple[float, float]] = ()
) -> tuple[float, float]:
    """The ``t`` in [0, 1] where the design direction's margin (:func:`design_margins`) is
    least, and that margin (rad). With ``failing`` intervals the search keeps to them, so the
    worst coefficient is one where the case does not close."""
    x = cheb.lobatto(GRID)
    if failing:
        inside = np.zeros(len(x), bool)
        for lo, hi in failing:
            inside |= (x >= 2 * lo - 1) & (x <= 2 * hi - 1)
        mids = np.array([lo + hi - 1.0 for lo, hi in failing])  # midpoints, in x
        x = np.unique(np.concatenate([x[inside], mids]))
    m = design_margins(rc, direction, x)
    best = int(np.argmin(m))
    lo, hi = x[max(best - 1, 0)], x[min(best + 1, len(x) - 1)]
    if failing:
        piece = next(((a, b) for a, b in failing if 2 * a - 1 <= x[best] <= 2 * b - 1), None)
        if piece is not None:
            lo, hi = max(lo, 2 * piece[0] - 1), min(hi, 2 * piece[1] - 1)
    xb, mb = _golden(rc, direction, lo, hi, float(x[best]), float(m[best]))
    return 0.5 * (xb + 1.0), mb


def _golden(
    rc: RangeCase, direction: np.ndarray | None, lo: float, hi: float, x0: float, m0: float
) -> tuple[float, float]:
    """Golden-section search for the least margin in [lo, hi]; never worse than ``x0``."""
    a, b = lo, hi
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = (float(v) for v in design_margins(rc, direction, np.array([c, d])))
    for _ in range(60):
        if b - a < GOLDEN_XTOL:
            break
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = float(design_margins(rc, direction, np.array([c]))[0])
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = float(design_margins(rc, direction, np.array([d]))[0])
    x, m = (c, fc) if fc < fd else (d, fd)
    return (x, m) if m < m0 else (x0, m0)


@dataclass(frozen=True)
class RangeInfo:
    """What holds over a kinetic friction range: the path, each case's polynomial form (for
    the load's direction swept), and per case at the design direction whether it closes
    throughout, where it fails and its worst coefficient (``t`` and margin, rad)."""

    path: FrictionPath
    problem: Problem
    cases: tuple[Case, ...]
    range_cases: tuple[RangeCase | None, ...]
    closes: tuple[bool | None, ...] = ()
    failing: tuple[tuple[tuple[float, float], ...], ...] = ()
    worst: tuple[tuple[float, float] | None, ...] = ()
    angular: bool = True  # whether the margins are angles (a design direction)
    bounded: tuple[Bounded | None, ...] = ()
    _arcs: dict[tuple[int, bytes], ArcSet] = field(default_factory=dict, compare=False)

    def mu(self, t: float) -> float:
        """The reference support's coefficient at ``t``."""
        return float(self.path.mu(t))

    def arcs(self, r: int, e1: np.ndarray, e2: np.ndarray) -> ArcSet:
        """Angles (rad) in the plane ``(e1, e2)`` where case ``r`` closes throughout."""
        key = (r, np.concatenate([e1, e2]).tobytes())
        if key not in self._arcs:
            rc = self.range_cases[r]
            self._arcs[key] = () if rc is None else range_arcs(rc, e1, e2)[0]
        return self._arcs[key]

    def for_wrench(self, b0: np.ndarray, big_b: np.ndarray) -> tuple[RangeCase | None, ...]:
        """The cases' polynomial forms for another swept wrench ``b0 + B d`` (gravity)."""
        return tuple(range_cases(self.problem, self.cases, self.path, rhs=(b0, big_b)))

    def mu_error(self, dt: float) -> float:
        """An error of ``t`` as an error of the reference support's coefficient."""
        return float(dt * abs(self.mu(1.0) - self.mu(0.0)))

    def summary(self, r: int) -> dict[str, object]:
        """The case's ``friction_range`` details (coefficients of the reference support)."""
        out: dict[str, object] = {
            "min": self.mu(0.0),
            "max": self.mu(1.0),
        }
        bounded = self.bounded[r] if r < len(self.bounded) else None
        if bounded is not None:
            out["fails_for_error"] = [
                [self.mu_error(ea), self.mu_error(eb)] for _, _, ea, eb in bounded.failing
            ]
            if bounded.unresolved:
                out["closes_throughout"] = None
                out["unresolved"] = [
                    {
                        "mu": [self.mu(a), self.mu(b)],
                        "error": [self.mu_error(ea), self.mu_error(eb)],
                        "condition": c,
                    }
                    for a, b, ea, eb, c in bounded.unresolved
                ]
        if r < len(self.closes) and self.closes[r] is not None:
            out["closes_throughout"] = bool(self.closes[r])
            worst = self.worst[r]
            if worst is not None:
                out["worst_mu"] = self.mu(worst[0])
                if self.angular:
                    out["worst_margin_deg"] = float(np.degrees(worst[1]))
            out["fails_for"] = intervals_json(
                tuple((self.mu(a), self.mu(b)) for a, b in self.failing[r])
            )
        if not self.path.uniform():
            out["reference"] = self.problem.names[self.path.reference]
        return out


def analyse_range(
    scene: Scene,
    mass: MassProperties,
    low: np.ndarray,
    high: np.ndarray,
    plane: tuple[np.ndarray, np.ndarray] | None = None,
) -> Analysis:
    """:func:`kcheck.analysis.cases.analyse_fixed` when the kinetic coefficients run from ``low`` to
    ``high`` (k,): every case must close for every coefficient of the range."""
    path = FrictionPath(np.asarray(low, float), np.asarray(high, float))
    top = analyse_fixed(scene, mass, plane, friction=path.high)
    problem, cases = top.problem, top.cases
    rcs = tuple(range_cases(problem, cases, path))
    load = scene.load
    sweeping = load is not None and load.magnitude > 0
    evaluate = top.design is not None or not sweeping
    results, friction = list(top.results), list(top.friction)
    closes: list[bool | None] = [None] * len(cases)
    failing: list[tuple[tuple[float, float], ...]] = [()] * len(cases)
    worst: list[tuple[float, float] | None] = [None] * len(cases)
    bounded: list[Bounded | None] = [None] * len(cases)
    at_worst: dict[float, Analysis] = {}
    for r, rc in enumerate(rcs):
        if (
            rc is None
            or not evaluate
            or top.results[r].outcome
            in (
                "undetermined",
                "ill_conditioned",
            )
        ):
            continue
        bounded[r] = found = bounded_intervals(rc, top.design)
        failing[r] = tuple((lo, hi) for lo, hi, _, _ in found.failing)
        # Unresolved slivers (and nothing that surely fails): neither closing nor failing.
        undecided = bool(found.unresolved) and not failing[r]
        closes[r] = None if undecided else bool(rc.closes(top.design)[0]) and not failing[r]
        worst[r] = worst_parameter(rc, top.design, failing[r])
        t = worst[r][0]  # type: ignore[index]
        if t not in at_worst:
            at_worst[t] = analyse_fixed(scene, mass, plane, friction=path.at(t))
        results[r], friction[r] = at_worst[t].results[r], at_worst[t].friction[r]
    info = RangeInfo(
        path,
        problem,
        cases,
        rcs,
        tuple(closes),
        tuple(failing),
        tuple(worst),
        top.design is not None,
        tuple(bounded),
    )
    results = [
        replace(res, details={**res.details, "friction_range": info.summary(r)})
        if rcs[r] is not None
        else res
        for r, res in enumerate(results)
    ]
    for r, held in enumerate(bounded):
        if held is not None and closes[r] is None:
            # Neither closing nor failing can be said: no trustworthy answer (issue 21).
            where = ", ".join(
                f"μ {info.mu(a):.6g}–{info.mu(b):.6g}" for a, b, *_ in held.unresolved
            )
            diagnostic = (
                f"unresolved near {where}: the conditions come within their rounding error of "
                "zero there (a degenerate case), so whether it closes for every coefficient "
                "of the range cannot be decided in double precision"
            )
            results[r] = replace(
                results[r],
                outcome="ill_conditioned",
                details={**results[r].details, "diagnostic": diagnostic},
            )
    analysis = replace(top, results=tuple(results), friction=tuple(friction), friction_range=info)
    if not sweeping or analysis.plane is None:
        return analysis
    return sweep_ranges(analysis, *analysis.plane)


def range_details(scene: Scene, analysis: Analysis) -> dict[str, object] | None:
    """The check-level ``friction_range``: the kinetic coefficients used (of the reference
    support), and over a range whether every case closes throughout and the worst coefficient
    and margin over all cases; None for plain coefficients."""
    info = analysis.friction_range
    if not isinstance(info, RangeInfo):
        return coefficients_used(scene, "kinetic")
    out: dict[str, object] = {"kind": "kinetic", "min": info.mu(0.0), "max": info.mu(1.0)}
    decided = [r for r, c in enumerate(info.closes) if c is not None]
    unresolved = [
        analysis.problem.names[r]
        for r, b in enumerate(info.bounded)
        if b is not None and b.unresolved and info.closes[r] is None
    ]
    if unresolved:
        # Not "closes throughout": these cases are too close to a degenerate system to say.
        out["unresolved_cases"] = unresolved
    if decided:
        out["closes_throughout"] = (
            None
            if unresolved and all(info.closes[r] for r in decided)
            else all(info.closes[r] for r in decided)
        )
        worst = min(
            (r for r in decided if info.worst[r] is not None),
            key=lambda r: info.worst[r][1],  # type: ignore[index]
            default=None,
        )
        if worst is not None:
            t, margin = info.worst[worst]  # type: ignore[misc]
            out["worst_mu"] = info.mu(t)
            out["worst_case"] = analysis.problem.names[worst]
            if info.angular:
                out["worst_margin_deg"] = float(np.degrees(margin))
    if not info.path.uniform():
        out["reference"] = analysis.problem.names[info.path.reference]
    return out


def coefficients_used(scene: Scene, kind: str) -> dict[str, object] | None:
    """Which coefficients a check used when the scene's friction is more than one number:
    ``{kind, min, max}`` of the support with the largest (static or kinetic) coefficient; None
    for plain coefficients."""
    if all(s.coefficients.plain for s in scene.supports):
        return None
    low, high = scene.friction_range(kind)  # type: ignore[arg-type]
    top = int(np.argmax(high))
    out: dict[str, object] = {"kind": kind, "min": float(low[top]), "max": float(high[top])}
    if len(scene.supports) and (np.ptp(low) > 0 or np.ptp(high) > 0):
        out["reference"] = scene.supports[top].name
    return out
