"""Words that misled a design reviewer (issue 22), each fixed and pinned here: good news said
as good news, small percentages with their digits, a warning marked as a warning, scene-level
warnings under a heading, hints that apply to the scene at hand, and no picture files claimed
that were never kept."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from kcheck.fmt import format_percent
from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import Status
from tests.conftest import FIXTURES, PLANAR_SCENE
from tests.kcheck.test_report_formats import render
from tests.kcheck.test_report_text import run


@pytest.fixture(scope="module")
def checks():
    return load_checks()


def test_a_passing_jamming_check_reads_as_good_news(checks) -> None:
    result = check_scene(FIXTURES / "planar-block" / "block.kcheck.yaml", checks)
    (jamming,) = [c for c in result.checks if c.id == "jamming"]
    assert jamming.status is Status.PASS
    assert jamming.message.startswith("jam-free at the design direction:")
    assert "cannot hold" not in jamming.message


@pytest.mark.parametrize(
    ("ratio", "text"),
    [(15.2e6 / 4.2e9, "0.36%"), (0.0049, "0.49%"), (0.3665, "37%"), (0.00995, "1%"),
     (1.02, "102%"), (0.0, "0%"), (2e-6, "0.0002%")],
)  # fmt: skip
def test_percentages_below_one_keep_their_digits(ratio: float, text: str) -> None:
    assert format_percent(ratio) == text


def test_hertz_under_a_light_load_says_a_percentage_that_is_not_zero(tmp_path: Path) -> None:
    """15 MPa against 4.2 GPa was "(0% of 4.2 GPa allowed)"."""
    from kcheck_checks.hertz import Hertz
    from kcheck_checks.hertz_materials import HertzOptions

    from kcheck.plugin import Inputs
    from kcheck.scene import Preload
    from tests.couplings import coupling_scene, three_vee, with_preloads

    scene = coupling_scene(tmp_path, three_vee(0.05, 6e-3, 45.0))
    centres = {s.geometry.coupling: s.geometry.ball_center for s in scene.supports}
    scene = with_preloads(
        scene, [Preload(f"spring {n}", c, np.array([0, 0, -1e-3])) for n, c in centres.items()]
    )
    result = Hertz().run(
        Inputs(scene, None, HertzOptions(ball_material="52100", seat_material="52100"))
    )
    share = re.search(r"\((\S+)% of 4\.2 GPa allowed\)", result.message)
    assert share is not None, result.message
    assert 0 < float(share.group(1)) < 1
    assert float(share.group(1)) == pytest.approx(100 * result.details["max_utilisation"], rel=0.01)


def test_markdown_marks_a_warning_as_a_warning() -> None:
    """maxwell failed with severity warning: ⚠️ as in the scene's verdict, not ❌."""
    row = next(line for line in render("markdown").splitlines() if "coupling.kcheck.yaml" in line)
    assert "maxwell ⚠️" in row and "maxwell ❌" not in row
    assert "analytical-2d ❌" in row  # a failure of severity error stays a failure


def test_scene_warnings_come_under_a_heading() -> None:
    lines = render("text", color="never").splitlines()
    at = next(i for i, line in enumerate(lines) if "1000× heavier" in line)
    assert re.fullmatch(r"  warn\s+scene  1 warning about the scene itself \(not a check's\)",
                        lines[at - 1])  # fmt: skip
    # and in the short summary, the scene is named as the one that warns
    assert any(
        line.startswith("WARN  parts/coupling.kcheck.yaml:3  scene: the body is 1000×")
        for line in lines
    )


def test_reversed_normals_hint_fits_explicit_supports(write_scene, checks) -> None:
    """`ball_on` belongs to coupling shorthands; explicit supports are told what applies."""
    text = PLANAR_SCENE.replace("normal: [0, 1, 0]", "normal: [0, -1, 0]").replace(
        "normal: [1, 0, 0]", "normal: [-1, 0, 0]"
    )
    (warning,) = check_scene(write_scene(text), checks).warnings
    assert warning.code == "normals-reversed" and warning.hint is not None
    assert "ball_on" not in warning.hint and "reverse the normals" in warning.hint
    coupling = (FIXTURES / "three-groove-beta-45" / "coupling.kcheck.yaml").read_text()
    (warning,) = check_scene(
        write_scene(coupling.replace("up: [0, 0, 1]", "up: [0, 0, -1]"), "c.kcheck.yaml"), checks
    ).warnings
    assert warning.hint is not None and "`ball_on`" in warning.hint


