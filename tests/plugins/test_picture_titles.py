"""Every picture's title says its check's verdict, and the scene's where that is worse, as the
JSON report does (issue 22: one source for verdict words).

Every bundled fixture is checked with pictures; each figure's title texts (suptitle, axes
titles, figure texts) are read as they are about to be written, and the verdict words in
them are compared with the statuses of the same run's JSON.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("matplotlib")

from kcheck.gate.runner import Settings, check_scene  # noqa: E402
from kcheck.plugin import load_checks  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = sorted((ROOT / "fixtures").glob("*/*.kcheck.yaml"))
WORDS = "PASS|MARGINAL|WARN|FAIL|ERROR"
CHECK_IDS = ("analytical-2d", "analytical-3d", "graphical-2d", "jamming", "hertz", "maxwell")
RANK = {w: i for i, w in enumerate(("pass", "marginal", "warn", "fail", "error"))}


def _word(check: dict[str, Any]) -> str:
    """The verdict word of a check in the JSON: a failed check of severity warning warns."""
    if check["status"] == "fail" and check.get("severity") == "warning":
        return "warn"
    return str(check["status"])


def _texts(fig: Any) -> list[str]:
    """Every title-like text of a figure, as drawn."""
    out = [t.get_text() for t in fig.texts]
    if fig._suptitle is not None:
        out.append(fig._suptitle.get_text())
    for ax in fig.axes:
        out += [ax.get_title(loc) for loc in ("left", "center", "right")]
    return [t for t in dict.fromkeys(out) if t]  # the suptitle is among the texts too


def _own(scene: dict[str, Any], name: str, checks: Any) -> str:
    """The check a picture belongs to: its file is ``<scene slug>-<check id>[-what].ext``."""
    from kcheck.pictures.plotting import slug

    rest = name.removeprefix(f"{slug(scene['name'])}-")
    return next(c for c in checks if rest.startswith(c))


@pytest.fixture(scope="module")
def drawn(tmp_path_factory: pytest.TempPathFactory) -> list[tuple[dict[str, Any], str, str]]:
    """(scene JSON, picture name, its title texts joined) for every picture of every fixture.
    Figures are read where they would be written, so no image is encoded (the slow part)."""
    from matplotlib.figure import Figure

    seen: list[tuple[str, str]] = []

    def record(fig: Figure, path: Any, *args: Any, **kwargs: Any) -> None:
        seen.append((Path(path).name, "\n".join(_texts(fig))))

    out = []
    checks = load_checks()
    mp = pytest.MonkeyPatch()
    mp.setattr(Figure, "savefig", record)
    try:
        for path in FIXTURES:
            seen.clear()
            directory = tmp_path_factory.mktemp("plots")
            result = check_scene(path, checks, settings=Settings(plots=directory))
            scene = result.to_json()
            assert not any("pictures of" in n for n in result.notes), result.notes
            out += [(scene, name, text) for name, text in seen]
    finally:
        mp.undo()
    return out


@pytest.mark.slow
def test_every_fixture_is_drawn(drawn: list[tuple[dict[str, Any], str, str]]) -> None:
    drawn_scenes = {scene["path"] for scene, _, _ in drawn}
    assert len(drawn_scenes) == len(FIXTURES)
    # the failing and warning fixtures are among them, each check with pictures drawn
    statuses = {scene["status"] for scene, _, _ in drawn}
    assert {"pass", "warn", "fail"} <= statuses
    for _, name, _ in drawn:
        assert any(c in name for c in CHECK_IDS), name


def test_titles_carry_the_json_verdicts(drawn: list[tuple[dict[str, Any], str, str]]) -> None:
    for scene, name, text in drawn:
        words = {c["id"]: _word(c) for c in scene["checks"] if c["status"] != "skipped"}
        own = _own(scene, name, words)
        said = re.findall(rf"\b({'|'.join(map(re.escape, words))}) ({WORDS})\b", text)
        assert said, f"{name}: no verdict in its title: {text!r}"
        # the picture's own check first, with the JSON's verdict
        assert said[0] == (own, words[own].upper()), (name, text)
        for check, word in said:
            assert word == words[check].upper(), (name, check, word, text)
        scene_said = re.findall(rf"\bscene ({WORDS})\b", text)
        if RANK[scene["status"]] > RANK[words[own]]:
            assert scene_said == [scene["status"].upper()], (name, text)
            # every check that makes the scene worse is named with its verdict
            for check, word in words.items():
                if RANK[word] > RANK[words[own]]:
                    assert (check, word.upper()) in said, (name, check, text)
        else:
            assert scene_said == [], (name, text)


def test_titles_carry_the_margin_the_json_gives(
    drawn: list[tuple[dict[str, Any], str, str]],
) -> None:
    """The design margin in a title is the check's own `design_margin_deg`, as written."""
    for scene, name, text in drawn:
        checks = {c["id"]: c for c in scene["checks"]}
        own = _own(scene, name, checks)
        margin = checks[own].get("design_margin_deg")
        if isinstance(margin, float) and checks[own].get("safe_ranges_deg") != []:
            assert f"{own} {_word(checks[own]).upper()}" in text
            assert f"margin {margin:.2f}°" in text, (name, text)


def test_graphical_picture_of_the_failing_scene_says_so(
    drawn: list[tuple[dict[str, Any], str, str]],
) -> None:
    """The reviewer's case: thesis appendix A passes Koster's construction, but the scene fails
    because retracting x3 makes y1 lose contact; the construction's picture says both."""
    (text,) = [
        t for s, n, t in drawn if "appendix-a" in s["path"] and n.endswith("graphical-2d.png")
    ]
    assert "graphical-2d PASS (mass-free" in text
    assert "scene FAIL: analytical-2d FAIL — retract x3 → y1 loses contact" in text


def test_a_failing_sphere_map_keeps_the_design_star(tmp_path: Path) -> None:
    """The 3-2-1 block pushed the wrong way: analytical-3d fails, its map is centred on the
    most robust direction, and the design direction (161° from it, on the other hemisphere)
    is still drawn as the star, on the rim, inside the map's frame."""
    from matplotlib.figure import Figure

    source = ROOT / "fixtures" / "block-321"
    (tmp_path / "block.stl").write_bytes((source / "block.stl").read_bytes())
    text = (source / "block.kcheck.yaml").read_text()
    scene = tmp_path / "block.kcheck.yaml"
    scene.write_text(
        text.replace("direction: [-0.57, -0.82, 0.04]", "direction: [0.57, 0.82, 0.3]")
    )
    figures: dict[str, list[Any]] = {}

    def record(fig: Figure, path: Any, *args: Any, **kwargs: Any) -> None:
        figures[Path(path).name] = [
            (ax.get_xlim(), ax.get_ylim(), [ln for ln in ax.lines if ln.get_marker() == "*"])
            for ax in fig.axes
        ]

    checks = [c for c in load_checks() if c.spec.name == "analytical-3d"]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Figure, "savefig", record)
        result = check_scene(scene, checks, settings=Settings(plots=tmp_path / "plots"))
    assert result.checks[0].status.value == "fail"
    (sphere,) = [v for k, v in figures.items() if k.endswith("-sphere.png")]
    zoom, overview = sphere[0], sphere[1]
    for xlim, ylim, stars in (zoom, overview):
        assert len(stars) == 1
        (x,), (y,) = stars[0].get_data()
        assert xlim[0] <= x <= xlim[1] and ylim[0] <= y <= ylim[1]
