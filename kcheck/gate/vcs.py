"""Which scenes changed in git (``--changed-only``, ``--since REF``): scene files changed or
untracked against a revision, and scenes whose mesh changed."""

from __future__ import annotations

import subprocess
from collections.abc import Sequence
from pathlib import Path

from kcheck.errors import UsageError

__all__ = ["changed_files", "changed_scenes"]


def _git(*args: str) -> str:
    try:
        proc = subprocess.run(
            ["git", *args], capture_output=True, text=True, check=False, encoding="utf-8"
        )
    except OSError as exc:
        raise UsageError(f"--changed-only/--since need git: {exc.strerror}") from None
    if proc.returncode != 0:
        raise UsageError(f"git {' '.join(args)}: {proc.stderr.strip() or 'failed'}")
    return proc.stdout


def changed_files(ref: str) -> set[Path]:
    """Absolute paths of files changed against ``ref`` (working tree and index) or untracked."""
    if ref.startswith("-"):
        raise UsageError(f"--since: expected a git revision, got {ref!r}")
    top = Path(_git("rev-parse", "--show-toplevel").strip())
    _git("rev-parse", "--verify", "--quiet", f"{ref}^{{commit}}")
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
