"""Links in the docs lead somewhere: every relative link and image of README.md and docs/*.md
names an existing file, and every ``#anchor`` (``#x`` in the same page, ``page.md#x``) names a
heading of the target page, by GitHub's slug of it, or an explicit ``<a id="x">`` there.

Links inside code (fenced blocks, inline code) are not links. External links (``https:``,
``mailto:``) are not followed: the suite runs offline. Anchors into other files than Markdown
(``file.py#L10``) are GitHub's line anchors and are not checked. Plain text, no subprocess.
"""

from __future__ import annotations

import os
import re
import unicodedata
from functools import cache
from pathlib import Path
from urllib.parse import unquote

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted([ROOT / "README.md", *(ROOT / "docs").glob("*.md")])

FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,}).*?^ {0,3}\1[`~]*[ \t]*$", re.S | re.M)
CODE_SPAN = re.compile(r"(`+)(?!`).+?(?<!`)\1(?!`)", re.S)
HTML_COMMENT = re.compile(r"<!--.*?-->", re.S)
# [text](target "title") and ![alt](target): the text may hold one level of brackets.
INLINE = re.compile(
    r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*(<[^>\n]*>|[^()\s]+(?:\([^()\s]*\)[^()\s]*)*)"
    r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^)]*\)))?\s*\)"
)
DEFINITION = re.compile(r"^ {0,3}\[[^\]\n]+\]:\s*(<[^>\n]*>|\S+)", re.M)
HTML_LINK = re.compile(r"<(?:a|img)\b[^>]*?\b(?:href|src)\s*=\s*[\"']([^\"']+)[\"']", re.I)
HEADING = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.+?)(?:[ \t]+#+)?[ \t]*$", re.M)
EXPLICIT_ID = re.compile(r"<[a-z][^>]*?\b(?:id|name)\s*=\s*[\"']([^\"']+)[\"']", re.I)
EXTERNAL = re.compile(r"^[a-z][a-z0-9+.-]*:", re.I)


def _blank(match: re.Match[str]) -> str:
    """The match replaced by spaces, its newlines kept (line numbers stay right)."""
    return re.sub(r"[^\n]", " ", match.group(0))


def prose(text: str) -> str:
    """The page without code blocks, code spans and comments, line numbers unchanged."""
    return CODE_SPAN.sub(_blank, FENCE.sub(_blank, HTML_COMMENT.sub(_blank, text)))


def slug(heading: str) -> str:
    """GitHub's anchor of a heading (as github-slugger makes it): the rendered text lowercased,
    every character but letters, marks, decimal digits, ``_``, ``-`` and spaces dropped, spaces
    made hyphens."""
    text = re.sub(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]\([^)]*\)", r"\1", heading)  # links
    text = re.sub(r"<[^>]+>", "", text)  # inline HTML
    text = re.sub(r"(`+)(.+?)\1", r"\2", text)  # code spans keep their text
    text = re.sub(r"(\*\*|__|\*)(?=\S)(.+?)(?<=\S)\1", r"\2", text)  # emphasis
    kept = (
        c
        for c in text.strip().lower()
        if c in " -" or unicodedata.category(c)[0] in "LM" or unicodedata.category(c) in "NdPc"
    )
    return "".join(kept).replace(" ", "-")


@cache
def anchors(page: Path) -> frozenset[str]:
    """Every anchor a link may name in ``page``: its headings' slugs (repeats numbered -1, -2,
    as GitHub numbers them) and its explicit ``id``/``name`` attributes."""
    raw = page.read_text(encoding="utf-8")
    found: set[str] = set(EXPLICIT_ID.findall(prose(raw)))
    seen: dict[str, int] = {}
    # a heading's code spans are part of its slug: only blocks and comments are blanked
    for m in HEADING.finditer(FENCE.sub(_blank, HTML_COMMENT.sub(_blank, raw))):
        base = slug(m.group(2))
        n = seen.get(base, 0)
        seen[base] = n + 1
        found.add(base if n == 0 else f"{base}-{n}")
    return frozenset(found)


def links(page: Path) -> list[tuple[int, str]]:
    """(line, target) of every link and image of ``page`` outside code."""
    text = prose(page.read_text(encoding="utf-8"))
    found = []
    for pattern in (INLINE, DEFINITION, HTML_LINK):
        for m in pattern.finditer(text):
            target = m.group(1).strip()
            if target.startswith("<") and target.endswith(">"):
                target = target[1:-1]
            found.append((text.count("\n", 0, m.start()) + 1, target))
    return sorted(found)


def broken(page: Path, root: Path = ROOT) -> list[tuple[str, str]]:
    """(where, target) of each relative link of ``page`` that names a missing file or
    anchor; ``where`` is the page, line and what is missing, paths relative to ``root``."""
    page, root, problems = page.resolve(), root.resolve(), []
    for line, target in links(page):
        if EXTERNAL.match(target) or target.startswith("//"):
            continue
        path_part, _, anchor = target.partition("#")
        dest = (page.parent / unquote(path_part)).resolve() if path_part else page
        where = f"{os.path.relpath(page, root)}:{line}"
        if not dest.exists():
            problems.append((f"{where}: no file {os.path.relpath(dest, root)}", target))
        elif anchor and dest.suffix == ".md" and unquote(anchor) not in anchors(dest):
            missing = f"no heading or id '{anchor}' in {os.path.relpath(dest, root)}"
            problems.append((f"{where}: {missing}", target))
    return problems


def test_slugs_are_githubs() -> None:
    # GitHub's anchors of these headings, as github.com renders them (github-slugger's rules:
    # lowercase, punctuation and symbols dropped, each space a hyphen, so " — " gives "--")
    assert slug("`tolerances` — does the coupling close as it may be made?") == (
        "tolerances--does-the-coupling-close-as-it-may-be-made"
    )
    assert slug("One colour language") == "one-colour-language"
    assert slug("5. The contacts: coupling shorthands") == "5-the-contacts-coupling-shorthands"
    assert slug("Friction ranges (`friction_range`)") == "friction-ranges-friction_range"
    assert slug("**Bold** and [a link](x.md) with μ ≥ 0.2") == "bold-and-a-link-with-μ--02"


def test_the_checker_finds_what_is_broken(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    (tmp_path / "there.md").write_text('# A heading\n\n<a id="kept"></a>\n', encoding="utf-8")
    page.write_text(
        "# Top\n\n[ok](there.md#a-heading) [ok](there.md#kept) [ok](#top) ![ok](there.md)\n"
        "[gone](missing.md) ![gone](img/none.png) [bad](there.md#nowhere) [bad](#nope)\n"
        "`[code](missing.md)` [web](https://example.org/x.md#y)\n"
        "```\n[fenced](missing.md)\n```\n[ref]: gone.md\n## Top\n[ok](#top-1) [bad](#top-2)\n",
        encoding="utf-8",
    )
    found = broken(page, tmp_path)
    assert {target for _, target in found} == {
        "missing.md", "img/none.png", "there.md#nowhere", "#nope", "gone.md", "#top-2"
    }  # fmt: skip
    assert ("page.md:4: no file img/none.png", "img/none.png") in found


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_link_resolves(page: Path) -> None:
    assert broken(page) == []
