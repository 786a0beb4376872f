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
        help="a study file (*.kcheck-study.yaml), or a folder holding exactly one",
    )
    p.add_argument(
        "-o",
        "--output",
        type=Path,
        help="the table: .parquet (needs kcheck[study]) or .csv "
        "(default: the study file's name with .parquet)",
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


def _studies(folder: Path) -> list[Path]:
    """Study files under a folder, in sorted order, passing over hidden folders."""
    from kcheck.scene.study import STUDY_SUFFIX

    return sorted(
        p
        for p in folder.rglob(f"*{STUDY_SUFFIX}")
        if not any(part.startswith(".") for part in p.relative_to(folder).parts[:-1])
    )


def _output(args: argparse.Namespace) -> Path:
    if args.output is not None:
        return Path(args.output)
    name = args.study.name.removesuffix(".yaml").removesuffix(".kcheck-study")
    return args.study.with_name(name + ".parquet")


def _client(args: argparse.Namespace) -> Any:
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        return None
    if args.scheduler is not None:
        return Client(args.scheduler)
    cluster = LocalCluster(
        n_workers=args.dask_local, threads_per_worker=1, processes=True, dashboard_address=None
    )
    return Client(cluster)


def run(args: argparse.Namespace) -> int:
    """Read and check the study file, run its variants, print the summary."""
    from kcheck.errors import SceneError
    from kcheck.gate import study as engine
    from kcheck.gate.runner import Settings
    from kcheck.plugin import load_checks
    from kcheck.scene.study import load_study

    if args.study.is_dir():
        found = _studies(args.study)
        if len(found) != 1:
            listed = "".join(f"\n  {f}" for f in found)
            return fail(
                f"{args.study}: expected one study file (*.kcheck-study.yaml) in the folder, "
                f"found {len(found)}{'; name one:' if found else ''}{listed}"
            )
        args.study = found[0]
    output = _output(args)
    if output.suffix not in (".parquet", ".csv"):
        return fail(f"--output {output}: expected a .parquet or .csv file")
    if output.suffix == ".parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            return fail(
                "a Parquet table needs pyarrow: pip install 'kcheck[study]' "
                "(or write CSV with -o FILE.csv)"
            )
    try:
        study = load_study(args.study)
    except SceneError as exc:
        for e in exc.all():
            print(f"kcheck: error: {e}", file=sys.stderr)
        return ExitCode.USAGE_OR_INPUT
    checks = load_checks()
    known = {c.spec.name for c in checks}
    lines = study.lines
    for i, c in enumerate(study.checks or ()):
        if c not in known:
            line = lines.get(("checks", i), "")
            return fail(
                f"{args.study}:{line}: field `checks[{i}]`: unknown check `{c}`; "
                f"installed: {', '.join(sorted(known))}"
            )
    for i, f in enumerate(study.figures):
        if f.split(".", 1)[0] not in known:
            line = lines.get(("figures", i), "")
            return fail(
                f"{args.study}:{line}: field `figures[{i}]`: `{f}` names no "
                f"installed check; installed: {', '.join(sorted(known))}"
            )
    selected = None if study.checks is None else frozenset(study.checks)
    settings = Settings(selected=selected, allow_outside=True, memo_mass=True)
    check_ids = [c.spec.name for c in checks if selected is None or c.spec.name in selected]
    client = None
    if args.dask_local is not None or args.scheduler is not None:
        client = _client(args)
        if client is None:
            return fail("Dask executors need distributed: pip install 'kcheck[dask]'")
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

    try:
        complete = engine.run_study(study, check_ids, output, executor, args.limit_chunks, progress)
    finally:
        if client is not None:
            cluster = getattr(client, "cluster", None)
            client.close()
            if cluster is not None:
                cluster.close()
    if sys.stderr.isatty():
        print(file=sys.stderr)
    if not complete:
        print(
            "kcheck: the table is incomplete (stopped, or a worker was killed); "
            f"run again to resume ({n} variants)",
            file=sys.stderr,
        )
        return ExitCode.USAGE_OR_INPUT
    table = engine.read_table(output)
    summary = engine.summarise(study, table)
    text = _summary_text(study, summary, output)
    print(text)
    pictures: list[Path] = []
    title = args.study.name.removesuffix(".kcheck-study.yaml")
    if args.plots is not None:
        try:
            from kcheck.pictures.study import draw_study
        except ImportError as exc:
            return fail(f"pictures need the plot extra: pip install 'kcheck[plot]' ({exc})")
        names = [p.name for p in study.parameters]
        pictures = draw_study(title, table, names, study.figures, args.plots)
        for path in pictures:
            print(f"picture: {path}")
    if args.html is not None:
        from kcheck.cli.common import write_text
        from kcheck.report.study import render_study_page

        page = render_study_page(
            title, text.splitlines(), summary.best, summary.sensitivity, pictures
        )
        write_text(page, args.html, "--html")
    return ExitCode.OK


def _summary_text(study: Any, s: Any, output: Path) -> str:
    out = [f"{s.variants} variants of {study.scene_path} written to {output}"]
    out.append(
        f"pass: {s.passed}/{s.variants} = {s.passed / max(s.variants, 1):.1%} "
        f"(95% interval {s.low:.1%}–{s.high:.1%}); marginal: {s.marginal}; errors: {s.errors}"
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
