"""The HTML report in a real browser: Debian's headless Chromium renders the page written by
``kcheck check --html``, with every verdict and picture present, and no network request.

The browser is found on PATH (``.ci/run`` installs Debian's ``chromium`` when it is missing);
the test is skipped, saying so, only where no Chromium is installed. Network requests are
seen in Chromium's own net log (requests whose isolation key is the page's ``file://`` site)
and in its console (a request the page's Content-Security-Policy blocks is still an attempt);
a probe page that does make a request proves the detector sees one. The console is read by
what the browser attributes to the page (its ``file://`` address), not by the wording of
Chromium's messages, which changes between releases ("Refused to load the image ..." became
"Loading the image ... violates ...").
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.conftest import FIXTURES, PLANAR_SCENE

BROWSERS = ("chromium", "chromium-browser", "google-chrome")
FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--hide-scrollbars",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-default-apps",
    "--disable-extensions",
    "--no-first-run",
    "--enable-logging=stderr",
    "--v=0",
    "--net-log-capture-mode=Default",
)


def _browser() -> str:
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    pytest.skip("no Chromium on PATH (Debian: apt-get install chromium; .ci/run installs it)")


def _open(
    page: Path, work: Path, screenshot: Path | None = None
) -> tuple[str, list[str], list[str]]:
    """Load ``page`` headless: its DOM after load, the URLs the page requested, and the lines
    of the browser's log that concern the page (its console messages name it as source)."""
    net = work / f"{page.stem}-net.json"
    args = [_browser(), *FLAGS, f"--user-data-dir={work / 'profile'}", f"--log-net-log={net}"]
    if screenshot is not None:
        args += [f"--screenshot={screenshot}", "--window-size=1280,2000"]
    proc = subprocess.run(
        [*args, "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    events = json.loads(net.read_text(encoding="utf-8"))["events"]
    # Requests of the page (not of the browser itself) carry the page's site as isolation key.
    requested = sorted(
        {
            e["params"]["url"]
            for e in events
            if "file://" in str(e.get("params", {}).get("network_isolation_key", ""))
            and "url" in e["params"]
        }
    )
    said = [line for line in proc.stderr.splitlines() if page.as_uri() in line]
    return proc.stdout, requested, said


@pytest.fixture(scope="module")
def page(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int, Path]:
    """One run: a passing scene, a failing one (checks that disagree), and a bad file."""
    from kcheck.cli import main

    work = tmp_path_factory.mktemp("html")
    bad = work / "bad" / "broken.kcheck.yaml"
    bad.parent.mkdir()
    text = (FIXTURES / "planar-block" / "block.kcheck.yaml").read_text()
    bad.write_text(text.replace("friction: 0.1", "friction: -1"), encoding="utf-8")
    html = work / "report.html"
    plots = work / "plots"
    scenes = [FIXTURES / "planar-block", FIXTURES / "thesis-appendix-a", bad]
    code = main(["check", *map(str, scenes), "--html", str(html), "--plots", str(plots), "-q"])
    return html, code, plots


def test_page_is_self_contained(page: tuple[Path, int, Path]) -> None:
    html, code, _ = page
    assert code == 2  # the bad file is an input error; the other scenes are still reported
    text = html.read_text(encoding="utf-8")
    assert "Content-Security-Policy" in text and "default-src 'none'" in text
    # Nothing to fetch: no external source, link target, style URL or import.
    assert not re.search(r"""(src|href)\s*=\s*["'](?!#|data:)""", text)
    assert not re.search(r"url\((?!#)", text)  # only references inside an SVG
    assert "@import" not in text and "<script" not in text


def test_page_renders_in_chromium(
    page: tuple[Path, int, Path], tmp_path: Path, record_property: Callable[..., None]
) -> None:
    html, _, plots = page
    shot = tmp_path / "report.png"
    dom, requested, console = _open(html, tmp_path, screenshot=shot)
    record_property("screenshot", str(shot))

    # The summary first: the run's verdict, then one row per scene with its verdict.
    assert dom.index('class="banner error"') < dom.index('class="summary"') < dom.index("<section")
    badges = re.findall(r'<span class="badge (\w+)">([^<]+)</span>', dom)
    summary = dom[dom.index('class="summary"') : dom.index("</table>", dom.index("summary"))]
    assert re.findall(r'class="badge (\w+)"', summary) == ["pass", "fail", "error"]
    assert {word for css, word in badges} >= {"pass", "fail", "error", "n/a"}
    # Each scene has its section, reachable from the summary.
    for i in (1, 2, 3):
        assert f'href="#scene-{i}"' in dom and f'id="scene-{i}"' in dom
    # The failing scene explains itself; the mass-free construction says what it cannot see
    # and that the analytical check disagrees.
    failing = dom[dom.index('id="scene-2"') : dom.index('id="scene-3"')]
    assert "mass-free: contact loss not checked" in failing
    assert "<b>but</b> analytical-2d: FAIL" in failing
    assert "x3 loses contact" in failing
    # The bad file: its error located by line.
    assert re.search(r"broken\.kcheck\.yaml:\d+", dom[dom.index('id="scene-3"') :])
    # Every picture is there, inline.
    svgs = sorted(p.name for p in plots.glob("*.svg"))
    assert len(svgs) >= 4
    assert dom.count("<svg") == len(svgs)
    for name in svgs:
        assert f"<figcaption>{name}</figcaption>" in dom

    # No request left the page, and none was even attempted (and blocked by the CSP): the
    # page said nothing on the console.
    assert requested == []
    assert console == []

    # The screenshot shows the verdict at a glance: the banner in the error colour.
    from PIL import Image

    image = Image.open(shot).convert("RGB")
    assert image.size == (1280, 2000)
    colours = image.getcolors(maxcolors=1 << 20) or []
    error_purple = (0x82, 0x50, 0xDF)
    assert any(colour == error_purple and n > 20_000 for n, colour in colours)


def test_the_request_detector_sees_a_request(tmp_path: Path) -> None:
    """Positive control: a page that loads an image from the network is caught, and the same
    page under kcheck's Content-Security-Policy shows the blocked attempt in the console."""
    probe = tmp_path / "probe.html"
    probe.write_text('<!DOCTYPE html><img src="http://127.0.0.1:9/x.png">', encoding="utf-8")
    _, requested, _ = _open(probe, tmp_path)
    assert requested == ["http://127.0.0.1:9/x.png"]
    from kcheck.report.html import CSP

    blocked = tmp_path / "blocked.html"
    blocked.write_text(
        f'<!DOCTYPE html><meta http-equiv="Content-Security-Policy" content="{CSP}">'
        '<img src="http://127.0.0.1:9/x.png">',
        encoding="utf-8",
    )
    _, requested, console = _open(blocked, tmp_path)
    assert requested == [] and any("http://127.0.0.1:9/x.png" in line for line in console)


def test_a_page_that_cannot_be_written_is_a_usage_error(cli, write_scene, tmp_path: Path) -> None:
    scene = str(write_scene(PLANAR_SCENE))
    blocker = tmp_path / "a-file"
    blocker.write_text("", encoding="utf-8")
    code, _, err = cli("check", scene, "--select", "maxwell", "--html", str(blocker / "r.html"))
    assert code == 2 and "--html" in err and f"{blocker} is a file, not a folder" in err
    if Path("/dev/full").exists():  # the disk fills up while the page is written
        code, _, err = cli("check", scene, "--select", "maxwell", "--html", "/dev/full")
        assert code == 2 and "--html /dev/full: no space left on the device" in err
    assert "Traceback" not in err


#: Where screenshots are kept as test artifacts: ``$KCHECK_TEST_ARTIFACTS`` when set (CI
#: uploads that folder, docs/ci.md), else the test's temporary folder.
ARTIFACTS_ENV = "KCHECK_TEST_ARTIFACTS"


def _artifacts(tmp_path: Path) -> Path:
    import os

    folder = Path(os.environ.get(ARTIFACTS_ENV) or tmp_path)
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@pytest.mark.parametrize("width", [420, 1280])
def test_page_fits_the_screen(
    page: tuple[Path, int, Path],
    tmp_path: Path,
    width: int,
    record_property: Callable[..., None],
) -> None:
    """No sideways scrolling on a phone (420 px) or a laptop (1280 px), and nothing fetched:
    Playwright drives Debian's Chromium (the one on PATH) at that viewport width over the page
    exactly as written, its Content-Security-Policy included; every request the page makes is
    recorded; a full-page screenshot is kept as a test artifact."""
    sync_api = pytest.importorskip("playwright.sync_api", reason="the `test` extra installs it")
    html, _, _ = page
    shot = _artifacts(tmp_path) / f"report-{width}px.png"
    requested: list[str] = []
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=_browser(), args=["--no-sandbox"])
        try:
            view = browser.new_page(viewport={"width": width, "height": 1000})
            view.on("request", lambda request: requested.append(request.url))
            view.goto(html.as_uri(), wait_until="load")
            scroll_width, inner_width = view.evaluate(
                "[document.scrollingElement.scrollWidth, window.innerWidth]"
            )
            widest = view.evaluate(
                "(() => { let w = 0, tag = ''; for (const e of document.querySelectorAll('body *'))"
                " { const r = e.getBoundingClientRect().right;"
                " if (r > w) { w = r; tag = e.tagName + '.' + e.className; } }"
                " return [Math.round(w), tag]; })()"
            )
            view.screenshot(path=str(shot), full_page=True)
        finally:
            browser.close()
    record_property("screenshot", str(shot))
    assert inner_width == width
    assert scroll_width <= inner_width, f"{scroll_width} px of content in a {width} px window"
    assert widest[0] <= width, f"{widest[1]} reaches {widest[0]} px in a {width} px window"
    # Offline: the page itself is the only thing loaded (pictures are inline SVG or data:).
    assert [url for url in requested if not url.startswith("data:")] == [html.as_uri()]
    from PIL import Image

    with Image.open(shot) as image:
        assert image.size[0] == width and image.size[1] > 1000  # the whole page, not a crop


def test_playwright_sees_overflow_and_requests(tmp_path: Path) -> None:
    """Positive control for the test above: a page 600 px wide overflows a 420 px viewport,
    and its image request is recorded."""
    sync_api = pytest.importorskip("playwright.sync_api", reason="the `test` extra installs it")
    probe = tmp_path / "wide.html"
    probe.write_text(
        '<!DOCTYPE html><div style="width:600px">wide</div><img src="http://127.0.0.1:9/x.png">',
        encoding="utf-8",
    )
    requested: list[str] = []
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=_browser(), args=["--no-sandbox"])
        try:
            view = browser.new_page(viewport={"width": 420, "height": 600})
            view.on("request", lambda request: requested.append(request.url))
            view.goto(probe.as_uri(), wait_until="load")
            scroll_width = view.evaluate("document.scrollingElement.scrollWidth")
        finally:
            browser.close()
    assert scroll_width > 420
    assert "http://127.0.0.1:9/x.png" in requested


#: The fixtures' page may weigh this much (issue 22: it was 12.6 MB, then 4.7 MB).
FIXTURES_PAGE_BYTES = 2_000_000


@pytest.mark.slow
def test_fixtures_page_is_light(tmp_path: Path) -> None:
    """Every fixture with every picture, in one page of at most 2 MB (docs/report.md: vector
    pictures with shared styles, heavy shading embedded as lossless WebP)."""
    from kcheck.cli import main

    html = tmp_path / "fixtures.html"
    main(["check", str(FIXTURES), "--html", str(html), "-q"])
    text = html.read_text(encoding="utf-8")
    scenes = len(list(FIXTURES.rglob("*.kcheck.yaml")))
    # Every scene is there with its pictures: the page is light, not empty.
    assert text.count('<section class="scene') == scenes
    assert text.count("<svg") >= 5 * scenes
    assert html.stat().st_size <= FIXTURES_PAGE_BYTES, html.stat().st_size
