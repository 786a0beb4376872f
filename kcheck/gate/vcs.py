"""Which scenes a change affects (``--changed-only``, ``--since REF``, the pre-commit hook),
so that an incremental run gives the verdict of the full run.

A scene is affected when its file changed (or is untracked), when a mesh it names changed,
was deleted or renamed away (the scene names the old path), and every scene is affected when
the configuration changed: a ``kcheck.toml``, or the ``[tool.kcheck]`` table of a
``pyproject.toml``, or the ``--baseline`` file (an entry dropped from it makes a failure
count again; one added accepts it). A scene that names a changed mesh in its text but
cannot be parsed is affected too (checking it reports it). ``--since REF`` compares with
the merge-base of REF and ``HEAD``, as a pull request does, so a branch behind REF is judged
by its own changes.
"""

from __future__ import annotations

import subprocess
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from kcheck.errors import UsageError

__all__ = ["changed_files", "changed_scenes", "config_changed", "merge_base"]

#: Configuration files whose change changes every verdict (``[tool.kcheck]`` only, for a
#: ``pyproject.toml``).
CONFIG_NAMES = ("kcheck.toml", "pyproject.toml")


def _git(*args: str, failure: str | None = None, cwd: Path | None = None) -> str:
    """git's output; a UsageError in kcheck's words if git is missing or fails (``failure``
    says what it means; git's own message, whose wording is git's, follows as the detail)."""
    from kcheck.errors import describe_os_error

    try:
        proc = subprocess.run(
            ["git", *args],
            capture_output=True,
            text=True,
            check=False,
            encoding="utf-8",
            errors="surrogateescape",
            cwd=cwd,
        )
    except OSError as exc:
        reason = "it is not installed" if isinstance(exc, FileNotFoundError) else None
        raise UsageError(
            f"--changed-only/--since need git, which cannot be run: "
            f"{reason or describe_os_error(exc)}"
        ) from None
    if proc.returncode != 0:
        said = proc.stderr.strip()
        what = failure or f"git {' '.join(args)} failed"
        raise UsageError(f"{what} (git: {said})" if said else what)
    return proc.stdout


def _top() -> Path:
    outside = "--changed-only/--since need the working directory in a git repository git can read"
    return Path(_git("rev-parse", "--show-toplevel", failure=outside).strip())


def _commit(ref: str) -> str:
    if ref.startswith("-"):
        raise UsageError(f"--since: expected a git revision, got {ref!r}")
    return _git(
        "rev-parse",
        "--verify",
        "--quiet",
        f"{ref}^{{commit}}",
        failure=f"--changed-only/--since: `{ref}` is not a commit of this git repository",
    ).strip()


def merge_base(ref: str) -> str:
    """The commit where ``HEAD`` left ``ref`` (what a pull request is compared with)."""
    commit = _commit(ref)
    return _git(
        "merge-base",
        commit,
        "HEAD",
        failure=f"--since: `{ref}` and HEAD have no common ancestor",
    ).strip()


def changed_files(base: str) -> tuple[Path, set[Path]]:
    """The repository's top folder, and the absolute paths changed between commit ``base``
    and the working tree (index included): added, modified, deleted, both sides of a rename
    (``--no-renames``), and untracked files that are not ignored."""
    top = _top()
    _commit(base)
    names = _git("diff", "--name-only", "--no-renames", "-z", base, "--", cwd=top).split("\0")
    names += _git(
        "ls-files", "--others", "--exclude-standard", "-z", "--full-name", ":/", cwd=top
    ).split("\0")
    return top, {_absolute(top / n) for n in names if n}


def _absolute(path: Path) -> Path:
    try:
        return path.resolve()
    except (OSError, RuntimeError):
        return path.absolute()


def _kcheck_table(text: str | None, name: str) -> Any:
    """The configuration a file's text holds (its [tool.kcheck] table for a pyproject.toml);
    a file that does not parse is a value of its own (a change to it counts)."""
    if text is None:
        return None
    import sys

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return ("not TOML", text)
    return data if name != "pyproject.toml" else data.get("tool", {}).get("kcheck")


def config_changed(top: Path, base: str, changed: set[Path]) -> Path | None:
    """A configuration file among ``changed`` whose kcheck settings differ from ``base``
    (a ``pyproject.toml`` whose other tables changed does not count)."""
    for path in sorted(changed):
        if path.name not in CONFIG_NAMES:
            continue
        try:
            relative = path.relative_to(top.resolve()).as_posix()
        except ValueError:
            return path
        try:
            before: str | None = _git("show", f"{base}:{relative}", cwd=top)
        except UsageError:
            before = None  # not in the base commit
        try:
            now: str | None = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            now = None
        if _kcheck_table(before, path.name) != _kcheck_table(now, path.name):
            return path
    return None


def changed_scenes(
    files: Sequence[Path], ref: str, *, since: bool = False, inputs: Sequence[Path] = ()
) -> list[Path]:
    """The scenes among ``files`` that a change against ``ref`` affects (``since``: against
    the merge-base of ``ref`` and ``HEAD``): see the module's documentation. ``inputs``:
    further files whose change affects every scene (the ``--baseline`` file)."""
    from kcheck.gate.paths import MESH_SUFFIXES, scenes_using

    _top()  # first: outside a repository, say so
    base = merge_base(ref) if since else _commit(ref)
    top, changed = changed_files(base)
    if config_changed(top, base, changed) is not None:
        return list(files)
    if any(_absolute(p) in changed for p in inputs):
        return list(files)
    meshes = [p for p in changed if p.suffix.lower() in MESH_SUFFIXES]
    users = {_absolute(s) for found in scenes_using(meshes, top).values() for s in found}
    return [f for f in files if _absolute(f) in changed or _absolute(f) in users]
