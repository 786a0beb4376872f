"""Peak memory and time of reading a mesh, against the STL file's size:
``python benchmarks/bench_mesh_memory.py [--source DIR]``.

Closed STL spheres (icospheres of 5 to 8 subdivisions, 0.5 to 62.5 MiB, the last just under
the default ``max_mesh_size`` of 64 MiB) are written to a temporary folder, and
``kcheck mass`` reads each in a fresh process (no mass-property cache: ``kcheck mass``
never uses it). The peak resident memory is ``ru_maxrss`` of that process from ``os.wait4``;
``python -c "import kcheck.body.mass, trimesh, scipy.spatial"`` is the floor it starts from.
``--source DIR`` runs the kcheck of another source tree (``git archive`` of an older commit)
for a before/after table.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def run(cmd: list[str], env: dict[str, str], cwd: str) -> tuple[float, float, int]:
    """Wall s, peak RSS MiB, exit code of one fresh process (in ``cwd``: ``python -c`` puts
    the working folder first on the import path)."""
    start = time.perf_counter()
    proc = subprocess.Popen(
        cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, cwd=cwd
    )
    assert proc.stderr is not None
    err = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    if code not in (0, 1):
        raise SystemExit(f"{cmd}: exit {code}: {err.decode(errors='replace')[-500:]}")
    return time.perf_counter() - start, usage.ru_maxrss / 1024, code


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, help="a kcheck source tree to run instead")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    import trimesh

    env = dict(os.environ)
    if args.source is not None:
        env["PYTHONPATH"] = f"{args.source.resolve()}:{args.source.resolve() / 'plugins'}"
    kcheck = [sys.executable, "-c", "from kcheck.cli import main; main()"]
    floor = [sys.executable, "-c", "import kcheck.body.mass, trimesh, scipy.spatial"]
    print(f"load average {os.getloadavg()[0]:.2f}; trimesh {trimesh.__version__}")
    print("| STL file | faces | peak memory | above the floor | ratio to file | time |")
    print("| --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        base = min(run(floor, env, tmp)[1] for _ in range(args.repeat))
        for subdivisions in (5, 6, 7, 8):
            path = Path(tmp) / f"sphere-{subdivisions}.stl"
            trimesh.creation.icosphere(subdivisions, radius=20.0).export(path)
            size = path.stat().st_size / 2**20
            cmd = [*kcheck, "mass", str(path), "--units", "mm", "--material", "aluminium"]
            samples = [run(cmd, env, tmp) for _ in range(args.repeat)]
            wall = sorted(s[0] for s in samples)[len(samples) // 2]
            peak = min(s[1] for s in samples)
            faces = 20 * 4**subdivisions
            print(
                f"| {size:.1f} MiB | {faces:,} | {peak:.0f} MiB | {peak - base:.0f} MiB | "
                f"{(peak - base) / size:.1f}× | {wall:.2f} s |"
            )
    print(f"floor (imports only): {base:.0f} MiB")


if __name__ == "__main__":
    main()
