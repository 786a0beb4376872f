"""Reading mesh files for mass properties: any format trimesh reads, STEP through the optional
``step`` extra (cascadio, OpenCASCADE, which converts the file's declared unit to metres),
scaled to metres, with vertices closer than a millionth of the mesh's size merged (STEP
tessellations and some STL exports repeat them per face), and the open edges of a mesh that
is not watertight located. trimesh is imported only inside these functions.
"""

from __future__ import annotations

import contextlib
import functools
import importlib.util
import io
import os
import re
import stat
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.body.mesh_edges import Edges, edges_of
from kcheck.errors import FieldPath, MeshError, describe_os_error
from kcheck.numerics.thresholds import EPS, MERGE_RTOL
from kcheck.records import dataclass
from kcheck.scene.limits import LIMITS

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "MERGE_RTOL",
    "MAX_MESH_BYTES",
    "STEP_INSTALL",
    "check_mesh_file",
    "load_mesh",
    "load_surface",
    "Surface",
    "load_triangles",
    "not_watertight",
    "release_memory",
    "reuse_freed_memory",
    "stl_triangle_count",
    "step_length_unit",
]

#: Largest mesh file read by default (configuration ``max_mesh_size``). Reading and checking
#: a binary STL takes about 12 times the file's size above the imports (a 15.6 MiB file peaks
#: at 340 MiB, a 62.5 MiB one at 862 MiB: benchmarks/bench_mesh_memory.py), so this keeps a
#: mesh well within the default memory budget of a scene (2 GiB).
MAX_MESH_BYTES = 64 * 2**20
#: Vertices farther from the origin are refused (the scene's coordinate limit, in m).
MAX_COORDINATE_M = LIMITS["coordinate"].high
STEP_INSTALL = "pip install 'kcheck[step]'"

#: A STEP file's length unit, as its text declares it (compiled on first use: re.I patterns
#: cost milliseconds, and most runs read no STEP file).
_STEP_UNIT_PATTERNS = (
    (r"SI_UNIT\s*\(\s*\.MILLI\.\s*,\s*\.METRE\.\s*\)", "mm"),
    (r"SI_UNIT\s*\(\s*\.CENTI\.\s*,\s*\.METRE\.\s*\)", "cm"),
    (r"SI_UNIT\s*\(\s*\.MICRO\.\s*,\s*\.METRE\.\s*\)", "um"),
    (r"CONVERSION_BASED_UNIT\s*\(\s*'INCH'", "in"),
    (r"CONVERSION_BASED_UNIT\s*\(\s*'(?:FOOT|FEET)'", "ft"),
    (r"SI_UNIT\s*\(\s*\$\s*,\s*\.METRE\.\s*\)", "m"),
)


@functools.cache
def _step_units() -> tuple[tuple[re.Pattern[str], str], ...]:
    return tuple((re.compile(rx, re.I), unit) for rx, unit in _STEP_UNIT_PATTERNS)


def step_length_unit(path: Path) -> str | None:
    """The length unit a STEP file declares (``mm``, ``in``, ...), from its text, or None.

    Only for reporting: OpenCASCADE applies the unit itself when it converts to metres. The
    unit is the LENGTH_UNIT among the representation context's assigned units.
    """
    try:
        with open(path, "rb") as handle:
            text = handle.read(8 << 20).decode("latin-1")
    except OSError:
        return None
    context = re.search(r"GLOBAL_UNIT_ASSIGNED_CONTEXT\s*\(\s*\(([^)]*)\)", text, re.I)
    candidates = []
    if context:
        for ref in re.findall(r"#\d+", context.group(1)):
            entity = re.search(rf"{ref}\s*=\s*([^;]*);", text)
            if entity and re.search(r"LENGTH_UNIT", entity.group(1), re.I):
                candidates.append(entity.group(1))
    candidates.append(text)  # no context found: the first unit named anywhere
    for candidate in candidates:
        found = [(m.start(), unit) for rx, unit in _step_units() if (m := rx.search(candidate))]
        if found:
            return min(found)[1]
    return None


