"""The text report as an engineer and a CI log read it: one line per passing scene, reasons for
failures, the short summary, no wrapping when piped, numbers never broken on an 80-column
terminal, one angle convention, no numerical noise, severity, every input error shown once,
and no character that can crash it (ASCII terminals, lone surrogates).

Subprocess tests run the installed CLI exactly as a user would (``python -m kcheck``); the
terminal ones give it a real pseudo-terminal of 80 columns.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import FIXTURES, PLANAR_SCENE

APPENDIX_A = str(FIXTURES / "thesis-appendix-a")
PLANAR = str(FIXTURES / "planar-block")
NUMBER = re.compile(r"-?\d+\.\d+(?:°|%)?")


def run(*args: str, **env: str) -> subprocess.CompletedProcess[str]:
    """``kcheck`` in a subprocess with stdout piped; NO_COLOR, and no COLUMNS unless given."""
    full = {**os.environ, "NO_COLOR": "1", **env}
    if "COLUMNS" not in env:
        full.pop("COLUMNS", None)  # piped without COLUMNS: nothing wraps
    full.pop("FORCE_COLOR", None)
    return subprocess.run(
        [sys.executable, "-m", "kcheck", *args],
        capture_output=True,
        text=True,
        encoding="utf-8",
        errors="backslashreplace",
        env=full,
        timeout=300,
    )


def run_tty(*args: str, columns: int = 80) -> str:
    """``kcheck`` on a pseudo-terminal ``columns`` wide; its screen output as text."""
    import fcntl
    import pty
    import struct
    import termios

    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, columns, 0, 0))
    env = {**os.environ, "NO_COLOR": "1", "COLUMNS": str(columns)}
    env.pop("FORCE_COLOR", None)
    proc = subprocess.Popen(
        [sys.executable, "-m", "kcheck", *args, "--progress", "never"],
        stdout=slave,
        stderr=slave,
        stdin=subprocess.DEVNULL,
        env=env,
    )
    os.close(slave)
    chunks = []
    while True:
        try:
            chunk = os.read(master, 1 << 16)
        except OSError:
            break
        if not chunk:
            break
        chunks.append(chunk)
    proc.wait(timeout=300)
    os.close(master)
    text = b"".join(chunks).decode("utf-8").replace("\r\n", "\n")
    return re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", text)


@pytest.fixture(scope="module")
def default_run() -> subprocess.CompletedProcess[str]:
    return run("check", PLANAR, APPENDIX_A)


@pytest.fixture(scope="module")
def verbose_run() -> str:
    return run("check", PLANAR, APPENDIX_A, "-v").stdout


@pytest.fixture(scope="module")
def every_fixture() -> str:
    """``-v`` over every bundled scene (planar and spatial, mm and m, custom sweep planes)."""
    return run("check", str(FIXTURES), "-v").stdout


def test_passing_scene_is_one_line(default_run: subprocess.CompletedProcess[str]) -> None:
    out = default_run.stdout
    lines = out.splitlines()
    (planar,) = [line for line in lines if "planar rectangular block" in line]
    # verdict, name, path, the key number, the skipped check as a count
    assert re.match(
        r"PASS\s+planar rectangular block\s+\S+planar-block/block\.kcheck\.yaml", planar
    )
    # analytical-3d and tolerances (no `tolerances:`) do not apply to this planar scene;
    # hertz applies but is not checked (no contact geometry: no coupling shorthands)
    assert "design margin 28.80°" in planar and "1 not checked; 2 n/a" in planar
    following = lines[lines.index(planar) + 1]
    assert following.startswith("FAIL") or following == ""  # nothing more about it
    assert "skipped" not in out and "plot written" not in out and " ms" not in out


def test_failing_scene_says_why_and_checks_disagree(
    default_run: subprocess.CompletedProcess[str],
) -> None:
    out = default_run.stdout
    assert default_run.returncode == 1 and default_run.stderr == ""
    block = out[out.index("FAIL   thesis appendix A block") :]
    # The mass-free construction passes, says what it cannot see, and the failing check that
    # sees contact loss is quoted next to it, on one whole line.
    graphical = next(line for line in block.splitlines() if "graphical-2d" in line)
    assert (
        graphical.lstrip().startswith("pass")
        and "mass-free: contact loss not checked" in graphical
        and graphical.count("mass-free") == 1
    )
    but = block.splitlines()[block.splitlines().index(graphical) + 1]
    assert re.match(r"\s+but analytical-2d: FAIL — retract x3 → y1 loses contact", but)


def test_short_summary_and_counts(default_run: subprocess.CompletedProcess[str]) -> None:
    lines = default_run.stdout.splitlines()
    start = lines.index("short summary")
    summary = lines[start + 1 : -1]
    assert summary and all(
        re.match(r"(FAIL|WARN|MARGINAL|ERROR)\s+\S+\.kcheck\.yaml", s) for s in summary
    )
    assert any("analytical-2d:" in s and "retract x3 → y1 loses contact" in s for s in summary)
    assert re.fullmatch(r"2 scenes: 1 passed, 1 failed in \d+(\.\d+)? s", lines[-1])


def test_piped_output_without_columns_never_wraps(
    default_run: subprocess.CompletedProcess[str],
) -> None:
    """Not a terminal and no COLUMNS: long lines stay whole (for grep in CI logs)."""
    out = default_run.stdout
    assert "\x1b[" not in out  # NO_COLOR: no style at all
    assert max(len(line) for line in out.splitlines()) > 120
    assert not any(line.endswith(" ") for line in out.splitlines())


def test_terminal_80_columns_never_breaks_a_number(verbose_run: str) -> None:
    screen = run_tty("check", PLANAR, APPENDIX_A, "-v")
    piped = verbose_run
    assert max(len(line.rstrip()) for line in screen.splitlines()) <= 80
    # Every number of the unwrapped report appears whole on the 80-column screen (the run
    # time of the last line differs between the two runs).
    piped = piped.rstrip("\n").rsplit("\n", 1)[0]
    assert set(NUMBER.findall(piped)) <= set(NUMBER.findall(screen))
    assert "…" not in screen  # no cell cut short


def _width(line: str) -> int:
    import unicodedata

    return sum(2 if unicodedata.east_asian_width(c) in "WF" else 1 for c in line)


def test_piped_at_columns_80_no_line_is_longer_and_no_number_splits(every_fixture: str) -> None:
    """Issue 22: `COLUMNS=80 NO_COLOR=1 kcheck check fixtures/ -v | ...` fits 80 columns, and
    every number of the unwrapped report — with its unit — is whole in the wrapped one."""
    wrapped = run("check", str(FIXTURES), "-v", COLUMNS="80").stdout
    lines = wrapped.splitlines()
    assert len(lines) > 500 and max(map(_width, lines)) <= 80
    assert not any(line.endswith(" ") for line in lines)
    number = re.compile(r"-?\d+(?:\.\d+)?(?:°|%)?(?: (?:N|mm|m/s²|kg|GPa|MPa|N/µm)\b)?")
    whole = every_fixture.rstrip("\n").rsplit("\n", 1)[0]  # the run time differs
    assert max(map(_width, whole.splitlines())) > 150  # the same report, unwrapped
    assert set(number.findall(whole)) <= set(number.findall(wrapped))


def test_mass_and_init_print_the_digits_the_input_justifies(tmp_path: Path) -> None:
    """A box whose corners carry 0.1 + 0.2 (0.30000000000000004): `kcheck mass` and
    `kcheck init` write 0.3 and 0.45, never the float's noise."""
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box(extents=[0.1 + 0.2, 0.7, 0.1 + 0.2])
    box.apply_translation([0.1 + 0.2] * 3)
    box.export(tmp_path / "box.stl")
    mass = run("mass", str(tmp_path / "box.stl"), "--units", "mm", "--material", "aluminium")
    init = run("init", "--mesh", str(tmp_path / "box.stl"), "-o", "-")
    assert mass.returncode == 0 and init.returncode == 0, mass.stderr + init.stderr
    for out in (mass.stdout, init.stdout):
        assert not re.search(r"\d\.\d*0000000|\d\.\d*9999999", out), out
    assert "centre of mass (0.3, 0.3, 0.3) mm" in mass.stdout
    assert "x 0.15 … 0.45" in mass.stdout and "x 0.15 … 0.45" in init.stdout
    assert "its centre of mass is [0.3, 0.3, 0.3] m" in init.stdout


