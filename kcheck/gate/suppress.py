"""Accepted failures: inline suppressions in a scene, per-path ignores in the configuration,
and the baseline file (issue 23).

A suppressed failure does not fail the run; it stays in the result, in its check's
``suppressed`` findings, each saying why (``Finding.suppressed``). A check whose every failure
is suppressed passes. Only failed checks' findings can be suppressed: bad input, crashes and
budgets cannot.

Inline, in the scene: ``# kcheck: ignore[CODE, ...] -- REASON``. ``CODE`` is a check id
(``jamming``: every rule of the check) or a rule (``analytical-2d/jams``). At the end of a
line it covers the failures located on that line; on a line of its own in the comments
before the first field, the whole scene; on a line of its own further down, the next line
holding a field. A suppression without a reason, or with no code, is an input error located
at the comment. One that covers no failure is reported as the scene warning
``unused-suppression``.
"""

from __future__ import annotations

import json
import os
import re
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

from kcheck.errors import format_path
from kcheck.records import dataclass
from kcheck.result import (
    BASELINE_REASON,
    PER_PATH_REASON,
    CheckResult,
    Finding,
    SceneResult,
    Status,
)

__all__ = [
    "Suppression",
    "SuppressionError",
    "inline_suppressions",
    "Baseline",
    "PathIgnores",
    "apply",
    "baseline_key",
    "write_baseline",
    "BASELINE_VERSION",
]

BASELINE_VERSION = 1

_MARK = re.compile(r"#\s*kcheck\s*:")
_FULL = re.compile(r"#\s*kcheck\s*:\s*ignore\[(?P<codes>[^\]]*)\]\s*(?P<rest>.*)$")
_CODE = re.compile(r"^[A-Za-z0-9_.-]+(/[A-Za-z0-9_.-]+)?$")


class SuppressionError(ValueError):
    """A malformed suppression comment, at ``line``:``column``."""

    def __init__(self, message: str, line: int, column: int) -> None:
        super().__init__(message)
        self.line = line
        self.column = column


@dataclass(frozen=True)
class Suppression:
    """One inline suppression: the codes it names, its reason, the line of the comment and
    the line it covers (None: the whole scene)."""

    codes: tuple[str, ...]
    reason: str
    line: int
    covers: int | None


def _comment_start(text: str) -> int | None:
    """Where a ``# kcheck:`` comment starts on a YAML line (a ``#`` at the line's start or
    after white space, outside quotes as far as a line tells), else None."""
    quote: str | None = None
    for k, ch in enumerate(text):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"" and (k == 0 or text[k - 1] in " :[{,-"):
            quote = ch
        elif ch == "#" and (k == 0 or text[k - 1] in " \t") and _MARK.match(text, k):
            return k
    return None


def inline_suppressions(text: str) -> list[Suppression]:
    """Every ``# kcheck: ignore[...] -- reason`` comment of a scene's text; raises
    :class:`SuppressionError` for a malformed one."""
    found: list[Suppression] = []
    if _MARK.search(text) is None:  # most scenes: no kcheck comment to look for, line by line
        return found
    pending: list[tuple[tuple[str, ...], str, int]] = []
    header = True
    for number, raw in enumerate(text.splitlines(), start=1):
        stripped = raw.strip()
        if not stripped or stripped == "---":
            continue
        start = _comment_start(raw) if _MARK.search(raw) else None
        own_line = stripped.startswith("#")
        if start is not None:
            codes, reason = _parse(raw[start:], number, start + 1)
            if not own_line:
                found.append(Suppression(codes, reason, number, number))
            elif header:
                found.append(Suppression(codes, reason, number, None))
            else:
                pending.append((codes, reason, number))
        if own_line:
            continue
        header = False
        found.extend(Suppression(c, r, n, number) for c, r, n in pending)
        pending = []
    # Own-line suppressions after the last field cover nothing: reported as unused.
    found.extend(Suppression(c, r, n, -1) for c, r, n in pending)
    return found


