"""Run checks over scene files: discovery, option validation, lazy mass properties, timing.

Nothing a check does not need is computed: mass properties (and so trimesh and every mesh
read) only when an applicable check needs them (``Check.needs_mass_for``), and then once
(through the mass-property cache when one is configured).
:func:`run_batch` yields scene results in the order of the files, whatever runs them (this
process, or worker processes with a time and memory budget per scene, :mod:`kcheck.gate.pool`),
so a report can print each scene as it finishes.
"""

from __future__ import annotations

import dataclasses
import importlib
import time
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import field
from pathlib import Path
from typing import Any

from kcheck.analysis.sanity import scene_warnings
from kcheck.errors import SceneError, SceneErrors
from kcheck.gate.paths import Excluder, discover_paths
from kcheck.plugin import Inputs, LoadedCheck, Options, SampleMap
from kcheck.records import dataclass
from kcheck.result import CheckResult, Finding, MassProperties, SceneResult, Severity, Status
from kcheck.scene import Scene, describe_pydantic, load_scene
from kcheck.scene.yamlio import DEFAULT_LIMITS

__all__ = [
    "Settings",
    "discover",
    "check_scene",
    "check_scenes",
    "check_files",
    "run_batch",
    "scene_status",
]

#: Top-level modules of the `plot` extra: only their absence means "install the extra".
PLOT_EXTRA = ("matplotlib", "networkx")

#: Key of a check's options in a scene that sets the check's severity, not an option.
SEVERITY_KEY = "severity"


@dataclass(frozen=True)
class Settings:
    """How scenes are checked: everything a worker needs besides the file and the checks.

    ``severities`` overrides a check's default severity (from configuration or the command
    line); a scene's own ``checks: {id: {severity: ...}}`` wins over both.
    ``check_options`` are per-check option defaults (from configuration): a scene's own
    options win key by key. ``selected`` names the checks to run (None: every check given
    that runs by default, ``Check.default_selected``, and the opt-in ones a scene names);
    options of the others are still validated, and are no error. ``cache_dir`` holds the
    mass-property cache (None: no cache). ``jobs`` is the number of worker processes (0: run
    in this process), each scene limited to ``timeout_s`` seconds and ``memory_bytes`` of
    address space (None: no limit; limits need workers). ``named``: the checks asked for by
    name (``select``), which run even when opt-in (``Check.default_selected`` False); an
    opt-in check otherwise runs only where the scene's ``checks:`` or ``check_options`` name it.
    ``memo_mass`` keeps mass properties and body surfaces in this process's memory (a study's
    variants). ``hints`` False skips the way-out searches behind failing findings' hints
    (:class:`kcheck.plugin.Inputs`; a study reads verdicts and figures only).
    ``sample_map`` runs the Monte Carlo checks' chunks of samples (:mod:`kcheck.gate.samples`;
    None: in the scene's own process, in turn).
    ``max_file_bytes`` is the largest scene file read (configuration ``max_file_size``),
    ``max_mesh_bytes`` the largest mesh file (``max_mesh_size``); None: the defaults.
    """

    allow_outside: bool = False
    plots: Path | None = None
    severities: Mapping[str, Severity] = field(default_factory=dict)
    check_options: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    selected: frozenset[str] | None = None
    named: frozenset[str] = frozenset()
    cache_dir: Path | None = None
    jobs: int = 0
    timeout_s: float | None = None
    memory_bytes: int | None = None
    max_file_bytes: int | None = None
    max_mesh_bytes: int | None = None
    plot_formats: tuple[str, ...] = ("png",)
    memo_mass: bool = False
    hints: bool = True
    sample_map: SampleMap | None = None