def test_verbose_and_quiet(verbose_run: str) -> None:
    verbose = verbose_run
    assert "centre of mass (50.00, 30.00, 10.00) mm" in verbose  # scene units, fixed decimals
    assert "inertia about the centre of mass (kg·mm²):" in verbose
    assert "analytical-2d per retracted support" in verbose and "n/a   analytical-3d" in verbose
    # No safe direction at all: say so, not a placeholder margin.
    assert re.search(r"^FAIL\s+thesis appendix A block.*no safe force direction", verbose, re.M)
    assert "x3         loses contact  translation along +x" in verbose
    quiet = run("check", PLANAR, APPENDIX_A, "-q").stdout
    assert "planar rectangular block" not in quiet and "thesis appendix A block" in quiet
    assert quiet.splitlines()[-1].startswith("2 scenes: 1 passed, 1 failed")


def test_one_angle_convention_everywhere(every_fixture: str) -> None:
    """Ranges start in [0°, 360°) and say "through 0°"; the convention is stated once."""
    out = every_fixture
    assert out.count("counter-clockwise about the sweep plane's normal from its 0°") == 1
    assert "339.27°–20.73° (through 0°)" in out  # three-groove; v1 wrote 339.27–380.73
    assert "sweep plane: 0° along −z, 90° along +x, counter-clockwise about −y" in out
    report_ranges = re.findall(r"(\d+\.\d+)°–(\d+\.\d+)°", out)
    assert report_ranges and all(float(a) < 360 and float(b) <= 360 for a, b in report_ranges)


