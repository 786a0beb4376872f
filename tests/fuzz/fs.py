"""File-system set-ups (kind ``fs``): scene and mesh paths that are links, loops, devices,
pipes, sockets, folders, unreadable, too long or oddly named; each next to a valid scene that
must still be checked."""

from __future__ import annotations

import copy
import random
from collections.abc import Callable

from tests.fuzz.model import Blob, Case, Entry, Expect, Fifo, Folder, Socket, Sparse, Symlink
from tests.fuzz.scenes import Fixture, dump, fixtures

__all__ = ["fs_case"]

BAD = Expect("invalid", ())  # an input error, located


def _valid(fx: Fixture) -> Expect:
    return Expect("valid", baseline=fx.name)


def _with_mesh() -> list[Fixture]:
    """Fixtures whose body is one mesh that the checks read (no explicit mass)."""
    return [
        f
        for f in fixtures()
        if isinstance(f.data.get("body"), dict)
        and "mesh" in f.data["body"]
        and "mass" not in f.data["body"]
    ]


def _placed(fx: Fixture, folder: str) -> dict[str, Entry]:
    prefix = f"{folder}/" if folder else ""
    return {
        f"{prefix}{name}": data for name, data in {**fx.files, fx.scene: fx.text.encode()}.items()
    }


def _mesh_scene(fx: Fixture, mesh: str) -> bytes:
    data = copy.deepcopy(fx.data)
    data["body"]["mesh"] = mesh
    return dump(data).encode("utf-8", "surrogatepass")


Setup = tuple[dict[str, Entry], tuple[str, ...], dict[str, Expect], str, bool, bool]


def _bad_scene_path(rng: random.Random, fx: Fixture) -> Setup:
    """A scene path that cannot be read, given directly or found in a folder."""
    name = "s.kcheck.yaml"
    options: list[tuple[dict[str, Entry], str, bool]] = [
        ({name: Symlink("nowhere.yaml")}, "a dangling link", False),
        ({name: Symlink("b.kcheck.yaml"), "b.kcheck.yaml": Symlink(name)}, "a link loop", False),
        ({name: Symlink(name)}, "a link to itself", False),
        ({name: Fifo()}, "a FIFO", False),
        ({name: Socket()}, "a socket", False),
        ({name: Symlink("/dev/zero")}, "a link to /dev/zero", False),
        ({name: Symlink("/dev/null")}, "a link to /dev/null", False),
        ({name: Symlink("/dev/urandom")}, "a link to /dev/urandom", False),
        ({name: Blob(fx.text.encode(), 0)}, "an unreadable file (mode 000)", True),
        ({name: b""}, "an empty file", False),
        ({name: Sparse(10**10, b"version: 1\n")}, "a 10 GB sparse file", False),
    ]
    files, what, unprivileged = rng.choice(options)
    targets: tuple[str, ...]
    results = {name: BAD}
    if "b.kcheck.yaml" in files:
        results["b.kcheck.yaml"] = BAD
    if rng.random() < 0.5:
        targets = tuple(results)
    else:
        targets = (".",)
        files = {**files, **_placed(fx, "ok")}
        results[f"ok/{fx.scene}"] = _valid(fx)
    return files, targets, results, what, unprivileged, False


def _folders(rng: random.Random, fx: Fixture) -> Setup:
    """Folders: unreadable, unsearchable, named like scenes, linked, looping, hidden."""
    choice = rng.randrange(8)
    ok = f"ok/{fx.scene}"
    files: dict[str, Entry] = dict(_placed(fx, "ok"))
    results: dict[str, Expect] = {ok: _valid(fx)}
    if choice == 0:
        files.update({**_placed(fx, "locked"), "locked": Folder(0)})
        results["locked"] = BAD
        return files, (".",), results, "an unreadable folder (mode 000)", True, False
    if choice == 1:
        files.update({**_placed(fx, "locked"), "locked": Folder(0o111)})
        results["locked"] = BAD
        return files, (".",), results, "a folder that cannot be listed (mode 111)", True, False
    if choice == 2:
        files.update({**_placed(fx, "locked"), "locked": Folder(0o444)})
        results[f"locked/{fx.scene}"] = BAD
        return files, (".",), results, "a folder that cannot be searched (mode 444)", True, False
    if choice == 3:
        files.update(_placed(fx, "d.kcheck.yaml"))
        results[f"d.kcheck.yaml/{fx.scene}"] = _valid(fx)
        targets = rng.choice(((".",), ("d.kcheck.yaml", "ok")))
        return files, targets, results, "a folder named like a scene", False, False
    if choice == 4:
        files["link.kcheck.yaml"] = Symlink("ok")
        files["ok/up"] = Symlink("..")
        return (
            files,
            (".",),
            results,
            "a link to a folder named like a scene, a link loop",
            False,
            False,
        )
    if choice == 5:
        files.update(_placed(fx, ".hidden"))
        files.update(_placed(fx, "node_modules"))
        return (
            files,
            (".",),
            results,
            "hidden and node_modules folders (not searched)",
            False,
            False,
        )
    if choice == 6:
        files["empty.kcheck.yaml"] = Folder()
        return (
            files,
            ("ok", "empty.kcheck.yaml"),
            {**results, "empty.kcheck.yaml": BAD},
            "an empty folder named like a scene",
            False,
            False,
        )
    files[f"hard/{fx.scene}"] = files[ok]
    files.update({f"hard/{n}": d for n, d in fx.files.items()})
    results[f"hard/{fx.scene}"] = _valid(fx)
    targets = (ok, "ok", ".", ok)
    return files, targets, results, "the same scene given four times, and a copy", False, False


