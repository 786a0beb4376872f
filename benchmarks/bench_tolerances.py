"""Benchmark of the `tolerances` check and of friction ranges.

Run: ``python benchmarks/bench_tolerances.py`` (medians of repeated warm runs). Prints the
tables recorded in docs/performance.md, with the machine's load average (the numbers are
only comparable on a quiet machine).

* the Monte Carlo core (:func:`kcheck.mechanics.tolerance.sample_margins`) on the three-groove
fixture
  and the planar block, 10^3 to 10^5 samples, and the whole check at 10^4;
* the analytical checks with ``friction: {min, max}`` against one coefficient;
* ``python benchmarks/bench_tolerances.py executors``: the two Monte Carlo checks,
  `tolerances` (40,000 samples) and `pose-error` (10^6 samples), on the three-groove fixture,
  on each sample executor of ``kcheck check`` — in this process, 1 and 2 local worker
  processes (``--sample-jobs``), a Dask LocalCluster of 1 and 2 workers (``--dask-local``) —
  interleaved round by round, so every executor sees the same load; wall time medians, and
  each executor's throughput over that of 1 local worker in the same rounds. The clusters are
  started once, before the rounds (their start-up is printed apart).
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np
from kcheck_checks.analytical_2d import Analytical2D
from kcheck_checks.analytical_3d import Analytical3D
from kcheck_checks.tolerances import Tolerances, TolerancesOptions

from kcheck.analysis.cases import problem_for
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.tolerance import perturb, sample_margins
from kcheck.plugin import Inputs
from kcheck.scene import Scene, load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = {
    "three-groove": ROOT / "fixtures" / "three-groove" / "coupling.kcheck.yaml",
    "planar-block": ROOT / "fixtures" / "planar-block" / "block.kcheck.yaml",
}


def median_s(fn: Callable[[], object], repeat: int = 5) -> float:
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def with_friction(scene: Scene, text: str, tmp: Path) -> Scene:
    source = scene.path.read_text()
    line = next(ln for ln in source.splitlines() if ln.startswith("friction:"))
    path = tmp / scene.path.name
    path.write_text(source.replace(line, f"friction: {text}"))
    for mesh in scene.path.parent.glob("*.stl"):
        (tmp / mesh.name).write_bytes(mesh.read_bytes())
    return load_scene(path)


def monte_carlo() -> None:
    print("| scene | samples | sample_margins | per sample | whole check |")
    print("|---|---|---|---|---|")
    for name, path in SCENES.items():
        scene = load_scene(path)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        problem = problem_for(scene, mass)
        design = scene.load.direction[: scene.dim]
        for count in (1_000, 10_000, 100_000):
            layouts = perturb(
                problem,
                position=0.05e-3,
                normal=np.radians(0.5),
                friction_low=problem.friction * 0.5,
                friction_high=problem.friction,
                count=count,
                rng=np.random.default_rng(0),
            )
            seconds = median_s(partial(sample_margins, problem, layouts, design), 3)
            whole = "–"
            if count == 10_000 and scene.tolerances is not None:
                inputs = Inputs(scene, mass, TolerancesOptions(samples=count))
                whole = f"{1e3 * median_s(partial(Tolerances().run, inputs), 3):.0f} ms"
            print(
                f"| {name} | {count:,} | {1e3 * seconds:.0f} ms | {1e6 * seconds / count:.1f} µs "
                f"| {whole} |"
            )


def ranges() -> None:
    import tempfile

    print("| scene | check | one coefficient | range {min, max} |")
    print("|---|---|---|---|")
    for name, path, check, text in (
        ("planar-block", SCENES["planar-block"], Analytical2D(), "{min: 0.05, max: 0.3}"),
        ("three-groove", SCENES["three-groove"], Analytical3D(), "{min: 0.05, max: 0.15}"),
    ):
        scene = load_scene(path)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        with tempfile.TemporaryDirectory() as tmp:
            ranged = with_friction(scene, text, Path(tmp))
            one = median_s(partial(check.run, Inputs(scene, mass, check.options())))
            many = median_s(partial(check.run, Inputs(ranged, mass, check.options())))
        print(f"| {name} | {check.id} | {1e3 * one:.1f} ms | {1e3 * many:.1f} ms |")


POSE = {
    "point": [0, 0, 50],
    "seat_position_um": 2,
    "seat_angle_urad": 50,
    "groups": [{"name": "mill", "couplings": ["g1a", "g1b", "g2a"], "position_um": 5}],
    "samples": 1_000_000,
}


def executors(rounds: int = 3) -> None:
    """Paired: each check on each sample executor, interleaved, ``rounds`` times."""
    import sys

    from kcheck_checks.pose_error import PoseError, PoseErrorOptions

    from kcheck.gate.samples import dask_samples, local_samples
    from kcheck.plugin.samples import serial

    scene = load_scene(SCENES["three-groove"])
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    runs = {
        "tolerances, 40,000 samples": (
            Tolerances(),
            TolerancesOptions(samples=40_000),
            40_000,
        ),
        "pose-error, 10^6 samples": (
            PoseError(),
            PoseErrorOptions.model_validate(POSE),
            1_000_000,
        ),
    }
    maps = {"in process": serial, "1 local worker": local_samples(1, None, None)}
    maps["2 local workers"] = local_samples(2, None, None)
    clients = []
    try:
        from distributed import Client, LocalCluster

        for n in (1, 2):
            start = time.perf_counter()
            cluster = LocalCluster(
                n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None
            )
            client = Client(cluster)
            client.run(lambda: __import__("kcheck_checks.tolerances"))  # warm the workers
            print(f"Dask LocalCluster of {n}: started in {time.perf_counter() - start:.1f} s")
            clients.append((client, cluster))
            maps[f"Dask, {n} worker{'s' if n > 1 else ''}"] = dask_samples(client)
    except ImportError:
        print("distributed is not installed: no Dask rows", file=sys.stderr)
    times: dict[tuple[str, str], list[float]] = {(r, m): [] for r in runs for m in maps}
    cpus: dict[tuple[str, str], list[float]] = {(r, m): [] for r in runs for m in maps}
    own: dict[tuple[str, str], list[float]] = {(r, m): [] for r in runs for m in maps}
    answers: dict[str, set[str]] = {r: set() for r in runs}
    dask_client = {
        f"Dask, {n} worker{'s' if n > 1 else ''}": c for n, (c, _) in enumerate(clients, 1)
    }

    def parent() -> float:
        import resource

        here = resource.getrusage(resource.RUSAGE_SELF)
        return here.ru_utime + here.ru_stime

    def cpu(map_name: str) -> float:
        """CPU seconds of this process, its waited-for children (the local workers) and,
        for Dask, the cluster's worker processes."""
        import resource

        here = resource.getrusage(resource.RUSAGE_SELF)
        kids = resource.getrusage(resource.RUSAGE_CHILDREN)
        total = here.ru_utime + here.ru_stime + kids.ru_utime + kids.ru_stime
        if map_name in dask_client:
            total += sum(dask_client[map_name].run(time.process_time).values())
        return total

    for _ in range(rounds):
        for run_name, (check, opts, _) in runs.items():
            for map_name, sample_map in maps.items():
                inputs = Inputs(scene, mass, opts, sample_map=sample_map)
                before, mine = cpu(map_name), parent()
                start = time.perf_counter()
                result = check.run(inputs)
                times[(run_name, map_name)].append(time.perf_counter() - start)
                own[(run_name, map_name)].append(parent() - mine)
                cpus[(run_name, map_name)].append(cpu(map_name) - before)
                answers[run_name].add(repr(result.details))
    for client, cluster in clients:
        client.close()
        cluster.close()
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print(
        "| check | executor | wall (median) | samples/s | over 1 local worker | CPU (median) "
        "| of it this process | cores busy |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for run_name, (_, _, count) in runs.items():
        base = statistics.median(times[(run_name, "1 local worker")])
        for map_name in maps:
            wall = statistics.median(times[(run_name, map_name)])
            used = statistics.median(cpus[(run_name, map_name)])
            mine = statistics.median(own[(run_name, map_name)])
            print(
                f"| {run_name} | {map_name} | {wall:.2f} s | {count / wall:,.0f} | "
                f"{base / wall:.2f}x | {used:.2f} s | {mine:.2f} s | {used / wall:.2f} |"
            )
        same = "identical" if len(answers[run_name]) == 1 else "DIFFERENT"
        print(f"| {run_name} | every executor's details | {same} | | |")


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["executors"] and os.environ.get("OPENBLAS_NUM_THREADS") != "1":
        # One BLAS thread, as `kcheck` runs (kcheck.cli.pin_blas_threads) and as Dask starts
        # its workers: a second BLAS thread waiting for a core on a loaded machine slows every
        # tiny matrix call. Effective only before numpy loads: start again with it.
        from kcheck.cli import BLAS_THREAD_VARIABLES

        env = {**os.environ, **dict.fromkeys(BLAS_THREAD_VARIABLES, "1")}
        os.execve(sys.executable, [sys.executable, *sys.argv], env)
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores\n")
    if sys.argv[1:] == ["executors"]:
        executors()
    else:
        monte_carlo()
        print()
        ranges()