def test_no_numerical_noise_in_verbose_report(every_fixture: str) -> None:
    out = every_fixture
    assert not re.search(r"\de[-+]\d", out.split("short summary")[0].replace("-v", ""))
    # A negative zero ("-0.000", "(-0,") is noise; a small negative value is not (the Mostly
    # Printed Probe's pins have a product of inertia of -0.000038 kg·mm², 3e-4 of the largest).
    assert not re.search(r"-0\.0+(?![0-9])", out) and "(-0," not in out
    assert "pure rotation about +z" in out  # block-321: the pitch is rounding noise
    assert "principal moments 1820.42, 1820.42, 3599.42 kg·mm²" in out  # three-groove


def test_noise_is_zeroed_relative_to_the_largest_entry() -> None:
    from kcheck.report.tables import mass_view
    from kcheck.result import MassProperties

    inertia = np.array([[0.0170547, -9.14796e-18, 0], [-9.14796e-18, 0.0270953, 0], [0, 0, 0.0358]])
    mass = MassProperties(6.885, np.array([0.1, 2.2e-18, 0.0425]), inertia, "mesh", 0.00255)
    view = mass_view(mass, "mm")
    assert dict(view.facts)["centre of mass"] == "(100.0, 0.0, 42.5) mm"
    assert dict(view.facts)["volume"] == "2550000 mm³"
    assert view.inertia is not None and view.inertia[0][1] == "0.0"
    assert [v for k, v in view.principal if k.startswith("axis")] == [
        "along +x",
        "along +y",
        "along +z",
    ]


def test_warning_severity_is_shown_as_a_warning(write_scene) -> None:
    text = PLANAR_SCENE + "checks:\n  maxwell: {severity: warning, min_cos: 0.99}\n"
    proc = run("check", str(write_scene(text)))
    assert proc.returncode == 0  # a warning does not fail the run
    lines = proc.stdout.splitlines()
    assert any(line.startswith("WARN ") and "planar block" in line for line in lines)
    assert any(re.match(r"\s+warn\s+maxwell", line) for line in lines)
    assert not any(re.match(r"\s+fail\s", line) for line in lines)
    assert re.search(r"^WARN\s+\S+scene\.kcheck\.yaml(:\d+)?\s+maxwell:", proc.stdout, re.M)
    assert lines[-1].startswith("1 scene: 0 passed, 1 with warnings in")


