"""The check protocol and the discovery of checks through the ``kcheck.checks`` entry points.

Built-in checks register in kcheck's own ``pyproject.toml`` exactly as a third-party
distribution would (compare flake8's ``flake8.extension``); the core never names them.
Discovery is two typed steps: find the entry points, then load them.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple

from kcheck.errors import PluginError
from kcheck.plugin.dist_info import EntryPoint, distributions
from kcheck.plugin.options import Field, Options, model_validator
from kcheck.plugin.samples import SampleMap, serial
from kcheck.records import dataclass

if TYPE_CHECKING:
    import importlib.metadata

    from kcheck.result import CheckResult, MassProperties, Severity
    from kcheck.scene import Scene

__all__ = [
    "GROUP",
    "Options",
    "Field",
    "model_validator",
    "Inputs",
    "SampleMap",
    "Check",
    "CheckSpec",
    "LoadedCheck",
    "find_checks",
    "load_checks",
]

GROUP = "kcheck.checks"


@dataclass(frozen=True)
class Inputs:
    """What a check receives: the scene, mass properties if it declared it needs them, and
    its validated options. ``hints`` False: the caller reads only verdicts and figures (a
    study's variants), so a check may skip the searches behind a failing finding's way-out
    hint (the least passing closing force or friction) and what only the hints use (e.g.
    ranges in a plane the check does not report); verdicts and figures are the same.
    ``sample_map``: where a Monte Carlo check runs its chunks of samples
    (:mod:`kcheck.plugin.samples`; default: here, in turn); the answer is the same on any."""

    scene: Scene
    mass: MassProperties | None
    options: Options
    hints: bool = True
    sample_map: SampleMap = serial


class Check:
    """Base class of a check. Subclasses set the class attributes and implement ``run``.

    * ``id``: the check's name, equal to its entry-point name;
    * ``summary``: one line saying what it checks;
    * ``applies_to``: one line saying which scenes it applies to;
    * ``needs_mass``: whether it needs the body's mass properties (only then are meshes read);
      a check whose need depends on the scene overrides ``needs_mass_for``;
    * ``options``: its options, an :class:`Options` subclass (fields declared with
      :func:`Field`; pydantic validates them only when a scene or the configuration sets
      them), or a pydantic model;
    * ``severity``: ``error`` (a failure fails the run) or ``warning`` (shown; fails the run
      only with ``--strict``); scenes and configuration may override it per check;
    * ``default_selected``: False for an opt-in check, which runs only on scenes whose
      ``checks:`` name it, when the configuration gives it options, or when ``--select``
      names it (not even listed otherwise).

    ``run`` returns an immutable :class:`~kcheck.result.CheckResult` and never prints.
    """

    id: ClassVar[str]
    summary: ClassVar[str]
    applies_to: ClassVar[str]
    needs_mass: ClassVar[bool] = False
    options: ClassVar[type[Options]] = Options
    severity: ClassVar[Severity] = "error"
    default_selected: ClassVar[bool] = True
    #: ``"module:function"`` drawing this check's pictures, called as
    #: ``function(check, inputs, result, directory) -> paths``. A string, so that the check's
    #: module never imports its pictures or matplotlib: they are imported only when pictures
    #: are asked for.
    pictures: ClassVar[str | None] = None

    def missing_extra(self) -> str | None:
        """What to install for this check to run here (an optional extra whose packages
        are absent), or None. Asked only of selected checks; the command line stops with it
        (exit 2) before any scene runs."""
        return None

    def skip_reason(self, scene: Scene) -> str | None:
        """Why this check does not apply to a scene, or None when it does."""
        return None

    def needs_mass_for(self, scene: Scene) -> bool:
        """Whether this check needs mass properties for a scene (``needs_mass`` by default).

        The runner computes them once per scene for every check that needs them, and reports
        a bad mesh as an input error of the scene.
        """
        return self.needs_mass

    def run(self, inputs: Inputs) -> CheckResult:
        """Check one scene."""
        raise NotImplementedError

    def run_many(self, inputs: Sequence[Inputs]) -> list[CheckResult]:
        """Check several scenes at once (a worker's chunk: a study's variants); the results,
        in order, are those ``run`` gives each scene. By default one ``run`` after another; a
        check overrides it to share work across the scenes (e.g. their algebra stacked in one
        batch of numpy calls). The runner calls it with every scene of a chunk the check runs
        on; when it raises, the scenes are run one by one, so a crash is its scene's alone."""
        return [self.run(i) for i in inputs]

    def plot(self, inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
        """Write pictures for a result into ``directory``; return their paths.

        By default this draws with the function ``pictures`` names (none without it). A check
        may override it instead.
        """
        if self.pictures is None:
            return ()
        module, _, name = self.pictures.partition(":")
        draw = getattr(importlib.import_module(module), name)
        return draw(self, inputs, result, directory)


class CheckSpec(NamedTuple):
    """A check before loading: its distribution and entry point."""

    package: str
    version: str
    entry_point: EntryPoint | importlib.metadata.EntryPoint

    @property
    def name(self) -> str:
        """The entry point's name, which is the check's id."""
        return self.entry_point.name

    @property
    def display_name(self) -> str:
        """Name for messages: ``package[check]``."""
        return f"{self.package}[{self.name}]"


class LoadedCheck(NamedTuple):
    """A loaded check: its spec and an instance."""

    spec: CheckSpec
    check: Check


def find_checks() -> list[CheckSpec]:
    """Every installed ``kcheck.checks`` entry point, sorted by name for determinism.

    The metadata folders are read directly (:mod:`kcheck.plugin.dist_info`, sparing every run
    the import of :mod:`importlib.metadata`), unless only importlib.metadata can list them."""
    specs: dict[tuple[str, str], CheckSpec] = {}
    dists = distributions()
    if dists is None:
        import importlib.metadata

        for dist in importlib.metadata.distributions():
            for ep in dist.entry_points:
                if ep.group == GROUP:
                    package = dist.metadata["Name"] or "unknown"
                    specs.setdefault((package, ep.name), CheckSpec(package, dist.version, ep))
        return sorted(specs.values(), key=lambda s: (s.name, s.package))
    for folder in dists:
        entries = folder.entry_points(GROUP)
        if not entries:
            continue
        # Its metadata read once for all its checks (start-up, issue 24).
        package, version = folder.name or "unknown", folder.version
        for entry in entries:
            # A distribution seen twice on sys.path (e.g. editable + installed) counts once.
            specs.setdefault((package, entry.name), CheckSpec(package, version, entry))
    return sorted(specs.values(), key=lambda s: (s.name, s.package))


def _load(spec: CheckSpec) -> LoadedCheck:
    try:
        obj = spec.entry_point.load()
    except Exception as exc:
        raise PluginError(
            f"cannot load check plugin {spec.display_name} ({spec.entry_point.value}): "
            f"{type(exc).__name__}: {exc}"
        ) from exc
    if not (isinstance(obj, type) and issubclass(obj, Check)):
        raise PluginError(
            f"check plugin {spec.display_name} points at {spec.entry_point.value}, "
            "which is not a kcheck.plugin.Check subclass"
        )
    for attr in ("id", "summary", "applies_to"):
        if not isinstance(getattr(obj, attr, None), str):
            raise PluginError(f"check plugin {spec.display_name} does not define `{attr}`")
    if obj.id != spec.name:
        raise PluginError(
            f"check plugin {spec.display_name}: class {obj.__name__} has id `{obj.id}` "
            f"but is registered as `{spec.name}`"
        )
    return LoadedCheck(spec, obj())


def load_checks(specs: Sequence[CheckSpec] | None = None) -> list[LoadedCheck]:
    """Load checks; duplicate ids from different distributions are an error naming both."""
    seen: dict[str, CheckSpec] = {}
    loaded = []
    for spec in find_checks() if specs is None else specs:
        if spec.name in seen:
            raise PluginError(
                f"check id `{spec.name}` is registered by both {seen[spec.name].display_name} "
                f"and {spec.display_name}"
            )
        seen[spec.name] = spec
        loaded.append(_load(spec))
    return loaded


def options_schema(checks: Sequence[LoadedCheck]) -> Mapping[str, Any]:
    """JSON Schema fragments of every check's options, keyed by check id."""
    return {lc.spec.name: lc.check.options.model_json_schema() for lc in checks}
