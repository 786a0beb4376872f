"""Broken meshes (kind ``mesh``): a fixture scene whose mesh file is truncated, garbage, open,
inverted, flat, NaN, huge, mislabelled or STEP garbage."""

from __future__ import annotations

import copy
import random
import struct
from collections.abc import Callable

import numpy as np

from tests.fuzz.contract import fmt_path
from tests.fuzz.model import ANY, Case, Claim, Entry, Expect, Sparse
from tests.fuzz.scenes import Fixture, dump, fixtures

__all__ = ["mesh_case", "binary_stl", "triangles"]

BAD = Expect("invalid", ())  # filled in with the mesh field by mesh_case
STL = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])


def triangles(raw: bytes) -> np.ndarray:
    """Triangles of a binary STL, shape (n, 3, 3)."""
    count = struct.unpack("<I", raw[80:84])[0]
    return np.frombuffer(raw[84 : 84 + 50 * count], dtype=STL)["v"].astype(float)


def binary_stl(tris: np.ndarray, count: int | None = None) -> bytes:
    """A binary STL of triangles (n, 3, 3); ``count`` overrides the header's count."""
    rec = np.zeros(len(tris), dtype=STL)
    with np.errstate(all="ignore"):
        rec["v"] = tris.astype("<f4")
    n = len(tris) if count is None else count
    return b"kcheck fuzz".ljust(80, b" ") + struct.pack("<I", n) + rec.tobytes()


def ascii_stl(tris: np.ndarray) -> str:
    out = ["solid fuzz"]
    for t in tris:
        out.append(" facet normal 0 0 0\n  outer loop")
        out.extend(f"   vertex {a!r} {b!r} {c!r}" for a, b, c in t)
        out.append("  endloop\n endfacet")
    out.append("endsolid fuzz")
    return "\n".join(out) + "\n"


def _icosphere(subdivisions: int, radius: float) -> np.ndarray:
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
    return np.asarray(sphere.triangles)


Broken = tuple[str, Entry, Expect, str]  # suffix, file, expectation, what


