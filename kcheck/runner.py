"""Run checks over scene files: discovery, option validation, lazy mass properties, timing.

Nothing a check does not need is computed: mass properties (and so trimesh and every mesh
read) only when an applicable check needs them (``Check.needs_mass_for``), and then once.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Iterable, Sequence
from pathlib import Path

from pydantic import ValidationError

from kcheck.errors import SceneError
from kcheck.plugin import Inputs, LoadedCheck, Options
from kcheck.result import CheckResult, SceneResult, Status
from kcheck.scene import SCENE_GLOB, Scene, _describe_pydantic, load_scene

__all__ = ["discover", "check_scene", "scene_status"]


def discover(paths: Iterable[Path | str]) -> tuple[list[Path], list[SceneResult]]:
    """Scene files under the given files and folders (folders recursively), sorted, and an
    error result for every path that does not exist or holds no scene."""
    found: list[Path] = []
    errors: list[SceneResult] = []
    for raw in paths:
        path = Path(raw)
        if path.is_dir():
            scenes = sorted(p for p in path.rglob(SCENE_GLOB) if p.is_file())
            if not scenes:
                errors.append(_error(path, f"{path}: no {SCENE_GLOB} files found in this folder"))
            found.extend(scenes)
        elif path.is_file():
            found.append(path)
        else:
            errors.append(_error(path, f"{path}: no such file or folder"))
    unique = list(dict.fromkeys(p.resolve() for p in found))
    cwd = Path.cwd()
    return [p.relative_to(cwd) if p.is_relative_to(cwd) else p for p in unique], errors


def _error(path: Path, message: str) -> SceneResult:
    return SceneResult(path=str(path), status=Status.ERROR, error=message)


def scene_status(checks: Sequence[CheckResult]) -> Status:
    """A scene errs if a check erred, fails if one failed, and passes otherwise."""
    states = {c.status for c in checks}
    if Status.ERROR in states:
        return Status.ERROR
    if Status.FAIL in states:
        return Status.FAIL
    return Status.PASS


def _options(scene: Scene, lc: LoadedCheck) -> Options:
    raw = scene.check_options.get(lc.spec.name, {})
    try:
        return lc.check.options.model_validate(raw)
    except ValidationError as exc:
        err = exc.errors(include_url=False)[0]
        where = ("checks", lc.spec.name, *err["loc"])
        raise scene.error(where, _describe_pydantic(err)) from None


def check_scene(
    path: Path,
    checks: Sequence[LoadedCheck],
    *,
    allow_outside: bool = False,
    plots: Path | None = None,
) -> SceneResult:
    """Load one scene and run every check on it; bad input becomes an error result."""
    from kcheck.mass import body_mass_properties

    try:
        scene = load_scene(path, allow_outside=allow_outside)
        known = {lc.spec.name for lc in checks}
        for check_id in scene.check_options:
            if check_id not in known:
                raise scene.error(
                    ("checks", check_id),
                    f"options for unknown check `{check_id}`; "
                    f"installed: {', '.join(sorted(known))}",
                )
        plan = []
        for lc in checks:
            options = _options(scene, lc)
            plan.append((lc, options, lc.check.skip_reason(scene)))
        mass = None
        if any(reason is None and lc.check.needs_mass_for(scene) for lc, _, reason in plan):
            if scene.body is None:
                raise scene.error(
                    ("body",),
                    "a check needs the body's mass properties; "
                    "give `body` with a mesh or explicit mass properties",
                )
            try:
                mass = body_mass_properties(scene.body, scene.scale)
            except SceneError as exc:
                where = exc.where or ("body",)
                raise SceneError(
                    scene.path, f"{exc.path}: {exc.message}", field=where, line=scene.line_of(where)
                ) from exc
    except SceneError as exc:
        return SceneResult(path=str(path), status=Status.ERROR, error=str(exc))
    except Exception as exc:  # a bug must not take the batch down or print a traceback
        return SceneResult(
            path=str(path),
            status=Status.ERROR,
            error=f"{path}: internal error while reading the scene "
            f"({type(exc).__name__}: {exc}); please report it",
        )

    results = []
    written: list[str] = []
    for lc, options, reason in plan:
        if reason is not None:
            results.append(CheckResult(lc.spec.name, Status.SKIPPED, reason))
            continue
        inputs = Inputs(scene, mass if lc.check.needs_mass_for(scene) else None, options)
        start = time.perf_counter()
        try:
            result = lc.check.run(inputs)
        except Exception as exc:  # a crashing check must not take the batch down
            result = CheckResult(
                lc.spec.name,
                Status.ERROR,
                f"check {lc.spec.display_name} crashed: {type(exc).__name__}: {exc}",
            )
        result = dataclasses.replace(result, runtime_s=time.perf_counter() - start)
        results.append(result)
        if plots is not None and result.status in (Status.PASS, Status.FAIL):
            try:
                files = lc.check.plot(inputs, result, plots)
            except ImportError as exc:
                files = ()
                scene = dataclasses.replace(
                    scene, notes=(*scene.notes, f"plots need the `plot` extra ({exc})")
                )
            written.extend(str(f) for f in files)
    return SceneResult(
        path=str(path),
        status=scene_status(results),
        name=scene.name,
        kind=scene.kind,
        mass_properties=mass,
        checks=tuple(results),
        notes=scene.notes + (mass.notes if mass is not None else ()),
        plots=tuple(written),
    )
