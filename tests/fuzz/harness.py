"""Running kcheck on fuzz inputs and judging what comes out.

Scene inputs run as one ``kcheck check --format json`` process per batch; every scene of the
batch is judged against its case's expectation, and the process as a whole against the
promise (exit code, nothing on stderr but kcheck's error lines, no traceback, a time limit,
peak memory). A batch-level failure is narrowed down by halving the batch until the input
that causes it is found. ``cli`` inputs run one process each.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from tests.fuzz.model import Case, Expect, make_removable, materialize

__all__ = ["Problem", "Stats", "Harness", "MEMORY_LIMIT_MB", "INPUT_TIME_LIMIT_S"]

#: Peak memory of one kcheck process (and its workers), MB: the issue's bound.
MEMORY_LIMIT_MB = 500.0
#: The longest one input may take (its scene's share of the batch, or a whole cli run), s.
INPUT_TIME_LIMIT_S = 10.0
#: Per-scene time budget given to kcheck (``--timeout``), s.
SCENE_BUDGET_S = 30.0
#: Messages of input errors that concern the file as a whole (no field, so no line).
WHOLE_FILE = re.compile(
    r"the file is empty|larger than|more than one YAML document|not a regular file|"
    r"is a folder|a folder, not|symbolic link|no such file|permission denied|too long|"
    r"cannot read|no \*\.kcheck\.yaml files|time budget|memory|stopped|invalid path|"
    r"expected a mapping of scene fields"
)
PROCESS_CLASSES = ("hang", "traceback", "broken-report", "memory", "stray-output", "wrong-exit")
#: Every kcheck process runs with Python's warnings turned into errors: a warning kcheck let
#: through would print on a user's stderr; here it is a crashed check or an internal error,
#: and so found and located (issue 25).
PYTHON_FLAGS = ("-W", "error")
DROP_PRIVILEGE = (
    "setpriv",
    "--bounding-set=-dac_override,-dac_read_search",
    "--inh-caps=-dac_override,-dac_read_search",
    "--",
)


#: Runs the command and writes its peak resident set (KiB, from wait4) to the file descriptor
#: given first. The command is not started by the fuzzer itself because Linux counts a
#: process's resident set before its exec in its maximum: every child of a fuzzer holding
#: 800 MB of inputs would "peak" at 800 MB. The launcher is small, so its child's number is
#: the command's own. A signal that ends the command ends the launcher the same way.
LAUNCHER = """
import os, signal, sys
fd = int(sys.argv[1])
os.set_inheritable(fd, False)
argv = sys.argv[2:]
pid = os.fork()
if pid == 0:
    try:
        os.execvp(argv[0], argv)
    except OSError as exc:
        os.write(2, f"launcher: {argv[0]}: {exc}\\n".encode())
        os._exit(127)
_, status, usage = os.wait4(pid, 0)
os.write(fd, str(usage.ru_maxrss).encode())
os.close(fd)
if os.WIFSIGNALED(status):
    signal.signal(os.WTERMSIG(status), signal.SIG_DFL)
    os.kill(os.getpid(), os.WTERMSIG(status))
