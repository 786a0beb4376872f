"""One colour language across the pictures (issue 22): every colour is written once, in
``kcheck/pictures/colours.py``; no picture module (nor a script drawing the docs' figures,
``docs/figures/*.py``) writes a colour of its own, and the legend picture renders the language
with its meanings."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

pytest.importorskip("matplotlib")

ROOT = Path(__file__).resolve().parents[2]
PICTURE_MODULES = sorted(
    [
        *(ROOT / "plugins/kcheck_checks/pictures").glob("*.py"),
        *(ROOT / "kcheck/pictures").glob("*.py"),
        *(ROOT / "docs/figures").glob("*.py"),
    ]
)
PALETTE = ROOT / "kcheck/pictures/colours.py"
HEX = re.compile(r"#[0-9a-fA-F]{3}(?:[0-9a-fA-F]{3})?(?:[0-9a-fA-F]{2})?")
GREY = re.compile(r"0?\.\d+|0|1(?:\.0*)?")
CYCLE = re.compile(r"C\d")
#: Arguments and style keys that take a colour, where one-letter colours ("k") count.
COLOUR_KEYS = {"color", "colors", "c", "mec", "mfc", "fc", "ec", "edgecolor", "facecolor"}


def _colour_names() -> set[str]:
    """Every colour or colour-map name matplotlib knows (CSS and xkcd names, tab:, maps)."""
    import matplotlib
    from matplotlib import colors

    names = {*colors.CSS4_COLORS, *colors.TABLEAU_COLORS, *colors.BASE_COLORS}
    names |= {*colors.XKCD_COLORS, *matplotlib.colormaps}
    # one-letter names ("y", "k") are colours only as a colour argument (axis="y" is not)
    return {n.lower() for n in names if len(n) > 1} - {"none"}


def colour_literals(path: Path, names: set[str]) -> list[tuple[int, str]]:
    """(line, text) of every string in ``path`` that is a colour: a hex code, a grey level, a
    colour or colour-map name, a property-cycle colour ``C3`` or ``f"C{i}"``."""
    found: list[tuple[int, str]] = []
    tree = ast.parse(path.read_text(encoding="utf-8"))
    parts = {id(v) for n in ast.walk(tree) if isinstance(n, ast.JoinedStr) for v in n.values}
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in parts:
            text = node.value.strip()
            if (
                HEX.fullmatch(text)
                or GREY.fullmatch(text)
                or CYCLE.fullmatch(text)
                or text.lower() in names
            ):
                found.append((node.lineno, text))
        elif isinstance(node, ast.keyword | ast.Dict):
            pairs = (
                [(node.arg, node.value)]
                if isinstance(node, ast.keyword)
                else [(k.value if isinstance(k, ast.Constant) else None, v)
                      for k, v in zip(node.keys, node.values, strict=True)]
            )  # fmt: skip
            for key, value in pairs:
                if (
                    key in COLOUR_KEYS
                    and isinstance(value, ast.Constant)
                    and isinstance(value.value, str)
                    and len(value.value) == 1
                ):
                    found.append((value.lineno, value.value))
        elif isinstance(node, ast.JoinedStr) and node.values:
            first = node.values[0]
            if isinstance(first, ast.Constant) and first.value == "C" and len(node.values) == 2:
                found.append((node.lineno, "f'C{...}'"))
    return found


def test_the_detector_finds_colours(tmp_path: Path) -> None:
    sample = tmp_path / "sample.py"
    sample.write_text(
        'a = "#d62728"\nb = "tab:red"\nc = "0.35"\nd = "navy"\ne = f"C{1}"\nf = "Greens"\n'
        'g = "none"\nh = "safe force directions"\ni = dict(color="k", axis="y")\n'
    )
    found = {text for _, text in colour_literals(sample, _colour_names())}
    assert found == {"#d62728", "tab:red", "0.35", "navy", "f'C{...}'", "Greens", "k"}


def test_no_picture_module_writes_a_colour() -> None:
    assert ROOT / "docs/figures/tool_changer.py" in PICTURE_MODULES  # the docs' figures too
    names = _colour_names()
    offenders = {
        path.relative_to(ROOT).as_posix(): literals
        for path in PICTURE_MODULES
        if path != PALETTE and (literals := colour_literals(path, names))
    }
    assert offenders == {}


def test_the_language_is_seven_distinct_colours() -> None:
    from matplotlib.colors import to_rgb

    from kcheck.pictures import colours

    meanings = [meaning.split(":")[0] for _, _, meaning in colours.LANGUAGE]
    for word in ("safe", "marginal", "failing", "jamming", "lost contact", "design", "supports"):
        assert any(m.startswith(word) for m in meanings), word
    rgb = [to_rgb(c) for c, _, _ in colours.LANGUAGE]
    # every two meanings differ clearly: at least 0.15 apart in some channel (0..1)
    for i in range(len(rgb)):
        for j in range(i):
            assert max(abs(a - b) for a, b in zip(rgb[i], rgb[j], strict=True)) > 0.15
    # outcomes speak the language
    assert colours.outcome_colour("closes") == colours.SAFE
    assert colours.outcome_colour("opens") == colours.FAILING
    assert colours.outcome_colour("loses_contact") == colours.LOST_CONTACT
    assert colours.outcome_colour("jams") == colours.JAMMING
    assert "marginal" in colours.VERDICT_COLOURS


def test_the_legend_picture_renders_every_meaning(tmp_path: Path) -> None:
    from matplotlib.colors import to_rgba

    from kcheck.pictures import colours
    from kcheck.pictures.legend import draw_legend, write_legend

    fig = draw_legend()
    fig.canvas.draw()
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    faces = {to_rgba(p.get_facecolor())[:3] for ax in fig.axes for p in ax.patches}
    for colour, name, meaning in colours.LANGUAGE:
        assert any(meaning in t for t in texts), meaning
        assert any(name in t for t in texts), name
        assert to_rgba(colour)[:3] in faces, colour
    paths = write_legend(tmp_path / "colour-legend.png")
    assert paths and paths[0].stat().st_size > 1000
    assert paths[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_docs_show_the_legend_and_name_every_colour() -> None:
    """docs/report.md shows the legend picture and names each colour with its meaning."""
    from kcheck.pictures import colours

    report = (ROOT / "docs" / "report.md").read_text(encoding="utf-8")
    assert "(img/colour-legend.png)" in report
    assert (ROOT / "docs" / "img" / "colour-legend.png").stat().st_size > 1000
    for _, name, _ in colours.LANGUAGE:
        assert f"**{name}**" in report, name
