"""Record the reference values of issue 24 (speed): run today's kcheck on the generated
spatial scenes (:mod:`spatial_scenes`) and keep the fields the speed work must not change,
into ``tests/golden/speed_reference.json.gz``. Recorded once, before optimising, at the commit
named in the file; ``tests/kcheck/test_speed_reference.py`` compares against it.

Run: ``python tests/record_speed_reference.py [--count 1000] [--jobs 2]``.
"""

from __future__ import annotations

import argparse
import gzip
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from spatial_scenes import kept_values, write_spatial_scenes  # noqa: E402

OUT = HERE / "golden" / "speed_reference.json.gz"
CHECKS = ("analytical-3d", "jamming")


def run_scenes(folder: Path, jobs: int) -> dict[str, dict]:
    """kcheck's JSON result of every scene in ``folder``, kept fields of CHECKS, by file name."""
    run = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(folder), "--format", "json",
         "--no-cache", "-j", str(jobs), "--color", "never"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    if run.returncode not in (0, 1):
        raise SystemExit(run.stderr)
    out = {}
    for scene in json.loads(run.stdout)["scenes"]:
        name = Path(scene["path"]).name
        out[name] = {c["id"]: kept_values(c) for c in scene["checks"] if c["id"] in CHECKS}
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=HERE
    ).stdout.strip()
    with tempfile.TemporaryDirectory() as tmp:
        write_spatial_scenes(Path(tmp), range(args.count))
        scenes = run_scenes(Path(tmp), args.jobs)
    text = json.dumps({"commit": commit, "count": args.count, "scenes": scenes}, sort_keys=True)
    OUT.write_bytes(gzip.compress((text + "\n").encode(), mtime=0))


if __name__ == "__main__":
    main()
