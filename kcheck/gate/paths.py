"""Where scenes come from and where reports go: discovery, meshes to scenes, output checks.

Every operating-system error (a path too long, no permission, a symlink loop or dangling
link, a folder where a file was expected, ``/proc``, a full disk) becomes a located message:
an input error for a scene path (the batch goes on), a usage error for an output path
(raised before the run starts). Nothing is dropped silently.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from kcheck.errors import UsageError, describe_os_error

__all__ = [
    "MESH_SUFFIXES",
    "SCENE_SUFFIX",
    "SKIPPED_FOLDERS",
    "DEFAULT_EXCLUDE",
    "DiscoveryError",
    "Excluder",
    "walk_scenes",
    "discover_paths",
    "discover_studies",
    "scenes_using",
    "search_root",
    "check_output_file",
    "check_output_dir",
]

SCENE_SUFFIX = ".kcheck.yaml"
#: Mesh file types a scene may name (what trimesh reads, STEP through cascadio); a changed
#: mesh re-checks the scenes that use it.
MESH_SUFFIXES = frozenset(
    (".stl", ".obj", ".ply", ".off", ".glb", ".gltf", ".3mf", ".dae", ".step", ".stp")
)


class DiscoveryError(Exception):
    """A scene path that cannot be used, with the reason (not raised to the user: the
    runner turns it into the path's error result)."""

    def __init__(self, path: Path, message: str) -> None:
        self.path = path
        self.message = message
        super().__init__(f"{path}: {message}")


def _missing(path: Path) -> str:
    """Why a path that ``stat`` cannot find is missing: a dangling link, or nothing there."""
    try:
        target = os.readlink(path)
    except OSError:
        return "no such file or folder"
    return f"a symbolic link to `{target}`, which does not exist"


def _stat(path: Path) -> os.stat_result:
    try:
        return path.stat()
    except FileNotFoundError:
        raise DiscoveryError(path, _missing(path)) from None
    except (OSError, ValueError) as exc:  # ValueError: a NUL byte in the path
        reason = describe_os_error(exc) if isinstance(exc, OSError) else "invalid path"
        raise DiscoveryError(path, reason) from None


#: Folders never searched for scenes (given explicitly, they are): hidden ones (``.git``,
#: ``.venv``, ``.kcheck_cache``...) and these.
SKIPPED_FOLDERS = frozenset(("__pycache__", "node_modules"))
#: The default of configuration ``exclude`` (gitignore patterns): the folders above.
DEFAULT_EXCLUDE = (".*/", "__pycache__/", "node_modules/")


class Excluder:
    """Which paths a folder search passes over, as ruff does: ``exclude`` (which replaces
    :data:`DEFAULT_EXCLUDE`) and ``extend-exclude`` patterns (gitignore syntax, relative to
    ``root``, the configuration file's folder), and, with ``gitignore``, the files git
    ignores (``git check-ignore`` inside a repository: tracked files are never ignored).
    Paths given explicitly are checked whatever the patterns (except with ``force``)."""

    def __init__(
        self, patterns: Iterable[str] = DEFAULT_EXCLUDE, root: Path | None = None,
        *, gitignore: bool = True,
    ) -> None:  # fmt: skip
        patterns = tuple(patterns)
        self.hidden = ".*/" in patterns
        self.names = frozenset(p[:-1] for p in patterns if p in DEFAULT_EXCLUDE[1:])
        rest = [p for p in patterns if p not in DEFAULT_EXCLUDE]
        self.root = Path(os.path.abspath(root or Path.cwd()))
        self.gitignore = gitignore
        self.spec: Any = None
        if rest:  # pathspec (~20 ms to import) only for patterns of the user's own
            import pathspec

            self.spec = pathspec.GitIgnoreSpec.from_lines(rest)

    def excluded(self, path: Path, is_dir: bool) -> bool:
        """Whether a folder search passes over ``path`` (by the patterns, not git)."""
        name = path.name
        if is_dir and ((self.hidden and name.startswith(".")) or name in self.names):
            return True
        if self.spec is None:
            return False
        absolute = Path(os.path.abspath(path))
        try:
            relative = absolute.relative_to(self.root).as_posix()
        except ValueError:
            relative = name
        return bool(self.spec.match_file(relative + ("/" if is_dir else "")))

    def forced(self, path: Path) -> bool:
        """Whether a path given explicitly is excluded (``--pre-commit``, as ruff's
        ``--force-exclude``): the file or a folder above it, up to ``root``."""
        absolute = Path(os.path.abspath(path))
        if self.excluded(absolute, False):
            return True
        return any(
            self.excluded(parent, True)
            for parent in absolute.parents
            if parent.is_relative_to(self.root) and parent != self.root
        )

    def git_ignored(self, folder: Path, found: list[Path]) -> set[Path]:
        """The paths among ``found`` (under ``folder``) that git ignores; none outside a
        repository, without git, or when git cannot tell (a path beyond a symbolic link)."""
        if not self.gitignore or not found:
            return set()
        start = Path(os.path.abspath(folder))
        if not any((p / ".git").exists() for p in (start, *start.parents)):
            return set()
        import subprocess

        try:
            proc = subprocess.run(
                ["git", "check-ignore", "--stdin", "-z"],
                input=b"".join(os.fsencode(os.path.abspath(p)) + b"\0" for p in found),
                capture_output=True,
                cwd=start,
                check=False,
            )
        except OSError:
            return set()
        if proc.returncode not in (0, 1):
            return set()
        ignored = {os.fsdecode(n) for n in proc.stdout.split(b"\0") if n}
        return {p for p in found if os.path.abspath(p) in ignored}


def _scene_file(path: Path) -> None:
    """Raise DiscoveryError unless ``path`` is a regular file (not a device, pipe or socket,
    which could block or never end)."""
    info = _stat(path)
    if stat.S_ISDIR(info.st_mode):
        raise DiscoveryError(path, "it is a folder, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise DiscoveryError(path, "not a regular file (a device, pipe or socket)")


def walk_scenes(
    folder: Path,
    errors: list[DiscoveryError],
    exclude: Excluder | None = None,
    suffix: str = SCENE_SUFFIX,
) -> Iterator[Path]:
    """Scene files (names ending in ``suffix``) under a folder, depth first in sorted
    order; every folder that cannot be read and every scene-named entry that cannot be
    used is appended to ``errors``.
    Symbolic links to folders are followed once (a link back up is not walked again);
    folders and files ``exclude`` excludes (default: hidden folders and
    :data:`SKIPPED_FOLDERS`) are passed over. (Git's ignores: :meth:`Excluder.git_ignored`.)"""
    exclude = exclude or Excluder(gitignore=False)
    seen: set[tuple[int, int]] = set()

    def walk(current: Path) -> Iterator[Path]:
        try:
            info = current.stat()
            key = (info.st_dev, info.st_ino)
            if key in seen:
                return
            seen.add(key)
            with os.scandir(current) as it:
                entries = sorted(it, key=lambda e: e.name)
        except OSError as exc:
            errors.append(
                DiscoveryError(current, f"cannot read this folder: {describe_os_error(exc)}")
            )
            return
        for entry in entries:
            path = Path(entry.path)
            try:
                is_dir = entry.is_dir()
            except OSError:
                is_dir = False
            if is_dir:
                if not exclude.excluded(path, True):
                    yield from walk(path)
            elif entry.name.endswith(suffix) and not exclude.excluded(path, False):
                try:
                    _scene_file(path)
                except DiscoveryError as exc:
                    errors.append(exc)
                    continue
                yield path

    yield from walk(folder)


def discover_paths(
    paths: Iterable[Path | str], exclude: Excluder | None = None
) -> tuple[list[Path], list[Path], list[DiscoveryError]]:
    """Scene files and mesh files named by ``paths`` (folders searched for scenes, passing
    over what ``exclude`` excludes and git ignores), and every path that cannot be used.
    Files are returned in the order given, each once."""
    exclude = exclude or Excluder()
    scenes: list[Path] = []
    meshes: list[Path] = []
    errors: list[DiscoveryError] = []
    for raw in paths:
        path = Path(raw)
        try:
            info = _stat(path)
        except DiscoveryError as exc:
            errors.append(exc)
            continue
        if stat.S_ISDIR(info.st_mode):
            before = len(errors)
            found = list(walk_scenes(path, errors, exclude))
            ignored = exclude.git_ignored(path, found)
            found = [f for f in found if f not in ignored]
            if not found and len(errors) == before:
                errors.append(
                    DiscoveryError(path, f"no *{SCENE_SUFFIX} files found in this folder")
                )
            scenes.extend(found)
        elif not stat.S_ISREG(info.st_mode):
            errors.append(DiscoveryError(path, "not a regular file (a device, pipe or socket)"))
        elif path.suffix.lower() in MESH_SUFFIXES and not path.name.endswith(SCENE_SUFFIX):
            meshes.append(path)
        else:
            scenes.append(path)
    return scenes, meshes, errors


def discover_studies(
    folder: Path, exclude: Excluder | None = None
) -> tuple[list[Path], list[DiscoveryError]]:
    """Study files (``*.kcheck-study.yaml``) under a folder, found as scenes are: depth
    first in sorted order, passing over what ``exclude`` excludes and git ignores."""
    from kcheck.scene.study import STUDY_SUFFIX

    exclude = exclude or Excluder()
    errors: list[DiscoveryError] = []
    found = list(walk_scenes(folder, errors, exclude, STUDY_SUFFIX))
    ignored = exclude.git_ignored(folder, found)
    return [f for f in found if f not in ignored], errors


def _strings(data: object) -> Iterator[str]:
    if isinstance(data, str):
        yield data
    elif isinstance(data, dict):
        for value in data.values():
            yield from _strings(value)
    elif isinstance(data, list):
        for value in data:
            yield from _strings(value)


def scenes_using(meshes: Iterable[Path], root: Path) -> dict[Path, list[Path]]:
    """For each mesh, the scene files under ``root`` that name it (any string value of the
    scene that resolves, relative to the scene's folder, to the same file).

    Scene files are first filtered by the mesh's file name in their text, so only a few
    are parsed. A scene that names the mesh in its text but cannot be parsed is counted as a
    user (checking it reports why it cannot be read, as the full run would); a mesh need not
    exist (a deleted or renamed mesh still has the scenes that name it).
    """
    from kcheck.scene.yamlio import load_yaml

    wanted = {}
    for mesh in meshes:
        try:
            wanted[mesh.resolve()] = mesh
        except (OSError, RuntimeError):
            continue
    found: dict[Path, list[Path]] = {m: [] for m in wanted.values()}
    if not wanted:
        return found
    names = {m.name for m in wanted}
    for scene in walk_scenes(root, []):
        try:
            text = scene.read_text(encoding="utf-8", errors="replace")
        except OSError:
            continue
        if not any(n in text for n in names):
            continue
        try:
            data, _ = load_yaml(scene)
        except Exception:  # a broken scene that may name the mesh: checking it reports it
            for name, mesh in ((m.name, m) for m in wanted.values()):
                if name in text and scene not in found[mesh]:
                    found[mesh].append(scene)
            continue
        for value in _strings(data):
            if not any(value.endswith(n) for n in names):
                continue
            try:
                target = (scene.parent / value).resolve()
            except (OSError, RuntimeError, ValueError):
                continue
            if target in wanted and scene not in found[wanted[target]]:
                found[wanted[target]].append(scene)
    return found


def search_root(mesh: Path) -> Path:
    """Where to look for scenes using a mesh: the git repository holding it; else the
    working directory if it holds the mesh; else the mesh's folder. (A scene names meshes in
    its own folder or below, unless --allow-outside-paths.)"""
    folder = mesh.resolve().parent
    for parent in (folder, *folder.parents):
        if (parent / ".git").exists():
            return parent
    cwd = Path.cwd().resolve()
    return cwd if folder.is_relative_to(cwd) else folder


def _first_existing(path: Path) -> Path:
    for parent in (path, *path.parents):
        if os.path.lexists(parent):
            return parent
    return Path(".")


def _refuse_special(path: Path) -> None:
    resolved = path.resolve()
    for special in ("/proc", "/sys"):
        if resolved.is_relative_to(special):
            raise UsageError(f"{path}: cannot write a report under {special}")


def check_output_file(path: Path, what: str) -> None:
    """Raise UsageError unless a report file can be written at ``path`` (its folder may be
    created). Probes without writing anything: a full device refuses even an empty write."""
    try:
        _refuse_special(path)
        if path.is_dir():
            raise UsageError(f"{what} {path}: is a folder; give a file name")
        anchor = _first_existing(path.parent)
        if not anchor.is_dir():
            raise UsageError(f"{what} {path}: {anchor} is a file, not a folder")
        if path.exists() and not stat.S_ISREG(path.stat().st_mode):
            # A device or a pipe: without blocking (a pipe nobody reads is ENXIO).
            fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
            try:
                os.write(fd, b"")
            finally:
                os.close(fd)
        elif not os.access(anchor, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
            raise UsageError(f"{what} {path}: permission denied")
    except OSError as exc:
        raise UsageError(f"{what} {path}: {describe_os_error(exc)}") from None
    except ValueError:
        raise UsageError(f"{what} {path}: invalid path") from None


def check_output_dir(path: Path, what: str) -> None:
    """Raise UsageError unless ``path`` is (or can be made) a folder kcheck can write into;
    creates it, and probes it with an empty temporary file."""
    import tempfile

    try:
        _refuse_special(path)
        if path.exists() and not path.is_dir():
            raise UsageError(f"{what} {path}: is a file, not a folder")
        anchor = _first_existing(path)
        if not anchor.is_dir():
            raise UsageError(f"{what} {path}: {anchor} is a file, not a folder")
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as exc:
        raise UsageError(f"{what} {path}: {describe_os_error(exc)}") from None
    except ValueError:
        raise UsageError(f"{what} {path}: invalid path") from None
