"""Configuration: ``[tool.kcheck]`` in ``pyproject.toml`` or a ``kcheck.toml``, found as ruff
and mypy find theirs, with command-line values on top.

The search starts in the working directory and goes upwards, stopping after the repository
root (the first folder holding ``.git``); in each folder ``kcheck.toml`` wins over a
``pyproject.toml``, and a ``pyproject.toml`` without ``[tool.kcheck]`` is passed over (as black
does). Relative paths in a file (``paths``, ``cache_dir``, output files) are relative to the
file's folder. Every value remembers where it came from, for ``kcheck config``.

Bad configuration is a :class:`ConfigError` naming the file, the key and what was expected.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Mapping
from dataclasses import field
from pathlib import Path
from typing import Any

from kcheck.errors import UsageError, describe_os_error
from kcheck.records import dataclass

__all__ = [
    "CONFIG_FILES",
    "KEYS",
    "Config",
    "ConfigError",
    "Key",
    "find_config",
    "load_config",
    "did_you_mean",
]

CONFIG_FILES = ("kcheck.toml", "pyproject.toml")
DEFAULT_SOURCE = "default"
CLI_SOURCE = "command line"


class ConfigError(UsageError):
    """Bad configuration: which file, which key, what was expected (exit code 2)."""


def did_you_mean(word: str, choices: Any) -> str:
    """`` (did you mean `x`?)`` for a near miss among ``choices``, else an empty string."""
    import difflib

    close = difflib.get_close_matches(word, sorted(choices), n=1, cutoff=0.6)
    return f" (did you mean `{close[0]}`?)" if close else ""


# -- value parsers: raw TOML/command-line value -> typed value, or ValueError(expected) ------


def _str_list(value: Any) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ValueError("a list of strings")
    return tuple(value)


def _check_ids(value: Any) -> tuple[str, ...]:
    ids = tuple(s.strip() for s in _str_list(value))
    if not ids or not all(ids):
        raise ValueError("a non-empty list of check ids")
    return ids


def _choice(*choices: str) -> Callable[[Any], str]:
    def parse(value: Any) -> str:
        if value not in choices:
            raise ValueError(" or ".join(f'"{c}"' for c in choices))
        return str(value)

    return parse


def _bool(value: Any) -> bool:
    if not isinstance(value, bool):
        raise ValueError("true or false")
    return value


def _jobs(value: Any) -> int:
    if value == "auto":
        return 0
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ValueError('a whole number of worker processes (0 or "auto": one per core)')
    return value


def _positive(unit: str) -> Callable[[Any], float]:
    def parse(value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
            raise ValueError(f"a positive number ({unit})")
        if value == float("inf"):
            raise ValueError(f"a finite positive number ({unit})")
        return float(value)

    return parse


#: The smallest memory budget of a scene (MiB): a worker's address space is about 300 MiB
#: (Python, numpy, trimesh, scipy) before it reads a scene, so a smaller budget fails every
#: scene, or stalls it until its time budget (200 MiB did), instead of bounding it.
MIN_MEMORY_MIB = 512.0


def memory_budget(value: Any) -> float:
    """A memory budget in MiB: positive, finite and at least :data:`MIN_MEMORY_MIB`."""
    budget = _positive("MiB")(value)
    if budget < MIN_MEMORY_MIB:
        raise ValueError(
            f"at least {MIN_MEMORY_MIB:g} MiB (kcheck's worker takes about 300 MiB of address "
            "space before it reads a scene)"
        )
    return budget


def _output_formats(value: Any) -> tuple[str, ...]:
    items = _str_list(value)
    for item in items:
        name, sep, target = item.partition(":")
        if not sep or not name or not target:
            raise ValueError('a list of "FORMAT:FILE" strings, e.g. "sarif:kcheck.sarif"')
    return items


def _path_ignores(value: Any) -> dict[str, tuple[str, ...]]:
    expected = (
        'a table of gitignore patterns to lists of check ids or rules: {"legacy/**" = ["maxwell"]}'
    )
    if not isinstance(value, dict):
        raise ValueError(expected)
    out: dict[str, tuple[str, ...]] = {}
    for pattern, codes in value.items():
        if (
            not pattern
            or not isinstance(codes, list)
            or not all(isinstance(c, str) and c for c in codes)
        ):
            raise ValueError(expected)
        out[str(pattern)] = tuple(codes)
    return out


def _path(value: Any) -> str:
    if not isinstance(value, str) or not value:
        raise ValueError("a path")
    return value


@dataclass(frozen=True)
class Key:
    """One configuration key: its parser, default and one line of documentation."""

    name: str
    parse: Callable[[Any], Any]
    default: Any
    doc: str


KEYS: tuple[Key, ...] = (
    Key("paths", _str_list, (), "scene files and folders checked when none are given"),
    Key(
        "select",
        _check_ids,
        None,
        "check ids to run (default: every installed check but the opt-in ones, e.g. reseat)",
    ),
    Key("ignore", _str_list, (), "check ids not to run"),
    Key("fail_on", _choice("error", "warning"), "error", "lowest severity that fails the run"),
    Key("jobs", _jobs, 0, "worker processes (0: one per core; 1: no parallelism)"),
    Key("format", _path, "text", "report format on standard output (or --output)"),
    Key("output_format", _output_formats, (), 'further reports, "FORMAT:FILE" each'),
    Key(
        "exclude",
        _str_list,
        (".*/", "__pycache__/", "node_modules/"),
        "gitignore patterns of paths a folder search passes over (replaces the default)",
    ),
    Key("extend_exclude", _str_list, (), "further patterns, added to `exclude`"),
    Key(
        "per_path_ignores",
        _path_ignores,
        {},
        'check ids or rules accepted in scenes matching a pattern: {"legacy/**" = ["maxwell"]}',
    ),
    Key("respect_gitignore", _bool, True, "pass over files git ignores (.gitignore...)"),
    Key("cache", _bool, True, "cache mass properties of meshes"),
    Key("cache_dir", _path, None, "cache folder (default: the user cache folder)"),
    Key("allow_outside_paths", _bool, False, "let scenes use meshes outside their folder"),
    Key("timeout", _positive("seconds"), 120.0, "time budget of one scene, s"),
    Key("memory_limit", memory_budget, 2048.0, "memory budget of one scene, MiB (≥ 512)"),
    Key("max_file_size", _positive("MiB"), 5.0, "largest scene file read, MiB"),
    Key("max_mesh_size", _positive("MiB"), 64.0, "largest mesh file read, MiB"),
)
_BY_NAME = {k.name: k for k in KEYS}
# Keys holding paths that are relative to the configuration file's folder.
_PATH_KEYS = ("paths", "cache_dir", "output_format")


@dataclass(frozen=True)
class Config:
    """The effective configuration: every key's value and where it came from.

    ``file`` is the configuration file used (None when there is none); ``root`` is its
    folder, or the working directory. ``checks`` holds per-check tables (options and
    ``severity``) from the file, validated later against the installed checks.
    """

    values: Mapping[str, Any]
    sources: Mapping[str, str]
    file: Path | None = None
    root: Path = field(default_factory=Path.cwd)
    checks: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)

    def __getitem__(self, name: str) -> Any:
        return self.values[name]

    def where(self, key: str) -> str:
        """Where to look for a key: ``pyproject.toml: [tool.kcheck] `jobs```."""
        if self.file is None:
            return f"`{key}`"
        table = "[tool.kcheck] " if self.file.name == "pyproject.toml" else ""
        return f"{self.file}: {table}`{key}`"

    def with_overrides(self, overrides: Mapping[str, Any]) -> Config:
        """This configuration with command-line values (already typed) on top."""
        values = dict(self.values)
        sources = dict(self.sources)
        for name, value in overrides.items():
            if value is not None:
                values[name] = value
                sources[name] = CLI_SOURCE
        return Config(values, sources, self.file, self.root, self.checks)


def _repo_root(start: Path) -> Path | None:
    for folder in (start, *start.parents):
        if (folder / ".git").exists():
            return folder
    return None


#: Largest configuration file read (pyproject.toml files are a few kB).
MAX_CONFIG_BYTES = 1 << 20


def _read_toml(path: Path) -> dict[str, Any]:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    from kcheck.scene.yamlio import open_regular

    try:
        # Not a pipe or device (which could block or never end), and bounded.
        with open_regular(path) as fh:
            raw = fh.read(MAX_CONFIG_BYTES + 1)
    except OSError as exc:
        raise ConfigError(
            f"{path}: cannot read the configuration ({describe_os_error(exc)})"
        ) from exc
    if len(raw) > MAX_CONFIG_BYTES:
        raise ConfigError(f"{path}: larger than {MAX_CONFIG_BYTES >> 20} MiB; not a configuration")
    try:
        return tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path}: not UTF-8 text (byte {exc.start}); save it as UTF-8") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from exc


def _table(path: Path, data: dict[str, Any]) -> dict[str, Any] | None:
    """The kcheck table of a configuration file (None: a pyproject.toml without one)."""
    if path.name != "pyproject.toml":
        return data
    table = data.get("tool", {}).get("kcheck")
    if table is not None and not isinstance(table, dict):
        raise ConfigError(f"{path}: [tool.kcheck] must be a table")
    return table


def find_config(start: Path | None = None) -> tuple[Path, dict[str, Any]] | None:
    """The nearest configuration file from ``start`` (default: the working directory)
    upwards, stopping after the repository root, and its kcheck table."""
    start = (start or Path.cwd()).resolve()
    stop = _repo_root(start)
    for folder in (start, *start.parents):
        for name in CONFIG_FILES:
            candidate = folder / name
            try:
                present = candidate.is_file()
            except OSError:
                present = False
            if present:
                table = _table(candidate, _read_toml(candidate))
                if table is not None:
                    return candidate, table
        if folder == stop:
            break
    return None


def _parse_table(path: Path, table: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    prefix = "[tool.kcheck] " if path.name == "pyproject.toml" else ""
    values: dict[str, Any] = {}
    checks: dict[str, Any] = {}
    for name, raw in table.items():
        if name == "checks":
            if not isinstance(raw, dict) or not all(isinstance(v, dict) for v in raw.values()):
                raise ConfigError(
                    f"{path}: {prefix}`checks`: expected a table per check id, "
                    "e.g. [tool.kcheck.checks.maxwell]"
                )
            checks = raw
            continue
        key = _BY_NAME.get(name.replace("-", "_"))
        if key is None:
            raise ConfigError(
                f"{path}: {prefix}unknown key `{name}`{did_you_mean(name, _BY_NAME)}; "
                f"known: {', '.join(sorted([*_BY_NAME, 'checks']))}"
            )
        try:
            values[key.name] = key.parse(raw)
        except ValueError as exc:
            raise ConfigError(f"{path}: {prefix}`{name}`: expected {exc}, got {raw!r}") from None
    root = path.parent
    if "paths" in values:
        values["paths"] = tuple(str(root / p) for p in values["paths"])
    if "cache_dir" in values:
        values["cache_dir"] = str(root / values["cache_dir"])
    if "output_format" in values:
        values["output_format"] = tuple(
            f"{n}:{root / t}" for n, _, t in (i.partition(":") for i in values["output_format"])
        )
    return values, checks


def load_config(explicit: Path | None = None, *, isolated: bool = False) -> Config:
    """The configuration from ``explicit`` (``--config``), else the nearest file, else the
    defaults (``isolated``: the defaults, whatever files exist)."""
    values = {k.name: k.default for k in KEYS}
    sources = dict.fromkeys(values, DEFAULT_SOURCE)
    if isolated:
        return Config(values, sources)
    if explicit is not None:
        table = _table(explicit, _read_toml(explicit))
        if table is None:
            raise ConfigError(f"{explicit}: no [tool.kcheck] table in this file")
        found: tuple[Path, dict[str, Any]] | None = (explicit.resolve(), table)
    else:
        found = find_config()
    if found is None:
        return Config(values, sources)
    path, table = found
    parsed, checks = _parse_table(path, table)
    values.update(parsed)
    sources.update(dict.fromkeys(parsed, str(path)))
    return Config(values, sources, path, path.parent, checks)


def cpu_count() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def user_cache_dir() -> Path:
    """The default cache folder: ``$KCHECK_CACHE_DIR``, else the user cache folder of
    ``kcheck`` as platformdirs finds it (``$XDG_CACHE_HOME/kcheck``, else
    ``~/.cache/kcheck`` on Linux; ``~/Library/Caches/kcheck`` on macOS;
    ``%LOCALAPPDATA%\\kcheck\\Cache`` on Windows)."""
    env = os.environ.get("KCHECK_CACHE_DIR")
    if env:
        return Path(env)
    common = _linux_user_cache_dir()
    if common is not None:
        return common
    import platformdirs

    return Path(platformdirs.user_cache_dir("kcheck", appauthor=False))


def _linux_user_cache_dir() -> Path | None:
    """platformdirs' answer in the common Linux cases, without importing it (4-6 ms of every
    start, issue 24): ``$XDG_CACHE_HOME/kcheck`` when that is an absolute path, else
    ``$HOME/.cache/kcheck`` when it is unset or empty and ``$HOME`` is absolute. None for
    anything else (another system, Android, a relative path): platformdirs decides.
    ``tests/kcheck/test_config.py`` compares it with platformdirs."""
    if sys.platform != "linux" or "ANDROID_DATA" in os.environ or "ANDROID_ROOT" in os.environ:
        return None
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    if os.path.isabs(xdg):
        return Path(xdg, "kcheck")
    home = os.environ.get("HOME", "")
    if xdg == "" and os.path.isabs(home):
        return Path(home, ".cache", "kcheck")
    return None