def _parse(comment: str, line: int, column: int) -> tuple[tuple[str, ...], str]:
    example = "`# kcheck: ignore[jamming] -- why this failure is accepted`"
    match = _FULL.match(comment)
    if match is None:
        raise SuppressionError(
            f"malformed kcheck comment {comment.strip()!r}: expected {example}", line, column
        )
    codes = tuple(c.strip() for c in match["codes"].split(",") if c.strip())
    if not codes:
        raise SuppressionError(f"the suppression names no check or rule: expected {example}",
                               line, column)  # fmt: skip
    for code in codes:
        if not _CODE.match(code):
            raise SuppressionError(f"{code!r} is not a check id or rule", line, column)
    rest = match["rest"].strip()
    reason = rest[2:].strip() if rest.startswith("--") else ""
    if not reason:
        raise SuppressionError(
            f"the suppression ignore[{', '.join(codes)}] gives no reason: a suppression needs "
            f"one, after `--`: {example}",
            line,
            column,
        )
    return codes, reason


def covers(code: str, rule: str, check: str) -> bool:
    """Whether a suppression code names this failure (its check, or its rule)."""
    return code in (check, rule) or rule.startswith(code + "/")


def rule_of(check: CheckResult, finding: Finding) -> str:
    """A failure's rule, as :func:`kcheck.report.issues.issues` names it."""
    code = finding.code
    return f"{check.id}/{code}" if code and code != check.id else check.id


def _what(finding: Finding) -> str:
    return format_path(finding.field) if finding.field is not None else finding.message


def relative_path(path: str, root: Path) -> str:
    """A scene's path relative to ``root`` (POSIX), else as given."""
    absolute = Path(os.path.abspath(path))
    try:
        return absolute.relative_to(root).as_posix()
    except ValueError:
        return Path(path).as_posix()


def baseline_key(path: str, rule: str, what: str) -> tuple[str, str, str]:
    """A baseline entry's key: scene path from the repository root, rule, field (else the
    message). No line: a moved line keeps its entry."""
    return (path, rule, what)


class PathIgnores:
    """``per-path-ignores``: gitignore patterns (relative to the configuration's folder) ->
    check ids or rules whose failures are accepted in matching scenes."""

    def __init__(self, table: Mapping[str, Sequence[str]], root: Path) -> None:
        self.root = root
        self.entries: list[tuple[str, Any, tuple[str, ...]]] = []
        if table:
            from pathspec import GitIgnoreSpec

            for pattern, codes in table.items():
                spec = GitIgnoreSpec.from_lines([pattern])
                self.entries.append((pattern, spec, tuple(codes)))

    def codes(self, path: str) -> list[tuple[str, str]]:
        """(pattern, code) pairs that apply to a scene's path."""
        if not self.entries:
            return []
        relative = relative_path(path, self.root)
        return [
            (pattern, code)
            for pattern, spec, codes in self.entries
            if spec.match_file(relative)
            for code in codes
        ]


class Baseline:
    """Accepted failures read from a baseline file: a multiset of keys."""

    def __init__(self, counts: Counter[tuple[str, str, str]], source: str) -> None:
        self.counts = counts
        self.source = source

    @classmethod
    def read(cls, path: Path) -> Baseline:
        """Read a baseline file; ValueError (with the reason) when it is not one."""
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except OSError as exc:
            from kcheck.errors import describe_os_error

            raise ValueError(f"cannot read the baseline: {describe_os_error(exc)}") from exc
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise ValueError(f"not a kcheck baseline (not JSON: {exc})") from exc
        entries = data.get("failures") if isinstance(data, dict) else None
        if not isinstance(entries, list) or data.get("version") != BASELINE_VERSION:
            raise ValueError(
                f'not a kcheck baseline: expected {{"version": {BASELINE_VERSION}, '
                '"failures": [...]}} as written by --write-baseline'
            )
        counts: Counter[tuple[str, str, str]] = Counter()
        for n, e in enumerate(entries):
            if not (isinstance(e, dict) and all(isinstance(e.get(k), str) for k in
                                                 ("path", "rule", "field"))):  # fmt: skip
                raise ValueError(f"failures[{n}]: expected path, rule and field (strings)")
            counts[baseline_key(e["path"], e["rule"], e["field"])] += 1
        return cls(counts, str(path))

    def stale(self, results: Iterable[SceneResult], root: Path) -> list[tuple[str, str, str]]:
        """Entries that matched no failure of the scenes checked (call after the run): of a
        scene whose checks ran, for a check that ran on it. Entries of scenes or checks this
        run left out (``--changed-only``, ``--select``, a scene that did not load) are not
        judged."""
        ran: dict[str, set[str]] = {}
        for scene in results:
            if scene.checks:
                checks = ran.setdefault(relative_path(scene.path, root), set())
                checks.update(c.id for c in scene.checks)
        return sorted(
            key
            for key, left in self.counts.items()
            for _ in range(left)
            if key[1].split("/")[0] in ran.get(key[0], ())
        )

    def take(self, key: tuple[str, str, str]) -> bool:
        """Accept one failure of this key, if the baseline still holds one."""
        if self.counts[key] > 0:
            self.counts[key] -= 1
            return True
        return False