def _odd_names(rng: random.Random, fx: Fixture) -> Setup:
    """Scene file names that are legal but odd: spaces, non-ASCII, a newline, bytes that are
    not UTF-8, a leading dash."""
    name = rng.choice(
        (
            "a b.kcheck.yaml",
            "ä ö 支.kcheck.yaml",
            "line\nbreak.kcheck.yaml",
            "\udcff\udcfe.kcheck.yaml",
            "-x.kcheck.yaml",
            ".kcheck.yaml",
            "x" * 240 + ".kcheck.yaml",
            "tab\there.kcheck.yaml",
        )
    )
    files: dict[str, Entry] = {**fx.files, name: fx.text.encode()}
    targets = (name,) if rng.random() < 0.5 else (".",)
    return files, targets, {name: _valid(fx)}, f"a scene named {name!r}", False, False


def _long_paths(rng: random.Random, fx: Fixture) -> Setup:
    """A scene deeper than PATH_MAX, given directly or found by walking."""
    depth = rng.choice((10, 25))
    folder = "/".join(["d" * 250] * depth)
    files: dict[str, Entry] = {f"{folder}/{n}": d for n, d in _placed(fx, "").items()}
    files.update(_placed(fx, "ok"))
    results: dict[str, Expect] = {f"ok/{fx.scene}": _valid(fx)}
    if rng.random() < 0.5:
        deep = f"{folder}/{fx.scene}"
        return (
            files,
            (deep, "ok"),
            {**results, deep: BAD if depth > 16 else _valid(fx)},
            f"a scene {len(deep)} characters deep, given",
            False,
            False,
        )
    return files, (".",), results, f"a scene {depth * 251} characters deep, walked", False, True


def _mesh_paths(rng: random.Random, fx: Fixture) -> Setup:
    """A scene whose mesh path leads somewhere odd."""
    fx = rng.choice(_with_mesh())
    mesh = fx.data["body"]["mesh"]
    real = fx.files[mesh]
    options: list[tuple[str, dict[str, Entry], Expect, bool, str]] = [
        ("m.stl", {"m.stl": Symlink("nowhere.stl")}, BAD, False, "a dangling link"),
        ("m.stl", {"m.stl": Symlink("m.stl")}, BAD, False, "a link loop"),
        ("m.stl", {"m.stl": Fifo()}, BAD, False, "a FIFO"),
        ("m.stl", {"m.stl": Socket()}, BAD, False, "a socket"),
        ("m.stl", {"m.stl": Folder()}, BAD, False, "a folder"),
        ("m.stl", {"m.stl": Symlink("/dev/zero")}, BAD, False, "a link to /dev/zero"),
        ("m.stl", {"m.stl": Blob(real, 0)}, BAD, True, "an unreadable mesh"),
        ("../outside.stl", {"../outside.stl": real}, BAD, False, "a mesh outside the folder"),
        ("/etc/hostname", {}, BAD, False, "an absolute path"),
        ("x" * 300 + ".stl", {}, BAD, False, "a name too long"),
        ("/".join(["d" * 200] * 30) + "/m.stl", {}, BAD, False, "a path too long"),
        ("", {}, BAD, False, "an empty path"),
        (".", {}, BAD, False, "the scene's folder"),
        ("s.kcheck.yaml", {}, BAD, False, "the scene itself"),
        ("sub/../" + mesh, {"sub": Folder()}, _valid(fx), False, "a path through sub/.."),
        ("blöck mesh.stl", {"blöck mesh.stl": real}, _valid(fx), False, "a non-ASCII name"),
        ("l.stl", {"l.stl": Symlink(mesh)}, _valid(fx), False, "a link to the mesh"),
        ("n\nl.stl", {"n\nl.stl": real}, _valid(fx), False, "a newline in the name"),
        ("M.STL", {"M.STL": real}, _valid(fx), False, "an upper-case suffix"),
    ]
    path, extra, expect, unprivileged, what = rng.choice(options)
    scene = "case/s.kcheck.yaml"
    files: dict[str, Entry] = {f"case/{n}": d for n, d in {**fx.files, **extra}.items()}
    files[scene] = _mesh_scene(fx, path)
    return (
        files,
        (scene,),
        {scene: expect},
        f"{fx.name}: mesh {what} ({path[:60]!r})",
        unprivileged,
        False,
    )


SETUPS: tuple[Callable[[random.Random, Fixture], Setup], ...] = (
    _bad_scene_path,
    _bad_scene_path,
    _folders,
    _folders,
    _odd_names,
    _long_paths,
    _mesh_paths,
    _mesh_paths,
    _mesh_paths,
)


def fs_case(seed: int, index: int) -> Case:
    """One file-system set-up."""
    rng = random.Random(f"{seed}:fs:{index}")
    fx = rng.choice(fixtures())
    setup = rng.choice(SETUPS)
    files, targets, results, what, unprivileged, other = setup(rng, fx)
    return Case(
        "fs",
        seed,
        index,
        f"{setup.__name__.strip('_')}: {what}",
        files,
        targets,
        results,
        unprivileged=unprivileged,
        other_results=other,
    )
