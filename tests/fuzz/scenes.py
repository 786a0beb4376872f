"""The fixture scenes as material: their data, their meshes, their verdicts, YAML writing, and
rewrites that must not change a verdict (key order, style, comments, aliases, encodings,
names, order of supports and couplings, direction lengths, units, explicit defaults)."""

from __future__ import annotations

import codecs
import copy
import functools
import random
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from kcheck.scene.yamlcompose import plain_scalar
from kcheck.scene.yamlio import load_yaml
from tests.fuzz.contract import COORDINATE_FIELDS, DIRECTION_FIELDS, RADIUS_FIELDS, UNIT_SCALE

__all__ = [
    "FIXTURES",
    "Fixture",
    "fixtures",
    "dump",
    "equivalent",
    "encode",
    "walk",
    "get",
    "put",
]

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures"


@dataclass(frozen=True)
class Fixture:
    """A fixture scene: its folder's name, the scene file's name, text, data, other files."""

    name: str
    scene: str
    text: str
    data: dict
    files: dict[str, bytes]

    @property
    def has_mesh(self) -> bool:
        body = self.data.get("body") or {}
        return "mesh" in body or "parts" in body


@functools.cache
def fixtures() -> tuple[Fixture, ...]:
    """Every fixture scene, in name order (one scene per fixture folder)."""
    out = []
    for scene in sorted(FIXTURES.glob("*/*.kcheck.yaml")):
        data, _ = load_yaml(scene)
        files = {
            p.name: p.read_bytes()
            for p in sorted(scene.parent.iterdir())
            if p.is_file() and p != scene
        }
        out.append(Fixture(scene.parent.name, scene.name, scene.read_text(), data, files))
    return tuple(out)


class _Dumper(yaml.SafeDumper):
    """Strings YAML 1.2 would read as something else are quoted; floats keep every digit."""

    def represent_str(self, data: str) -> yaml.ScalarNode:  # type: ignore[override]
        if not isinstance(plain_scalar(data, 0, 0), str) or data in ("<<", "="):
            return self.represent_scalar("tag:yaml.org,2002:str", data, style="'")
        return super().represent_str(data)

    def ignore_aliases(self, data: Any) -> bool:  # aliases only where a list is shared
        return not isinstance(data, list)


_Dumper.add_representer(str, _Dumper.represent_str)


def dump(data: Any, rng: random.Random | None = None) -> str:
    """YAML text of plain data; with ``rng``, in a random (equivalent) style."""
    if rng is None:
        return yaml.dump(data, Dumper=_Dumper, sort_keys=False, width=10**6, allow_unicode=True)
    style = rng.choice((None, None, True, False))
    return yaml.dump(
        data,
        Dumper=_Dumper,
        sort_keys=False,
        default_flow_style=style,
        indent=rng.choice((2, 2, 3, 4)),
        width=10**6,
        allow_unicode=rng.random() < 0.8,
        explicit_start=rng.random() < 0.2,
        explicit_end=rng.random() < 0.1,
    )


def walk(data: Any, path: tuple[Any, ...] = ()) -> list[tuple[tuple[Any, ...], Any]]:
    """Every (path, value) below ``data``, containers included, depth first."""
    out = [(path, data)]
    if isinstance(data, dict):
        for k, v in data.items():
            out.extend(walk(v, (*path, k)))
    elif isinstance(data, list):
        for i, v in enumerate(data):
            out.extend(walk(v, (*path, i)))
    return out


def get(data: Any, path: tuple[Any, ...]) -> Any:
    """The value at ``path``."""
    for part in path:
        data = data[part]
    return data


def put(data: Any, path: tuple[Any, ...], value: Any) -> None:
    """Set the value at ``path`` (which must not be empty)."""
    get(data, path[:-1])[path[-1]] = value


# --- rewrites that keep the verdict ------------------------------------------------------------


def _shuffle_keys(data: Any, rng: random.Random) -> Any:
    if isinstance(data, dict):
        items = list(data.items())
        rng.shuffle(items)
        return {k: _shuffle_keys(v, rng) for k, v in items}
    if isinstance(data, list):
        return [_shuffle_keys(v, rng) for v in data]
    return data


NAMES = ("a", "Stütze 1", "ζ-2", "pin #3", "'quoted'", "x" * 200, "1", "yes", "null", "~", "支点")


def _rename(data: dict, rng: random.Random) -> str:
    used: set[str] = set()
    for key in ("supports", "couplings", "preloads"):
        for item in data.get(key) or []:
            while True:
                name = rng.choice(NAMES) + ("" if rng.random() < 0.5 else str(rng.randrange(99)))
                name = name[:200]
                if name not in used:
                    break
            used.add(name)
            item["name"] = name
    return "support, coupling and preload names changed"


