"""Run checks over scene files: discovery, option validation, lazy mass properties, timing.

Nothing a check does not need is computed: mass properties (and so trimesh and every mesh
read) only when an applicable check needs them (``Check.needs_mass_for``), and then once.
:func:`run_batch` yields scene results in the order of the files, whatever runs them, so a
report can print each scene as it finishes.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from pydantic import ValidationError

from kcheck.errors import SceneError
from kcheck.plugin import Inputs, LoadedCheck, Options
from kcheck.result import CheckResult, Finding, SceneResult, Severity, Status
from kcheck.scene import SCENE_GLOB, Scene, _describe_pydantic, load_scene

__all__ = ["Settings", "discover", "check_scene", "run_batch", "scene_status"]

#: Key of a check's options in a scene that sets the check's severity, not an option.
SEVERITY_KEY = "severity"


@dataclass(frozen=True)
class Settings:
    """How scenes are checked: everything a worker needs besides the file and the checks.

    ``severities`` overrides a check's default severity (from configuration or the command
    line); a scene's own ``checks: {id: {severity: ...}}`` wins over both.
    """

    allow_outside: bool = False
    plots: Path | None = None
    severities: Mapping[str, Severity] = field(default_factory=dict)
    plot_formats: tuple[str, ...] = ("png",)


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


def _error(path: Path, message: str, errors: tuple[Finding, ...] = ()) -> SceneResult:
    return SceneResult(
        path=str(path),
        status=Status.ERROR,
        error=message,
        errors=errors or (Finding(message),),
    )


def _input_error(path: Path, exc: SceneError) -> SceneResult:
    """An error result listing every input error of the file, each located."""
    findings = tuple(
        Finding(e.message, field=e.where or _field(e.field), line=e.line, column=e.column)
        for e in exc.all()
    )
    return _error(path, str(exc.all()[0]), findings)


def _field(text: str | None) -> tuple[str, ...] | None:
    """A field given as text (``supports[2].normal``) as a one-part field path."""
    return None if not text else (text,)


def scene_status(checks: Sequence[CheckResult], warnings: Sequence[Finding] = ()) -> Status:
    """``error`` if a check erred; ``fail`` if a check of severity ``error`` failed; ``warn``
    if only checks of severity ``warning`` failed or the scene has warnings; else ``pass``."""
    if any(c.status is Status.ERROR for c in checks):
        return Status.ERROR
    failed = [c for c in checks if c.status is Status.FAIL]
    if any(c.severity == "error" for c in failed):
        return Status.FAIL
    if failed or warnings:
        return Status.WARN
    return Status.PASS


def _options(scene: Scene, lc: LoadedCheck) -> tuple[Options, Severity | None]:
    raw = dict(scene.check_options.get(lc.spec.name, {}))
    severity = raw.pop(SEVERITY_KEY, None)
    if severity is not None and severity not in ("error", "warning"):
        raise scene.error(
            ("checks", lc.spec.name, SEVERITY_KEY),
            f"expected `error` or `warning`, got {severity!r}",
        )
    try:
        return lc.check.options.model_validate(raw), severity
    except ValidationError as exc:
        err = exc.errors(include_url=False)[0]
        where = ("checks", lc.spec.name, *err["loc"])
        raise scene.error(where, _describe_pydantic(err)) from None


def _locate(scene: Scene, findings: Sequence[Finding]) -> tuple[Finding, ...]:
    """Findings with the line of their field in the scene file filled in."""
    return tuple(
        dataclasses.replace(f, line=scene.line_of(f.field))
        if f.field is not None and f.line is None
        else f
        for f in findings
    )


def check_scene(
    path: Path,
    checks: Sequence[LoadedCheck],
    *,
    allow_outside: bool = False,
    plots: Path | None = None,
    settings: Settings | None = None,
) -> SceneResult:
    """Load one scene and run every check on it; bad input becomes an error result."""
    from kcheck.mass import body_mass_properties

    if settings is None:
        settings = Settings(allow_outside=allow_outside, plots=plots)
    started = time.perf_counter()
    try:
        scene = load_scene(path, allow_outside=settings.allow_outside)
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
            options, severity = _options(scene, lc)
            severity = severity or settings.severities.get(lc.spec.name) or lc.check.severity
            plan.append((lc, options, severity, lc.check.skip_reason(scene)))
        mass = None
        if any(reason is None and lc.check.needs_mass_for(scene) for lc, _, _, reason in plan):
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
        return _input_error(path, exc)
    except Exception as exc:  # a bug must not take the batch down or print a traceback
        return _error(
            path,
            f"{path}: internal error while reading the scene "
            f"({type(exc).__name__}: {exc}); please report it",
        )

    results = []
    written: list[str] = []
    notes = scene.notes
    for lc, options, severity, reason in plan:
        if reason is not None:
            results.append(CheckResult(lc.spec.name, Status.SKIPPED, reason, severity=severity))
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
        result = dataclasses.replace(
            result,
            runtime_s=time.perf_counter() - start,
            severity=severity,
            findings=_locate(scene, result.findings),
        )
        results.append(result)
        if settings.plots is not None and result.status in (Status.PASS, Status.FAIL):
            files, note = _plot(lc, inputs, result, settings)
            notes = notes if note is None else (*notes, note)
            written.extend(str(f) for f in files)
    return SceneResult(
        path=str(path),
        status=scene_status(results),
        name=scene.name,
        kind=scene.kind,
        mass_properties=mass,
        checks=tuple(results),
        notes=notes + (mass.notes if mass is not None else ()),
        plots=tuple(written),
        units=scene.units,
        runtime_s=time.perf_counter() - started,
        sweep=(tuple(scene.sweep.normal.tolist()), tuple(scene.sweep.e1.tolist())),
    )


def _plot(
    lc: LoadedCheck, inputs: Inputs, result: CheckResult, settings: Settings
) -> tuple[Sequence[Path], str | None]:
    """A check's pictures, or none and a note saying why: a picture never stops a batch."""
    from kcheck.plotting import formats

    assert settings.plots is not None
    try:
        with formats(settings.plot_formats):
            return lc.check.plot(inputs, result, settings.plots), None
    except ImportError as exc:
        return (), f"pictures need the plot extra: pip install 'kcheck[plot]' ({exc})"
    except Exception as exc:  # a picture must not take the batch down
        return (), f"pictures of {lc.spec.name} failed ({type(exc).__name__}: {exc})"


def run_batch(
    files: Sequence[Path], checks: Sequence[LoadedCheck], settings: Settings
) -> Iterator[SceneResult]:
    """Check scene files one after another, yielding each result as it is done, in order."""
    for path in files:
        yield check_scene(path, checks, settings=settings)
