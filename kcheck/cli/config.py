"""The CI-gate options of ``kcheck check`` and ``kcheck config``, which prints the effective
configuration and where each value came from (default, configuration file, command line)."""

from __future__ import annotations

import argparse
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck.cli.common import ExitCode
from kcheck.errors import UsageError
from kcheck.gate.config import (
    KEYS,
    Config,
    ConfigError,
    cpu_count,
    did_you_mean,
    load_config,
    user_cache_dir,
)
from kcheck.records import dataclass

if TYPE_CHECKING:
    from kcheck.plugin import LoadedCheck
    from kcheck.result import Severity

__all__ = [
    "add_gate_options",
    "add_parser",
    "effective_config",
    "CheckPlan",
    "plan_checks",
    "cache_folder",
    "output_targets",
    "run",
]


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}") from None
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return value


def _memory_budget(text: str) -> float:
    from kcheck.gate.config import memory_budget

    try:
        return memory_budget(_positive_float(text))
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"expected {exc}, got {text!r}") from None


def _jobs(text: str) -> int:
    if text == "auto":
        return 0
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected a number of worker processes or `auto`, got {text!r}"
        ) from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected 0 or more worker processes, got {value}")
    return value


def add_gate_options(parser: argparse.ArgumentParser) -> None:
    """The configuration and CI-gate options (shared by ``check`` and ``config``)."""
    gate = parser.add_argument_group(
        "configuration and CI gate",
        "These override [tool.kcheck] in pyproject.toml or kcheck.toml (found from the "
        "working directory upwards, up to the repository root); kcheck config shows the "
        "result.",
    )
    gate.add_argument("--config", type=Path, metavar="FILE", help="use this configuration file")
    gate.add_argument(
        "--isolated", action="store_true", help="ignore configuration files (defaults only)"
    )
    gate.add_argument(
        "--select",
        metavar="IDS",
        help="comma-separated check ids to run (default: every installed check but the opt-in "
        "ones, e.g. reseat)",
    )
    gate.add_argument("--ignore", metavar="IDS", help="comma-separated check ids not to run")
    gate.add_argument(
        "--fail-on",
        choices=("error", "warning"),
        help="lowest severity of a failed check that fails the run (exit 1; default: error)",
    )
    gate.add_argument(
        "--strict",
        action="store_true",
        help="marginal results, failed checks of severity warning and scene warnings fail "
        "the run too (same as --fail-on warning)",
    )
    gate.add_argument(
        "--output-format",
        action="append",
        metavar="FORMAT:FILE",
        help="also write a report in FORMAT to FILE (- for standard output, in the place "
        "of the --format report); repeatable, e.g. "
        "--output-format sarif:kcheck.sarif --output-format junit:kcheck.xml",
    )
    gate.add_argument(
        "-j",
        "--jobs",
        type=_jobs,
        metavar="N",
        help="worker processes (default: one per core; 1: one worker, no parallelism)",
    )
    gate.add_argument(
        "--timeout",
        type=_positive_float,
        metavar="SECONDS",
        help="time budget of one scene; past it the scene is an error and the batch goes on "
        "(default: 120)",
    )
    gate.add_argument(
        "--memory-limit",
        type=_memory_budget,
        metavar="MIB",
        help="memory (address space) budget of one scene's worker, MiB, at least 512 "
        "(default: 2048)",
    )
    gate.add_argument(
        "--no-cache", action="store_true", help="compute mass properties without the cache"
    )
    gate.add_argument(
        "--cache-dir",
        type=Path,
        metavar="DIR",
        help="mass-property cache folder (default: $KCHECK_CACHE_DIR, else the user cache "
        "folder found by platformdirs: ~/.cache/kcheck on Linux, honouring XDG_CACHE_HOME; "
        "kcheck config shows it)",
    )
    gate.add_argument(
        "--changed-only",
        action="store_true",
        help="check only the scenes a change in git affects (working tree and index against "
        "HEAD, and untracked files): changed scenes, scenes naming a changed, deleted or "
        "renamed mesh, and every scene when the configuration changed",
    )
    gate.add_argument(
        "--since",
        metavar="REF",
        help="like --changed-only, against the merge-base of a git revision and HEAD, as a "
        "pull request is compared (e.g. origin/main)",
    )
    gate.add_argument(
        "--pre-commit",
        action="store_true",
        help="what the pre-commit hook runs: the files given, and every scene that a change "
        "against HEAD affects (as --changed-only), so that a commit passes only when the "
        "full run would",
    )