def test_every_input_error_shown_once(write_scene) -> None:
    bad = write_scene(PLANAR_SCENE.replace("friction: 0.1", "friction: -1"), "bad.kcheck.yaml")
    good = write_scene(PLANAR_SCENE, "good.kcheck.yaml")
    proc = run("check", str(bad), str(good))
    assert proc.returncode == 2 and proc.stderr == ""  # the text report on stdout has it
    located = re.findall(rf"{re.escape(str(bad))}:\d+(:\d+)?: field `friction`", proc.stdout)
    assert len(located) == 1  # in the scene's block, once
    assert proc.stdout.count("expected 0 ≤ friction ≤ 100, got -1") == 2  # block + summary
    assert "planar block" in proc.stdout  # the good scene is still reported
    as_json = run("check", str(bad), str(good), "--format", "json")
    assert as_json.stderr.count("field `friction`") == 1 and as_json.stdout.startswith("{")


def test_several_errors_of_a_file_each_with_line_and_column() -> None:
    from rich.console import Console

    from kcheck.report.text import render_scene
    from kcheck.result import Finding, SceneResult, Status

    errors = (
        Finding("expected a number, got 'lots'", field=("load", "magnitude"), line=14, column=14),
        Finding("unknown key; did you mean `friction`?", field=("frcition",), line=9, column=1),
        Finding("expected 3 numbers, got 2", field=("supports", 1, "normal"), line=7, column=40),
    )
    scene = SceneResult("s.kcheck.yaml", Status.ERROR, error="s.kcheck.yaml:14: ...", errors=errors)
    console = Console(width=100_000, soft_wrap=True, no_color=True, color_system=None, record=True)
    render_scene(console, scene)
    out = console.export_text()
    assert "s.kcheck.yaml:14:14: field `load.magnitude`: expected a number" in out
    assert "s.kcheck.yaml:9:1: field `frcition`: unknown key; did you mean `friction`?" in out
    assert "s.kcheck.yaml:7:40: field `supports[1].normal`: expected 3 numbers" in out
    assert out.count("s.kcheck.yaml:") == 3


ODD_NAME_SCENE = PLANAR_SCENE.replace("name: planar block (methods.md §7)", 'name: "block ±2° μ"')


def test_ascii_terminal_and_lone_surrogates(write_scene, tmp_path: Path) -> None:
    """An ASCII terminal gets every character it cannot show as a fallback, and a file name
    with a byte that is not UTF-8 (decoded to a lone surrogate) never crashes a report; a
    lone surrogate inside a scene file is an input error of that file (the loader)."""
    odd = write_scene(ODD_NAME_SCENE, "odd.kcheck.yaml")
    broken = write_scene(
        PLANAR_SCENE.replace("{name: y1,", '{name: "y\\ud800",'), "broken.kcheck.yaml"
    )
    undecodable = tmp_path / os.fsdecode(b"bytes-\xff.kcheck.yaml")
    undecodable.write_text(PLANAR_SCENE, encoding="utf-8")
    assert "\udcff" in str(undecodable)
    ascii_env = {"PYTHONIOENCODING": "ascii", "LANG": "C", "LC_ALL": "C"}
    fast = ["--select", "maxwell"]  # no pictures: the text is what is tested
    scenes = [APPENDIX_A, str(odd), str(broken), str(undecodable)]
    for args in (["-v"], ["--format", "json", *fast], ["--html", str(tmp_path / "r.html"), *fast]):
        proc = run("check", *scenes, *args, **ascii_env)
        assert "Traceback" not in proc.stderr and proc.returncode in (1, 2), proc.stderr
        proc.stdout.encode("ascii")  # nothing the terminal cannot show
        if args[0] == "-v":
            assert "block +/-2 deg mu" in proc.stdout  # ±, ° and μ spelled out
            assert "thesis appendix A block" in proc.stdout  # the batch went on
            assert "broken.kcheck.yaml:" in proc.stdout  # the surrogate: a located error
            assert "\\udcff" in proc.stdout  # the file name escaped, not dropped
    html = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "thesis appendix A block" in html and "\\udcff" in html