def failures(results: Iterable[SceneResult], root: Path) -> list[dict[str, str]]:
    """The failures of a run that count (not suppressed), as baseline entries, sorted."""
    out = []
    for scene in results:
        path = relative_path(scene.path, root)
        for check in scene.checks:
            if check.status not in (Status.FAIL, Status.MARGINAL):
                continue
            for f in check.findings or (Finding(check.message),):
                out.append({"path": path, "rule": rule_of(check, f), "field": _what(f)})
    return sorted(out, key=lambda e: (e["path"], e["rule"], e["field"]))


def write_baseline(path: Path, results: Iterable[SceneResult], root: Path) -> int:
    """Record the run's failures; return how many."""
    entries = failures(results, root)
    document = {"version": BASELINE_VERSION, "failures": entries}
    path.write_text(json.dumps(document, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    return len(entries)


def apply(
    scene: SceneResult,
    inline: Sequence[Suppression] = (),
    ignores: PathIgnores | None = None,
    baseline: Baseline | None = None,
    root: Path | None = None,
) -> SceneResult:
    """The scene's result with its suppressed failures moved aside (inline first, then
    per-path ignores, then the baseline), its status recomputed, and unused inline
    suppressions as ``unused-suppression`` warnings."""
    from kcheck.gate.runner import scene_status

    if not scene.checks:
        return scene
    path_codes = ignores.codes(scene.path) if ignores is not None else []
    key_path = relative_path(scene.path, root or Path.cwd())
    used: set[int] = set()
    checks = []
    changed = False
    for check in scene.checks:
        if check.status not in (Status.FAIL, Status.MARGINAL):
            checks.append(check)
            continue
        kept: list[Finding] = []
        accepted: list[Finding] = list(check.suppressed)
        for f in check.findings or (Finding(check.message),):
            rule = rule_of(check, f)
            why = None
            for k, s in enumerate(inline):
                if (s.covers is None or s.covers == f.line) and any(
                    covers(c, rule, check.id) for c in s.codes
                ):
                    used.add(k)
                    why = s.reason
                    break
            if why is None:
                for pattern, code in path_codes:
                    if covers(code, rule, check.id):
                        why = f"{PER_PATH_REASON}{pattern!r} ignores {code}"
                        break
            if why is None and baseline is not None:
                if baseline.take(baseline_key(key_path, rule, _what(f))):
                    why = f"{BASELINE_REASON}{baseline.source}"
            if why is None:
                kept.append(f)
            else:
                accepted.append(replace(f, suppressed=why))
        if len(accepted) == len(check.suppressed):
            checks.append(check)
            continue
        changed = True
        if kept:
            checks.append(replace(check, findings=tuple(kept), suppressed=tuple(accepted)))
        else:
            checks.append(
                replace(
                    check,
                    status=Status.PASS,
                    message=f"suppressed: {check.message}",
                    findings=(),
                    suppressed=tuple(accepted),
                )
            )
    ran = {c.id for c in scene.checks if c.status in (Status.PASS, Status.MARGINAL, Status.FAIL)}
    unused = [
        Finding(
            f"unused suppression ignore[{', '.join(s.codes)}]: no failure of "
            f"{', '.join(s.codes)} {'in this scene' if s.covers is None else 'on this line'}",
            code="unused-suppression",
            line=s.line,
            hint="remove the comment",
        )
        for k, s in enumerate(inline)
        if k not in used and any(c.split("/")[0] in ran for c in s.codes)
    ]
    if not changed and not unused:
        return scene
    warnings = (*scene.warnings, *unused)
    status = scene_status(checks, warnings) if scene.status is not Status.ERROR else scene.status
    return replace(scene, checks=tuple(checks), warnings=warnings, status=status)
