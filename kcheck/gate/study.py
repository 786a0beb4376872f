"""Running a study: every variant of a scene checked by the runner's per-scene function, in
chunks, on local worker processes or a Dask cluster, each chunk written as soon as it is done.

A chunk is a part file in ``OUTPUT.parts/`` (written to a temporary name, then renamed, so a
part is whole or absent); a study that stops resumes from the parts already there, and the
parts are joined into the output at the end, streamed one part at a time. The table is the
same whatever ran it: the variants are fixed by the study file (and its seed) and each row
depends on its variant alone.
"""

from __future__ import annotations

import csv
import hashlib
import json
import math
import shutil
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from kcheck.errors import UsageError
from kcheck.gate.runner import Settings, check_scenes
from kcheck.plugin import LoadedCheck
from kcheck.records import dataclass
from kcheck.result import SceneResult, Status
from kcheck.scene.study import Study, variant_document

__all__ = ["Summary", "columns", "run_variants", "run_study", "summarise", "read_table"]

#: Columns every table has before the parameters and figures.
FIXED = ("variant", "status", "error")
#: The column saying why a figure of a row is empty (a check that did not run, a case that
#: closes at no μ), so an empty cell is never silent.
MISSING = "figures_missing"


def columns(study: Study, check_ids: Sequence[str]) -> list[tuple[str, str]]:
    """The table's columns and their kinds (``int``, ``float``, ``str``), in order."""
    cols = [("variant", "int")]
    cols += [(p.name, "float" if p.numeric else "str") for p in study.parameters]
    cols += [("status", "str"), ("error", "str")]
    cols += [(f"{c}.status", "str") for c in check_ids]
    cols += [(f, "float") for f in study.figures]
    cols += [(MISSING, "str")]
    return cols


def _figure(result: SceneResult, name: str) -> tuple[float | None, str | None]:
    """A figure of one check's result and, when it has none, why: ``CHECK.limiting_friction``
    (:func:`_limiting_friction`) or a number among its details (``CHECK.design_margin_deg``)."""
    check_id, key = name.split(".", 1)
    for c in result.checks:
        if c.id != check_id:
            continue
        if c.status not in (Status.PASS, Status.MARGINAL, Status.FAIL):
            return None, f"{check_id} {c.status.value}"
        if key == "limiting_friction":
            return _limiting_friction(c, result)
        value = c.details.get(key)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value), None
        if c.status is Status.FAIL:  # a failing check's details may lack its margins
            return None, f"{check_id} fails: {c.message.split(';')[0]}"
        return None, f"{check_id} reports no `{key}`"
    return None, f"{check_id} did not run" if result.status is not Status.ERROR else None


def _limiting_friction(check: Any, result: SceneResult) -> tuple[float | None, str | None]:
    """The least over the check's retraction cases of each case's limiting friction: the
    upper end of the interval of μ holding the variant's μ in which the case closes or, when
    it does not close at the variant's μ, of the nearest such interval below it (the μ the
    variant's friction must come down to). So a failing variant has a value too, and the
    figure depends on the geometry, not on where the variant's own μ falls (μ_lim(β) of the
    worked example). None, with why, when a case closes for no μ up to the variant's."""
    mu = max((float(s.get("friction") or 0.0) for s in result.supports), default=0.0)
    limits = []
    for k in check.cases:
        if k.limiting_friction is not None:
            limits.append(float(k.limiting_friction))
            continue
        intervals = k.details.get("friction_intervals")
        if intervals is None:
            return None, f"retracting `{k.retracted}` is {k.outcome}: no friction intervals"
        below = [hi for _, hi in intervals if hi is not None and hi < mu]
        if not below:
            return None, f"retracting `{k.retracted}` closes for no μ up to the variant's {mu:g}"
        limits.append(float(max(below)))
    if not limits:
        return None, "no retraction case"
    return min(limits), None


def _row(
    study: Study, index: int, values: list[Any], result: SceneResult, check_ids: Sequence[str]
) -> dict[str, Any]:
    row: dict[str, Any] = {"variant": index}
    row.update({p.name: _plain(v) for p, v in zip(study.parameters, values, strict=True)})
    row["status"] = result.status.value
    row["error"] = result.error if result.status is Status.ERROR else None
    if result.status is Status.ERROR and row["error"] is None:
        errs = [c.message for c in result.checks if c.status is Status.ERROR]
        row["error"] = "; ".join(errs) or None
    ran = [c for c in result.checks if c.status is not Status.SKIPPED]
    if result.status is not Status.ERROR and not ran:
        # No check judged this variant: it is not a pass (why not, in `error`).
        row["status"] = Status.SKIPPED.value
        row["error"] = "; ".join(f"{c.id}: {c.message}" for c in result.checks) or None
    by_id = {c.id: c.status.value for c in result.checks}
    for c in check_ids:
        row[f"{c}.status"] = by_id.get(c)
    missing = []
    for f in study.figures:
        row[f], why = _figure(result, f)
        if row[f] is None and why is not None:
            missing.append(f"{f}: {why}")
    row[MISSING] = "; ".join(missing) or None
    return row


