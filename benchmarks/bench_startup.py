"""Start-up (issue 24): ``kcheck check`` of a planar scene without a mesh against
``python -c "import numpy"``, in the same run, interleaved, medians; plus what pydantic and
the scene models cost on top of numpy (off a valid scene's path since issue 24: the cost the
pydantic-free acceptor and options save).

Run: ``python benchmarks/bench_startup.py [--python PATH ...] [--repeat 15]``. ``--python`` is
the interpreter of an install to measure (a non-editable ``pip install .`` into another venv,
say; give it twice, a baseline's and the new one's, to pair them too); by default this one.
Every case is a fresh process with bytecode caches (see bench_gate.py), started from a folder
without a ``pyproject.toml``. Wall and CPU (user + sys, ``os.wait4``). The ratios are against
``python -c "import numpy"`` as it runs by default (its BLAS starting a thread per core);
``import numpy, one BLAS thread`` is numpy as kcheck imports it, for the stricter reading.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import tempfile
from pathlib import Path

from bench_gate import ENV, explicit_scene, run

ONE_THREAD_NUMPY = "import os; os.environ['OPENBLAS_NUM_THREADS'] = '1'; import numpy"


def cases(pythons: list[str], scene: Path) -> dict[str, list[str]]:
    first = pythons[0]
    todo = {
        "python -c pass": [first, "-c", "pass"],
        'python -c "import numpy"': [first, "-c", "import numpy"],
        # kcheck pins numpy's BLAS to one thread (kcheck.cli.pin_blas_threads); numpy's own
        # default starts a thread per core at import, which costs CPU that varies with load.
        "import numpy, one BLAS thread": [first, "-c", ONE_THREAD_NUMPY],
        "import numpy, pydantic": [first, "-c", "import numpy, pydantic"],
    }
    for python in pythons:
        tag = f" [{python}]" if len(pythons) > 1 else ""
        todo[f"kcheck check (planar, explicit mass, design direction){tag}"] = [
            *(python, "-m", "kcheck", "check", str(scene), "--format", "json")
        ]
        todo[f"import numpy, kcheck.scene.models{tag}"] = [
            *(python, "-c", "import numpy, kcheck.scene.models")
        ]
    return todo


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--python", action="append")
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as name:
        tmp = Path(name)
        scene = explicit_scene(tmp)
        pythons = args.python or [sys.executable]
        todo = cases(pythons, scene)
        os.chdir(tmp)
        for cmd in todo.values():  # warm-up: writes bytecode caches, fills the page cache
            assert run(cmd, ENV)[3] == 0, cmd
        samples: dict[str, list[tuple[float, float]]] = {k: [] for k in todo}
        for _ in range(args.repeat):  # interleaved, so load changes hit every case alike
            for key, cmd in todo.items():
                wall, cpu, _, code = run(cmd, ENV)
                assert code == 0, cmd
                samples[key].append((wall, cpu))
    med = {k: tuple(statistics.median(s[i] for s in v) for i in (0, 1)) for k, v in samples.items()}
    numpy_wall, numpy_cpu = med['python -c "import numpy"']
    print(
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"{', '.join(pythons)}; load average {os.getloadavg()[0]:.1f}; "
        f"{args.repeat} interleaved runs"
    )
    print("| what | wall (median) | CPU (median) | × numpy wall | × numpy CPU |")
    print("| --- | --- | --- | --- | --- |")
    for key, (wall, cpu) in med.items():
        print(
            f"| {key} | {wall:.3f} s | {cpu:.3f} s "
            f"| {wall / numpy_wall:.2f} | {cpu / numpy_cpu:.2f} |"
        )


if __name__ == "__main__":
    main()
