"""Command-line misuse (kind ``cli``): bad options, ``--select`` oddities, unwritable and
conflicting outputs, bad configuration, and every command on bad input. Each case is one
process with the exit codes it may end with (2 always with a message)."""

from __future__ import annotations

import random
from collections.abc import Callable

from tests.fuzz.model import Blob, Case, Entry, Fifo, Folder, Symlink
from tests.fuzz.scenes import Fixture, fixtures

__all__ = ["cli_case"]

USAGE = frozenset({2})
CHECKED = frozenset({0, 1})
EITHER = frozenset({0, 1, 2})
# Maxwell's criterion alone: its severity is "warning", so no fixture fails the gate.
MAXWELL_ONLY = frozenset({0})


def _fx(rng: random.Random) -> Fixture:
    return rng.choice(fixtures())


def _placed(fx: Fixture, folder: str = "s") -> dict[str, Entry]:
    return {f"{folder}/{n}": d for n, d in {**fx.files, fx.scene: fx.text.encode()}.items()}


def _verdict(fx: Fixture) -> frozenset[int]:
    from tests.fuzz.baseline import exit_code_of

    return frozenset({exit_code_of(fx.name)})


# Each maker returns (argv, files, exit codes, what, unprivileged, env, outputs).
Made = tuple[list[str], dict[str, Entry], frozenset[int], str, bool, dict[str, str], dict[str, str]]


def _select(rng: random.Random) -> Made:
    fx = _fx(rng)
    value, codes = rng.choice(
        (
            (",", USAGE),
            (" ", USAGE),
            ("", USAGE),
            (",,", USAGE),
            ("maxwell,,", USAGE),
            (" maxwell ", CHECKED),
            ("MAXWELL", USAGE),
            ("nope", USAGE),
            ("maxwell,nope", USAGE),
            ("maxwell,maxwell", CHECKED),
            ("*", USAGE),
            ("maxwell\n", CHECKED),
            ("é", USAGE),
            ("maxwell", CHECKED),
            ("hertz", CHECKED),
        )
    )
    argv = ["check", "s", "--format", "json", "--select", value]
    what = f"--select {value!r}"
    if rng.random() < 0.3:
        other = rng.choice(("maxwell", "nope", ",", "analytical-3d"))
        argv += ["--ignore", other]
        what += f" --ignore {other!r}"
        codes = EITHER if codes == CHECKED else codes
    return argv, _placed(fx), codes, what, False, {}, {}


def _outputs(rng: random.Random) -> Made:
    fx = _fx(rng)
    files = _placed(fx)
    target, extra, codes, unprivileged = rng.choice(
        (
            ("/proc/kcheck.json", {}, USAGE, False),
            ("/dev/full", {}, USAGE, False),
            ("f/below.json", {"f": b"a file"}, USAGE, False),
            (".", {}, USAGE, False),
            ("d", {"d": Folder()}, USAGE, False),
            ("/dev/null", {}, CHECKED, False),
            ("new/deep/out.json", {}, CHECKED, False),
            ("fifo", {"fifo": Fifo()}, EITHER, False),
            ("x" * 300, {}, USAGE, False),
            ("/", {}, USAGE, False),
            ("/sys/kernel/kcheck", {}, USAGE, False),
            ("ro/out.json", {"ro": Folder(0o555)}, USAGE, True),
            ("ro.json", {"ro.json": Blob(b"", 0o444)}, USAGE, True),
            ("link.json", {"link.json": Symlink("/proc/self/status")}, USAGE, False),
        )
    )
    files.update(extra)
    option = rng.choice(("--output", "--output-format", "--plots"))
    if option == "--output":
        argv = ["check", "s", "--format", "json", "--output", target]
    elif option == "--output-format":
        fmt = rng.choice(("sarif", "junit", "json", "markdown", "github", "concise", "text"))
        argv = ["check", "s", "--format", "json", "--output-format", f"{fmt}:{target}"]
    else:
        argv = ["check", "s", "--format", "json", "--plots", target]
        if target in ("/dev/null", "fifo", "ro.json", "link.json"):
            codes = USAGE  # not folders
        if target in ("new/deep/out.json", ".", "/", "d"):
            codes = CHECKED  # folders kcheck may write into (the case runs as root)
    if codes == CHECKED:
        codes = _verdict(fx)
    return argv, files, codes, f"{option} {target!r}", unprivileged, {}, {}