def discover(
    paths: Iterable[Path | str], exclude: Excluder | None = None
) -> tuple[list[Path], list[SceneResult]]:
    """Scene files under the given files and folders (folders recursively, in sorted order),
    each once, and an error result for every path that cannot be used: missing, a dangling
    symlink or a symlink loop, an unreadable folder, a folder without scenes, a path too long.
    Mesh files among ``paths`` are replaced by the scenes that use them, searched for in the
    mesh's repository (:func:`kcheck.gate.paths.scenes_using`). Folders are searched
    passing over what ``exclude`` excludes (default: hidden folders and what git ignores)."""
    from kcheck.gate.paths import scenes_using, search_root

    scenes, meshes, problems = discover_paths(paths, exclude)
    for mesh in meshes:
        for users in scenes_using([mesh], search_root(mesh)).values():
            scenes.extend(users)
    errors = [_error(p.path, f"{p.path}: {p.message}") for p in problems]
    cwd = Path.cwd()
    unique: dict[Path, Path] = {}
    for p in scenes:
        try:
            key = p.resolve()
        except (OSError, RuntimeError):
            key = p.absolute()
        unique.setdefault(key, p)
    found = [k.relative_to(cwd) if k.is_relative_to(cwd) else k for k in unique]
    return found, errors


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
    if only checks of severity ``warning`` failed or the scene has warnings; ``marginal`` if a
    check is marginal and nothing is worse; else ``pass``."""
    if any(c.status is Status.ERROR for c in checks):
        return Status.ERROR
    failed = [c for c in checks if c.status is Status.FAIL]
    if any(c.severity == "error" for c in failed):
        return Status.FAIL
    if failed or warnings:
        return Status.WARN
    if any(c.status is Status.MARGINAL for c in checks):
        return Status.MARGINAL
    return Status.PASS


def _nothing_checked(results: Sequence[CheckResult]) -> tuple[Finding, ...]:
    """A scene on which no check gave a verdict (each was n/a or not checked) is not a pass:
    a warning saying so, so that its status is ``warn`` (never a pass on nothing)."""
    if any(r.status is not Status.SKIPPED for r in results):
        return ()
    which = ", ".join(r.id for r in results) or "no check was selected for it"
    return (
        Finding(
            f"nothing was checked: every check was n/a or not checked ({which})",
            code="nothing-checked",
            hint="give what the checks' n/a lines ask for, or select checks that apply to it",
        ),
    )


def _opted_in(lc: LoadedCheck, scene: Scene, settings: Settings) -> bool:
    """Whether a check runs on a scene as far as opting in goes: every default check; an
    opt-in one when the scene, the configuration or ``select`` names it."""
    name = lc.spec.name
    if lc.check.default_selected:
        return True
    return name in scene.check_options or name in settings.check_options or name in settings.named


def _options(
    scene: Scene, lc: LoadedCheck, defaults: Mapping[str, Any]
) -> tuple[Options, Severity | None]:
    raw = {**defaults, **scene.check_options.get(lc.spec.name, {})}
    severity = raw.pop(SEVERITY_KEY, None)
    if severity is not None and severity not in ("error", "warning"):
        raise scene.error(
            ("checks", lc.spec.name, SEVERITY_KEY),
            f"expected `error` or `warning`, got {severity!r}",
        )
    try:
        return lc.check.options.model_validate(raw), severity
    except Exception as exc:
        # pydantic is imported only where options are validated by it (issue 24)
        from pydantic import ValidationError

        if not isinstance(exc, ValidationError):
            raise
        raise SceneErrors(
            [
                scene.error(where, describe_pydantic({**err, "loc": where}))
                for err in exc.errors(include_url=False)
                for where in [("checks", lc.spec.name, *err["loc"])]
            ]
        ) from None


def _crashed(lc: LoadedCheck, exc: Exception) -> str:
    return f"check {lc.spec.display_name} crashed: {type(exc).__name__}: {exc}"


def _ask(lc: LoadedCheck, scene: Scene) -> tuple[str | None, bool, str | None]:
    """A check's skip reason for a scene, whether it then needs mass properties, and the
    crash message when the plugin raised while answering (that check's error, not the
    scene's: the other checks still run)."""
    try:
        reason = lc.check.skip_reason(scene)
        return reason, reason is None and lc.check.needs_mass_for(scene), None
    except MemoryError:
        raise
    except Exception as exc:
        return None, False, _crashed(lc, exc)


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
    load: Callable[[], Scene] | None = None,
) -> SceneResult:
    """Load one scene and run every check on it; bad input becomes an error result.
    ``load`` builds the scene instead of reading ``path`` (a study's variant,
    :mod:`kcheck.gate.study`); its errors are the scene's, as the file's would be."""
    if settings is None:
        settings = Settings(allow_outside=allow_outside, plots=plots)
    return check_scenes(path, checks, settings, [load])[0]


