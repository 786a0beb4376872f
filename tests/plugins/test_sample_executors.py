"""Issues 27 and 28: `tolerances` and `pose-error` run their samples on the executors of
`kcheck study` (here in turn, local worker processes, a Dask LocalCluster) and give the same
answer, number for number, whichever runs them and however many workers.

References: numpy's own ``SeedSequence.spawn`` for the chunk streams, scipy's whole Sobol
sequence (``random_base2``) for the Sobol chunks, and the serial run for the executors (the
claim under test is identity, so the reference is the same computation in one process).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from kcheck_checks.pose_error import PoseError, PoseErrorOptions
from kcheck_checks.tolerances import Tolerances, TolerancesOptions

from kcheck.body.mass import body_mass_properties
from kcheck.gate.samples import groups, local_samples
from kcheck.mechanics import pose_error as pe
from kcheck.mechanics import tolerance as tm
from kcheck.numerics.streams import chunk_bounds, chunk_generator
from kcheck.plugin import Inputs
from kcheck.plugin.samples import serial
from kcheck.scene import load_scene
from tests.conftest import FIXTURES

THREE_GROOVE = FIXTURES / "three-groove"

POSE = {
    "point": [0, 0, 50],
    "seat_position_um": 2,
    "seat_angle_urad": 50,
    "groups": [{"name": "mill", "couplings": ["g1a", "g1b", "g2a"], "position_um": 5}],
    "seed": 11,
    "allowed_translation_um": 20,
}


def _scene_file(folder: Path, tolerance_samples: int, pose_samples: int, sampler: str) -> Path:
    """The three-groove fixture (six contacts, tolerances, a mesh) asking for both checks."""
    for f in THREE_GROOVE.iterdir():
        shutil.copy(f, folder / f.name)
    path = folder / "coupling.kcheck.yaml"
    pose = json.dumps({**POSE, "samples": pose_samples, "sampler": sampler})
    path.write_text(
        path.read_text(encoding="utf-8")
        + f"  tolerances: {{samples: {tolerance_samples}, seed: 7}}\n"
        + f"  pose-error: {pose}\n",
        encoding="utf-8",
    )
    return path


def test_chunk_streams_are_numpys_spawned_children():
    for seed, index in ((0, 0), (7, 3), (2**40, 12)):
        child = np.random.SeedSequence(seed).spawn(index + 1)[index]
        expected = np.random.default_rng(child).random(5)
        np.testing.assert_array_equal(chunk_generator(seed, index).random(5), expected)
    assert chunk_bounds(10, 4) == [(0, 4), (4, 8), (8, 10)]


def test_groups_keep_every_chunk_in_order():
    chunks = list(range(23))
    for tasks in (1, 2, 5, 8, 23, 40):
        cut = groups(chunks, tasks)
        assert [c for g in cut for c in g] == chunks
        assert len(cut) == min(tasks, 23)
        assert max(map(len, cut)) - min(map(len, cut)) <= 1


def test_sobol_chunks_are_stretches_of_one_sequence():
    """Each chunk fast-forwards to its start: together they are scipy's whole sequence."""
    from scipy.stats import qmc

    whole = qmc.Sobol(5, scramble=True, seed=4).random_base2(17)
    chunks = [pe._sobol_points(4, 5, a, b - a) for a, b in chunk_bounds(2**17, pe.CHUNK)]
    np.testing.assert_array_equal(np.vstack(chunks), whole)


def _run_both(scene_path: Path, sample_map) -> dict:
    scene = load_scene(scene_path)
    mass = body_mass_properties(scene.body, scene.scale)
    out = {}
    for check, options in (
        (Tolerances(), TolerancesOptions(**scene.check_options["tolerances"])),
        (PoseError(), PoseErrorOptions.model_validate(scene.check_options["pose-error"])),
    ):
        result = check.run(Inputs(scene, mass, options, sample_map=sample_map))
        out[check.id] = (result.status, result.message, result.error_estimate, result.details)
    return out


@pytest.mark.parametrize("sampler", ["random", "sobol"])
def test_local_worker_processes_give_every_number_of_the_serial_run(tmp_path, sampler):
    """Several chunks of each check (tolerances 3 chunks and a short one, pose-error 3 and a
    short one) on 1 and 2 forked workers: results identical to the serial run's."""
    path = _scene_file(tmp_path, 3 * tm.CHUNK + 100, 3 * pe.CHUNK + 5000, sampler)
    reference = _run_both(path, serial)
    assert reference["tolerances"][3]["samples"] == 3 * tm.CHUNK + 100
    expected_pose = 3 * pe.CHUNK + 5000 if sampler == "random" else 2**18
    assert reference["pose-error"][3]["samples"] == expected_pose
    # Monte Carlo bounds are still there, and hold the estimate
    t = reference["pose-error"][3]["translation_um"]
    assert t["quantile_bounds"][0] <= t["quantile"] <= t["quantile_bounds"][1]
    assert t["mean_bounds"][0] < t["mean"] < t["mean_bounds"][1]
    low, high = reference["tolerances"][3]["pass_probability_bounds"]
    assert low <= reference["tolerances"][3]["pass_probability"] <= high
    for jobs in (1, 2):
        assert _run_both(path, local_samples(jobs, None, None)) == reference


