"""Cache of mesh mass properties (and of the supports against the mesh: :class:`PlacementCache`,
under ``placement/``), keyed by everything that determines them.

The key is a SHA-256 over: each part's mesh content (SHA-256 of the file's bytes), file name
(it appears in notes) and field in the scene file (warnings point at it), every other field of
the part (density, units, transform, repair...), every other field of the body (point
masses...), the scene's length scale, the entry format, the kcheck, trimesh, numpy and scipy
versions, and the source of the code that computes them (every module of ``kcheck/body/`` and
the limits of ``kcheck/scene/limits.py``, so a changed computation or limit never reads an old
answer, even between releases). A changed mesh gives a new key; nothing is ever looked up by
file name or date.

An entry holds **everything a result depends on**: mass, centre of mass, inertia, volume,
notes, the meshes' bounding box (``bounds``) and each part's (``part_bounds``: the sanity
warnings judge the body's size and a part in another unit by them), and the warnings of
reading the meshes (``mesh-repaired``). A result from the cache is the result computed afresh,
field for field (``tests/cli/test_same_answer.py`` runs every fixture and 200 generated scenes
cold, warm and without the cache and compares the JSON).

An entry is one JSON file, written atomically, carrying its format (:data:`FORMAT`). It is
trusted only if its format is the current one, it parses, carries its own key, its checksum
matches, it has exactly the fields of its format and its numbers are physical (finite, positive
mass, symmetric inertia, ordered boxes); otherwise it is recomputed and rewritten: an entry of
an older format is never half-read. Errors are never cached. The folder gets a
``CACHEDIR.TAG`` and a ``.gitignore`` (as ``.ruff_cache`` does).
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck import __version__
from kcheck.numerics.thresholds import CACHED_SYMMETRY_RTOL

if TYPE_CHECKING:
    import numpy as np

    from kcheck.result import Finding, MassProperties
    from kcheck.scene import Body

__all__ = [
    "CACHE_FOLDER",
    "FORMAT",
    "MassCache",
    "PlacementCache",
    "body_key",
    "body_mass_properties_cached",
    "mesh_body_key",
    "placement_key",
]

CACHE_FOLDER = ".kcheck_cache"
#: Format of an entry; raised whenever what an entry holds changes (2: bounds, part bounds
#: and mesh warnings added). An entry of another format is recomputed.
FORMAT = 2
_TAG = (
    "Signature: 8a477f597d28d172789f06886806bc55\n"
    "# This file is a cache directory tag created by kcheck.\n"
    "# For information about cache directory tags see https://bford.info/cachedir/\n"
)


def _sha256(data: bytes = b"") -> Any:
    import hashlib  # when a mesh's mass properties are cached: not on a meshless start-up

    return hashlib.sha256(data)


def _file_sha256(path: Path) -> str:
    digest = _sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _plain(value: Any) -> Any:
    """A JSON-able, deterministic form of a part field."""
    kind = type(value)
    # The plain leaves first, by exact type (none has ``tolist``: what the general path
    # below returns them as, unchanged); most of a key's values are these.
    if kind is float or kind is str or kind is int or kind is bool or value is None:
        return value
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
    """kcheck, trimesh, numpy and scipy versions and the source of what computes the values
    (``kcheck/body/*.py``) and of the limits they are gated by (``kcheck/scene/limits.py``)."""
    global _CODE_FINGERPRINT
    if _CODE_FINGERPRINT is None:
        import importlib.util

        from kcheck.plugin.dist_info import version

        digest = _sha256(__version__.encode())
        for dist in ("trimesh", "numpy", "scipy"):
            digest.update(f"|{dist} {version(dist) or '?'}".encode())
        sources: list[Path] = []
        body = importlib.util.find_spec("kcheck.body")
        if body is not None and body.submodule_search_locations:
            for folder in body.submodule_search_locations:
                sources.extend(sorted(Path(folder).glob("*.py")))
        limits = importlib.util.find_spec("kcheck.scene.limits")
        if limits is not None and limits.origin is not None:
            sources.append(Path(limits.origin))
        for source in sources:
            digest.update(f"|{source.name}|".encode() + source.read_bytes())
        _CODE_FINGERPRINT = digest.hexdigest()
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
        parts.append(
            {
                "sha256": _file_sha256(part.mesh),
                "name": part.mesh.name,
                # Warnings of reading the mesh point at the part's field: it is in the key.
                "field": _plain(part.field),
                "fields": fields,
            }
        )
    # Everything else the body carries (point masses, ...), whatever the scene format adds.
    rest = {
        f.name: _plain(getattr(body, f.name))
        for f in dataclasses.fields(body)
        if f.name not in ("parts", "explicit")
    }
    material = {
        "format": FORMAT,
        "code": _code_fingerprint(),
        "scale": scale,
        "parts": parts,
        "body": rest,
    }
    return _sha256(json.dumps(material, sort_keys=True).encode()).hexdigest()


def mesh_body_key(body: Body, scale: float, max_mesh_bytes: int | None) -> str | None:
    """:func:`body_key` of a body with meshes, their sizes checked first (a file past
    ``max_mesh_bytes`` is not read at all: :class:`~kcheck.errors.SceneError`); None when a
    mesh cannot be read (the computation then reports why, as without a cache)."""
    from kcheck.body.meshio import check_mesh_file  # meshes only (issue 24: start-up)

    for part in body.parts:
        check_mesh_file(part.mesh, (*part.field, "mesh"), max_mesh_bytes)
    try:
        return body_key(body, scale)
    except OSError:
        return None


def _checksum(payload: Any) -> str:
    return _sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


class MassCache:
    """Mass properties on disk under ``folder/mass/``."""

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)

    def _path(self, key: str) -> Path:
        return self.folder / "mass" / key[:2] / f"{key}.json"

    def get(self, key: str) -> MassProperties | None:
        """The entry for ``key``, or None when absent, unreadable, corrupt or implausible."""
        payload = _read_entry(self._path(key), FORMAT, key)
        try:
            return None if payload is None else _from_payload(payload)
        except (ValueError, KeyError, TypeError, AttributeError, IndexError):
            return None

    def put(self, key: str, mass: MassProperties) -> None:
        """Store an entry atomically; a cache that cannot be written is silently skipped."""
        _write_entry(self.folder, self._path(key), FORMAT, key, _to_payload(mass))


def _read_entry(path: Path, format: int | str, key: str) -> Any:
    """The payload of the cache entry at ``path``, or None when absent, unreadable, of another
    format (recomputed, never half-read), not ``key``'s or not matching its checksum."""
    try:
        entry = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(entry, dict) or entry.get("format") != format:
            return None
        payload = entry["payload"]
        if entry["key"] != key or entry["checksum"] != _checksum(payload):
            return None
        return payload
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _write_entry(folder: Path, path: Path, format: int | str, key: str, payload: Any) -> None:
    """Store a cache entry atomically (a temporary file renamed over ``path``), tagging the
    cache ``folder`` first; a cache that cannot be written is silently skipped."""
    import tempfile

    entry = {"format": format, "key": key, "checksum": _checksum(payload), "payload": payload}
    try:
        _prepare(folder)
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


def _prepare(folder: Path) -> None:
    """Create the cache folder with its CACHEDIR.TAG and a .gitignore of everything."""
    if (folder / "CACHEDIR.TAG").exists():
        return
    folder.mkdir(parents=True, exist_ok=True)
    (folder / ".gitignore").write_text("# Created by kcheck.\n*\n", encoding="utf-8")
    (folder / "CACHEDIR.TAG").write_text(_TAG, encoding="utf-8")


def _to_payload(mass: MassProperties) -> dict[str, Any]:
    return {
        "mass": mass.mass,
        "center_of_mass": mass.center_of_mass.tolist(),
        "inertia": mass.inertia.tolist(),
        "source": mass.source,
        "volume": mass.volume,
        "notes": list(mass.notes),
        "bounds": None if mass.bounds is None else mass.bounds.tolist(),
        "part_bounds": [b.tolist() for b in mass.part_bounds],
        "warnings": [_finding_payload(w) for w in mass.warnings],
    }


_PAYLOAD_KEYS = frozenset(
    ("mass", "center_of_mass", "inertia", "source", "volume", "notes")
    + ("bounds", "part_bounds", "warnings")
)
_FINDING_KEYS = ("message", "code", "field", "hint", "line", "column")


def _finding_payload(finding: Finding) -> dict[str, Any]:
    return {
        "message": finding.message,
        "code": finding.code,
        "field": None if finding.field is None else list(finding.field),
        "hint": finding.hint,
        "line": finding.line,
        "column": finding.column,
    }


def _text(value: Any, optional: bool = True) -> bool:
    return isinstance(value, str) or (optional and value is None)


def _integer(value: Any) -> bool:
    return value is None or (isinstance(value, int) and not isinstance(value, bool))


def _finding(value: Any) -> Finding | None:
    """A finding from its payload, or None unless it is exactly one."""
    from kcheck.result import Finding

    if not isinstance(value, dict) or set(value) != set(_FINDING_KEYS):
        return None
    field = value["field"]
    if field is not None and not (
        isinstance(field, list)
        and all(_text(p, False) or (_integer(p) and p is not None) for p in field)
    ):
        return None
    if not (
        _text(value["message"], False)
        and _text(value["code"])
        and _text(value["hint"])
        and _integer(value["line"])
        and _integer(value["column"])
    ):
        return None
    return Finding(
        value["message"],
        value["code"],
        None if field is None else tuple(field),
        value["hint"],
        value["line"],
        value["column"],
    )


def _box(value: Any) -> np.ndarray | None:
    """An axis-aligned box (rows min, max) from its payload, or None unless it is one."""
    import numpy as np

    box = np.asarray(value, dtype=float)
    if box.shape != (2, 3) or not np.all(np.isfinite(box)) or not np.all(box[0] <= box[1]):
        return None
    return box


def _from_payload(payload: Any) -> MassProperties | None:
    """The mass properties of an entry's payload; None unless it holds exactly the fields of
    this format, each of its type and physical."""
    import numpy as np

    from kcheck.result import MassProperties

    if not isinstance(payload, dict) or set(payload) != _PAYLOAD_KEYS:
        return None
    mass = float(payload["mass"])
    com = np.asarray(payload["center_of_mass"], dtype=float)
    inertia = np.asarray(payload["inertia"], dtype=float)
    volume = payload["volume"]
    notes = payload["notes"]
    bounds = None if payload["bounds"] is None else _box(payload["bounds"])
    part_bounds = [_box(b) for b in payload["part_bounds"]]
    warnings = [_finding(w) for w in payload["warnings"]]
    plausible = (
        np.isfinite(mass)
        and mass > 0
        and com.shape == (3,)
        and inertia.shape == (3, 3)
        and bool(np.all(np.isfinite(com)))
        and bool(np.all(np.isfinite(inertia)))
        # np.allclose(inertia, inertia.T, rtol=CACHED_SYMMETRY_RTOL, atol=0) of a finite
        # inertia (tested just above), written as its test: |x - y| <= rtol |y|, or equal.
        and bool(
            np.all(
                (np.abs(inertia - inertia.T) <= CACHED_SYMMETRY_RTOL * np.abs(inertia.T))
                | (inertia == inertia.T)
            )
        )
        and payload["source"] == "mesh"
        and (volume is None or (isinstance(volume, (int, float)) and volume > 0))
        and isinstance(notes, list)
        and all(isinstance(n, str) for n in notes)
        and (payload["bounds"] is None or bounds is not None)
        and all(b is not None for b in part_bounds)
        and all(w is not None for w in warnings)
    )
    if not plausible:
        return None
    return MassProperties(
        mass,
        com,
        inertia,
        "mesh",
        None if volume is None else float(volume),
        tuple(notes),
        bounds,
        tuple(w for w in warnings if w is not None),
        tuple(b for b in part_bounds if b is not None),
    )


#: Mass properties computed in this process, by body key (and mesh size limit), for callers
#: that check many variants of one body (:mod:`kcheck.gate.study`): its meshes are read once.
_MEMO: dict[tuple[str, int | None], MassProperties] = {}
MEMO_ENTRIES = 16


def body_mass_properties_cached(
    body: Body,
    scale: float,
    folder: Path | None,
    max_mesh_bytes: int | None = None,
    memo: bool = False,
    key: str | None = None,
) -> MassProperties:
    """:func:`kcheck.body.mass.body_mass_properties`, through the cache in ``folder`` when the
    body's mass properties come from meshes (None: no cache), and with ``memo`` through this
    process's memory first. ``key``: the body's :func:`body_key` when the caller has it
    already (its meshes are then not hashed again)."""
    from kcheck.body.mass import body_mass_properties

    if (folder is None and not memo) or body.explicit is not None or not body.parts:
        return body_mass_properties(body, scale, max_mesh_bytes)
    if key is None:
        key = mesh_body_key(body, scale, max_mesh_bytes)
        if key is None:  # a mesh cannot be read: let the computation report it
            return body_mass_properties(body, scale, max_mesh_bytes)
    if memo and (key, max_mesh_bytes) in _MEMO:
        return _MEMO[key, max_mesh_bytes]
    if folder is None:
        mass = body_mass_properties(body, scale, max_mesh_bytes)
    else:
        cache = MassCache(folder)
        hit = cache.get(key)
        if hit is not None:
            mass = hit
        else:
            mass = body_mass_properties(body, scale, max_mesh_bytes)
            cache.put(key, mass)
    if memo:
        if len(_MEMO) >= MEMO_ENTRIES:
            _MEMO.pop(next(iter(_MEMO)))
        _MEMO[key, max_mesh_bytes] = mass
    return mass


# -- the supports against the body's mesh ---------------------------------------------------

#: Format of a placement entry (:class:`PlacementCache`).
PLACEMENT_FORMAT = 1
#: What computes a placement's warnings besides ``kcheck/body/`` (in :func:`_code_fingerprint`):
#: their sources are in the key, so a changed rule or message never reads an old answer.
_PLACEMENT_SOURCES = (
    "kcheck.analysis.placement",
    "kcheck.fmt",
    "kcheck.result",
    "kcheck.scene.types",
    "kcheck.scene.units",
    "kcheck.numerics.thresholds",
)
_PLACEMENT_FINGERPRINT: str | None = None


def _placement_fingerprint() -> str:
    global _PLACEMENT_FINGERPRINT
    if _PLACEMENT_FINGERPRINT is None:
        import importlib.util

        digest = _sha256(_code_fingerprint().encode())
        for name in _PLACEMENT_SOURCES:
            spec = importlib.util.find_spec(name)
            if spec is not None and spec.origin is not None:
                digest.update(f"|{name}|".encode() + Path(spec.origin).read_bytes())
        _PLACEMENT_FINGERPRINT = digest.hexdigest()
    return _PLACEMENT_FINGERPRINT


def placement_key(body: str, scene: Any) -> str:
    """The cache key of the supports against a body's mesh
    (:func:`kcheck.analysis.placement.support_placement`): the body's :func:`body_key` and
    everything of the scene the placement reads: its kind, units, length scale and supports
    (every field: position, normal, coupling geometry, where each is written)."""
    material = {
        "format": PLACEMENT_FORMAT,
        "code": _placement_fingerprint(),
        "body": body,
        "kind": scene.kind,
        "units": scene.units,
        "scale": scene.scale,
        "supports": _plain(list(scene.supports)),
    }
    return _sha256(json.dumps(material, sort_keys=True).encode()).hexdigest()


class PlacementCache:
    """The warnings of the supports against a body's mesh on disk under
    ``folder/placement/``: a warm run reads no mesh for them. Only placements without errors
    are stored (errors are never cached). An entry is trusted as a mass entry is (its format,
    its own key, its checksum, exactly its fields)."""

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)

    def _path(self, key: str) -> Path:
        return self.folder / "placement" / key[:2] / f"{key}.json"

    def get(self, key: str) -> tuple[Finding, ...] | None:
        """The warnings stored for ``key``, or None when absent, unreadable or corrupt."""
        payload = _read_entry(self._path(key), PLACEMENT_FORMAT, key)
        try:
            if not isinstance(payload, dict) or set(payload) != {"warnings"}:
                return None
            warnings = [_finding(w) for w in payload["warnings"]]
            if any(w is None for w in warnings):
                return None
            return tuple(w for w in warnings if w is not None)
        except (OSError, ValueError, KeyError, TypeError, AttributeError, IndexError):
            return None

    def put(self, key: str, warnings: tuple[Finding, ...]) -> None:
        """Store an entry atomically; a cache that cannot be written is silently skipped."""
        payload = {"warnings": [_finding_payload(w) for w in warnings]}
        _write_entry(self.folder, self._path(key), PLACEMENT_FORMAT, key, payload)