@dataclass
class _Prepared:
    """A scene read and planned: what its checks run on (:func:`_prepare`)."""

    scene: Scene
    plan: list[Any]
    mass: MassProperties | None
    placement: tuple[Finding, ...]
    unavailable: list[CheckResult]
    elapsed: float  # s, reading and planning it
    results: dict[int, CheckResult] = field(default_factory=dict)  # by plan entry
    inputs: dict[int, Inputs] = field(default_factory=dict)


def check_scenes(
    path: Path,
    checks: Sequence[LoadedCheck],
    settings: Settings,
    loads: Sequence[Callable[[], Scene] | None],
) -> list[SceneResult]:
    """:func:`check_scene` of several scenes (a worker's chunk of a study's variants, each
    built by its ``load``; None reads ``path``): each scene is read and planned alone, then
    every check is given all the scenes it runs on at once (``Check.run_many``, which may
    stack their algebra). Each result is the one :func:`check_scene` gives its scene alone
    (``runtime_s`` aside: a batch's time is shared equally among its scenes)."""
    return _check_many([(path, load) for load in loads], checks, settings)


def check_files(
    paths: Sequence[Path], checks: Sequence[LoadedCheck], settings: Settings
) -> list[SceneResult]:
    """:func:`check_scenes` of several scene files (a worker's chunk of ``kcheck check``):
    each result is the one :func:`check_scene` gives its file alone (``runtime_s`` aside)."""
    return _check_many([(path, None) for path in paths], checks, settings)


def _check_many(
    items: Sequence[tuple[Path, Callable[[], Scene] | None]],
    checks: Sequence[LoadedCheck],
    settings: Settings,
) -> list[SceneResult]:
    prepared = [_prepare(path, checks, settings, load) for path, load in items]
    for lc in checks:
        batch = [
            (p, k)
            for p in prepared
            if isinstance(p, _Prepared)
            for k, entry in enumerate(p.plan)
            if entry[0] is lc and entry[3] is None and entry[5] is None
        ]
        if not batch:
            continue
        inputs = []
        for p, k in batch:
            _, options, _, _, needs_mass, _ = p.plan[k]
            p.inputs[k] = Inputs(
                p.scene, p.mass if needs_mass else None, options, hints=settings.hints
            )
            if settings.sample_map is not None:
                p.inputs[k] = dataclasses.replace(p.inputs[k], sample_map=settings.sample_map)
            inputs.append(p.inputs[k])
        start = time.perf_counter()
        results = _run_many(lc, inputs)
        share = (time.perf_counter() - start) / len(batch)
        for (p, k), result in zip(batch, results, strict=True):
            p.results[k] = dataclasses.replace(result, runtime_s=share)
    return [
        p if isinstance(p, SceneResult) else _finish(path, checks, settings, p)
        for (path, _), p in zip(items, prepared, strict=True)
    ]


def _run_many(lc: LoadedCheck, inputs: list[Inputs]) -> list[CheckResult]:
    """A check's results on several scenes; when the batch raises, each scene alone, so that
    a crash is the result of its own scene only (a crashing check must not take the batch
    down)."""
    try:
        results = list(lc.check.run_many(inputs))
        if len(results) == len(inputs):
            return results
    except MemoryError:
        raise
    except Exception:  # noqa: S110 - told apart scene by scene below
        pass
    out = []
    for one in inputs:
        try:
            out.append(lc.check.run(one))
        except MemoryError:
            raise
        except Exception as exc:
            out.append(CheckResult(lc.spec.name, Status.ERROR, _crashed(lc, exc)))
    return out


