"""``kcheck study``: every variant of a scene over a design of experiments, checked as
``kcheck check`` checks a scene, into a Parquet (or CSV) table and a summary (docs/study.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from kcheck.cli.common import ExitCode, fail

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``study`` command."""
    p = sub.add_parser(
        "study",
        help="check every variant of a scene over a design of experiments (a study file)",
        description="Vary fields of a scene (grid, Latin hypercube, Sobol or Monte Carlo), "
        "check every variant as `kcheck check` does, write one row per variant to a Parquet "
        "or CSV table and print a summary. An interrupted study resumes from its written rows.",
    )
    p.add_argument(
        "study",
        type=Path,
        help="a study file (*.kcheck-study.yaml), or a folder: every study file in it "
        "(found as scenes are, honouring exclude and .gitignore), each run in turn",
    )
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        help="the table: .parquet (needs kcheck[study]) or .csv, or a folder for "
        "<study>.parquet (a folder of several studies: a folder) "
        "(default: the study file's name with .parquet, beside it)",
    )
    where = p.add_mutually_exclusive_group()
    where.add_argument("-j", "--jobs", type=int, default=0, help="local worker processes")
    where.add_argument(
        "--dask-local", type=int, metavar="N", help="start a Dask LocalCluster of N workers"
    )
    where.add_argument(
        "--scheduler", metavar="ADDRESS", help="an existing Dask scheduler (tcp://HOST:8786)"
    )
    p.add_argument(
        "--plots",
        type=Path,
        metavar="DIR",
        help="write pictures there: each figure against each parameter, and the pass map of "
        "the first two parameters (needs kcheck[plot])",
    )
    p.add_argument(
        "--html",
        type=Path,
        metavar="FILE",
        help="write the summary, best variant, sensitivity and pictures as an HTML page",
    )
    p.add_argument("--limit-chunks", type=int, help=argparse.SUPPRESS)  # tests: stop early
    p.set_defaults(handler=run)


def _studies(folder: Path) -> tuple[list[Path], list[str]]:
    """Study files under a folder, found as ``kcheck check`` finds scenes: sorted, passing
    over the configuration's ``exclude``/``extend-exclude`` and what git ignores."""
    from kcheck.gate.config import load_config
    from kcheck.gate.paths import Excluder, discover_studies

    config = load_config()
    patterns = (*config["exclude"], *config["extend_exclude"])
    exclude = Excluder(patterns, config.root, gitignore=config["respect_gitignore"])
    found, errors = discover_studies(folder, exclude)
    return found, [str(e) for e in errors]


def _name(study: Path) -> str:
    return study.name.removesuffix(".yaml").removesuffix(".kcheck-study")


def _plan(args: argparse.Namespace) -> list[tuple[Path, Path, Path | None, Path | None]]:
    """Each study with its table, HTML page and pictures folder. One study: ``-o`` is the
    table (or a folder to hold it), ``--html`` the page, ``--plots`` the folder. Several (a
    folder holding several study files): ``-o``, ``--html`` and ``--plots`` are folders,
    each study's files named after it; without ``-o`` each table sits beside its study."""
    from kcheck.errors import UsageError

    studies = [args.study]
    if args.study.is_dir():
        studies, errors = _studies(args.study)
        if errors:
            raise UsageError("; ".join(errors))
        if not studies:
            raise UsageError(f"{args.study}: no *.kcheck-study.yaml files found in this folder")
    several = len(studies) > 1
    out = args.output
    if several:
        if out is not None and out.suffix in (".parquet", ".csv"):
            raise UsageError(
                f"--output {out}: {args.study} holds {len(studies)} study files; give a "
                "folder for their tables (one <study>.parquet each)"
            )
        if args.html is not None and args.html.suffix == ".html":
            raise UsageError(
                f"--html {args.html}: {args.study} holds {len(studies)} study files; give a "
                "folder for their pages (one <study>.html each)"
            )
        names = [_name(s) for s in studies]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice and (out is not None or args.html is not None or args.plots is not None):
            raise UsageError(
                f"{args.study}: several study files are named {', '.join(twice)}; their "
                "outputs would collide in one folder (run them one by one)"
            )
    plans = []
    for study in studies:
        name = _name(study)
        if out is None:
            table = study.with_name(name + ".parquet")
        elif several or out.is_dir():
            table = out / (name + ".parquet")
        else:
            table = out
        html = args.html
        if html is not None and several:
            html = html / (name + ".html")
        plots = None if args.plots is None else (args.plots / name if several else args.plots)
        plans.append((study, table, html, plots))
    return plans


def _client(args: argparse.Namespace) -> Any:
    from kcheck.cli.executors import dask_client

    return dask_client(args.dask_local, args.scheduler)


def _load(path: Path, output: Path, known: set[str]) -> Any:
    """The study file read and checked (its table's type, its checks and figures), or the
    list of its error messages."""
    from kcheck.errors import SceneError
    from kcheck.scene.study import load_study

    if output.suffix not in (".parquet", ".csv"):
        return [f"--output {output}: expected a .parquet or .csv file"]
    if output.suffix == ".parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            return [
                "a Parquet table needs pyarrow: pip install 'kcheck[study]' "
                "(or write CSV with -o FILE.csv)"
            ]
    try:
        study = load_study(path)
    except SceneError as exc:
        return [str(e) for e in exc.all()]
    lines = study.lines
    for i, c in enumerate(study.checks or ()):
        if c not in known:
            line = lines.get(("checks", i), "")
            return [
                f"{path}:{line}: field `checks[{i}]`: unknown check `{c}`; "
                f"installed: {', '.join(sorted(known))}"
            ]
    for i, f in enumerate(study.figures):
        if f.split(".", 1)[0] not in known:
            line = lines.get(("figures", i), "")
            return [
                f"{path}:{line}: field `figures[{i}]`: `{f}` names no "
                f"installed check; installed: {', '.join(sorted(known))}"
            ]
    return study


