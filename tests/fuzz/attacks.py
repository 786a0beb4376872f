"""YAML attacks (kind ``yaml``): a fixture scene with an attack written into its text."""

from __future__ import annotations

import codecs
import random
from collections.abc import Callable

from tests.fuzz.model import ANY, Case, Expect, Sparse
from tests.fuzz.scenes import Fixture, fixtures

__all__ = ["yaml_case", "CANARY"]

#: A file a code-execution payload would create; it must never appear.
CANARY = "pwned"
MUST_FAIL = Expect("invalid", ())  # an input error, located (anywhere)


def _lines(fx: Fixture) -> list[str]:
    return fx.text.splitlines()


def _insert_top(fx: Fixture, block: str, rng: random.Random) -> str:
    """A top-level entry inserted between two top-level entries of the fixture."""
    lines = _lines(fx)
    starts = [
        i for i, line in enumerate(lines) if line and not line[0].isspace() and line[0] != "#"
    ]
    at = rng.choice(starts + [len(lines)])
    return "\n".join(lines[:at] + block.rstrip("\n").split("\n") + lines[at:]) + "\n"


def _bomb(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    levels, width = rng.randint(3, 12), rng.randint(2, 10)
    rows = [f"  a0: &a0 [{', '.join(['x'] * width)}]"]
    for i in range(1, levels):
        rows.append(f"  a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * width)}]")
    key = rng.choice(("zz_bomb", "checks_x"))
    text = _insert_top(fx, f"{key}:\n" + "\n".join(rows), rng)
    return text.encode(), f"alias bomb, {levels} levels of {width}", MUST_FAIL


def _recursive(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    block = rng.choice(
        (
            "zz: &r {a: *r}",
            "zz: &r [*r]",
            "zz: &r {a: [1, {b: *r}]}",
            "zz: *undefined",
            "zz: &a [1]\nyy: &a [*a, *a]",
        )
    )
    return _insert_top(fx, block, rng).encode(), f"alias: {block!r}", MUST_FAIL


def _deep(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    depth = rng.choice((63, 64, 65, 100, 1000, 10_000, 100_000))
    style = rng.randrange(3)
    if style == 0:
        block = "zz: " + "[" * depth + "]" * depth
    elif style == 1:
        block = "zz: " + "{a: " * depth + "1" + "}" * depth
    else:
        depth = min(depth, 2000)
        block = "zz:\n" + "\n".join(" " * (i + 1) + "a:" for i in range(depth)) + " 1"
    return _insert_top(fx, block, rng).encode(), f"nesting {depth} deep (style {style})", MUST_FAIL


def _huge_list(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    n = rng.choice((1000, 100_000, 250_000, 1_000_000, 2_000_000))
    items = ", ".join(["1"] * n)
    where = rng.randrange(2)
    if where == 0:
        text = _insert_top(fx, f"zz: [{items}]", rng)
    else:
        lines = _lines(fx)
        i = next(i for i, line in enumerate(lines) if "[" in line and not line.startswith("#"))
        lines[i] = lines[i].replace("[", f"[{items}, ", 1)
        text = "\n".join(lines) + "\n"
    return text.encode(), f"a flow list of {n} numbers", MUST_FAIL


def _many_supports(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    n = rng.choice((7, 100, 10_000, 150_000))
    rows = "\n".join(
        f"  - {{name: s{i}, position: [0, {i}, 0], normal: [0, 1, 0]}}" for i in range(n)
    )
    lines = [line for line in _lines(fx) if not line.startswith(("supports:", "couplings:", "  "))]
    text = "\n".join(lines) + f"\nsupports:\n{rows}\n"
    return text.encode(), f"{n} supports", MUST_FAIL


def _big_file(fx: Fixture, rng: random.Random) -> tuple[bytes | Sparse, str, Expect]:
    if rng.random() < 0.5:
        size = rng.choice((5 * 2**20 + 1, 6 * 2**20, 10**10))
        return Sparse(size, fx.text.encode()), f"{size} bytes (sparse)", MUST_FAIL
    pad = "# " + "x" * 1000 + "\n"
    count = rng.choice((100, 5300))
    text = fx.text + pad * count
    return (
        text.encode(),
        f"{len(text)} bytes of comments",
        (MUST_FAIL if len(text) > 5 * 2**20 else Expect("valid", baseline=fx.name)),
    )


def _long_string(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    n = rng.choice((201, 10_000, 1_000_000))
    text = fx.text.replace("\nname: ", f"\nname: {'n' * n} ", 1)
    if text == fx.text:
        text = _insert_top(fx, f"name: {'n' * n}", rng)
    return text.encode(), f"a name of {n}+ characters", MUST_FAIL


def _bytes_at(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    raw = fx.text.encode()
    bad = rng.choice(
        (b"\x00", b"\xff", b"\xc0\xaf", b"\xed\xa0\x80", b"\x80", b"\xe2\x82", b"\xfe\xff")
    )
    at = rng.randrange(len(raw) + 1)
    while 0 < at < len(raw) and (raw[at] & 0xC0) == 0x80:  # not inside a UTF-8 sequence
        at -= 1
    return raw[:at] + bad + raw[at:], f"{bad!r} at byte {at}", MUST_FAIL


def _encodings(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    text = fx.text.replace("\nname: ", "\nname: Größe ", 1)
    valid = Expect("valid", baseline=fx.name)
    choice = rng.randrange(8)
    if choice == 0:
        return text.encode("latin-1", "replace"), "Latin-1", MUST_FAIL if text != fx.text else ANY
    if choice == 1:
        return text.encode("utf-16-le"), "UTF-16 LE without a BOM", MUST_FAIL
    if choice == 2:
        return codecs.BOM_UTF8 + text.encode(), "UTF-8 with a BOM", valid
    if choice == 3:
        return text.encode("utf-32"), "UTF-32 with a BOM", valid
    if choice == 4:
        return codecs.BOM_UTF8 * 2 + text.encode(), "two BOMs", ANY
    if choice == 5:
        return codecs.BOM_UTF16_LE + text.encode(), "a UTF-16 BOM on UTF-8 text", MUST_FAIL
    if choice == 6:
        return text.replace("\n", "\r").encode(), "CR line ends", valid
    lines = text.split("\n")
    i = rng.randrange(len(lines))
    lines[i] = lines[i] + " # \u2028\u2029\x85 end"
    return "\n".join(lines).encode(), "line and paragraph separators in a comment", ANY


def _merge(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    block = rng.choice(
        (
            "zz: &base {name: a}\nyy:\n  <<: *base",
            "base: &b {x: 1}\nsweep: {<<: *b}",
            "zz: {<<: [{a: 1}, {b: 2}]}",
        )
    )
    return _insert_top(fx, block, rng).encode(), f"merge key: {block!r}", MUST_FAIL


def _odd_key(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    key = rng.choice(
        (
            "null",
            "~",
            "true",
            "1",
            "1.5",
            "[a, b]",
            "{a: 1}",
            '""',
            '"\\0"',
            '"\\ud800"',
            "x" * 2000,
            "friction",  # a duplicate
            "? complex",
            "!!python/name:os.system x",
        )
    )
    block = f"{key}: 1" if not key.startswith("?") else f"{key}\n: 1"
    return _insert_top(fx, block, rng).encode(), f"key {key[:40]!r}", MUST_FAIL


def _tags(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    payload = rng.choice(
        (
            f'!!python/object/apply:os.system ["touch {CANARY}"]',
            f'!!python/object/apply:subprocess.call [["touch", "{CANARY}"]]',
            "!!python/name:os.system",
            f'!!python/object/new:os.system ["touch {CANARY}"]',
            "!!binary aGVsbG8=",
            "!!set {a, b}",
            "!!omap [a: 1]",
            "!!timestamp 2001-12-14",
            "!custom x",
            "!<tag:example.com,2000:app/foo> x",
        )
    )
    if rng.random() < 0.5:
        text = _insert_top(fx, f"zz: {payload}", rng)
    else:
        text = fx.text.replace("friction: ", f"friction: {payload} #", 1)
    return text.encode(), f"tag {payload!r}", MUST_FAIL


def _core_tags(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    if "\nfriction: " not in fx.text:
        return fx.text.encode(), "nothing", Expect("valid", baseline=fx.name)
    tag = rng.choice(("!!float", "!!str", "!!int", "!!bool", "!!null"))
    text = fx.text.replace("\nfriction: ", f"\nfriction: {tag} ", 1)
    expect = Expect("valid", baseline=fx.name) if tag == "!!float" else MUST_FAIL
    return text.encode(), f"friction tagged {tag}", expect


def _documents(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    choice = rng.randrange(6)
    if choice == 0:
        return (fx.text + "---\n{}\n").encode(), "a second document", MUST_FAIL
    if choice == 1:
        return (fx.text + "...\ngarbage: [\n").encode(), "garbage after the end", MUST_FAIL
    if choice == 2:
        return ("%YAML 1.1\n---\n" + fx.text).encode(), "%YAML 1.1 directive", ANY
    if choice == 3:
        return ("%YAML 2.0\n---\n" + fx.text).encode(), "%YAML 2.0 directive", ANY
    if choice == 4:
        return ("%TAG ! tag:example.com,2000:\n---\n" + fx.text).encode(), "%TAG", ANY
    return ("---\n" + fx.text).encode(), "an explicit start", Expect("valid", baseline=fx.name)


def _not_a_mapping(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    text = rng.choice(
        ("", " \n\n", "# only a comment\n", "---\n", "~\n", "[]\n", "'scene'\n", "42\n", "- a\n")
    )
    return text.encode(), f"the whole file {text!r}", MUST_FAIL


def _control(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    char = rng.choice(("\x01", "\x1b", "\x7f", "\x0b", "\x0c", "\ufffe", "\U0001f600"))
    lines = _lines(fx)
    i = rng.randrange(len(lines))
    lines[i] = lines[i][: len(lines[i]) // 2] + char + lines[i][len(lines[i]) // 2 :]
    return (
        ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass"),
        f"{char!r} in line {i + 1}",
        ANY,
    )


def _tabs(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    lines = _lines(fx)
    # Block context only: inside a flow collection ([...] or {...} over several lines) a tab
    # is ordinary white space, and YAML allows it.
    depth, block = 0, []
    for i, line in enumerate(lines):
        if depth == 0:
            block.append(i)
        code = line.split(" #")[0] if not line.lstrip().startswith("#") else ""
        depth += code.count("[") + code.count("{") - code.count("]") - code.count("}")
    indented = [i for i in block if lines[i].startswith("  ")]
    if not indented:
        return _control(fx, rng)
    i = rng.choice(indented)
    lines[i] = "\t" + lines[i].lstrip(" ")
    return ("\n".join(lines) + "\n").encode(), f"a tab indenting line {i + 1}", MUST_FAIL


def _long_line(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    n = rng.choice((10_000, 1_000_000, 4_000_000))
    text = fx.text + "# " + "y" * n + "\n"
    return text.encode(), f"a comment line of {n} characters", Expect("valid", baseline=fx.name)


def _duplicate_key(fx: Fixture, rng: random.Random) -> tuple[bytes, str, Expect]:
    lines = _lines(fx)
    tops = [line for line in lines if line and not line[0].isspace() and line[0] != "#"]
    line = rng.choice(tops)
    return (fx.text + line + "\n").encode(), f"{line.split(':')[0]} given twice", MUST_FAIL


ATTACKS: tuple[Callable[[Fixture, random.Random], tuple[bytes | Sparse, str, Expect]], ...] = (
    _bomb,
    _bomb,
    _recursive,
    _deep,
    _huge_list,
    _many_supports,
    _big_file,
    _long_string,
    _bytes_at,
    _bytes_at,
    _encodings,
    _merge,
    _odd_key,
    _tags,
    _tags,
    _core_tags,
    _documents,
    _not_a_mapping,
    _control,
    _tabs,
    _long_line,
    _duplicate_key,
)


def yaml_case(seed: int, index: int) -> Case:
    """A fixture scene with one YAML attack in its text."""
    rng = random.Random(f"{seed}:yaml:{index}")
    fx = rng.choice(fixtures())
    attack = rng.choice(ATTACKS)
    raw, what, expect = attack(fx, rng)
    return Case(
        "yaml",
        seed,
        index,
        f"{fx.name}: {attack.__name__.strip('_')}: {what}",
        {**fx.files, fx.scene: raw},
        (fx.scene,),
        {fx.scene: expect},
        absent=(CANARY,),
    )