def _permute(data: dict, rng: random.Random) -> str:
    for key in ("supports", "couplings"):
        if isinstance(data.get(key), list):
            rng.shuffle(data[key])
    return "supports and couplings reordered"


def _scale_directions(data: dict, rng: random.Random) -> str:
    factor = rng.choice((1e-3, 0.5, 2.0, 7.0, 1e3))
    for path, value in walk(data):
        if path and path[-1] in DIRECTION_FIELDS and path[0] != "checks":
            if isinstance(value, list) and len(value) == 3:
                put(data, path, [x * factor for x in value])
    return f"direction vectors scaled by {factor:g}"


def _change_units(data: dict, rng: random.Random) -> str | None:
    """Another length unit with every length converted (scenes without meshes only)."""
    body = data.get("body") or {}
    if "mesh" in body or "parts" in body or data.get("checks"):
        return None
    old = data.get("units", "m")
    new = rng.choice([u for u in ("m", "cm", "mm", "um") if u != old])
    factor = UNIT_SCALE[old] / UNIT_SCALE[new]
    for path, value in walk(data):
        name = next((p for p in reversed(path) if isinstance(p, str)), None)
        if name in COORDINATE_FIELDS and isinstance(value, list):
            put(data, path, [x * factor for x in value])
        elif name in RADIUS_FIELDS and isinstance(value, (int, float)):
            put(data, path, value * factor)
        elif path == ("tolerances", "position") and isinstance(value, (int, float)):
            put(data, path, value * factor)  # a length too (a scalar, unlike a position)
    data["units"] = new
    return f"units {old} -> {new}, lengths converted"


def _explicit_defaults(data: dict, rng: random.Random) -> str:
    for c in data.get("couplings") or []:
        c.setdefault("ball_on", "body")
    for s in data.get("supports") or []:
        s.setdefault("friction", data.get("friction", 0.0))
    body = data.get("body")
    if isinstance(body, dict) and "mesh" in body:
        body.setdefault("repair", False)
    data.setdefault("sweep", {"normal": [0.0, 0.0, 1.0], "zero": [1.0, 0.0, 0.0]})
    data.setdefault("preloads", [])
    return "defaults written out"


def _share_lists(data: dict, rng: random.Random) -> str:
    """Equal vectors become one list: the YAML gets anchors and aliases."""
    seen: dict[tuple, list] = {}
    for path, value in walk(data):
        if (
            isinstance(value, list)
            and len(value) == 3
            and all(isinstance(x, (int, float)) for x in value)
        ):
            key = tuple(value)
            if key in seen:
                put(data, path, seen[key])
            else:
                seen[key] = value
    return "equal vectors written as aliases"


DATA_REWRITES = (_rename, _permute, _scale_directions, _change_units, _explicit_defaults)


def _comments(text: str, rng: random.Random) -> str:
    out = []
    for line in text.splitlines():
        if rng.random() < 0.3:
            out.append(" " * rng.randrange(8) + "# " + rng.choice(("note", "µ", "ä: [", "#", "'")))
        out.append(line + (" # c" if rng.random() < 0.2 and line.strip() else ""))
    return "\n".join(out) + "\n"


def encode(text: str, rng: random.Random) -> tuple[bytes, str]:
    """The text in a random encoding kcheck documents as readable (UTF-8 with or without a
    byte-order mark, UTF-16/32 with one, CRLF line ends)."""
    choice = rng.randrange(6)
    if choice == 0:
        return codecs.BOM_UTF8 + text.encode(), "UTF-8 with BOM"
    if choice == 1:
        return text.encode("utf-16"), "UTF-16 with BOM"
    if choice == 2:
        return codecs.BOM_UTF16_BE + text.encode("utf-16-be"), "UTF-16 BE with BOM"
    if choice == 3:
        return text.encode("utf-32"), "UTF-32 with BOM"
    if choice == 4:
        return text.replace("\n", "\r\n").encode(), "CRLF line ends"
    return text.encode(), "UTF-8"


def equivalent(fixture: Fixture, rng: random.Random, steps: int = 3) -> tuple[bytes, str]:
    """A rewrite of a fixture scene that must get the fixture's verdict, and what was done."""
    data = copy.deepcopy(fixture.data)
    done = []
    for rewrite in rng.sample(DATA_REWRITES, k=min(steps, len(DATA_REWRITES))):
        what = rewrite(data, rng)
        if what:
            done.append(what)
    data = _shuffle_keys(data, rng) if rng.random() < 0.7 else data
    if rng.random() < 0.3:
        done.append(_share_lists(data, rng))
    text = dump(data, rng)
    if rng.random() < 0.5:
        text = _comments(text, rng)
        done.append("comments added")
    raw, encoding = encode(text, rng)
    done.append(encoding)
    return raw, "; ".join(done)