def _ids(text: str | None) -> tuple[str, ...] | None:
    if text is None:
        return None
    return tuple(s.strip() for s in text.split(","))


def _known_format(config: Config, where: str | None = None) -> None:
    """An unknown report format is a usage error, located at the file's key or ``where``;
    the file's value is checked even where the command line overrides it."""
    from kcheck.report import FORMATS

    name = config["format"]
    if name not in FORMATS:
        raise UsageError(
            f"{where or config.where('format')}: unknown format `{name}`"
            f"{did_you_mean(name, FORMATS)}; known: {', '.join(FORMATS)}"
        )


def effective_config(args: argparse.Namespace) -> Config:
    """The configuration file's values with the command line's on top."""
    config = load_config(args.config, isolated=args.isolated)
    _known_format(config)
    fail_on = "warning" if args.strict else args.fail_on
    cli: dict[str, Any] = {
        "select": _ids(args.select),
        "ignore": _ids(args.ignore),
        "fail_on": fail_on,
        "jobs": args.jobs,
        "output_format": tuple(args.output_format) if args.output_format else None,
        "cache": False if args.no_cache else None,
        "cache_dir": None if args.cache_dir is None else str(args.cache_dir),
        "timeout": args.timeout,
        "memory_limit": args.memory_limit,
        "format": getattr(args, "format", None),
        "allow_outside_paths": True if getattr(args, "allow_outside_paths", False) else None,
    }
    paths = getattr(args, "paths", None)
    if paths and not getattr(args, "pre_commit", False):  # the hook's files come on top
        cli["paths"] = tuple(str(p) for p in paths)
    effective = config.with_overrides(cli)
    _known_format(effective, "--format")
    return effective


@dataclass(frozen=True)
class CheckPlan:
    """Which installed checks run, with the configuration's severities and option defaults."""

    selected: frozenset[str]
    severities: Mapping[str, Severity]
    options: Mapping[str, Mapping[str, Any]]
    #: the checks ``select`` names (they run even when opt-in)
    named: frozenset[str] = frozenset()


def _check_list(config: Config, key: str, known: set[str]) -> tuple[str, ...] | None:
    ids = config[key]
    if ids is None or (key == "ignore" and ids == ()):
        return None
    origin = config.sources[key]
    where = f"--{key}" if origin == "command line" else config.where(key)
    if not ids or not all(ids):
        raise UsageError(
            f"{where}: selects no check (an empty check id); expected comma-separated ids "
            f"from: {', '.join(sorted(known))}"
        )
    for check_id in ids:
        if check_id not in known:
            raise UsageError(
                f"{where}: unknown check `{check_id}`{did_you_mean(check_id, known)}; "
                f"installed: {', '.join(sorted(known))}"
            )
    return ids


def plan_checks(config: Config, checks: Sequence[LoadedCheck]) -> CheckPlan:
    """Validate ``select``/``ignore`` and the per-check tables against the installed checks."""
    by_id = {lc.spec.name: lc for lc in checks}
    known = set(by_id)
    select = _check_list(config, "select", known)
    ignore = _check_list(config, "ignore", known) or ()
    # Every check not ignored may run: an opt-in one (``default_selected`` False) where a
    # scene, the configuration or ``select`` names it (kcheck.gate.runner).
    selected = frozenset(select if select is not None else known) - set(ignore)
    asked = frozenset(
        select if select is not None else (k for k in known if by_id[k].check.default_selected)
    ) - set(ignore)
    if not selected:
        raise UsageError(
            f"no check left to run (select {', '.join(select or sorted(known))}, "
            f"ignore {', '.join(ignore)}); installed: {', '.join(sorted(known))}"
        )
    for check_id in sorted(asked):
        missing = by_id[check_id].check.missing_extra()
        if missing is not None:
            raise UsageError(f"check `{check_id}` cannot run here: {missing}")
    severities: dict[str, Severity] = {}
    options: dict[str, dict[str, Any]] = {}
    for check_id, table in config.checks.items():
        where = config.where(f"checks.{check_id}")
        if check_id not in by_id:
            raise ConfigError(
                f"{where}: unknown check `{check_id}`{did_you_mean(check_id, known)}; "
                f"installed: {', '.join(sorted(known))}"
            )
        table = dict(table)
        severity = table.pop("severity", None)
        if severity is not None:
            if severity not in ("error", "warning"):
                raise ConfigError(
                    f'{config.where(f"checks.{check_id}.severity")}: expected "error" or '
                    f'"warning", got {severity!r}'
                )
            severities[check_id] = severity
        try:
            by_id[check_id].check.options.model_validate(table)
        except Exception as exc:
            # pydantic is imported only where options are validated by it (issue 24)
            from pydantic import ValidationError

            from kcheck.scene import describe_pydantic

            if not isinstance(exc, ValidationError):
                raise
            err = exc.errors(include_url=False)[0]
            key = ".".join(str(p) for p in (check_id, *err["loc"]))
            raise ConfigError(
                f"{config.where(f'checks.{key}')}: {describe_pydantic(err)}"
            ) from None
        options[check_id] = table
    named = frozenset(select or ()) - set(ignore)
    return CheckPlan(selected, severities, options, named)


