"""``kcheck study``: the worked example against independent statics, bad study files, error
rows, resuming, and the same table from every executor."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from kcheck.gate import study as engine
from kcheck.gate.runner import Settings
from kcheck.plugin import Check, CheckSpec, LoadedCheck, load_checks
from kcheck.result import CheckResult, Status
from kcheck.scene.study import load_study
from tests.conftest import FIXTURES

SCENE = FIXTURES / "maxwell-three-vee" / "coupling.kcheck.yaml"
EXAMPLE = FIXTURES / "three-vee-study.kcheck-study.yaml"


def _mu_lim_statics(beta_deg: float, radius: float = 0.05, ball: float = 0.006) -> float:
    """Limiting friction of the symmetric three-vee coupling (balls on the base, 120° apart,
    grooves radial, flank normals ``beta`` from the vertical) under a vertical closing force
    through its axis, from statics alone: one flank contact retracted, the body's one free
    motion is the null space of the other five contacts; returning along it, each contact's
    friction opposes its sliding, and the case stops closing where the closing force, the
    five normal forces and their friction are in equilibrium with no acceleration, i.e.
    where the 6x6 matrix of those wrenches is singular. The root is found by bisection on
    its determinant, with no use of kcheck. Mass, load magnitude and load height drop out
    (every external force acts along the axis), so the curve is one of geometry and μ."""
    from scipy.optimize import brentq

    b = np.radians(beta_deg)
    z = np.array([0.0, 0.0, 1.0])
    points, normals = [], []
    for phi in np.radians([90.0, 210.0, 330.0]):
        e = np.array([np.cos(phi), np.sin(phi), 0.0])
        t = np.cross(z, e)
        for s in (1.0, -1.0):
            u = s * np.sin(b) * t + np.cos(b) * z  # force of the ball on the plate
            points.append(radius * e + ball * u)
            normals.append(u)
    p, u = np.array(points), np.array(normals)
    rows = np.array([np.concatenate([u[i], np.cross(p[i], u[i])]) for i in range(1, 6)])
    twist = np.linalg.svd(rows)[2][-1]
    v, w = twist[:3], twist[3:]
    if u[0] @ (v + np.cross(w, p[0])) < 0:  # the retracted contact opens along +twist
        v, w = -v, -w

    def det(mu: float) -> float:
        cols = [np.concatenate([-z, np.zeros(3)])]
        for i in range(1, 6):
            slide = v + np.cross(w, p[i])
            f = u[i] + mu * slide / np.linalg.norm(slide)
            cols.append(np.concatenate([f, np.cross(p[i], f)]))
        return float(np.linalg.det(np.array(cols).T))

    mus = np.linspace(1e-6, 2.0, 2001)
    d = np.array([det(m) for m in mus])
    k = int(np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0])
    return float(brentq(det, mus[k], mus[k + 1], xtol=1e-14))


def _write(tmp_path, text: str, name: str = "s.kcheck-study.yaml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text).replace("SCENE", str(SCENE)), encoding="utf-8")
    return path


def test_worked_example_traces_limiting_friction(cli, tmp_path):
    """The bundled study's μ_lim(β) equals the independent statics above, and a variant
    passes (or is marginal: it passes, near its failure line) exactly when its μ is below
    μ_lim(β); marginal variants keep their figures."""
    out = tmp_path / "t.parquet"
    code, stdout, err = cli("study", str(EXAMPLE), "-o", str(out))
    assert code == 0, err
    table = engine.read_table(out)
    assert len(table["variant"]) == 7 * 6
    beta = np.array(table["half_angle"])
    mu = np.array(table["friction"])
    lim = np.array([np.nan if x is None else x for x in table["analytical-3d.limiting_friction"]])
    for b in np.unique(beta):
        expected = _mu_lim_statics(b)
        # every variant has it, failing ones too: μ_lim depends on β alone, not on the
        # variant's own μ (so its rank correlation with μ is 0)
        got = lim[beta == b]
        assert got.size == 6 and np.allclose(got, expected, rtol=1e-7), (b, got, expected)
        # marginal: a pass within analytical-3d's default band of its failure line
        passed = np.isin(np.array(table["status"])[beta == b], ["pass", "marginal"])
        np.testing.assert_array_equal(passed, mu[beta == b] < expected)
    assert "pass: 38/42" in stdout and "6 of them marginal" in stdout
    marginal = np.array(table["status"]) == "marginal"
    assert marginal.any() and np.isfinite(lim[marginal]).all()
    # an empty figure says why: failing variants have no design margin
    why = dict(zip(table["variant"], table["figures_missing"], strict=True))
    for i, status in zip(table["variant"], table["status"], strict=True):
        assert (why[i] is None) == (status != "fail"), (i, status, why[i])
        assert why[i] is None or "design_margin_deg: analytical-3d fails" in why[i]
    # docs/study.md shows this run: its summary lines are what the command prints.
    doc = (FIXTURES.parent / "docs" / "study.md").read_text(encoding="utf-8")
    block = doc.split("$ kcheck study fixtures/three-vee-study.kcheck-study.yaml")[1]
    shown = block.split("```")[0].strip().splitlines()[2:]
    assert shown == stdout.strip().splitlines()[1:]


def test_example_is_not_a_scene():
    """`kcheck check fixtures/` looks for *.kcheck.yaml: the study file is not one."""
    from kcheck.gate.runner import discover

    found, errors = discover([FIXTURES])
    assert not errors
    assert all(not p.name.endswith(".kcheck-study.yaml") for p in found)


@pytest.mark.parametrize(
    ("parameter", "field", "words"),
    [
        ("{path: couplings.v9.groove.half_angle, values: [40]}", "parameters[0].path", "v9"),
        ("{path: friction, range: [0.3, 0.1]}", "parameters[0].range", "greater than"),
        (
            "{path: friction, distribution: {type: normal, mean: 0.1}}",
            "parameters[0].distribution",
            "`sd`",
        ),
        (
            "{path: couplings.*.groove.half_angle, values: [45, 95]}",
            "parameters[0]",
            "the scene is invalid",
        ),
    ],
)
def test_bad_study_is_located_before_any_variant(cli, tmp_path, parameter, field, words):
    study = _write(
        tmp_path,
        f"""\
        version: 1
        scene: SCENE
        design: {{type: monte-carlo, samples: 4, seed: 1}}
        parameters:
          - {parameter}
        """,
    )
    out = tmp_path / "t.parquet"
    code, _, err = cli("study", str(study), "-o", str(out))
    assert code == 2
    assert f"{study}:5" in err and f"field `{field}`" in err and words in err
    assert not out.exists() and not out.with_name(out.name + ".parts").exists()


class _Crashes(Check):
    """Raises for friction above 0.2: a variant that fails must be a row with its error."""

    id = "crashes"
    summary = "test"
    applies_to = "spatial"

    def run(self, inputs):
        if inputs.scene.supports[0].friction > 0.2:
            raise RuntimeError("boom")
        return CheckResult(self.id, Status.PASS, "ok")


def test_failing_variant_is_a_row_with_its_error(tmp_path):
    study = load_study(
        _write(
            tmp_path,
            """\
        version: 1
        scene: SCENE
        parameters: [{path: friction, values: [0.1, 0.3, 0.15]}]
        figures: [crashes.limiting_friction]
        """,
        )
    )
    from importlib.metadata import EntryPoint

    spec = CheckSpec("test", "0", EntryPoint("crashes", "x:y", "kcheck.checks"))
    rows = engine.run_variants(study, [LoadedCheck(spec, _Crashes())], Settings(), 0, 3)
    assert [r["status"] for r in rows] == ["pass", "error", "pass"]
    assert "boom" in rows[1]["error"] and rows[0]["error"] is None


class _Dies(_Crashes):
    """Kills its worker process (as a kill -9 from outside would) for friction above 0.2."""

    def run(self, inputs):
        if inputs.scene.supports[0].friction > 0.2:
            import os

            os._exit(9)
        return CheckResult(self.id, Status.PASS, "ok")


def test_killed_worker_loses_no_written_row(tmp_path):
    """The chunk whose worker was killed is not written (nor made rows of errors): the other
    chunks are, the study reports itself incomplete, and a re-run retries only that chunk."""
    from importlib.metadata import EntryPoint

    study = load_study(
        _write(
            tmp_path,
            """\
        version: 1
        scene: SCENE
        parameters: [{path: friction, values: [0.1, 0.15, 0.3, 0.12, 0.18]}]
        figures: [crashes.limiting_friction]
        chunk: 2
        """,
        )
    )
    spec = CheckSpec("test", "0", EntryPoint("crashes", "x:y", "kcheck.checks"))
    checks = [LoadedCheck(spec, _Dies())]
    out = tmp_path / "t.csv"
    executor = engine.local_executor(study, checks, Settings(), jobs=1)
    assert not engine.run_study(study, ["crashes"], out, executor)
    written = sorted(p.name for p in (tmp_path / "t.csv.parts").glob("chunk-*"))
    assert written == ["chunk-0000000.csv", "chunk-0000002.csv"]  # chunk 1 holds μ = 0.3
    assert not out.exists()


SMALL = """\
    version: 1
    scene: SCENE
    design: {type: latin-hypercube, samples: 10, seed: 7}
    parameters:
      - {name: beta, path: couplings.*.groove.half_angle, range: [35, 55]}
      - {name: mu, path: friction, distribution: {type: truncated-normal, mean: 0.2, sd: 0.05,
         min: 0.1, max: 0.3}}
    checks: [analytical-3d]
    chunk: 3
    """


@pytest.mark.parametrize("suffix", [".parquet", ".csv"])
def test_interrupted_study_resumes_to_the_same_table(cli, tmp_path, suffix):
    study = _write(tmp_path, SMALL)
    whole, part = tmp_path / f"whole{suffix}", tmp_path / f"part{suffix}"
    assert cli("study", str(study), "-o", str(whole))[0] == 0
    code, _, err = cli("study", str(study), "-o", str(part), "--limit-chunks", "2")
    assert code == 2 and "resume" in err and not part.exists()
    assert len(list(part.with_name(part.name + ".parts").glob("chunk-*"))) == 2
    assert cli("study", str(study), "-o", str(part))[0] == 0
    assert engine.read_table(part) == engine.read_table(whole)
    table = engine.read_table(whole)
    assert len(table["variant"]) == 10
    assert all(0.1 <= m <= 0.3 for m in table["mu"])  # truncated normal within its bounds
    assert all(35 <= b <= 55 for b in table["beta"])


def test_parallel_workers_give_the_same_table(cli, tmp_path):
    study = _write(tmp_path, SMALL)
    a, b = tmp_path / "a.parquet", tmp_path / "b.parquet"
    assert cli("study", str(study), "-o", str(a))[0] == 0
    assert cli("study", str(study), "-o", str(b), "-j", "2")[0] == 0
    assert engine.read_table(a) == engine.read_table(b)


def test_dask_local_cluster_gives_the_same_table(tmp_path):
    """As a user runs it: `kcheck study` in a fresh interpreter (a Dask cluster's processes
    and threads stay out of the test process), local workers against a LocalCluster."""
    import importlib.util
    import subprocess
    import sys

    # not importorskip: importing distributed here would change this process's finders
    if importlib.util.find_spec("distributed") is None:
        pytest.skip("kcheck study --dask-local needs the `dask` extra")

    study = _write(tmp_path, SMALL)
    a, b = tmp_path / "a.parquet", tmp_path / "b.parquet"
    for out, extra in ((a, []), (b, ["--dask-local", "2"])):
        done = subprocess.run(
            [sys.executable, "-m", "kcheck", "study", str(study), "-o", str(out), *extra],
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert done.returncode == 0, done.stderr[-3000:]
    first, second = engine.read_table(a), engine.read_table(b)
    assert set(first["status"]) <= {"pass", "marginal", "fail"}, first
    assert first == second


def test_pictures_are_drawn(cli, tmp_path):
    pytest.importorskip("matplotlib")
    study = _write(tmp_path, SMALL)
    page = tmp_path / "study.html"
    code, stdout, _ = cli(
        "study",
        str(study),
        "-o",
        str(tmp_path / "a.csv"),
        "--plots",
        str(tmp_path / "pics"),
        "--html",
        str(page),
    )
    assert code == 0
    html = page.read_text(encoding="utf-8")
    assert stdout.splitlines()[1] in html  # the pass line, as printed
    assert html.count("data:image/png;base64,") == len(list((tmp_path / "pics").iterdir()))
    names = sorted(p.name for p in (tmp_path / "pics").iterdir())
    assert "study-pass-map-beta-mu.png" in names
    assert "study-analytical-3d-design-margin-deg.png" in names
    assert all((tmp_path / "pics" / n).read_bytes()[:4] == b"\x89PNG" for n in names)


@pytest.mark.slow
def test_sigint_loses_no_written_row(tmp_path):
    """A real interruption: SIGINT once two chunks are written; the re-run completes the
    table, identical to an uninterrupted one."""
    import signal
    import subprocess
    import sys
    import time

    # 1000 one-variant chunks: on a loaded machine this process may not be scheduled for
    # seconds, and 200 variants could all be written before the signal is sent.
    study = _write(
        tmp_path, SMALL.replace("samples: 10", "samples: 1000").replace("chunk: 3", "chunk: 1")
    )
    whole, part = tmp_path / "whole.csv", tmp_path / "part.csv"
    cmd = [sys.executable, "-m", "kcheck", "study", str(study), "-o"]
    parts = part.with_name(part.name + ".parts")
    proc = subprocess.Popen([*cmd, str(part)], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while len(list(parts.glob("chunk-*.csv"))) < 2 and proc.poll() is None:
        assert time.monotonic() < deadline
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "interrupted" in err, err
    written = len(list(parts.glob("chunk-*.csv")))
    assert 2 <= written < 1000 and not part.exists()
    assert not list(parts.glob("*.tmp"))
    assert subprocess.run([*cmd, str(part)], capture_output=True).returncode == 0
    assert subprocess.run([*cmd, str(whole)], capture_output=True).returncode == 0
    assert engine.read_table(part) == engine.read_table(whole)


def test_designs_are_reproducible_and_cover_the_cube():
    from kcheck.numerics.design import grid_indices, unit_points

    for design in ("latin-hypercube", "sobol", "monte-carlo"):
        u = unit_points(design, 16, 3, seed=5)
        assert u.shape == (16, 3) and np.all((u >= 0) & (u < 1))
        np.testing.assert_array_equal(u, unit_points(design, 16, 3, seed=5))
    # A Latin hypercube has exactly one point in each of the n strata of every axis.
    u = unit_points("latin-hypercube", 16, 3, seed=5)
    for j in range(3):
        assert sorted((u[:, j] * 16).astype(int).tolist()) == list(range(16))
    assert grid_indices([2, 3]).tolist() == [[0, 0], [0, 1], [0, 2], [1, 0], [1, 1], [1, 2]]


def test_checks_are_known(cli, tmp_path):
    study = _write(tmp_path, SMALL.replace("[analytical-3d]", "[analytical-4d]"))
    code, _, err = cli("study", str(study), "-o", str(tmp_path / "x.csv"))
    assert code == 2 and "analytical-4d" in err and ":8:" in err
    assert load_checks()  # the installed checks were listed


def test_a_folder_runs_each_study(cli, tmp_path, monkeypatch):
    """A folder is searched as scenes are: hidden folders and git-ignored files are passed
    over; each study found gets its own table (`-o` a folder), the same table a run of that
    study alone writes; a table file for several studies is refused before any variant."""
    import shutil
    import subprocess

    if shutil.which("git") is None:
        pytest.skip("needs git for .gitignore")
    root = tmp_path / "studies"
    (root / "sub").mkdir(parents=True)
    (root / ".hidden").mkdir()
    subprocess.run(["git", "init", "-q", str(root)], check=True)
    (root / ".gitignore").write_text("ignored.kcheck-study.yaml\n", encoding="utf-8")
    monkeypatch.chdir(root)
    a = _write(root, SMALL, "a.kcheck-study.yaml")
    b = _write(root / "sub", SMALL.replace("seed: 7", "seed: 8"), "b.kcheck-study.yaml")
    for skipped in (root / ".hidden", root):
        _write(skipped, SMALL.replace("samples: 10", "samples: 3"), "ignored.kcheck-study.yaml")
    code, _, err = cli("study", str(root), "-o", str(tmp_path / "one.csv"))
    assert code == 2 and "2 study files" in err and not (tmp_path / "one.csv").exists()
    out = tmp_path / "tables"
    code, stdout, err = cli("study", str(root), "-o", str(out))
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == ["a.parquet", "b.parquet"]
    assert stdout.count("10 variants") == 2
    for study, name in ((a, "a"), (b, "b")):
        alone = tmp_path / f"{name}-alone.parquet"
        assert cli("study", str(study), "-o", str(alone))[0] == 0
        assert engine.read_table(out / f"{name}.parquet") == engine.read_table(alone)
    assert engine.read_table(out / "a.parquet") != engine.read_table(out / "b.parquet")
    code, _, _ = cli("study", str(root))  # no -o: each table beside its study
    assert code == 0
    assert (root / "a.parquet").is_file() and (root / "sub" / "b.parquet").is_file()


def test_a_folder_without_study_is_an_error(cli, tmp_path):
    code, _, err = cli("study", str(tmp_path))
    assert code == 2 and "no *.kcheck-study.yaml" in err


def test_paths_names_wildcards_and_units(tmp_path):
    """`*` sets every coupling, a name one support item, an index one coordinate; `unit: m`
    is converted to the scene's mm and `rad` to degrees."""
    study = load_study(
        _write(
            tmp_path,
            """\
        version: 1
        scene: SCENE
        parameters:
          - {name: beta, path: couplings.*.groove.half_angle, values: [0.7], unit: rad}
          - {name: x, path: couplings.v2.ball.center.0, values: [-0.04], unit: m}
          - {name: z, path: load.point.2, values: [20]}
        """,
        )
    )
    values = [col[0] for col in study.values()]
    assert values[0] == pytest.approx(np.degrees(0.7)) and values[1] == pytest.approx(-40.0)
    from kcheck.scene.study import variant_document

    doc = variant_document(study, values)
    couplings = doc.data["couplings"]
    assert [c["groove"]["half_angle"] for c in couplings] == [pytest.approx(np.degrees(0.7))] * 3
    assert couplings[1]["ball"]["center"][0] == pytest.approx(-40.0)
    assert couplings[0]["ball"]["center"][0] == 0  # the others unchanged
    assert doc.data["load"]["point"] == [0, 0, 20]
    assert study.scene.data["load"]["point"] == [0, 0, 16]  # the base scene is not changed