def test_progress_line_goes_to_stderr_and_disappears(write_scene) -> None:
    # Wide enough for the temporary path: at 80 columns a long one wraps inside its name.
    proc = run("check", str(write_scene(PLANAR_SCENE)), "--progress", "always", COLUMNS="400")
    assert "[1/1]" in proc.stderr and "scene.kcheck.yaml" in proc.stderr
    assert proc.stderr.rstrip("\n").endswith("\x1b[?25h") or "\x1b[2K" in proc.stderr
    assert "[1/1]" not in proc.stdout


def test_help_lists_exit_codes_and_explains_every_option() -> None:
    proc = run("check", "--help")
    assert proc.returncode == 0
    text = proc.stdout
    assert "exit codes:" in text and "  2  bad input or usage" in text
    assert "`" not in text and "``" not in text and ":ref:" not in text
    from kcheck.cli import _parser

    sub = next(a for a in _parser()._actions if a.dest == "command")
    check = sub.choices["check"]  # type: ignore[attr-defined]
    for action in check._actions:
        assert action.help, f"{action.option_strings or action.dest} has no help text"


def test_findings_say_why_then_what_to_change() -> None:
    """A failing check's findings, each with its line and hint, under its verdict; the same
    reason quoted next to a passing check of the same question (text and HTML)."""
    from rich.console import Console

    from kcheck.report.html import render_page
    from kcheck.report.text import render_scene
    from kcheck.result import CheckResult, Finding, SceneResult, Status

    finding = Finding(
        "retract x3 → y1 loses contact (N = -0.087 N)",
        code="loses-contact",
        field=("supports", 0),
        hint="move the force towards 310°, or y1 further from x3",
        line=9,
    )
    failing = CheckResult(
        "analytical-2d", Status.FAIL, "no safe force angle", safe_ranges_deg=(), findings=(finding,)
    )
    passing = CheckResult(
        "graphical-2d",
        Status.PASS,
        "safe force angles: 292.41°–317.76°",
        safe_ranges_deg=((292.41, 317.76),),
        details={"limitations": ["mass-free: contact loss not checked"], "design_margin_deg": 7.6},
    )
    scene = SceneResult("a.kcheck.yaml", Status.FAIL, name="block", checks=(failing, passing))
    console = Console(width=100_000, soft_wrap=True, no_color=True, color_system=None, record=True)
    render_scene(console, scene)
    lines = console.export_text().splitlines()
    why = next(i for i, line in enumerate(lines) if "✗ retract x3 → y1 loses contact" in line)
    assert lines[why].endswith("(line 9)") and lines[why - 1].lstrip().startswith("fail")
    assert lines[why + 1].strip() == "→ move the force towards 310°, or y1 further from x3"
    assert any(
        line.strip() == "but analytical-2d: FAIL — retract x3 → y1 loses contact (N = -0.087 N)"
        for line in lines
    )
    page = render_page([scene], 1.0, [{}])
    assert "retract x3 → y1 loses contact" in page and "line 9" in page
    assert '<span class="hint">move the force towards 310°' in page