def _prepare(
    path: Path,
    checks: Sequence[LoadedCheck],
    settings: Settings,
    load: Callable[[], Scene] | None,
) -> _Prepared | SceneResult:
    """A scene read, its checks' options validated and planned, its mass properties and the
    supports against its mesh; an error result for bad input."""
    from kcheck.gate.config import did_you_mean

    started = time.perf_counter()
    try:
        limits = (
            DEFAULT_LIMITS
            if settings.max_file_bytes is None
            else dataclasses.replace(DEFAULT_LIMITS, max_bytes=settings.max_file_bytes)
        )
        scene = (
            load_scene(path, allow_outside=settings.allow_outside, limits=limits)
            if load is None
            else load()
        )
        known = {lc.spec.name for lc in checks}
        wrong: list[SceneError] = []  # every check's options' errors, said together
        for check_id in scene.check_options:
            if check_id not in known:
                wrong.append(
                    scene.error(
                        ("checks", check_id),
                        f"options for unknown check `{check_id}`"
                        f"{did_you_mean(check_id, known)}; installed: {', '.join(sorted(known))}",
                    )
                )
        plan = []
        unavailable: list[CheckResult] = []  # opt-in checks a scene asks for that cannot run
        for lc in checks:
            defaults = settings.check_options.get(lc.spec.name, {})
            try:
                options, severity = _options(scene, lc, defaults)
            except SceneError as exc:
                wrong.extend(exc.all())
                continue
            if settings.selected is not None and lc.spec.name not in settings.selected:
                continue  # its options are valid; it just does not run
            if not _opted_in(lc, scene, settings):
                continue  # an opt-in check nobody asked for: not run, not listed
            missing = lc.check.missing_extra()
            if missing is not None:  # asked for by the scene, its extra absent: not checked
                unavailable.append(
                    CheckResult(lc.spec.name, Status.SKIPPED, f"not checked: {missing}")
                )
                continue
            severity = severity or settings.severities.get(lc.spec.name) or lc.check.severity
            plan.append((lc, options, severity, *_ask(lc, scene)))
        if wrong:
            raise SceneErrors(sorted(wrong, key=lambda e: (e.line or 0, e.column or 0)))
        from kcheck.body.mass import shared_meshes

        with shared_meshes():  # mass properties and the supports' check read each mesh once
            mass, placement = _matter(scene, plan, settings)
    except SceneError as exc:
        return _input_error(path, exc)
    except MemoryError:
        raise  # a budget, not a bug: the batch reports it (run_batch)
    except Exception as exc:  # a bug must not take the batch down or print a traceback
        message = (
            f"{path}: internal error while reading the scene "
            f"({type(exc).__name__}: {exc}); please report it"
        )
        return _error(path, message, (Finding(message, code=BUDGET_CODES["crashed"]),))
    return _Prepared(scene, plan, mass, placement, unavailable, time.perf_counter() - started)


def _finish(
    path: Path, checks: Sequence[LoadedCheck], settings: Settings, prepared: _Prepared
) -> SceneResult:
    """A planned scene's result from its checks' results: skipped and crashed-on-asking
    checks, findings located, the scene's warnings and status, its pictures."""
    started = time.perf_counter()
    scene, mass = prepared.scene, prepared.mass
    results = list(prepared.unavailable)
    written: list[str] = []
    drawn: list[tuple[LoadedCheck, Inputs, CheckResult]] = []
    notes = scene.notes
    for k, (lc, _, severity, reason, _, crash) in enumerate(prepared.plan):
        if crash is not None:
            results.append(CheckResult(lc.spec.name, Status.ERROR, crash, severity=severity))
            continue
        if reason is not None:
            results.append(CheckResult(lc.spec.name, Status.SKIPPED, reason, severity=severity))
            continue
        result = dataclasses.replace(
            prepared.results[k],
            severity=severity,
            findings=_locate(scene, prepared.results[k].findings),
        )
        results.append(result)
        drawn.append((lc, prepared.inputs[k], result))
    if prepared.unavailable:  # in the checks' order, as the others
        order = {lc.spec.name: k for k, lc in enumerate(checks)}
        results.sort(key=lambda r: order.get(r.id, len(order)))
    warnings = _locate(
        scene,
        (*prepared.placement, *scene_warnings(scene, mass, results), *_nothing_checked(results)),
    )
    status = scene_status(results, warnings)
    # Pictures after every check, so that each title carries the scene's verdict too.
    for lc, inputs, result in drawn if settings.plots is not None else ():
        if result.status in (Status.PASS, Status.MARGINAL, Status.FAIL):
            files, note = _plot(lc, inputs, result, settings, (status, results, warnings))
            notes = notes if note is None else (*notes, note)
            written.extend(str(f) for f in files)
    return SceneResult(
        path=str(path),
        status=status,
        name=scene.name,
        kind=scene.kind,
        mass_properties=mass,
        checks=tuple(results),
        notes=notes + (mass.notes if mass is not None else ()),
        plots=tuple(written),
        units=scene.units,
        runtime_s=prepared.elapsed
        + sum(r.runtime_s or 0.0 for r in prepared.results.values())
        + time.perf_counter()
        - started,
        warnings=warnings,
        supports=tuple(s.to_json() for s in scene.supports),
        # The scene's own plane: planar scenes, or a `sweep:` entry (a spatial check that
        # chooses a plane of its own reports it in its `sweep_plane`).
        sweep=(tuple(scene.sweep.normal.tolist()), tuple(scene.sweep.e1.tolist()))
        if scene.kind == "planar" or scene.sweep.given
        else None,
    )