def _plain(v: Any) -> Any:
    return v.item() if isinstance(v, np.generic) else v


def run_variants(
    study: Study,
    checks: Sequence[LoadedCheck],
    settings: Settings,
    start: int,
    stop: int,
    values: list[np.ndarray] | None = None,
    offset: int = 0,
) -> list[dict[str, Any]]:
    """The rows of variants ``start`` to ``stop``: each checked as ``kcheck check`` checks a
    scene, all of them in one :func:`~kcheck.gate.runner.check_scenes` (a variant the scene
    reader or a check refuses is a row with its error).
    ``values``: the parameters' columns from variant ``offset`` on (default: the study's)."""
    from kcheck.scene.load import scene_from_document

    columns_ = study.values() if values is None else values
    check_ids = [
        c.spec.name for c in checks if settings.selected is None or c.spec.name in settings.selected
    ]
    values_ = [[col[i - offset] for col in columns_] for i in range(start, stop)]

    def loader(v: list[Any]) -> Callable[[], Any]:
        doc = variant_document(study, v)
        return lambda: scene_from_document(study.scene_path, doc, allow_outside=True)

    # The chunk's variants together: each check gets all of them at once (Check.run_many:
    # analytical-3d stacks their algebra), each row as the variant alone would give it.
    results = check_scenes(study.scene_path, checks, settings, [loader(v) for v in values_])
    return [
        _row(study, i, v, result, check_ids)
        for i, v, result in zip(range(start, stop), values_, results, strict=True)
    ]


# --- the parts of a table ---------------------------------------------------------------


def fingerprint(study: Study, check_ids: Sequence[str]) -> str:
    """What a table's rows depend on: the study and scene files' bytes, the checks run, the
    chunk size and kcheck's version."""
    from kcheck import __version__

    h = hashlib.sha256()
    for path in (study.path, study.scene_path):
        h.update(path.read_bytes())
    h.update(json.dumps([list(check_ids), study.chunk, __version__]).encode())
    return h.hexdigest()[:16]


