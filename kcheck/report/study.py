"""The HTML page of a ``kcheck study``: its summary (the lines the command prints), the best
variant, the sensitivity ranking and the study's pictures, in one self-contained page styled
as the check report (pictures inlined as data: URLs; the page fetches nothing)."""

from __future__ import annotations

import base64
import datetime
from collections.abc import Mapping, Sequence
from html import escape
from importlib import resources
from pathlib import Path
from typing import Any

from kcheck import __version__

__all__ = ["render_study_page"]

CSP = "default-src 'none'; style-src 'unsafe-inline'; img-src data:"


def _e(text: object) -> str:
    return escape(str(text), quote=True)


def render_study_page(
    title: str,
    lines: Sequence[str],
    best: Mapping[str, Any] | None,
    sensitivity: Mapping[str, Sequence[tuple[str, float]]],
    pictures: Sequence[Path],
) -> str:
    """The page: ``lines`` as the summary, the best variant's row, one sensitivity table per
    figure, and each PNG or SVG picture."""
    style = resources.files("kcheck.report").joinpath("report.css").read_text(encoding="utf-8")
    when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    out = [
        "<!DOCTYPE html>\n",
        '<html lang="en"><head><meta charset="utf-8">',
        f'<meta http-equiv="Content-Security-Policy" content="{CSP}">',
        f"<title>kcheck study: {_e(title)}</title><style>{style}</style></head><body><main>",
        f"<h1>kcheck study: {_e(title)}</h1>",
        f'<div class="muted small">kcheck {_e(__version__)} · {_e(when)}</div>',
        "<h2>Summary</h2><ul>",
        *(f"<li>{_e(line)}</li>" for line in lines),
        "</ul>",
    ]
    if best is not None:
        out.append("<h2>Best variant</h2><table><tbody>")
        out += [
            f'<tr><th>{_e(k)}</th><td class="num">{_e(v)}</td></tr>'
            for k, v in best.items()
            if v is not None
        ]
        out.append("</tbody></table>")
    for figure, ranking in sensitivity.items():
        if not ranking:
            continue
        out.append(f"<h2>Sensitivity of {_e(figure)}</h2>")
        out.append("<table><thead><tr><th>parameter</th><th>Spearman ρ</th></tr></thead><tbody>")
        out += [f'<tr><td>{_e(n)}</td><td class="num">{r:+.3f}</td></tr>' for n, r in ranking]
        out.append("</tbody></table>")
    if pictures:
        out.append("<h2>Pictures</h2>")
    for path in pictures:
        kind = "svg+xml" if path.suffix == ".svg" else "png"
        data = base64.b64encode(path.read_bytes()).decode()
        out.append(
            f'<figure><img alt="{_e(path.stem)}" src="data:image/{kind};base64,{data}">'
            f"<figcaption>{_e(path.stem)}</figcaption></figure>"
        )
    out.append("</main></body></html>\n")
    return "".join(out)