os._exit(os.waitstatus_to_exitcode(status))
"""


@dataclass(frozen=True)
class Problem:
    """A broken promise: its class, the input (``kind-seed-index``), what happened."""

    klass: str
    case: str
    detail: str


@dataclass
class Stats:
    """Counts over a run, per kind of input."""

    inputs: Counter = field(default_factory=Counter)
    accepted: Counter = field(default_factory=Counter)
    rejected: Counter = field(default_factory=Counter)
    named_file: Counter = field(default_factory=Counter)
    with_line: Counter = field(default_factory=Counter)
    with_field: Counter = field(default_factory=Counter)
    #: errors whose field was checked against the schema (along the scene's data)
    real_fields: Counter = field(default_factory=Counter)
    processes: int = 0
    peak_mb: float = 0.0
    peak_what: str = ""
    slowest_s: float = 0.0
    slowest_what: str = ""

    def input_time(self, seconds: float, what: str) -> None:
        if seconds > self.slowest_s:
            self.slowest_s, self.slowest_what = seconds, what

    def memory(self, mb: float, what: str) -> None:
        if mb > self.peak_mb:
            self.peak_mb, self.peak_what = mb, what


@dataclass
class Run:
    """One finished kcheck process."""

    code: int | None  # None: killed at its deadline
    stdout: str
    stderr: str
    wall_s: float
    peak_mb: float
    line_times: list[float]


def _kcheck_env(folder: Path, extra: dict[str, str]) -> dict[str, str]:
    env = {
        "PATH": os.environ.get("PATH", "/usr/bin:/bin"),
        "HOME": str(folder),
        "LANG": "C.UTF-8",
        "PYTHONUNBUFFERED": "1",  # each JSON line arrives as its scene finishes
        "NO_COLOR": "1",
        "COLUMNS": "100",
        "KCHECK_CACHE_DIR": str(folder / ".cache"),
        # One BLAS thread, as kcheck would set itself: the fuzzer keeps to one core.
        "OPENBLAS_NUM_THREADS": "1",
        "OMP_NUM_THREADS": "1",
    }
    env.update(extra)
    return env


def run_process(
    argv: Sequence[str],
    cwd: Path,
    *,
    deadline_s: float,
    unprivileged: bool = False,
    env: dict[str, str] | None = None,
    stdin: bytes | None = None,
) -> Run:
    """Run a command in its own session; kill the whole session at the deadline. Peak memory
    is the largest resident set of the command and every descendant it waited for, as
    measured by a small launcher (see :data:`LAUNCHER`); 0 when the command was killed."""
    if unprivileged and os.geteuid() == 0:
        # Root without the capabilities that override file permissions: mode 000 then
        # means unreadable, as it does for any other user.
        argv = [*DROP_PRIVILEGE, *argv]
    report_r, report_w = os.pipe()
    started = time.monotonic()
    try:
        proc = subprocess.Popen(
            [sys.executable, "-I", "-S", "-c", LAUNCHER, str(report_w), *argv],
            cwd=cwd,
            env=env,
            stdin=subprocess.PIPE if stdin is not None else subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            start_new_session=True,
            pass_fds=(report_w,),
        )
    finally:
        os.close(report_w)
    lines: list[bytes] = []
    times: list[float] = []
    err: list[bytes] = []

    def read_out() -> None:
        assert proc.stdout is not None
        for line in iter(proc.stdout.readline, b""):
            times.append(time.monotonic() - started)
            lines.append(line)

    def read_err() -> None:
        assert proc.stderr is not None
        err.append(proc.stderr.read(16 << 20))
        proc.stderr.read()  # drain the rest unseen

    fired: list[bool] = []

    def kill() -> None:
        fired.append(True)
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass

    readers = [threading.Thread(target=read_out), threading.Thread(target=read_err)]
    for t in readers:
        t.start()
    if stdin is not None and proc.stdin is not None:
        try:
            proc.stdin.write(stdin)
            proc.stdin.close()
        except OSError:
            pass
    timer = threading.Timer(deadline_s, kill)
    timer.start()
    _, status = os.waitpid(proc.pid, 0)
    timer.cancel()
    with os.fdopen(report_r, "rb") as report:  # the launcher wrote and closed it, or died
        measured = report.read().decode() or "0"
    killed = bool(fired)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - started
    try:  # a worker left behind would hold the pipes open
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    for t in readers:
        t.join(timeout=30)
    code = None if killed and proc.returncode == -signal.SIGKILL else proc.returncode
    return Run(
        code,
        b"".join(lines).decode("utf-8", "replace"),
        b"".join(err).decode("utf-8", "replace"),
        wall,
        int(measured) / 1024,
        times,
    )


def _norm(path: str) -> str:
    return os.path.normpath(path)


def claim_matches(claim_field: str | None, finding_field: str | None) -> bool:
    """Whether an error at ``finding_field`` is the error a claim asks for: the same field,
    a part of it, or the named field holding it (``gravity`` for ``gravity[1]``)."""
    if claim_field is None:
        return True
    if finding_field is None:
        return False
    if finding_field == claim_field:
        return True
    if finding_field.startswith((claim_field + ".", claim_field + "[")):
        return True
    anchor = re.sub(r"(\[\d+\])+$", "", claim_field)
    return claim_field.startswith(finding_field) and len(finding_field) >= len(anchor)


class Harness:
    """Runs batches of cases under ``root`` and collects problems and statistics."""

    def __init__(
        self,
        root: Path,
        baseline: dict[str, tuple[str, dict[str, str]]],
        *,
        python: str = sys.executable,
        keep: bool = False,
        log: Any = None,
        time_limit_s: float = INPUT_TIME_LIMIT_S,
    ) -> None:
        self.root = root
        self.baseline = baseline
        self.python = python
        self.keep = keep
        self.log = log
        self.time_limit_s = time_limit_s  # per input: a hang, not a speed test
        self.stats = Stats()
        self.pythonpath: str | None = None  # another kcheck source tree to run
        self.problems: list[Problem] = []
        self._batches = 0

    # --- scene batches --------------------------------------------------------------------

    def _env(self, folder: Path, extra: dict[str, str]) -> dict[str, str]:
        env = _kcheck_env(folder, extra)
        if self.pythonpath:
            env["PYTHONPATH"] = self.pythonpath
        return env

    def scene_argv(self, targets: list[str], jobs: int, extra: Sequence[str]) -> list[str]:
        return [
            self.python,
            *PYTHON_FLAGS,
            "-m",
            "kcheck",
            "check",
            "--format",
            "json",
            "--isolated",
            "-j",
            str(jobs),
            "--timeout",
            f"{SCENE_BUDGET_S:g}",
            *extra,
            "--",
            *targets,
        ]

    def run_batch(
        self,
        cases: Sequence[Case],
        *,
        jobs: int = 1,
        outputs: dict[str, str] | None = None,
        count: bool = True,
    ) -> list[Problem]:
        """Run cases as one batch (writing further ``outputs``, file -> format, which must
        read back); judge it; narrow batch-level failures down to inputs. Returns the
        problems found (also kept in ``self.problems``)."""
        outputs = outputs or {}
        problems, classes = self._judge_batch(
            cases, jobs, _output_args(outputs), count=count, outputs=outputs
        )
        for klass in classes:
            culprits = self._narrow(list(cases), klass, jobs, outputs)
            if not culprits:
                problems.append(
                    Problem(klass, ",".join(c.ident for c in cases[:3]) + ",...", "batch only")
                )
            for case, detail in culprits:
                problems.append(Problem(klass, case.ident, detail))
        self.problems.extend(problems)
        return problems

    def _narrow(
        self, cases: list[Case], klass: str, jobs: int, outputs: dict[str, str]
    ) -> list[tuple[Case, str]]:
        """The inputs that alone cause a batch-level failure, by halving."""
        if len(cases) == 1:
            classes, detail = self._process_only(cases, jobs, outputs)
            return [(cases[0], detail.get(klass, ""))] if klass in classes else []
        half = len(cases) // 2
        found = []
        for part in (cases[:half], cases[half:]):
            classes, _ = self._process_only(part, jobs, outputs)
            if klass in classes:
                found.extend(self._narrow(part, klass, jobs, outputs))
        return found

    def _process_only(
        self, cases: Sequence[Case], jobs: int, outputs: dict[str, str]
    ) -> tuple[list[str], dict[str, str]]:
        run, folder = self._execute(cases, jobs, _output_args(outputs))
        classes, detail = self._process_classes(run, cases, folder, outputs)
        self._cleanup(folder)
        return classes, detail

    def _execute(self, cases: Sequence[Case], jobs: int, extra: Sequence[str]) -> tuple[Run, Path]:
        self._batches += 1
        folder = self.root / f"batch-{self._batches}"
        targets = []
        for case in cases:
            materialize(case, folder / case.ident)
            targets.extend(t if os.path.isabs(t) else f"{case.ident}/{t}" for t in case.targets)
        (folder / ".cache").mkdir(exist_ok=True)
        os.chmod(folder / ".cache", 0o777)
        unprivileged = any(c.unprivileged for c in cases)
        env = self._env(folder, {k: v for c in cases for k, v in c.env.items()})
        deadline = 60 + len(cases) * 2 * self.time_limit_s
        run = run_process(
            self.scene_argv(targets, jobs, extra),
            folder,
            deadline_s=deadline,
            unprivileged=unprivileged,
            env=env,
        )
        self.stats.processes += 1
        return run, folder

    def _cleanup(self, folder: Path) -> None:
        if self.keep:
            return
        make_removable(folder)
        shutil.rmtree(folder, ignore_errors=True)

    def _process_classes(
        self, run: Run, cases: Sequence[Case], folder: Path, outputs: dict[str, str]
    ) -> tuple[list[str], dict[str, str]]:
        """Batch-level failures: class -> detail."""
        found: dict[str, str] = {}
        if run.code is not None and "cannot write" not in run.stderr:
            broken = read_back(outputs, folder)
            if broken:
                found["broken-report"] = "; ".join(p.detail for p in broken)
        if run.code is None:
            found["hang"] = f"killed after {run.wall_s:.0f} s"
        text = run.stdout + run.stderr
        if "Traceback (most recent call last)" in text:
            found["traceback"] = _excerpt(text, "Traceback")
        if run.peak_mb > MEMORY_LIMIT_MB:
            found["memory"] = f"peak {run.peak_mb:.0f} MB"
        doc = _parse(run.stdout)
        if doc is None and run.code is not None:
            found["broken-report"] = f"exit {run.code}; stdout {run.stdout[-300:]!r}"
            found["broken-report"] += f"; stderr {run.stderr[-300:]!r}"
        if doc is not None:
            stray = stray_stderr_lines(run.stderr, doc)
            if stray:
                found["stray-output"] = "\n".join(stray)[:600]
            elif run.stderr.strip() and not any(s["status"] == "error" for s in doc["scenes"]):
                # without an input error there is nothing to say there: stderr stays empty
                found["stray-output"] = run.stderr.strip()[:600]
            want = _exit_code(doc["scenes"])
            if run.code is not None and run.code != want and "cannot write" not in run.stderr:
                found["wrong-exit"] = f"exit {run.code}, expected {want}"
        return list(found), found

    def _judge_batch(
        self,
        cases: Sequence[Case],
        jobs: int,
        extra: Sequence[str],
        *,
        count: bool,
        outputs: dict[str, str],
    ) -> tuple[list[Problem], list[str]]:
        run, folder = self._execute(cases, jobs, extra)
        classes, _ = self._process_classes(run, cases, folder, outputs)
        what = f"batch of {len(cases)} ({cases[0].ident}...)"
        self.stats.memory(run.peak_mb, what)
        problems: list[Problem] = []
        doc = _parse(run.stdout)
        if doc is None:
            self._cleanup(folder)
            return problems, classes
        scenes = doc["scenes"]
        durations = _durations(run.line_times, len(scenes))
        by_path: dict[str, list[int]] = {}
        for i, s in enumerate(scenes):
            by_path.setdefault(_norm(s["path"]), []).append(i)
        claimed: set[int] = set()
        for case in cases:
            if count:
                self.stats.inputs[case.kind] += 1
            for rel, expect in case.results.items():
                keys = {_norm(f"{case.ident}/{rel}")}
                try:
                    keys.add(os.path.relpath(os.path.realpath(folder / case.ident / rel), folder))
                except (OSError, ValueError):
                    pass
                hits = sorted({i for k in keys for i in by_path.get(k, [])} - claimed)
                if not hits:
                    problems.append(Problem("lost-scene", case.ident, f"no result for {rel}"))
                    continue
                i = hits[0]
                claimed.add(i)
                seconds = durations[i]
                if seconds is not None:
                    self.stats.input_time(seconds, case.ident)
                    if seconds > self.time_limit_s:
                        problems.append(Problem("slow", case.ident, f"{seconds:.1f} s"))
                problems.extend(self._judge_scene(case, scenes[i], expect, count, folder))
        seen: set[str] = set()
        for i, s in enumerate(scenes):
            owner = next((c for c in cases if _norm(s["path"]).startswith(c.ident + "/")), None)
            if owner is not None:
                seen.add(owner.ident)
            if i in claimed:
                continue
            if owner is not None and owner.other_results:
                problems.extend(
                    self._judge_scene(owner, s, Expect("any"), count=False, folder=folder)
                )
                continue
            problems.append(Problem("extra-result", owner.ident if owner else "?", s["path"]))
        for case in cases:
            if case.other_results and case.ident not in seen:
                problems.append(Problem("lost-scene", case.ident, "no result at all"))
            for name in case.absent:
                if (folder / name).exists() or (folder / case.ident / name).exists():
                    problems.append(Problem("code-execution", case.ident, f"{name} was created"))
        self._cleanup(folder)
        return problems, classes

    def _judge_scene(
        self, case: Case, r: dict, expect: Expect, count: bool, folder: Path | None = None
    ) -> list[Problem]:
        out: list[Problem] = []
        p = case.ident
        status = r["status"]
        text = json.dumps(r)
        if "internal error" in text:
            out.append(Problem("internal-error", p, (r.get("error") or text)[:400]))
        if status == "error" and not any(c.get("status") == "error" for c in r["checks"]):
            if count:
                self.stats.rejected[case.kind] += 1
            error = r.get("error") or ""
            findings = r.get("errors") or []
            named = r["path"] in error
            lined = any(f.get("line") for f in findings)
            fielded = any(f.get("field") for f in findings)
            if count:
                self.stats.named_file[case.kind] += named
                self.stats.with_line[case.kind] += lined
                self.stats.with_field[case.kind] += fielded
            if not named:
                out.append(Problem("unlocated", p, f"the message names no file: {error[:300]}"))
            for f in findings:
                if not f.get("line") and not (
                    f.get("field") is None and WHOLE_FILE.search(f["message"])
                ):
                    out.append(Problem("unlocated", p, f"no line: {f}"[:400]))
                elif f.get("field") is not None and not f.get("column"):
                    out.append(Problem("unlocated", p, f"no column: {f}"[:400]))
            data = _scene_data(folder, r["path"]) if folder is not None else None
            for f in findings:
                unreal = _unreal(f, data)
                if unreal:
                    out.append(Problem("unreal-field", p, f"{unreal}: {f}"[:400]))
                elif count and data is not None and f.get("field") is not None:
                    self.stats.real_fields[case.kind] += 1
            if expect.outcome in ("valid", "accepted"):
                out.append(Problem("rejected-valid", p, error[:400]))
            elif (
                expect.outcome == "invalid"
                and expect.exact
                and expect.claims
                and not any(
                    claim_matches(c.field, f.get("field")) for c in expect.claims for f in findings
                )
            ):
                claims = ", ".join(f"{c.field} ({c.why})" for c in expect.claims)
                got = "; ".join(f"{f.get('field')}: {f['message']}" for f in findings)
                out.append(
                    Problem("misplaced", p, f"expected an error at {claims}; got {got}"[:500])
                )
            return out
        crashed = [c for c in r["checks"] if c.get("status") == "error"]
        for c in crashed:
            out.append(Problem("check-crash", p, f"{c['id']}: {c.get('message', '')}"[:400]))
        if crashed:
            return out
        if count:
            self.stats.accepted[case.kind] += 1
        if expect.outcome == "invalid":
            claims = ", ".join(f"{c.field} ({c.why})" for c in expect.claims)
            out.append(Problem("accepted-invalid", p, f"{status}; expected an error at {claims}"))
        elif expect.outcome == "valid":
            want_status, want_checks = self.baseline[expect.baseline or ""]
            got_checks = {c["id"]: c["status"] for c in r["checks"]}
            if status != want_status or got_checks != want_checks:
                diff = {
                    k: (want_checks.get(k), got_checks.get(k))
                    for k in set(want_checks) | set(got_checks)
                    if want_checks.get(k) != got_checks.get(k)
                }
                out.append(
                    Problem(
                        "wrong-verdict",
                        p,
                        f"{status} (baseline {expect.baseline}: {want_status}); checks {diff}",
                    )
                )
        return out

    # --- single command lines ---------------------------------------------------------------

    def run_cli(self, case: Case) -> list[Problem]:
        """Run a ``cli`` case (its own process) and judge it."""
        self._batches += 1
        folder = self.root / f"cli-{self._batches}"
        materialize(case, folder)
        (folder / ".cache").mkdir(exist_ok=True)
        argv = [a.replace("{case}", str(folder)) for a in case.argv or ()]
        run = run_process(
            [self.python, *PYTHON_FLAGS, "-m", "kcheck", *argv],
            folder,
            deadline_s=max(60.0, 2 * self.time_limit_s),
            unprivileged=case.unprivileged,
            env=self._env(folder, case.env),
            stdin=case.stdin,
        )
        self.stats.processes += 1
        self.stats.inputs[case.kind] += 1
        self.stats.memory(run.peak_mb, case.ident)
        self.stats.input_time(run.wall_s, case.ident)
        problems = judge_cli(case, run, self.time_limit_s)
        if run.code in (0, 1):
            problems.extend(
                Problem(p.klass, case.ident, p.detail) for p in read_back(case.outputs, folder)
            )
        for name in case.absent:
            if (folder / name).exists():
                problems.append(Problem("code-execution", case.ident, f"{name} was created"))
        self.problems.extend(problems)
        self._cleanup(folder)
        return problems


def _scene_data(folder: Path, path: str) -> Any:
    """A scene file's data as kcheck reads it, or None when it cannot be read."""
    from kcheck.scene.yamlio import load_yaml

    try:
        return load_yaml(folder / path)[0]
    except Exception:
        return None