def _matter(
    scene: Scene, plan: list[Any], settings: Settings
) -> tuple[MassProperties | None, tuple[Finding, ...]]:
    """The body's mass properties when a check needs them (through the cache), and the
    supports checked against its mesh (:func:`_placement`)."""
    from kcheck.gate.cache import body_mass_properties_cached

    key = _body_key(scene, settings)  # hashed once: mass properties, surface, placement
    mass = None
    if any(needs_mass for *_, needs_mass, _ in plan):
        if scene.body is None:
            raise scene.error(
                ("body",),
                "a check needs the body's mass properties; "
                "give `body` with a mesh or explicit mass properties",
            )
        try:
            mass = body_mass_properties_cached(
                scene.body,
                scene.scale,
                settings.cache_dir,
                settings.max_mesh_bytes,
                memo=settings.memo_mass,
                key=key,
            )
        except SceneError as exc:
            where = exc.where or ("body",)
            raise scene.error(where, f"{exc.path}: {exc.message}") from exc
        from kcheck.body.mass import body_limits_problem

        problem = body_limits_problem(mass)
        if problem is not None:
            raise scene.error(("body",), problem)
    placement = _placement(scene, settings, key)
    return mass, placement


def _body_key(scene: Scene, settings: Settings) -> str | None:
    """The body's cache key (:func:`kcheck.gate.cache.body_key`) when something is cached
    (the cache folder, or ``memo_mass``); None otherwise, or when its meshes cannot be keyed
    (too large, unreadable: the computations then report why, as without a cache)."""
    if (settings.cache_dir is None and not settings.memo_mass) or scene.body is None:
        return None
    if not scene.body.parts:
        return None
    from kcheck.gate.cache import mesh_body_key

    try:
        return mesh_body_key(scene.body, scene.scale, settings.max_mesh_bytes)
    except SceneError:
        return None


def _placement(scene: Scene, settings: Settings, key: str | None = None) -> tuple[Finding, ...]:
    """The supports against the body's mesh (:mod:`kcheck.analysis.placement`): raises the
    errors (a support off the body, a normal pointing out of it) as input errors; returns the
    warnings (where the mesh cannot tell). With a cache folder and the body's ``key``, the
    warnings of a placement without errors are stored there
    (:class:`kcheck.gate.cache.PlacementCache`): a warm run reads no mesh for them."""
    if scene.body is None or not scene.body.parts:
        return ()
    from kcheck.analysis.placement import support_placement
    from kcheck.body.surface import body_surface
    from kcheck.gate.cache import PlacementCache, placement_key

    cache = None
    if key is not None and settings.cache_dir is not None:
        cache = (PlacementCache(settings.cache_dir), placement_key(key, scene))
        hit = cache[0].get(cache[1])
        if hit is not None:
            return hit
    try:
        surface = _surface(scene, settings, key) if settings.memo_mass else None
        if surface is None:
            surface = body_surface(scene.body, settings.max_mesh_bytes)
    except SceneError as exc:
        where = exc.where or ("body",)
        raise scene.error(where, f"{exc.path}: {exc.message}") from exc
    if surface is None:
        return ()
    found = support_placement(scene, surface)
    if found.errors:
        raise SceneErrors(
            [
                scene.error(f.field or ("supports",), f.message + (f"; {f.hint}" if f.hint else ""))
                for f in found.errors
            ]
        )
    if cache is not None:
        cache[0].put(cache[1], found.warnings)
    return found.warnings


