"""Output examples in the docs are what the tool prints: every ```text or ```console block of
docs/*.md and README.md that starts with `$ kcheck ...` run from the repository root is run,
and its output must match the block.

A line `...` in a block stands for any number of lines (an abridged example); run times
(`in 4.6 s`, `, 1.93 s`) and trailing blanks are not compared. Blocks whose command needs
files outside the repository (a scene the reader writes) or says `# abridged` are left out.

`KCHECK_RECORD_DOCS=1 pytest tests/test_docs_examples.py` rewrites every unabridged block
that no longer matches with what the tool prints (review the diff before committing it).
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys

import pytest

from tests.conftest import ROOT

BLOCK = re.compile(r"```(?:text|console)\n\$ (kcheck [^\n]*)\n(.*?)```", re.S)
TIME = re.compile(r"\b\d+(?:\.\d+)? (?:s|ms)\b")


def _examples() -> list[tuple[str, str, str]]:
    found = []
    for md in sorted([*(ROOT / "docs").glob("*.md"), ROOT / "README.md"]):
        for m in BLOCK.finditer(md.read_text(encoding="utf-8")):
            command, body = m.group(1), m.group(2)
            if "#" in command:  # `# abridged`, `# the scene's "warnings", two of eight`
                continue
            args = shlex.split(command)[1:]
            paths = [a for a in args if not a.startswith("-") and ("/" in a or "." in a)]
            if not all((ROOT / a).exists() for a in paths):
                continue  # a file the reader writes
            found.append((f"{md.name}: {command}", command, body))
            _SOURCES[(command, body)] = md
    return found


def _pattern(body: str) -> re.Pattern[str]:
    parts = []
    for line in body.rstrip("\n").split("\n"):
        if line.strip() == "...":
            parts.append(r"(?:[^\n]*\n)*?")
            continue
        escaped = re.escape(TIME.sub("TIME", line.rstrip())).replace(
            "TIME", r"\d+(?:\.\d+)? (?:s|ms)"
        )
        parts.append(escaped + r"[ \t]*\n")
    return re.compile("".join(parts) + r"\Z")


_SOURCES: dict[tuple[str, str], object] = {}
EXAMPLES = _examples()


def test_the_docs_have_runnable_examples():
    # The report's own examples at least: a change to this file's discovery must not
    # silently turn the drift check into no check.
    names = [name for name, _, _ in EXAMPLES]
    assert "report.md: kcheck check fixtures/" in names
    assert "report.md: kcheck check fixtures/ -q" in names


@pytest.mark.parametrize(
    ("command", "body"), [e[1:] for e in EXAMPLES], ids=[e[0] for e in EXAMPLES]
)
def test_example_output_is_what_the_tool_prints(command, body):
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "FORCE_COLOR")}
    env["NO_COLOR"] = "1"
    proc = subprocess.run(
        [sys.executable, "-m", "kcheck", *shlex.split(command)[1:]],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    printed = "\n".join(line.rstrip() for line in (proc.stdout + proc.stderr).split("\n"))
    printed = printed.rstrip("\n") + "\n"
    if os.environ.get("KCHECK_RECORD_DOCS") and "..." not in body.split("\n"):
        md = _SOURCES[(command, body)]
        text = md.read_text(encoding="utf-8")  # type: ignore[attr-defined]
        old = f"$ {command}\n{body}```"
        assert text.count(old) == 1, f"{md}: `{command}` with this output is not unique"
        md.write_text(  # type: ignore[attr-defined]
            text.replace(old, f"$ {command}\n{printed}```"), encoding="utf-8"
        )
        return
    assert _pattern(body).match(printed), (
        f"the example of `{command}` no longer matches what it prints; run it and paste the "
        f"output (NO_COLOR=1, COLUMNS unset). It printed:\n{printed}"
    )