def _conflicts(rng: random.Random) -> Made:
    fx = _fx(rng)
    choice = rng.randrange(9)
    base = ["check", "s", "--format", "json"]
    cases: list[tuple[list[str], frozenset[int], dict[str, str]]] = [
        (base + ["--output", "a.json", "--output-format", "junit:a.json"], USAGE, {}),
        (base + ["--output-format", "sarif:a", "--output-format", "sarif:a"], USAGE, {}),
        (base + ["--output-format", "sarif:a", "--output-format", "junit:./a"], USAGE, {}),
        (base + ["--output-format", "sarif"], USAGE, {}),
        (base + ["--output-format", "nope:x"], USAGE, {}),
        (base + ["--output-format", "sarif:"], USAGE, {}),
        (base + ["--output-format", ":x"], USAGE, {}),
        (["check", "s", "--format", "nope"], USAGE, {}),
        (
            base
            + [
                "--output",
                "r.json",
                "--output-format",
                "sarif:r.sarif",
                "--output-format",
                "junit:r.xml",
                "--output-format",
                "markdown:r.md",
            ],
            _verdict(fx),
            {"r.json": "json", "r.sarif": "sarif", "r.xml": "junit", "r.md": "text"},
        ),
    ]
    argv, codes, outputs = cases[choice]
    return argv, _placed(fx), codes, " ".join(argv[2:]), False, {}, outputs


def _numbers(rng: random.Random) -> Made:
    fx = _fx(rng)
    option, value, codes = rng.choice(
        (
            ("-j", "-1", USAGE),
            ("-j", "abc", USAGE),
            ("-j", "1.5", USAGE),
            ("-j", "0", CHECKED),
            ("-j", "1000", CHECKED),
            ("-j", "auto", CHECKED),
            ("-j", "99999999999999999999", CHECKED),
            ("--timeout", "0", USAGE),
            ("--timeout", "-1", USAGE),
            ("--timeout", "nan", USAGE),
            ("--timeout", "inf", USAGE),
            ("--timeout", "1e-9", USAGE),
            ("--timeout", "1e300", CHECKED),
            ("--timeout", "abc", USAGE),
            ("--memory-limit", "1", USAGE),
            ("--memory-limit", "0", USAGE),
            ("--memory-limit", "1e9", CHECKED),
            ("--memory-limit", "1e30", EITHER),
            ("--memory-limit", "nan", USAGE),
            ("--color", "nope", USAGE),
            ("--fail-on", "nope", USAGE),
        )
    )
    if codes == CHECKED:
        codes = _verdict(fx)
    argv = ["check", "s", "--format", "json", option, value]
    return argv, _placed(fx), codes, f"{option} {value}", False, {}, {}


CONFIGS = (
    ("[tool.kcheck]\nnope = 1\n", USAGE),
    ('[tool.kcheck]\njobs = "x"\n', USAGE),
    ("[tool.kcheck]\ntimeout = -1\n", USAGE),
    ("[tool.kcheck]\nselect = 5\n", USAGE),
    ("[tool.kcheck]\npaths = [1]\n", USAGE),
    ('[tool.kcheck]\nformat = "nope"\n', USAGE),
    ("[tool.kcheck]\nmax_file_size = 0\n", USAGE),
    ("[tool.kcheck]\nmax_file_size = 0.0001\n", USAGE),
    ('[tool.kcheck]\nfail_on = "x"\n', USAGE),
    ('[tool.kcheck.checks.maxwell]\nseverity = "x"\n', USAGE),
    ("[tool.kcheck.checks.nope]\nx = 1\n", USAGE),
    ('[tool.kcheck]\nselect = ["maxwell"]\n', MAXWELL_ONLY),
    ("[tool.kcheck\n", USAGE),
    ("\x00\x01", USAGE),
    ("[tool.kcheck]\nselect = []\n", USAGE),
    ("[tool.kcheck]\ntimeout = inf\n", USAGE),
    ("[tool.kcheck]\nmemory_limit = nan\n", USAGE),
    ('[tool.kcheck]\noutput_format = ["sarif:/dev/full"]\n', USAGE),
    ('[tool.kcheck]\ncache_dir = "/proc/x"\n', EITHER),
)