#: Body surfaces built in this process, by body key (and mesh size limit): a study's variants
#: of one body read and place its meshes once (as their mass properties, ``memo_mass``).
_SURFACES: dict[tuple[str, int | None], Any] = {}


def _surface(scene: Scene, settings: Settings, body: str | None) -> Any:
    """The body's surface through :data:`_SURFACES`, by the body's key ``body`` (None: its
    meshes cannot be keyed; the caller builds it and reports why)."""
    from kcheck.body.surface import body_surface
    from kcheck.gate.cache import MEMO_ENTRIES

    assert scene.body is not None
    if body is None:
        return None
    key = (body, settings.max_mesh_bytes)
    if key not in _SURFACES:
        if len(_SURFACES) >= MEMO_ENTRIES:
            _SURFACES.pop(next(iter(_SURFACES)))
        _SURFACES[key] = body_surface(scene.body, settings.max_mesh_bytes)
    return _SURFACES[key]


#: Codes of the error results of a scene whose worker ran out of a budget, died or crashed:
#: the rule ids the CI formats report them under (:mod:`kcheck.report.issues`), apart from
#: ``input-error``.
BUDGET_CODES = {
    "time": "budget-exceeded/time",
    "memory": "budget-exceeded/memory",
    "died": "worker-died",
    "crashed": "internal-error",
}


def _budget_error(path: Path, outcome: Any, settings: Settings) -> SceneResult:
    """The error result of a scene whose worker ran out of a budget or died, under its own
    code (:data:`BUDGET_CODES`), not an input error's."""
    message = _budget_message(path, outcome, settings)
    return _error(path, message, (Finding(message, code=BUDGET_CODES.get(outcome.kind)),))


def _budget_message(path: Path, outcome: Any, settings: Settings) -> str:
    """What happened to a scene whose worker ran out of a budget or died."""
    memory = (
        "the memory available"
        if settings.memory_bytes is None
        else f"its memory budget of {settings.memory_bytes / 2**20:g} MiB"
    )
    raise_it = (
        "; the batch went on without it (raise the budget with {} if the scene is meant "
        "to be this large)"
    )
    if outcome.kind == "time":
        text = f"exceeded its time budget of {settings.timeout_s:g} s" + raise_it.format(
            "--timeout (configuration `timeout`)"
        )
    elif outcome.kind == "memory":
        text = f"exceeded {memory}" + raise_it.format(
            "--memory-limit (configuration `memory_limit`)"
        )
    elif outcome.kind == "crashed":
        return f"{path}: internal error ({outcome.detail}); please report it"
    else:
        text = f"stopped: {outcome.detail}"
        if settings.memory_bytes is not None:
            text += f", most likely past {memory}"
        text += "; the batch went on without it"
    return f"{path}: checking this scene {text}"


def _plot(
    lc: LoadedCheck,
    inputs: Inputs,
    result: CheckResult,
    settings: Settings,
    scene: tuple[Status, Sequence[CheckResult], Sequence[Finding]],
) -> tuple[Sequence[Path], str | None]:
    """A check's pictures, or none and a note saying why: a picture never stops a batch.
    ``scene``: the scene's verdict, every check's result and the scene's warnings, which the
    pictures' titles state beside the check's own verdict."""
    from kcheck.pictures.plotting import formats, scene_verdict

    assert settings.plots is not None
    try:
        with formats(settings.plot_formats), scene_verdict(*scene):
            return lc.check.plot(inputs, result, settings.plots), None
    except ModuleNotFoundError as exc:
        if (exc.name or "").split(".")[0] not in PLOT_EXTRA:
            return (), f"pictures of {lc.spec.name} failed (ModuleNotFoundError: {exc})"
        return (), f"pictures need the plot extra: pip install 'kcheck[plot]' ({exc})"
    except Exception as exc:  # a picture must not take the batch down
        return (), f"pictures of {lc.spec.name} failed ({type(exc).__name__}: {exc})"