def test_the_html_page_is_written_a_scene_at_a_time(tmp_path) -> None:
    """Fuzz finding (campaign seed 4242, batch 15: 105 scenes with --plots and --html): the
    page of a hundred scenes with pictures (about 70 MB) was joined whole, several copies at
    once, and kcheck peaked past the issue's 500 MB. Written a scene at a time, the extra
    memory is about one scene's share, whatever the number of scenes."""
    import tracemalloc

    from kcheck.report.html import write_page
    from kcheck.result import CheckResult, SceneResult, Status

    check = CheckResult("maxwell", Status.PASS, "determinate")
    scenes = [SceneResult(f"s{i}.kcheck.yaml", Status.PASS, checks=(check,)) for i in range(40)]
    picture = "<svg>" + "<path d='M 0 0 L 1 1'/>" * 40_000 + "</svg>"  # about 1 MB
    pictures = [{f"s{i}-maxwell.svg": picture} for i in range(40)]  # about 40 MB in all
    with (tmp_path / "page.html").open("w", encoding="utf-8") as stream:
        tracemalloc.start()
        write_page(stream, scenes, 1.0, pictures)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    assert (tmp_path / "page.html").stat().st_size > 40 * len(picture)
    assert peak < 8e6, f"{peak / 1e6:.0f} MB held while writing a 40 MB page"


def test_the_html_reporter_does_not_hold_a_batch_of_pictures(tmp_path) -> None:
    """docs/robustness.md left open that the HTML reporter kept every scene's SVG pictures
    until the run ended (about 0.7 MB a scene: a few hundred scenes passed 500 MB). Each
    scene's section now goes to a temporary file as it arrives; 40 scenes with a 1 MB picture
    each are held at most about one scene at a time, and the page still has all of them in
    order after its summary."""
    import tracemalloc

    from kcheck.report import ReportOptions
    from kcheck.report.html import HtmlReporter
    from kcheck.result import CheckResult, SceneResult, Status

    picture = "<svg>" + "<path d='M 0 0 L 1 1'/>" * 40_000 + "</svg>"  # about 1 MB
    check = CheckResult("maxwell", Status.PASS, "determinate")
    scenes = []
    for i in range(40):
        svg = tmp_path / f"s{i}-maxwell.svg"
        svg.write_text(picture.replace("<svg>", f"<svg><title>picture {i}</title>"))
        scenes.append(
            SceneResult(f"s{i}.kcheck.yaml", Status.PASS, checks=(check,), plots=(str(svg),))
        )
    page = tmp_path / "page.html"
    with page.open("w", encoding="utf-8") as stream:
        reporter = HtmlReporter(stream, ReportOptions())
        tracemalloc.start()
        reporter.start(len(scenes))
        for scene in scenes:
            reporter.scene(scene)
        reporter.finish(scenes, 1.0)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    text = page.read_text(encoding="utf-8")
    assert peak < 10e6, f"{peak / 1e6:.0f} MB held for a 40 MB page"
    positions = [text.index(f"picture {i}<") for i in range(40)]
    assert positions == sorted(positions) and text.index("<h2>Scenes</h2>") < positions[0]
    assert text.rstrip().endswith("</html>")


def test_mass_with_point_masses_says_so() -> None:
    """A new user read "mass 0.28233 kg (mesh)" for a plate mesh plus three ball point masses
    (0.27 + 3 × 0.00411 kg): the label now says what the number is made of."""
    from kcheck.body.mass import body_mass_properties
    from kcheck.report.tables import mass_lines
    from kcheck.scene import load_scene

    scene = load_scene(FIXTURES / "tool-changer" / "tool.kcheck.yaml")  # a 12 g magnet added
    assert scene.body is not None
    lines = mass_lines(body_mass_properties(scene.body), "mm")
    assert lines[0].startswith("mass 0.105285 kg (mesh + point masses)")
    explicit = load_scene(FIXTURES / "thesis-block-4-2" / "block.kcheck.yaml")
    assert explicit.body is not None
    assert "(explicit)" in mass_lines(body_mass_properties(explicit.body), "mm")[0]