def _config(rng: random.Random) -> Made:
    fx = _fx(rng)
    text, codes = rng.choice(CONFIGS)
    files = _placed(fx)
    how = rng.randrange(3)
    raw = text.encode() if rng.random() < 0.9 else text.encode("utf-16")
    if raw != text.encode():
        codes = USAGE
    if codes == CHECKED:
        codes = _verdict(fx)
    if how == 0:
        files["pyproject.toml"] = raw
        argv = ["check", "s", "--format", "json"]
    elif how == 1:
        # A kcheck.toml has the keys at the top level (docs/ci.md): no [tool.kcheck] table.
        # (Seed 4245 judged `select = ["maxwell"]` under that table: kcheck rightly said
        # "unknown key `tool`".)
        standalone = text.replace("[tool.kcheck.", "[").replace("[tool.kcheck]\n", "")
        if raw == text.encode():
            raw = standalone.encode()
        files["k.toml"] = raw
        argv = ["check", "s", "--format", "json", "--config", "k.toml"]
    else:
        target, codes = rng.choice(
            (("missing.toml", USAGE), ("d", USAGE), ("/dev/zero", USAGE), ("fifo", USAGE))
        )
        files.update({"d": Folder(), "fifo": Fifo()})
        argv = ["check", "s", "--format", "json", "--config", target]
        text = target
    return argv, files, codes, f"configuration {text!r} ({how})", False, {}, {}


def _paths(rng: random.Random) -> Made:
    fx = _fx(rng)
    files = _placed(fx)
    mesh = next(iter(fx.files), None)
    args, codes = rng.choice(
        (
            (["nonexistent"], USAGE),
            (["-"], USAGE),
            (["s", "nonexistent"], USAGE),
            (["x" * 5000], USAGE),
            (["/".join(["d" * 250] * 20)], USAGE),
            ([f"n{i}" for i in range(3000)], USAGE),
            ([f"s/{mesh}"] if mesh else ["s"], EITHER),
            (["s/../s/./"], _verdict(fx)),
            (["/dev/null"], USAGE),
            (["/proc/self/status"], USAGE),
        )
    )
    return (
        ["check", "--format", "json", "--", *args],
        files,
        codes,
        f"paths {args[:2]}",
        False,
        {},
        {},
    )