def _truncated(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    cut = rng.randrange(len(raw))
    return ".stl", raw[:cut], ANY, f"binary STL cut at byte {cut} of {len(raw)}"


def _garbage(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    n = rng.choice((0, 1, 83, 84, 134, 1000, 100_000))
    data = rng.randbytes(n)
    if n >= 84 and rng.random() < 0.5:
        data = data[:80] + struct.pack("<I", (n - 84) // 50) + data[84:]
    return ".stl", data, BAD, f"{n} random bytes"


def _counts(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    count = rng.choice((len(t) + 1, len(t) * 2, 2**31, 2**32 - 1, 0))
    return ".stl", binary_stl(t, count), ANY, f"header claims {count} triangles, has {len(t)}"


def _open(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    k = rng.randint(1, max(1, len(t) // 3))
    keep = sorted(rng.sample(range(len(t)), len(t) - k))
    return ".stl", binary_stl(t[keep]), BAD, f"{k} faces removed (open)"


def _inverted(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    return ".stl", binary_stl(t[:, ::-1, :]), BAD, "every face wound inwards"


def _inconsistent(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    t = t.copy()
    i = rng.randrange(len(t))
    t[i] = t[i][::-1]
    return ".stl", binary_stl(t), BAD, f"face {i} wound the other way"


def _flat(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    t = t.copy()
    axis = rng.randrange(3)
    t[:, :, axis] = 0.0
    return ".stl", binary_stl(t), BAD, f"axis {axis} flattened (no volume)"


def _non_finite(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    t = t.copy()
    value = rng.choice((np.nan, np.inf, -np.inf))
    t[rng.randrange(len(t)), rng.randrange(3), rng.randrange(3)] = value
    if rng.random() < 0.5:
        return ".stl", ascii_stl(t).encode(), BAD, f"ASCII STL with a {value} coordinate"
    return ".stl", binary_stl(t), BAD, f"a {value} coordinate"


def _scaled(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    k = rng.choice((-300, -200, -100, -40, -20, -12, 6, 12, 20, 30, 38))
    scaled = t * 10.0**k
    if abs(k) > 36:  # past float32: written as ASCII text
        return ".stl", ascii_stl(scaled).encode(), ANY, f"ASCII STL scaled by 1e{k}"
    return ".stl", binary_stl(scaled), ANY, f"scaled by 1e{k}"


def _few(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    n = rng.choice((0, 1, 2))
    return ".stl", binary_stl(t[:n]), BAD, f"{n} triangle(s)"


def _doubled(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    return ".stl", binary_stl(np.concatenate([t, t])), ANY, "every face twice"


def _ascii_damage(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    text = ascii_stl(t)
    lines = text.splitlines()
    i = rng.randrange(len(lines))
    op = rng.randrange(3)
    if op == 0:
        del lines[i]
    elif op == 1:
        lines[i] = lines[i] + " garbage 1e999"
    else:
        lines = lines[:i]
    return ".stl", ("\n".join(lines) + "\n").encode(), ANY, f"ASCII STL damaged at line {i} ({op})"


def _suffix(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    suffix = rng.choice((".obj", ".ply", ".off", ".glb", ".3mf", ".xyz", "", ".STL", ".yaml"))
    return suffix, raw, ANY, f"a binary STL named *{suffix}"


def _other_format(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
    choice = rng.randrange(4)
    if choice == 0:
        return ".stl", obj.encode(), BAD, "an OBJ (one open triangle) named .stl"
    if choice == 1:
        return ".obj", obj.replace("f 1 2 3", "f 1 2 99").encode(), ANY, "an OBJ with a bad index"
    if choice == 2:
        return (
            ".ply",
            b"ply\nformat ascii 1.0\nelement vertex 99999999\nend_header\n",
            ANY,
            "a PLY header promising 1e8 vertices",
        )
    return ".off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n", ANY, "a truncated OFF"


def _step(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    choice = rng.randrange(4)
    head = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('x'),'2;1');\nENDSEC;\nDATA;\n"
    if choice == 0:
        return ".step", b"", BAD, "an empty STEP file"
    if choice == 1:
        return ".step", rng.randbytes(2000), BAD, "2000 random bytes named .step"
    if choice == 2:
        body = "".join(f"#{i}=CARTESIAN_POINT('',({i},0.,0.));\n" for i in range(1, 50))
        return (
            ".stp",
            (head + body + "ENDSEC;\nEND-ISO-10303-21;\n").encode(),
            BAD,
            "STEP points, no solid",
        )
    return ".step", (head + "#1=GARBAGE((((;\n").encode(), BAD, "a STEP file cut short"


def _big(t: np.ndarray, raw: bytes, rng: random.Random) -> Broken:
    choice = rng.randrange(3)
    if choice == 0:
        sub = rng.choice((5, 6, 7))
        tris = _icosphere(sub, 20.0)
        return ".stl", binary_stl(tris), ANY, f"an icosphere of {len(tris)} faces"
    size = rng.choice((200 * 2**20, 2 * 2**30))
    if choice == 1:
        return ".stl", Sparse(size), ANY, f"a {size >> 20} MiB STL of zero bytes (sparse)"
    head = binary_stl(t[:0], (size - 84) // 50)[:84]
    return ".stl", Sparse(size, head), ANY, f"a {size >> 20} MiB binary STL of zero triangles"


BREAKERS: tuple[Callable[[np.ndarray, bytes, random.Random], Broken], ...] = (
    _truncated,
    _garbage,
    _counts,
    _open,
    _inverted,
    _inconsistent,
    _flat,
    _non_finite,
    _scaled,
    _scaled,
    _few,
    _doubled,
    _ascii_damage,
    _suffix,
    _other_format,
    _step,
    _big,
)


def _subjects() -> list[tuple[Fixture, tuple]]:
    """Fixtures whose mesh the checks read, with the field naming it."""
    out = []
    for fx in fixtures():
        body = fx.data.get("body")
        if not isinstance(body, dict) or "mass" in body:
            continue
        if "mesh" in body:
            out.append((fx, ("body", "mesh")))
        for i, _ in enumerate(body.get("parts") or []):
            out.append((fx, ("body", "parts", i, "mesh")))
    return out


def mesh_case(seed: int, index: int) -> Case:
    """A fixture scene with one of its meshes broken."""
    rng = random.Random(f"{seed}:mesh:{index}")
    fx, field = rng.choice(_subjects())
    data = copy.deepcopy(fx.data)
    holder = data
    for part in field[:-1]:
        holder = holder[part]
    original = holder["mesh"]
    raw = fx.files[original]
    breaker = rng.choice(BREAKERS)
    suffix, entry, expect, what = breaker(triangles(raw), raw, rng)
    name = f"broken{suffix}"
    holder["mesh"] = name
    if rng.random() < 0.15:
        holder["repair"] = True
        what += ", repair: true"
        expect = ANY
    files: dict[str, Entry] = {**fx.files, name: entry, fx.scene: dump(data).encode()}
    if expect.outcome == "invalid":
        expect = Expect("invalid", (Claim(fmt_path(field), f"a usable mesh ({what})"),))
    return Case(
        "mesh",
        seed,
        index,
        f"{fx.name}: {'.'.join(map(str, field))} {what}",
        files,
        (fx.scene,),
        {fx.scene: expect},
    )