def test_the_verbose_report_says_which_friction_was_used() -> None:
    """A new user with `friction: {min: 0.1, max: 0.2}` could not tell from the text which μ
    the tables were at. The scene block now states the supports' friction as checked."""
    from kcheck.report.views import friction_text
    from kcheck.result import SceneResult, Status

    def scene(*records: dict) -> SceneResult:
        return SceneResult("s.kcheck.yaml", Status.PASS, supports=records)

    one = {"name": "y1", "friction": 0.15, "friction_static": [0.15, 0.15]}
    one["friction_kinetic"] = [0.15, 0.15]
    assert friction_text(scene(one, {**one, "name": "y2"})) == "friction: μ = 0.15 at every support"
    ranged = {**one, "friction_static": [0.1, 0.2], "friction_kinetic": [0.1, 0.2]}
    text = friction_text(scene(ranged))
    assert text is not None and text.startswith("friction: μ 0.1–0.2 at every support (a range")
    two = {**one, "friction_static": [0.2, 0.2], "friction_kinetic": [0.1, 0.1]}
    dry = {**one, "name": "y2", "friction": 0.0, "friction_static": [0, 0]}
    dry["friction_kinetic"] = [0, 0]
    assert friction_text(scene(two, dry)) == ("friction: y1 static μ 0.2, kinetic μ 0.1, y2 μ = 0")


def test_headline_of_a_tiny_safe_share_is_not_no_safe_direction(
    cli, cli_json, tmp_path: Path
) -> None:
    """A user's Kelvin clamp (gravity and a spring the only closing forces): the headline
    said "no safe force direction" (from jamming's lattice lower bound, 0 of 20 000 points)
    while analytical-3d said "safe gravity directions: 0.01%" — and the sphere picture
    "0.0%". Reference for the share being positive, an independent computation: analytical-3d's
    own lattice cross-check (200 000 directions counted one by one) finds safe directions too.
    The headline now quotes the smallest share with its source, in gravity directions, with
    digits enough to be non-zero; the check and its picture write the same number."""
    import yaml

    from tests.couplings import user_kelvin

    path = user_kelvin(tmp_path)
    code, out, _ = cli("check", "-j", "1", "-v", str(path))
    head = next(line for line in out.splitlines() if line.startswith("FAIL "))
    assert "no safe" not in head
    assert re.search(r"analytical-3d: [^;]*0\.0056% of gravity directions safe", head)
    assert "safe gravity directions: 0.0056% of the sphere" in out
    assert "gravity directions free of jamming: 0%–0.090% of the sphere" in out

    doc = yaml.safe_load(path.read_text(encoding="utf-8"))
    doc["checks"] = {"analytical-3d": {"sphere_points": 200_000}}
    path.write_text(yaml.safe_dump(doc), encoding="utf-8")
    _, doc = cli_json("-j", "1", "--select", "analytical-3d", str(path))
    check = doc["scenes"][0]["checks"][0]
    exact, counted = check["safe_solid_angle_fraction"], check["lattice_fraction"]
    assert counted > 0 and exact == pytest.approx(counted, rel=0.5)  # 11 of 200 000 counted


def test_the_sphere_picture_writes_the_share_as_the_check_does(tmp_path: Path) -> None:
    """The analytical-3d sphere picture's title carries the check's share as its message
    writes it (the user saw "0.0%" above a text saying "0.01%")."""
    pytest.importorskip("matplotlib")
    from kcheck_checks.analytical_3d import Analytical3D, Analytical3DOptions, spatial_result
    from kcheck_checks.pictures.sphere import sphere_figure

    from kcheck.analysis import analyse
    from kcheck.body.mass import body_mass_properties
    from kcheck.scene import load_scene
    from tests.couplings import user_kelvin

    scene = load_scene(user_kelvin(tmp_path))
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    result, smap, analysis = spatial_result(
        Analytical3D.id, scene, analyse(scene, mass), Analytical3DOptions()
    )
    assert smap is not None
    fig = sphere_figure(scene, analysis, smap, result)
    title = fig._suptitle.get_text()
    assert "0.0056% of the sphere" in title and "0.0056% of the sphere" in result.message
    # The hemisphere the map leaves out holds safe directions too (the range at ~155° in the
    # sweep plane): its note gives that share instead of "no safe direction".
    notes = [
        t.get_text() for ax in fig.axes if ax.get_legend() for t in [ax.get_legend().get_title()]
    ]
    assert any("of the sphere also safe" in n for n in notes)