def run(args: argparse.Namespace) -> int:
    """Find and check every study file before any variant runs, then run each in turn and
    print its summary."""
    from kcheck.errors import UsageError
    from kcheck.plugin import load_checks

    try:
        plans = _plan(args)
    except UsageError as exc:
        return fail(str(exc))
    checks = load_checks()
    known = {c.spec.name for c in checks}
    loaded = []
    bad = False
    for path, output, html, plots in plans:
        study = _load(path, output, known)
        if isinstance(study, list):
            for message in study:
                print(f"kcheck: error: {message}", file=sys.stderr)
            bad = True
        loaded.append((path, study, output, html, plots))
    if bad:
        return ExitCode.USAGE_OR_INPUT
    worst: int = ExitCode.OK
    for k, (path, study, output, html, plots) in enumerate(loaded):
        if k:
            print()
        code = _run_one(args, path, study, checks, output, html, plots)
        worst = max(worst, code)
    return worst


def _run_one(
    args: argparse.Namespace,
    path: Path,
    study: Any,
    checks: Any,
    output: Path,
    html: Path | None,
    plots: Path | None,
) -> int:
    """Run one study's variants, print its summary, draw its pictures and page."""
    from kcheck.gate import study as engine
    from kcheck.gate.runner import Settings

    selected = None if study.checks is None else frozenset(study.checks)
    # hints=False: a study's table holds verdicts and figures, never a finding's hint, and
    # the way-out searches cost a failing spatial variant several times its check.
    settings = Settings(selected=selected, allow_outside=True, memo_mass=True, hints=False)
    check_ids = [c.spec.name for c in checks if selected is None or c.spec.name in selected]
    client = None
    if args.dask_local is not None or args.scheduler is not None:
        client = _client(args)
        if client is None:
            from kcheck.cli.executors import DASK_MISSING

            return fail(DASK_MISSING)
        executor = engine.dask_executor(
            study,
            settings,
            client,
            window=4 * max(1, len(client.scheduler_info().get("workers", {}))),
        )
    else:
        executor = engine.local_executor(study, checks, settings, args.jobs)
    n = engine.variant_count(study)

    def progress(done: int, total: int) -> None:
        if sys.stderr.isatty():
            print(f"\r{done}/{total} variants", end="", file=sys.stderr, flush=True)

    output.parent.mkdir(parents=True, exist_ok=True)
    try:
        complete = engine.run_study(study, check_ids, output, executor, args.limit_chunks, progress)
    finally:
        if client is not None:
            from kcheck.cli.executors import close_client

            close_client(client)
    if sys.stderr.isatty():
        print(file=sys.stderr)
    if not complete:
        print(
            f"kcheck: {path}: the table is incomplete (stopped, or a worker was killed); "
            f"run again to resume ({n} variants)",
            file=sys.stderr,
        )
        return ExitCode.USAGE_OR_INPUT
    table = engine.read_table(output)
    summary = engine.summarise(study, table)
    text = _summary_text(study, summary, output)
    print(text)
    pictures: list[Path] = []
    title = path.name.removesuffix(".kcheck-study.yaml")
    if plots is not None:
        try:
            from kcheck.pictures.study import draw_study
        except ImportError as exc:
            return fail(f"pictures need the plot extra: pip install 'kcheck[plot]' ({exc})")
        names = [p.name for p in study.parameters]
        pictures = draw_study(title, table, names, study.figures, plots)
        for picture in pictures:
            print(f"picture: {picture}")
    if html is not None:
        from kcheck.cli.common import write_text
        from kcheck.report.study import render_study_page

        page = render_study_page(
            title, text.splitlines(), summary.best, summary.sensitivity, pictures
        )
        html.parent.mkdir(parents=True, exist_ok=True)
        write_text(page, html, "--html")
    return ExitCode.OK


def _summary_text(study: Any, s: Any, output: Path) -> str:
    out = [f"{s.variants} variants of {study.scene_path} written to {output}"]
    out.append(
        f"pass: {s.passed}/{s.variants} = {s.passed / max(s.variants, 1):.1%} "
        f"(95% interval {s.low:.1%}–{s.high:.1%}; {s.marginal} of them marginal); "
        f"errors: {s.errors}"
    )
    if s.best is not None:
        values = ", ".join(
            f"{p.name} = {s.best[p.name]:.6g}" if p.numeric else f"{p.name} = {s.best[p.name]}"
            for p in study.parameters
        )
        out.append(
            f"best by {s.best_by}: variant {s.best['variant']} ({values}): {s.best[s.best_by]:.4g}"
        )
    for figure, ranking in s.sensitivity.items():
        if ranking:
            ranked = ", ".join(f"{name} ({rho:+.2f})" for name, rho in ranking)
            out.append(f"sensitivity of {figure} (Spearman ρ): {ranked}")
    return "\n".join(out)
