"""Whether a body friction can hold is held uniquely: the rigid model's second answer
(:mod:`kcheck.mechanics.second_answer`) for the cases the `jamming` check says friction holds,
at the load's design direction (or the fixed wrench alone: weight, torque, preloads), with the
supports' kinetic coefficients (the upper ends of their ranges) for the motion."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from kcheck.analysis.cases import load_design, problem_for
from kcheck.mechanics.second_answer import Body, second_answers
from kcheck.result import MassProperties
from kcheck.scene import Scene

__all__ = ["held_alternatives"]


def held_alternatives(
    scene: Scene, mass: MassProperties, cases: Sequence[tuple[int, np.ndarray | Sequence[int]]]
) -> dict[int, list[str] | None]:
    """For each case ``(retracted, kept)`` (support indices), the supports the second answer's
    motion separates from (an empty list: it slides on every kept one), or None when the
    search finds no motion beside rest."""
    problem = problem_for(scene, mass)
    wrench = problem.wrench(load_design(scene, problem.dim)[1])
    keeps = [np.asarray(kept, dtype=int) for _, kept in cases]
    body = Body(
        problem.points, problem.normals, problem.friction, problem.com, problem.inertia, wrench
    )
    answers = second_answers(
        body,
        [
            ((problem.points[r], problem.normals[r]), keep)
            for (r, _), keep in zip(cases, keeps, strict=True)
        ],
    )
    return {
        r: None if answer is None else [problem.names[int(j)] for j in keep[answer.lifted]]
        for (r, _), keep, answer in zip(cases, keeps, answers, strict=True)
    }