def _unreal(finding: dict, data: Any) -> str | None:
    """Why an error's field is not a real field of the scene format, or None (errors sit at
    real fields: the field exists in the JSON Schema along the branch the data takes; an
    unknown field is named itself, in a mapping that is real)."""
    from tests.fuzz.schema import in_schema, parse_path

    field = finding.get("field")
    if field is None or data is None:
        return None
    path = parse_path(field)
    if finding["message"].startswith("unknown field") and path[:1] != ("checks",):
        if not in_schema(path[:-1], data):
            return "its mapping is not a field of the scene format"
        return "a known field called unknown" if in_schema(path, data) else None
    return None if in_schema(path, data) else "not a field of the scene format"


def judge_cli(case: Case, run: Run, time_limit_s: float = INPUT_TIME_LIMIT_S) -> list[Problem]:
    """The promise for one command line: its exit code, a message with exit 2, nothing but
    kcheck's messages and argparse's usage on stderr, no traceback, time and memory."""
    p = case.ident
    out = []
    text = run.stdout + run.stderr
    if run.code is None:
        return [Problem("hang", p, f"killed after {run.wall_s:.0f} s")]
    if "Traceback (most recent call last)" in text:
        out.append(Problem("traceback", p, _excerpt(text, "Traceback")))
    if "internal error" in text:
        out.append(Problem("internal-error", p, _excerpt(text, "internal error")))
    if run.code not in case.exit_codes:
        out.append(
            Problem(
                "wrong-exit",
                p,
                f"exit {run.code}, expected {sorted(case.exit_codes)}; "
                f"stderr {run.stderr.strip()[-300:]!r}",
            )
        )
    if run.code == 2 and "kcheck: error:" not in run.stderr:
        out.append(Problem("unlocated", p, f"exit 2 without a message: {run.stderr[-300:]!r}"))
    stray = [
        line
        for line in run.stderr.splitlines()
        if line.strip()
        and not line.startswith(("kcheck: error:", "usage:", " ", "kcheck: interrupted"))
    ]
    if stray and run.code != 2:
        out.append(Problem("stray-output", p, "\n".join(stray)[:600]))
    elif any(re.search(r"Warning\b", line) for line in stray):
        out.append(Problem("stray-output", p, "\n".join(stray)[:600]))
    if run.peak_mb > MEMORY_LIMIT_MB:
        out.append(Problem("memory", p, f"peak {run.peak_mb:.0f} MB"))
    if run.wall_s > time_limit_s:
        out.append(Problem("slow", p, f"{run.wall_s:.1f} s"))
    return out