def _write_part(rows: list[dict[str, Any]], cols: list[tuple[str, str]], path: Path) -> None:
    tmp = path.with_name(path.name + ".tmp")
    if path.suffix == ".csv":
        with tmp.open("w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            for r in rows:
                w.writerow(["" if r[c] is None else r[c] for c, _ in cols])
    else:
        import pyarrow.parquet as pq

        pq.write_table(_arrow_table(rows, cols), tmp)
    tmp.replace(path)


def _arrow_schema(cols: list[tuple[str, str]]) -> Any:
    import pyarrow as pa

    kinds = {"int": pa.int64(), "float": pa.float64(), "str": pa.string()}
    return pa.schema([(c, kinds[k]) for c, k in cols])


def _arrow_table(rows: list[dict[str, Any]], cols: list[tuple[str, str]]) -> Any:
    import pyarrow as pa

    schema = _arrow_schema(cols)
    return pa.table({c: [r[c] for r in rows] for c, _ in cols}, schema=schema)


def _join(parts: list[Path], cols: list[tuple[str, str]], output: Path) -> None:
    """The parts, in order, as one table, streamed part by part."""
    tmp = output.with_name(output.name + ".tmp")
    if output.suffix == ".csv":
        with tmp.open("w", newline="", encoding="utf-8") as out:
            csv.writer(out).writerow([c for c, _ in cols])
            for part in parts:
                with part.open(encoding="utf-8") as f:
                    shutil.copyfileobj(f, out)
    else:
        import pyarrow.parquet as pq

        with pq.ParquetWriter(tmp, _arrow_schema(cols)) as writer:
            for part in parts:
                writer.write_table(pq.read_table(part))
    tmp.replace(output)


def read_table(path: Path) -> dict[str, list[Any]]:
    """A written table as columns of plain values (in a CSV table an empty cell is None,
    numbers are read back as numbers)."""
    if path.suffix == ".csv":
        with path.open(newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            header = next(reader)
            cells = list(reader)
        return {h: [_cell(r[i]) for r in cells] for i, h in enumerate(header)}
    import pyarrow.parquet as pq

    return {k: list(v) for k, v in pq.read_table(path).to_pydict().items()}


def _cell(text: str) -> Any:
    if text == "":
        return None
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


# --- executors ------------------------------------------------------------------------------


Chunk = tuple[int, int]
#: Runs chunks, yielding each one's rows in chunk order (None: the chunk's worker died; the
#: chunk is left unwritten, to be run again when the study resumes).
Executor = Callable[[list[Chunk]], Iterator[list[dict[str, Any]] | None]]


def local_executor(
    study: Study, checks: Sequence[LoadedCheck], settings: Settings, jobs: int
) -> Executor:
    """Chunks in this process (``jobs`` 0) or in ``jobs`` forked worker processes
    (:mod:`kcheck.gate.pool`): a chunk whose worker crashed or ran out of a budget is rows
    with that error; one whose worker was killed is left unwritten, for the resume."""
    from kcheck.gate import pool

    values = study.values()

    def work(chunk: Chunk) -> list[dict[str, Any]]:
        return run_variants(study, checks, settings, *chunk, values=values)

    def run(chunks: list[Chunk]) -> Iterator[list[dict[str, Any]] | None]:
        if jobs < 1 or not pool.available():
            yield from map(work, chunks)
            return
        budget = pool.Budget(settings.timeout_s, settings.memory_bytes)
        for chunk, out in zip(
            chunks, pool.run_in_workers(chunks, work, jobs=jobs, budget=budget), strict=True
        ):
            if isinstance(out, pool.BudgetExceeded) and out.kind == "died":
                yield None  # killed from outside, not the variants' doing: retried on resume
            elif isinstance(out, pool.BudgetExceeded):
                yield _failed_chunk(
                    study,
                    checks,
                    settings,
                    chunk,
                    values,
                    f"the worker stopped ({out.kind}: {out.detail})",
                )
            else:
                yield out

    return run


def _failed_chunk(
    study: Study,
    checks: Sequence[LoadedCheck],
    settings: Settings,
    chunk: Chunk,
    values: list[np.ndarray],
    why: str,
) -> list[dict[str, Any]]:
    check_ids = [
        c.spec.name for c in checks if settings.selected is None or c.spec.name in settings.selected
    ]
    rows = []
    for i in range(*chunk):
        v = [col[i] for col in values]
        result = SceneResult(path=str(study.scene_path), status=Status.ERROR, error=why)
        rows.append(_row(study, i, v, result, check_ids))
    return rows


_WORKER_CHECKS: dict[tuple[str, ...], list[LoadedCheck]] = {}


def _dask_chunk(
    study: Study,
    selected: tuple[str, ...] | None,
    start: int,
    stop: int,
    values: list[np.ndarray],
) -> list[dict[str, Any]]:
    """One chunk on a Dask worker: the checks are loaded there, once per worker."""
    from kcheck.plugin import load_checks

    key = selected or ()
    if key not in _WORKER_CHECKS:
        _WORKER_CHECKS[key] = load_checks()
    settings = Settings(
        selected=None if selected is None else frozenset(selected), memo_mass=True, hints=False
    )
    return run_variants(study, _WORKER_CHECKS[key], settings, start, stop, values, start)


def dask_executor(study: Study, settings: Settings, client: Any, window: int) -> Executor:
    """Chunks on a Dask cluster (``client``: a ``distributed.Client``), at most ``window``
    in flight, results in chunk order."""
    selected = None if settings.selected is None else tuple(sorted(settings.selected))

    values = study.values()

    def submit(chunk: Chunk, study_future: Any) -> Any:
        start, stop = chunk
        mine = [col[start:stop] for col in values]  # each task carries its own values
        return client.submit(_dask_chunk, study_future, selected, start, stop, mine, pure=False)

    def run(chunks: list[Chunk]) -> Iterator[list[dict[str, Any]] | None]:
        from collections import deque

        study_future = client.scatter(study, broadcast=True)
        queue: deque[Any] = deque()
        todo = iter(chunks)
        for chunk in todo:
            queue.append(submit(chunk, study_future))
            if len(queue) >= window:
                break
        while queue:
            yield queue.popleft().result()
            nxt = next(todo, None)
            if nxt is not None:
                queue.append(submit(nxt, study_future))

    return run


# --- the study ----------------------------------------------------------------------------


def variant_count(study: Study) -> int:
    return len(study.values()[0])


def run_study(
    study: Study,
    check_ids: Sequence[str],
    output: Path,
    executor: Executor,
    limit: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> bool:
    """Run the variants whose chunks are not written yet, writing each chunk's part; join
    the parts into ``output`` once every chunk is there. ``limit``: stop after that many
    chunks (as an interruption would). True when the table is complete."""
    n = variant_count(study)
    cols = columns(study, check_ids)
    parts_dir = output.with_name(output.name + ".parts")
    stamp = parts_dir / "study.json"
    key = fingerprint(study, check_ids)
    if parts_dir.exists():
        try:
            old = json.loads(stamp.read_text(encoding="utf-8")).get("fingerprint")
        except (OSError, ValueError):
            old = None
        if old != key:
            raise UsageError(
                f"{parts_dir} holds rows of another study (or of an earlier version of this "
                "one); delete it to start afresh"
            )
    else:
        parts_dir.mkdir(parents=True)
        stamp.write_text(json.dumps({"fingerprint": key, "variants": n}), encoding="utf-8")
    suffix = ".csv" if output.suffix == ".csv" else ".parquet"
    chunks = [(s, min(s + study.chunk, n)) for s in range(0, n, study.chunk)]
    part = [parts_dir / f"chunk-{i:07d}{suffix}" for i in range(len(chunks))]
    todo = [i for i in range(len(chunks)) if not part[i].exists()]
    if limit is not None:
        todo = todo[:limit]
    done = n - sum(chunks[i][1] - chunks[i][0] for i in range(len(chunks)) if not part[i].exists())
    for i, rows in zip(todo, executor([chunks[i] for i in todo]), strict=False):
        if rows is None:
            continue
        _write_part(rows, cols, part[i])
        done += len(rows)
        if progress is not None:
            progress(done, n)
    if not all(p.exists() for p in part):
        return False
    _join(part, cols, output)
    shutil.rmtree(parts_dir)
    return True


_PASSING = frozenset((Status.PASS.value, Status.MARGINAL.value))


@dataclass(frozen=True)
class Summary:
    """What a table says: pass fraction with its 95 % interval, the best variant, and the
    parameters ranked by how strongly they move each figure."""

    variants: int
    passed: int
    errors: int
    #: Variants past their failure line but short of a minimum margin (not in ``passed``).
    marginal: int
    low: float
    high: float
    best: dict[str, Any] | None
    best_by: str | None
    sensitivity: dict[str, list[tuple[str, float]]]


def summarise(study: Study, table: dict[str, list[Any]]) -> Summary:
    """Pass fraction (Clopper–Pearson 95 %), the variant with the largest first figure
    among passing ones, and per figure the parameters by |Spearman rank correlation|."""
    from kcheck.numerics.stats import clopper_pearson

    status = [str(s) for s in table["status"]]
    n = len(status)
    # A marginal variant passes (closer to its failure line than the check's band), as
    # `kcheck check` passes a marginal scene without --strict.
    passed = sum(s in _PASSING for s in status)
    errors = sum(s == "error" for s in status)
    marginal = sum(s == "marginal" for s in status)
    low, high = clopper_pearson(passed, n, 0.95) if n else (math.nan, math.nan)
    best = best_by = None
    figures = [f for f in study.figures if f in table]

    def num(x: Any) -> float:
        try:
            return float(x)
        except (TypeError, ValueError):
            return math.nan

    for f in figures:
        vals = np.array([num(x) for x in table[f]])
        ok = np.isfinite(vals) & np.array([s in _PASSING for s in status])
        if ok.any():
            i = int(np.flatnonzero(ok)[np.argmax(vals[ok])])
            best = {k: v[i] for k, v in table.items()}
            best_by = f
            break
    sens: dict[str, list[tuple[str, float]]] = {}
    for f in figures:
        y = np.array([num(x) for x in table[f]])
        ranking = []
        for p in study.parameters:
            if not p.numeric:
                continue
            x = np.array([num(v) for v in table[p.name]])
            ok = np.isfinite(x) & np.isfinite(y)
            if ok.sum() < 3 or np.ptp(x[ok]) == 0 or np.ptp(y[ok]) == 0:
                continue
            from scipy.stats import spearmanr

            ranking.append((p.name, float(spearmanr(x[ok], y[ok])[0])))
        ranking.sort(key=lambda t: -abs(t[1]))
        sens[f] = ranking
    return Summary(n, passed, errors, marginal, low, high, best, best_by, sens)