def run_batch(
    files: Sequence[Path],
    checks: Sequence[LoadedCheck],
    settings: Settings,
    tick: Callable[[], None] | None = None,
) -> Iterator[SceneResult]:
    """Check scene files, yielding each result as soon as it and every earlier file are done,
    in the order of the files.

    With ``settings.jobs`` > 0 (and on Linux) scenes run in that many worker processes, each
    given a few consecutive files at once (:func:`chunk_size`, :func:`check_files`), each
    scene within the time and memory budget of ``settings``; a scene that exceeds one is an
    error result naming the budget, and the batch goes on: a chunk that exceeds one scene's
    budget is checked again file by file, each with its own budget
    (:func:`kcheck.gate.pool.run_chunks_in_workers`). Otherwise they run here, in turn.
    ``tick`` is called now and then while workers run (:func:`kcheck.gate.pool.run_in_workers`).
    """
    from kcheck.gate import pool

    if settings.jobs < 1 or not files or not pool.available():
        for path in files:
            try:
                yield check_scene(path, checks, settings=settings)
            except MemoryError:
                yield _budget_error(path, pool.BudgetExceeded("memory", ""), settings)
        return

    def work(chunk: Sequence[Path]) -> list[SceneResult]:
        return check_files(chunk, checks, settings)

    for name in WORKER_MODULES + (HINT_MODULES if settings.hints else ()):
        importlib.import_module(name)  # once here, before the forks (WORKER_MODULES)

    # Workers that draw pictures grow (matplotlib's caches): recycled past a threshold.
    recycle = pool.RECYCLE_RSS_BYTES if settings.plots is not None else None
    if recycle is not None:
        # Imported once here, before the forks: a recycled worker starts with matplotlib and
        # its font list loaded instead of loading them again.
        import matplotlib.figure  # noqa: F401
        from matplotlib.backends import backend_agg  # noqa: F401
    budget = pool.Budget(settings.timeout_s, settings.memory_bytes, recycle)
    outcomes = pool.run_chunks_in_workers(
        files,
        work,
        jobs=settings.jobs,
        budget=budget,
        chunk=chunk_size(len(files), settings.jobs),
        tick=tick,
    )
    for path, outcome in zip(files, outcomes, strict=True):
        if isinstance(outcome, pool.BudgetExceeded):
            yield _budget_error(path, outcome, settings)
        else:
            yield outcome


#: Modules a worker imports for nearly every scene it checks, imported once by
#: :func:`run_batch` before the workers are forked: the mass-property cache (every scene), the
#: body's mass properties and the check of their units (every scene with a body); with
#: :data:`HINT_MODULES` when ``Settings.hints``. Light modules (numpy and kcheck's own), each
#: imported in a scene's process anyway: in a forked worker an import costs about three times
#: as much as here (its first writes to the import system's pages it shares with this process
#: copy them; issue 24: about 2 ms of a one-scene run), and every worker of a batch paid it
#: again.
WORKER_MODULES = (
    "kcheck.gate.cache",
    "kcheck.body.mass",
    "kcheck.analysis.mass_units",
)

#: Imported with :data:`WORKER_MODULES` when ``Settings.hints``: the ways out that failing
#: findings' hints search (the analytical checks).
HINT_MODULES = ("kcheck.analysis.way_out",)

#: Most scene files a worker is given at once (:func:`chunk_size`).
CHUNK_SCENES = 8


def chunk_size(files: int, jobs: int) -> int:
    """How many scene files a worker checks at once: up to :data:`CHUNK_SCENES` (the checks'
    ``run_many`` batches, one message each way), but small enough that every worker gets
    about four chunks or more (results stream and the workers end together); 1 for small
    batches."""
    return max(1, min(CHUNK_SCENES, files // (4 * max(jobs, 1))))
