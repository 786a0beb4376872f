"""Which scenes changed in git (``--changed-only``, ``--since REF``): scene files changed or
untracked against a revision, and scenes whose mesh changed."""

from __future__ import annotations

import subprocess
from collections.abc import Sequence
from pathlib import Path

from kcheck.errors import UsageError

__all__ = ["changed_files", "changed_scenes"]


def _git(*args: str, failure: str | None = None) -> str:
    """git's output; a UsageError in kcheck's words if git is missing or fails (``failure``
    says what it means; git's own message, whose wording is git's, follows as the detail)."""
    from kcheck.errors import describe_os_error

    try:
        proc = subprocess.run(
            ["git", *args], capture_output=True, text=True, check=False, encoding="utf-8"
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


def changed_files(ref: str) -> set[Path]:
    """Absolute paths of files changed against ``ref`` (working tree and index) or untracked."""
    if ref.startswith("-"):
        raise UsageError(f"--since: expected a git revision, got {ref!r}")
    outside = "--changed-only/--since need the working directory in a git repository git can read"
    top = Path(_git("rev-parse", "--show-toplevel", failure=outside).strip())
    _git(
        "rev-parse",
        "--verify",
        "--quiet",
        f"{ref}^{{commit}}",
        failure=f"--changed-only/--since: `{ref}` is not a commit of this git repository",
    )
    names = _git("diff", "--name-only", "-z", ref, "--").split("\0")
    names += _git("ls-files", "--others", "--exclude-standard", "-z", "--full-name", ":/").split(
        "\0"
    )
    return {(top / n).resolve() for n in names if n}


def changed_scenes(files: Sequence[Path], ref: str) -> list[Path]:
    """The scenes among ``files`` that changed against ``ref``, or use a mesh that did."""
    from kcheck.gate.paths import MESH_SUFFIXES, scenes_using

    changed = changed_files(ref)
    meshes = [p for p in changed if p.suffix.lower() in MESH_SUFFIXES and p.exists()]
    top = Path(_git("rev-parse", "--show-toplevel").strip())
    users = {s.resolve() for found in scenes_using(meshes, top).values() for s in found}
    return [f for f in files if f.resolve() in changed or f.resolve() in users]
