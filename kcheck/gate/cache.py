"""Cache of mesh mass properties, keyed by everything that determines them.

The key is a SHA-256 over: each part's mesh content (SHA-256 of the file's bytes) and file
name (it appears in notes), every other field of the part (density, and whatever else the
scene gives: units, transform, repair...), every other field of the body (point masses...),
the scene's length scale, the kcheck version, the trimesh version, and the source of the
code that computes them (``kcheck/body/mass.py``, so a changed computation never reads an old
answer, even between releases). A changed mesh gives
a new key; nothing is ever looked up by file name or date.

An entry is one JSON file, written atomically. It is trusted only if it parses, carries its
own key, its checksum matches and its numbers are physical (finite, positive mass, symmetric
inertia); otherwise it is recomputed and rewritten. Errors are never cached. The folder gets
a ``CACHEDIR.TAG`` and a ``.gitignore`` (as ``.ruff_cache`` does).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck import __version__
from kcheck.numerics.thresholds import CACHED_SYMMETRY_RTOL

if TYPE_CHECKING:
    from kcheck.result import MassProperties
    from kcheck.scene import Body

__all__ = ["CACHE_FOLDER", "MassCache", "body_mass_properties_cached"]

CACHE_FOLDER = ".kcheck_cache"
_FORMAT = 1
_TAG = (
    "Signature: 8a477f597d28d172789f06886806bc55\n"
    "# This file is a cache directory tag created by kcheck.\n"
    "# For information about cache directory tags see https://bford.info/cachedir/\n"
)


def _file_sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _plain(value: Any) -> Any:
    """A JSON-able, deterministic form of a part field."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in sorted(value.items())}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return repr(value)


_CODE_FINGERPRINT: str | None = None


def _code_fingerprint() -> str:
    """kcheck and trimesh versions and the source of kcheck.body.mass (what computes the values)."""
    global _CODE_FINGERPRINT
    if _CODE_FINGERPRINT is None:
        import importlib.util

        from kcheck.plugin.dist_info import version

        spec = importlib.util.find_spec("kcheck.body.mass")
        source = b""
        if spec is not None and spec.origin is not None:
            source = Path(spec.origin).read_bytes()
        trimesh_version = version("trimesh") or "?"
        _CODE_FINGERPRINT = hashlib.sha256(
            f"{__version__}|{trimesh_version}|".encode() + source
        ).hexdigest()
    return _CODE_FINGERPRINT


def body_key(body: Body, scale: float) -> str:
    """The cache key of a body's mesh mass properties."""
    parts = []
    for part in body.parts:
        fields = {
            f.name: _plain(getattr(part, f.name))
            for f in dataclasses.fields(part)
            if f.name not in ("mesh", "field")
        }
        parts.append({"sha256": _file_sha256(part.mesh), "name": part.mesh.name, "fields": fields})
    # Everything else the body carries (point masses, ...), whatever the scene format adds.
    rest = {
        f.name: _plain(getattr(body, f.name))
        for f in dataclasses.fields(body)
        if f.name not in ("parts", "explicit")
    }
    material = {
        "format": _FORMAT,
        "code": _code_fingerprint(),
        "scale": scale,
        "parts": parts,
        "body": rest,
    }
    return hashlib.sha256(json.dumps(material, sort_keys=True).encode()).hexdigest()


def _checksum(payload: dict[str, Any]) -> str:
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


class MassCache:
    """Mass properties on disk under ``folder/mass/``."""

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)

    def _path(self, key: str) -> Path:
        return self.folder / "mass" / key[:2] / f"{key}.json"

    def get(self, key: str) -> MassProperties | None:
        """The entry for ``key``, or None when absent, unreadable, corrupt or implausible."""
        try:
            entry = json.loads(self._path(key).read_text(encoding="utf-8"))
            payload = entry["payload"]
            if entry["key"] != key or entry["checksum"] != _checksum(payload):
                return None
            return _from_payload(payload)
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def put(self, key: str, mass: MassProperties) -> None:
        """Store an entry atomically; a cache that cannot be written is silently skipped."""
        import tempfile

        payload = _to_payload(mass)
        entry = {"key": key, "checksum": _checksum(payload), "payload": payload}
        path = self._path(key)
        try:
            self._prepare()
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-")
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as fh:
                    json.dump(entry, fh)
                os.replace(tmp, path)
            except BaseException:
                os.unlink(tmp)
                raise
        except OSError:
            pass

    def _prepare(self) -> None:
        if (self.folder / "CACHEDIR.TAG").exists():
            return
        self.folder.mkdir(parents=True, exist_ok=True)
        (self.folder / ".gitignore").write_text("# Created by kcheck.\n*\n", encoding="utf-8")
        (self.folder / "CACHEDIR.TAG").write_text(_TAG, encoding="utf-8")


def _to_payload(mass: MassProperties) -> dict[str, Any]:
    return {
        "mass": mass.mass,
        "center_of_mass": mass.center_of_mass.tolist(),
        "inertia": mass.inertia.tolist(),
        "source": mass.source,
        "volume": mass.volume,
        "notes": list(mass.notes),
    }


def _from_payload(payload: dict[str, Any]) -> MassProperties | None:
    import numpy as np

    from kcheck.result import MassProperties

    mass = float(payload["mass"])
    com = np.asarray(payload["center_of_mass"], dtype=float)
    inertia = np.asarray(payload["inertia"], dtype=float)
    volume = payload["volume"]
    notes = payload["notes"]
    plausible = (
        np.isfinite(mass)
        and mass > 0
        and com.shape == (3,)
        and inertia.shape == (3, 3)
        and bool(np.all(np.isfinite(com)))
        and bool(np.all(np.isfinite(inertia)))
        and bool(np.allclose(inertia, inertia.T, rtol=CACHED_SYMMETRY_RTOL, atol=0))
        and payload["source"] == "mesh"
        and (volume is None or (isinstance(volume, (int, float)) and volume > 0))
        and isinstance(notes, list)
        and all(isinstance(n, str) for n in notes)
    )
    if not plausible:
        return None
    return MassProperties(
        mass, com, inertia, "mesh", None if volume is None else float(volume), tuple(notes)
    )


def body_mass_properties_cached(
    body: Body, scale: float, folder: Path | None, max_mesh_bytes: int | None = None
) -> MassProperties:
    """:func:`kcheck.body.mass.body_mass_properties`, through the cache in ``folder`` when the
    body's mass properties come from meshes (None: no cache)."""
    from kcheck.body.mass import body_mass_properties
    from kcheck.body.meshio import check_mesh_file

    if folder is None or body.explicit is not None or not body.parts:
        return body_mass_properties(body, scale, max_mesh_bytes)
    for part in body.parts:  # before hashing it: a file past the limit is not read at all
        check_mesh_file(part.mesh, (*part.field, "mesh"), max_mesh_bytes)
    cache = MassCache(folder)
    try:
        key = body_key(body, scale)
    except OSError:  # the mesh cannot be read: let the computation report it
        return body_mass_properties(body, scale, max_mesh_bytes)
    hit = cache.get(key)
    if hit is not None:
        return hit
    mass = body_mass_properties(body, scale, max_mesh_bytes)
    cache.put(key, mass)
    return mass