def _output_args(outputs: dict[str, str]) -> list[str]:
    """``--output-format FORMAT:FILE`` for each report; ``--plots DIR`` for ``plots``."""
    args: list[str] = []
    for rel, fmt in outputs.items():
        args += ["--plots", rel] if fmt == "plots" else ["--output-format", f"{fmt}:{rel}"]
    return args


def read_back(outputs: dict[str, str], folder: Path) -> list[Problem]:
    """Every report file a run wrote (file -> format) must read back in its format."""
    import xml.etree.ElementTree as ET

    out = []
    for rel, fmt in outputs.items():
        if fmt == "plots":
            continue
        path = folder / rel
        try:
            text = path.read_text(encoding="utf-8")
            if fmt in ("json", "sarif"):
                doc = json.loads(text)
                assert "scenes" in doc if fmt == "json" else "runs" in doc
            elif fmt == "junit":
                ET.fromstring(text)
            else:
                assert text.strip()
        except (OSError, ValueError, AssertionError, ET.ParseError) as exc:
            out.append(Problem("broken-report", "", f"{rel} ({fmt}): {exc}"[:300]))
    return out


def stray_stderr_lines(stderr: str, doc: dict) -> list[str]:
    """Lines of stderr that are not kcheck's own: its `kcheck: error:` lines, and the further
    lines of a message that spans lines (each is one of the JSON report's)."""
    said = json.dumps(doc["scenes"], ensure_ascii=False)
    return [
        line
        for line in stderr.splitlines()
        if line.strip()
        and not line.startswith("kcheck: error: ")
        and json.dumps(line, ensure_ascii=False)[1:-1] not in said
    ]


def _exit_code(scenes: list[dict]) -> int:
    states = {s["status"] for s in scenes}
    if "error" in states:
        return 2
    return 1 if "fail" in states else 0


def _parse(stdout: str) -> dict | None:
    try:
        doc = json.loads(stdout)
    except ValueError:
        return None
    return doc if isinstance(doc, dict) and isinstance(doc.get("scenes"), list) else None


def _durations(times: list[float], n: int) -> list[float | None]:
    """Each scene's share of the run from the arrival times of the JSON lines: scene ``i``'s
    line is complete when the next one starts, so line ``i`` (0 = the head) arrives as scene
    ``i + 1`` is written; the first scene (whose time includes start-up) gets None."""
    arrivals = times[: n + 1]
    out: list[float | None] = [None] * n
    for i in range(1, n):
        if i < len(arrivals):
            out[i] = arrivals[i] - arrivals[i - 1]
    return out


def _excerpt(text: str, marker: str) -> str:
    at = text.find(marker)
    return text[max(at - 200, 0) : at + 1200]