#: Odd 64-bit multipliers mixing a vertex's three rounded coordinates into one sort key.
_MIX = (np.uint64(0x9E3779B97F4A7C15), np.uint64(0xC2B2AE3D27D4EB4F))


def _sorted_with_ids(key: np.ndarray, bits: int) -> np.ndarray:
    """Keys (uint64) with their ids (0..n-1, ``bits`` wide) in the low bits, sorted: ids by
    the keys' high bits, ties by id (a stable order), through numpy's sort of plain integers
    (twice as fast as an argsort)."""
    low = np.uint64((1 << bits) - 1)
    packed = (key & ~low) | np.arange(len(key), dtype=np.uint64)
    packed.sort()
    return packed


def _equal_runs(q: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Rows of integer columns ``q`` (three, n each) in an order that puts equal rows next to
    each other, each run led by its first row, and where each run starts: one sort of a
    64-bit mix of each row (a third of a lexsort's time), checked column by column; a
    lexsort when two different rows mix alike."""
    n = len(q[0])
    bits = max(1, (n - 1).bit_length())
    u = [c.view(np.uint64) for c in q]
    with np.errstate(over="ignore"):
        # A polynomial, not a xor of products: xor collides on a grid's coordinates.
        h = (u[0] * _MIX[0] + u[1]) * _MIX[1] + u[2]
        # splitmix64's finaliser (a bijection): every bit of the mix moves the high bits the
        # sort compares first.
        h ^= h >> np.uint64(30)
        h *= np.uint64(0xBF58476D1CE4E5B9)
        h ^= h >> np.uint64(27)
        h *= np.uint64(0x94D049BB133111EB)
        h ^= h >> np.uint64(31)
    packed = _sorted_with_ids(h, bits)
    order = (packed & np.uint64((1 << bits) - 1)).view(np.int64)
    high = packed >> np.uint64(bits)
    start = np.empty(n, bool)
    start[0] = True
    np.not_equal(high[1:], high[:-1], out=start[1:])
    for c in q:
        s = c[order]
        mixed_alike = ~start[1:] & (s[1:] != s[:-1])
        if np.any(mixed_alike):  # two different rows mixed alike (or alike in high bits)
            order = np.lexsort((q[2], q[1], q[0]))
            rows = np.column_stack(q)[order]
            return order, np.r_[True, np.any(rows[1:] != rows[:-1], axis=1)]
    return order, start


def _merged_equal(
    vertices: np.ndarray, faces: np.ndarray, soup: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The vertices kept and the new id of every vertex when vertices equal once rounded to
    1e-8 (m) are joined: what trimesh's ``process()`` does to a mesh without texture
    coordinates or vertex normals (the same vertices in the same order, each group kept at
    its first occurrence, unreferenced vertices dropped). ``soup``: every vertex is known
    to be used (an STL's, three per face), so nothing is counted."""
    if soup:
        ref, every = np.zeros(0, np.int64), True
    else:
        ref = np.flatnonzero(np.bincount(faces.ravel(), minlength=len(vertices)) > 0)
        every = len(ref) == len(vertices)  # an STL's soup: no gathers through ``ref``
    used = vertices if every else vertices[ref]
    q = []
    for k in range(3):
        # Cast to integers, as trimesh does: their bits mix densely (a whole float's low
        # mantissa bits are zeros, and mixed they collided on this file's vertices).
        column = used[:, k] * 1e8
        q.append(np.round(column, out=column).astype(np.int64))
    order, start = _equal_runs(q)
    first = order[start]
    # Merged vertices numbered by first occurrence, as trimesh keeps them.
    leads = np.zeros(len(used), bool)
    leads[first] = True
    kept = np.flatnonzero(leads)
    rank = (np.cumsum(leads) - 1)[first]
    inverse = np.zeros(len(vertices), np.int64)
    inverse[order if every else ref[order]] = rank[np.cumsum(start) - 1]
    return (kept if every else ref[kept]), inverse


def _merge_equal(mesh: trimesh.Trimesh) -> None:
    """Join the vertices equal once rounded to 1e-8 (m), in place (:func:`_merged_equal`)."""
    vertices, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    if len(vertices) == 0 or len(faces) == 0:
        return
    keep, inverse = _merged_equal(vertices, faces)
    with mesh._cache:
        mesh.update_vertices(mask=keep, inverse=inverse)
        mesh._cache.clear(exclude={"face_normals", "vertex_normals"})
    mesh.metadata["processed"] = True


#: A direction along no axis or diagonal of a CAD part, to sweep vertices along: its
#: components in no small integer ratio (an earlier (3, 2, 1) direction projected the points
#: of a regular grid onto the same values, 3 candidate pairs per vertex on a tessellated
#: plate against 0.5 along this one).
_SWEEP = np.array([0.7946433181949646, 0.5145659500691985, 0.3221240131959728])


def _close_pairs(vertices: np.ndarray, tolerance: float) -> np.ndarray:
    """Pairs of vertex ids (k, 2) at most ``tolerance`` apart (m): a sweep along one direction
    (vertices nearer than the tolerance are nearer than it along any direction), each
    candidate pair measured; scipy's KD-tree when the sweep finds too many candidates."""
    n = len(vertices)
    along = vertices @ _SWEEP
    order = np.argsort(along)
    s = along[order]
    # A little beyond the tolerance: the projection's rounding must not lose a pair.
    reach = tolerance * (1 + 1e-9) + 4 * EPS * float(np.abs(s).max(initial=0))
    count = np.searchsorted(s, s + reach, side="right") - np.arange(n) - 1
    total = int(count.sum())
    if total > 20 * n:
        from scipy.spatial import cKDTree

        return np.asarray(cKDTree(vertices).query_pairs(tolerance, output_type="ndarray"))
    i = np.repeat(np.arange(n), count)
    j = i + 1 + np.arange(total) - np.repeat(np.cumsum(count) - count, count)
    a, b = order[i], order[j]
    d = vertices[a] - vertices[b]
    close = np.einsum("ij,ij->i", d, d) <= tolerance**2
    return np.column_stack([a[close], b[close]])


def _merged_close(
    vertices: np.ndarray, faces: np.ndarray, tolerance: float
) -> tuple[np.ndarray, np.ndarray, int]:
    """The vertices and faces with vertices closer than ``tolerance`` (m) joined (each group
    at its first vertex, faces that collapse dropped), and how many were joined."""
    pairs = _close_pairs(vertices, tolerance)
    if len(pairs) == 0:
        return vertices, faces, 0
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    n = len(vertices)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    count, labels = connected_components(graph, directed=False)
    first = np.full(count, n)
    np.minimum.at(first, labels, np.arange(n))
    f = labels[faces]
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    return vertices[first], f[keep], n - count


def _merge_close(mesh: trimesh.Trimesh, tolerance: float) -> tuple[trimesh.Trimesh, int]:
    """The mesh with vertices closer than ``tolerance`` (m) joined, and how many were."""
    import trimesh

    vertices, faces, merged = _merged_close(
        np.asarray(mesh.vertices), np.asarray(mesh.faces), tolerance
    )
    if not merged:
        return mesh, 0
    return trimesh.Trimesh(vertices, faces, process=False), merged


def check_mesh_file(path: Path, field: FieldPath | str, max_bytes: int | None = None) -> None:
    """MeshError unless ``path`` is a regular file of at most ``max_bytes`` (default
    :data:`MAX_MESH_BYTES`): a pipe or device could block or never end, and a mesh file's
    size bounds the memory and time reading it takes (about 12 times its size in memory)."""
    limit = MAX_MESH_BYTES if max_bytes is None else max_bytes
    try:
        info = os.stat(path)
    except OSError as exc:
        raise MeshError(
            path, f"cannot read the mesh ({describe_os_error(exc)})", field=field
        ) from None
    if not stat.S_ISREG(info.st_mode):
        raise MeshError(path, "not a regular file (a folder, pipe, socket or device)", field=field)
    if info.st_size > limit:
        raise MeshError(
            path,
            f"the mesh file is {_size(info.st_size)}, more than the limit of {_size(limit)} "
            "(configuration `max_mesh_size`); simplify the mesh, or raise the limit",
            field=field,
        )


def _size(n: int) -> str:
    return f"{n / 2**20:.1f} MiB" if n >= 2**20 else f"{n} bytes"


def _read(
    path: Path, field: FieldPath | str, max_bytes: int | None = None, part: str | None = None
) -> trimesh.Trimesh:
    import trimesh

    check_mesh_file(path, field, max_bytes)
    if path.suffix.lower() in (".step", ".stp") and importlib.util.find_spec("cascadio") is None:
        raise MeshError(
            path,
            f"STEP files need the optional `step` extra (OpenCASCADE via cascadio): {STEP_INSTALL}",
            field=field,
        )
    step = path.suffix.lower() in (".step", ".stp")
    try:
        with _captured_output() if step else contextlib.nullcontext() as said:
            # Unprocessed: trimesh's vertex merging casts coordinates times 1e8 to integers,
            # which overflows (with a RuntimeWarning) on huge or non-finite ones; they are
            # refused first, and the mesh processed after (load_mesh). Face normals stored
            # in the file are cast as read; NaN ones (a damaged file) would warn, and kcheck
            # never uses them.
            with np.errstate(invalid="ignore", over="ignore"):
                scene = trimesh.load_scene(str(path), process=False)
            mesh = _single_mesh(scene) if part is None else _named_part(scene, part)
    except MeshError as exc:
        raise MeshError(path, exc.message, field=field) from None
    except MemoryError:  # the scene's memory budget, not a bad file: the gate reports it
        raise
    except Exception as exc:  # trimesh raises many types for unreadable files
        if step:
            # OpenCASCADE writes its reason to the terminal and trimesh then fails to
            # open the conversion it expected: the reason is OpenCASCADE's.
            reason = _occ_reason(said.getvalue() if said else "") or "no solid found"
            raise MeshError(
                path, f"cannot read the STEP file (OpenCASCADE: {reason})", field=field
            ) from exc
        # What kcheck expected first: trimesh's reason alone is often an internal detail
        # ("IndexError: list index out of range"), and its wording is trimesh's.
        kind = path.suffix.lstrip(".").upper() or "mesh"
        raise MeshError(
            path,
            f"cannot read the mesh: not a valid {kind} file (trimesh: {type(exc).__name__}: {exc})",
            field=field,
        ) from exc
    if mesh.is_empty or len(mesh.faces) == 0:
        raise MeshError(path, "the mesh is empty (no triangles)", field=field)
    return mesh


def _single_mesh(scene: trimesh.Scene) -> trimesh.Trimesh:
    """The scene's one mesh as it is when it is alone and not moved (an STL, OBJ, PLY file);
    otherwise every mesh baked into one with its transform (glTF, 3MF, STEP assemblies).
    Taking the lone mesh saves the copy baking makes: on a 16 MB STL, 75 of 140 MB."""
    import trimesh

    geometry = list(scene.geometry.values())
    nodes = scene.graph.nodes_geometry
    if len(geometry) == 1 and isinstance(geometry[0], trimesh.Trimesh) and len(nodes) == 1:
        transform, _ = scene.graph[nodes[0]]
        if np.array_equal(transform, np.eye(4)):
            return geometry[0]
    return scene.to_mesh()


def _named_part(scene: trimesh.Scene, name: str) -> trimesh.Trimesh:
    """The part called ``name`` in an assembly (a node's or its geometry's name: STEP,
    glTF, 3MF), every instance of it moved by its transform and baked into one mesh;
    MeshError listing the names there are when none is called so."""
    import trimesh

    graph = scene.graph
    nodes = [n for n in graph.nodes_geometry if name in (n, graph[n][1])]
    if not nodes:
        names = sorted({str(g) for g in scene.geometry} | set(graph.nodes_geometry))
        raise MeshError("", f"no part named `{name}`; the parts are: {', '.join(names)}")
    meshes = []
    for node in nodes:
        transform, geometry = graph[node]
        mesh = scene.geometry[geometry]
        if isinstance(mesh, trimesh.Trimesh):
            meshes.append(mesh.copy().apply_transform(transform))
    if not meshes:
        raise MeshError("", f"the part `{name}` has no triangles")
    baked: Any = meshes[0] if len(meshes) == 1 else trimesh.util.concatenate(meshes)
    return baked


@contextlib.contextmanager
def _captured_output() -> Iterator[io.StringIO]:
    """Capture what native code writes to the process's standard output and error (file
    descriptors 1 and 2) while the block runs: OpenCASCADE prints its diagnostics there,
    which would corrupt a JSON report on stdout."""
    said = io.StringIO()
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    with tempfile.TemporaryFile() as sink:
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield said
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
            sink.seek(0)
            said.write(sink.read(1 << 16).decode("utf-8", "replace"))


def _occ_reason(text: str) -> str:
    """The first diagnostic line OpenCASCADE printed, without colour codes and stars."""
    for line in re.sub(r"\x1b\[[0-9;]*m", "", text).splitlines():
        line = line.strip(" *\t")
        if line:
            return line[:200]
    return ""


def _check_finite(vertices: np.ndarray, path: Path, field: FieldPath | str) -> None:
    if not np.all(np.isfinite(vertices)):
        raise MeshError(path, "the mesh has non-finite vertex coordinates", field=field)


def _check_reach(vertices: np.ndarray, path: Path, field: FieldPath | str) -> None:
    largest = max(float(vertices.max()), -float(vertices.min()))
    if not largest <= MAX_COORDINATE_M:
        raise MeshError(
            path,
            f"the mesh reaches {largest:.3g} m from the origin, beyond {MAX_COORDINATE_M:g} m "
            "(are the units right?)",
            field=field,
        )


def load_mesh(
    path: Path,
    scale: float,
    field: FieldPath | str,
    *,
    max_bytes: int | None = None,
    part: str | None = None,
) -> trimesh.Trimesh:
    """Load a mesh file as one Trimesh scaled to metres (``scale`` metres per file unit), with
    vertices closer than ``MERGE_RTOL`` of its size merged; MeshError if it is unusable or
    larger than ``max_bytes`` (default :data:`MAX_MESH_BYTES`). With ``part``, only the part
    of that name in an assembly file, placed by its transform (:func:`_named_part`)."""
    mesh = _read(path, field, max_bytes, part)
    _check_finite(np.asarray(mesh.vertices), path, field)
    with np.errstate(over="ignore"):
        # In place: apply_scale would build the scaled vertices and normals anew (+48 MB on a
        # 16 MB STL); normals do not change under a uniform scale.
        mesh.vertices *= scale
    _check_reach(np.asarray(mesh.vertices), path, field)
    if path.suffix.lower() == ".stl":
        # An STL has no texture coordinates or vertex normals, so trimesh's merge is a merge
        # of positions alone: the same result, in the same order, 2.4 times faster.
        _merge_equal(mesh)
    else:
        mesh.process()
    extent = float(np.ptp(mesh.vertices, axis=0).max())
    if extent > 0:
        mesh, merged = _merge_close(mesh, MERGE_RTOL * extent)
        if merged:
            mesh.metadata["kcheck_merged"] = merged
    return mesh


@dataclass
class Surface:
    """A triangle mesh as the contact finder uses it: vertices (n, 3, m) and faces (vertex
    ids, k × 3), and ``merged``, how many vertices were joined for being closer than
    ``MERGE_RTOL`` of its size; ``mesh``, the Trimesh it was read as, if it was."""

    vertices: np.ndarray
    faces: np.ndarray
    merged: int = 0
    mesh: Any = None

    @functools.cached_property
    def edges(self) -> Edges:
        """The faces' shared edges (pairs of faces, closedness)."""
        return edges_of(self.faces)

    @property
    def is_watertight(self) -> bool:
        """Every edge shared by exactly two faces (trimesh's ``is_watertight``)."""
        return self.edges.closed

    @functools.cached_property
    def bounds(self) -> np.ndarray:
        """The lowest and highest corner (2, 3, m) of the vertices the faces use."""
        used = np.zeros(len(self.vertices), bool)
        used[self.faces] = True
        v = self.vertices[used]
        return np.array([v.min(axis=0), v.max(axis=0)])

    def trimesh(self) -> trimesh.Trimesh:
        """As a Trimesh: the one it was read as, or one made of its arrays."""
        if self.mesh is None:
            import trimesh

            self.mesh = trimesh.Trimesh(self.vertices, self.faces, process=False)
        return self.mesh


_STL_RECORD = np.dtype([("normal", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("extra", "<u2")])


def stl_triangle_count(head: bytes, size: int) -> int | None:
    """The triangles of a binary STL file from its first 84 bytes ``head`` and its length
    ``size`` (bytes), or None when it is no binary STL with triangles (ASCII, a length its
    header does not announce, or empty), as trimesh tells them apart."""
    if len(head) < 84:
        return None
    count = int.from_bytes(head[80:84], "little")
    if count == 0 or 84 + _STL_RECORD.itemsize * count != size:
        return None
    return count


def _binary_stl(path: Path, field: FieldPath | str) -> np.ndarray | None:
    """The vertices (3 per face, float32) of a binary STL file, or None when the file is no
    binary STL with triangles (ASCII, a length its header does not announce, or empty), as
    trimesh tells them apart."""
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as exc:
        raise MeshError(
            path, f"cannot read the mesh ({describe_os_error(exc)})", field=field
        ) from None
    count = stl_triangle_count(data[:84], len(data))
    if count is None:
        return None
    records = np.frombuffer(data, _STL_RECORD, count, 84)
    return np.ascontiguousarray(records["vertices"]).reshape(-1, 3)


def load_surface(
    path: Path,
    scale: float,
    field: FieldPath | str,
    *,
    max_bytes: int | None = None,
    part: str | None = None,
) -> Surface:
    """:func:`load_mesh`'s vertices and faces, as a :class:`Surface`. A binary STL is read by
    kcheck itself (without importing trimesh, 0.2 s of a start): the same vertices and faces
    as :func:`load_mesh` (a test compares them); any other file goes through it."""
    if part is None and path.suffix.lower() == ".stl":
        check_mesh_file(path, field, max_bytes)
        raw = _binary_stl(path, field)
        if raw is not None:
            _check_finite(raw, path, field)
            vertices = raw.astype(np.float64)
            with np.errstate(over="ignore"):
                vertices *= scale
            _check_reach(vertices, path, field)
            faces = np.arange(len(vertices), dtype=np.int64).reshape(-1, 3)
            keep, inverse = _merged_equal(vertices, faces, soup=True)
            vertices, faces = vertices[keep], inverse[faces]
            merged = 0
            extent = float(np.ptp(vertices, axis=0).max())
            if extent > 0:
                vertices, faces, merged = _merged_close(vertices, faces, MERGE_RTOL * extent)
            return Surface(vertices, faces, merged)
    mesh = load_mesh(path, scale, field, max_bytes=max_bytes, part=part)
    return Surface(
        np.asarray(mesh.vertices),
        np.asarray(mesh.faces),
        int(mesh.metadata.get("kcheck_merged", 0)),
        mesh,
    )


def load_triangles(
    path: Path, scale: float, field: FieldPath | str, most: int, *, max_bytes: int | None = None
) -> np.ndarray:
    """About ``most`` triangles (t, 3, 3) of a mesh file, every k-th face, in metres, for a
    picture: read without processing (no vertex merge, no checks), so drawing a large mesh
    costs its reading alone (a 16 MB STL: 65 MB, where :func:`load_mesh` takes 200 MB)."""
    mesh = _read(path, field, max_bytes)
    step = max(1, -(-len(mesh.faces) // max(1, most)))
    with np.errstate(all="ignore"):
        return np.asarray(mesh.vertices)[np.asarray(mesh.faces)[::step]] * scale


def release_memory(collect: bool = False) -> None:
    """Give the memory freed after reading a mesh back to the system (glibc's ``malloc_trim``,
    5 µs); with ``collect``, cyclic garbage first (``gc.collect``, tens of ms: for large
    meshes only).

    glibc raises its mmap threshold after the first large arrays are freed, so a mesh's later
    arrays come from the heap and stay in the process when freed: after a 16 MB STL, 160 MB
    more than before reading it, which the checks' pictures then add to. A no-op where the C
    library has no ``malloc_trim``."""
    if collect:
        import gc

        gc.collect()
    trim = _malloc_trim()
    if trim is not None:
        trim(0)


def reuse_freed_memory() -> None:
    """Keep the memory of freed large arrays in the process for the next ones (glibc's
    ``mallopt``: no mmap threshold below 1 GiB, no trimming until a release_memory call, the
    heap grown 64 MB at a time).

    glibc maps arrays above 32 MB afresh and unmaps them when freed, so every such temporary
    costs its pages' zero-filling again: on two 500,000-face meshes, ``kcheck contacts``
    spent 0.5 s of system time so, for no higher peak memory when reused. A no-op where the
    C library has no ``mallopt``."""
    mallopt = _libc_function("mallopt")
    if mallopt is not None:
        mallopt(-3, 1 << 30)  # M_MMAP_THRESHOLD
        mallopt(-1, 2**31 - 1)  # M_TRIM_THRESHOLD
        mallopt(-2, 64 << 20)  # M_TOP_PAD: grow the heap in large steps
        # One arena for every thread (two files are read at once): a thread's own arena
        # would map its large arrays afresh and keep them (a third more peak memory).
        mallopt(-8, 1)  # M_ARENA_MAX


@functools.cache
def _libc_function(name: str) -> Any:
    import ctypes

    try:
        return getattr(ctypes.CDLL(None), name)  # the C library kcheck runs on (glibc)
    except (OSError, AttributeError):
        return None


@functools.cache
def _malloc_trim() -> Any:
    import ctypes

    try:
        return ctypes.CDLL(None).malloc_trim  # the C library kcheck runs on (glibc)
    except (OSError, AttributeError):
        return None


def _holes(mesh: trimesh.Trimesh) -> list[tuple[np.ndarray, float, int]]:
    """Open boundaries: (centre in m, size in m, number of edges), largest first."""
    import trimesh
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    single = trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)
    edges = mesh.edges_sorted[single]
    if len(edges) == 0:
        return []
    n = len(mesh.vertices)
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    out = []
    for label in np.unique(labels[edges[:, 0]]):
        loop = edges[labels[edges[:, 0]] == label]
        points = mesh.vertices[np.unique(loop)]
        size = float(np.linalg.norm(np.ptp(points, axis=0)))
        out.append((points.mean(axis=0), size, len(loop)))
    return sorted(out, key=lambda h: -h[1])


def not_watertight(
    mesh: trimesh.Trimesh, path: Path, field: FieldPath | str, scale: float, units: str
) -> MeshError:
    """The located error for an open mesh: how many open edges, where the largest hole is."""
    _, counts = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
    holes = _holes(mesh)
    open_edges = sum(h[2] for h in holes)
    crowded = int(np.count_nonzero(counts > 2))
    parts = []
    if holes:
        centre, size, _ = holes[0]
        c = ", ".join(f"{v:.4g}" for v in np.round(centre / scale, 12) + 0.0)
        parts.append(
            f"{open_edges} open edge(s) in {len(holes)} hole(s); the largest is centred at "
            f"({c}) {units} in the file's coordinates, {size / scale:.4g} {units} across"
        )
    if crowded:
        parts.append(f"{crowded} edge(s) shared by more than two faces")
    return MeshError(
        path,
        "the mesh is not watertight (" + "; ".join(parts) + "), so it encloses no volume and "
        "has no meaningful centre of mass; close it in CAD and export again, or set "
        "`repair: true` to let kcheck merge vertices, fix the winding and fill small holes",
        field=field,
    )