def _commands(rng: random.Random) -> Made:
    fx = _fx(rng)
    files = {**_placed(fx), "g.stl": b"garbage" * 20, "bad.kcheck.yaml": b"version: [\n"}
    files.update({"fifo": Fifo(), "d": Folder()})
    scene = f"s/{fx.scene}"
    mesh = next((f"s/{n}" for n in fx.files), "g.stl")
    argv, codes = rng.choice(
        (
            (["expand", "bad.kcheck.yaml"], USAGE),
            (["expand", "missing.kcheck.yaml"], USAGE),
            (["expand", "d"], USAGE),
            (["expand", "fifo"], USAGE),
            (["expand", scene], frozenset({0})),
            (["expand", scene, "--output", "/dev/full"], USAGE),
            (["expand", scene, "--output", "/proc/x"], USAGE),
            (["mass", "g.stl", "--units", "mm", "--material", "aluminium"], USAGE),
            (["mass", "missing.stl", "--units", "mm", "--material", "aluminium"], USAGE),
            (["mass", mesh, "--units", "mm", "--density", "nan"], USAGE),
            (["mass", mesh, "--units", "mm", "--density", "-1"], USAGE),
            (["mass", mesh, "--units", "mm", "--density", "1e308"], USAGE),
            (["mass", mesh, "--units", "mm", "--material", "unobtainium"], USAGE),
            (["mass", mesh, "--units", "mm", "--material", "steel", "--format", "json"], EITHER),
            (["mass", "fifo", "--units", "mm", "--material", "steel"], USAGE),
            (["init", "--coupling", "nope"], USAGE),
            (["init", "--output", "/dev/full"], USAGE),
            (["init", "--output", scene], USAGE),
            (["init", "--mesh", "g.stl"], USAGE),
            (["init", "--mesh", "missing.stl"], USAGE),
            (["init", "--output", "new.kcheck.yaml"], frozenset({0})),
            (["init", "--output", "-"], frozenset({0})),
            (["suggest", "bad.kcheck.yaml"], USAGE),
            (["suggest", scene, "--points", "0"], USAGE),
            (["suggest", scene, "--points", "-5"], USAGE),
            (["suggest", scene, "--directions", "0"], USAGE),
            (["suggest", scene, "--friction", "1", "0"], USAGE),
            (["suggest", scene, "--friction", "nan", "nan"], USAGE),
            # A box of one point is allowed (docs/suggest.md: XMIN <= XMAX); exit 2 only for
            # a planar scene (campaign seed 4243 expected 2 here, wrongly).
            (["suggest", scene, "--box", "0", "0", "0", "0", "0", "0"], EITHER),
            (["suggest", scene, "--top", "0"], USAGE),
            (["suggest", scene, "--magnitude", "inf"], USAGE),
            (["suggest", scene, "--magnitude", "-1"], USAGE),
            (
                ["suggest", scene, "--plot", "/proc/x.png", "--points", "20", "--directions", "20"],
                USAGE,
            ),
            (
                ["suggest", scene, "--write", "/dev/full", "--points", "20", "--directions", "20"],
                USAGE,
            ),
            (
                ["suggest", scene, "--points", "30", "--directions", "30", "--format", "json"],
                EITHER,
            ),
            (["config", "--format", "nope"], USAGE),
            (["config", "--json"], frozenset({0})),
            (["schema"], frozenset({0})),
            (["plugins"], frozenset({0})),
            ([], USAGE),
            (["nope"], USAGE),
            (["check", "--nope"], USAGE),
            (["--version"], frozenset({0})),
        )
    )
    return argv, files, codes, " ".join(argv)[:80], False, {}, {}


def _terminals(rng: random.Random) -> Made:
    """The text report where stdout cannot show everything (a report-lane promise)."""
    fx = _fx(rng)
    env = rng.choice(
        ({"PYTHONIOENCODING": "ascii"}, {"LANG": "C", "LC_ALL": "C"}, {"COLUMNS": "20"})
    )
    argv = ["check", "s", "--format", "text"]
    return argv, _placed(fx), _verdict(fx), f"text report with {env}", False, env, {}


MAKERS: tuple[Callable[[random.Random], Made], ...] = (
    _select,
    _outputs,
    _outputs,
    _conflicts,
    _numbers,
    _config,
    _paths,
    _commands,
    _commands,
    _terminals,
)


def cli_case(seed: int, index: int) -> Case:
    """One command line."""
    rng = random.Random(f"{seed}:cli:{index}")
    maker = rng.choice(MAKERS)
    argv, files, codes, what, unprivileged, env, outputs = maker(rng)
    return Case(
        "cli",
        seed,
        index,
        f"{maker.__name__.strip('_')}: {what}",
        files,
        argv=tuple(argv),
        exit_codes=codes,
        unprivileged=unprivileged,
        env=env,
        outputs=outputs,
    )