def test_a_worker_that_dies_is_the_checks_error_not_a_wrong_answer(tmp_path):
    """A sample chunk whose worker is killed: the map raises (the runner reports the check's
    error), it never returns fewer results."""
    import os
    import signal

    from kcheck.gate.samples import SampleWorkerError

    def die(chunk: int) -> int:
        if chunk == 5:
            os.kill(os.getpid(), signal.SIGKILL)
        return chunk

    run = local_samples(2, None, None)
    assert run(abs, list(range(-4, 4))) == [4, 3, 2, 1, 0, 1, 2, 3]
    with pytest.raises(SampleWorkerError, match="died"):
        run(die, list(range(8)))


def _kcheck_json(path: Path, *extra: str) -> list[dict]:
    done = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(path), "--select", "tolerances,pose-error"]
        + ["--format", "json", *extra],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    checks = json.loads(done.stdout)["scenes"][0]["checks"]
    for c in checks:
        c.pop("runtime_s", None)  # the one field allowed to differ
    return checks


@pytest.mark.slow
def test_command_line_serial_local_workers_and_dask_agree(tmp_path):
    """As a user runs it, in fresh interpreters (a Dask cluster's processes and threads stay
    out of the test process): `kcheck check` in turn, with `--sample-jobs 2`, and with
    `--dask-local 2` (a distributed.LocalCluster of 2 workers) gives the same checks, every
    number and word."""
    import importlib.util

    path = _scene_file(tmp_path, 10 * tm.CHUNK, 5 * pe.CHUNK, "random")
    serial_run = _kcheck_json(path)
    assert [c["id"] for c in serial_run] == ["pose-error", "tolerances"]
    assert serial_run[0]["samples"] == 5 * pe.CHUNK and serial_run[1]["samples"] == 10 * tm.CHUNK
    assert _kcheck_json(path, "--sample-jobs", "2") == serial_run
    # not importorskip: importing distributed here would change this process's finders
    if importlib.util.find_spec("distributed") is None:
        pytest.skip("--dask-local needs the `dask` extra")
    assert _kcheck_json(path, "--dask-local", "2") == serial_run


def test_scene_workers_and_sample_workers_are_one_choice(cli, tmp_path):
    path = _scene_file(tmp_path, 200, 200, "random")
    code, _, err = cli("check", str(path), "-j", "2", "--sample-jobs", "2")
    assert code == 2 and "give one" in err
    code, _, err = cli("check", str(path), "--sample-jobs", "0")
    assert code == 2 and "--sample-jobs" in err


def test_the_retired_workers_option_says_what_replaces_it(cli, tmp_path):
    """`tolerances: {workers: N}` was the check's own process pool; a scene that still gives
    it is told where the choice went, at its line, not just "unknown field"."""
    path = _scene_file(tmp_path, 200, 200, "random")
    text = path.read_text(encoding="utf-8").replace("seed: 7}", "seed: 7, workers: 2}")
    path.write_text(text, encoding="utf-8")
    line = next(i for i, t in enumerate(text.splitlines(), 1) if "workers: 2" in t)
    code, out, err = cli("check", str(path), "--select", "tolerances")
    err += out
    assert code == 2 and "Traceback" not in err
    assert f"coupling.kcheck.yaml:{line}:" in err and "checks.tolerances.workers" in err
    assert "--sample-jobs" in err and "--dask-local" in err


class _Future:
    def __init__(self, value=None, error=None):
        self.value, self.error = value, error


class _Client:
    """The three calls of distributed.Client the Dask map uses, run here; a task whose
    chunk is negative fails, as a Dask task would."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self.tasks: list[list[int]] = []

    def scheduler_info(self):
        return {"workers": {f"w{i}": {} for i in range(self.workers)}}

    def map(self, function, functions, tasks, pure):
        assert pure is False and all(f is functions[0] for f in functions)
        self.tasks = [list(t) for t in tasks]
        out = []
        for f, t in zip(functions, tasks, strict=True):
            try:
                out.append(_Future(function(f, t)))
            except ValueError as exc:
                out.append(_Future(error=exc))
        return out

    def gather(self, futures):
        for f in futures:
            if f.error is not None:
                raise f.error
        return [f.value for f in futures]


def _checked(chunk: int) -> int:
    if chunk < 0:
        raise ValueError("a negative chunk")
    return chunk * chunk


def test_dask_map_sends_a_few_tasks_per_worker_and_keeps_chunk_order():
    from kcheck.gate.samples import TASKS_PER_WORKER, SampleWorkerError, dask_samples

    client = _Client(workers=2)
    run = dask_samples(client)
    assert run(_checked, list(range(50))) == [c * c for c in range(50)]
    assert len(client.tasks) == 2 * TASKS_PER_WORKER
    assert [c for t in client.tasks for c in t] == list(range(50))
    client.tasks = []
    assert run(_checked, [3]) == [9] and client.tasks == []  # one chunk stays here
    with pytest.raises(SampleWorkerError, match="a negative chunk"):
        run(_checked, [1, 2, -3, 4])