def test_html_alone_claims_no_picture_files(tmp_path: Path) -> None:
    page = tmp_path / "review.html"
    alone = run("check", str(FIXTURES / "planar-block"), "--html", str(page), "-v")
    assert page.stat().st_size > 0 and "<svg" in page.read_text()
    assert "written" not in alone.stdout and "picture:" not in alone.stdout
    plots = tmp_path / "plots"
    kept = run("check", str(FIXTURES / "planar-block"), "--html", str(page), "--plots", str(plots))
    (said,) = re.findall(r"(\d+) picture files written", kept.stdout)
    assert int(said) == len(list(plots.iterdir())) > 0


def test_markdown_carries_the_numbers_of_failing_cases_and_folds_passing_scenes() -> None:
    out = run(
        "check", str(FIXTURES / "thesis-appendix-a"), str(FIXTURES / "planar-block"),
        "--format", "markdown",
    ).stdout  # fmt: skip
    numbers = out.split("### Numbers", 1)[1].split("<details>", 1)[0]
    assert "**analytical-2d** ❌ fail: no safe direction" in numbers
    assert "  - retract x3: loses contact, y1 N = -0.0866 N" in numbers  # as the JSON has it
    assert "**maxwell** ⚠️ warn" in numbers and "retract y1: poor, cos θ = 0.555" in numbers
    assert "planar-block" not in numbers
    folded = out.split("<details><summary>1 passing scene: key numbers</summary>", 1)[1]
    folded = folded.split("</details>", 1)[0]
    assert "planar-block/block.kcheck.yaml` planar rectangular block — analytical-2d: design " \
        "margin 28.80°" in folded  # fmt: skip


def _with_not_checked():
    """The formats' passing scene with one check not checked for want of a material, and
    one that does not apply."""
    import dataclasses

    from kcheck.result import CheckResult
    from tests.kcheck.test_report_formats import PASS

    extra = (
        CheckResult("hertz", Status.SKIPPED, "not checked: material of v1's ball unknown"),
        CheckResult("analytical-3d", Status.SKIPPED, "applies to spatial scenes"),
    )
    return (dataclasses.replace(PASS, checks=(*PASS.checks, *extra)),)


def test_not_checked_reads_not_checked_with_its_reason_in_every_format() -> None:
    """A check that could not run for want of input is "not checked" with what is missing,
    never the "n/a" of a check that does not apply (last round's review)."""
    from kcheck.report.views import verdict

    (scene,) = _with_not_checked()
    words = {c.id: verdict(c) for c in scene.checks}
    assert words["hertz"] == "not checked" and words["analytical-3d"] == "n/a"
    text = render("text", _with_not_checked(), color="never", verbosity=1)
    assert re.search(r"not checked hertz  material of v1's ball unknown", text), text
    assert "n/a   hertz" not in text
    short = render("text", _with_not_checked(), color="never")
    assert "1 not checked; 1 n/a" in short  # the headline counts the two apart
    markdown = render("markdown", _with_not_checked())
    assert "**hertz** not checked: material of v1's ball unknown" in markdown
    assert "1 not checked, 1 n/a" in markdown
    html = render("html", _with_not_checked())
    assert '<span class="badge na">not checked</span> hertz' in html
    assert "material of v1&#x27;s ball unknown" in html or "material of v1's ball unknown" in html
    junit = render("junit", _with_not_checked())
    assert "not checked: material of v1" in junit


@pytest.mark.parametrize("width", range(20, 61))
def test_wrapping_never_parts_a_number_from_its_unit_or_relation(width: int) -> None:
    """Issue 22: at any width a value stays with its unit (0.0866 N, 4.2 GPa, 28.80°) and
    a relation with its number (N = -0.0866, μ ≤ 0.122)."""
    from kcheck.report.text import wrap_offsets

    text = (
        "retract x3 → y1 loses contact (N = -0.0866 N); it closes for μ ≤ 0.122; peak "
        "1.4 GPa, 33 % of 4.2 GPa allowed; stiffness 215 N/µm; margin 28.80 ° outside"
    )
    breaks = wrap_offsets(text, width)
    kept = [r"N = -0\.0866 N", r"μ ≤ 0\.122", r"1\.4 GPa", r"33 %", r"4\.2 GPa", r"215 N/µm",
            r"28\.80 °"]  # fmt: skip
    for pattern in kept:
        m = re.search(pattern, text)
        assert m is not None
        assert not any(m.start() < b < m.end() for b in breaks), (pattern, width)
    bounds = [0, *breaks, len(text)]
    assert all(
        len(text[a:b].rstrip()) <= width for a, b in zip(bounds[:-1], bounds[1:], strict=True)
    )