def cache_folder(config: Config) -> Path | None:
    """Where the mass-property cache lives (None: no cache)."""
    if not config["cache"]:
        return None
    if config["cache_dir"] is not None:
        return Path(config["cache_dir"])
    return user_cache_dir()


def output_targets(config: Config) -> list[tuple[str, Path]]:
    """The ``FORMAT:FILE`` reports, validated: known formats, writable files."""
    from kcheck.gate.paths import check_output_file
    from kcheck.report import FORMATS

    targets: list[tuple[str, Path]] = []
    for item in config["output_format"]:
        name, sep, target = item.partition(":")
        where = (
            "--output-format"
            if config.sources["output_format"] == "command line"
            else (config.where("output_format"))
        )
        if not sep or not target:
            raise UsageError(f"{where}: expected FORMAT:FILE, got {item!r}")
        if name not in FORMATS:
            raise UsageError(
                f"{where}: unknown format `{name}`{did_you_mean(name, FORMATS)}; "
                f"known: {', '.join(FORMATS)}"
            )
        path = Path(target)
        if target == "-":  # standard output, once
            if any(str(p) == "-" for _, p in targets):
                raise UsageError(f"{where}: only one report can go to standard output (-)")
            targets.append((name, path))
            continue
        check_output_file(path, f"--output-format {name}")
        targets.append((name, path))
    return targets


def add_parser(sub: Any) -> None:
    """Register the ``config`` command."""
    parser = sub.add_parser(
        "config",
        help="print the effective configuration and where each value came from",
        description="Print the configuration kcheck check would use: every key, its value "
        "and its origin (default, a configuration file, or the command line).",
    )
    parser.add_argument("--json", action="store_true", help="print it as JSON")
    parser.add_argument("--format", help="override the report format (as for check)")
    add_gate_options(parser)
    parser.set_defaults(handler=run)


def _shown(config: Config, name: str) -> str:
    value = config[name]
    if name == "jobs" and value == 0:
        return f"0 (one per core: {cpu_count()})"
    if name == "select" and value is None:
        return "(every installed check but the opt-in ones)"
    if name == "cache_dir" and value is None:
        folder = cache_folder(config) if config["cache"] else None
        return f"(default: {folder})" if folder is not None else "(cache off)"
    if name == "paths" and not value:
        return '(default: ".")'
    if isinstance(value, tuple):
        value = list(value)
    return json.dumps(value, ensure_ascii=False)


def run(args: argparse.Namespace) -> int:
    """Print the effective configuration (an unknown format is an error, as for `check`:
    :func:`effective_config` refuses it)."""
    config = effective_config(args)
    if args.json:
        doc = {
            "file": None if config.file is None else str(config.file),
            "values": {k.name: config[k.name] for k in KEYS},
            "sources": {k.name: config.sources[k.name] for k in KEYS},
            "checks": {k: dict(v) for k, v in config.checks.items()},
        }
        print(json.dumps(doc, indent=2, default=list))
        return ExitCode.OK
    if config.file is None:
        print("configuration file: none found (defaults and command line only)")
    else:
        print(f"configuration file: {config.file}")
    rows = [(k.name, _shown(config, k.name), config.sources[k.name]) for k in KEYS]
    for check_id, table in config.checks.items():
        for key, value in table.items():
            rows.append((f"checks.{check_id}.{key}", json.dumps(value), str(config.file)))
    width = max(len(r[0]) for r in rows)
    vwidth = min(40, max(len(r[1]) for r in rows))
    for name, value, source in rows:
        print(f"{name:<{width}}  {value:<{vwidth}}  {source}")
    return ExitCode.OK
