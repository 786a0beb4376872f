"""The edges a triangle mesh's faces share: the pairs of faces across each edge, and whether
the mesh is closed (every edge shared by exactly two faces, trimesh's ``is_watertight``), from
one sort of integer edge keys over the faces' vertex ids."""

from __future__ import annotations

import numpy as np

from kcheck.records import dataclass

__all__ = ["Closure", "Edges", "closure_of", "edges_of", "face_pairs"]


@dataclass(frozen=True)
class Edges:
    """Pairs of faces (k, 2) sharing an edge, an edge of three or more faces chained pairwise;
    ``closed``: every edge is shared by exactly two faces; ``manifold``: none by more."""

    pairs: np.ndarray
    closed: bool
    manifold: bool


def _keys(faces: np.ndarray) -> np.ndarray:
    """One integer per face edge (face k's edges at 3k, 3k+1, 3k+2), the same for the two
    directions of an edge."""
    f = faces.astype(np.int64)
    first, second = f.ravel(), np.roll(f, -1, axis=1).ravel()
    return np.minimum(first, second) * (int(f.max(initial=0)) + 1) + np.maximum(first, second)


@dataclass(frozen=True)
class Closure:
    """What a mesh's faces alone say of it: its shared edges, whether it is watertight
    (trimesh's ``is_watertight``) and whether each shared edge runs opposite ways in its two
    faces (trimesh's ``is_winding_consistent``, which only means that for a watertight mesh)."""

    edges: Edges
    watertight: bool
    consistent: bool


def closure_of(faces: np.ndarray, *, empty: bool = False) -> Closure:
    """:class:`Closure` of faces given by vertex ids (n, 3): the answers of trimesh's
    ``is_watertight`` and ``is_winding_consistent`` from one sort (no faces: both, as
    trimesh says of a mesh with vertices but no faces; ``empty``: the mesh has neither, and
    trimesh says neither)."""
    faces = np.asarray(faces)
    edges, order, same = _edges(faces)
    if empty:
        return Closure(edges, False, False)
    f = faces.astype(np.int64)
    first, second = f.ravel(), np.roll(f, -1, axis=1).ravel()
    # trimesh: in each pair of equal edges, the first one's end is the second one's start
    consistent = bool(np.all(second[order[:-1][same]] == first[order[1:][same]]))
    return Closure(edges, edges.closed, consistent)


def edges_of(faces: np.ndarray) -> Edges:
    """The shared edges of faces given by vertex ids (n, 3)."""
    return _edges(faces)[0]


def _edges(faces: np.ndarray) -> tuple[Edges, np.ndarray, np.ndarray]:
    """:func:`edges_of`, with the face edges' ids in key order and where a key equals the next."""
    key = _keys(faces)
    bits = max(1, (len(key) - 1).bit_length())
    if len(key) and int(key.max()) < 1 << (63 - bits):
        # The edge's id packed below its key: a plain sort (twice as fast as an argsort)
        # gives the keys in order and, in the low bits, where each came from.
        packed = (key << bits) | np.arange(len(key), dtype=np.int64)
        packed.sort()
        order, s = packed & ((1 << bits) - 1), packed >> bits
    else:
        order = np.argsort(key)
        s = key[order]
    same = s[1:] == s[:-1]
    pairs = np.column_stack([order[:-1][same] // 3, order[1:][same] // 3])
    # Runs of equal keys: a run of one is an open edge, of three or more a crowded one.
    manifold = not np.any(same[1:] & same[:-1])
    closed = manifold and len(s) % 2 == 0 and bool(np.all(s[0::2] == s[1::2]))
    return Edges(pairs, closed, manifold), order, same


def face_pairs(faces: np.ndarray) -> np.ndarray:
    """Pairs of faces (k, 2) sharing an edge (the same two vertex ids), from the faces'
    vertex ids (n, 3); an edge of three or more faces chains them pairwise."""
    return edges_of(faces).pairs
